"""Stochastic updates (Chapter III): the static Kalman filter (MAYB 79) that
improves a matched feature's mean location and covariance with every look.

The feature does not move (static: state transition I, no process noise), so
one update with a measurement ``z`` of covariance ``R`` is

    K = P (P + R)^-1,   m' = m + K (z - m),   P' = (I - K) P

which equals information fusion ``P' = (P^-1 + R^-1)^-1``.

What ``R`` is decides the honesty of the covariance:

* **as written** (A-30, :func:`measurement_covariance_a30`): the camera's own
  position error is taken as zero, so ``R = C_pi`` of A-31, the rig's
  camera-relative covariance turned into room axes;
* **alternative** (A-29, :func:`measurement_covariance_a29`): the
  ``P_i N_Y`` term kept — ``R = C_pi + P_i C_c P_i^T``, the camera estimate's
  covariance carried to the point (the product term ``N_Pi N_Y`` is second
  order and dropped).

The Kalman update assumes the looks' errors independent.  The rig's are not:
from nearby viewpoints a feature lands on the same quantised disparity and
the same end row again and again, so its covariance shrinks with every look
while its error does not (measured in docs/model.md).  A second named
alternative, :func:`covariance_intersection` (Julier & Uhlmann 1997), fuses
with the weight ``w`` that minimises the trace of
``P' = (w P^-1 + (1-w) R^-1)^-1``: never overconfident whatever the
correlation, at the price of shrinking slowly.
"""

from __future__ import annotations

import numpy as np

from .geometry import environment_covariance


def static_update(mean, cov, z, R) -> tuple[np.ndarray, np.ndarray]:
    """One static Kalman update of a 3-D feature (or a stack of them:
    ``mean`` (N,3), ``cov`` (N,3,3))."""
    mean = np.asarray(mean, dtype=np.float64)
    cov = np.asarray(cov, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    S = cov + R
    # K = P S^-1, computed as (S^-1 P)^T since both are symmetric
    K = np.swapaxes(np.linalg.solve(S, cov), -1, -2)
    m = mean + np.einsum("...ij,...j->...i", K, z - mean)
    eye = np.eye(3)
    P = (eye - K) @ cov
    P = (P + np.swapaxes(P, -1, -2)) / 2
    return m, P


def measurement_covariance_a30(M, Cq) -> np.ndarray:
    """A-30 (as written): camera error ignored, ``R = M C_i M^T`` (A-31)."""
    return environment_covariance(M, Cq)


def measurement_covariance_a29(M, Cq, pose_point_covariance) -> np.ndarray:
    """A-29 (alternative): ``R = M C_i M^T + P_i C_c P_i^T``; pass the second
    term as computed by :meth:`model.pose.PoseEstimate.pose_covariance_at`."""
    return environment_covariance(M, Cq) + np.asarray(pose_point_covariance, dtype=np.float64)


def covariance_intersection(mean, cov, z, R, steps: int = 21) -> tuple[np.ndarray, np.ndarray]:
    """Covariance intersection of a feature (mean, cov) with a measurement
    (z, R), for one feature or a stack; ``w`` searched on a grid of ``steps``."""
    mean = np.atleast_2d(np.asarray(mean, dtype=np.float64))
    cov = np.asarray(cov, dtype=np.float64).reshape(-1, 3, 3)
    z = np.atleast_2d(np.asarray(z, dtype=np.float64))
    R = np.asarray(R, dtype=np.float64).reshape(-1, 3, 3)
    Pi, Ri = np.linalg.inv(cov), np.linalg.inv(R)
    w = np.linspace(0.0, 1.0, steps)
    info = w[:, None, None, None] * Pi[None] + (1 - w)[:, None, None, None] * Ri[None]
    P = np.linalg.inv(info)                                       # (steps, N, 3, 3)
    best = np.argmin(np.trace(P, axis1=2, axis2=3), axis=0)       # (N,)
    n = np.arange(len(mean))
    Pb = P[best, n]
    wb = w[best][:, None]
    m = np.einsum("nij,nj->ni", Pb, wb * np.einsum("nij,nj->ni", Pi, mean)
                  + (1 - wb) * np.einsum("nij,nj->ni", Ri, z))
    return m, (Pb + np.swapaxes(Pb, -1, -2)) / 2


def kalman_gain(cov, R) -> np.ndarray:
    """The static update's gain ``K = P (P + R)^-1`` (one feature or a stack)."""
    cov = np.asarray(cov, dtype=np.float64)
    return np.swapaxes(np.linalg.solve(cov + np.asarray(R, dtype=np.float64), cov), -1, -2)


def consider_update(K, report_cov, R_true, correlated: bool = True,
                    steps: int = 21) -> np.ndarray:
    """The consider covariance: how uncertain the filter's mean REALLY is when its
    gain ``K`` was computed from one covariance and the errors are those of another.

    The filter's mean moves by ``m' = (I - K) m + K z``, so its error is
    ``e' = (I - K) e + K e_z``.  With ``report_cov`` the covariance of ``e`` and
    ``R_true`` the measured (honest) covariance of ``e_z``:

    * ``correlated=False`` (Joseph form): ``(I-K) P (I-K)^T + K R K^T``, exact
      when the look's error is independent of the feature's;
    * ``correlated=True`` (default): the bound that holds whatever their
      correlation, ``A / w + B / (1 - w)`` with ``A = (I-K) P (I-K)^T`` and
      ``B = K R K^T`` (``Cov(a + b) <= Cov(a)/w + Cov(b)/(1-w)`` for any w in
      (0, 1)), ``w`` chosen on a grid to minimise the trace — covariance
      intersection's argument applied to the filter's own gain.

    Only the reported covariance changes; the mean and the filter's covariance
    (which the matcher gates with and the pose weighs by) are the filter's."""
    K = np.asarray(K, dtype=np.float64)
    I_K = np.eye(3) - K
    A = I_K @ np.asarray(report_cov, dtype=np.float64) @ np.swapaxes(I_K, -1, -2)
    B = K @ np.asarray(R_true, dtype=np.float64) @ np.swapaxes(K, -1, -2)
    if not correlated:
        P = A + B
    else:
        w = np.linspace(0.0, 1.0, steps + 2)[1:-1]                     # open interval
        cand = (A[None] / w.reshape(-1, *([1] * A.ndim))
                + B[None] / (1 - w).reshape(-1, *([1] * B.ndim)))
        best = np.argmin(np.trace(cand, axis1=-2, axis2=-1), axis=0)
        P = np.take_along_axis(cand, best[None, ..., None, None] if A.ndim == 3
                               else np.asarray(best).reshape(1, 1, 1), axis=0)[0]
    return (P + np.swapaxes(P, -1, -2)) / 2


KALMAN_MODES = {"a30": "camera error ignored (as written)",
                "a29": "camera error propagated (alternative)",
                "ci": "A-29's measurement covariance, fused by covariance intersection "
                      "(correlated looks; alternative)"}


# --- the a-posteriori variance factor (adjustment theory) ---------------------------

CHI2_3DOF_MEDIAN = 2.365974       # the median of chi-square with 3 degrees of freedom


def normalised_innovation(mean, cov, z, R) -> float:
    """The innovation's squared Mahalanobis length ``r^T (P + R)^-1 r``, ``r = z - m``
    (the filter's NIS: chi-square with 3 degrees of freedom when P and R are honest)."""
    r = np.asarray(z, dtype=np.float64) - np.asarray(mean, dtype=np.float64)
    S = np.asarray(cov, dtype=np.float64) + np.asarray(R, dtype=np.float64)
    return float(r @ np.linalg.solve(S, r))


def variance_of_unit_weight(nis, dof: int = 3) -> float:
    """The a-posteriori variance factor of a sequence of innovations: the sum of
    their normalised squares over their degrees of freedom, ``sum(NIS) / (dof n)``.
    1 when the claimed covariances are honest; 4 when the errors are twice the
    claimed sigma.  NaN for an empty sequence."""
    nis = np.asarray(nis, dtype=np.float64).ravel()
    return float(nis.sum() / (dof * len(nis))) if len(nis) else float("nan")


def robust_variance_factor(nis, dof: int = 3) -> float:
    """The variance factor from the median of many innovations' NIS, over the
    median of chi-square (3 degrees of freedom): a few phantoms far out do not
    move it.  NaN for an empty sequence."""
    if dof != 3:
        raise ValueError("robust_variance_factor: only 3 degrees of freedom")
    nis = np.asarray(nis, dtype=np.float64).ravel()
    return float(np.median(nis) / CHI2_3DOF_MEDIAN) if len(nis) else float("nan")


def feature_variance_factors(nis_lists, global_factor: float, prior_dof: float = 3.0,
                             dof: int = 3, floor: float | None = 1.0) -> np.ndarray:
    """One variance factor per feature: its own innovations' where it has them, the
    ``global_factor`` where it has none, and between them the pooled estimate
    ``(prior_dof g + sum NIS) / (prior_dof + dof n)`` (the global factor counted as
    ``prior_dof`` degrees of freedom of evidence: one look's worth by default), so a
    feature seen twice is not judged on one innovation alone.  ``floor``: no factor
    below it (1: the reported covariance is only ever widened); None: none."""
    g = float(global_factor) if np.isfinite(global_factor) else 1.0
    out = np.array([(prior_dof * g + float(np.sum(n))) / (prior_dof + dof * len(n))
                    for n in nis_lists], dtype=np.float64)
    if floor is not None:
        out = np.maximum(out, floor)
    return out
