"""The walk benchmark's Mahalanobis breakdown (bench/walk.py --breakdown) on a
hand-made model: every group's count, share inside 2 sigma and share beyond 10."""

import importlib.util
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parent.parent / "bench" / "walk.py"
_spec = importlib.util.spec_from_file_location("bench_walk", _PATH)
bw = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("bench_walk", bw)
_spec.loader.exec_module(bw)


def test_mahalanobis_rows_group_by_looks_range_and_confirmation():
    from model.mapping import WalkConfig, WalkResult
    from model.symbolic import SymbolicModel
    model = SymbolicModel()
    # unit covariances, the camera at the origin at look 0; (truth offset, looks, nis, where)
    spec = [((1, 0, 0), 1, [], (0, 0, 3)),        # seen once, 3 ft away: inside (1)
            ((20, 0, 0), 1, [], (0, 0, 8)),       # seen once, 8 ft: beyond 10 (20)
            ((2, 0, 0), 2, [1.0], (0, 0, 8)),     # seen twice, consistent: confirmed, inside
            ((0, 3, 0), 5, [1.0] * 4, (0, 0, 12))]  # seen 5 times, 12 ft: outside (3 > 2.83)
    for off, looks, nis, where in spec:
        truth = np.array(where, float)
        v = model.add_vertex(truth + off, np.eye(3), "top", (3, 9), 0)
        v.truth, v.looks, v.nis = truth, looks, nis
    rec = SimpleNamespace(true_pose=SimpleNamespace(x=0.0, z=0.0))
    res = WalkResult(WalkConfig(confirm=2), [rec], model)
    rows = {r.split(" | ")[1]: r.split(" | ")[2:] for r in bw.mahalanobis_rows("t", [res])}
    assert rows["all"][:3] == ["4", "50.0 %", "25.0 %"]
    assert rows["seen once"][:3] == ["2", "50.0 %", "50.0 %"]
    assert rows["seen twice"][:3] == ["1", "100.0 %", "0.0 %"]
    assert rows["seen 5-9 times"][:3] == ["1", "0.0 %", "0.0 %"]
    assert "seen 10+ times" not in rows
    assert rows["first seen at 0-5 ft"][0] == "1" and rows["first seen at 10-15 ft"][0] == "1"
    assert rows["track-confirmed"][:2] == ["2", "50.0 %"]      # the twice and five-times seen
    assert rows["tentative"][:3] == ["2", "50.0 %", "50.0 %"]
    assert rows["all"][3].strip(" |") == "2.50"                # median of 1, 20, 2, 3


def _chart_look():
    """Look 7 of the bundled walk: the left wall's chequered chart (0.5 ft checks: the same
    grey pattern again every 1.0 ft along the wall) close on the right of the picture."""
    from world.render import range_128
    from world.room import bundled_lab
    from world.walk import bundled_walk
    room, pose = bundled_lab(), bundled_walk()[7]
    z, which = range_128(room.quads, pose.camera_centre("left"), pose.rotation())
    return SimpleNamespace(room=room, pose=pose, range_left=z, surface_left=which)


def _feature_at(model, look, col, row, disparity, truth):
    """A vertex placed by the rig's triangulation of (col, row, disparity) in ``look``'s
    left camera, with a tight covariance, scored against ``truth``."""
    R, left = look.pose.rotation(), look.pose.camera_centre("left")
    z = 0.75 * 180.0 / disparity
    mean = left + R @ np.array([z * (col - 64) / 180, z * (row - 60) / 180, z])
    v = model.add_vertex(mean, np.eye(3) * 0.01, "top", (2, 11), 0)
    v.truth, v.seen_at = np.asarray(truth, float), (col, row, int(np.floor(row)), disparity)
    return v


def test_outside_evidence_finds_a_chart_matched_one_period_off():
    from model.mapping import WalkConfig, WalkResult
    from model.symbolic import SymbolicModel
    from world.render import project
    look = _chart_look()
    col, row = 118.3, 60.5
    R, left = look.pose.rotation(), look.pose.camera_centre("left")
    quad = look.room.quads[int(look.surface_left[60, 118])]
    assert quad.name == "left chart"
    # the chart point the left pixel sees, and the right camera's view of the same grey
    # pattern one period (two 0.5 ft checks) further along the wall: the picket fence
    d = R @ np.array([(col - 64) / 180, (row - 60) / 180, 1.0])
    on_chart = left + (-4.0 - left[0]) / d[0] * d
    period_off = on_chart + np.array([0.0, 0.0, 1.0])
    col_r = float(project(period_off, look.pose, "right")[0])
    wrong_disp = col - col_r
    true_disp = 0.75 * 180.0 / float(look.range_left[60, 118])
    model = SymbolicModel()
    v_wrong = _feature_at(model, look, col, row, wrong_disp, on_chart)
    v_right = _feature_at(model, look, col, row, true_disp, on_chart)
    res = WalkResult(WalkConfig(), [SimpleNamespace(true_pose=look.pose)], model)
    ev = {e["vertex"]: e for e in bw.outside_evidence(res, [look])}
    assert v_right.id not in ev                       # on its truth: inside 2 sigma
    e = ev[v_wrong.id]
    assert e["surface"] == "left chart" and e["wrong_match"] and not e["occluding"]
    assert e["shift_ft"] == pytest.approx(1.0, abs=1e-4)
    assert e["true_disparity"] == pytest.approx(true_disp)
    assert wrong_disp < true_disp - 10                 # a period off is placed far beyond
    assert e["feature_range"] > float(look.range_left[60, 118]) + 2
    table = bw.outside_tables([("t", list(ev.values()))])
    assert "| t | 1 | 1 | 0 | 0 | 0 |" in table and "| left chart |" in table


def test_outside_evidence_names_the_side_of_an_occluding_edge():
    """From the start pose the crate's right edge (X = 0, Z = 5 ft) stands before the back
    wall 19 ft away: a feature there at the wall's range lies on the far side of the
    scorer's window."""
    from model.mapping import WalkConfig, WalkResult
    from model.symbolic import SymbolicModel
    from world.pose import Pose
    from world.render import range_128
    from world.room import bundled_lab
    room, pose = bundled_lab(), Pose(0.0, 0.0, 0.0)
    z, which = range_128(room.quads, pose.camera_centre("left"), pose.rotation())
    look = SimpleNamespace(room=room, pose=pose, range_left=z, surface_left=which)
    assert room.quads[which[80, 77]].name == "crate front" and z[80, 77] == pytest.approx(5.0)
    assert room.quads[which[80, 78]].name == "back wall" and z[80, 78] == pytest.approx(19.0)
    model = SymbolicModel()
    crate_edge = np.array([0.0, 5.0 * 20.5 / 180, 5.0])
    v = _feature_at(model, look, 78.2, 80.5, 0.75 * 180 / float(z[80, 78]), crate_edge)
    res = WalkResult(WalkConfig(), [SimpleNamespace(true_pose=pose)], model)
    (e,) = bw.outside_evidence(res, [look])
    assert e["vertex"] == v.id and e["occluding"] and e["side"] == "far"
    assert e["surface"] == "back wall" and not e["wrong_match"]


def test_ten_look_ratio_and_how_far_one_feature_moves_it():
    # three features seen ten times (errors after their 1st and 10th look: 0.3 -> 0.1,
    # 0.4 -> 0.2, 0.0 -> 0.5) and one seen nine times, which does not count
    def h(first, tenth, n=10):
        return [first] + [9.0] * (n - 2) + [tenth]
    r = bw.ten_look_ratio([h(0.3, 0.1), h(0.4, 0.2), h(0.0, 0.5), h(5.0, 0.0, n=9)])
    assert r["features"] == 3
    assert r["rms_1"] == pytest.approx(np.sqrt(0.25 / 3))
    assert r["rms_10"] == pytest.approx(np.sqrt(0.30 / 3))
    assert r["ratio"] == pytest.approx(np.sqrt(0.30 / 0.25))
    # left out in turn: sqrt(0.29/0.16), sqrt(0.26/0.09), sqrt(0.05/0.25)
    assert r["leave_one_out"] == pytest.approx((np.sqrt(0.05 / 0.25), np.sqrt(0.26 / 0.09)))
    assert bw.ten_look_ratio([h(1.0, 1.0, n=9)])["ratio"] is None


def test_ten_look_census_pairs_the_runs_features_by_their_truth():
    from model.symbolic import SymbolicModel

    def run(spec):
        model, history = SymbolicModel(), {}
        for truth_id, truth, first, errors in spec:
            v = model.add_vertex(np.zeros(3), np.eye(3), "top", (3, 9), first)
            v.truth, v.truth_id = np.array(truth, float), truth_id
            history[v.id] = errors
        return SimpleNamespace(model=model, error_history=history)
    corner = [0.4] + [0.2] * 9                            # ten looks
    a = run([(7, (1, 0, 5), 3, corner), (-1, (2.04, 0, 5), 0, [0.3] * 12),
             (8, (0, 0, 9), 1, [0.5] * 4)])
    b = run([(7, (1, 0, 5), 5, [0.4] * 8), (7, (1, 0, 5), 6, [0.5]),
             (-1, (1.96, 0.01, 5.02), 0, [0.3] * 11)])
    rows = {r["truth"]: r for r in bw.ten_look_census({"a": a, "b": b})}
    # corner 8 is followed four times only, in a; corner 7 ten times in a, eight in b
    assert set(rows) == {("corner", 7), ("point", 2.0, 0.0, 5.0)}
    assert [(f["first_look"], f["looks"], f["error_10"]) for f in rows[("corner", 7)]["a"]] \
        == [(3, 10, 0.2)]
    assert [(f["first_look"], f["looks"]) for f in rows[("corner", 7)]["b"]] == [(5, 8), (6, 1)]
    assert rows[("point", 2.0, 0.0, 5.0)]["b"][0]["looks"] == 11
    text = bw.ten_look_tables({"a": SimpleNamespace(**vars(a)), "b": b})
    assert "| corner 7 | v0 from look 3, 10 looks, 0.40 -> 0.20 |" in text


def test_seed_tables_count_the_draws_meeting_each_target():
    f = dict(position_ft=0.2, heading_deg=0.7, ten_look_features=20, ten_look_ratio=0.45,
             leave_one_out=(0.40, 0.52), inside_2sigma=0.91, features=500, look_ms=30.0)
    g = dict(f, position_ft=0.3, ten_look_ratio=0.55, inside_2sigma=0.85)
    h = dict(f, ten_look_features=0, ten_look_ratio=None, leave_one_out=(None, None))
    text = bw.seed_tables([("x", 1985, f), ("x", 1986, g), ("x", 1987, h)])
    assert "| x | 1985 | 0.20 | 0.70 | 45.0 % (20; 40.0 .. 52.0 %) | 91.0 % of 500 | 30 |" in text
    assert "| x | 1987 | 0.20 | 0.70 | - (0) |" in text
    # position met twice, heading three times, the ratio once (none without ten-look
    # features), inside twice; all four once; the median of 45 and 55 %, of 91, 85, 91 %
    assert "| x | 3 | 2 | 3 | 1 | 2 | 1 | 50.0 % | 91.0 % |" in text
