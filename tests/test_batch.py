"""rig scan over many pictures (rig.batch): lists and globs of pairs, stereo
videos (two files, side by side), workers, bad frames skipped and reported;
every frame's CSV is what the reference path gives for the same digitized
pictures."""

import csv
import shutil

import cv2
import numpy as np
import pytest

from diskfmt.layouts import decode_bi
from rig import batch
from rig import scan as scanmod
from rig.main import main as rig_main
from rig.scene import bundled_path
from rigtools import ctrl_c_default


def bundled_pair():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def summary(out):
    with open(out / "summary.csv") as f:
        return list(csv.DictReader(f))


def reference_csv(left, right):
    return scanmod.csv_text(scanmod.scan_pair(left, right).points)


def as_photo(pic128):
    """A 4-bit 120x128 picture as an 8-bit 240x256 photo whose digitized and
    condensed form is the picture again (level k -> grey 16k+8, 2x2 blocks)."""
    return np.kron(pic128.astype(np.uint8) * 16 + 8, np.ones((2, 2), dtype=np.uint8))


def test_pair_list_with_a_bad_pair_keeps_the_others(tmp_path, capsys):
    left, right = bundled_pair()
    shutil.copy(bundled_path("LAB-L.BI"), tmp_path / "a-L.BI")
    shutil.copy(bundled_path("LAB-R.BI"), tmp_path / "a-R.BI")
    cv2.imwrite(str(tmp_path / "b-L.png"), as_photo(left))
    cv2.imwrite(str(tmp_path / "b-R.png"), as_photo(right))
    (tmp_path / "broken-L.png").write_bytes(b"not a png")
    (tmp_path / "list.txt").write_text("# pairs\na-L.BI a-R.BI\nmissing-L.BI a-R.BI\n"
                                       "b-L.png, b-R.png\nbroken-L.png b-R.png\n")
    out = tmp_path / "out"
    code = rig_main(["scan", "--pair-list", str(tmp_path / "list.txt"), "--out", str(out),
                     "--quiet"])
    assert code == 2                                    # bad frames: non-zero, others kept
    rows = summary(out)
    assert [r["status"] for r in rows] == ["ok", "error", "ok", "error"]
    assert "no such file" in rows[1]["error"] and "missing-L.BI" in rows[1]["error"]
    assert "broken-L.png" in rows[3]["error"]
    want = reference_csv(left, right)
    assert (out / "frame-000000.csv").read_text() == want
    assert (out / "frame-000002.csv").read_text() == want     # through the digitizer
    assert not (out / "frame-000001.csv").exists()
    err = capsys.readouterr().err
    assert "frame 1" in err and "skipped" in err


def test_globs_pair_sorted_files_and_refuse_uneven_counts(tmp_path):
    for k in range(3):
        shutil.copy(bundled_path("LAB-L.BI"), tmp_path / f"f{k}-L.BI")
        shutil.copy(bundled_path("LAB-R.BI"), tmp_path / f"f{k}-R.BI")
    pairs = batch.pairs_from_globs(str(tmp_path / "*-L.BI"), str(tmp_path / "*-R.BI"))
    assert [p[0][-7:] for p in pairs] == ["f0-L.BI", "f1-L.BI", "f2-L.BI"]
    (tmp_path / "f3-L.BI").write_bytes(b"")
    with pytest.raises(batch.BatchError, match="cannot pair"):
        batch.pairs_from_globs(str(tmp_path / "*-L.BI"), str(tmp_path / "*-R.BI"))


def write_video(path, frames, fourcc="FFV1"):
    h, w = frames[0].shape[:2]
    vw = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), 10, (w, h))
    assert vw.isOpened()
    for f in frames:
        vw.write(cv2.cvtColor(f, cv2.COLOR_GRAY2BGR))
    vw.release()


def shifted_pairs(n):
    left, right = bundled_pair()
    return [(np.roll(left, k, axis=1), np.roll(right, k, axis=1)) for k in range(n)]


@pytest.mark.parametrize("workers", [1, 2])
def test_side_by_side_video_every_frame_equals_the_reference(tmp_path, workers):
    pairs = shifted_pairs(5)
    video = tmp_path / "sbs.avi"
    write_video(video, [np.hstack([as_photo(l), as_photo(r)]) for l, r in pairs])
    out = tmp_path / "out"
    code = rig_main(["scan", "--video", str(video), "--out", str(out), "--quiet",
                     "--workers", str(workers), "--chunk", "2"])
    assert code == 0
    rows = summary(out)
    assert [int(r["frame"]) for r in rows] == list(range(5))
    for k, (l, r) in enumerate(pairs):
        assert (out / f"frame-{k:06d}.csv").read_text() == reference_csv(l, r), k


def test_two_video_files_and_frame_limit(tmp_path):
    pairs = shifted_pairs(4)
    write_video(tmp_path / "l.avi", [as_photo(l) for l, _ in pairs])
    write_video(tmp_path / "r.avi", [as_photo(r) for _, r in pairs])
    out = tmp_path / "out"
    assert rig_main(["scan", "--video", str(tmp_path / "l.avi"), str(tmp_path / "r.avi"),
                     "--frames", "3", "--out", str(out), "--quiet", "--ply-frames"]) == 0
    assert len(summary(out)) == 3
    l, r = pairs[2]
    assert (out / "frame-000002.csv").read_text() == reference_csv(l, r)
    ply = (out / "frame-000002.ply").read_text()
    assert ply == scanmod.ply_text(scanmod.scan_pair(l, r).points)


def test_bad_batch_input_is_one_clear_error(tmp_path, capsys):
    assert rig_main(["scan", "--video", str(tmp_path / "none.avi"), "--out",
                     str(tmp_path / "o"), "--quiet"]) == 1
    assert "none.avi: no such video file" in capsys.readouterr().err
    with pytest.raises(SystemExit, match="one of"):
        rig_main(["scan", "--video", "a", "--pair-list", "b"])


def test_ctrl_c_stops_cleanly_and_keeps_every_finished_frame(tmp_path):
    """The Ctrl-C comes once 20 frames are published, with 49 980 still to go
    (at tens of frames a second: minutes of work), so it cannot come after
    the end however loaded the machine; the timeouts only detect a hang."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
    shutil.copy(bundled_path("LAB-L.BI"), tmp_path / "L.BI")
    shutil.copy(bundled_path("LAB-R.BI"), tmp_path / "R.BI")
    frames = 50000
    (tmp_path / "list.txt").write_text("L.BI R.BI\n" * frames)
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "rig.main", "scan", "--pair-list",
                          str(tmp_path / "list.txt"), "--out", str(out), "--workers", "2",
                          "--chunk", "8", "--quiet"], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=ctrl_c_default)
    try:
        deadline = time.monotonic() + 600                # a hang detector
        while len(list(out.glob("frame-*.csv"))) < 20:
            assert p.poll() is None, p.communicate()[1]
            assert time.monotonic() < deadline, "no 20 frames in 600 s"
            time.sleep(0.05)
        p.send_signal(signal.SIGINT)
        stdout, stderr = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert p.returncode == 130, stderr
    assert "interrupted" in stdout
    rows = summary(out)
    assert 20 <= len(rows) < frames
    assert all(r["status"] == "ok" for r in rows)
    done = {int(r["frame"]) for r in rows}
    assert {int(f.stem.split("-")[1]) for f in out.glob("frame-*.csv")} >= done
