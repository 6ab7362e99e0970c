"""Environmental model relative coordinates (Appendix A, A-21 to A-32).

Axes.  The room ("environmental model") frame is the simulated world's: X to
the right, Y DOWN, Z forward as seen from the start pose, feet.  A camera's
orientation is a 3x3 matrix ``R`` whose COLUMNS are its x (right), y (down)
and z (forward, the image axis) axes in room coordinates.

A camera-relative feature point is written in the order of Appendix A,
``q = (p, x, y)`` = (range along the image axis ``d_p``, horizontal offset
``d_x`` to the right, vertical offset ``d_y``), exactly the order of the rig's
covariance A-20.  The rig measures ``d_y`` DOWNWARD (rows grow downward,
``dy = DD*dp/dv``), so the third direction-cosine vector ``R_y`` of the state
is the camera's DOWN axis here; the text calls it the "upward vertical axis"
with an upward ``d_y``.  Either way ``P_i Y = X_i`` holds; only the sign
convention of the vertical axis differs.

The camera state of A-21 is the 12-vector

    Y = (P_c, R_p, R_x, R_y)

with ``P_c`` the LEFT camera's centre (the rig locates edges relative to the
left camera) and ``R_p, R_x, R_y`` its image (forward), right and vertical
axes.  ``P_i`` of A-22 is ``[I, p_i I, x_i I, y_i I]`` (3x12) so that
``P_i Y = P_c + p_i R_p + x_i R_x + y_i R_y`` is the feature's room location
(A-23).

A-31 writes the room-relative covariance of a point as ``C_pi = Y^T C_i Y``
with the augmented 12x12 ``C_i`` of A-27; read as the 3x3 result A-32 shows,
it is ``M C M^T`` with ``M = [R_p R_x R_y]`` and ``C`` the camera-relative
covariance A-19 in (p, x, y) order, which is what :func:`environment_covariance`
computes.
"""

from __future__ import annotations

import numpy as np

HALF_BASELINE_FT = 0.375     # the left camera sits 0.375 ft left of the rig centre


def axes_matrix(R: np.ndarray) -> np.ndarray:
    """``M = [R_p R_x R_y]`` (columns) from a camera rotation with columns x, y, z."""
    R = np.asarray(R, dtype=np.float64)
    return np.column_stack([R[:, 2], R[:, 0], R[:, 1]])


def rotation_from_axes(M: np.ndarray) -> np.ndarray:
    """The inverse of :func:`axes_matrix`: columns x, y, z from ``[R_p R_x R_y]``."""
    M = np.asarray(M, dtype=np.float64)
    return np.column_stack([M[:, 1], M[:, 2], M[:, 0]])


def state_vector(left_centre, R) -> np.ndarray:
    """Equation A-21: ``Y = (P_c, R_p, R_x, R_y)``, a 12-vector."""
    M = axes_matrix(R)
    return np.concatenate([np.asarray(left_centre, dtype=np.float64), M[:, 0], M[:, 1], M[:, 2]])


def state_parts(Y) -> tuple[np.ndarray, np.ndarray]:
    """``(P_c, M)`` of a state vector; M has columns R_p, R_x, R_y (not forced orthonormal)."""
    Y = np.asarray(Y, dtype=np.float64)
    return Y[:3].copy(), np.column_stack([Y[3:6], Y[6:9], Y[9:12]])


def design_row(q) -> np.ndarray:
    """Equation A-22: the 3x12 ``P_i = [I, p_i I, x_i I, y_i I]`` of one camera point."""
    p, x, y = (float(v) for v in q)
    eye = np.eye(3)
    return np.hstack([eye, p * eye, x * eye, y * eye])


def design_matrix(q) -> np.ndarray:
    """Equation A-24: the stacked ``P`` (3N x 12) of N camera points (N x 3)."""
    q = np.atleast_2d(np.asarray(q, dtype=np.float64))
    return np.vstack([design_row(r) for r in q]) if len(q) else np.zeros((0, 12))


def transform(Y, q) -> np.ndarray:
    """Equation A-23/A-26: room locations ``P_i Y`` of camera points (N x 3)."""
    pc, M = state_parts(Y)
    q = np.atleast_2d(np.asarray(q, dtype=np.float64))
    return pc + q @ M.T


def environment_covariance(M, C) -> np.ndarray:
    """Equations A-31/A-32: ``C_pi = M C M^T`` for one 3x3 ``C`` or a stack (N,3,3)."""
    M = np.asarray(M, dtype=np.float64)
    C = np.asarray(C, dtype=np.float64)
    return M @ C @ M.T if C.ndim == 2 else np.einsum("ij,njk,lk->nil", M, C, M)


def camera_points(R, left_centre, X) -> np.ndarray:
    """Room points X (N x 3) in camera-relative (p, x, y) order for an
    orthonormal camera ``R`` at ``left_centre`` (the inverse of A-23)."""
    v = (np.atleast_2d(np.asarray(X, dtype=np.float64)) - left_centre) @ np.asarray(R)
    return v[:, [2, 0, 1]]


def left_centre(centre, R) -> np.ndarray:
    """The left camera's centre from the rig centre (midway between the cameras)."""
    return np.asarray(centre, dtype=np.float64) - HALF_BASELINE_FT * np.asarray(R)[:, 0]


def rig_centre(left, x_axis) -> np.ndarray:
    """The rig centre from the left camera and its (possibly unnormalised) x axis."""
    x_axis = np.asarray(x_axis, dtype=np.float64)
    n = np.linalg.norm(x_axis)
    return np.asarray(left, dtype=np.float64) + HALF_BASELINE_FT * (x_axis / n if n > 0 else x_axis)


def heading_deg(forward) -> float:
    """Heading of a forward axis: turned from +Z toward +X (right turn positive)."""
    return float(np.degrees(np.arctan2(forward[0], forward[2])))


def rotation_from_angles(heading_deg: float, pitch_deg: float = 0.0, roll_deg: float = 0.0) -> np.ndarray:
    """Camera rotation (columns x, y, z) for heading, pitch (nose up) and roll
    (x axis tilting toward +Y), composed heading * pitch * roll, as the world's Pose."""
    h, p, r = np.radians([heading_deg, pitch_deg, roll_deg])
    Rh = np.array([[np.cos(h), 0, np.sin(h)], [0, 1, 0], [-np.sin(h), 0, np.cos(h)]])
    # pitch up: forward tilts toward -Y (rotation about the camera x axis)
    Rp = np.array([[1, 0, 0], [0, np.cos(p), -np.sin(p)], [0, np.sin(p), np.cos(p)]])
    # roll: x axis tilts toward +Y (rotation about the camera z axis)
    Rr = np.array([[np.cos(r), -np.sin(r), 0], [np.sin(r), np.cos(r), 0], [0, 0, 1]])
    return Rh @ Rp @ Rr


def wrap_deg(a):
    """An angle difference folded into (-180, 180]."""
    return (np.asarray(a) + 180.0) % 360.0 - 180.0
