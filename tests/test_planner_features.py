"""The floor features the map is regenerated from (planner.features,
``DriveConfig.occupied="model"``) on hand-made looks."""

import math

import numpy as np
import pytest

from planner.features import FloorFeatures, associate, ellipse_cells, fuse2, \
    pose_point_covariance, segment_cells
from planner.evidence import Perception
from planner.loop import DriveConfig, run
from planner.octree import VolumeOfInterest, cell_centres, feature_cells, features_cells, \
    mark_free_rays, mark_occupied
from planner.tiny import GOAL, tiny_room
from vehicle.commands import Forward, Turn
from vehicle.sim import State, Vehicle, odometry_covariance
from world.odometry import OdometryNoise

RES = 0.25


def _cov(sx, sz, rho=0.0):
    return np.array([[sx * sx, rho * sx * sz], [rho * sx * sz, sz * sz]])


def test_a_near_look_shrinks_a_far_looks_feature_and_its_growth():
    # a corner at (1.0, 6.0): a far look puts it 0.3 ft off with a wide error,
    # a near look within 0.02 ft with a small one
    f = FloorFeatures()
    far_cov, near_cov = _cov(0.4, 0.6), _cov(0.03, 0.05)
    f.add_look([[1.1, 6.3]], [far_cov])
    far_cells = ellipse_cells(f.mean, f.cov, RES)
    ids = f.add_look([[1.01, 6.02]], [near_cov])
    assert list(ids) == [0] and f.looks[0] == 2 and len(f) == 1
    # the information update by hand: (P^-1 + R^-1)^-1, the mean weighted by them
    P = np.linalg.inv(np.linalg.inv(far_cov) + np.linalg.inv(near_cov))
    m = P @ (np.linalg.solve(far_cov, [1.1, 6.3]) + np.linalg.solve(near_cov, [1.01, 6.02]))
    assert np.allclose(f.cov[0], P) and np.allclose(f.mean[0], m)
    assert np.trace(f.cov[0]) < np.trace(near_cov) < np.trace(far_cov)
    assert np.hypot(*(f.mean[0] - [1.0, 6.0])) < 0.05
    near_cells = ellipse_cells(f.mean, f.cov, RES)
    assert len(near_cells) < len(far_cells) / 5
    # confirmed by two looks: occupied, no uncertain cells left
    occ, unc = f.cells(RES, confirm_looks=2)
    assert len(unc) == 0 and {tuple(c) for c in occ} == {tuple(c) for c in near_cells}


def test_a_contradicting_far_hit_does_not_fuse():
    f = FloorFeatures()
    f.add_look([[1.0, 6.0]], [_cov(0.03, 0.05)])
    # 1.5 ft behind it, with an error of 0.3 ft: 5 standard deviations off
    ids = f.add_look([[1.0, 7.5]], [_cov(0.2, 0.3)])
    assert list(ids) == [1] and list(f.looks) == [1, 1]
    assert np.allclose(f.mean[0], [1.0, 6.0])
    occ, unc = f.cells(RES, confirm_looks=2)
    assert len(occ) == 0 and len(unc) > 0


def test_association_is_nearest_and_one_to_one_within_a_look():
    feats = np.array([[0.0, 5.0], [1.0, 5.0]])
    covs = np.array([_cov(0.2, 0.2)] * 2)
    # two hits, both nearer feature 0 than feature 1: the nearer takes 0, the
    # other the next nearest within the gate
    obs = np.array([[0.1, 5.0], [0.3, 5.0]])
    match = associate(feats, covs, obs, np.array([_cov(0.2, 0.2)] * 2))
    assert list(match) == [0, 1]
    # far from both: none
    assert list(associate(feats, covs, [[5.0, 5.0]], [_cov(0.2, 0.2)])) == [-1]


def test_fusion_is_the_model_packages_static_update_in_the_plane():
    m, P = fuse2(np.array([[0.0, 4.0]]), np.array([_cov(0.2, 0.4, 0.3)]),
                 np.array([[0.2, 4.4]]), np.array([_cov(0.3, 0.1, -0.2)]))
    A, B = _cov(0.2, 0.4, 0.3), _cov(0.3, 0.1, -0.2)
    K = A @ np.linalg.inv(A + B)
    assert np.allclose(m[0], [0.0, 4.0] + K @ [0.2, 0.4])
    assert np.allclose(P[0], (np.eye(2) - K) @ A)


def test_ellipse_cells_equal_the_octrees_growth_in_the_floor_plane():
    rng = np.random.default_rng(3)
    means = rng.uniform(-3, 3, (40, 2))
    L = rng.normal(0, 0.25, (40, 2, 2))
    covs = L @ np.swapaxes(L, 1, 2) + 1e-4 * np.eye(2)
    y = 1.3                                        # inside one cell of the octree's grid
    m3 = np.column_stack([means[:, 0], np.full(40, y), means[:, 1]])
    c3 = np.zeros((40, 3, 3))
    c3[:, 0, 0], c3[:, 0, 2], c3[:, 2, 0], c3[:, 2, 2] = covs[:, 0, 0], covs[:, 0, 1], \
        covs[:, 1, 0], covs[:, 1, 1]
    c3[:, 1, 1] = 1e-6
    ref = features_cells(m3, c3, RES)
    ref = ref[np.isclose(ref[:, 1], (math.floor(y / RES) + 0.5) * RES)]
    ref = {(int(math.floor(x / RES)), int(math.floor(z / RES))) for x, _, z in ref}
    got = {tuple(c) for c in ellipse_cells(means, covs, RES)}
    assert got == ref and len(got) > 40
    # and the plain per-feature growth (octree.feature_cells, one at a time) where the cap
    # does not bite
    small = np.flatnonzero(2 * np.sqrt(np.diagonal(covs, axis1=1, axis2=2)).max(1) < 1.0)
    assert len(small) > 10
    plain = set()
    for n in small:
        for x, yy, z in feature_cells(m3[n], c3[n], RES):
            if np.isclose(yy, (math.floor(y / RES) + 0.5) * RES):
                plain.add((int(math.floor(x / RES)), int(math.floor(z / RES))))
    assert {tuple(c) for c in ellipse_cells(means[small], covs[small], RES)} == plain
    # a segment's cells as the octree's surface sampling
    seg = {tuple(c) for c in segment_cells([[0.0, 4.0]], [[1.3, 5.1]], RES)}
    ref = cell_centres(np.linspace([0.0, 0.0, 4.0], [1.3, 0.0, 5.1], 200), RES)
    assert seg == {(int(math.floor(x / RES)), int(math.floor(z / RES))) for x, _, z in ref}


def test_a_feature_later_looks_see_through_retires():
    p = Perception(VolumeOfInterest(32.0, 7), (-0.5, 2.75), 12.0, confirm_looks=2, free_looks=1)
    p.occupied = "model"
    origin = np.array([0.0, 1.0, 0.0])
    ghost, wall = np.array([0.1, 1.0, 4.0]), np.array([0.1, 1.0, 8.0])
    # a look hits the ghost (a false match) and the wall beyond it, each once
    p.features.add_look([ghost[[0, 2]], [0.5, 8.0]], [_cov(0.05, 0.1)] * 2)
    mark_occupied(p.tree, cell_centres(np.vstack([ghost, [0.5, 1.0, 8.0]]), RES))
    fm = p.floor_map([(0.0, 0.0), (0.0, 9.0)])
    assert fm.state_at(0.1, 4.0) == 3                       # uncertain (one look)
    # later looks see the wall through the ghost's cell: one miss is not enough
    mark_free_rays(p.tree, origin, [wall])
    assert p.retire(origin, 15.0) == 0
    for _ in range(2):
        mark_free_rays(p.tree, origin, [wall])
    assert p.retire(origin, 15.0) == 1
    assert list(p.features.alive) == [False, True]
    fm = p.floor_map([(0.0, 0.0), (0.0, 9.0)])
    assert fm.state_at(0.1, 4.0) == 0                       # free now
    assert fm.state_at(0.5, 8.0) == 3                       # the wall's feature stays


def test_pose_error_carried_to_a_point_by_its_lever_arm():
    pose_cov = np.diag([0.01, 0.04, math.radians(2.0) ** 2])
    C = pose_point_covariance([[3.0, 4.0]], [0.0, 0.0], pose_cov)[0]
    # by finite differences of p = pivot + Rot(heading) v (heading from +z toward +x)
    v = np.array([3.0, 4.0])

    def place(dx, dz, dh):
        a = math.atan2(v[0], v[1]) + dh
        r = np.hypot(*v)
        return np.array([dx + r * math.sin(a), dz + r * math.cos(a)])
    eps = 1e-6
    J = np.column_stack([(place(eps, 0, 0) - place(0, 0, 0)) / eps,
                         (place(0, eps, 0) - place(0, 0, 0)) / eps,
                         (place(0, 0, eps) - place(0, 0, 0)) / eps])
    assert np.allclose(C, J @ pose_cov @ J.T, atol=1e-6)


def test_odometry_covariance_matches_the_noisy_vehicle():
    """The propagated covariance against the spread of many noisy runs of one
    command string (the world's odometry noise model)."""
    cmds = [Forward(3.0), Turn(40.0), Forward(2.0), Forward(2.0), Turn(-90.0), Forward(3.0)]
    errs = []
    for seed in range(1500):
        v = Vehicle(np.zeros((0, 4)), (-50, 50, -50, 50), State(0.0, 0.0, 0.0),
                    noise=OdometryNoise(seed=seed), sweep_ft=1.0, sweep_deg=45.0)
        v.execute(cmds)
        errs.append([v.dead.x - v.true.x, v.dead.z - v.true.z,
                     math.radians(v.dead.heading_deg - v.true.heading_deg)])
        track = v.dead_track
    P = np.zeros((3, 3))
    for a, b in zip(track[:-1], track[1:]):
        P = odometry_covariance(P, a, b)
    S = np.cov(np.array(errs).T)
    assert np.allclose(np.sqrt(np.diag(S)), np.sqrt(np.diag(P)), rtol=0.12)
    assert abs(S[0, 1] / math.sqrt(S[0, 0] * S[1, 1]) -
               P[0, 1] / math.sqrt(P[0, 0] * P[1, 1])) < 0.1
    # noise off: nothing
    assert np.allclose(odometry_covariance(np.zeros((3, 3)), track[0], track[1], 0.0, 0.0), 0)


def test_the_loop_on_the_regenerated_map_reaches_the_tiny_rooms_goal():
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py)
    res = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes="truth", occupied="model", sight_lines="band"), noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.features is not None and len(res.features) > 0 and res.features.fused > 0


def test_room_156s_passage_stays_open_on_the_fused_map_and_closes_on_the_per_look_map():
    """Bench room 156 (noise seed 156; the task leaves 0.25 ft to spare): on the per-look
    map (occupied="looks", the default before 2026-12-05 13:45) the hits one look saw keep
    their look's wide growth, the way out of the start narrows below the vehicle and the
    drive never moves; drawn from the fused features (the default since) the same looks
    leave it open and the vehicle reaches the goal, by its true pose too, without a
    collision (the world's exact geometry counts both).  On the seen map alone (the
    default before 2026-12-05 16:30, as traced): the map out to the walls sends it round
    the far side at look 3, where the seen map has no way for two looks."""
    from rigtools import DRIVE_BEFORE_2026_12_06_1540, assert_reached_by_the_truth, bench_drives
    assert DriveConfig.occupied == "model"
    goal, res = bench_drives(156, "occupied", ("looks", "model"), map_extent="seen",
                             **{**DRIVE_BEFORE_2026_12_06_1540, "max_looks": 20})
    looks, model = res["looks"], res["model"]
    assert not looks.reached and "narrower than the vehicle" in looks.reason, looks.reason
    assert looks.collisions == 0
    assert_reached_by_the_truth(model, goal)


def test_an_unknown_occupied_source_is_refused():
    with pytest.raises(ValueError, match="unknown occupied 'octree'; one of looks, model"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, occupied="octree"))
    with pytest.raises(ValueError, match="unknown feature_pose 'gps'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, feature_pose="gps"))
    with pytest.raises(ValueError, match="unknown hit_at 'floor'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, hit_at="floor"))


def test_drift_since_a_feature_was_last_seen_widens_only_what_is_seen_again():
    f = FloorFeatures()
    P0 = np.zeros((3, 3))
    f.add_look([[0.0, 5.0], [3.0, 5.0]], [_cov(0.05, 0.05)] * 2, near=(0.0, 0.0),
               near_ft=20.0, drift_cov=P0)
    # the vehicle has since drifted (heading 2 deg): a corner 5 ft ahead of it
    # is uncertain by 5 ft x 2 deg = 0.175 ft across, so a hit 0.3 ft to the
    # side (6 of the look's standard deviations, under 2 of the drift's) fuses
    P1 = np.diag([0.0, 0.0, math.radians(2.0) ** 2])
    ids = f.add_look([[0.3, 5.0]], [_cov(0.05, 0.05)], near=(0.0, 0.0), near_ft=20.0,
                     drift_cov=P1)
    assert list(ids) == [0] and f.looks[0] == 2
    # without the drift it would not have
    g = FloorFeatures()
    g.add_look([[0.0, 5.0]], [_cov(0.05, 0.05)], near=(0.0, 0.0), near_ft=20.0)
    assert list(g.add_look([[0.3, 5.0]], [_cov(0.05, 0.05)], near=(0.0, 0.0),
                           near_ft=20.0)) == [1]
    # the feature not seen again keeps its covariance and the frame it was seen in
    assert np.allclose(f.cov[1], _cov(0.05, 0.05)) and np.allclose(f.seen_pose_cov[1], P0)
    assert np.allclose(f.seen_pose_cov[0], P1)


def test_a_hit_the_plans_walls_explain_starts_no_feature():
    """``wall_explained``: a hit whose two-sigma ellipse (the pose's share in its
    covariance) reaches a wall of the floor plan, or that lies past one, is the wall's;
    by hand on a plan 10 x 20 ft."""
    from planner.evidence import wall_explained
    bounds = (-5.0, 5.0, -5.0, 15.0)
    obs = [(4.0, 0.0), (4.0, 0.0), (0.0, 14.5), (0.0, 14.5), (5.3, 0.0), (0.0, 0.0),
           (-4.5, 6.0)]
    cov = [_cov(0.6, 0.1),        # reaches x 5.2: the right wall's
           _cov(0.4, 0.1),        # reaches x 4.8: a feature
           _cov(0.1, 0.2),        # reaches z 14.9: a feature
           _cov(0.1, 0.3),        # reaches z 15.1: the back wall's
           _cov(0.01, 0.01),      # past the right wall
           _cov(3.0, 3.0),        # the middle of the room, but 6 ft of error: reaches any
           _cov(0.1, 0.3, 0.9)]   # 0.5 ft from the left wall, 0.2 ft of x error: a feature
    assert wall_explained(obs, cov, bounds).tolist() == [True, False, False, True, True,
                                                         True, False]
    with pytest.raises(ValueError, match="unknown wall_hits 'wall'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, wall_hits="wall"))


def test_room_119_is_reached_when_the_plans_walls_explain_their_hits():
    """Bench room 119 (noise seed 119), traced under the defaults before 2026-12-06 20:30
    (``one_grey_runs`` "prove"): as every hit starts a feature (``wall_hits`` "feature",
    the default then) the right wall's points, hit once at look 2 just before it, narrow
    the way along it; the drive goes round the far side and stops "narrower than the
    vehicle" after 51 looks.  With the hits the plan's walls explain left out ("plan",
    the default since) the vehicle drives along the wall and reaches the goal by its
    true pose, having started under a third as many features."""
    from rigtools import DRIVE_BEFORE_2026_12_06_2030, assert_reached_by_the_truth, bench_drives
    before = {k: v for k, v in DRIVE_BEFORE_2026_12_06_2030.items() if k != "wall_hits"}
    goal, res = bench_drives(119, "wall_hits", ("feature", "plan"), **before)
    feature, plan = res["feature"], res["plan"]
    assert not feature.reached and "narrower than the vehicle" in feature.reason, feature.reason
    assert feature.collisions == 0
    assert_reached_by_the_truth(plan, goal)
    assert 3 * plan.features.started < feature.features.started


def test_room_881_a_face_in_a_tiled_floors_grey_is_not_proved_floor_under_near_seen():
    """Bench room 881 under ``wall_hits="plan"``: at look 36 the vehicle faces box 1
    from 1.5 ft; its face, checked in greys 3 and 14 on a floor tiled in 3 and 5, fills
    the bottom rows, the floor in view proves the floor 3.2 ft out, inside the box, and
    the vehicle hits it at look 46.  Under ``one_grey_runs="near-seen"`` (the default
    since 2026-12-06 20:30, with ``wall_hits="plan"``) a run showing one of the tiles'
    greys only proves nothing where the last map had not shown the floor before its
    bottom row free: no collision (the world's exact geometry)."""
    from rigtools import bench_drives
    _, res = bench_drives(881, "one_grey_runs", ("prove", "near-seen"), wall_hits="plan")
    assert res["prove"].collisions == 1 and "hit something" in res["prove"].reason
    assert res["near-seen"].collisions == 0
    with pytest.raises(ValueError, match="unknown one_grey_runs 'never'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, one_grey_runs="never"))
