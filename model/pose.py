"""Camera location estimation (Appendix A, A-33 to A-50; Chapter III
"Camera Position Estimation"), as written, and the named alternatives beside it.

Inputs are N correspondences: camera-relative points ``q`` (N x 3, (p, x, y)
order, see :mod:`model.geometry`) with their A-19/A-20 covariances ``Cq``
(N x 3 x 3), and the matched model locations ``X`` (N x 3, room coordinates)
with their covariances ``CX``.

Methods (the names are those of ``rig walk`` and its JSON):

* ``a48`` — **as written**: the 12-element state Y (A-21), ``P_i`` (A-22),
  weights ``D_i = C_pi^-1`` with ``C_pi`` from A-31 evaluated at the current Y
  (iterated from the prior pose), the normal equations A-47, the solution A-48
  and its covariance ``C_c = (P^T D P)^-1`` (A-50).  Only the camera-relative
  error enters D (A-30 assumes the model exact).  The three axes are NOT
  forced orthonormal.  The text's three conditions are checked (at least 3
  points, not colinear, perfect matches — the last is the matcher's promise,
  see :mod:`model.matching`); a fourth follows from A-48 itself: ``P^T D P``
  is invertible only if the points span 3-D (with 3 points, or any coplanar
  set, the 12 unknowns have a 3-dimensional null space).  A look that fails
  gets a :class:`PoseRefused`, not a number.
* ``rigid`` — alternative (a): the same cost A-36 over a TRUE rotation
  (Gauss-Newton on SO(3)), weights from the full covariance of each pair,
  ``(R C_i R^T + C_X)^-1``, covariance from the Gauss-Newton normal matrix.
* ``robust`` — alternative (b): ``rigid`` inside a rejection of wrong
  correspondences: a consensus search over minimal triples (and the prior),
  then residuals gated at the chi-square 99 % point (3 degrees of freedom)
  and the fit repeated on the survivors.
* ``floor`` — alternative (c): floor-following, only (x, z, heading) free,
  the rig 3 ft above the floor and level; full-covariance weights and the same
  rejection as ``robust``.
* ``kabsch`` — reference: unweighted Kabsch (scipy ``Rotation.align_vectors``)
  on all pairs.
* ``opencv`` — reference: OpenCV ``estimateAffine3D`` (RANSAC, 3x4 affine).

Every method returns a :class:`PoseEstimate`: the left camera's centre and axes,
the rig centre, heading, the inlier mask, and a 6x6 covariance of
(position, rotation vector) where the method gives one.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations
from math import comb

import numpy as np

from .geometry import (HALF_BASELINE_FT, axes_matrix, environment_covariance, heading_deg,
                       rig_centre, rotation_from_axes, state_parts, state_vector)

CHI2_3DOF_99 = 11.345            # chi-square 99 % point, 3 degrees of freedom
COLINEAR_TOL = 1e-6              # relative singular value below which points are colinear/coplanar


class PoseRefused(ValueError):
    """A look the method cannot fix the camera from; the message says why."""


@dataclass
class PoseEstimate:
    method: str
    left: np.ndarray                 # left camera centre, room coordinates
    M: np.ndarray                    # [R_p R_x R_y] as estimated (A-48: not orthonormal)
    inliers: np.ndarray              # bool mask over the correspondences used
    covariance6: np.ndarray | None = None   # (position of the LEFT camera, rotation vector)
    Y: np.ndarray | None = None              # the 12-state (a48)
    Cc: np.ndarray | None = None             # A-50 (a48)
    iterations: int = 0
    notes: dict = field(default_factory=dict)

    @property
    def R(self) -> np.ndarray:
        """Axes as columns x, y, z (as estimated; orthonormal except for a48/opencv)."""
        return rotation_from_axes(self.M)

    @property
    def centre(self) -> np.ndarray:
        return rig_centre(self.left, self.M[:, 1])

    @property
    def heading_deg(self) -> float:
        return heading_deg(self.M[:, 0])

    def transform(self, q) -> np.ndarray:
        """Room locations of camera points with this pose (A-23)."""
        q = np.atleast_2d(np.asarray(q, dtype=np.float64))
        return self.left + q @ self.M.T

    def pose_covariance_at(self, q) -> np.ndarray:
        """Covariance (N,3,3) of ``P_i Y`` due to the camera's own error: the
        ``P_i N_Y`` term of A-29.  For a48 it is ``P_i C_c P_i^T``; for the
        rigid methods ``J C6 J^T`` with ``J = [I, -[R v]x]``.  Zero when the
        method gives no covariance."""
        q = np.atleast_2d(np.asarray(q, dtype=np.float64))
        n = len(q)
        if self.Cc is not None:
            a = np.column_stack([np.ones(n), q])                 # (1, p, x, y)
            C = self.Cc.reshape(4, 3, 4, 3)
            return np.einsum("nj,jakb,nk->nab", a, C, a)
        if self.covariance6 is None:
            return np.zeros((n, 3, 3))
        w = (q @ self.M.T)                                       # R v
        J = np.zeros((n, 3, 6))
        J[:, :, :3] = np.eye(3)
        J[:, :, 3:] = -_skew_stack(w)
        return np.einsum("nij,jk,nlk->nil", J, self.covariance6, J)

    def xz_heading_covariance(self) -> np.ndarray | None:
        """3x3 covariance of (rig centre x, z, heading in radians)."""
        if self.Cc is not None:
            J = np.zeros((3, 12))
            J[0, 0] = 1.0
            J[0, 6] = HALF_BASELINE_FT
            J[1, 2] = 1.0
            J[1, 8] = HALF_BASELINE_FT
            a, b = self.M[0, 0], self.M[2, 0]
            s = a * a + b * b
            J[2, 3] = b / s
            J[2, 5] = -a / s
            return J @ self.Cc @ J.T
        if self.covariance6 is None:
            return None
        off = HALF_BASELINE_FT * self.M[:, 1]
        J = np.zeros((3, 6))
        Jc = np.hstack([np.eye(3), -_skew(off)])                # centre = left + R*(0.375, 0, 0)
        J[0] = Jc[0]
        J[1] = Jc[2]
        J[2, 4] = 1.0                                           # heading = rotation about room Y
        return J @ self.covariance6 @ J.T


def _skew(w) -> np.ndarray:
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _skew_stack(w) -> np.ndarray:
    S = np.zeros((len(w), 3, 3))
    S[:, 0, 1], S[:, 0, 2] = -w[:, 2], w[:, 1]
    S[:, 1, 0], S[:, 1, 2] = w[:, 2], -w[:, 0]
    S[:, 2, 0], S[:, 2, 1] = -w[:, 1], w[:, 0]
    return S


def _rodrigues(w) -> np.ndarray:
    from scipy.spatial.transform import Rotation
    return Rotation.from_rotvec(w).as_matrix()


def _as_arrays(q, Cq, X, CX=None):
    q = np.atleast_2d(np.asarray(q, dtype=np.float64)).reshape(-1, 3)
    X = np.atleast_2d(np.asarray(X, dtype=np.float64)).reshape(-1, 3)
    Cq = np.asarray(Cq, dtype=np.float64).reshape(-1, 3, 3)
    if len(q) != len(X) or len(Cq) != len(q):
        raise ValueError(f"correspondences disagree: {len(q)} camera points, {len(Cq)} "
                         f"covariances, {len(X)} model points")
    CX = np.zeros_like(Cq) if CX is None else np.asarray(CX, dtype=np.float64).reshape(-1, 3, 3)
    return q, Cq, X, CX


# --- the text's conditions ---------------------------------------------------------

def check_conditions(q, need_3d: bool = True) -> None:
    """The conditions under A-48: at least 3 points, not colinear (and, for the
    12-element solve, not coplanar: ``P^T D P`` must be invertible).  Raises
    :class:`PoseRefused` naming the failed condition."""
    q = np.atleast_2d(np.asarray(q, dtype=np.float64))
    n = len(q) if q.size else 0
    if n < 3:
        raise PoseRefused(f"only {n} matched point{'s' if n != 1 else ''}: "
                          f"A-48 needs at least 3 (condition 1)")
    s = np.linalg.svd(q - q.mean(axis=0), compute_uv=False)
    if s[0] <= 0 or s[1] <= COLINEAR_TOL * s[0]:
        raise PoseRefused(f"the {n} matched points are colinear: A-48 needs 3 that are "
                          f"not (condition 2)")
    if need_3d and (n < 4 or s[2] <= COLINEAR_TOL * s[0]):
        raise PoseRefused(f"the {n} matched points lie in one plane, so P^T D P (A-47) is "
                          f"singular: the 12-element solve needs 4 points not in one plane")


# --- A-48 as written ------------------------------------------------------------

def normal_equations(q, Cq, X, M) -> tuple[np.ndarray, np.ndarray]:
    """A-33..A-47: ``P^T D P`` (12x12) and ``P^T D X'`` (12) with ``D_i`` the
    inverse of A-31's ``C_pi`` evaluated with the axes ``M``.  ``P_i^T D_i P_i``
    is the Kronecker product of ``a a^T`` (``a = (1, p, x, y)``) with ``D_i``,
    the block pattern of A-41."""
    D = np.linalg.inv(environment_covariance(M, Cq))
    a = np.column_stack([np.ones(len(q)), q])
    PtDP = np.einsum("nj,nk,nab->jakb", a, a, D).reshape(12, 12)
    PtDX = np.einsum("nj,nab,nb->ja", a, D, X).reshape(12)
    return PtDP, PtDX


def solve_a48(q, Cq, X, prior_left, prior_R, iterations: int = 3) -> PoseEstimate:
    """Equation A-48, ``Y = (P^T D P)^-1 (P^T D X')``, with ``C_c`` of A-50.

    D depends on the camera's axes (A-31), so it is first evaluated at the
    prior pose, then at each solution in turn (``iterations`` solves)."""
    q, Cq, X, _ = _as_arrays(q, Cq, X)
    check_conditions(q)
    Y = state_vector(prior_left, prior_R)
    for _ in range(max(1, iterations)):
        _, M = state_parts(Y)
        PtDP, PtDX = normal_equations(q, Cq, X, M)
        if np.linalg.cond(PtDP) > 1e14:
            raise PoseRefused("P^T D P (A-47) is singular for these points")
        Y = np.linalg.solve(PtDP, PtDX)
    _, M = state_parts(Y)
    PtDP, _ = normal_equations(q, Cq, X, M)
    Cc = np.linalg.inv(PtDP)
    Cc = (Cc + Cc.T) / 2
    pc, M = state_parts(Y)
    return PoseEstimate("a48", pc, M, np.ones(len(q), bool), Y=Y, Cc=Cc,
                        iterations=max(1, iterations))


# --- (a) a true rotation, full covariance weights ---------------------------------

def _weights(R, Cv, CX) -> np.ndarray:
    return np.linalg.inv(np.einsum("ij,njk,lk->nil", R, Cv, R) + CX)


def _to_v(q, Cq):
    """Camera points and covariances in (x, y, z) order (columns of R)."""
    perm = [1, 2, 0]
    return q[:, perm], Cq[:, perm][:, :, perm]


def solve_rigid(q, Cq, X, CX, prior_left, prior_R, iterations: int = 20,
                floor: bool = False, method: str = "rigid") -> PoseEstimate:
    """Alternative (a): minimise ``sum r_i^T W_i r_i``, ``r_i = c + R v_i - X_i``,
    over a true rotation R (or, with ``floor``, over x, z and heading only,
    the rig level at y = 0), ``W_i = (R C_i R^T + C_Xi)^-1``, by Gauss-Newton
    from the prior.  Covariance: the inverse normal matrix, 6x6 over (left
    camera position, rotation vector in room axes)."""
    q, Cq, X, CX = _as_arrays(q, Cq, X, CX)
    check_conditions(q, need_3d=False)
    v, Cv = _to_v(q, Cq)
    R = np.array(prior_R, dtype=np.float64)
    c = np.array(prior_left, dtype=np.float64)
    if floor:
        h = np.radians(heading_deg(R[:, 2]))
        R = _yaw(h)
        c = _floor_left(c, R)
    it = 0
    for it in range(1, iterations + 1):
        W = _weights(R, Cv, CX)
        Rv = v @ R.T
        r = c + Rv - X
        J = np.zeros((len(q), 3, 6))
        J[:, :, :3] = np.eye(3)
        J[:, :, 3:] = -_skew_stack(Rv)
        if floor:
            J = J[:, :, [0, 2, 4]]
        H = np.einsum("nai,nab,nbj->ij", J, W, J)
        g = np.einsum("nai,nab,nb->i", J, W, r)
        try:
            delta = -np.linalg.solve(H, g)
        except np.linalg.LinAlgError as exc:
            raise PoseRefused(f"the {len(q)} points do not fix the pose ({exc})") from None
        if floor:
            d6 = np.zeros(6)
            d6[[0, 2, 4]] = delta
            delta = d6
        c = c + delta[:3]
        R = _rodrigues(delta[3:]) @ R
        if np.linalg.norm(delta) < 1e-9:
            break
    W = _weights(R, Cv, CX)
    J = np.zeros((len(q), 3, 6))
    J[:, :, :3] = np.eye(3)
    J[:, :, 3:] = -_skew_stack(v @ R.T)
    if floor:
        H3 = np.einsum("nai,nab,nbj->ij", J[:, :, [0, 2, 4]], W, J[:, :, [0, 2, 4]])
        cov = np.zeros((6, 6))
        cov[np.ix_([0, 2, 4], [0, 2, 4])] = np.linalg.inv(H3)
    else:
        cov = np.linalg.inv(np.einsum("nai,nab,nbj->ij", J, W, J))
    return PoseEstimate(method, c, axes_matrix(R), np.ones(len(q), bool),
                        covariance6=(cov + cov.T) / 2, iterations=it)


def _yaw(h: float) -> np.ndarray:
    return np.array([[np.cos(h), 0, np.sin(h)], [0, 1.0, 0], [-np.sin(h), 0, np.cos(h)]])


def _floor_left(left, R) -> np.ndarray:
    """Left camera of a level rig whose centre is at y = 0, near ``left``."""
    centre = np.asarray(left, dtype=np.float64) + HALF_BASELINE_FT * R[:, 0]
    centre[1] = 0.0
    return centre - HALF_BASELINE_FT * R[:, 0]


def mahalanobis2(est: PoseEstimate, q, Cq, X, CX) -> np.ndarray:
    """Squared Mahalanobis residual of each pair under a pose (full covariance)."""
    v, Cv = _to_v(q, Cq)
    R = est.R
    r = est.left + v @ R.T - X
    W = _weights(R, Cv, CX)
    return np.einsum("na,nab,nb->n", r, W, r)


# --- (b) robust rejection, (c) floor-following --------------------------------------

def _kabsch(v, X):
    import warnings
    from scipy.spatial.transform import Rotation
    vc, Xc = v.mean(axis=0), X.mean(axis=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)     # near-degenerate sets: still a rotation
        rot, _ = Rotation.align_vectors(X - Xc, v - vc)
    R = rot.as_matrix()
    return Xc - R @ vc, R


def _kabsch_triples(v, X, idx):
    """Rigid fits (c, R) of many small subsets at once (rows of ``idx``), by the
    SVD of each subset's cross-covariance; degenerate subsets are dropped."""
    if len(idx) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3, 3))
    A, B = v[idx], X[idx]                                   # (T, k, 3)
    ac, bc = A.mean(axis=1), B.mean(axis=1)
    A0, B0 = A - ac[:, None], B - bc[:, None]
    s = np.linalg.svd(A0, compute_uv=False)
    ok = s[:, 1] > 1e-3 * np.maximum(s[:, 0], 1e-12)
    H = np.einsum("tki,tkj->tij", A0[ok], B0[ok])
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(np.einsum("tij,tjk->tik", U, Vt)))
    D = np.zeros((len(d), 3, 3))
    D[:, 0, 0] = D[:, 1, 1] = 1.0
    D[:, 2, 2] = d
    R = np.einsum("tji,tjk,tlk->til", Vt, D, U)             # V D U^T
    c = bc[ok] - np.einsum("tij,tj->ti", R, ac[ok])
    return c, R


def solve_robust(q, Cq, X, CX, prior_left, prior_R, gate: float = CHI2_3DOF_99,
                 floor: bool = False, max_triples: int = 60, seed: int = 0,
                 method: str | None = None) -> PoseEstimate:
    """Alternative (b) (and (c) with ``floor``): wrong correspondences rejected.

    Hypotheses: the prior and rigid fits of up to ``max_triples`` triples
    (all of them when there are few pairs, else a seeded sample).  The one
    with the lowest truncated cost ``sum min(d_i^2, gate)`` wins; the rigid
    (or floor) fit is then repeated on the pairs within the gate until the set
    stops changing.  Refused when fewer than 3 pairs survive."""
    name = method or ("floor" if floor else "robust")
    q, Cq, X, CX = _as_arrays(q, Cq, X, CX)
    check_conditions(q, need_3d=False)
    n = len(q)
    v, _ = _to_v(q, Cq)
    if comb(n, 3) <= max_triples:
        triples = list(combinations(range(n), 3))
    else:
        rng = np.random.default_rng(seed)
        triples = [rng.choice(n, 3, replace=False) for _ in range(max_triples)]
    cs, Rs = _kabsch_triples(v, X, np.array(triples, dtype=np.int64).reshape(-1, 3))
    if floor and len(Rs):
        Rs = np.array([_yaw(np.radians(heading_deg(R[:, 2]))) for R in Rs])
    cs = np.vstack([np.asarray(prior_left, float)[None], cs])
    Rs = np.concatenate([np.asarray(prior_R, float)[None], Rs])
    # every hypothesis scored with the prior's weights (one inverse per pair, not per pair
    # and hypothesis): the truncated cost sum min(d^2, gate)
    W0 = _weights(np.asarray(prior_R, float), _to_v(q, Cq)[1], CX)
    r = cs[:, None, :] + np.einsum("hij,nj->hni", Rs, v) - X[None]
    d2 = np.einsum("hna,nab,hnb->hn", r, W0, r)
    h = int(np.argmin(np.minimum(d2, gate).sum(axis=1)))
    best = PoseEstimate(name, cs[h], axes_matrix(Rs[h]), np.ones(n, bool))
    inl = mahalanobis2(best, q, Cq, X, CX) <= gate
    est = best
    for _ in range(5):
        if inl.sum() < 3:
            raise PoseRefused(f"only {int(inl.sum())} of {n} matched points agree on one pose: "
                              f"too few to fix the camera")
        try:
            est = solve_rigid(q[inl], Cq[inl], X[inl], CX[inl], est.left, est.R,
                              floor=floor, method=name)
        except PoseRefused as exc:
            raise PoseRefused(f"{int(inl.sum())} consistent points: {exc}") from None
        new = mahalanobis2(est, q, Cq, X, CX) <= gate
        if np.array_equal(new, inl):
            break
        inl = new
    est.inliers = inl
    est.notes["rejected"] = int(n - inl.sum())
    return est


# --- references --------------------------------------------------------------------

def solve_kabsch(q, Cq, X, CX=None, prior_left=None, prior_R=None) -> PoseEstimate:
    """Reference: unweighted Kabsch on all pairs (scipy ``Rotation.align_vectors``)."""
    q, Cq, X, _ = _as_arrays(q, Cq, X, CX)
    check_conditions(q, need_3d=False)
    v, _ = _to_v(q, Cq)
    c, R = _kabsch(v, X)
    return PoseEstimate("kabsch", c, axes_matrix(R), np.ones(len(q), bool))


def solve_opencv(q, Cq, X, CX=None, prior_left=None, prior_R=None) -> PoseEstimate:
    """Reference: OpenCV ``estimateAffine3D`` (RANSAC over 3x4 affine maps, its
    default threshold); the affine's columns are taken as the camera axes."""
    import cv2
    q, Cq, X, _ = _as_arrays(q, Cq, X, CX)
    if len(q) < 4:
        raise PoseRefused(f"only {len(q)} matched points: estimateAffine3D needs 4")
    v, _ = _to_v(q, Cq)
    ok, A, inl = cv2.estimateAffine3D(v.astype(np.float64), X.astype(np.float64))
    if not ok or A is None:
        raise PoseRefused("estimateAffine3D found no consensus")
    A = np.asarray(A, dtype=np.float64)
    est = PoseEstimate("opencv", A[:, 3].copy(), axes_matrix(A[:, :3]),
                       np.asarray(inl).reshape(-1).astype(bool))
    est.notes["det"] = float(np.linalg.det(A[:, :3]))
    return est


def estimate(method: str, q, Cq, X, CX, prior_left, prior_R) -> PoseEstimate:
    """One of the named methods on the same correspondences."""
    if method == "a48":
        try:
            return solve_a48(q, Cq, X, prior_left, prior_R)
        except np.linalg.LinAlgError:
            # an iterate whose (unconstrained) axes collapsed makes M C M^T of A-31 singular
            raise PoseRefused("A-31's covariance is singular at an A-48 iterate "
                              "(its axes degenerate)") from None
    if method == "rigid":
        return solve_rigid(q, Cq, X, CX, prior_left, prior_R)
    if method == "robust":
        return solve_robust(q, Cq, X, CX, prior_left, prior_R)
    if method == "floor":
        return solve_robust(q, Cq, X, CX, prior_left, prior_R, floor=True)
    if method == "kabsch":
        return solve_kabsch(q, Cq, X)
    if method == "opencv":
        return solve_opencv(q, Cq, X)
    raise ValueError(f"unknown pose method {method!r}")


ESTIMATORS = ("a48", "rigid", "robust", "floor", "kabsch", "opencv")
METHOD_NOTES = {
    "dead_reckoning": "the odometry alone, integrated from the start",
    "fused": "the robot's pose: the driving method's fix combined with the odometry's prior by "
             "their covariances (the pose the model is updated with)",
    "a48": "Appendix A as written: 12-element state Y, D_i = C_pi^-1 (A-31), A-47/A-48, C_c of A-50",
    "rigid": "alternative (a): true rotation, full covariance weights (R C_i R^T + C_X)^-1",
    "robust": "alternative (b): (a) with wrong correspondences rejected (consensus + chi-square gate)",
    "floor": "alternative (c): floor-following, x, z, heading only, with (b)'s rejection",
    "kabsch": "reference: unweighted Kabsch, scipy Rotation.align_vectors",
    "opencv": "reference: OpenCV estimateAffine3D (RANSAC affine)",
}
