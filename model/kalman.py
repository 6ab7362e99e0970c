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


KALMAN_MODES = {"a30": "camera error ignored (as written)",
                "a29": "camera error propagated (alternative)"}
