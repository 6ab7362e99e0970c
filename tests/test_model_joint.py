"""The joint filter of pose and features (model.joint, ``rig walk --kalman joint``).

External truths: (a) a linear walk whose filter result must equal the batch weighted
least squares solution of all its measurements, computed independently from the normal
equations; (b) a hand-made loop closure whose true geometry is known exactly; the
Jacobians against finite differences; (c) the command end to end."""

import json

import numpy as np
import pytest

from model.joint import (JointFilter, camera_point, camera_point_jacobians, ekf_augment,
                         ekf_predict, ekf_update, room_point, room_point_jacobians)
from model.kalman import static_update


def test_predict_moves_only_the_pose_rows_and_columns_as_the_full_product_does():
    rng = np.random.default_rng(3)
    n, k = 12, 3
    A = rng.normal(size=(n, n))
    P = A @ A.T + n * np.eye(n)
    F = np.array([[1.0, 0.0, 0.4], [0.0, 1.0, -0.2], [0.0, 0.0, 1.0]])
    Q = np.diag([0.01, 0.02, 0.003])
    Fn = np.eye(n)
    Fn[:k, :k] = F
    Qn = np.zeros((n, n))
    Qn[:k, :k] = Q
    want = Fn @ P @ Fn.T + Qn                   # the textbook product over the whole state
    got = ekf_predict(P, F, Q, k)
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    assert np.array_equal(got, got.T)
    assert np.array_equal(got[k:, k:], P[k:, k:])   # the features' own block untouched
    same = P.copy()
    out = ekf_predict(same, F, Q, k, in_place=True)
    assert out is same and np.array_equal(same, got)
    assert not np.array_equal(P, got)           # the plain call left its argument alone


# --- (a) linear: the filter equals batch weighted least squares -----------------------

def test_linear_joint_filter_equals_batch_weighted_least_squares():
    """A 2-D robot (x, y) moves by noisy odometry and measures three 2-D landmarks
    relative to itself (z = f - x + noise); the filter's final pose and landmarks, and
    their joint covariance, are the batch solution over every pose and landmark
    (the information matrix A^T W A inverted, its final-pose and landmark block)."""
    rng = np.random.default_rng(7)
    d = 2
    p0, q, r = 0.02, np.diag([0.04, 0.01]), np.diag([0.09, 0.05])
    odometry = [np.array([1.0, 0.2]), np.array([0.8, -0.1]), np.array([-1.5, 0.3])]
    # (look, landmark) pairs: the last look re-observes landmark 0 (a loop)
    seen = {0: [0, 1], 1: [0, 2], 2: [1, 2], 3: [0]}
    z = {(t, j): rng.normal(size=d) * 3 for t in seen for j in seen[t]}
    T, N = len(odometry) + 1, 3

    # the filter: state (pose, landmarks in the order first seen)
    mean, cov = np.zeros(d), p0 * np.eye(d)
    order = []
    for t in range(T):
        if t:
            mean = mean.copy()
            mean[:d] += odometry[t - 1]
            cov = ekf_predict(cov, np.eye(d), q, d)
        old = [j for j in seen[t] if j in order]
        if old:
            H = np.zeros((d * len(old), len(mean)))
            innov = np.zeros(d * len(old))
            R = np.zeros((d * len(old), d * len(old)))
            for k, j in enumerate(old):
                i = d + d * order.index(j)
                rows = slice(d * k, d * k + d)
                H[rows, :d] = -np.eye(d)
                H[rows, i:i + d] = np.eye(d)
                R[rows, rows] = r
                innov[rows] = z[t, j] - (mean[i:i + d] - mean[:d])
            mean, cov = ekf_update(mean, cov, innov, H, R)
        for j in seen[t]:
            if j not in order:
                J = np.zeros((d, len(mean)))
                J[:, :d] = np.eye(d)
                mean, cov = ekf_augment(mean, cov, mean[:d] + z[t, j], J, r)
                order.append(j)

    # the batch: unknowns x_0..x_{T-1}, f_0..f_{N-1}
    n = d * (T + N)
    rows_A, rows_b, rows_W = [], [], []

    def row(coeffs, b, W):
        A = np.zeros((d, n))
        for idx, c in coeffs:
            A[:, d * idx:d * idx + d] += c * np.eye(d)
        rows_A.append(A), rows_b.append(b), rows_W.append(np.linalg.inv(W))
    row([(0, 1.0)], np.zeros(d), p0 * np.eye(d))
    for t in range(1, T):
        row([(t, 1.0), (t - 1, -1.0)], odometry[t - 1], q)
    for (t, j), zz in z.items():
        row([(T + j, 1.0), (t, -1.0)], zz, r)
    A = np.vstack(rows_A)
    b = np.concatenate(rows_b)
    W = np.zeros((len(b), len(b)))
    for k, Wk in enumerate(rows_W):
        W[d * k:d * k + d, d * k:d * k + d] = Wk
    info = A.T @ W @ A
    theta = np.linalg.solve(info, A.T @ W @ b)
    C = np.linalg.inv(info)
    keep = list(range(d * (T - 1), d * T)) + [d * (T + j) + a for j in order for a in range(d)]
    np.testing.assert_allclose(mean, theta[keep], atol=1e-10)
    np.testing.assert_allclose(cov, C[np.ix_(keep, keep)], atol=1e-10)


# --- the floor pose's measurement functions -------------------------------------------

@pytest.mark.parametrize("pose", [(0.0, 0.0, 0.0), (1.5, -2.0, np.radians(37.0)),
                                  (-3.0, 4.0, np.radians(-160.0))])
@pytest.mark.parametrize("pitch", [0.0, -8.0])
def test_measurement_and_augmentation_jacobians_match_finite_differences(pose, pitch):
    f = np.array([2.0, -1.2, 7.5])
    q = camera_point(pose, f, pitch)
    np.testing.assert_allclose(room_point(pose, q, pitch), f, atol=1e-12)
    for fun, arg, jac in ((camera_point, f, camera_point_jacobians),
                          (room_point, q, room_point_jacobians)):
        Jp, Ja = jac(pose, arg, pitch)
        eps = 1e-6
        for c in range(3):
            dp = np.zeros(3)
            dp[c] = eps
            num = (fun(np.add(pose, dp), arg, pitch) - fun(np.subtract(pose, dp), arg, pitch)) / (2 * eps)
            np.testing.assert_allclose(Jp[:, c], num, atol=1e-6)
            num = (fun(pose, arg + dp, pitch) - fun(pose, arg - dp, pitch)) / (2 * eps)
            np.testing.assert_allclose(Ja[:, c], num, atol=1e-6)


# --- (b) loop closure -------------------------------------------------------------------

def test_reobserving_the_first_feature_pulls_the_pose_and_the_other_features_back():
    """Look 0 at the known start sees A; the odometry then claims 1.3 ft to the right
    where the robot moved 1.0; look 1 sees B and C for the first time (placed 0.3 ft off,
    with the pose's error); look 2, not moving, sees A again.  The joint filter pulls the
    pose and B and C back to their true places; the per-feature static update (A-29:
    the pose's covariance in the measurement) improves only A, and B and C keep their
    0.3 ft."""
    A, B, C = np.array([0.0, 0.0, 8.0]), np.array([3.0, 0.5, 9.0]), np.array([-1.0, -0.4, 6.0])
    true0, true1 = np.array([0.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])
    Cq = np.diag([0.02, 0.005, 0.005]) ** 2
    Q = np.diag([0.3, 0.3, np.radians(0.5)]) ** 2          # the step's noise, honest to 0.3 ft

    jf = JointFilter((0.0, 0.0, 0.0), np.zeros((3, 3)))
    jf.add(0, camera_point(true0, A), Cq)
    jf.predict((1.3, 0.0, 0.0), np.eye(3), Q)
    jf.add(1, camera_point(true1, B), Cq)
    jf.add(2, camera_point(true1, C), Cq)
    before = {vid: np.linalg.norm(jf.feature(vid)[0] - X) for vid, X in ((1, B), (2, C))}
    assert before[1] == pytest.approx(0.3, abs=1e-9) and before[2] == pytest.approx(0.3, abs=1e-9)
    assert jf.cov[0, 3 + 3] > 0                  # B's x shares the pose's x error
    jf.predict((1.3, 0.0, 0.0), np.eye(3), np.diag([1e-4, 1e-4, 1e-6]))
    jf.update([(0, camera_point(true1, A), Cq)])
    assert abs(jf.mean[0] - 1.0) < 0.02 and abs(jf.mean[1]) < 0.02
    for vid, X in ((1, B), (2, C)):
        assert np.linalg.norm(jf.feature(vid)[0] - X) < 0.05
    assert np.linalg.norm(jf.feature(0)[0] - A) < 0.02

    # the per-feature update: A's look-2 observation placed from the odometry's pose
    # (1.3, 0, 0) with its 0.3 ft in the measurement covariance; B and C are not touched
    Rp = Q[0, 0] * np.diag([1.0, 0.0, 1.0]) + np.diag([0.0, 1e-12, 0.0])
    zA = room_point((1.3, 0.0, 0.0), camera_point(true1, A))
    mA, _ = static_update(A, Cq, zA, Cq + Rp)
    assert np.linalg.norm(mA - A) < 0.01        # A stays, being the surer
    # the per-feature model's B and C are where the drifted pose placed them
    for X in (B, C):
        placed = room_point((1.3, 0.0, 0.0), camera_point(true1, X))
        assert np.linalg.norm(placed - X) == pytest.approx(0.3, abs=1e-9)


def test_drop_marginalises_a_feature():
    jf = JointFilter((0.0, 0.0, 0.0), np.diag([0.01, 0.01, 0.001]))
    jf.add_many([(5, np.array([6.0, 0.1, 0.2]), np.eye(3) * 0.01),
                 (9, np.array([8.0, -0.5, 0.0]), np.eye(3) * 0.02)])
    m9, c9 = jf.feature(9)
    cross = jf.cov[:3, 6:9].copy()
    jf.drop([5])
    assert jf.ids == [9] and 5 not in jf and len(jf.mean) == 6
    np.testing.assert_allclose(jf.feature(9)[0], m9)
    np.testing.assert_allclose(jf.feature(9)[1], c9)
    np.testing.assert_allclose(jf.cov[:3, 3:6], cross)
    with pytest.raises(ValueError, match="already"):
        jf.add(9, np.array([5.0, 0.0, 0.0]), np.eye(3))


# --- (c) the command ----------------------------------------------------------------------

def test_rig_walk_kalman_joint_end_to_end(tmp_path):
    from rig.main import main
    rc = main(["walk", "--looks", "5", "--kalman", "joint", "--confirm", "2",
               "--out", str(tmp_path / "o"), "--json", str(tmp_path / "w.json"), "--quiet"])
    assert rc == 0
    doc = json.loads((tmp_path / "w.json").read_text())
    assert [lk["look"] for lk in doc["looks"]] == [0, 1, 2, 3, 4]
    fused = [lk["methods"]["fused"] for lk in doc["looks"]]
    assert fused[0]["position_error_ft"] == 0.0
    assert max(f["position_error_ft"] for f in fused) < 0.5
    assert max(f["heading_error_deg"] for f in fused) < 3.0
    model = doc["model"]
    assert model["features"] > 50 and 0.5 < model["inside_2sigma"] <= 1
    full = json.loads((tmp_path / "o" / "model.json").read_text())
    assert len(full["model_tables"]["vertices"]) == model["features"]


def test_joint_filter_keeps_the_model_and_the_state_in_step():
    """After a short walk the symbolic model's vertices are exactly the joint state's
    features, each with the state's marginal mean and covariance."""
    from model.mapping import Walker, WalkConfig
    from world.odometry import OdometryNoise, dead_reckon
    from world.render import render_look
    from world.room import bundled_lab
    from world.walk import bundled_walk
    room, poses = bundled_lab(), bundled_walk()[:4]
    dr = dead_reckon(poses, OdometryNoise(seed=1985))
    w = Walker(room, WalkConfig(kalman="joint", methods=("robust",)))
    for k, p in enumerate(poses):
        w.step(render_look(room, p, seed=1985 + k), p, dr[k], dr[k - 1] if k else None)
    assert sorted(w.joint.ids) == sorted(w.model.vertices)
    for vid, v in w.model.vertices.items():
        m, c = w.joint.feature(vid)
        np.testing.assert_array_equal(v.mean, m)
        np.testing.assert_array_equal(v.cov, c)
    np.testing.assert_allclose(w.records[-1].pose_covariance, w.joint.pose_cov)
    assert np.all(np.linalg.eigvalsh(w.joint.cov) > -1e-9)


def test_joint_with_the_tilt_floor_is_refused(tmp_path, capsys):
    """The tilt floor widens the static consider's camera term; the joint state carries
    the pose itself: one clear error, nothing written."""
    from model.mapping import Walker, WalkConfig
    from rig.main import main
    from world.room import bundled_lab
    with pytest.raises(ValueError, match="joint"):
        Walker(bundled_lab(), WalkConfig(kalman="joint", consider="bound", tilt_floor=(0.3, 3)))
    rc = main(["walk", "--looks", "2", "--kalman", "joint", "--consider", "bound",
               "--tilt-floor", "measured", "--out", str(tmp_path / "o"), "--quiet"])
    assert rc == 2 and "--tilt-floor" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


# --- the consider covariance of the joint filter ------------------------------------------

def _linear_walk(rng, R_true, trials, r, q, consider):
    """A linear 2-D walk (the batch test's): the robot moves by odometry with noise q
    and sees landmarks relative to itself; the filter's gains come from ``r``, the
    measurements' errors are drawn with ``R_true``.  Returns (the filter's errors over
    ``trials`` draws (trials, n), its own covariance, the consider covariance)."""
    from model.joint import consider_joint_update, ekf_update_with_gain
    d = 2
    truth_f = np.array([[3.0, 1.0], [-2.0, 4.0], [1.0, -3.0]])
    odometry = [np.array([1.0, 0.2]), np.array([0.8, -0.1]), np.array([-1.5, 0.3])]
    seen = {0: [0, 1], 1: [0, 2], 2: [1, 2], 3: [0, 1]}
    Lq, Lt = np.linalg.cholesky(q), np.linalg.cholesky(R_true)
    errors = []
    for _ in range(trials):
        x = np.zeros(d)
        mean, cov, Pc, order = np.zeros(d), np.zeros((d, d)), np.zeros((d, d)), []
        for t in range(len(seen)):
            if t:
                x = x + odometry[t - 1] + Lq @ rng.normal(size=d)     # the true motion
                mean = mean.copy()
                mean[:d] += odometry[t - 1]
                cov = ekf_predict(cov, np.eye(d), q, d)
                Pc = ekf_predict(Pc, np.eye(d), q, d)
            z = {j: truth_f[j] - x + Lt @ rng.normal(size=d) for j in seen[t]}
            old = [j for j in seen[t] if j in order]
            if old:
                m = d * len(old)
                H, innov = np.zeros((m, len(mean))), np.zeros(m)
                for k, j in enumerate(old):
                    i = d + d * order.index(j)
                    H[d * k:d * k + d, :d] = -np.eye(d)
                    H[d * k:d * k + d, i:i + d] = np.eye(d)
                    innov[d * k:d * k + d] = z[j] - (mean[i:i + d] - mean[:d])
                R = np.kron(np.eye(len(old)), r)
                mean, cov, K = ekf_update_with_gain(mean, cov, innov, H, R)
                Pc = consider_joint_update(Pc, K, H, np.kron(np.eye(len(old)), R_true),
                                           consider)
            for j in seen[t]:
                if j not in order:
                    J = np.zeros((d, len(mean)))
                    J[:, :d] = np.eye(d)
                    _, Pc = ekf_augment(mean, Pc, mean[:d] + z[j], J, R_true)
                    mean, cov = ekf_augment(mean, cov, mean[:d] + z[j], J, r)
                    order.append(j)
        errors.append(mean - np.concatenate([x, *truth_f[order]]))
    return np.array(errors), cov, Pc


def test_joseph_consider_covariance_equals_a_monte_carlo_of_the_filters_error():
    """Hand test (linear, so the gains do not depend on the draws): the filter computes
    its gains with r, the true measurement noise is three times the variance and
    correlated; over 3000 draws the covariance of the filter's error equals the Joseph
    consider covariance within 10 % on the diagonal, while the filter's own covariance
    is well below it."""
    rng = np.random.default_rng(1985)
    q, r = np.diag([0.04, 0.01]), np.diag([0.09, 0.05])
    R_true = np.array([[0.27, 0.05], [0.05, 0.15]])
    err, own, Pc = _linear_walk(rng, R_true, 3000, r, q, "joseph")
    mc = np.cov(err.T)
    np.testing.assert_allclose(np.diag(Pc), np.diag(mc), rtol=0.10)
    assert np.all(np.diag(own) < 0.8 * np.diag(mc))
    # the bound covers it too (positive semidefinite difference, within sampling noise)
    _, _, Pb = _linear_walk(np.random.default_rng(1), R_true, 1, r, q, "bound")
    assert np.linalg.eigvalsh(Pb - 1.05 * mc).min() > -1e-3 * np.trace(mc)
    assert np.all(np.diag(Pb) >= np.diag(Pc))


def test_consider_joint_update_with_the_filters_own_noise_is_the_filters_covariance():
    """With R_true = R the Joseph form equals the filter's P - K S K^T (the optimal gain)."""
    from model.joint import consider_joint_update, ekf_update_with_gain
    rng = np.random.default_rng(3)
    A = rng.normal(size=(7, 7))
    P = A @ A.T + np.eye(7)
    H = np.zeros((4, 7))
    H[:, [0, 1, 4, 5]] = rng.normal(size=(4, 4))
    R = np.diag([0.5, 0.2, 0.3, 0.4])
    _, P1, K = ekf_update_with_gain(np.zeros(7), P, rng.normal(size=4), H, R)
    np.testing.assert_allclose(consider_joint_update(P, K, H, R, "joseph"), P1, atol=1e-10)
    # and the dense (I-KH) P (I-KH)^T + K R K^T written out
    I_KH = np.eye(7) - K @ H
    np.testing.assert_allclose(consider_joint_update(P, K, H, 2 * R, "joseph"),
                               I_KH @ P @ I_KH.T + K @ (2 * R) @ K.T, atol=1e-10)


@pytest.mark.parametrize("mode", ["joseph", "bound"])
def test_joint_consider_leaves_means_and_poses_unchanged_end_to_end(tmp_path, mode):
    """``rig walk --kalman joint --consider MODE``: every pose and every feature mean
    equal plain joint's to the digit; the features report the consider covariance (wider
    than the filter's), and it is what is scored."""
    from rig.main import main
    docs = {}
    for name, extra in (("plain", []), (mode, ["--consider", mode])):
        rc = main(["walk", "--looks", "4", "--kalman", "joint", "--confirm", "2",
                   "--column-error", "calibrated", *extra, "--out", str(tmp_path / name),
                   "--json", str(tmp_path / f"{name}.json"), "--quiet"])
        assert rc == 0
        docs[name] = (json.loads((tmp_path / f"{name}.json").read_text()),
                      json.loads((tmp_path / name / "model.json").read_text()))
    (plain, plain_model), (cons, cons_model) = docs["plain"], docs[mode]
    for a, b in zip(plain["looks"], cons["looks"]):
        for key in ("x", "z", "heading_deg"):
            assert a["methods"]["fused"][key] == b["methods"]["fused"][key]
    va, vb = plain_model["model_tables"]["vertices"], cons_model["model_tables"]["vertices"]
    assert len(va) == len(vb) > 50
    for a, b in zip(va, vb):
        assert a["mean"] == b["mean"] and a["cov"] == b["cov"]
        assert a["report_cov"] is None and b["report_cov"] is not None
    trace = [(np.trace(np.array(b["report_cov"])), np.trace(np.array(b["cov"]))) for b in vb]
    assert np.median([c / f for c, f in trace]) > 1.2
    assert cons["model"]["inside_2sigma"] > plain["model"]["inside_2sigma"]
    assert cons["model"]["filter_inside_2sigma"] == plain["model"]["inside_2sigma"]


def test_the_map_legend_names_the_kalman_mode():
    from types import SimpleNamespace
    from rig.walkpictures import path_legend
    joint = path_legend(SimpleNamespace(config=SimpleNamespace(kalman="joint")), "robust")
    assert "kalman joint" in joint[1] and "fused" not in joint[1]
    static = path_legend(SimpleNamespace(config=SimpleNamespace(kalman="a29")), "robust")
    assert static[1] == "estimated (fused: robust + odometry)"


def test_the_joint_gate_leaves_out_an_observation_far_outside_its_joint_covariance():
    """A re-observation 2 ft off where pose and feature are sure to centimetres is left out
    (nothing moves); the same 2 ft inside a wide pose covariance passes and is fused."""
    f = np.array([1.0, 0.0, 8.0])
    Cq = np.eye(3) * 0.02 ** 2
    for pose_sigma, left_out in ((0.01, True), (3.0, False)):
        jf = JointFilter((0.0, 0.0, 0.0), np.zeros((3, 3)))
        jf.add(3, camera_point((0.0, 0.0, 0.0), f), Cq)
        jf.predict((0.0, 0.0, 0.0), np.eye(3), np.diag([pose_sigma, pose_sigma, 1e-4]) ** 2)
        before = jf.mean.copy()
        out = jf.update([(3, camera_point((2.0, 0.0, 0.0), f), Cq)], gate_chi2=16.27)
        assert (out == [3]) is left_out
        assert np.array_equal(jf.mean, before) is left_out


def test_seed_tables_carry_the_model_update_time_where_the_rows_have_it():
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    import walk as bw
    f = dict(position_ft=0.1, heading_deg=0.5, ten_look_features=20, ten_look_ratio=0.3,
             leave_one_out=(0.25, 0.35), inside_2sigma=0.75, features=500, look_ms=150.0,
             update_ms=97.0, update_ms_last10=122.0, final_model=591)
    text = bw.seed_tables([("joint", 1985, f)])
    assert "| 75.0 % of 500 | 150 | 97, 122 (591) |" in text
    assert "model update ms" in text


def test_bench_joint_consider_rows_are_the_joint_rows_with_the_consider_covariance():
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    import walk as bw
    rows = bw.joint_consider_configs("joseph")
    assert list(rows) == [f"{n} + consider joseph" for n in bw.JOINT_CONFIGS]
    for (name, kw), plain in zip(rows.items(), bw.JOINT_CONFIGS.values()):
        assert kw == dict(plain, consider="joseph")


# --- the in-place working form equals the plain steps ---------------------------------------

def _random_joint_problem(rng, n_features=40, pairs=12):
    """A random SPD joint covariance (pose + features), a look's H touching the pose and
    ``pairs`` features, block-diagonal R and R_true, an innovation."""
    n = 3 + 3 * n_features
    A = rng.normal(size=(n, n + 5))
    P = A @ A.T / n + 0.1 * np.eye(n)
    seen = np.sort(rng.choice(n_features, pairs, replace=False))
    m = 3 * pairs
    H = np.zeros((m, n))
    R, R_true = np.zeros((m, m)), np.zeros((m, m))
    for k, f in enumerate(seen):
        rows = slice(3 * k, 3 * k + 3)
        H[rows, :3] = rng.normal(size=(3, 3))
        H[rows, 3 + 3 * f:6 + 3 * f] = rng.normal(size=(3, 3))
        B = rng.normal(size=(3, 3))
        R[rows, rows] = B @ B.T * 0.01 + 0.01 * np.eye(3)
        R_true[rows, rows] = 2.5 * R[rows, rows] + 0.005 * np.eye(3)
    cols = np.flatnonzero(np.any(H != 0, axis=0))
    return P, H, cols, R, R_true, rng.normal(size=m), rng.normal(size=n)


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_the_in_place_update_equals_the_plain_update_on_random_states():
    from model.joint import ekf_update_in_place, ekf_update_with_gain
    rng = np.random.default_rng(11)
    for trial in range(5):
        P, H, cols, R, _, innov, mean = _random_joint_problem(rng, 30 + 20 * trial, 5 + trial)
        m_plain, P_plain, K_plain = ekf_update_with_gain(mean, P, innov, H, R)
        m_fast, P_fast = mean.copy(), P.copy()
        K = ekf_update_in_place(m_fast, P_fast, innov, H[:, cols], cols, R,
                                np.empty(P.size))
        assert _rel(K, K_plain) < 1e-12
        assert _rel(m_fast, m_plain) < 1e-12
        assert _rel(P_fast, P_plain) < 1e-12
        assert np.array_equal(P_fast, P_fast.T)           # exactly symmetric (syrk)
        assert not np.allclose(P_fast, P)                 # it did change


@pytest.mark.parametrize("mode", ["joseph", "bound"])
def test_the_in_place_consider_update_equals_the_plain_one_on_random_states(mode):
    from model.joint import consider_joint_update, consider_update_in_place, ekf_update_with_gain
    rng = np.random.default_rng(12)
    for trial in range(5):
        P, H, cols, R, R_true, innov, mean = _random_joint_problem(rng, 30 + 20 * trial,
                                                                   5 + trial)
        B = rng.normal(size=P.shape)
        Pc = P + B @ B.T / len(P)                         # a wider consider covariance
        _, _, K = ekf_update_with_gain(mean, P, innov, H, R)
        want = consider_joint_update(Pc, K, H, R_true, mode)
        got = Pc.copy()
        consider_update_in_place(got, K, H[:, cols], cols, R_true, mode, np.empty(P.size))
        assert _rel(got, want) < 1e-12
        assert np.array_equal(got, got.T)


def _two_filters(consider):
    return [JointFilter((0.3, -0.2, 10.0), np.diag([0.01, 0.02, 1e-3]), 4.0,
                        consider=consider, reference=ref) for ref in (True, False)]


@pytest.mark.parametrize("consider", [None, "joseph", "bound"])
def test_the_joint_filter_in_place_equals_its_plain_reference_over_a_sequence(consider):
    """Augment past the first allocation (200 features > 128), predict, update with the
    gate, drop, augment again: the preallocated in-place filter's mean, covariance and
    consider covariance are the plain steps' to 1e-12 relative."""
    rng = np.random.default_rng(5)
    filters = _two_filters(consider)
    pts = np.column_stack([rng.uniform(-6, 6, 260), rng.uniform(-1, 1, 260),
                           rng.uniform(3, 15, 260)])
    Cq = np.diag([0.2, 0.03, 0.03]) ** 2
    Ct = 2.0 * Cq
    pose = (0.3, -0.2, 10.0)

    def obs(ids, shift=0.0):
        return [(int(k), camera_point(np.array([pose[0] + shift, pose[1], np.radians(pose[2])]),
                                      pts[k], 4.0) + rng.normal(size=3) * 0.01, Cq)
                for k in ids]

    batches = [("add", range(0, 90)), ("add", range(90, 200)), ("predict", None),
               ("update", rng.choice(200, 25, replace=False)), ("drop", range(10, 40)),
               ("add", range(200, 260)), ("predict", None),
               ("update", rng.choice(np.r_[0:10, 40:260], 30, replace=False))]
    for what, ids in batches:
        if what == "add":
            o = obs(ids)
            for jf in filters:
                jf.add_many(o, [Ct] * len(o) if consider else None)
        elif what == "predict":
            F = np.array([[1.0, 0.0, 0.1], [0.0, 1.0, -0.05], [0.0, 0.0, 1.0]])
            for jf in filters:
                jf.predict((pose[0] + 0.5, pose[1], pose[2] + 3.0), F,
                           np.diag([0.02, 0.02, 0.01]) ** 2)
        elif what == "update":
            o = obs(ids, shift=0.02)
            outs = [jf.update(o, 16.27, [Ct] * len(o) if consider else None) for jf in filters]
            assert outs[0] == outs[1]
        else:
            for jf in filters:
                jf.drop(ids)
        plain, fast = filters
        assert plain.ids == fast.ids
        assert _rel(fast.mean, plain.mean) < 1e-12
        assert _rel(fast.cov, plain.cov) < 1e-12
        if consider:
            assert _rel(fast.consider_cov, plain.consider_cov) < 1e-12
    assert fast._cap > 3 + 3 * 128                   # it grew past the first allocation
    assert len(fast.mean) == 3 + 3 * len(fast.ids) == fast.cov.shape[0]
    means, covs, considered = fast.marginals()      # all the blocks at once
    for j, vid in enumerate(fast.ids):
        m, c = fast.feature(vid)
        assert np.array_equal(means[j], m) and np.array_equal(covs[j], c)
        if consider:
            assert np.array_equal(considered[j], fast.consider_feature(vid))
    assert (considered is None) is (consider is None)


def test_the_bundled_walk_with_the_in_place_filter_is_the_plain_filters(monkeypatch):
    """End to end (the issue's target configuration, 12 looks): the same pairs used, the
    same poses, means and covariances as with the plain reference steps, to rounding."""
    import functools
    import model.mapping as mapping
    from world.odometry import OdometryNoise, dead_reckon
    from world.render import render_look
    from world.room import bundled_lab
    from world.walk import bundled_walk
    room, poses = bundled_lab(), bundled_walk()[:12]
    dr = dead_reckon(poses, OdometryNoise(seed=1985))
    cfg = mapping.WalkConfig(kalman="joint", methods=("robust",), confirm=2,
                             column_error_px=mapping.CALIBRATED_COLUMN_ERROR_PX,
                             ambiguity_gate="resolve", consider="bound")
    looks = [render_look(room, p, seed=1985 + k) for k, p in enumerate(poses)]
    walkers = {}
    for ref in (True, False):
        monkeypatch.setattr(mapping, "JointFilter",
                            functools.partial(JointFilter, reference=ref))
        w = mapping.Walker(room, cfg)
        for k, p in enumerate(poses):
            w.step(looks[k], p, dr[k], dr[k - 1] if k else None)
        walkers[ref] = w
    plain, fast = walkers[True], walkers[False]
    assert plain.joint.reference and not fast.joint.reference
    assert len(fast.joint.ids) > 100
    for a, b in zip(plain.records, fast.records):
        assert (a.matched, a.used, a.added, a.model_size) == (b.matched, b.used, b.added,
                                                              b.model_size)
        # 1e-9, as for the covariances below: OpenBLAS picks its kernels by CPU, and on
        # an AMD EPYC the two filters' different operation orders part by ~1e-10 rad.
        np.testing.assert_allclose(b.estimates["fused"], a.estimates["fused"],
                                   rtol=1e-9, atol=1e-12)
    assert plain.joint.ids == fast.joint.ids
    assert _rel(fast.joint.cov, plain.joint.cov) < 1e-9
    assert _rel(fast.joint.consider_cov, plain.joint.consider_cov) < 1e-9
    for vid, v in fast.model.vertices.items():
        u = plain.model.vertices[vid]
        np.testing.assert_allclose(v.mean, u.mean, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(v.report_cov, u.report_cov, rtol=1e-8, atol=1e-14)

