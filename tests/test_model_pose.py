"""Camera location estimation (Appendix A, A-21..A-50) and its alternatives.

External truth: hand-made poses built with scipy's rotations (independent of
model.geometry), the exact algebra of A-22/A-23, and Monte Carlo runs."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from model.geometry import design_row, environment_covariance
from model.pose import (ESTIMATORS, PoseRefused, check_conditions, estimate, solve_a48,
                        solve_robust)


def hand_pose():
    """A camera turned 30 deg right, 4 deg nose up, 2 deg roll, at (1.5, -0.2, 2.0).
    Columns: x right, y down, z forward.  Built by scipy, not by model.geometry."""
    # heading about room +Y (down) turns +Z toward +X; pitch about the camera x axis
    # (negative sense so the nose goes to -Y); roll about the camera z axis
    R = (Rotation.from_euler("y", 30, degrees=True)
         * Rotation.from_euler("x", -4, degrees=True)
         * Rotation.from_euler("z", 2, degrees=True)).as_matrix()
    return np.array([1.5, -0.2, 2.0]), R


# camera-relative (p, x, y) = (range, right, down): five corners, not coplanar
Q = np.array([[6.0, -1.0, 1.2], [8.5, 2.0, -0.8], [11.0, -2.5, -1.5], [5.0, 1.5, 2.0],
              [9.0, 0.2, 0.4]])
CQ = np.array([np.diag([0.2 * p * p / 36, 0.004 * p, 0.003 * p]) for p in Q[:, 0]])


def room_points(c, R, q):
    # X_i = P_c + p R_p + x R_x + y R_y, written out by hand
    return np.array([c + p * R[:, 2] + x * R[:, 0] + y * R[:, 1] for p, x, y in q])


def test_design_row_is_a22():
    P = design_row((2.0, 3.0, 5.0))
    assert P.shape == (3, 12)
    np.testing.assert_array_equal(P[:, :3], np.eye(3))
    np.testing.assert_array_equal(P[:, 3:6], 2 * np.eye(3))
    np.testing.assert_array_equal(P[:, 6:9], 3 * np.eye(3))
    np.testing.assert_array_equal(P[:, 9:], 5 * np.eye(3))


def test_a48_recovers_a_known_pose_exactly():
    c, R = hand_pose()
    X = room_points(c, R, Q)
    prior_R = Rotation.from_euler("y", 22, degrees=True).as_matrix()   # 8 deg off
    est = solve_a48(Q, CQ, X, c + [0.4, 0.0, -0.3], prior_R)
    Y_true = np.concatenate([c, R[:, 2], R[:, 0], R[:, 1]])
    np.testing.assert_allclose(est.Y, Y_true, atol=1e-9)
    assert est.heading_deg == pytest.approx(np.degrees(np.arctan2(R[0, 2], R[2, 2])), abs=1e-9)
    np.testing.assert_allclose(est.centre, c + 0.375 * R[:, 0], atol=1e-9)


@pytest.mark.parametrize("method", ESTIMATORS)
def test_every_method_agrees_on_noise_free_points(method):
    c, R = hand_pose()
    if method == "floor":      # x, z, heading only: a level rig 3 ft above the floor
        c, R = np.array([1.5, 0.0, 2.0]), Rotation.from_euler("y", 30, degrees=True).as_matrix()
    X = room_points(c, R, Q)
    est = estimate(method, Q, CQ, X, np.zeros_like(CQ), c + 0.2,
                   Rotation.from_euler("y", 25, degrees=True).as_matrix())
    tol = 1e-3 if method == "opencv" else 1e-8
    np.testing.assert_allclose(est.left, c, atol=tol)
    assert est.heading_deg == pytest.approx(30.0, abs=tol * 10)


def test_a48_refuses_too_few_points():
    c, R = hand_pose()
    X = room_points(c, R, Q[:2])
    with pytest.raises(PoseRefused, match="only 2 matched points.*at least 3"):
        solve_a48(Q[:2], CQ[:2], X, c, R)
    with pytest.raises(PoseRefused, match="only 0"):
        check_conditions(np.zeros((0, 3)))


def test_a48_refuses_colinear_points():
    c, R = hand_pose()
    q = np.array([[5.0, 0.0, 0.0], [6.0, 0.5, 0.25], [7.0, 1.0, 0.5], [9.0, 2.0, 1.0]])
    X = room_points(c, R, q)
    with pytest.raises(PoseRefused, match="colinear"):
        solve_a48(q, CQ[:4], X, c, R)


def test_a48_refuses_coplanar_points_its_normal_matrix_is_singular():
    # three points satisfy the text's conditions 1 and 2, but P^T D P is rank 9
    c, R = hand_pose()
    X = room_points(c, R, Q[:3])
    with pytest.raises(PoseRefused, match="one plane"):
        solve_a48(Q[:3], CQ[:3], X, c, R)


def monte_carlo(c, R, q, Cq, trials, perturb, seed):
    rng = np.random.default_rng(seed)
    X = room_points(c, R, q)
    L = np.linalg.cholesky(Cq)
    Cpi = environment_covariance(np.column_stack([R[:, 2], R[:, 0], R[:, 1]]), Cq)
    Lx = np.linalg.cholesky(Cpi)
    ys = []
    for _ in range(trials):
        if perturb == "model":        # Y is linear in X'; X' noisy with C_pi
            n = np.einsum("nij,nj->ni", Lx, rng.standard_normal(q.shape))
            ys.append(solve_a48(q, Cq, X + n, c, R, iterations=1).Y)
        else:                         # the rig's own error: camera points noisy with C_i
            n = np.einsum("nij,nj->ni", L, rng.standard_normal(q.shape))
            ys.append(solve_a48(q + n, Cq, X, c, R, iterations=1).Y)
    return np.cov(np.array(ys).T)


@pytest.mark.parametrize("perturb", ["model", "camera"])
def test_a50_covariance_agrees_with_monte_carlo(perturb):
    c, R = hand_pose()
    rng = np.random.default_rng(7)
    q = np.column_stack([rng.uniform(4, 12, 12), rng.uniform(-3, 3, 12), rng.uniform(-2, 2, 12)])
    Cq = np.array([np.diag([(0.01 * p) ** 2, 0.01 ** 2, 0.012 ** 2]) for p in q[:, 0]])
    Cc = solve_a48(q, Cq, room_points(c, R, q), c, R, iterations=1).Cc
    mc = monte_carlo(c, R, q, Cq, 3000, perturb, seed=11)
    ratio = np.diag(mc) / np.diag(Cc)
    assert np.all(np.abs(ratio - 1) < 0.10), ratio


def test_pose_covariance_at_is_p_cc_pt():
    c, R = hand_pose()
    est = solve_a48(Q, CQ, room_points(c, R, Q) + 0.01, c, R)
    got = est.pose_covariance_at(Q)
    for i, qi in enumerate(Q):
        P = design_row(qi)
        np.testing.assert_allclose(got[i], P @ est.Cc @ P.T, rtol=1e-10, atol=1e-14)


def test_robust_rejects_wrong_correspondences():
    c, R = hand_pose()
    rng = np.random.default_rng(3)
    q = np.column_stack([rng.uniform(4, 12, 14), rng.uniform(-3, 3, 14), rng.uniform(-2, 2, 14)])
    Cq = np.array([np.diag([(0.02 * p) ** 2, 0.01 ** 2, 0.01 ** 2]) for p in q[:, 0]])
    X = room_points(c, R, q) + rng.normal(0, 0.005, (14, 3))
    X[[2, 9]] += [[1.5, 0.0, 0.0], [-0.8, 0.0, 1.0]]          # two wrong pairs
    est = solve_robust(q, Cq, X, np.zeros_like(Cq), c + 0.3, R)
    assert list(np.flatnonzero(~est.inliers)) == [2, 9]
    np.testing.assert_allclose(est.left, c, atol=0.05)


def test_a48_with_degenerate_weights_is_refused_not_raised(monkeypatch):
    # an A-48 iterate whose axes collapse makes the A-31 covariance singular: the look is
    # refused with a reason, as the text's other conditions are, instead of an exception
    import model.pose as pose
    from model.pose import PoseRefused, estimate

    def singular(*a, **k):
        raise np.linalg.LinAlgError("Singular matrix")
    monkeypatch.setattr(pose, "solve_a48", singular)
    with pytest.raises(PoseRefused, match="singular"):
        estimate("a48", np.zeros((4, 3)), np.zeros((4, 3, 3)), np.zeros((4, 3)),
                 np.zeros((4, 3, 3)), np.zeros(3), np.eye(3))
