"""planner/passage.py: straight through a passage narrower than the pivot circle
(DriveConfig.passage="straight"), on hand-made masks and a hand-made room whose
geometry the assertions measure against."""

import math

import numpy as np
import pytest

from planner.floormap import true_floor_map
from planner.loop import DriveConfig
from planner.motion import safe_prefix
from planner.passage import heading_ray, shorten_straight, straight_passable, straight_runs
from planner.planning import plan
from planner.search import Passable, clearance_map
from vehicle.commands import Forward, Turn
from vehicle.profile import DEFAULT
from vehicle.sim import State

CELL = 0.25
HALF = DEFAULT.width_ft / 2 + DEFAULT.margin_ft     # 0.55 ft: the grown half width
RADIUS = DEFAULT.planning_radius_ft                  # 0.79 ft: the pivot circle and margin

# a room 8 ft wide crossed at z 5..6 by two boxes leaving a gap x -0.75..1.0: seven
# free cells (1.75 ft).  The gap's middle column (x 0.0..0.25, centre 0.125) has its
# centre 4 cells from both boxes' cells: the "anywhere" clearance (4 - sqrt 2) x 0.25
# = 0.646 ft, over the half width 0.55, under the radius 0.79; the columns beside it,
# (3 - sqrt 2) x 0.25 = 0.396 ft, under both
BOXES = [(-4.0, -0.75, 5.0, 6.0), (1.0, 4.0, 5.0, 6.0)]
BOUNDS = (-4.0, 4.0, -3.0, 14.0)
GAP_X = 0.125


def _gap_map():
    return true_floor_map(BOXES, BOUNDS, CELL)


def _true_clearance(x: float, z: float) -> float:
    """Distance (ft) from the point to the nearest box or wall of the room."""
    d = min(x - BOUNDS[0], BOUNDS[1] - x, z - BOUNDS[2], BOUNDS[3] - z)
    for x0, x1, z0, z1 in BOXES:
        d = min(d, math.hypot(max(x0 - x, 0.0, x - x1), max(z0 - z, 0.0, z - z1)))
    return d


def _narrow(p: Passable) -> Passable:
    return Passable(p.clearance >= HALF - 1e-9, p.clearance, p.blocked, p.fmap, HALF,
                    p.unknown, p.at)


def test_hand_made_masks_a_straight_run_between_wide_cells_opens_a_bent_one_does_not():
    wide = np.zeros((7, 7), bool)
    narrow = np.zeros((7, 7), bool)
    # a column of narrow cells, rows 1..5, wide at rows 0 and 6: all five opened
    wide[0, 0] = wide[6, 0] = True
    narrow[:, 0] = True
    assert straight_runs(wide, narrow)[:, 0].tolist() == [False] + [True] * 5 + [False]
    # an L: down column 3 from a wide cell, then along row 6 to another; no straight
    # line of narrow cells joins the two wide cells, so nothing is opened
    wide[:] = narrow[:] = False
    wide[0, 3] = wide[6, 6] = True
    narrow[1:7, 3] = True
    narrow[6, 3:6] = True
    assert not straight_runs(wide, narrow).any()
    # a diagonal run from (1, 1) to (5, 5) between wide (0, 0) and (6, 6)
    wide[:] = narrow[:] = False
    wide[0, 0] = wide[6, 6] = True
    narrow[np.arange(1, 6), np.arange(1, 6)] = True
    runs = straight_runs(wide, narrow)
    assert runs.sum() == 5 and runs[np.arange(1, 6), np.arange(1, 6)].all()


def test_the_gap_s_middle_column_alone_is_opened():
    fm = _gap_map()
    p = clearance_map(fm, RADIUS, "blocked")
    runs = straight_runs(p.ok, _narrow(p).ok)
    ii, jj = np.nonzero(runs)
    xs, zs = fm.centre(ii, jj)
    assert set(np.round(xs, 3)) == {GAP_X}
    # it runs through the boxes' rows (z 5..6) and from the last wide cell before
    # them to the first after: every cell of it narrow, none wide
    assert zs.min() < 5.0 and zs.max() > 6.0
    assert not p.ok[runs].any()
    assert all(_true_clearance(x, z) >= HALF for x, z in zip(xs, zs))


def test_the_circle_refuses_the_gap_and_straight_drives_through_it():
    fm = _gap_map()
    est = State(-2.0, 1.0, 30.0)
    goal = (2.0, 10.0)
    # the circle: no way through (the planner heads for the cell nearest the goal)
    pts, _, note = plan(fm, est, goal, DriveConfig(goal=goal))
    assert note.startswith("goal not reachable") and "narrower than the vehicle" in note
    assert pts[-1][1] < 5.0
    pts, cmds, note = plan(fm, est, goal, DriveConfig(goal=goal, passage="straight"))
    assert note == "path to the goal (straight through a narrow way)"
    assert pts[0] == (est.x, est.z) and pts[-1] == goal
    # the corners lie where the pivot circle fits; every point of every leg has the
    # grown half width to the TRUE boxes and walls, sampled each 0.01 ft
    for x, z in pts[1:-1]:
        assert _true_clearance(x, z) >= RADIUS
    for (ax, az), (bx, bz) in zip(pts[:-1], pts[1:]):
        for t in np.linspace(0.0, 1.0, int(math.hypot(bx - ax, bz - az) / 0.01) + 2):
            assert _true_clearance(ax + t * (bx - ax), az + t * (bz - az)) >= HALF
    # the leg through the gap runs along the gap's middle, straight across z 5..6
    through = [(a, b) for a, b in zip(pts[:-1], pts[1:]) if a[1] < 5.0 < 6.0 < b[1]]
    assert len(through) == 1
    (ax, az), (bx, bz) = through[0]
    assert ax == pytest.approx(GAP_X) and bx == pytest.approx(GAP_X)
    assert isinstance(cmds[0], Turn) and all(isinstance(c, (Turn, Forward)) for c in cmds)


def test_a_vehicle_standing_in_the_gap_leaves_it_along_its_heading():
    fm = _gap_map()
    p = clearance_map(fm, RADIUS, "blocked")
    narrow = _narrow(p)
    start = (GAP_X, 5.5)
    ahead = heading_ray(p, narrow.ok, start, 0.0)
    assert ahead and p.ok[ahead[-1]] and not any(p.ok[c] for c in ahead[:-1])
    assert fm.centre(*ahead[-1])[1] > 6.0
    # sideways the way leaves the narrow cells at once
    assert heading_ray(p, narrow.ok, start, 90.0) == []
    q = straight_passable(p, narrow, start, 0.0, (2.0, 10.0))
    assert all(q.ok[c] for c in ahead)


def test_shorten_straight_turns_only_where_the_circle_fits():
    fm = _gap_map()
    p = clearance_map(fm, RADIUS, "blocked")
    narrow = _narrow(p)
    # a staircase through the gap: pulled taut, its corners are wide cells
    raw = [(-2.0, 1.0), (GAP_X, 3.0), (GAP_X, 5.5), (GAP_X, 8.0), (2.0, 10.0)]
    out = shorten_straight(p.ok, narrow, raw)
    assert out[0] == raw[0] and out[-1] == raw[-1]
    for q in out[1:-1]:
        assert p.ok[fm.index(*q)]
    assert (GAP_X, 5.5) not in out


def _forward_through(safe):
    # from (GAP_X, 3.0) facing +z, 4 ft: across the gap (z 5..6) to z 7.0
    got = safe_prefix([Forward(4.0)], State(GAP_X, 3.0, 0.0), safe, np.ones(safe.ok.shape, bool),
                      4.0, None, *DEFAULT.grown_half_ft)
    return sum(c.distance_ft for c in got)


def test_a_forward_move_crosses_the_gap_only_with_the_narrow_cells_allowed():
    fm = _gap_map()
    safe = clearance_map(fm, RADIUS, "blocked", uncertain="blocked")
    assert _forward_through(safe) < 2.0                 # cut before the gap
    safe.narrow = safe.clearance >= HALF - 1e-9
    assert _forward_through(safe) == 4.0


def test_a_forward_move_stops_where_its_grown_nose_would_reach_an_obstacle():
    # the way past the gap closed at z 7.5 by a box across it: a move to z 7.0
    # would end with the vehicle's grown nose (0.65 ft ahead) at 7.65, in the box
    boxes = BOXES + [(-0.75, 1.0, 7.5, 8.0)]
    fm = true_floor_map(boxes, BOUNDS, CELL)
    safe = clearance_map(fm, RADIUS, "blocked", uncertain="blocked")
    safe.narrow = safe.clearance >= HALF - 1e-9
    driven = _forward_through(safe)
    assert driven < 4.0
    # where it stops, the grown nose is short of the box, and it stops past the gap
    assert 3.0 + driven + DEFAULT.grown_half_ft[1] <= 7.5
    assert 3.0 + driven >= 6.0


def test_room_516_is_reached_where_the_circle_stops_short():
    # the defaults, odometry noise seed 516 (bench/drive.py's room 516): under the
    # circle the map leaves the goal nearer an obstacle than the planning radius and
    # 16 looks pass without progress.  Under passage="moves" (the default) the plans
    # are the same, but at look 4 the move toward the goal is no longer cut where the
    # planning radius meets the obstacle's cells (0.9 ft on): its grown width is
    # clear, so it drives the whole 1.5 ft, and two looks later the estimate enters the
    # goal's disc (one look more ends the run inside it, finish="inner"), with no
    # collision of the TRUE footprint with the TRUE room.  The world's exact geometry
    # judges it.
    from rigtools import assert_reached_by_the_truth, bench_drives
    assert DriveConfig.passage == "moves"
    goal, res = bench_drives(516, "passage", ("circle", "moves"))
    circle, moves = res["circle"], res["moves"]
    assert not circle.reached and circle.collisions == 0
    assert "is 0.71 ft" in circle.reason and "from an obstacle" in circle.reason
    assert [c.command for c in circle.cycles[:3]] == [c.command for c in moves.cycles[:3]]
    assert [c.note for c in circle.cycles[:4]] == [c.note for c in moves.cycles[:4]]
    assert circle.cycles[3].command.endswith("FORWARD 0.9")
    assert moves.cycles[3].command.endswith("FORWARD 1.5")
    assert_reached_by_the_truth(moves, goal)
    assert moves.looks == 7


def test_room_401_is_reached_straight_through_once_the_circle_made_no_progress():
    # odometry noise seed 401 (bench/drive.py's room 401): the circle's map leaves the
    # way past (-2.4, 8.1) 1.29 ft, narrower than the vehicle's 1.58; under the
    # defaults ("moves") it stops there.  Under passage="stuck" the vehicle turns to
    # look from (-2.4, 7.3) at looks 10-13 without progress; at the next look
    # (STRAIGHT_AFTER = 4) it plans straight through the narrow way and reaches the
    # goal 3 looks later, with no collision of the TRUE footprint with the TRUE room.
    from planner.loop import STRAIGHT_AFTER
    # (the defaults before 2026-12-06 15:40, as traced)
    from rigtools import DRIVE_BEFORE_2026_12_06_1540, assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(401, "passage", ("moves", "stuck"), **DRIVE_BEFORE_2026_12_06_1540)
    moves, stuck = res["moves"], res["stuck"]
    assert not moves.reached and moves.collisions == 0
    assert "narrower than the vehicle" in moves.reason
    first = next(k for k, c in enumerate(stuck.cycles)
                 if "(straight through a narrow way)" in c.note)
    assert STRAIGHT_AFTER == 4 and first == 13          # look 14
    for c in stuck.cycles[first - STRAIGHT_AFTER:first]:
        assert "FORWARD" not in c.command and "narrower than the vehicle" in c.note
    assert_reached_by_the_truth(stuck, goal)
