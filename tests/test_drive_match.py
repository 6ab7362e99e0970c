"""The drive's stereo matcher (``DriveConfig.match``, ``rig drive --match``,
``bench/drive.py --match``): the 1985 eyes by default, the improved matcher
of package ``matching`` as a named option."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from planner.loop import DriveConfig, run, scan_look, true_range_points
from planner.tiny import GOAL, tiny_room
from vehicle.sim import State
from world.odometry import OdometryNoise
from rigtools import STEP_BACK_FT, drive_config

REPO = Path(__file__).resolve().parent.parent


def _tiny_look():
    from world.pose import Pose
    from world.render import render_look
    return render_look(tiny_room(), Pose(0.0, 0.0, 0.0, -25.0), seed=1986, supersample=2)


def _in_front(points, look, by_ft=0.5) -> int:
    """Located points more than ``by_ft`` in front of the TRUE surface at their
    pixel (the world's range per pixel): false matches."""
    true = true_range_points(points, look)
    return sum(p.dp < t.dp - by_ft for p, t in zip(points, true))


def test_the_1985_scan_is_the_eyes_bit_for_bit():
    from rig.scan import scan_pair
    look = _tiny_look()
    lines = DriveConfig(goal=GOAL).lines
    assert DriveConfig(goal=GOAL).match == "improved"        # the drive's default since 2026-12-05
    a = scan_look(look.left_bi, look.right_bi, lines, "1985")
    b = scan_pair(look.left_bi, look.right_bi, lines)            # the reference rig, 1985
    assert a.points == b.points and len(a.points) > 100


def test_the_improved_matcher_locates_fewer_false_matches_against_the_world():
    """On a look of the tiny room, scored against the world's true range per
    pixel: the improved matcher's located edges lie in front of the true
    surface far less often than the 1985 matcher's (measured 8 % against 22 %),
    and every edge it located has a "matched" verdict with a confidence."""
    look = _tiny_look()
    lines = DriveConfig(goal=GOAL).lines
    old = scan_look(look.left_bi, look.right_bi, lines, "1985")
    new = scan_look(look.left_bi, look.right_bi, lines, "improved")
    share_old = _in_front(old.points, look) / len(old.points)
    share_new = _in_front(new.points, look) / len(new.points)
    assert len(new.points) >= 0.5 * len(old.points)
    assert share_new < 0.6 * share_old, (share_new, share_old)
    for r in new.results:
        matched = {v.edge: v for v in r.verdicts if v.matched}
        for e, pos in r.positions.items():
            if pos is not None:
                assert e in matched and 0.0 < matched[e].confidence <= 1.0


def test_an_unknown_matcher_is_refused():
    with pytest.raises(ValueError, match="unknown stereo matcher 'sgbm'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, match="sgbm"))
    with pytest.raises(ValueError, match="unknown stereo matcher"):
        scan_look(np.zeros((120, 128)), np.zeros((120, 128)), [60], "sgbm")


def test_the_loop_on_the_improved_matcher_reaches_the_tiny_room_goal():
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py)
    res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, match="improved",
                                                             sight_lines="band"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.travelled_ft <= 1.3 * res.optimal_ft + STEP_BACK_FT   # (rigtools)
    data = res.as_json()
    assert data["match"] == "improved"
    assert all(0 < c["scan_ms"] <= c["work_ms"] for c in data["cycles"])
    # the loop's CPU time: no more than the wall-clock time it was measured over
    # (1 ms for the two clocks' granularity)
    assert all(0 < c["work_cpu_ms"] <= c["work_ms"] + 1.0 for c in data["cycles"])


def test_rig_drive_match_reaches_the_loop(tmp_path, monkeypatch):
    from rig.main import main
    assert drive_config(monkeypatch, tmp_path, "--match", "1985").match == "1985"
    assert drive_config(monkeypatch, tmp_path).match == "improved"
    with pytest.raises(SystemExit):
        main(["drive", "--out", str(tmp_path), "--match", "sgbm"])


@pytest.mark.processes
def test_bench_drive_runs_with_the_improved_matcher(tmp_path):
    """bench/drive.py --match improved as a user runs it (from its own
    directory on the path, where no module may hide the matching package)."""
    import json
    out = tmp_path / "b.json"
    r = subprocess.run([sys.executable, str(REPO / "bench" / "drive.py"), "--rooms", "1",
                        "--first", "6", "--max-looks", "2", "--match", "improved",
                        "--out", str(out)], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    data = json.loads(out.read_text())
    assert data["summary"]["match"] == "improved"
    assert data["rooms"][0]["looks"] == 2
