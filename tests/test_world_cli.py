"""python -m world: a look's files, a walk file, a map, and one clear error for bad input."""

import json

import numpy as np

from diskfmt.layouts import decode_bi
from world.__main__ import main
from world.walk import read_walk


def test_look_writes_the_pair_and_truth(tmp_path, capsys):
    assert main(["look", "--pose", "1.5,4,30,2,-1", "--supersample", "1",
                 "--out", str(tmp_path), "--png", str(tmp_path / "l.png")]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["pose"]["heading_deg"] == 30.0 and info["visible_vertices"] > 0
    bi = decode_bi((tmp_path / "LOOK-L.BI").read_bytes())
    assert bi.shape == (120, 128) and bi.max() <= 15
    z = np.load(tmp_path / "LOOK-RANGE.npy")
    assert z.shape == (120, 128) and z.min() > 0
    assert (tmp_path / "l.png").stat().st_size > 1000
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]   # no temporaries


def test_walk_and_map(tmp_path):
    out = tmp_path / "w.csv"
    assert main(["walk", "--room", "2", "--looks", "15", "-o", str(out)]) == 0
    assert len(read_walk(out)) == 15
    assert main(["map", "--room", "2", "--walk", str(out), "-o", str(tmp_path / "m.png")]) == 0
    assert (tmp_path / "m.png").exists()


def test_bad_input_is_one_clear_error(tmp_path, capsys):
    assert main(["look", "--pose", "0,40,0", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "outside the free floor" in err and "z=40" in err
    assert not list(tmp_path.iterdir())
    bad = tmp_path / "bad.csv"
    bad.write_text("x,z,heading_deg,pitch_deg,roll_deg\n1,2,x,0,0\n")
    assert main(["look", "--walk", str(bad)]) == 2
    assert "line 2" in capsys.readouterr().err
