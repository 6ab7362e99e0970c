"""``pre`` subcommands: results, --help, and bad input (clear message,
non-zero exit, nothing overwritten or half-written)."""

import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from diskfmt.layouts import decode_bi, encode_bi, encode_vd
from pre.main import main

REPO = Path(__file__).resolve().parents[1]


def _vd(tmp_path, name="A.VD"):
    pic = np.zeros((240, 256), dtype=np.uint8)
    pic[:, 128:] = 12
    pic[0:2, 0:2] = [[1, 2], [2, 1]]                     # -> (6+2)/4 = 2
    p = tmp_path / name
    p.write_bytes(encode_vd(pic))
    return p


@pytest.mark.parametrize("cmd", ["import", "shrink", "cartoon", "show", "pair", "compare"])
def test_help(cmd, capsys):
    with pytest.raises(SystemExit) as e:
        main([cmd, "--help"])
    assert e.value.code == 0
    assert "usage: pre " + cmd in capsys.readouterr().out


def test_shrink(tmp_path):
    out = tmp_path / "A.BI"
    assert main(["shrink", str(_vd(tmp_path)), "-o", str(out)]) == 0
    bi = decode_bi(out.read_bytes())
    assert bi[0, 0] == 2 and bi[0, 1] == 0 and (bi[:, 64:] == 12).all()


def test_cartoon_and_report(tmp_path, capsys):
    pic = np.full((120, 128), 3, dtype=np.uint8)
    pic[:, 64:] = 12
    src = tmp_path / "S.BI"
    src.write_bytes(encode_bi(pic))
    out = tmp_path / "C.BI"
    assert main(["cartoon", str(src), "-o", str(out)]) == 0
    assert np.array_equal(decode_bi(out.read_bytes()), pic)
    text = capsys.readouterr().out
    # each row (and column pass): S G+ S = 4 + 3*(2+7+4) = 43 bits per row;
    # vertical pass: each column is one S: 4 + 13 = 17 bits
    assert "horizontal pass 360 symbols, 0.336 bits/pixel" in text   # 120*43/15360
    assert "after the vertical pass 128 symbols, 0.142 bits/pixel" in text   # 128*17/15360


def test_show_png(tmp_path):
    out = tmp_path / "A.PNG"
    assert main(["show", str(_vd(tmp_path)), "-o", str(out)]) == 0
    img = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert img.shape == (240, 256) and img[0, 200] == 12 * 17 and img[0, 0] == 17


def test_pair_writes_four_files(tmp_path):
    left = np.full((240, 256), 100, dtype=np.uint8)
    right = np.full((240, 256), 200, dtype=np.uint8)
    cv2.imwrite(str(tmp_path / "l.png"), left)
    cv2.imwrite(str(tmp_path / "r.png"), right)
    stem = str(tmp_path / "DESK")
    assert main(["pair", str(tmp_path / "l.png"), str(tmp_path / "r.png"), "-o", stem]) == 0
    assert (tmp_path / "DESK-L.VD").read_bytes() == bytes([0x66]) * 30720 + bytes(2048)
    assert (tmp_path / "DESK-R.VD").read_bytes() == bytes([0xCC]) * 30720 + bytes(2048)
    assert (tmp_path / "DESK-L.BI").read_bytes() == bytes([0, 6]) * 15360
    assert (tmp_path / "DESK-R.BI").read_bytes() == bytes([0, 12]) * 15360


def test_pair_refuses_before_writing_anything(tmp_path, capsys):
    cv2.imwrite(str(tmp_path / "l.png"), np.zeros((240, 256), np.uint8))
    (tmp_path / "DESK-R.BI").write_bytes(b"keep")
    rc = main(["pair", str(tmp_path / "l.png"), str(tmp_path / "l.png"), "-o",
               str(tmp_path / "DESK")])
    assert rc == 1
    assert "DESK-R.BI: already exists" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["DESK-R.BI", "l.png"]


def test_missing_file(tmp_path, capsys):
    assert main(["shrink", str(tmp_path / "NO.VD"), "-o", str(tmp_path / "X.BI")]) == 1
    assert f"{tmp_path / 'NO.VD'}: no such file" in capsys.readouterr().err
    assert main(["import", str(tmp_path / "no.png"), "-o", str(tmp_path / "X.VD")]) == 1
    assert list(tmp_path.iterdir()) == []


def test_unreadable_picture(tmp_path, capsys):
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"this is not a PNG at all" * 10)
    assert main(["import", str(bad), "-o", str(tmp_path / "X.VD")]) == 1
    err = capsys.readouterr().err
    assert "bad.png" in err and "not a picture OpenCV can read" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.png"]


def test_vd_of_the_wrong_size(tmp_path, capsys):
    short = tmp_path / "SHORT.VD"
    short.write_bytes(bytes(1000))
    assert main(["shrink", str(short), "-o", str(tmp_path / "X.BI")]) == 1
    assert "SHORT.VD: 1000 bytes, expected 32768" in capsys.readouterr().err
    bi = tmp_path / "REAL.BI"
    bi.write_bytes(bytes(30720))
    assert main(["shrink", str(bi), "-o", str(tmp_path / "Y.BI")]) == 1
    assert "size of a .BI file" in capsys.readouterr().err
    assert not (tmp_path / "X.BI").exists() and not (tmp_path / "Y.BI").exists()


def test_existing_output_is_not_overwritten(tmp_path, capsys):
    vd = _vd(tmp_path)
    out = tmp_path / "A.BI"
    out.write_bytes(b"keep me")
    assert main(["shrink", str(vd), "-o", str(out)]) == 1
    assert "already exists; not overwritten" in capsys.readouterr().err
    assert out.read_bytes() == b"keep me"
    assert main(["shrink", str(vd), "-o", str(out), "--force"]) == 0
    assert len(out.read_bytes()) == 30720
    assert sorted(p.name for p in tmp_path.iterdir()) == ["A.BI", "A.VD"]   # no temporaries


def test_bad_option_values(tmp_path):
    with pytest.raises(SystemExit) as e:
        main(["cartoon", "x.BI", "-o", "y.BI", "--threshold", "many"])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        main(["import", "x.png", "-o", "y.VD", "--fit", "squash"])
    assert e.value.code == 2


@pytest.mark.processes
def test_menu_as_a_process(tmp_path):
    vd = _vd(tmp_path)
    bi = tmp_path / "M.BI"
    proc = subprocess.run([sys.executable, "-m", "pre"], cwd=REPO,
                          input=f"10\n{vd}\n2\n4\n{bi}\nfour\n-1\n", capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0
    assert "** 'four' is not a number" in proc.stdout
    assert main(["shrink", str(vd), "-o", str(tmp_path / "C.BI")]) == 0
    assert bi.read_bytes() == (tmp_path / "C.BI").read_bytes()


def test_import_to_a_bi_name_writes_a_bi_not_a_vd(tmp_path, capsys):
    cv2.imwrite(str(tmp_path / "p.png"), np.full((240, 256), 200, np.uint8))
    assert main(["import", str(tmp_path / "p.png"), "-o", str(tmp_path / "P.BI")]) == 0
    data = (tmp_path / "P.BI").read_bytes()
    assert len(data) == 30720 and decode_bi(data).max() == 12       # floor(200/16)
    assert main(["import", str(tmp_path / "p.png"), "-o", str(tmp_path / "P.png")]) == 1
    assert "name it .VD" in capsys.readouterr().err
    assert not (tmp_path / "P.png").exists()


def test_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0 and capsys.readouterr().out.startswith("pre ")
