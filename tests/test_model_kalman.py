"""The static Kalman update (Chapter III "Stochastic Updates") against a
3-D example computed by hand."""

import numpy as np
import pytest

from model.kalman import measurement_covariance_a29, measurement_covariance_a30, static_update


def test_static_update_hand_example():
    # P = diag(4, 1, 9), R = diag(4, 3, 4.5): K = diag(4/8, 1/4, 9/13.5) = diag(1/2, 1/4, 2/3)
    # m = (1, 2, 3), z = (3, 6, 6): m' = (1 + 2/2, 2 + 4/4, 3 + 3*2/3) = (2, 3, 5)
    # P' = (I - K) P = diag(2, 3/4, 3)
    m, P = static_update([1, 2, 3], np.diag([4.0, 1, 9]), [3, 6, 6], np.diag([4.0, 3, 4.5]))
    np.testing.assert_allclose(m, [2, 3, 5], atol=1e-12)
    np.testing.assert_allclose(P, np.diag([2, 0.75, 3]), atol=1e-12)


def test_static_update_hand_example_in_turned_axes():
    # the same example seen in axes turned by the 3-4-5 rotation Q (exact entries):
    # every mean turns by Q, every covariance becomes Q C Q^T; worked out by hand,
    # Q diag(a, b, c) Q^T = [[.36a+.64b, .48a-.48b, 0], [.48a-.48b, .64a+.36b, 0], [0, 0, c]]
    Q = np.array([[0.6, -0.8, 0], [0.8, 0.6, 0], [0, 0, 1.0]])

    def turned(a, b, c):
        return np.array([[.36 * a + .64 * b, .48 * a - .48 * b, 0],
                         [.48 * a - .48 * b, .64 * a + .36 * b, 0], [0, 0, c]])

    m, P = static_update(Q @ [1, 2, 3], turned(4, 1, 9), Q @ [3, 6, 6], turned(4, 3, 4.5))
    np.testing.assert_allclose(m, [0.6 * 2 - 0.8 * 3, 0.8 * 2 + 0.6 * 3, 5], atol=1e-12)
    np.testing.assert_allclose(P, turned(2, 0.75, 3), atol=1e-12)


def test_update_is_information_fusion_and_stacks():
    rng = np.random.default_rng(5)
    A = rng.normal(size=(4, 3, 3))
    P = A @ A.transpose(0, 2, 1) + np.eye(3)
    B = rng.normal(size=(4, 3, 3))
    R = B @ B.transpose(0, 2, 1) + 0.5 * np.eye(3)
    m, z = rng.normal(size=(4, 3)), rng.normal(size=(4, 3))
    mm, PP = static_update(m, P, z, R)
    for i in range(4):
        info = np.linalg.inv(P[i]) + np.linalg.inv(R[i])
        np.testing.assert_allclose(PP[i], np.linalg.inv(info), rtol=1e-9)
        want = np.linalg.solve(info, np.linalg.solve(P[i], m[i]) + np.linalg.solve(R[i], z[i]))
        np.testing.assert_allclose(mm[i], want, rtol=1e-9, atol=1e-12)


def test_a29_adds_the_camera_term_to_a30():
    M = np.array([[0, 1.0, 0], [0, 0, 1], [1, 0, 0]])     # R_p = z, R_x = x, R_y = y
    C = np.diag([0.09, 0.01, 0.04])                      # (p, x, y)
    a30 = measurement_covariance_a30(M, C)
    np.testing.assert_allclose(a30, np.diag([0.01, 0.04, 0.09]))
    extra = np.diag([0.001, 0.002, 0.003])
    np.testing.assert_allclose(measurement_covariance_a29(M, C, extra), a30 + extra)


def test_covariance_intersection_hand_example():
    from model.kalman import covariance_intersection
    # equal covariances 2I: P' = (w/2 + (1-w)/2)^-1 I = 2I for every w (trace ties: w = 0
    # is the first grid point), mean = w m + (1-w) z = z; never smaller than either input
    m, P = covariance_intersection([0, 0, 0], 2 * np.eye(3), [1, 2, 3], 2 * np.eye(3))
    np.testing.assert_allclose(P[0], 2 * np.eye(3))
    # a sure feature and a vague measurement: w = 1 keeps the feature as it is
    m, P = covariance_intersection([1, 1, 1], 0.1 * np.eye(3), [5, 5, 5], 10 * np.eye(3))
    np.testing.assert_allclose(m[0], [1, 1, 1])
    np.testing.assert_allclose(P[0], 0.1 * np.eye(3))
    # complementary axes: P = diag(1, 4, 1), R = diag(4, 1, 1); the trace of
    # (w P^-1 + (1-w) R^-1)^-1 is least at w = 1/2: P' = diag(1.6, 1.6, 1)
    m, P = covariance_intersection([0, 0, 0], np.diag([1.0, 4, 1]), [1, 1, 1], np.diag([4.0, 1, 1]))
    np.testing.assert_allclose(P[0], np.diag([1.6, 1.6, 1.0]), atol=1e-12)
    np.testing.assert_allclose(m[0], [0.2, 0.8, 0.5], atol=1e-12)


def test_consider_update_hand_examples():
    from model.kalman import consider_update, kalman_gain
    # P = R = I: K = I/2.  Joseph form with the gain's own R is the filter's covariance, I/2;
    # the correlation-proof bound: A = B = I/4, A/w + B/(1-w) least at w = 1/2, giving I —
    # two equally good looks whose errors may be the same error are no better than one
    P, R = np.eye(3), np.eye(3)
    K = kalman_gain(P, R)
    np.testing.assert_allclose(K, np.eye(3) / 2, atol=1e-15)
    np.testing.assert_allclose(consider_update(K, P, R, correlated=False), np.eye(3) / 2,
                               atol=1e-15)
    np.testing.assert_allclose(consider_update(K, P, R), np.eye(3), atol=1e-12)
    # the gain from a filter that believes R = I/4 (K = 0.8 I) while the truth is R = 4 I,
    # P = I: Joseph 0.04 I + 0.64 * 4 I = 2.6 I, more than either the filter's 0.2 I or P
    K = kalman_gain(P, np.eye(3) / 4)
    np.testing.assert_allclose(consider_update(K, P, 4 * np.eye(3), correlated=False),
                               2.6 * np.eye(3), atol=1e-12)
    # a stack works feature by feature
    Ks = np.stack([np.eye(3) / 2, np.eye(3) / 2])
    np.testing.assert_allclose(consider_update(Ks, np.stack([P, P]), np.stack([R, R])),
                               np.stack([np.eye(3), np.eye(3)]), atol=1e-12)


def test_consider_bound_covers_correlated_looks_monte_carlo():
    # a feature seen in 6 looks whose errors share one common part (the look's pose error
    # the features of a walk share): the filter, believing the looks independent and its
    # sigma a quarter of the truth, claims far too little; the consider bound fed the true
    # per-look covariance holds the truth inside 2 sigma at least 95 % of the time; the
    # Joseph form (independent looks) does not
    from model.kalman import consider_update, kalman_gain
    from model.mapping import CHI2_3DOF_2SIGMA
    rng = np.random.default_rng(5)
    R_true = np.diag([0.3, 0.1, 0.1]) ** 2                  # per look, common + own parts
    R_filter = R_true / 16
    inside = {"filter": 0, "bound": 0, "joseph": 0}
    trials = 400
    for _ in range(trials):
        common = rng.multivariate_normal(np.zeros(3), 0.8 * R_true)
        zs = [common + rng.multivariate_normal(np.zeros(3), 0.2 * R_true) for _ in range(6)]
        m, P = zs[0], R_filter.copy()
        Pb, Pj = R_true.copy(), R_true.copy()
        for z in zs[1:]:
            K = kalman_gain(P, R_filter)
            Pb = consider_update(K, Pb, R_true)
            Pj = consider_update(K, Pj, R_true, correlated=False)
            m, P = static_update(m, P, z, R_filter)
        for name, C in (("filter", P), ("bound", Pb), ("joseph", Pj)):
            inside[name] += float(m @ np.linalg.solve(C, m)) <= CHI2_3DOF_2SIGMA
    assert inside["bound"] / trials >= 0.95
    assert inside["joseph"] / trials < 0.8
    assert inside["filter"] / trials < 0.3


# --- the a-posteriori variance factor ------------------------------------------------

def test_variance_of_unit_weight_hand_examples():
    from model.kalman import (feature_variance_factors, normalised_innovation,
                              robust_variance_factor, variance_of_unit_weight)
    # r = (2, 0, 0) against P + R = diag(2, 1, 1) + diag(2, 1, 1): 4 / 4 = 1
    assert normalised_innovation([0, 0, 0], np.diag([2.0, 1, 1]), [2, 0, 0],
                                 np.diag([2.0, 1, 1])) == pytest.approx(1.0)
    # NIS 3, 6, 9 over 3 degrees of freedom each: 18 / 9 = 2
    assert variance_of_unit_weight([3.0, 6.0, 9.0]) == pytest.approx(2.0)
    assert np.isnan(variance_of_unit_weight([]))
    # the median of chi-square(3) is 2.365974: NIS whose median is that give factor 1
    assert robust_variance_factor([0.1, 2.365974, 50.0]) == pytest.approx(1.0)
    # pooling (prior 3 dof at the global factor g = 1): a feature with NIS 12, 12 gives
    # (3 * 1 + 24) / (3 + 6) = 3; none gives g; one tiny NIS gives (3 + 0.3) / 6 = 0.55,
    # floored at 1 unless the floor is off
    f = feature_variance_factors([[12.0, 12.0], [], [0.3]], 1.0)
    np.testing.assert_allclose(f, [3.0, 1.0, 1.0])
    f = feature_variance_factors([[12.0, 12.0], [], [0.3]], 1.0, floor=None)
    np.testing.assert_allclose(f, [3.0, 1.0, 0.55])


def test_variance_factor_is_four_when_errors_are_twice_the_claimed_sigma_monte_carlo():
    # 2000 static features seen in 6 looks each; the filter claims R (anisotropic, range
    # 10x the lateral), the observations are drawn with twice its sigma.  Every
    # innovation's true covariance is then 4 (P + R): the variance of unit weight of the
    # innovations is 4 (honest sigma: 1), the robust one too, and a feature's pooled factor
    # is near 4 once it has several looks
    from model.kalman import (feature_variance_factors, normalised_innovation,
                              robust_variance_factor, static_update, variance_of_unit_weight)
    rng = np.random.default_rng(42)
    R = np.diag([0.25, 0.0025, 0.0025])
    L = np.linalg.cholesky(R)
    for scale, want in ((2.0, 4.0), (1.0, 1.0)):
        nis_lists = []
        for _ in range(2000):
            truth = rng.uniform(-5, 5, 3)
            m, P = truth + scale * L @ rng.normal(size=3), R.copy()
            nis = []
            for _ in range(5):
                z = truth + scale * L @ rng.normal(size=3)
                nis.append(normalised_innovation(m, P, z, R))
                m, P = static_update(m, P, z, R)
            nis_lists.append(nis)
        every = [x for n in nis_lists for x in n]
        assert variance_of_unit_weight(every) == pytest.approx(want, rel=0.05)
        assert robust_variance_factor(every) == pytest.approx(want, rel=0.08)
        f = feature_variance_factors(nis_lists, robust_variance_factor(every), floor=None)
        assert np.median(f) == pytest.approx(want, rel=0.15)


def test_robust_variance_factor_is_not_moved_by_phantoms():
    # 10 % of the innovations are phantoms 100x out: the plain variance of unit weight
    # follows them (about 10.9), the robust one stays near the honest 1 (the median moves
    # to the clean share's 55.6 % point, chi-square(3) 2.62: factor 1.11)
    from model.kalman import robust_variance_factor, variance_of_unit_weight
    rng = np.random.default_rng(7)
    nis = rng.chisquare(3, 5000)
    nis[:500] *= 100
    assert variance_of_unit_weight(nis) > 5
    assert 1.0 < robust_variance_factor(nis) < 1.2
