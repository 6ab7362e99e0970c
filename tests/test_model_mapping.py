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
