"""The loop's look-ahead (``DriveConfig.look_ahead``, ``--look-ahead``, not 1985,
on by default since 2026-12-01): before a move, the first never-seen cell on the planned path's
swept band is looked at while the vehicle is still far enough for a look to
show it.  Hand-made floor maps; the cut points and turns derived by hand."""

import math

import numpy as np
import pytest

from planner.floormap import FloorMap
from planner.loop import DriveConfig, run
from planner.motion import HALF_FOV_DEG, looked_ahead, first_unseen_on_band, look_ahead, \
    near_visible_ft
from planner.octree import FREE, UNKNOWN
from planner.search import clearance_map
from vehicle.commands import Forward, Turn
from vehicle.profile import DEFAULT
from vehicle.sim import State
from planner.trajectory import heading_to, wrap
from rigtools import STEP_BACK_FT

NEAR = 2.3                     # near_visible_ft of the default profile, rounded
HALF = DEFAULT.width_ft / 2 + DEFAULT.margin_ft     # 0.55 ft: the swept band's half width


def free_map():
    """16 x 16 ft, 0.25 ft cells, all seen free; the origin at a cell corner."""
    return FloorMap(np.full((64, 64), FREE, np.uint8), -8.0, -8.0, 0.25)


def test_the_first_unseen_cell_the_band_enters_and_none_when_it_is_all_seen():
    fm = free_map()
    path = [(0.0, 0.0), (0.0, 6.0)]
    assert first_unseen_on_band(fm, path, HALF, 4.0) is None
    # x 0.75..1.0 lies outside the band (it reaches x = 0.55): not on the way
    fm.cells[fm.index(0.8, 2.1)] = UNKNOWN
    assert first_unseen_on_band(fm, path, HALF, 4.0) is None
    # x 0.5..0.75 is entered; z 3.0..3.25: centre (0.625, 3.125)
    fm.cells[fm.index(0.6, 3.1)] = UNKNOWN
    assert first_unseen_on_band(fm, path, HALF, 4.0) == (0.625, 3.125)
    # a nearer one on the other side comes first; one past the look-ahead never counts
    fm.cells[fm.index(-0.3, 2.6)] = UNKNOWN
    assert first_unseen_on_band(fm, path, HALF, 4.0) == (-0.375, 2.625)
    only_far = free_map()
    only_far.cells[only_far.index(0.0, 4.6)] = UNKNOWN
    assert first_unseen_on_band(only_far, path, HALF, 4.0) is None
    assert first_unseen_on_band(only_far, path, HALF, 5.0) == (0.125, 4.625)


def test_the_band_follows_the_path_round_its_corner():
    # (0,0) -> (0,2) -> (2,2): a cell just above the second leg, x 1.0..1.25,
    # z 2.5..2.75 (the band reaches z = 2.55); the first leg's band never comes near
    fm = free_map()
    fm.cells[fm.index(1.1, 2.6)] = UNKNOWN
    path = [(0.0, 0.0), (0.0, 2.0), (2.0, 2.0)]
    assert first_unseen_on_band(fm, path, HALF, 4.0) == (1.125, 2.625)
    assert first_unseen_on_band(fm, path, HALF, 2.9) is None     # 2 ft + 0.9 ft: short of x 1.0


def test_the_move_is_cut_where_the_cell_still_shows_and_turned_toward():
    # the cell at (1.625, 3.125), the move 1.5 ft straight up +z from the origin:
    # |(1.625, 3.125 - t)| = 2.55 ft (near + a cell) at t = 3.125 - sqrt(2.55^2 - 1.625^2)
    # = 1.1598 ft, taken down to 1.15; from (0, 1.15) the cell's bearing is
    # atan2(1.625, 1.975) = 39.45 deg, 15.5 deg (the half view less 4 deg) the
    # largest it may be: a turn of 23.95 deg
    est = State(0.0, 0.0, 0.0)
    cell = (1.625, 3.125)
    t = 3.125 - math.sqrt(2.55 ** 2 - 1.625 ** 2)
    assert t == pytest.approx(1.1598, abs=1e-4)
    out = look_ahead([Forward(1.5)], est, cell, 2.3, 0.25)
    assert [type(c) for c in out] == [Forward, Turn]
    assert out[0].distance_ft == pytest.approx(1.15)
    bearing = math.degrees(math.atan2(1.625, 3.125 - 1.15))
    assert bearing == pytest.approx(39.45, abs=0.01)
    assert out[1].angle_deg == pytest.approx(round(bearing - (HALF_FOV_DEG - 4.0), 2))
    # after them the cell lies inside the view and no nearer than a look shows
    off = wrap(heading_to((0.0, 1.15), cell) - out[1].angle_deg)
    assert abs(off) <= HALF_FOV_DEG
    assert math.hypot(cell[0], cell[1] - 1.15) >= 2.3
    # to the left: the turn the other way
    left = look_ahead([Forward(1.5)], est, (-1.625, 3.125), 2.3, 0.25)
    assert left[1].angle_deg == pytest.approx(-out[1].angle_deg)


def test_a_pivot_before_the_move_is_kept_and_a_cell_in_view_needs_no_turn():
    # heading 10 deg, TURN -10 then the move up +z: the cut as above; the cell
    # (0.625, 3.125) is 14.2 deg off the way from the cut: inside 15.5, no turn
    est = State(0.0, 0.0, 10.0)
    out = look_ahead([Turn(-10.0), Forward(1.5)], est, (0.625, 3.125), 2.3, 0.25)
    t = 3.125 - math.sqrt(2.55 ** 2 - 0.625 ** 2)
    assert [type(c) for c in out] == [Turn, Forward]
    assert out[1].distance_ft == pytest.approx(math.floor(t * 100) / 100)


def test_nothing_changes_when_the_cell_is_already_too_near_or_never_reached():
    est = State(0.0, 0.0, 0.0)
    seg = [Forward(1.5)]
    assert look_ahead(seg, est, (0.625, 2.375), 2.3, 0.25) is None     # 2.46 ft: too late
    assert look_ahead(seg, est, (0.625, 5.125), 2.3, 0.25) is None     # still 3.68 ft after it


def _safe(fm):
    return clearance_map(fm, DEFAULT.planning_radius_ft, "free", uncertain="blocked")


def test_the_loop_step_looks_ahead_once_per_cell_and_keeps_the_safety_rules():
    near = near_visible_ft(DEFAULT, DriveConfig.lowest_obstacle_ft)
    assert near == pytest.approx(NEAR, abs=0.05)
    est = State(0.0, 0.0, 0.0)
    seg = [Forward(1.5)]
    path = [(0.0, 0.0), (0.0, 8.0)]
    fm = free_map()
    fm.cells[fm.index(0.6, 3.6)] = UNKNOWN          # (0.625, 3.625), on the band
    args = (est, fm, path, near, _safe(fm), fm.cells != UNKNOWN, None, DEFAULT, None)
    done = set()
    got = looked_ahead(seg, *args, done)
    assert got is not None
    cmds, note = got
    assert "looking ahead at (0.6, 3.6)" in note
    d = cmds[0].distance_ft
    assert 0 < d < 1.5
    assert math.hypot(0.625, 3.625 - d) >= near + 0.25
    assert math.hypot(0.625, 3.625 - d - 0.01) < near + 0.25 + 0.02
    assert done == {fm.index(0.625, 3.625)}
    assert looked_ahead(seg, *args, done) is None  # looked at once: drive on
    # the band all seen: nothing changes
    clear = free_map()
    assert looked_ahead(seg, est, clear, path, near, _safe(clear), clear.cells != UNKNOWN,
                         None, DEFAULT, None, set()) is None


def test_no_look_ahead_whose_pivot_would_reach_unseen_space():
    # the same cell, but the cut point's pivot circle (the footprint's half
    # diagonal, 0.64 ft) holds an unseen cell beside the way: the move stays as it was
    near = near_visible_ft(DEFAULT, DriveConfig.lowest_obstacle_ft)
    est = State(0.0, 0.0, 0.0)
    fm = free_map()
    fm.cells[fm.index(1.625, 3.125)] = UNKNOWN       # off the band: not the look-ahead's
    fm.cells[fm.index(0.6, 2.6)] = UNKNOWN           # the band's first unseen cell, (0.625, 2.625)
    first = first_unseen_on_band(fm, [(0.0, 0.0), (0.0, 8.0)], HALF, 4.0)
    assert first == (0.625, 2.625)
    cut = look_ahead([Forward(1.5)], est, first, near, 0.25)
    assert cut is not None and isinstance(cut[0], Forward)
    # a cell 0.6 ft beside the cut point, x 0.5..0.75, within the pivot circle
    fm.cells[fm.index(0.6, cut[0].distance_ft + 0.05)] = UNKNOWN
    assert looked_ahead([Forward(1.5)], est, fm, [(0.0, 0.0), (0.0, 8.0)], near, _safe(fm),
                         fm.cells != UNKNOWN, None, DEFAULT, None, set()) is None


@pytest.mark.parametrize("eyes", ["truth", "depth"])
def test_the_loop_drives_the_tiny_room_looking_ahead(eyes):
    # as tests/test_drive.py's tiny-room drive (the oracle eyes; and the depth eyes)
    from planner.tiny import GOAL, tiny_room
    from world.odometry import OdometryNoise
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py)
    res = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes=eyes, look_ahead=True, sight_lines="band"), noise=OdometryNoise(seed=1),
              keep_maps=False)
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.travelled_ft <= 1.3 * res.optimal_ft + STEP_BACK_FT   # (rigtools)


def test_rig_drive_and_the_bench_take_look_ahead(monkeypatch, tmp_path):
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path, "--look-ahead").look_ahead is True
    assert drive_config(monkeypatch, tmp_path, "--no-look-ahead").look_ahead is False
    assert drive_config(monkeypatch, tmp_path).look_ahead is True      # the default since 2026-12-01
    assert DriveConfig(goal=(0.0, 0.0)).look_ahead is True
