"""What the floor map covers (``DriveConfig.map_extent``, :func:`planner.loop.map_around`):
under ``"seen"`` every hit so far, the estimate and the goal, 2 ft round, its border
blocking the search; under ``"walls"`` (a named option) the room's floor plan as well;
``"fallback"`` (the default since 2026-12-05) the seen map, or the walls' one in a cycle
where only that has a way.  Rooms 26 and 99 on depth eyes drove into a dead end because
the way round the far side of a box lay off the map.  Hand-made maps; every extent and
bound derived by hand (and bench rooms driven both ways)."""

import math

import numpy as np
import pytest

from planner.evidence import Perception, mark_walls
from planner.floormap import empty_map
from planner.loop import Drive, DriveConfig, MAP_EXTENTS, _check_config, map_around
from planner.motion import mark_track_free
from planner.octree import OCCUPIED, UNKNOWN, VolumeOfInterest, mark_occupied
from planner.planning import plan
from planner.search import clearance_map
from vehicle.profile import DEFAULT
from vehicle.sim import State
from world.room import Room

ROOM = (-6.0, 6.0, -2.0, 12.0)          # the floor plan: x0, x1, z0, z1 (ft)
START, GOAL = State(0.0, 0.0, 0.0), (0.0, 9.0)
# a barrier from the left wall to x = 3 ft, z 5..5.25 ft: the way to the goal is round
# its right end, between it and the right wall (3 ft: 12 free cells of 0.25 ft)
BARRIER = (-6.0, 3.0, 5.0, 5.25)
R = DEFAULT.planning_radius_ft          # 0.79 ft


def test_map_around_adds_the_floor_plan_only_under_walls():
    assert map_around(START, GOAL, ROOM, "seen") == [(0.0, 0.0), (0.0, 9.0)]
    assert map_around(START, GOAL, ROOM, "walls") == [(0.0, 0.0), (0.0, 9.0),
                                                      (-6.0, -2.0), (6.0, 12.0)]
    with pytest.raises(ValueError, match="unknown map_extent 'room'"):
        map_around(START, GOAL, ROOM, "room")


def test_the_floor_map_of_a_model_without_hits_covers_what_map_around_gives():
    # no hits yet: "seen" covers the estimate and the goal 2 ft round; "walls" the
    # whole plan 2 ft round (the 0.25 ft cells align with both)
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=8.0)
    seen = m.floor_map(map_around(START, GOAL, ROOM, "seen"))
    walls = m.floor_map(map_around(START, GOAL, ROOM, "walls"))
    assert seen.extent() == pytest.approx((-2.0, 2.0, -2.0, 11.0))
    assert walls.extent() == pytest.approx((-8.0, 8.0, -4.0, 14.0))
    assert (walls.cells == UNKNOWN).all()


def _barrier_map(bounds):
    """UNKNOWN cells over ``bounds``, the barrier's cells OCCUPIED, the plan's walls marked."""
    fm = empty_map(bounds, 0.25, 0.0)
    x0, x1, z0, z1 = BARRIER
    i0, j0 = fm.index(x0 + 1e-6, z0 + 1e-6)
    i1, j1 = fm.index(x1 - 1e-6, z1 - 1e-6)
    fm.cells[i0:i1 + 1, j0:j1 + 1] = OCCUPIED
    mark_walls(fm, ROOM)
    return fm


def test_off_the_seen_map_there_is_no_way_round_and_with_the_walls_there_is():
    # "seen": the barrier's hits (x -6..3, z 5..5.25), the start and the goal, 2 ft
    # round: x -8..5.  Right of the barrier 3..5 ft is 8 free cells to the map's border,
    # one fewer than the 9 the 1.58 ft vehicle needs: no path, so the loop heads for
    # the reachable cell nearest the goal, below the barrier
    cfg = DriveConfig(goal=GOAL)
    seen = _barrier_map((-8.0, 5.0, -2.0, 11.0))
    assert seen.extent() == pytest.approx((-8.0, 5.0, -2.0, 11.0))
    p = clearance_map(seen, R, "free", uncertain="blocked")
    row, end = seen.index(BARRIER[1], 5.125)       # the barrier's row, x 3..3.25 on
    assert not p.ok[row, end:].any()
    pts, _, note = plan(seen, START, GOAL, cfg)
    assert note.startswith("goal not reachable")
    assert pts[-1][1] < BARRIER[2] - R          # the target: short of the barrier
    # "walls": the map reaches the plan (x -8..8, the cells past x = 6 occupied): 3 ft,
    # 12 cells, right of the barrier: the path goes round its right end
    walls = _barrier_map((-8.0, 8.0, -4.0, 14.0))
    pts, _, note = plan(walls, START, GOAL, DriveConfig(goal=GOAL, map_extent="walls"))
    assert note == "path to the goal"
    assert tuple(pts[-1]) == GOAL
    # the first cell passable in the barrier's row (z 5..5.25) right of its end is
    # x 4..4.25: its centre 5 cells from the end cell's, less the bound's diagonal,
    # (5 - sqrt 2) x 0.25 = 0.896 ft >= R; the cell before it (4 - sqrt 2) x 0.25 =
    # 0.646 ft < R.  So the path crosses z = 5.125 at x >= 4, and no path is shorter
    # than through (4, 5.125): 6.501 + 5.569 = 12.070 ft
    p = clearance_map(walls, R, "free", uncertain="blocked")
    row = walls.index(0.0, 5.125)[0]
    ok_x = [float(walls.centre(row, j)[0]) for j in range(walls.shape[1]) if p.ok[row, j]]
    assert ok_x == pytest.approx([4.125, 4.375, 4.625, 4.875])
    low = math.hypot(4.0, 5.125) + math.hypot(4.0, 9.0 - 5.125)
    assert low == pytest.approx(12.070, abs=1e-3)

    def crossing(pts):
        return [a[0] + (b[0] - a[0]) * (5.125 - a[1]) / (b[1] - a[1])
                for a, b in zip(pts[:-1], pts[1:]) if (a[1] - 5.125) * (b[1] - 5.125) <= 0]
    assert crossing(pts) and min(crossing(pts)) >= 4.0
    assert sum(math.dist(a, b) for a, b in zip(pts[:-1], pts[1:])) >= low
    # A* on the same map: within 0.6 ft of the bound (the dissertation's search,
    # hierarchical, is longer: 13.44 ft here, through (4.5, 5) and (2, 9))
    best, _, _ = plan(walls, START, GOAL, DriveConfig(goal=GOAL, map_extent="walls",
                                                      search="astar"))
    assert min(crossing(best)) >= 4.0
    assert low <= sum(math.dist(a, b) for a, b in zip(best[:-1], best[1:])) <= low + 0.6
    # and every point of it stays inside the walls by the radius
    assert all(ROOM[0] + R <= x <= ROOM[1] - R and ROOM[2] + R <= z <= ROOM[3] - R
               for x, z in pts)


def test_walls_needs_the_floor_plan_and_an_unknown_extent_is_one_clear_error():
    with pytest.raises(ValueError, match="map_extent 'walls' needs known_walls"):
        _check_config(DriveConfig(goal=GOAL, map_extent="walls", known_walls=False))
    with pytest.raises(ValueError, match="map_extent 'fallback' needs known_walls"):
        _check_config(DriveConfig(goal=GOAL, map_extent="fallback", known_walls=False))
    with pytest.raises(ValueError,
                       match="unknown map_extent 'room'; one of seen, walls, fallback"):
        _check_config(DriveConfig(goal=GOAL, map_extent="room"))
    assert MAP_EXTENTS == ("seen", "walls", "fallback")
    _check_config(DriveConfig(goal=GOAL, map_extent="walls"))
    _check_config(DriveConfig(goal=GOAL, map_extent="fallback"))
    assert DriveConfig(goal=GOAL).map_extent == "fallback"     # the default since 2026-12-05


def _drive(extent, barrier=True, by_goal=False, **how):
    """A Drive in the plan ROOM whose model holds the barrier's cells (and with
    ``by_goal`` the cell x 0..0.25, z 9.5..9.75 beside the goal), hit twice (confirmed)
    at a height inside the vehicle's band, as a look's hits enter it under
    ``occupied="looks"`` (the per-look octree the cells are written into; the fused
    features of the default draw theirs each cycle); ``how``: more DriveConfig fields."""
    room = Room("barrier", (), np.zeros((0, 3)), np.zeros((0, 2, 3)),
                np.array([BARRIER] if barrier else np.zeros((0, 4))), ROOM)
    d = Drive(room, START, DriveConfig(goal=GOAL, map_extent=extent,
                                       **{"occupied": "looks", "fine_map": "off", **how}),
              None, False,
              Perception)
    xz = np.zeros((0, 2))
    if barrier:
        xs = np.arange(BARRIER[0] + 0.125, BARRIER[1], 0.25)       # the cells' centres
        xz = np.c_[xs, np.full_like(xs, 5.125)]
    if by_goal:
        xz = np.vstack([xz, [(0.125, 9.625)]])
    centres = np.c_[xz[:, 0], np.full(len(xz), 2.0), xz[:, 1]]
    for _ in range(d.cfg.confirm_looks):
        mark_occupied(d.model.tree, centres)
    d.model._extend(xz)
    return d


def _set_down(fm):
    """The cells of ``fm`` with the clear spot the vehicle is set down in free (as the
    loop marks its track: the footprint grown by start_clear_ft), the walls marked after."""
    mark_track_free(fm, [START], DEFAULT.footprint, DriveConfig.start_clear_ft)
    mark_walls(fm, ROOM)
    return fm.cells


def test_fallback_plans_on_the_walls_map_only_where_the_seen_map_has_no_way():
    # the model's own map over what was seen is the hand-made one above: x -8..5
    for extent in ("seen", "fallback"):
        d = _drive(extent)
        fm = d.drawn_map(START, "seen")
        assert fm.extent() == pytest.approx((-8.0, 5.0, -2.0, 11.0))
        assert (fm.cells == _set_down(_barrier_map((-8.0, 5.0, -2.0, 11.0)))).all()
        used = d.map_to_plan_on(fm, START)
        if extent == "seen":
            assert used is fm                     # the default: as before
        else:
            # no way on it: the map out to the walls, where the way round exists
            assert used.extent() == pytest.approx((-8.0, 8.0, -4.0, 14.0))
            assert (used.cells == _set_down(_barrier_map((-8.0, 8.0, -4.0, 14.0)))).all()
            assert plan(used, START, GOAL, d.cfg)[2] == "path to the goal"
    # where the seen map has a way to the goal, fallback keeps it
    d = _drive("fallback", barrier=False)
    fm = d.drawn_map(START, "seen")
    assert d.map_to_plan_on(fm, START) is fm


def test_fallback_keeps_the_seen_map_where_the_walls_map_refuses_the_goal_too():
    # an obstacle cell beside the goal: its centre 2 cells from the goal cell's, (2 -
    # sqrt 2) x 0.25 = 0.146 ft by the bound, under R: the goal refused on either map,
    # so the wider map would only move the nearest reachable cell; the seen one stays
    # (planned to as a point: the goal's disc, the default since 2026-12-05, has a standable
    # cell in it on either map, so neither refuses the goal)
    d = _drive("fallback", by_goal=True, goal_region="point")
    fm = d.drawn_map(START, "seen")
    wide = d.drawn_map(START, "walls")
    for m in (fm, wide):
        assert plan(m, START, GOAL, d.cfg)[2].startswith("goal not reachable (the goal")
    assert d.map_to_plan_on(fm, START) is fm
    # planned to its disc the goal is not refused on the map out to the walls, which has a
    # standable cell of the disc the vehicle's reaches: the fallback takes that map
    disc = _drive("fallback", by_goal=True)
    assert disc.cfg.goal_region == "disc"
    fm, wide = disc.drawn_map(START, "seen"), disc.drawn_map(START, "walls")
    assert plan(fm, START, GOAL, disc.cfg)[2].startswith("goal not reachable")
    assert plan(wide, START, GOAL, disc.cfg)[2].startswith("path to the goal")
    assert disc.map_to_plan_on(fm, START) is not fm


def test_plan_walls_grown_by_two_sigma_of_the_estimate():
    """``plan_walls="grown"``: the map is placed by the estimate, the plan by the truth;
    with the estimate's x uncertain by sigma 0.3 ft and z by 0.1 ft, the side walls come
    0.6 ft nearer and the near and far walls 0.2 ft; "plan" draws them where they are."""
    room = Room("plan", (), np.zeros((0, 3)), np.zeros((0, 2, 3)), np.zeros((0, 4)), ROOM)
    cells = {}
    for how in ("plan", "grown"):
        d = Drive(room, START, DriveConfig(goal=GOAL, plan_walls=how, map_extent="walls"),
                  None, False, Perception)
        d.dead_cov = np.diag([0.3 ** 2, 0.1 ** 2, 0.0])
        fm = d.drawn_map(START, "walls")
        xs = fm.x0 + (np.arange(fm.shape[1]) + 0.5) * fm.cell
        zs = fm.z0 + (np.arange(fm.shape[0]) + 0.5) * fm.cell
        row = fm.cells[int((0.0 - fm.z0) / fm.cell)]        # across the room at z = 0.1
        col = fm.cells[:, int((0.0 - fm.x0) / fm.cell)]     # along it at x = 0.1
        cells[how] = (xs[row != OCCUPIED], zs[col != OCCUPIED])
    x0, x1, z0, z1 = ROOM
    px, pz = cells["plan"]
    gx, gz = cells["grown"]
    assert px.min() == pytest.approx(x0 + 0.125) and px.max() == pytest.approx(x1 - 0.125)
    # a cell is free only wholly inside the grown plan, and the first such is within a cell
    for lo, hi, g, free in ((x0, x1, 0.6, gx), (z0, z1, 0.2, gz)):
        assert lo + g <= free.min() - 0.125 < lo + g + 0.25
        assert hi - g - 0.25 < free.max() + 0.125 <= hi - g
    assert pz.min() == pytest.approx(z0 + 0.125)
    with pytest.raises(ValueError, match="plan_walls"):
        _check_config(DriveConfig(goal=GOAL, plan_walls="inset"))


def test_room_538_reached_round_the_far_side_where_the_seen_map_stops():
    """Bench room 538 (noise seed 538; the task leaves a quarter foot to spare): on the seen
    map alone the way out is narrower than the vehicle and the drive stops after 16
    looks without progress; with the map out to the walls where the seen one has no
    way (the default since 2026-12-05 16:30) it goes round the far side and reaches
    the goal, by its true pose too, without a collision (the world's exact geometry).
    Both under ``uncertain="blocked"``, the default then: under "core" the seen map's
    run plans past the narrow way's once-seen features and uses up the 24 looks."""
    from rigtools import DRIVE_BEFORE_2026_12_06_1540, assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(538, "map_extent", ("seen", "fallback"), uncertain="blocked",
                             **{**DRIVE_BEFORE_2026_12_06_1540, "max_looks": 24})
    seen, fallback = res["seen"], res["fallback"]
    assert not seen.reached and "narrower than the vehicle" in seen.reason, seen.reason
    assert seen.collisions == 0
    assert_reached_by_the_truth(fallback, goal)


def test_the_seen_maps_plan_is_searched_once_a_cycle(monkeypatch):
    # the fallback asks whether the seen map has a way, then the cycle plans on it: the
    # same map, estimate and kept path give the same answer, so the search runs once
    import planner.loop as loop
    calls = []

    def counted(*args):
        calls.append(args[0])
        return plan(*args)
    monkeypatch.setattr(loop, "plan_path", counted)
    d = _drive("fallback", barrier=False)
    fm = d.drawn_map(START, "seen")
    assert d.map_to_plan_on(fm, START) is fm and len(calls) == 1
    pts, cmds, note = d._plan_on(fm, START)
    assert len(calls) == 1
    assert (pts, cmds, note) == plan(fm, START, GOAL, d.cfg)
    d.prev_path = pts                         # a kept path (or a new map, a new estimate):
    d._plan_on(fm, START)                     # searched again
    d._plan_on(d.drawn_map(START, "seen"), START)
    d._plan_on(fm, State(0.0, 0.25, 0.0))
    assert len(calls) == 4
    # the seen map without a way: the walls' map is searched, and the cycle's plan on
    # it is that search
    blocked = _drive("fallback")
    calls.clear()
    wide = blocked.map_to_plan_on(blocked.drawn_map(START, "seen"), START)
    assert len(calls) == 2 and calls[-1] is wide
    assert blocked._plan_on(wide, START)[2] == "path to the goal" and len(calls) == 2
