"""Where the kept path resumes (issue 11, 2026-12-01; ``DriveConfig.rejoin``):
the to-and-fro that used up the 60 looks of rooms 8 11 12 15 32 34 37 40
(depth eyes, noise off).  A vehicle that drove a short way past a corner of
its kept path was nearer that corner than the next waypoint, so the
``"waypoint"`` rule sent it back to the corner, and from the corner forward
again.  ``"leg"`` (a named option) resumes at the end of the leg nearest
the vehicle.  Hand-made floor maps; every path, length and command derived
by hand."""

import math

import numpy as np
import pytest

from planner.floormap import FloorMap
from planner.loop import DriveConfig
from planner.octree import FREE, OCCUPIED
from planner.planning import REJOINS, _nearest_leg, _still_good, plan
from planner.search import clearance_map, line_of_sight, path_length
from vehicle.commands import Forward, Turn
from vehicle.profile import DEFAULT
from vehicle.sim import State

# an L-shaped kept path: from (-3, 0) east to the corner (0, 0), then north to the goal
CORNER, GOAL = (0.0, 0.0), (0.0, 4.0)
PREV = [(-3.0, 0.0), CORNER, GOAL]


def free_map(n=64):
    """n x n cells of 0.25 ft, all seen free, x and z -8..8 ft."""
    return FloorMap(np.full((n, n), FREE, np.uint8), -n / 8, -n / 8, 0.25)


def passable(fm):
    return clearance_map(fm, DEFAULT.planning_radius_ft, "free")


def test_the_nearest_leg_by_point_to_segment_distance_later_on_a_tie():
    # (0, 0.5): 0.5 ft from leg 0 (its end, the corner), 0 from leg 1
    assert _nearest_leg(PREV, (0.0, 0.5)) == 1
    # (-1, 0.2): 0.2 ft from leg 0, 1 ft from leg 1
    assert _nearest_leg(PREV, (-1.0, 0.2)) == 0
    # on the corner: 0 from both, the later one (the corner counts as passed)
    assert _nearest_leg(PREV, CORNER) == 1


def test_past_the_corner_the_waypoint_rule_goes_back_and_the_leg_rule_on():
    p = passable(free_map())
    s = (0.0, 0.5)                       # 0.5 ft past the corner, on the leg north
    # waypoint: the corner (0.5 ft) is nearer than the goal (3.5 ft): back to it
    back = _still_good(p, PREV, s, "waypoint")
    assert back == [s, CORNER, GOAL]
    assert path_length(back) == pytest.approx(0.5 + 4.0)
    # leg: the nearest leg is the one north; resume at its end
    on = _still_good(p, PREV, s, "leg")
    assert on == [s, GOAL]
    assert path_length(on) == pytest.approx(3.5)
    # before the corner both rules agree: (-1, 0) resumes at the corner
    assert _still_good(p, PREV, (-1.0, 0.0), "waypoint") == \
        _still_good(p, PREV, (-1.0, 0.0), "leg") == [(-1.0, 0.0), CORNER, GOAL]


def test_the_kept_way_back_is_within_keep_ft_so_plan_keeps_it():
    # the new path from (0, 0.5) is the straight 3.5 ft north; the way back
    # 4.5 ft is within keep_ft (3 ft) of it, so "waypoint" keeps it and the
    # first command turns the vehicle round; "leg" drives on 3.5 ft
    fm = free_map()
    est = State(0.0, 0.5, 0.0)           # heading 0: +Z, the leg's direction
    for rule, first in (("waypoint", Turn), ("leg", Forward)):
        cfg = DriveConfig(goal=GOAL, rejoin=rule)
        pts, cmds, note = plan(fm, est, GOAL, cfg, PREV)
        assert note == "path to the goal (kept)"
        assert isinstance(cmds[0], first)
    pts, cmds, _ = plan(fm, est, GOAL, DriveConfig(goal=GOAL, rejoin="waypoint"), PREV)
    assert abs(cmds[0].angle_deg) == pytest.approx(180.0)
    pts, cmds, _ = plan(fm, est, GOAL, DriveConfig(goal=GOAL, rejoin="leg"), PREV)
    assert pts == [(0.0, 0.5), GOAL]
    assert cmds == [Forward(3.5)]


def drive_cut(cmds, state, budget_ft):
    """Execute the commands exactly (pivot turns, straight legs) until
    ``budget_ft`` of forward travel is used: a move cut short, as the loop's
    safe prefix cuts one where the way is not yet seen."""
    x, z, h = state.x, state.z, state.heading_deg
    for c in cmds:
        if isinstance(c, Turn):
            h += c.angle_deg
            continue
        d = min(c.distance_ft, budget_ft)
        x += d * math.sin(math.radians(h))
        z += d * math.cos(math.radians(h))
        budget_ft -= d
        if budget_ft <= 1e-9:
            break
    return State(round(x, 9), round(z, 9), h)


@pytest.mark.parametrize("rule", REJOINS)
def test_moves_cut_at_half_a_foot_oscillate_under_waypoint_and_advance_under_leg(rule):
    # each cycle: plan with the kept path, drive 0.5 ft of it.  From the corner
    # the vehicle goes 0.5 ft north; "waypoint" then sends it back to the
    # corner (turn round, 0.5 ft), and from the corner north again: z 0.5, 0,
    # 0.5, 0 ... for ever.  "leg" goes on: z 0.5, 1.0, ... 3.5 (the goal's
    # tolerance, 0.75 ft, reached at z 3.5).
    fm = free_map()
    state, prev = State(0.0, 0.0, 0.0), PREV
    zs = []
    for _ in range(8):
        if math.hypot(state.x - GOAL[0], state.z - GOAL[1]) <= 0.75:
            break
        pts, cmds, _ = plan(fm, state, GOAL, DriveConfig(goal=GOAL, rejoin=rule), prev)
        prev = pts
        state = drive_cut(cmds, state, 0.5)
        assert state.x == pytest.approx(0.0, abs=1e-9)
        zs.append(round(state.z, 6))
    if rule == "waypoint":
        assert zs == [0.5, 0.0] * 4
    else:
        assert zs == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5]


def test_a_blocked_kept_path_is_abandoned_under_either_rule():
    # a box across the leg north at z 2..2.5, x -0.5..0.5: the kept path is no
    # longer passable, so plan replans round it
    fm = free_map()
    i0, j0 = fm.index(-0.5, 2.0)
    fm.cells[i0:i0 + 2, j0:j0 + 4] = OCCUPIED
    p = passable(fm)
    s = (0.0, 0.5)
    for rule in REJOINS:
        assert _still_good(p, PREV, s, rule) is None
        pts, cmds, note = plan(fm, State(*s, 0.0), GOAL, DriveConfig(goal=GOAL, rejoin=rule),
                               PREV)
        assert note == "path to the goal (replanned)"
        assert pts[0] == s and pts[-1] == GOAL and len(pts) > 2
        assert all(line_of_sight(p, a, b) for a, b in zip(pts[:-1], pts[1:]))
        # round the box: every point of the new path at least the planning
        # radius from the box's true rectangle (sampled every 0.05 ft)
        for a, b in zip(pts[:-1], pts[1:]):
            for t in np.linspace(0.0, 1.0, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.05) + 2):
                x, z = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
                dx, dz = max(-0.5 - x, 0.0, x - 0.5), max(2.0 - z, 0.0, z - 2.5)
                assert math.hypot(dx, dz) >= DEFAULT.planning_radius_ft - 1e-9


def test_the_leg_rule_does_not_keep_a_path_whose_way_on_is_not_in_sight():
    # the vehicle at (1.5, 0.3): 1.5 ft from the leg north, 1.53 from the leg
    # east, so the leg north is nearest; a box x 1.25..2.25, z 1.5..2.0 (grown
    # by the planning radius 0.79 ft) lies across its straight line to the
    # leg's end, the goal (it crosses z 0.71 at x 1.33).  The corner is in
    # sight (the line to it stays 1.2 ft south of the box) and the leg north
    # is clear (x 0..0.25 is 1 ft from the box), but going back to the corner
    # is not kept: the path is dropped and plan searches anew
    fm = free_map()
    i0, j0 = fm.index(1.25, 1.5)
    fm.cells[i0:i0 + 2, j0:j0 + 4] = OCCUPIED
    p = passable(fm)
    s = (1.5, 0.3)
    assert _nearest_leg(PREV, s) == 1
    assert not line_of_sight(p, s, GOAL)
    assert line_of_sight(p, s, CORNER) and line_of_sight(p, CORNER, GOAL)
    assert _still_good(p, PREV, s, "leg") is None
    # the waypoint rule resumes at the nearest waypoint, the corner (1.53 ft; the goal 3.99)
    assert _still_good(p, PREV, s, "waypoint") == [s, CORNER, GOAL]
    _, _, note = plan(fm, State(*s, 0.0), GOAL, DriveConfig(goal=GOAL, rejoin="leg"), PREV)
    assert note == "path to the goal (replanned)"


def test_an_unknown_rule_is_one_clear_error():
    with pytest.raises(ValueError, match="unknown rejoin 'nearest'; one of waypoint, leg"):
        _still_good(passable(free_map()), PREV, (0.0, 0.5), "nearest")
    # plan refuses it on the first cycle, before any path is kept
    with pytest.raises(ValueError, match="unknown rejoin 'nearest'"):
        plan(free_map(), State(0.0, 0.5, 0.0), GOAL, DriveConfig(goal=GOAL, rejoin="nearest"))


# --- planning round the blind zone (DriveConfig.blind_zone, a named option) ------------

NEAR = 2.3            # near_visible_ft of the default profile, rounded (2.31 ft)
HALF = DEFAULT.width_ft / 2 + DEFAULT.margin_ft    # 0.55 ft


def test_the_blind_zone_closes_the_cells_beside_a_near_unseen_cell():
    # an unseen cell x 0.5..0.75, z 1.0..1.25 (centre 1.29 ft from the vehicle,
    # inside 2.3 ft): a cell k columns / l rows away is closed when its nearest
    # point, (max(|k| - 0.5, 0), max(|l| - 0.5, 0)) cells, lies within 0.55 ft
    # = 2.2 cells of that centre: |k|, |l| <= 2 (2 and 2: 1.5^2 + 1.5^2 = 4.5 <=
    # 4.84), not 3 (2.5^2 = 6.25)
    from planner.octree import UNKNOWN
    from planner.planning import avoid_blind
    fm = free_map()
    i0, j0 = fm.index(0.6, 1.1)
    fm.cells[i0, j0] = UNKNOWN
    p = passable(fm)
    q = avoid_blind(p, (0.0, 0.0), NEAR, HALF)
    closed = p.ok & ~q.ok
    ii, jj = np.nonzero(closed)
    assert (ii.min(), ii.max(), jj.min(), jj.max()) == (i0 - 2, i0 + 2, j0 - 2, j0 + 2)
    assert closed.sum() == 25 - (~p.ok[i0 - 2:i0 + 3, j0 - 2:j0 + 3]).sum()
    # the same cell 3.1 ft away is no blind spot: a look from here can show it
    fm2 = free_map()
    fm2.cells[fm2.index(0.1, 3.1)] = UNKNOWN
    p2 = passable(fm2)
    assert (avoid_blind(p2, (0.0, 0.0), NEAR, HALF).ok == p2.ok).all()
    # the start's own cell keeps its state even beside an unseen cell
    fm3 = free_map()
    fm3.cells[fm3.index(0.3, 0.1)] = UNKNOWN
    p3 = passable(fm3)
    si, sj = fm3.index(0.0, 0.0)
    assert avoid_blind(p3, (0.0, 0.0), NEAR, HALF).ok[si, sj] == p3.ok[si, sj]


def test_blind_zone_plans_round_a_near_unseen_cell_or_as_before_when_it_cannot():
    # the goal 5 ft north; an unseen cell x 0..0.25, z 1.0..1.25 on the straight way.
    # Without the option the path is straight through it (unknown plans free);
    # with it every point of the path stays more than 0.55 ft - half a cell
    # diagonal from that cell's centre (0.125, 1.125)
    from planner.octree import UNKNOWN
    fm = free_map()
    fm.cells[fm.index(0.1, 1.1)] = UNKNOWN
    est, goal = State(0.0, 0.0, 0.0), (0.0, 5.0)
    plain, _, _ = plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="off"))
    assert plain == [(0.0, 0.0), goal]
    round_, _, _ = plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="any"))
    assert round_ != plain and round_[0] == (0.0, 0.0) and round_[-1] == goal
    for a, b in zip(round_[:-1], round_[1:]):
        for t in np.linspace(0.0, 1.0, 200):
            x, z = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
            assert math.hypot(x - 0.125, z - 1.125) > HALF - 0.25 * math.sqrt(2) / 2
    # unseen cells all round the vehicle at 1 ft: no path avoids them, so the plan is as without
    ring = free_map()
    ii, jj = np.indices(ring.shape)
    cx, cz = ring.centre(ii, jj)
    ring.cells[np.abs(np.hypot(cx, cz) - 1.0) < 0.15] = UNKNOWN
    assert plan(ring, est, goal, DriveConfig(goal=goal, blind_zone="any"))[0] == \
        plan(ring, est, goal, DriveConfig(goal=goal, blind_zone="off"))[0]


def test_blind_zone_short_takes_the_way_round_only_within_keep_ft():
    # an unseen bar z 1.0..1.25 across x -2.25..2.25 (every cell centre within
    # 2.3 ft of the vehicle but the two end ones, 2.40 ft), continued by walls
    # of occupied cells to the map's west edge and east to x 5: the way round
    # the bar's grown cells runs east of x 5, 13 ft or more (up to the wall's
    # end and back: 5 + 5 ft at least, plus the 4 ft north), against 5 ft
    # straight through.  "any" takes it; "short" (more than keep_ft = 3 ft
    # longer) plans straight as without the option.
    from planner.octree import UNKNOWN
    fm = free_map()
    i0, _ = fm.index(0.0, 1.1)
    xs = fm.centre(0, np.arange(fm.shape[1]))[0]
    fm.cells[i0, (xs > -2.25) & (xs < 2.25)] = UNKNOWN
    fm.cells[i0, (xs < -2.25) | ((xs > 2.25) & (xs < 5.0))] = OCCUPIED
    est, goal = State(0.0, 0.0, 0.0), (0.0, 5.0)
    plain, _, _ = plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="off"))
    assert plain == [(0.0, 0.0), goal]
    any_, _, _ = plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="any"))
    assert path_length(any_) > 5.0 + 3.0 and max(x for x, _ in any_) > 5.0
    assert plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="short"))[0] == plain
    with pytest.raises(ValueError, match="unknown blind_zone 'on'; one of off, any, short"):
        plan(fm, est, goal, DriveConfig(goal=goal, blind_zone="on"))


def test_a_plan_searches_no_map_twice_for_the_same_ends(monkeypatch):
    """blind_zone="short" compares the way round with the plain way, then
    plans: each map is searched once for each pair of ends, and the paths are
    those of the same plan searched every time."""
    import planner.planning as planning
    from planner.octree import UNKNOWN
    fm = free_map()
    i0, _ = fm.index(0.0, 1.1)
    xs = fm.centre(0, np.arange(fm.shape[1]))[0]
    fm.cells[i0, (xs > -0.75) & (xs < 0.75)] = UNKNOWN     # a short bar: the way round is kept
    est, goal = State(0.0, 0.0, 0.0), (0.0, 5.0)
    calls = []
    search = planning.SEARCHES["dissertation"]

    def counted(p, a, b):
        calls.append((id(p), tuple(a), tuple(b)))
        return search(p, a, b)
    monkeypatch.setitem(planning.SEARCHES, "dissertation", counted)
    for zone in ("short", "any", "off"):
        calls.clear()
        pts, _, _ = plan(fm, est, goal, DriveConfig(goal=goal, blind_zone=zone))
        assert len(calls) == len(set(calls)) >= 1, zone
        assert pts[0] == (0.0, 0.0) and pts[-1] == goal
        if zone == "short":
            assert len(calls) == 2                      # the way round and the plain way
