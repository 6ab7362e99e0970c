"""The walk loop's pieces: the odometry prior, the fusion of a fix with it, the
world's truth of an observation."""

import numpy as np
import pytest

from model.edges import Camera, VertexObservation
from model.geometry import axes_matrix, left_centre, rotation_from_angles
from model.mapping import _compose_step, _fuse, observed_truth
from model.pose import PoseEstimate
from world.pose import Pose


def test_prior_is_the_odometry_step_applied_to_the_last_estimate():
    # the wheels report 0.75 ft straight ahead while facing +X, then a 10 degree right turn;
    # the robot believes it faces +Z at the origin: the step carries it to (0, 0.75), 10 degrees
    xzh, step, turn = _compose_step((0.0, 0.0, 0.0), Pose(1.0, 2.0, 90.0), Pose(1.75, 2.0, 100.0))
    assert xzh == pytest.approx((0.0, 0.75, 10.0))
    assert step == pytest.approx(0.75) and turn == pytest.approx(10.0)


def fix_at(x, z, heading, cov6):
    R = rotation_from_angles(heading)
    return PoseEstimate("robust", left_centre((x, 0.0, z), R), axes_matrix(R), np.ones(5, bool),
                        covariance6=cov6)


def test_fusion_of_equal_uncertainties_is_the_midpoint():
    fix = fix_at(1.2, 3.0, 12.0, np.diag([0.01, 0.0001, 0.01, 1e-6, np.radians(1.0) ** 2, 1e-6]))
    P = fix.xz_heading_covariance()                 # the prior exactly as uncertain as the fix
    est, P_post = _fuse(fix, (1.0, 3.2, 10.0), P)
    assert est.centre[0] == pytest.approx(1.1) and est.centre[2] == pytest.approx(3.1)
    assert est.heading_deg == pytest.approx(11.0)
    np.testing.assert_allclose(P_post, P / 2, atol=1e-15)


def test_a_fix_far_outside_the_prior_is_not_used():
    fix = fix_at(4.0, 3.0, 40.0, np.diag([0.01, 0.0001, 0.01, 1e-6, np.radians(1.0) ** 2, 1e-6]))
    reason = _fuse(fix, (1.0, 3.2, 10.0), np.diag([0.01, 0.01, np.radians(1.0) ** 2]))
    assert isinstance(reason, str) and "disagrees with the odometry" in reason


def test_observed_truth_is_the_named_pixel_at_the_true_range():

    R = rotation_from_angles(0.0)
    left = left_centre((0.0, 0.0, 0.0), R)
    rng = np.full((120, 128), 10.0)
    # column 82 (centre 82.0 continuous), row 42: 18 px right, 18 px up of the centre at 10 ft
    o = VertexObservation(np.zeros(3), np.eye(3), "top", 82.0, 42.0, 13.5, (1, 2), 0, 42)
    pts, idx = observed_truth([o], rng, left, R, np.zeros((0, 3)), Camera())
    np.testing.assert_allclose(pts[0], [-0.375 + 1.0, -1.0, 10.0])
    assert idx[0] == -1
    pts, idx = observed_truth([o], rng, left, R, np.array([[0.7, -1.1, 10.1]]),
                              Camera())
    assert idx[0] == 0 and pts[0] == pytest.approx([0.7, -1.1, 10.1])


def test_fused_pose_covariance_stays_positive_semidefinite():
    # a fix whose position and heading are correlated (off-diagonal terms): the fused 6x6
    # must be the fix's covariance conditioned on the prior, a covariance (no negative
    # variance anywhere it is carried, as A-29's camera term does)
    L = np.random.default_rng(3).normal(size=(6, 6)) * np.array([0.2, 0.03, 0.2, 0.003,
                                                                     0.05, 0.003])[:, None]
    C6 = L @ L.T                                   # a covariance with strong cross terms
    fix = fix_at(1.0, 3.0, 10.0, C6)
    P = np.diag([0.0004, 0.0004, np.radians(0.5) ** 2])      # a much surer prior
    est, P_post = _fuse(fix, (1.0, 3.0, 10.0), P)
    assert np.linalg.eigvalsh(est.covariance6).min() > -1e-12
    # conditioning only shrinks: no variance grows
    assert np.all(np.diag(est.covariance6) <= np.diag(C6) + 1e-15)
    q = np.array([[10.0, 3.0, -1.0], [5.0, -2.0, 0.5]])
    for C in est.pose_covariance_at(q):
        assert np.linalg.eigvalsh(C).min() > -1e-12


def test_floored_pose_raises_only_what_is_below_the_floor():
    from model.mapping import floored_pose
    C6 = np.diag([0.04 ** 2, 1e-4, 0.3 ** 2, 1e-6, np.radians(0.4) ** 2, 1e-6])
    fix = fix_at(1.0, 3.0, 0.0, C6)
    f = floored_pose(fix, 0.13, 0.85)
    np.testing.assert_allclose(np.diag(f.covariance6),
                               [0.13 ** 2, 1e-4, 0.3 ** 2, 1e-6, np.radians(0.85) ** 2, 1e-6])
    assert np.all(np.linalg.eigvalsh(f.covariance6 - C6) >= -1e-15)
    # a point 10 ft straight ahead: the heading's sigma moves it sideways by 10 ft * 0.85 deg
    C = f.pose_covariance_at(np.array([[10.0, 0.0, 0.0]]))[0]
    assert C[0, 0] == pytest.approx(0.13 ** 2 + (10 * np.radians(0.85)) ** 2, rel=1e-9)


def test_pose_floor_gives_the_stated_coverage_on_correlated_errors_monte_carlo():
    # every look's pose is off by one error (common to all the features it places: the
    # correlated error of a look) drawn with sigmas 0.13 ft and 0.85 deg, while the pose's
    # own covariance claims a third of that.  A feature placed with A-29's camera term
    # (plus the rig's own covariance) has its truth inside the 2-sigma ellipsoid 95 % of the
    # time with the floor, far less without
    from model.geometry import axes_matrix, left_centre, rotation_from_angles
    from model.kalman import measurement_covariance_a29
    from model.mapping import CHI2_3DOF_2SIGMA, floored_pose
    rng = np.random.default_rng(11)
    claimed = np.diag([0.045 ** 2, 1e-6, 0.045 ** 2, 1e-8, np.radians(0.3) ** 2, 1e-8])
    q = np.column_stack([rng.uniform(4, 12, 40), rng.uniform(-3, 3, 40), rng.uniform(-2, 1, 40)])
    Cq = np.array([np.diag([0.02 ** 2, 0.01 ** 2, 0.01 ** 2])] * len(q))
    inside = {"floored": [], "claimed": []}
    for _ in range(300):
        h = rng.normal(0, 0.85)
        R = rotation_from_angles(h)
        centre = np.array([rng.normal(0, 0.13), 0.0, rng.normal(0, 0.13)])
        truth = left_centre(centre, R) + q @ axes_matrix(R).T
        est = PoseEstimate("fused", left_centre(np.zeros(3), np.eye(3)), axes_matrix(np.eye(3)),
                           np.ones(1, bool), covariance6=claimed)
        noisy = q + np.array([rng.multivariate_normal(np.zeros(3), c) for c in Cq])
        z = est.transform(noisy)
        for name, pose in (("floored", floored_pose(est, 0.13, 0.85)), ("claimed", est)):
            Rm = measurement_covariance_a29(est.M, Cq, pose.pose_covariance_at(noisy))
            d = z - truth
            inside[name].extend(np.einsum("ni,ni->n", d, np.linalg.solve(Rm, d[..., None])[..., 0])
                                <= CHI2_3DOF_2SIGMA)
    assert 0.93 < np.mean(inside["floored"]) < 0.98
    assert np.mean(inside["claimed"]) < 0.6


def _given_pose():
    R = rotation_from_angles(0.0)
    return PoseEstimate("given", left_centre((0.0, 0.0, 0.0), R), axes_matrix(R),
                        np.zeros(0, bool), covariance6=np.zeros((6, 6)))


def _obs_at(q):
    return VertexObservation(np.asarray(q, float), np.diag([0.04, 0.0004, 0.0004]), "top",
                             64.0, 60.0, 13.5, (3, 9), 0, 60)


def test_feature_gate_refuses_a_wrong_merge_splits_and_retires():
    # one model vertex at 10 ft straight ahead with a 0.2 ft range sigma; an observation
    # 3 ft farther is 15 sigma off: not fused (the vertex keeps its mean), counted as a
    # contradiction, and it starts a vertex of its own; contradicted again in a second look,
    # the vertex (seen once) leaves the model but stays on record
    from model.mapping import FEATURE_GATE_CHI2, _update_model
    from model.symbolic import SymbolicModel
    est = _given_pose()
    model = SymbolicModel()
    z0 = est.transform(np.array([[10.0, 0.0, 0.0]]))[0]
    v = model.add_vertex(z0, np.diag([0.0004, 0.0004, 0.04]), "top", (3, 9), 0)
    far = _obs_at([13.0, 0.0, 0.0])
    truth = est.transform(far.q[None])
    for look in (1, 2):
        added = _update_model(model, [], [far], [(v.id, 0)], [(v.id, 0)], est, "a30", look,
                              truth, np.array([-1]), {}, feature_gate=FEATURE_GATE_CHI2)
        assert added == 1
        np.testing.assert_allclose(v.mean, z0)
        assert v.contradicted == look and v.looks == 1
    assert v.id not in model.vertices and model.retired[v.id] is v
    assert len(model.vertices) == 2                 # the two split-off vertices
    assert set(model.vertices).isdisjoint(model.retired)
    # a near observation passes the gate and is fused as before
    model = SymbolicModel()
    v = model.add_vertex(z0, np.diag([0.0004, 0.0004, 0.04]), "top", (3, 9), 0)
    near = _obs_at([10.1, 0.0, 0.0])
    added = _update_model(model, [], [near], [(v.id, 0)], [(v.id, 0)], est, "a30", 1,
                          est.transform(near.q[None]), np.array([-1]), {},
                          feature_gate=FEATURE_GATE_CHI2)
    assert added == 0 and v.looks == 2 and v.contradicted == 0
    assert v.mean[2] == pytest.approx(10.05, abs=1e-9)      # equal range variances: the midpoint


def test_consider_covariance_is_scored_and_the_filter_kept():
    # with the consider covariance on, the vertex keeps the filter's covariance (used by the
    # matcher) and carries the measured one beside it; the score uses the measured one
    from model.mapping import WalkConfig, _measured_covariances, _update_model
    from model.symbolic import SymbolicModel
    est = _given_pose()
    model = SymbolicModel()
    o = _obs_at([10.0, 0.0, 0.0])
    honest = _measured_covariances([o], est, WalkConfig(), [8, 10, 12], given=True)
    # the range bound of A-13 with the measured 1.7 px disparity bound at 13.5 px disparity,
    # by hand: 0.75 * 180 * 1.7 / (13.5^2 - 13.5 * 1.7) ft, two sigma (room z is the range)
    ep = 0.75 * 180 * 1.7 / (13.5 ** 2 - 13.5 * 1.7)
    assert honest[0][2, 2] == pytest.approx((ep / 2) ** 2, rel=1e-12)
    _update_model(model, [], [o], [], [], est, "a30", 0, est.transform(o.q[None]),
                  np.array([-1]), {}, honest=honest, consider="bound")
    (v,) = model.vertices.values()
    np.testing.assert_allclose(v.report_cov, honest[0])
    np.testing.assert_allclose(np.diag(v.cov), np.diag(o.cov)[[1, 2, 0]])
    _update_model(model, [], [o], [(v.id, 0)], [(v.id, 0)], est, "a30", 1,
                  est.transform(o.q[None]), np.array([-1]), {}, honest=honest, consider="bound")
    # two equal looks: the filter halves its covariance, the bound (they may share one error)
    # does not shrink at all
    np.testing.assert_allclose(np.diag(v.cov), np.diag(o.cov)[[1, 2, 0]] / 2, rtol=1e-9)
    assert np.all(np.diag(v.report_cov) >= np.diag(honest[0]) * (1 - 1e-9))


def test_retire_unseen_takes_out_what_a_fixed_pose_should_have_seen():
    # three vertices: 10 ft straight ahead (well inside the view), 10 ft ahead but 40 degrees
    # to the side (outside the 39 degree field of view) and 20 ft ahead (beyond the 15 ft the
    # model uses).  A look that matches none of them misses only the first; with N = 1 it is
    # retired after one miss per look it was seen in, a vertex seen twice after two
    from model.mapping import WalkConfig, _retire_unseen
    from model.symbolic import SymbolicModel
    est = _given_pose()
    est = PoseEstimate("fused", est.left, est.M, est.inliers, covariance6=est.covariance6)
    model = SymbolicModel()
    C = np.eye(3) * 0.01
    ahead = model.add_vertex(est.left + [0, 0, 10.0], C, "top", (3, 9), 0)
    side = model.add_vertex(est.left + [10 * np.sin(np.radians(40)), 0,
                                        10 * np.cos(np.radians(40))], C, "top", (3, 9), 0)
    far = model.add_vertex(est.left + [0, 0, 20.0], C, "top", (3, 9), 0)
    twice = model.add_vertex(est.left + [0.5, 0.5, 8.0], C, "bottom", (3, 9), 0)
    twice.looks = 2
    config = WalkConfig(retire_unseen=1)
    _retire_unseen(model, [], est, 1, (8, 113), config)
    assert ahead.id in model.retired and ahead.missed == 1
    assert side.id in model.vertices and far.id in model.vertices
    assert side.missed == far.missed == 0
    assert twice.id in model.vertices and twice.missed == 1
    # a matched vertex is not missed; the twice-seen one goes at its second miss
    _retire_unseen(model, [(side.id, 0)], est, 2, (8, 113), config)
    assert twice.id in model.retired and side.missed == 0
    # a vertex added in this very look is not counted
    new = model.add_vertex(est.left + [0, 0, 9.0], C, "top", (3, 9), 3)
    _retire_unseen(model, [], est, 3, (8, 113), config)
    assert new.id in model.vertices and new.missed == 0


def test_floored_pose_raises_height_and_tilt():
    # the height and tilt floor (the consider covariance's --tilt-floor): y and the rotations
    # about the two horizontal room axes (x, z) raised where smaller; a point 10 ft straight
    # ahead (room z) moves vertically by 10 ft * the tilt about x, plus the height
    from model.mapping import floored_pose
    C6 = np.diag([0.04 ** 2, 1e-4, 0.3 ** 2, 1e-6, np.radians(0.4) ** 2, np.radians(5) ** 2])
    f = floored_pose(fix_at(1.0, 3.0, 0.0, C6), 0.0, 0.0, 0.32, 3.2)
    t = np.radians(3.2) ** 2
    np.testing.assert_allclose(np.diag(f.covariance6),
                               [0.04 ** 2, 0.32 ** 2, 0.3 ** 2, t, np.radians(0.4) ** 2,
                                np.radians(5) ** 2])
    C = f.pose_covariance_at(np.array([[10.0, 0.0, 0.0]]))[0]
    assert C[1, 1] == pytest.approx(0.32 ** 2 + 100 * t, rel=1e-9)


def _scored_result(vertices, **config):
    from model.mapping import WalkConfig, WalkResult
    from model.symbolic import SymbolicModel
    model = SymbolicModel()
    for mean, cov, truth, nis, missed in vertices:
        v = model.add_vertex(mean, cov, "top", (3, 9), 0)
        v.truth, v.nis, v.missed, v.looks = np.asarray(truth, float), list(nis), missed, 1 + len(nis)
    return WalkResult(WalkConfig(**config), [], model)


def test_track_confirmation_scores_confirmed_and_tentative_apart():
    # four vertices, unit covariance; truths at distance 1 (inside 2 sigma) or 5 (outside):
    #   a: seen 3 times, both later looks consistent (NIS 1, 2)          -> confirmed, inside
    #   b: seen twice, the second look inconsistent (NIS 20 > 11.345)    -> tentative, inside
    #   c: seen once                                                     -> tentative, outside
    #   d: seen twice, consistent, but missed 3 times where it should have been seen
    #      (2 consistent looks < 3 misses)                               -> tentative, outside
    I = np.eye(3)
    res = _scored_result([([0, 0, 0], I, [1, 0, 0], [1.0, 2.0], 0),
                          ([5, 0, 0], I, [6, 0, 0], [20.0], 0),
                          ([9, 0, 0], I, [14, 0, 0], [], 0),
                          ([20, 0, 0], I, [25, 0, 0], [0.5], 3)], confirm=2)
    fs = res.feature_scores()
    assert fs["track_confirmed"] == 1 and fs["tentative"] == 3
    assert fs["track_confirmed_inside_2sigma"] == 1.0
    assert fs["tentative_inside_2sigma"] == pytest.approx(1 / 3)
    assert fs["track_confirmed_rms_error_ft"] == pytest.approx(1.0)
    assert fs["inside_2sigma"] == 0.5                      # all four: still reported
    # M = 3: a has exactly three consistent looks; nothing else changes
    assert _scored_result([([0, 0, 0], I, [1, 0, 0], [1.0, 2.0], 0)],
                          confirm=3).feature_scores()["track_confirmed"] == 1
    assert _scored_result([([0, 0, 0], I, [1, 0, 0], [1.0], 0)],
                          confirm=3).feature_scores()["track_confirmed"] == 0
    # without the option no such fields
    assert "track_confirmed" not in _scored_result([([0, 0, 0], I, [1, 0, 0], [1.0], 0)]
                                                   ).feature_scores()


def test_variance_factor_widens_only_the_reported_covariance():
    # ten vertices with unit reported covariance and their truths at distance 2.5
    # (Mahalanobis^2 6.25: inside the 8.02 of 2 sigma) ... and one at distance 4 (16:
    # outside) whose own innovations say its errors are 3x the claimed variance: NIS 9, 9,
    # 9 pooled with the global factor (the median of all NIS over 2.366, floored at 1):
    # (3 g + 27) / 12 with g = 9 / 2.366 = 3.8 -> 3.2; Mahalanobis^2 16 / 3.2 = 5: inside.  The
    # means and the filter's covariances are untouched
    I = np.eye(3)
    verts = [([0, 0, 0], I, [2.5, 0, 0], [], 0)] * 10 + [([0, 0, 0], I, [4, 0, 0], [9.0] * 3, 0)]
    plain = _scored_result(verts).feature_scores()
    res = _scored_result(verts, variance_factor=True)
    scaled = res.feature_scores()
    g, f = res.variance_factors()
    assert g == pytest.approx(9 / 2.365974, rel=1e-6)
    last_id = max(res.model.vertices)
    assert f[last_id] == pytest.approx((3 * g + 27) / 12, rel=1e-9)
    # the vertices without innovations take the global factor
    assert all(f[i] == pytest.approx(g) for i in res.model.vertices if i != last_id)
    assert plain["inside_2sigma"] == pytest.approx(10 / 11)
    assert scaled["inside_2sigma"] == 1.0
    assert scaled["rms_error_ft"] == plain["rms_error_ft"]
    assert scaled["filter_inside_2sigma"] == plain["filter_inside_2sigma"]
    for v in res.model.vertices.values():
        np.testing.assert_array_equal(v.cov, I)


def test_confirmation_counts_misses_without_retiring():
    # with --confirm alone the looks that should have seen a vertex are counted (the
    # evidence against it), and nothing leaves the model
    from model.mapping import WalkConfig, _retire_unseen
    from model.symbolic import SymbolicModel
    est = _given_pose()
    est = PoseEstimate("fused", est.left, est.M, est.inliers, covariance6=est.covariance6)
    model = SymbolicModel()
    ahead = model.add_vertex(est.left + [0, 0, 10.0], np.eye(3) * 0.01, "top", (3, 9), 0)
    for look in (1, 2, 3):
        _retire_unseen(model, [], est, look, (8, 113), WalkConfig(confirm=2))
    assert ahead.id in model.vertices and ahead.missed == 3


def test_observed_truth_at_an_occluding_edge_is_the_occluding_surface():
    """The scorer's rule at an occluding edge, against the world's exact geometry: from the
    start pose the crate's right edge (X = 0, Z = 5 ft, a true vertical edge of the room)
    stands before the back wall (19 ft).  A located edge named on either side of it within a
    pixel is the crate's: the boundary belongs to the nearer surface (the far one only
    disappears behind it), and the truth is the crate's edge, not the wall 14 ft beyond."""
    from world.render import range_128
    from world.room import bundled_lab
    room, pose = bundled_lab(), Pose(0.0, 0.0, 0.0)
    assert any(np.allclose(e[:, [0, 2]], [[0.0, 5.0], [0.0, 5.0]]) for e in room.vertical_edges)
    z, which = range_128(room.quads, pose.camera_centre("left"), pose.rotation())
    assert room.quads[which[80, 77]].name == "crate front"
    assert room.quads[which[80, 78]].name == "back wall" and z[80, 78] == pytest.approx(19.0)
    R, left = pose.rotation(), pose.camera_centre("left")
    obs = [VertexObservation(np.zeros(3), np.eye(3), "top", col, 80.5, 10.0, (1, 2), 0, 80)
           for col in (76.8, 78.2, 79.6)]
    pts, idx = observed_truth(obs, z, left, R, np.zeros((0, 3)), Camera())
    for p in pts[:2]:                     # the crate side and the wall side of the edge
        assert p[2] == pytest.approx(5.0) and abs(p[0]) < 0.04
        assert p[1] == pytest.approx(5.0 * 20.5 / 180)
    # two columns off the edge the scorer's window (the named column and one either side) is
    # all wall: that observation is scored against the wall
    assert pts[2][2] == pytest.approx(19.0)


def _fence_look():
    """A hand-made picket fence: stripes 4 px wide (period 8 px) seen at a true disparity of
    20 px (right[x] = left[x + 20]); the rig matched the edge at column 72 one period off,
    at 28 px.  Its top corner at row 39.5 (line 40)."""
    from types import SimpleNamespace
    from model.edges import EdgeObservation, locate
    x = np.arange(128 + 20)
    stripes = np.where((x // 4) % 2 == 0, 3, 12)
    look = SimpleNamespace(left_bi=np.tile(stripes[:128], (120, 1)),
                           right_bi=np.tile(stripes[20:], (120, 1)))
    lines = (40, 42, 44, 46)
    q, C = locate(72.5, 39.5, 28.0, Camera(), e_d=1.5)
    v = VertexObservation(q, C, "top", 72.5, 39.5, 28.0, (3, 12), 0, 40)
    edge = EdgeObservation(lines, (72.5,) * 4, (28.0,) * 4, np.zeros(3), np.eye(3), (3, 12),
                           False, False, vertices=[v])
    return look, edge


def _at_start(disparity):
    """The room point of the fence's corner at ``disparity``, the robot at the origin facing
    +z (A-23 with the prior's axes)."""
    from model.edges import locate
    from model.mapping import _rotation
    R = _rotation(0.0)
    M = np.column_stack([R[:, 2], R[:, 0], R[:, 1]])
    return left_centre((0.0, 0.0, 0.0), R) + M @ locate(72.5, 39.5, disparity, Camera(), e_d=1.5)[0]


def test_resolve_picks_the_period_the_model_predicts():
    """--ambiguity-gate resolve on a hand-made picket fence: the rig's disparity (28) is a
    period off; the model holds the corner where the true disparity (20) puts it (6.75 ft
    ahead), and the prior's prediction moves the edge there.  Where the model holds the
    corner at the rig's own period, the rig's is kept; where it holds nothing, the edge
    starts no feature and every period is remembered as a candidate."""
    from world.room import bundled_lab
    from model.mapping import Walker, WalkConfig
    P = np.diag([0.01, 0.01, np.radians(1.0) ** 2])
    for held, expect in ((20, 20.0), (28, 28.0)):
        walker = Walker(bundled_lab(), WalkConfig(ambiguity_gate="resolve"))
        walker.model.add_vertex(_at_start(held), np.eye(3) * 0.01, "top", (3, 12), 0)
        look, edge = _fence_look()
        no_new, unresolved = walker._resolve(look, [edge], ((0.0, 0.0, 0.0), P))
        (v,) = edge.vertices
        assert v.disparity == expect and walker.resolved == (expect != 28.0)
        assert v.q[0] == pytest.approx(0.75 * 180 / expect)
        # matched to the model's feature, or nothing: it starts none
        assert no_new == {id(v)} and unresolved == []
    # nothing in the model: unresolved; its candidates are every period inside the picture
    walker = Walker(bundled_lab(), WalkConfig(ambiguity_gate="resolve"))
    look, edge = _fence_look()
    no_new, unresolved = walker._resolve(look, [edge], ((0.0, 0.0, 0.0), P))
    assert edge.vertices[0].disparity == 28.0 and no_new == {id(edge.vertices[0])}
    assert sorted(c.disparity for c in unresolved) == [12, 20, 28, 36, 44, 52, 60, 68]
    # remembered one look: the next look's candidate that agrees with one may start a feature
    from model.mapping import _rotation
    R = _rotation(0.0)
    walker._remember_unresolved(unresolved, PoseEstimate(
        "given", left_centre((0.0, 0.0, 0.0), R), axes_matrix(R), np.zeros(0, bool),
        covariance6=np.zeros((6, 6))))
    assert len(walker.pending.vertices) == 8
    look, edge = _fence_look()
    no_new, unresolved = walker._resolve(look, [edge], ((0.0, 0.0, 0.0), P))
    assert no_new == set() and unresolved == []
