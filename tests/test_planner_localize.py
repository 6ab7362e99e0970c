"""The camera estimate fixed against the floor plan's walls (planner.localize,
``pose="walls"``): hand-made geometry with a known answer — points placed exactly on the
walls by a known pose (world.pose, independent of the fix's own algebra), a prior off by
(0.5 ft, 0.3 ft, 3 deg) — and the loop with the option in the tiny room."""

import math

import numpy as np
import pytest

from planner.localize import MAX_RESIDUAL_FT, depth_wall_points, fix_against_walls, \
    level_points
from world.pose import Pose

BOUNDS = (-5.0, 7.0, -4.0, 16.0)           # x0, x1, z0, z1
TRUE = (1.0, 2.0, 30.0)                    # x, z, heading deg
PITCH = -25.0
PRIOR = (TRUE[0] + 0.5, TRUE[1] + 0.3, TRUE[2] + 3.0)
PRIOR_COV = np.diag([0.5 ** 2, 0.5 ** 2, math.radians(4.0) ** 2])
SIGMA = 0.02


def right_wall(n=8):
    """Room points on the right wall (x = 7) in view of TRUE, 0.5-2.5 ft below the cameras."""
    z = np.linspace(6.0, 14.0, n)
    return np.stack([np.full(n, 7.0), np.linspace(0.5, 2.5, n), z], 1)


def back_wall(n=8):
    """Room points on the back wall (z = 16)."""
    x = np.linspace(0.0, 6.0, n)
    return np.stack([x, np.linspace(2.5, 0.5, n), np.full(n, 16.0)], 1)


def box_face(n=6):
    """Points on a box face 2 ft inside the back wall (z = 14), not on any wall."""
    x = np.linspace(1.0, 3.0, n)
    return np.stack([x, np.full(n, 1.5), np.full(n, 14.0)], 1)


def look(room_points, true=TRUE, pan=0.0, pitch=PITCH):
    """The points in the left camera's axes of the rig at ``true`` (head panned ``pan``),
    with SIGMA each way."""
    q = Pose(true[0], true[1], true[2] + pan, pitch).to_camera(room_points, "left")
    return q, np.broadcast_to(np.eye(3) * SIGMA ** 2, (len(q), 3, 3)).copy()


def test_level_points_place_a_camera_point_as_the_pose_does():
    """The level frame plus heading reproduces world.pose's camera-to-room transform."""
    pts = np.array([[1.0, -0.5, 6.0], [-2.0, 1.0, 3.0]])
    pose = Pose(0.7, -1.2, 35.0, PITCH)
    q = pose.to_camera(pts, "left")
    lev, _ = level_points(q, np.zeros((2, 3, 3)), PITCH)
    h = math.radians(35.0)
    x = 0.7 + math.cos(h) * lev[:, 0] + math.sin(h) * lev[:, 2]
    z = -1.2 - math.sin(h) * lev[:, 0] + math.cos(h) * lev[:, 2]
    assert np.allclose(np.stack([x, lev[:, 1], z], 1), pts, atol=1e-12)


def test_two_perpendicular_walls_recover_the_true_pose():
    q, c = look(np.vstack([right_wall(), back_wall()]))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert fix.fixed and fix.used.all() and fix.walls == ("x1", "z1")
    assert abs(fix.x - TRUE[0]) < 0.01 and abs(fix.z - TRUE[1]) < 0.01
    assert abs(fix.heading_deg - TRUE[2]) < 0.05
    # the fix is far surer than the prior in all three
    assert np.all(np.sqrt(np.diag(fix.cov)) < 0.2 * np.sqrt(np.diag(PRIOR_COV)))
    assert np.allclose(fix.cov, fix.cov.T) and np.all(np.linalg.eigvalsh(fix.cov) > 0)


def test_one_wall_corrects_only_the_distance_to_it_and_the_heading():
    """The back wall (z = 16) alone: z and the heading are recovered, x is the prior's
    exactly and so is its variance (the prior's covariance is diagonal)."""
    q, c = look(back_wall(12))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert fix.fixed and fix.walls == ("z1",)
    assert fix.x == pytest.approx(PRIOR[0], abs=1e-9)
    assert fix.cov[0, 0] == pytest.approx(PRIOR_COV[0, 0], rel=1e-9)
    assert abs(fix.z - TRUE[1]) < 0.01 and abs(fix.heading_deg - TRUE[2]) < 0.05
    assert fix.cov[1, 1] < 0.05 * PRIOR_COV[1, 1]


def test_box_points_off_the_walls_are_rejected_and_do_not_pull_the_fix():
    walls = np.vstack([right_wall(), back_wall()])
    q, c = look(np.vstack([walls, box_face()]))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert fix.fixed
    assert fix.used[:len(walls)].all() and not fix.used[len(walls):].any()
    alone = fix_against_walls(*look(walls), PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert (fix.x, fix.z, fix.heading_deg) == pytest.approx(
        (alone.x, alone.z, alone.heading_deg), abs=1e-9)


def test_a_box_face_nearer_its_wall_than_the_prior_spread_is_dropped_after_the_first_solve():
    """Box points 0.8 ft inside the back wall pass the first gate (within MAX_RESIDUAL_FT
    and the prior's spread) but not the second, at the solution."""
    box = box_face(4)
    box[:, 2] = 16.0 - 0.8
    assert 0.8 < MAX_RESIDUAL_FT
    walls = np.vstack([right_wall(10), back_wall(10)])
    q, c = look(np.vstack([walls, box]))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert fix.fixed and not fix.used[len(walls):].any()
    assert abs(fix.x - TRUE[0]) < 0.01 and abs(fix.z - TRUE[1]) < 0.01
    assert abs(fix.heading_deg - TRUE[2]) < 0.05


def test_too_few_points_give_the_prior_unchanged():
    q, c = look(back_wall(4))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert not fix.fixed and not fix.used.any()
    assert (fix.x, fix.z, fix.heading_deg) == PRIOR
    assert np.array_equal(fix.cov, PRIOR_COV)


def test_only_box_points_give_the_prior_unchanged():
    q, c = look(box_face(10))
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH)
    assert not fix.fixed and (fix.x, fix.z, fix.heading_deg) == PRIOR


def test_a_prior_known_exactly_is_not_moved():
    q, c = look(np.vstack([right_wall(), back_wall()]))
    fix = fix_against_walls(q, c, PRIOR, np.zeros((3, 3)), BOUNDS, PITCH)
    assert not fix.fixed and (fix.x, fix.z, fix.heading_deg) == PRIOR


def test_the_heading_may_turn_two_of_its_sigmas_and_no_more():
    """Both walls seen from TRUE, the prior's heading 1.5 or 2.5 of its standard
    deviations (2 deg) off: within 2 sigma (the default since 2026-12-05) the fix turns
    it to the truth; beyond, the points' word against the prior's by more than the
    window allows, no fix (the window's price: a true correction of 2.5 sigma is
    refused too), which 3 sigma (the window before) would have made."""
    from planner.localize import HEADING_SIGMAS
    assert HEADING_SIGMAS == 2.0
    q, c = look(np.vstack([right_wall(), back_wall()]))
    cov = np.diag([0.1 ** 2, 0.1 ** 2, math.radians(2.0) ** 2])
    for sigmas, fixed in ((1.5, True), (2.5, False)):
        prior = (TRUE[0], TRUE[1], TRUE[2] + 2.0 * sigmas)
        fix = fix_against_walls(q, c, prior, cov, BOUNDS, PITCH)
        assert fix.fixed is fixed
        assert abs(fix.heading_deg - (TRUE[2] if fixed else prior[2])) < 0.05
        wide = fix_against_walls(q, c, prior, cov, BOUNDS, PITCH, heading_sigmas=3.0)
        assert wide.fixed and abs(wide.heading_deg - TRUE[2]) < 0.05


def test_room_684s_skirting_turns_the_heading_only_under_the_wider_window():
    """Room 684 (the 1985 eyes, the bench's goal and noise seed; the defaults of
    2026-12-05 01:35, as traced): the floor's ends along its side walls, a skirting of
    the floor's grey, lie 0.8-1 ft beyond the walls.  With the fix's heading allowed 3
    sigma they turn it 4-6 deg at look 3, and more than 10 deg off the truth by look 12;
    within 2 sigma look 3's fix keeps it within 2 deg.  (Until 2026-12-06 the 3-sigma run
    went on to 17 deg by look 12 and hit a box at look 16, and this test said so; on the
    machine of 2026-12-07, at the same commit, it is 14.8 deg and no hit: something below
    the code, the machine or the libraries pip installed there, rounds the run apart by
    look 11.  The false turns hold on both; the collision is not asserted.)"""
    from planner.loop import DriveConfig, run
    from rigtools import DRIVE_BEFORE_2026_12_05_0430, bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(684)
    res = {k: run(room, start, DriveConfig(goal=goal, wall_fix_sigmas=k,
                                           **{**DRIVE_BEFORE_2026_12_05_0430, "max_looks": 20}),
                  noise=OdometryNoise(seed=684), keep_maps=False) for k in (3.0, 2.0)}
    off = {k: [abs(c.estimate.heading_deg - c.true.heading_deg) for c in r.cycles]
           for k, r in res.items()}
    assert 4.0 < off[3.0][2] < 6.5                   # look 3: the skirting's turn taken
    assert off[2.0][2] < 2.0                         # ... and refused within 2 sigma
    assert max(off[3.0][:12]) > 10.0
    assert res[2.0].collisions == 0


def test_a_look_with_the_head_panned_and_tilted_fixes_the_body():
    """The head turned 10 deg right and tilted 20 deg down: the look is the body turned as
    much (vehicle.sim.camera_pose); the fix returns the BODY's heading."""
    q, c = look(np.vstack([right_wall(), back_wall()]), pan=10.0, pitch=PITCH - 20.0)
    fix = fix_against_walls(q, c, PRIOR, PRIOR_COV, BOUNDS, PITCH - 20.0, pan_deg=10.0)
    assert fix.fixed
    assert abs(fix.x - TRUE[0]) < 0.01 and abs(fix.z - TRUE[1]) < 0.01
    assert abs(fix.heading_deg - TRUE[2]) < 0.05


def test_depth_points_leave_out_the_floor_and_keep_the_wall():
    """A hand-made range picture: the rig pitched -25 deg over the floor (3 ft below)
    facing a wall 6 ft ahead (level).  Every pixel looks down, so a pixel shows the
    floor or, nearer, the wall; only the wall's pixels higher than 0.1 ft above the
    floor are kept, each exactly on the wall."""
    from planner.perception import CY_128, FOCAL_128
    c, s = math.cos(math.radians(PITCH)), math.sin(math.radians(PITCH))
    v = (np.arange(120) + 0.5 - CY_128) / FOCAL_128
    V = np.broadcast_to(v[:, None], (120, 128))
    down = c * V - s                        # level y per unit Z
    ahead = s * V + c                       # level z per unit Z
    assert np.all(down > 0)
    z_floor = 3.0 / down
    z_wall = 6.0 / ahead
    Z = np.minimum(z_floor, z_wall)
    q, cov = depth_wall_points(Z, PITCH, 3.0)
    lev, _ = level_points(q, cov, PITCH)
    assert len(q) > 50
    assert np.allclose(lev[:, 2], 6.0, atol=1e-9)                 # on the wall
    assert np.all(lev[:, 1] < 3.0 - 0.1)                          # off the floor
    on_wall = (z_wall < z_floor)[::4, ::4] & (6.0 / ahead * down < 2.9)[::4, ::4]
    assert len(q) == int(on_wall.sum())
    # a picture of the floor alone gives nothing
    assert len(depth_wall_points(z_floor, PITCH, 3.0)[0]) == 0


# --- the loop --------------------------------------------------------------------------

def test_the_loop_knows_the_walls_estimate_and_allows_it_with_the_head():
    from planner.loop import POSES, DriveConfig, _check_config
    assert "walls" in POSES and DriveConfig(goal=(0.0, 1.0)).pose == "walls"   # since 2026-12-05
    _check_config(DriveConfig(goal=(0.0, 1.0), pose="walls", head="pan-tilt"))
    with pytest.raises(ValueError, match="pose 'walls'.*known_walls"):
        _check_config(DriveConfig(goal=(0.0, 1.0), known_walls=False, map_extent="seen"))
    _check_config(DriveConfig(goal=(0.0, 1.0), known_walls=False, pose="dead_reckoning",
                              map_extent="seen"))


def test_the_loop_fixed_against_the_walls_ends_nearer_the_truth_than_dead_reckoning():
    """The tiny room, depth eyes, the head, odometry five times noisier than the
    default (seed 3: a 15 deg heading error after the first move): dead reckoning's
    estimate ends 0.7 ft from the truth; fixed against the walls (the first look has
    nothing to fix: the start is known exactly) the estimate is within a fifth of a foot
    of the truth at every look, ends within a fraction of dead reckoning's error, and the
    vehicle reaches the goal by the truth, without collision.  (Traced with the fix's
    heading allowed 3 sigma, the window before 2026-12-05; within 2 sigma, the default
    since, the noisier odometry's larger turns are refused at 4 of 12 looks, the estimate
    strays up to half a foot, and the goal is still reached by the truth: the window's
    price.)"""
    from planner.loop import DriveConfig, run
    from planner.tiny import GOAL, tiny_room
    from rigtools import DRIVE_BEFORE_2026_12_04
    from vehicle.sim import State
    from world.odometry import OdometryNoise

    def drive(pose, sigmas=3.0):
        return run(tiny_room(), State(0.0, 0.0, 0.0),
                   DriveConfig(goal=GOAL, eyes="depth", head="pan-tilt", pose=pose,
                               wall_fix_sigmas=sigmas, **DRIVE_BEFORE_2026_12_04),
                   noise=OdometryNoise(0.1, 5.0, seed=3), keep_maps=False)

    def errors(res):
        return [math.hypot(c.estimate.x - c.true.x, c.estimate.z - c.true.z) for c in res.cycles]
    dead, walls = drive("dead_reckoning"), drive("walls")
    assert walls.reached and walls.collisions == 0
    assert walls.wall_fixes >= len(walls.cycles) - 1 and dead.wall_fixes is None
    assert max(errors(walls)) < 0.2
    assert walls.final_true_error_ft <= 0.75
    assert dead.track_errors()[-1] > 3 * walls.track_errors()[-1]
    narrow = drive("walls", 2.0)
    assert narrow.reached and narrow.collisions == 0 and narrow.final_true_error_ft <= 0.75
    assert narrow.wall_fixes < len(narrow.cycles) - 1 and max(errors(narrow)) > 0.2


def test_a_look_without_a_fix_widens_the_next_fixs_window():
    """``wall_fix_widen``: the tiny room as above (depth eyes, the head, odometry five
    times noisier, seed 3), the fix's window 2 sigma.  The first move throws the heading
    15 deg off, beyond the window: kept at 2 sigma the estimate stays that far off for
    two looks and, after a later throw, for three, 12 looks in all; widened by a sigma per
    look without a fix, no throw outlasts two looks (the first none: the first look,
    with nothing to fix, had widened the window already), and the goal is reached in 8
    looks.  Out of range is refused by name."""
    from planner.loop import DriveConfig, run, _check_config
    from planner.tiny import GOAL, tiny_room
    from rigtools import DRIVE_BEFORE_2026_12_04
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    assert DriveConfig.wall_fix_widen == 1.0

    def drive(widen):
        res = run(tiny_room(), State(0.0, 0.0, 0.0),
                  DriveConfig(goal=GOAL, eyes="depth", head="pan-tilt", pose="walls",
                              wall_fix_sigmas=2.0,
                              **{**DRIVE_BEFORE_2026_12_04, "wall_fix_widen": widen}),
                  noise=OdometryNoise(0.1, 5.0, seed=3), keep_maps=False)
        off = [abs((c.estimate.heading_deg - c.true.heading_deg + 180.0) % 360.0 - 180.0)
               for c in res.cycles]
        longest = run_ = 0
        for o in off:
            run_ = run_ + 1 if o > 5.0 else 0
            longest = max(longest, run_)
        return res, longest
    kept, kept_run = drive(0.0)
    widened, widened_run = drive(1.0)
    assert kept.reached and widened.reached and kept.collisions == widened.collisions == 0
    assert kept_run >= 3 and widened_run <= 2
    assert len(widened.cycles) < len(kept.cycles)
    for bad in (-1.0, 10.0, True, "1"):
        with pytest.raises(ValueError, match="wall_fix_widen"):
            _check_config(DriveConfig(goal=GOAL, wall_fix_widen=bad))


def test_rig_drive_pose_walls_reaches_the_loop_with_the_head(tmp_path, monkeypatch):
    """``rig drive --pose walls`` sets ``DriveConfig.pose``, with ``--head pan-tilt`` too;
    an unknown estimate is one clear error naming it."""
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path).pose == "walls"
    cfg = drive_config(monkeypatch, tmp_path, "--pose", "walls", "--head", "pan-tilt")
    assert (cfg.pose, cfg.head) == ("walls", "pan-tilt")
    assert drive_config(monkeypatch, tmp_path, "--pose", "dead_reckoning").pose == \
        "dead_reckoning"
    from rig.main import main
    with pytest.raises(SystemExit) as e:
        main(["drive", "--out", str(tmp_path), "--pose", "floorplan"])
    assert e.value.code not in (0, None)


def test_floor_end_points_meet_the_floor_where_the_run_ends():
    """A picture whose floor (grey 6) ends at the top edge of row 40 in every column: each
    column's point lies on the floor plane 3 ft below the camera, as far ahead as a ray
    25 deg - atan(20 / 180) below the horizontal meets it (8.9 ft), and its error along the
    ray is half a row's footprint there (closed forms, not the module's algebra)."""
    from planner.localize import floor_end_points
    pic = np.full((120, 128), 9, np.uint8)
    pic[40:] = 6
    greys = np.zeros(16, bool)
    greys[6] = True
    q, cov = floor_end_points(pic, greys, PITCH, 3.0)
    assert len(q) == 64                                   # every second column
    c, s = math.cos(math.radians(PITCH)), math.sin(math.radians(PITCH))
    y_level = c * q[:, 1] - s * q[:, 2]
    z_level = s * q[:, 1] + c * q[:, 2]
    assert np.allclose(y_level, 3.0)

    def ahead(edge_row):
        # the floor point's distance straight ahead (level frame) of a ray through that
        # row's edge: a row above the centre row 60 looks up from the axis, pitched 25 deg down
        below = math.radians(-PITCH) - math.atan((60.0 - edge_row) / 180.0)
        return 3.0 / math.tan(below)
    assert np.allclose(z_level, ahead(40.0))              # 8.88 ft, in every column
    k = 32                                                # column 64, beside the centre
    along = math.sqrt(cov[k].trace() - 3 * 0.03 ** 2)     # the row's part (the floor: 0.03 each way)
    assert along == pytest.approx(abs(ahead(39.5) - ahead(40.5)) / 2, rel=1e-3)


def test_floor_end_points_of_a_rendered_look_lie_on_walls_and_box_feet():
    """External truth: rooms rendered at their start pose (world.render), the floor's true
    grey; the floor's end points, placed at the true pose, lie within 0.35 ft of a wall or
    a box outline for at least 80 % of them (the rest: a face of the floor's grey, noise)."""
    from planner.localize import floor_end_points
    from planner.loop import camera_pose
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.render import render_look
    from world.room import generate_room
    for seed, grey in ((3, 5), (5, 6), (7, 7), (11, 6)):       # rooms with a flat floor
        room = generate_room(seed)
        look = render_look(room, camera_pose(State(0.0, 0.0, 0.0), 0.0, 0.0, DEFAULT))
        greys = np.zeros(16, bool)
        greys[grey] = True
        q, cov = floor_end_points(look.left_bi, greys, PITCH, 3.0)
        lev, _ = level_points(q, cov, PITCH)              # heading 0 at (0, 0): room x, z
        x, z = lev[:, 0], lev[:, 2]
        x0, x1, z0, z1 = room.bounds
        d = np.min(np.abs([x - x0, x - x1, z - z0, z - z1]), axis=0)
        for bx0, bx1, bz0, bz1 in room.obstacles:
            dx = np.maximum(np.maximum(bx0 - x, x - bx1), 0.0)
            dz = np.maximum(np.maximum(bz0 - z, z - bz1), 0.0)
            d = np.minimum(d, np.hypot(dx, dz))
        assert len(d) >= 40
        assert np.mean(d < 0.35) >= 0.8, (seed, np.round(np.percentile(d, [50, 80, 95]), 2))


def test_the_floor_ends_hold_the_heading_where_the_edges_cannot():
    """Room 471, the 1985 eyes, the default odometry noise: the drive whose heading drift
    once put the vehicle into the left wall.  Fixed against the walls by the look's located
    points alone the estimate's heading still drifts 6 deg from the truth (one look in 23
    gives a fix); with the floor in view's ends (``wall_points="floor-ends"``) most looks
    give one and the heading stays within 2 deg of the truth at every look."""
    from planner.loop import WALL_POINTS, DriveConfig, run, _check_config
    from planner.planning import random_goal
    from rigtools import DRIVE_BEFORE_2026_12_05
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    from world.room import generate_room
    assert WALL_POINTS == ("edges", "floor-ends") and DriveConfig.wall_points == "floor-ends"
    with pytest.raises(ValueError, match="wall_points"):
        _check_config(DriveConfig(goal=(0.0, 1.0), wall_points="feet"))
    # (the rest of the drive as traced, before 2026-12-05)
    traced = {**DRIVE_BEFORE_2026_12_05, "pose": "walls"}
    room = generate_room(471)
    start = State(0.0, 0.0, 0.0)
    goal = random_goal(room, start, DEFAULT, np.random.default_rng(471))

    def drive(points):
        res = run(room, start, DriveConfig(goal=goal, **{**traced, "wall_points": points,
                                                           "max_looks": 30}),
                  noise=OdometryNoise(seed=471), keep_maps=False)
        off = [abs((c.estimate.heading_deg - c.true.heading_deg + 180.0) % 360.0 - 180.0)
               for c in res.cycles]
        return res, off
    edges, off_edges = drive("edges")
    ends, off_ends = drive("floor-ends")
    assert max(off_edges) > 5.0 and edges.wall_fixes <= 2
    assert max(off_ends) < 2.0 and ends.wall_fixes >= len(ends.cycles) // 2
    assert edges.collisions == ends.collisions == 0


def test_rig_drive_wall_points_reach_the_loop(tmp_path, monkeypatch):
    from planner.loop import DriveConfig, _check_config
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path).wall_fix_sigmas == 2.0
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-sigmas", "3").wall_fix_sigmas == 3.0
    assert drive_config(monkeypatch, tmp_path).wall_fix_widen == 1.0
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-widen", "0").wall_fix_widen == 0.0
    for bad in (0.0, -1.0, 12.0, "2"):
        with pytest.raises(ValueError, match="wall_fix_sigmas"):
            _check_config(DriveConfig(goal=(0.0, 1.0), wall_fix_sigmas=bad))
    assert drive_config(monkeypatch, tmp_path).wall_points == "floor-ends"
    cfg = drive_config(monkeypatch, tmp_path, "--pose", "walls", "--wall-points", "edges")
    assert (cfg.pose, cfg.wall_points) == ("walls", "edges")



def test_room_866s_false_fix_in_the_widened_window_and_the_base_window_first():
    """Bench room 866 (noise seed 866; today's defaults, as traced): looks 1 and 2 find no
    fix, so at look 3 the window has widened to 4 sigma.  In it 75 points at a heading 10
    deg off the truth outvote 10 on the far wall, and the estimate ends the look 14.8 deg
    off the true heading.  With the base window tried first (``wall_fix_first="base"``,
    not 1985) the 10 points fix it within half a degree of the truth (the world's exact
    pose).  An unknown order is one clear error."""
    from planner.loop import DriveConfig, run
    from rigtools import bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(866)
    off = {}
    for first in ("widened", "base"):
        res = run(room, start, DriveConfig(goal=goal, wall_fix_first=first, max_looks=3),
                  noise=OdometryNoise(seed=866), keep_maps=False)
        c = res.cycles[2]
        off[first] = abs((c.estimate.heading_deg - c.true.heading_deg + 180) % 360 - 180)
    assert off["widened"] > 10.0
    assert off["base"] < 0.5
    from planner.loop import _check_config
    with pytest.raises(ValueError, match="unknown wall_fix_first 'both'; one of widened, base"):
        _check_config(DriveConfig(goal=goal, wall_fix_first="both"))


def test_the_widened_window_is_bounded_where_asked():
    """``wall_fix_most``: bench room 329 planned on half cells where no map has a way
    (``fine_map="fallback"``).  Nine looks in a row without a fix widen the window to
    11 sigma (3.3 deg each), where 18 points that agree on a heading 17 deg off the
    truth take the far wall's place at look 30, and the vehicle drives into a box on
    that estimate at look 40.  Bounded at 4 sigma, the window refuses that fix and the
    drive ends without a collision (the world's exact geometry judges both).  Out of
    range is refused by name."""
    from planner.loop import DriveConfig, _check_config
    from rigtools import DRIVE_BEFORE_2026_12_06_1645, bench_drives
    assert DriveConfig.wall_fix_most == 4.0
    # (the defaults before 2026-12-06 16:45, as traced)
    _, res = bench_drives(329, "wall_fix_most", (None, 4.0), fine_map="fallback",
                          **DRIVE_BEFORE_2026_12_06_1645)
    assert res[None].collisions == 1
    assert res[4.0].collisions == 0
    for bad in (0, -1.0, 10.0, True, "4"):
        with pytest.raises(ValueError, match="wall_fix_most"):
            _check_config(DriveConfig(goal=(0.0, 5.0), wall_fix_most=bad))


def test_rig_drive_takes_the_windows_bound(tmp_path, monkeypatch):
    """``rig drive --wall-fix-most S`` sets the bound; 0 is no bound (None)."""
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path).wall_fix_most == 4.0
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-most", "3").wall_fix_most == 3.0
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-most", "0").wall_fix_most is None


def test_a_fix_far_from_the_prior_on_few_points_is_a_far_turn():
    """``far_turn``: both walls seen from TRUE (16 points), the prior's heading 2.5 or
    3.5 of its standard deviations (2 deg) off, the window 4 sigma: both fixes turn it
    to the truth.  Asking 30 points, the 3.5 sigma fix is a far turn of -7 deg (the
    truth less the prior) and the 2.5 sigma one is not; asking 16 (as many as it has),
    or 0 (off), neither is; a look without a fix has none."""
    from planner.localize import FAR_SIGMAS, far_turn
    assert FAR_SIGMAS == 3.0
    q, c = look(np.vstack([right_wall(), back_wall()]))
    cov = np.diag([0.1 ** 2, 0.1 ** 2, math.radians(2.0) ** 2])
    for sigmas in (2.5, 3.5):
        prior = (TRUE[0], TRUE[1], TRUE[2] + 2.0 * sigmas)
        fix = fix_against_walls(q, c, prior, cov, BOUNDS, PITCH, heading_sigmas=4.0)
        assert fix.fixed and fix.used.sum() == 16 and abs(fix.heading_deg - TRUE[2]) < 0.05
        far = far_turn(fix, prior[2], cov, 30)
        if sigmas == 3.5:
            assert far == pytest.approx(-7.0, abs=0.05)
        else:
            assert far is None
        assert far_turn(fix, prior[2], cov, 16) is None and far_turn(fix, prior[2], cov, 0) is None
    none = fix_against_walls(q[:3], c[:3], prior, cov, BOUNDS, PITCH, heading_sigmas=4.0)
    assert not none.fixed and far_turn(none, prior[2], cov, 30) is None


def test_a_far_turn_from_fewer_sigmas_where_asked(tmp_path, monkeypatch):
    """``wall_fix_far_sigmas`` (``--wall-fix-far-sigmas``, not the default): the fix of
    the test above from a prior 2.5 standard deviations off is no far turn at the
    default 3 sigmas and a far turn of -5 deg (the truth less the prior) from 2; the flag
    reaches the loop, and a value out of range is refused by name."""
    from planner.localize import far_turn
    from planner.loop import DriveConfig, _check_config
    from rigtools import drive_config
    q, c = look(np.vstack([right_wall(), back_wall()]))
    cov = np.diag([0.1 ** 2, 0.1 ** 2, math.radians(2.0) ** 2])
    prior = (TRUE[0], TRUE[1], TRUE[2] + 5.0)
    fix = fix_against_walls(q, c, prior, cov, BOUNDS, PITCH, heading_sigmas=4.0)
    assert fix.fixed and far_turn(fix, prior[2], cov, 30) is None
    assert far_turn(fix, prior[2], cov, 30, far_sigmas=2.0) == pytest.approx(-5.0, abs=0.05)
    assert DriveConfig.wall_fix_far_sigmas == 3.0
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-far-sigmas",
                        "2").wall_fix_far_sigmas == 2.0
    for bad in (0, -1.0, 10.0, True, "2"):
        with pytest.raises(ValueError, match="wall_fix_far_sigmas"):
            _check_config(DriveConfig(goal=(0.0, 5.0), wall_fix_far_sigmas=bad))


def test_a_far_turn_waits_for_a_second_look_where_asked():
    """``wall_fix_far``: bench room 473 takes a fix at look 3 that turns the heading
    7.9 deg (3.2 sigma) on 15 points of the right wall, 7.9 deg off the truth.  Under
    the defaults before 2026-12-06 16:45 the drive stops without reaching the goal,
    the estimate 0.9 ft off; with the goal's once-seen blocker let go
    (``goal_evidence="look-expire"``, a default since then) it drives on that estimate
    into a box.  Asking 30 points of a far turn (the default since then), that turn
    waits for a second look, and the goal is reached by the truth (the world's exact
    geometry judges all three)."""
    from rigtools import assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(473, "wall_fix_far", (0, 30), goal_evidence="off")
    assert not res[0].reached and res[0].collisions == 0
    assert_reached_by_the_truth(res[30], goal)
    goal, res = bench_drives(473, "wall_fix_far", (0, 30))
    assert res[0].collisions == 1 and "hit something" in res[0].reason
    assert_reached_by_the_truth(res[30], goal)


def test_rig_drive_takes_the_far_fixs_points(tmp_path, monkeypatch):
    """``rig drive --wall-fix-far N`` sets ``wall_fix_far`` (30 by default since
    2026-12-06 16:45; 0, off, before); a count that is no count is refused by name."""
    from planner.loop import DriveConfig, _check_config
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path).wall_fix_far == 30
    assert drive_config(monkeypatch, tmp_path, "--wall-fix-far", "0").wall_fix_far == 0
    for bad in (-1, 2.5, True, "30"):
        with pytest.raises(ValueError, match="wall_fix_far"):
            _check_config(DriveConfig(goal=(0.0, 5.0), wall_fix_far=bad))


def test_a_far_turn_needs_its_second_look_from_elsewhere():
    """``wall_fix_far``: bench room 879.  At look 4, 8 points of the far wall turn the
    heading 10.7 deg (3.6 sigma), 10.2 deg off the truth, and under the defaults the
    estimate stays 7.6-10.3 deg off over the next seven looks.  The looks after it,
    0.23 ft on and turned in place, show the same false consensus: from about the same
    place a false consensus shows again, so asking 30 points of a far turn also asks
    its second look from 1 ft away or more (``FAR_WITNESS_FT``).  Then the heading stays
    within 3.5 deg of the truth over the first ten looks (the world's exact pose
    judges)."""
    from planner.loop import FAR_WITNESS_FT
    from rigtools import bench_drives
    assert FAR_WITNESS_FT == 1.0
    _, res = bench_drives(879, "wall_fix_far", (0, 30))

    def heading_errors(r):
        return [abs((c.estimate.heading_deg - c.true.heading_deg + 180.0) % 360.0 - 180.0)
                for c in r.cycles[:10]]
    assert min(heading_errors(res[0])[3:7]) > 10.0
    assert max(heading_errors(res[30])) < 3.5
