"""The loop's behaviour when the way lacks evidence (planner.loop): where the
path's execution would stop (_blocker), a place a look there shows from
(_viewpoint), the commands that fetch that look (fetch_evidence), and the plan
through uncertain cells (plan, ``uncertain="look"``).  All on hand-made floor
maps with 0.25 ft cells, checked against their own geometry."""

import math

import numpy as np
import pytest

from planner.floormap import FloorMap
from planner.loop import DriveConfig
from planner.motion import PivotSweep, _blocker, fetch_evidence, _viewpoint, near_visible_ft
from planner.planning import plan
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN
from planner.search import clearance_map
from planner.trajectory import polyline
from vehicle.profile import DEFAULT
from vehicle.sim import State
from rigtools import STEP_BACK_FT

R = DEFAULT.planning_radius_ft
NEAR = near_visible_ft(DEFAULT, 0.8)            # 2.33 ft: nearer, a look shows nothing


def corridor_map():
    """A 20 x 20 ft map: unknown everywhere but a seen-free corridor 4 ft wide
    along z from -8 to +2 ft about x = 0 (cells -2 <= x < 2)."""
    cells = np.full((80, 80), UNKNOWN, np.uint8)
    fm = FloorMap(cells, -10.0, -10.0, 0.25)
    i0, _ = fm.index(0.0, -8.0)
    i1, _ = fm.index(0.0, 2.0)
    _, j0 = fm.index(-2.0, 0.0)
    _, j1 = fm.index(2.0, 0.0)
    cells[i0:i1, j0:j1] = FREE
    return fm


def cell_states_along(fm, pts):
    out = set()
    for a, b in zip(pts[:-1], pts[1:]):
        for t in np.linspace(0, 1, 50):
            x, z = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
            out.add(int(fm.cells[fm.index(x, z)]))
    return out


def test_blocker_is_the_first_cell_not_seen_free_on_the_path():
    fm = corridor_map()
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    # straight up the corridor and on into the unknown beyond z = 2
    u = _blocker(fm, safe, [(0.0, -6.0), (0.0, 6.0)], NEAR)
    assert u is not None
    assert u[0] == pytest.approx(0.125) or u[0] == pytest.approx(-0.125)
    assert u[1] == pytest.approx(2.125)               # the first row of unknown cells
    # a path wholly inside the corridor, clear of its sides, has no blocker
    assert _blocker(fm, safe, [(0.0, -6.0), (0.0, -1.0)], NEAR) is None


def test_blocker_is_an_uncertain_cell_within_the_radius_of_the_path():
    fm = corridor_map()
    i, j = fm.index(0.9, -3.0)
    fm.cells[i, j] = UNCERTAIN                        # 0.9 ft beside the path: within R
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    u = _blocker(fm, safe, [(0.0, -6.0), (0.0, -1.0)], NEAR)
    assert u == pytest.approx(fm.centre(i, j))


def test_viewpoint_is_reached_through_seen_free_space_at_a_distance_a_look_shows():
    fm = corridor_map()
    seen_only = clearance_map(fm, R, "blocked", uncertain="blocked")
    target = (0.125, 2.125)
    est = State(0.0, 1.0, 0.0)                        # 1.1 ft from it: too near to see it
    vp = _viewpoint(fm, seen_only, est, target, NEAR, [])
    assert vp is not None and len(vp) >= 2
    d = math.hypot(vp[-1][0] - target[0], vp[-1][1] - target[1])
    assert NEAR + 0.3 <= d <= NEAR + 2.0
    assert cell_states_along(fm, vp) == {FREE}        # never through space not seen free
    # a place already looked from is not chosen again
    vp2 = _viewpoint(fm, seen_only, est, target, NEAR, [vp[-1]])
    assert math.hypot(vp2[-1][0] - vp[-1][0], vp2[-1][1] - vp[-1][1]) > 0.5


def test_fetch_evidence_backs_off_to_look_at_what_is_too_near_to_see():
    """The vehicle 1 ft short of the unknown, facing it: a look from here shows
    nothing nearer than 2.33 ft, so it drives (turning round: forward only)
    through seen-free space to where the first unknown cell shows, then turns
    to it and looks (up to three looks from one place)."""
    fm = corridor_map()
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    seen = fm.cells != UNKNOWN
    cfg = DriveConfig(goal=(0.0, 8.0))
    est = State(0.0, 1.0, 0.0)
    tried = {}
    seg, note = fetch_evidence(fm, safe, seen, est, [(0.0, 1.0), (0.0, 8.0)], NEAR, DEFAULT,
                                cfg, tried)
    assert "to look at (0.1, 2.1)" in note or "to look at (-0.1, 2.1)" in note
    where = polyline(seg, est.x, est.z, est.heading_deg)
    assert cell_states_along(fm, where) == {FREE}
    # forward only: it first turns round (and looks before driving the new way) ...
    assert len(seg) == 1 and abs(seg[0].angle_deg) > 120
    turned = State(est.x, est.z, est.heading_deg + seg[0].angle_deg)
    seg, note = fetch_evidence(fm, safe, seen, turned, [(0.0, 1.0), (0.0, 8.0)], NEAR, DEFAULT,
                                cfg, tried)
    # ... then drives away from the unknown
    where = polyline(seg, turned.x, turned.z, turned.heading_deg)
    assert cell_states_along(fm, where) == {FREE}
    u = (0.0, 2.125)
    assert math.hypot(where[-1][0] - u[0], where[-1][1] - u[1]) > 2.0
    # standing where it shows, facing it: look again, no motion
    there = State(0.0, 2.125 - NEAR - 0.5, 0.0)
    seg, note = fetch_evidence(fm, safe, seen, there, [(there.x, there.z), (0.0, 8.0)], NEAR,
                                DEFAULT, cfg, tried)
    assert seg == [] and "looking again" in note
    # facing away: turn to it
    away = State(there.x, there.z, 90.0)
    seg, note = fetch_evidence(fm, safe, seen, away, [(away.x, away.z), (0.0, 8.0)], NEAR,
                                DEFAULT, cfg, {})
    assert len(seg) == 1 and seg[0].angle_deg == pytest.approx(-90.0, abs=5.0)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_the_evidence_looks_again_from_one_place_looks_per_viewpoint_times(n):
    """Standing where the corridor's blocker (0, 2.125) shows, facing it:
    ``DriveConfig.looks_per_viewpoint`` (default 3) calls in a row look again
    with no motion, the next one drives off to another place to see it from."""
    fm = corridor_map()
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    seen = fm.cells != UNKNOWN
    cfg = DriveConfig(goal=(0.0, 8.0), looks_per_viewpoint=n)
    there = State(0.0, 2.125 - NEAR - 0.5, 0.0)
    tried = {}
    for _ in range(n):
        seg, note = fetch_evidence(fm, safe, seen, there, [(there.x, there.z), (0.0, 8.0)],
                                    NEAR, DEFAULT, cfg, tried)
        assert seg == [] and "looking again at (-0.1, 2.1)" in note
    seg, note = fetch_evidence(fm, safe, seen, there, [(there.x, there.z), (0.0, 8.0)], NEAR,
                                DEFAULT, cfg, tried)
    assert seg and "looking again" not in note and "to look at (-0.1, 2.1) from" in note
    assert DriveConfig.looks_per_viewpoint == 3
    with pytest.raises(ValueError, match="looks_per_viewpoint 0"):
        from planner.loop import _check_config
        _check_config(DriveConfig(goal=(0.0, 8.0), looks_per_viewpoint=0))


def test_plan_passes_uncertain_cells_only_when_no_way_avoids_them():
    """A wall across the map with one gap, an uncertain cell in the gap: the
    dissertation's plan (uncertain blocked) finds no way; ``uncertain="look"``
    plans through the gap to look again; the executed moves still treat the
    cell as an obstacle (the safe map blocks it).  (A map with no features'
    core drawn: "core", the default, plans as "blocked".)"""
    cells = np.full((60, 60), FREE, np.uint8)
    fm = FloorMap(cells, -7.5, -7.5, 0.25)
    i, _ = fm.index(0.0, 0.0)
    cells[i, :] = OCCUPIED
    _, j0 = fm.index(-1.5, 0.0)
    _, j1 = fm.index(1.5, 0.0)
    cells[i, j0:j1] = FREE                            # a 3 ft gap
    gi, gj = fm.index(0.0, 0.0)
    cells[gi, gj] = UNCERTAIN                         # a possible obstacle in it
    est = State(0.0, -5.0, 0.0)
    goal = (0.0, 5.0)
    _, _, note = plan(fm, est, goal, DriveConfig(goal=goal))          # the default
    assert note.startswith("goal not reachable")     # toward the reachable cell nearest it
    pts, cmds, note = plan(fm, est, goal, DriveConfig(goal=goal, uncertain="look"))
    assert "through uncertain cells" in note
    assert min(abs(p[1]) for p in pts) < 1.0 or len(pts) == 2      # it goes through the gap
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    assert not safe.ok[gi, gj]
    with pytest.raises(ValueError, match="unknown uncertain-cell plan"):
        plan(fm, est, goal, DriveConfig(goal=goal, uncertain="maybe"))


def test_back_prefix_backs_over_seen_free_space_only():
    """BACK along the heading over the corridor (seen free), cut where the
    tail would reach the unknown below z = -8 ft; none for a vehicle that
    cannot reverse."""
    from planner.motion import back_prefix
    from vehicle.commands import Back
    fm = corridor_map()
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    seen = fm.cells != UNKNOWN
    assert back_prefix(State(0.0, 0.0, 0.0), 1.0, safe, seen, DEFAULT) == [Back(1.0)]
    seg = back_prefix(State(0.0, -6.5, 0.0), 1.5, safe, seen, DEFAULT)
    tail = DEFAULT.length_ft / 2 + DEFAULT.margin_ft
    assert len(seg) == 1 and isinstance(seg[0], Back)
    assert -6.5 - seg[0].distance_ft - tail >= -8.0 - 1e-6          # the tail stays seen
    assert seg[0].distance_ft > 0.5
    assert back_prefix(State(0.0, -7.3, 0.0), 1.0, safe, seen, DEFAULT) == []


def test_forward_to_turn_moves_on_until_the_pivot_clears_a_never_seen_notch(monkeypatch, tmp_path):
    """``turn_room="forward"``: in the corridor, with the cells x 0.75..1.25, z -7..-6.5
    never seen, a vehicle at (0, -6.5) facing +z may not pivot to +x: its grown footprint
    (0.55 by 0.65 ft half sides) reaches hypot(0.55, 0.65) = 0.85 ft, and the notch's nearest
    corner (0.75, -6.5) is 0.75 ft away.  A quarter foot on it is 0.79 ft away, still within
    reach; half a foot on, hypot(0.75, 0.5) = 0.90 ft, out of it: FORWARD 0.5, TURN 90.
    Near the corridor's end no move on leaves room to pivot: None."""
    from planner.motion import forward_to_turn, pivot_allowed, pivot_radius_ft
    from rigtools import drive_config
    from vehicle.commands import Forward, Turn
    fm = corridor_map()
    i0, j0 = fm.index(0.75, -7.0)
    i1, j1 = fm.index(1.25, -6.5)
    fm.cells[i0:i1, j0:j1] = UNKNOWN
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    seen = fm.cells != UNKNOWN
    sweep, pivot_ft = PivotSweep(DEFAULT.footprint, DEFAULT.margin_ft), pivot_radius_ft(DEFAULT)
    reach = math.hypot(DEFAULT.width_ft / 2 + DEFAULT.margin_ft,
                       DEFAULT.length_ft / 2 + DEFAULT.margin_ft)
    assert math.hypot(0.75, 0.25) < reach < math.hypot(0.75, 0.5)
    here = State(0.0, -6.5, 0.0)
    assert not pivot_allowed(fm, here, 90.0, DEFAULT, sweep, pivot_ft)
    east = (lambda end: 90.0,)
    assert forward_to_turn(fm, here, east, safe, seen, DEFAULT, sweep, pivot_ft) == \
        [Forward(0.5), Turn(90.0)]
    # an aim with no heading, or one already faced, is passed over
    assert forward_to_turn(fm, here, (lambda end: None, lambda end: 0.0) + east, safe, seen,
                           DEFAULT, sweep, pivot_ft) == [Forward(0.5), Turn(90.0)]
    # 0.9 ft from the corridor's end at z = 2: the nose (0.65 ft) reaches unseen cells
    # before the grown footprint's reach clears them
    assert forward_to_turn(fm, State(0.0, 0.9, 0.0), east, safe, seen, DEFAULT, sweep,
                           pivot_ft) is None
    assert DriveConfig.turn_room == "forward"            # the default since 2026-12-05 15:00
    assert drive_config(monkeypatch, tmp_path, "--turn-room", "off").turn_room == "off"
    assert drive_config(monkeypatch, tmp_path, "--turn-room", "forward").turn_room == "forward"


def test_room_170_moves_on_to_turn_where_it_stood_before():
    """Bench room 170 (noise seed 170): without turning room the vehicle stops "cannot
    turn", standing where every pivot it needs sweeps floor no look has shown; with it
    (the default since 2026-12-05 15:00) a cycle moves on and turns, and the goal is
    reached by the true pose too, without a collision (the world's exact geometry).  Both
    drives on the seen map alone (the default before 2026-12-05 16:30) and with the
    margin's ring seen free (pivot="swept", the default before 19:10).  (Room 385 showed
    it until a move's band was checked to both edges, 19:50: its drive without turning
    room now reaches the goal.)  Both where it cannot turn stand and look again
    (backing="map", the default before 2026-12-07 12:15)."""
    from rigtools import assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(170, "turn_room", ("off", "forward"), map_extent="seen",
                             pivot="swept", backing="map")
    off, on = res["off"], res["forward"]
    assert not off.reached and "cannot turn: space within its radius" in off.reason
    assert off.collisions == 0
    assert_reached_by_the_truth(on, goal)
    assert any("forward to where it can" in c.note for c in on.cycles)


def test_the_evidence_options_drive_the_tiny_room_without_collision():
    """The named options together (look at what the path lacks, progress by
    evidence, backing over the map allowed, plan through uncertain cells) still reach the
    tiny room's goal with oracle eyes, no collision; a bad option value is
    refused."""
    import dataclasses
    from planner.loop import run
    from planner.tiny import GOAL, tiny_room
    from world.odometry import OdometryNoise
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py)
    cfg = DriveConfig(goal=GOAL, eyes="truth", look_around="evidence", progress="evidence",
                      uncertain="look", profile=dataclasses.replace(DEFAULT, reverse=True),
                      backing="map", sight_lines="band")
    res = run(tiny_room(), State(0.0, 0.0, 0.0), cfg, noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.travelled_ft <= 1.3 * res.optimal_ft + STEP_BACK_FT   # (rigtools)
    with pytest.raises(ValueError, match="unknown look_around 'spin'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, look_around="spin"))


def test_swept_track_marks_the_moves_and_pivots_shrunk_by_the_margin():
    """``track_free="swept"``: a 2 ft move then a 90 deg pivot; the poses
    between are marked too (the middle of the move, the pivot's corners at 45
    deg), the footprint shrunk by the margin; the default marks only the
    poses themselves (nothing at the move's middle)."""
    from planner.motion import mark_track_free, swept_poses
    track = [State(0.0, 0.0, 0.0), State(0.0, 2.0, 0.0), State(0.0, 2.0, 90.0)]
    poses = swept_poses(track)
    assert poses[0] == track[0] and poses[-1] == track[-1]
    assert any(abs(p.z - 1.0) < 1e-9 and p.heading_deg == 0.0 for p in poses)
    assert sorted(p.heading_deg for p in poses if p.z == 2.0) == pytest.approx(
        [10.0 * k for k in range(10)])                   # every 10 deg of the pivot
    # a 1 x 1 ft footprint: the default leaves the move's middle (z = 1) unmarked
    fm = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, -5.0, 0.25)
    mark_track_free(fm, track, (1.0, 1.0))
    assert fm.state_at(0.0, 0.1) == FREE and fm.state_at(0.0, 1.0) == UNKNOWN
    fm = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, -5.0, 0.25)
    mark_track_free(fm, track, (1.0, 1.0), swept_margin=0.1)
    assert fm.state_at(0.0, 1.0) == FREE
    # a 1 x 3 ft footprint: its 45 deg pose in the pivot about (0, 2) reaches (0.9, 2.9)
    poses_only = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, -5.0, 0.25)
    mark_track_free(poses_only, track, (1.0, 3.0))
    swept = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, -5.0, 0.25)
    mark_track_free(swept, track, (1.0, 3.0), swept_margin=0.25)
    assert swept.state_at(0.9, 2.9) == FREE and poses_only.state_at(0.9, 2.9) == UNKNOWN
    # shrunk by 0.25 ft: 0.4 ft beside the start (inside the 0.5 ft half width) is not
    assert poses_only.state_at(0.4, 0.0) == FREE and swept.state_at(0.4, 0.0) == UNKNOWN


def _bench_drive():
    """bench/drive.py as a module (it is a script, not a package)."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[1] / "bench" / "drive.py"
    spec = importlib.util.spec_from_file_location("bench_drive", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench


def test_bench_sorts_the_stop_reasons_by_kind():
    """bench/drive.py's table of stop reasons, on reasons the loop writes."""
    bench = _bench_drive()
    k = bench.stop_kind
    assert k("goal reached") == "reached"
    assert k("stopped after 8 looks without progress: no path: the way from the start to the "
             "goal is narrower than the vehicle (1.58 ft) near (1, 2) ft") == \
        "narrower than the vehicle"
    assert k("stopped after 8 looks without progress: goal not reachable (the goal (1, 2) ft is "
             "0.71 ft from an obstacle; the vehicle needs 0.79 ft); toward (1, 1) (cannot turn: "
             "space within its radius not seen free)") == "goal too near an obstacle on the map"
    assert k("stopped after 8 looks without progress: path to the goal (kept) (cannot turn: "
             "space within its radius not seen free)") == "cannot turn"
    assert k("stopped after 8 looks without progress: path to the goal (kept)") == \
        "path kept, not driven"
    assert k("stopped: the vehicle hit something (true footprint against the room)") == \
        "collision"
    assert k("stopped by Ctrl-C after 2 looks") == "other"


# --- the floor plan's walls grown by the pose's uncertainty (planner.evidence) -------------

def test_the_walls_grow_by_two_standard_deviations_of_the_estimate_at_most_a_features_growth():
    from planner.evidence import wall_growth
    assert wall_growth(np.zeros((3, 3))) == (0.0, 0.0)
    # sigma_x 0.3 ft, sigma_z 0.2 ft: 0.6 and 0.4 ft (the heading's variance plays no part)
    gx, gz = wall_growth(np.diag([0.09, 0.04, 0.5]))
    assert (gx, gz) == pytest.approx((0.6, 0.4))
    # sigma 1 ft: 2 ft, capped at the 1.5 ft a feature is grown at most (planner.octree)
    assert wall_growth(np.diag([1.0, 0.01, 0.0])) == pytest.approx((1.5, 0.2))


def test_assumed_lines_are_cut_a_cell_past_where_they_leave_the_walls_less_the_growth():
    from planner.evidence import within_walls
    o = np.array([1.0, 2.0, 1.0])                      # the camera 2 ft up at (1, 1)
    ends = np.array([[9.0, 0.0, 1.0],                  # along +x: leaves x = 3 at t = 0.25
                     [1.0, 0.0, 9.0],                  # along +z: leaves z = 5 at t = 0.5
                     [1.5, 0.0, 1.5],                  # inside: kept whole
                     [-3.0, 0.0, -3.0]])               # toward (0, 0) corner: x = 0 at t = 0.25
    out = within_walls(o, ends, (0.0, 3.0, 0.0, 5.0), 0.25)
    L = np.linalg.norm(ends - o, axis=1)
    t = np.minimum(1.0, np.array([0.25, 0.5, 1.0, 0.25]) + 0.25 / L)   # by hand, a cell on
    assert out == pytest.approx(o + t[:, None] * (ends - o))
    assert out[2] == pytest.approx(ends[2])
    # from outside the walls less the growth (the estimate within 2 sigma of a wall): nothing
    assert within_walls(np.array([3.5, 2.0, 1.0]), ends, (0.0, 3.0, 0.0, 5.0), 0.25) == \
        pytest.approx(np.repeat([[3.5, 2.0, 1.0]], 4, 0))


def test_bench_counts_success_by_the_slack_a_task_leaves():
    """bench/drive.py's ``success_by_slack``: each room in the bin of its slack
    (a bin holds its lower edge, not its upper), a room without a slack in none."""
    bench = _bench_drive()
    rows = [{"slack_ft": 0.0, "reached": False}, {"slack_ft": 0.125, "reached": True},
            {"slack_ft": 0.25, "reached": True}, {"slack_ft": 0.375, "reached": False},
            {"slack_ft": 0.5, "reached": True}, {"slack_ft": 2.0, "reached": True},
            {"slack_ft": None, "reached": False}]
    got = bench.success_by_slack(rows)
    assert got == {"0-0.25 ft": {"reached": 1, "rooms": 2, "rate": 0.5},
                   "0.25-0.5 ft": {"reached": 1, "rooms": 2, "rate": 0.5},
                   ">=0.5 ft": {"reached": 2, "rooms": 2, "rate": 1.0}}


def test_plan_core_passes_only_the_uncertain_cells_beyond_one_sigma():
    """``uncertain="core"``: a wall across the map with a 3 ft gap, each of
    its ends an uncertain feature grown 0.5 ft into it (two sigma), leaving
    8 free cells (2 ft), fewer than the 9 the vehicle of 1.58 ft needs on
    0.25 ft cells (clearance_map); their one-sigma cells reach 0.25 ft in and
    leave 10.  The default heads for the nearest reachable
    cell; "core" plans through the gap; the moves' safe map still blocks every
    uncertain cell.  With the one-sigma cells across the whole gap, or on a
    map that has no core drawn, "core" is the default."""
    cells = np.full((60, 60), FREE, np.uint8)
    fm = FloorMap(cells, -7.5, -7.5, 0.25)
    i, _ = fm.index(0.0, 0.0)
    cells[i - 1:i + 1, :] = OCCUPIED
    _, j0 = fm.index(-1.5, 0.0)
    _, j1 = fm.index(1.5, 0.0)
    cells[i - 1:i + 1, j0:j1] = UNCERTAIN              # the gap, ...
    cells[i - 1:i + 1, j0 + 2:j1 - 2] = FREE           # ... 0.5 ft of it at each end uncertain
    core = np.zeros(cells.shape, bool)
    core[i - 1:i + 1, j0:j0 + 1] = core[i - 1:i + 1, j1 - 1:j1] = True
    fm.uncertain_core = core
    est = State(0.0, -5.0, 0.0)
    goal = (0.0, 5.0)
    assert plan(fm, est, goal, DriveConfig(goal=goal, uncertain="blocked"))[2].startswith(
        "goal not reachable")
    pts, cmds, note = plan(fm, est, goal, DriveConfig(goal=goal))
    assert "past uncertain features' outer sigma" in note
    assert all(abs(p[0]) < 0.3 for p in pts if abs(p[1]) < 0.5)     # through the gap's middle
    safe = clearance_map(fm, R, "free", uncertain="blocked")
    _, jm = fm.index(0.0, 0.0)
    assert not safe.ok[i, jm]                          # the moves may not pass it yet
    for where in ("whole", "none"):
        if where == "whole":
            fm.uncertain_core = (cells == UNCERTAIN) | core
            fm.uncertain_core[i - 1:i + 1, j0:j1] = True
        else:
            fm.uncertain_core = None
        assert plan(fm, est, goal, DriveConfig(goal=goal, uncertain="core"))[2].startswith(
            "goal not reachable")


def test_the_core_drawn_is_the_uncertain_features_one_sigma():
    """Perception._draw_features: a feature seen once, sigma 0.5 ft along z and
    0.05 ft along x, is UNCERTAIN out to 1 ft along z and core out to 0.5 ft;
    a confirmed one is OCCUPIED and no core."""
    from planner.evidence import Perception
    from planner.octree import VolumeOfInterest
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1)
    m.draw_core = True                                  # (the loop's, under uncertain="core")
    cov = np.diag([0.05 ** 2, 0.5 ** 2])
    m.features.add_look(np.array([[0.1, 5.1], [3.1, 5.1]]), np.array([cov, cov]))
    m.features.looks[1] = 2                             # confirmed
    fm = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, 0.0, 0.25)
    m._draw_features(fm)
    for z, state, core in ((5.1, UNCERTAIN, True), (5.5, UNCERTAIN, True),
                           (5.8, UNCERTAIN, False), (6.05, UNCERTAIN, False), (6.4, UNKNOWN, False)):
        assert fm.state_at(0.1, z) == state, z
        assert fm.uncertain_core[fm.index(0.1, z)] == core, z
    assert fm.state_at(3.1, 5.1) == OCCUPIED and not fm.uncertain_core[fm.index(3.1, 5.1)]


def test_room_3_is_reached_when_the_plan_may_pass_the_outer_sigma():
    # the defaults, odometry noise seed 3 (bench/drive.py's room 3): no way round
    # the once-seen features' two-sigma cells, 16 looks pass without progress;
    # with uncertain="core" the plan passes their outer sigma, the vehicle looks
    # again from nearer, and the goal is reached.  The world's exact geometry
    # judges it.
    # (the defaults before 2026-12-06 15:40, as traced)
    from rigtools import DRIVE_BEFORE_2026_12_06_1540, assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(3, "uncertain", ("blocked", "core"), **DRIVE_BEFORE_2026_12_06_1540)
    assert not res["blocked"].reached and res["blocked"].collisions == 0
    assert "16 looks without progress" in res["blocked"].reason
    assert_reached_by_the_truth(res["core"], goal)
    assert any("past uncertain features' outer sigma" in c.note for c in res["core"].cycles)


def test_room_73_is_reached_looking_once_from_each_place():
    # bench/drive.py's room 73 under its own odometry noise: with three looks from each
    # place (the default) the drive stops without progress; looking once from each place
    # and driving on to the next (looks_per_viewpoint 1, a named option) it reaches the
    # goal.  The world's exact geometry judges it.
    from rigtools import assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(73, "looks_per_viewpoint", (1, 3))
    assert not res[3].reached and res[3].reason.startswith("stopped after 24 looks")
    assert res[3].collisions == 0
    assert_reached_by_the_truth(res[1], goal)
