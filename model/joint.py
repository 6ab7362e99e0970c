"""The joint filter: one extended Kalman filter over the robot's floor pose and
every feature of the model, with their full covariance (``rig walk --kalman
joint``; a named alternative beyond Chapter III, never the default).

What it adds to Chapter III.  The dissertation's static update ("Stochastic
Updates", A-29/A-30, :mod:`model.kalman`) improves each feature on its own,
and the camera's position (A-21..A-50, :mod:`model.pose`) is then fixed from
those same features.  Neither keeps the covariance BETWEEN the pose and a
feature, or between two features.  So an error the two share -- a feature
first placed while the camera pose was off carries that pose error, and the
pose later fixed from it carries it back -- is invisible to the filter and is
never removed: pose and features drift together (docs/model.md, model7's
trace of the z = -5 wall).  Keeping the cross-covariance (the stochastic map of
Smith, Self & Cheeseman 1987, i.e. EKF SLAM) lets one observation move
everything correlated with it: when the walk's second lap sees the first lap's
features again, the pose AND the features placed from the drifted pose are
pulled back together (loop closure).

The state is ``(x, z, heading)`` of the rig centre -- the walk's
floor-following case, height 0 and the rig's known mounting pitch, level roll,
as the odometry's prior treats them -- then ``(X, Y, Z)`` of every feature in
room axes.  One look is

* **predict** (:meth:`JointFilter.predict`): the pose moved by the odometry's
  step with the Jacobian ``F`` and process noise ``G Q G^T`` of the documented
  odometry model (the walk's ``_odometry_step``); features are static, so only
  the pose rows and columns change (``P_pf <- F P_pf``);
* **augment** (:meth:`JointFilter.add`): a feature seen for the first time
  enters at ``f = left(pose) + M q`` with ``J_pose P J_pose^T + M C_q M^T`` and
  its cross-covariance ``J_pose P_p.`` to everything already held;
* **update** (:meth:`JointFilter.update`): the look's matched observations in
  camera axes, ``q = M^T (f - left(pose))`` (A-23 inverted), each with its
  A-19/A-20 camera covariance ``C_q``; the Jacobians w.r.t. the feature
  (``M^T``) and the pose, all pairs in one batch.

WHICH observations are used is decided exactly as for the static filters (the
matcher, the pose methods, the odometry gate, the feature gate, confirmation);
only the estimator changes -- except for the filter's own validation gate
(:meth:`JointFilter.update`, ``WalkConfig.joint_gate``): a pair inconsistent with the JOINT
covariance is left out, as an EKF must (one wrong pair fused with its A-19/A-20 covariance
turns the pose and, through it, every correlated feature).  The generic steps :func:`ekf_predict`,
:func:`ekf_augment` and :func:`ekf_update` are plain linear-Gaussian algebra,
tested against a batch weighted least squares solution.

``--consider joseph|bound`` (:func:`consider_joint_update`): the consider covariance of the
joint state -- a second dense covariance through the same predictions and gains with the
measured measurement covariance -- reported and scored as the features' covariance, never
gated with (tested against a Monte Carlo of a linear walk).
"""

from __future__ import annotations

from contextlib import nullcontext

import numpy as np
from scipy.linalg import solve_triangular

from .geometry import axes_matrix, left_centre, rotation_from_angles, wrap_deg
from .pose import PoseEstimate

POSE_DIM = 3                      # x, z, heading (radians)
_DH = 1e-6                        # radians: the heading's finite difference (central)

# BLAS threads for the joint state's dense algebra.  One: on this project's two-core
# machines a second OpenBLAS thread made the bundled walk's look 2.2 times SLOWER
# (median 184 against 84 ms, load average 1-3; docs/model.md), the n^2 m products of a
# few hundred features being too small to share and the other core busy with the rest.
JOINT_BLAS_THREADS = 1
_CAPACITY = POSE_DIM + 3 * 128    # the state's first allocation (features 128)
_GROWTH = 1.5                     # a full state grows to 1.5 times what it must hold
_blas_controller = None


def _blas_limit():
    """A context limiting BLAS to :data:`JOINT_BLAS_THREADS` threads (threadpoolctl; its
    controller found once, since finding the libraries costs milliseconds)."""
    global _blas_controller
    if JOINT_BLAS_THREADS is None:
        return nullcontext()
    if _blas_controller is None:
        from threadpoolctl import ThreadpoolController
        _blas_controller = ThreadpoolController()
    return _blas_controller.limit(limits=JOINT_BLAS_THREADS, user_api="blas")


# --- the generic linear-Gaussian steps ------------------------------------------------

def ekf_predict(cov, F, Q, k: int, in_place: bool = False):
    """The covariance after a motion of the first ``k`` state entries with
    Jacobian ``F`` (k x k) and process noise ``Q`` (k x k); the rest is static.

    Only the first ``k`` rows and columns change (``[F P_kk F^T + Q, F P_k.]`` and
    its transpose), so they are all that is computed: O(k n), where copying and
    symmetrising the whole n x n covariance cost a fifth of a 600-feature look.
    ``in_place``: write into ``cov`` itself (a float64 array), not a copy."""
    P = cov if in_place else np.array(cov, dtype=np.float64)
    rows = F @ P[:k, :]                                    # F P_k.   (k, n)
    block = rows[:, :k] @ F.T + Q
    rows[:, :k] = (block + block.T) / 2
    P[:k, :] = rows
    P[:, :k] = rows.T
    return P


def ekf_augment(mean, cov, new_mean, J, R, G=None):
    """The state grown by ``new_mean`` = g(state, v), ``J`` = dg/dstate (m x n),
    ``v``'s covariance ``R`` entering through ``G`` = dg/dv (identity if None)."""
    mean = np.asarray(mean, dtype=np.float64)
    P = np.asarray(cov, dtype=np.float64)
    J = np.asarray(J, dtype=np.float64).reshape(-1, len(mean))
    G = np.eye(J.shape[0]) if G is None else np.asarray(G, dtype=np.float64)
    cross = J @ P                                          # (m, n)
    Pnn = J @ P @ J.T + G @ np.asarray(R, dtype=np.float64) @ G.T
    top = np.hstack([P, cross.T])
    bottom = np.hstack([cross, (Pnn + Pnn.T) / 2])
    return np.concatenate([mean, np.asarray(new_mean, dtype=np.float64)]), np.vstack([top, bottom])


def ekf_update(mean, cov, innovation, H, R):
    """One Kalman update with all the look's measurements at once: ``K = P H^T
    S^-1``, ``S = H P H^T + R``; ``P' = P - K S K^T`` (symmetrised)."""
    m, P, _ = ekf_update_with_gain(mean, cov, innovation, H, R)
    return m, P


def ekf_update_with_gain(mean, cov, innovation, H, R):
    """:func:`ekf_update`, also returning the gain ``K`` (for the consider covariance)."""
    P = np.asarray(cov, dtype=np.float64)
    H = np.asarray(H, dtype=np.float64)
    # a look touches the pose and its matched features only: P H^T from those columns
    cols = np.flatnonzero(np.any(H != 0, axis=0))
    PHt = P[:, cols] @ H[:, cols].T
    S = H[:, cols] @ PHt[cols] + np.asarray(R, dtype=np.float64)
    S = (S + S.T) / 2
    K = np.linalg.solve(S, PHt.T).T
    m = np.asarray(mean, dtype=np.float64) + K @ np.asarray(innovation, dtype=np.float64)
    P = P - K @ S @ K.T
    return m, (P + P.T) / 2, K


CONSIDER_STEPS = 21               # model.kalman.consider_update's grid of weights


def consider_joint_update(consider_cov, K, H, R_true, mode: str = "joseph",
                          steps: int = CONSIDER_STEPS) -> np.ndarray:
    """The joint filter's consider covariance after one update: the covariance of the
    filter's error when its gain ``K`` (computed from its own covariance and the
    A-19/A-20 ``R``) meets errors whose covariance is ``R_true`` (the measured one).

    The filter's error moves by ``e' = (I - K H) e + K e_z``, so with ``consider_cov``
    the covariance of ``e``:

    * ``"joseph"``: ``A + B``, ``A = (I-KH) Pc (I-KH)^T``, ``B = K R_true K^T`` -- exact
      when the look's error is independent of the state's (Joseph form);
    * ``"bound"``: ``A / w + B / (1 - w)``, holding whatever their correlation,
      ``w`` on :func:`model.kalman.consider_update`'s grid minimising the trace
      (covariance intersection's argument applied to the two terms, one ``w`` for
      the whole state).

    ``A`` is formed from the columns H touches (``Pc - K H Pc - (K H Pc)^T + K H Pc
    H^T K^T``): the same O(n^2 m) work as the filter's own update, never an n x n
    product with ``I - K H``."""
    Pc = np.asarray(consider_cov, dtype=np.float64)
    H = np.asarray(H, dtype=np.float64)
    cols = np.flatnonzero(np.any(H != 0, axis=0))
    Hc = H[:, cols]
    HPc = Hc @ Pc[cols, :]                                  # (m, n)
    KHPc = K @ HPc                                          # (n, n)
    Sc = HPc[:, cols] @ Hc.T                                # H Pc H^T (m, m)
    R_true = np.asarray(R_true, dtype=np.float64)
    if mode == "joseph":
        P = Pc - KHPc - KHPc.T + K @ (Sc + R_true) @ K.T
    elif mode == "bound":
        A = Pc - KHPc - KHPc.T + K @ Sc @ K.T
        B = K @ R_true @ K.T
        w = np.linspace(0.0, 1.0, steps + 2)[1:-1]         # open interval
        tA, tB = float(np.trace(A)), float(np.trace(B))
        best = float(w[np.argmin(tA / w + tB / (1 - w))])
        P = A / best + B / (1 - best)
    else:
        raise ValueError(f"unknown consider covariance {mode!r}; one of joseph, bound")
    return (P + P.T) / 2


# --- the same steps in place: the joint filter's working form ----------------------------
#
# The plain steps above are the reference: each forms new n x n arrays (P - K S K^T, its
# transpose, their mean; the consider's K H Pc, K Sc K^T, K R K^T).  On the bundled walk's
# ~1800-entry state each such array is 26 MB, and the products cost 2 n^2 m multiplications
# apiece.  The forms below do the same algebra in place, with symmetric rank-m products
# (BLAS syrk: half the multiplications, exactly symmetric) into one scratch buffer;
# tests/test_model_joint.py holds them equal to the plain steps to rounding.

def _syrk(W, scratch) -> np.ndarray:
    """``W W^T`` in ``scratch`` (a flat buffer of at least n*n): numpy's matmul of an array
    with its own transpose is BLAS syrk, one triangle computed and mirrored."""
    n = W.shape[0]
    T = scratch[:n * n].reshape(n, n)
    np.matmul(W, W.T, out=T)
    return T


def ekf_update_in_place(mean, P, innovation, Hc, cols, R, scratch) -> np.ndarray:
    """:func:`ekf_update_with_gain` on ``mean`` and ``P`` in place; returns the gain K.

    ``Hc`` = H's columns ``cols`` (the pose and the matched features: H is zero
    elsewhere).  With S = L L^T (Cholesky), ``K S K^T = W W^T``, ``W = P H^T L^-T``: the
    covariance is downdated by one syrk, ``P -= W W^T``, without an n x n temporary
    beyond ``scratch``."""
    PHt = P[:, cols] @ Hc.T                                 # (n, m)
    S = Hc @ PHt[cols] + R
    S = (S + S.T) / 2
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:                           # S not positive definite
        K = np.linalg.solve(S, PHt.T).T
        T = scratch[:P.shape[0] ** 2].reshape(P.shape)
        np.matmul(K @ S, K.T, out=T)
        P -= (T + T.T) / 2
    else:
        W = solve_triangular(L, PHt.T, lower=True, check_finite=False).T      # P H^T L^-T
        K = solve_triangular(L, W.T, lower=True, trans="T", check_finite=False).T
        P -= _syrk(W, scratch)
    mean += K @ np.asarray(innovation, dtype=np.float64)
    return K


def consider_update_in_place(Pc, K, Hc, cols, R_true, mode: str, scratch,
                             steps: int = CONSIDER_STEPS) -> None:
    """:func:`consider_joint_update` on ``Pc`` in place.

    With ``V = Pc H^T`` and ``Sc = H Pc H^T``, the Joseph form's change is
    ``K Sc K^T - K V^T - V K^T + K R K^T = K Z^T + Z K^T``, ``Z = K (Sc + R) / 2 - V``
    (and the bound's ``A/w + B/(1-w)`` the same with ``Z = (K Sc/2 - V)/w + K R / (2(1-w))``
    and ``Pc`` scaled by ``1/w``; the traces that choose ``w`` come from K, V, Z without
    forming A or B).  The symmetric rank-2m change is two syrks,
    ``K Z^T + Z K^T = (X X^T - Y Y^T) / 2``, ``X, Y = a K +- Z / a`` (``a`` balances
    their sizes against cancellation)."""
    V = Pc[:, cols] @ Hc.T                                  # (n, m)
    Sc = Hc @ V[cols]
    Sc = (Sc + Sc.T) / 2
    R_true = np.asarray(R_true, dtype=np.float64)
    if mode == "joseph":
        Z = K @ ((Sc + R_true) / 2) - V
        scale = 1.0
    elif mode == "bound":
        Za = K @ (Sc / 2) - V
        KR = K @ R_true
        tA = float(np.trace(Pc)) + 2.0 * float(np.einsum("ij,ij->", K, Za))
        tB = float(np.einsum("ij,ij->", K, KR))
        w = np.linspace(0.0, 1.0, steps + 2)[1:-1]
        best = float(w[np.argmin(tA / w + tB / (1 - w))])
        Z = Za / best + KR / (2 * (1 - best))
        scale = 1.0 / best
    else:
        raise ValueError(f"unknown consider covariance {mode!r}; one of joseph, bound")
    nk, nz = float(np.linalg.norm(K)), float(np.linalg.norm(Z))
    a = np.sqrt(nz / nk) if nk > 0 and nz > 0 else 1.0
    X = (a * K + Z / a) / np.sqrt(2.0)
    Y = (a * K - Z / a) / np.sqrt(2.0)
    if scale != 1.0:
        Pc *= scale
    Pc += _syrk(X, scratch)
    Pc -= _syrk(Y, scratch)


# --- the walk's floor pose and point features ---------------------------------------

def floor_rotation(heading_rad: float, pitch_deg: float = 0.0) -> np.ndarray:
    return rotation_from_angles(float(np.degrees(heading_rad)), pitch_deg)


def _left_and_M(pose, pitch_deg):
    R = floor_rotation(pose[2], pitch_deg)
    return left_centre((pose[0], 0.0, pose[1]), R), axes_matrix(R)


def camera_point(pose, f, pitch_deg: float = 0.0) -> np.ndarray:
    """The camera-axes point (A-23 inverted: ``q = M^T (f - left)``) of room point
    ``f`` seen from the floor pose ``(x, z, heading rad)``."""
    left, M = _left_and_M(pose, pitch_deg)
    return M.T @ (np.asarray(f, dtype=np.float64) - left)


def room_point(pose, q, pitch_deg: float = 0.0) -> np.ndarray:
    """A-23: the room point of camera point ``q`` from the floor pose."""
    left, M = _left_and_M(pose, pitch_deg)
    return left + M @ np.asarray(q, dtype=np.float64)


def _heading_derivative(fun, pose, arg, pitch_deg):
    hi, lo = np.array(pose, float), np.array(pose, float)
    hi[2] += _DH
    lo[2] -= _DH
    return (fun(hi, arg, pitch_deg) - fun(lo, arg, pitch_deg)) / (2 * _DH)


def camera_point_jacobians(pose, f, pitch_deg: float = 0.0):
    """(d q / d pose (3x3), d q / d f (3x3)) of :func:`camera_point`."""
    _, M = _left_and_M(pose, pitch_deg)
    Jp = np.zeros((3, 3))
    Jp[:, 0] = -M.T[:, 0]                  # x moves the left camera along room X
    Jp[:, 1] = -M.T[:, 2]                  # z along room Z
    Jp[:, 2] = _heading_derivative(camera_point, pose, f, pitch_deg)
    return Jp, M.T


def room_point_jacobians(pose, q, pitch_deg: float = 0.0):
    """(d f / d pose (3x3), d f / d q (3x3)) of :func:`room_point`."""
    _, M = _left_and_M(pose, pitch_deg)
    Jp = np.zeros((3, 3))
    Jp[0, 0] = 1.0
    Jp[2, 1] = 1.0
    Jp[:, 2] = _heading_derivative(room_point, pose, q, pitch_deg)
    return Jp, M


class JointFilter:
    """The stochastic map: the floor pose and the features' 3-D positions, one
    mean and one dense covariance.  Features are named by the symbolic model's
    vertex ids.

    ``consider`` ("joseph" or "bound"; None: off): a second dense covariance beside the
    filter's, ``consider_cov``, propagated with the SAME predictions, Jacobians and
    gains but the measured measurement covariances the caller passes (``honest``):
    the covariance of the filter's mean under the errors as measured
    (:func:`consider_joint_update`).  Reported only: the mean, the gains and the gate
    use the filter's own ``cov``, so they are the same with it on or off.

    Storage: ``mean``, ``cov`` and ``consider_cov`` are views of preallocated buffers
    grown by half again when full, so a new feature writes only its own rows and
    columns; the update and the consider update run in place
    (:func:`ekf_update_in_place`, :func:`consider_update_in_place`), BLAS limited to
    :data:`JOINT_BLAS_THREADS`.  ``reference=True``: the plain steps
    (:func:`ekf_augment`, :func:`ekf_update_with_gain`, :func:`consider_joint_update`)
    instead -- the same numbers to rounding, kept for the tests and ``bench/joint.py``."""

    def __init__(self, pose_xzh_deg, pose_cov, pitch_deg: float = 0.0,
                 consider: str | None = None, reference: bool = False):
        if consider not in (None, "joseph", "bound"):
            raise ValueError(f"unknown consider covariance {consider!r}; one of joseph, bound")
        self.consider = consider
        self.reference = bool(reference)
        self.pitch_deg = float(pitch_deg)
        self._n, self._cap = 0, 0
        self._x = np.zeros(0)
        self._P = np.zeros((0, 0))
        self._Pc = np.zeros((0, 0)) if consider else None
        self._scratch = np.zeros(0)
        x, z, h = pose_xzh_deg
        cov = np.array(pose_cov, dtype=np.float64).reshape(POSE_DIM, POSE_DIM)
        self._set_state(np.array([x, z, np.radians(h)], dtype=np.float64), cov,
                        cov if consider else None)
        self.ids: list[int] = []
        self._slot: dict[int, int] = {}

    # --- the preallocated state ---------------------------------------------------------

    def _reserve(self, n: int) -> None:
        """Room for a state of ``n`` entries (the first ``self._n`` kept)."""
        if n <= self._cap:
            return
        cap = max(int(n * _GROWTH), _CAPACITY)
        old = self._n
        x = np.zeros(cap)
        x[:old] = self._x[:old]
        self._x = x
        for name in ("_P", "_Pc"):
            buf = getattr(self, name)
            if buf is not None:
                grown = np.zeros((cap, cap))
                grown[:old, :old] = buf[:old, :old]
                setattr(self, name, grown)
        self._scratch = np.empty(cap * cap)
        self._cap = cap

    def _set_state(self, mean, cov, consider_cov=None) -> None:
        n = len(mean)
        self._reserve(n)
        self._n = n
        self._x[:n] = mean
        self._P[:n, :n] = cov
        if consider_cov is not None:
            self._Pc[:n, :n] = consider_cov

    @property
    def mean(self) -> np.ndarray:
        return self._x[:self._n]

    @property
    def cov(self) -> np.ndarray:
        return self._P[:self._n, :self._n]

    @property
    def consider_cov(self) -> np.ndarray | None:
        return None if self._Pc is None else self._Pc[:self._n, :self._n]

    def __contains__(self, vid) -> bool:
        return int(vid) in self._slot

    def __len__(self) -> int:
        return len(self.ids)

    def _index(self, vid) -> int:
        return POSE_DIM + 3 * self._slot[int(vid)]

    @property
    def pose_xzh(self) -> tuple[float, float, float]:
        return (float(self.mean[0]), float(self.mean[1]),
                float(wrap_deg(np.degrees(self.mean[2]))))

    @property
    def pose_cov(self) -> np.ndarray:
        return self.cov[:POSE_DIM, :POSE_DIM].copy()

    def feature(self, vid) -> tuple[np.ndarray, np.ndarray]:
        i = self._index(vid)
        return self.mean[i:i + 3].copy(), self.cov[i:i + 3, i:i + 3].copy()

    def consider_feature(self, vid) -> np.ndarray:
        """The feature's marginal block of the consider covariance."""
        i = self._index(vid)
        return self.consider_cov[i:i + 3, i:i + 3].copy()

    def marginals(self):
        """Every feature's marginal at once, in ``ids`` order: (means (k, 3), covariances
        (k, 3, 3), consider covariances (k, 3, 3) or None) -- :meth:`feature`'s and
        :meth:`consider_feature`'s blocks, gathered in one indexing each."""
        k = len(self.ids)
        at = POSE_DIM + 3 * np.arange(k)[:, None, None]
        rows, cols = at + np.arange(3)[:, None], at + np.arange(3)[None, :]
        means = self.mean[POSE_DIM:].reshape(k, 3).copy()
        return (means, self.cov[rows, cols],
                self.consider_cov[rows, cols] if self.consider else None)

    def predict(self, new_xzh_deg, F, Q) -> None:
        """The odometry's step: the pose becomes ``new_xzh_deg`` (the step composed on
        the last estimate), its covariance ``F P F^T + Q``, its cross terms ``F P_pf``."""
        self.mean[:POSE_DIM] = (new_xzh_deg[0], new_xzh_deg[1], np.radians(new_xzh_deg[2]))
        with _blas_limit():
            ekf_predict(self.cov, F, Q, POSE_DIM, in_place=True)
            if self.consider:
                ekf_predict(self.consider_cov, F, Q, POSE_DIM, in_place=True)

    def add(self, vid, q, Cq) -> None:
        """A new feature from camera point ``q`` (covariance ``Cq``) at the current pose."""
        self.add_many([(vid, q, Cq)])

    def add_many(self, observations, honest=None) -> None:
        """New features ``(vid, q, Cq)`` at the current pose, in one augmentation (their
        cross-covariances to each other come through the pose).  ``honest``: with
        ``consider``, each observation's measured covariance (camera axes), entering
        the consider covariance through the same Jacobians (exactly, in both modes:
        a new feature's error is the pose's error and its own).

        A new feature depends on the pose alone (``J`` is zero beyond the pose's
        columns), so its cross-covariance is ``J_pose P_p.``: 3 rows of the state, written
        into the new rows and columns of the preallocated buffers."""
        observations = list(observations)
        if not observations:
            return
        pose = self.mean[:POSE_DIM].copy()
        k = len(observations)
        Jpose = np.zeros((3 * k, POSE_DIM))
        G = np.zeros((3 * k, 3 * k))
        R = np.zeros((3 * k, 3 * k))
        new = np.zeros(3 * k)
        for j, (vid, q, Cq) in enumerate(observations):
            if int(vid) in self._slot:
                raise ValueError(f"feature {vid} is already in the joint state")
            rows = slice(3 * j, 3 * j + 3)
            Jp, Jq = room_point_jacobians(pose, q, self.pitch_deg)
            Jpose[rows] = Jp
            G[rows, rows] = Jq
            R[rows, rows] = Cq
            new[rows] = room_point(pose, q, self.pitch_deg)
        R_true = None
        if self.consider:
            R_true = np.zeros_like(R)
            for j, C in enumerate(self._honest(honest, k)):
                R_true[3 * j:3 * j + 3, 3 * j:3 * j + 3] = C
        with _blas_limit():
            if self.reference:
                n = self._n
                J = np.zeros((3 * k, n))
                J[:, :POSE_DIM] = Jpose
                mean, cov = ekf_augment(self.mean, self.cov, new, J, R, G)
                cons = (ekf_augment(self.mean, self.consider_cov, new, J, R_true, G)[1]
                        if self.consider else None)
                self._set_state(mean, cov, cons)
            else:
                self._augment_in_place(new, Jpose, G, R, R_true)
        for vid, _, _ in observations:
            self._slot[int(vid)] = len(self.ids)
            self.ids.append(int(vid))

    def _augment_in_place(self, new, Jpose, G, R, R_true) -> None:
        n, a = self._n, len(new)
        self._reserve(n + a)
        for buf, Rm in ((self._P, R), (self._Pc, R_true)):
            if buf is None:
                continue
            cross = Jpose @ buf[:POSE_DIM, :n]                  # J P   (a, n)
            Pnn = cross[:, :POSE_DIM] @ Jpose.T + G @ Rm @ G.T
            buf[n:n + a, :n] = cross
            buf[:n, n:n + a] = cross.T
            buf[n:n + a, n:n + a] = (Pnn + Pnn.T) / 2
        self._x[n:n + a] = new
        self._n = n + a

    def drop(self, vids) -> None:
        """Forget features (marginalising a Gaussian is deleting its rows and columns):
        the kept ones move up in order, in the same buffers."""
        gone = {int(v) for v in vids} & set(self._slot)
        if not gone:
            return
        keep = list(range(POSE_DIM))
        ids = []
        for vid in self.ids:
            if vid not in gone:
                i = self._index(vid)
                keep += [i, i + 1, i + 2]
                ids.append(vid)
        keep = np.array(keep)
        k = len(keep)
        self._x[:k] = self._x[keep]
        self._P[:k, :k] = self._P[np.ix_(keep, keep)]
        if self.consider:
            self._Pc[:k, :k] = self._Pc[np.ix_(keep, keep)]
        self._n = k
        self.ids = ids
        self._slot = {vid: k for k, vid in enumerate(ids)}

    def _honest(self, honest, k: int) -> list:
        if honest is None or len(honest) != k:
            raise ValueError("the consider covariance needs one measured covariance per "
                             "observation")
        return [np.asarray(C, dtype=np.float64).reshape(3, 3) for C in honest]

    def update(self, observations, gate_chi2: float | None = None,
               honest=None) -> list[int]:
        """All of one look's matched observations ``(vid, q, Cq)`` in one batch.
        ``gate_chi2``: the filter's own validation gate -- an observation whose
        innovation lies outside this chi-square bound of its joint innovation
        covariance ``H_k P H_k^T + C_q`` (the pose's, the feature's and their cross
        terms) is left out.  ``honest``: with ``consider``, each observation's measured
        covariance (camera axes) for the consider covariance.  Returns the ids left out."""
        observations = list(observations)
        if not observations:
            return []
        if self.consider:
            honest = self._honest(honest, len(observations))
        pose = self.mean[:POSE_DIM].copy()
        rows_H, rows_r, Cqs, ids, out, Cts = [], [], [], [], [], []
        for n_obs, (vid, q, Cq) in enumerate(observations):
            i = self._index(vid)
            f = self.mean[i:i + 3]
            Jp, Jf = camera_point_jacobians(pose, f, self.pitch_deg)
            r = np.asarray(q, dtype=np.float64) - camera_point(pose, f, self.pitch_deg)
            if gate_chi2 is not None:
                at = [0, 1, 2, i, i + 1, i + 2]
                Hk = np.hstack([Jp, Jf])
                S = Hk @ self.cov[np.ix_(at, at)] @ Hk.T + Cq
                if float(r @ np.linalg.solve(S, r)) > gate_chi2:
                    out.append(int(vid))
                    continue
            rows_H.append((i, Jp, Jf))
            rows_r.append(r)
            Cqs.append(Cq)
            ids.append(int(vid))
            if self.consider:
                Cts.append(honest[n_obs])
        if not ids:
            return out
        m = 3 * len(ids)
        R = np.zeros((m, m))
        R_true = np.zeros((m, m)) if self.consider else None
        for k in range(len(ids)):
            rows = slice(3 * k, 3 * k + 3)
            R[rows, rows] = Cqs[k]
            if self.consider:
                R_true[rows, rows] = Cts[k]
        innovation = np.concatenate(rows_r)
        with _blas_limit():
            if self.reference:
                H = np.zeros((m, self._n))
                for k, (i, Jp, Jf) in enumerate(rows_H):
                    H[3 * k:3 * k + 3, :POSE_DIM] = Jp
                    H[3 * k:3 * k + 3, i:i + 3] = Jf
                mean, cov, K = ekf_update_with_gain(self.mean, self.cov, innovation, H, R)
                cons = (consider_joint_update(self.consider_cov, K, H, R_true, self.consider)
                        if self.consider else None)
                self._set_state(mean, cov, cons)
            else:
                # H is zero beyond the pose's and the matched features' columns
                starts = sorted({i for i, _, _ in rows_H})
                at = {i: POSE_DIM + 3 * j for j, i in enumerate(starts)}
                cols = np.array([0, 1, 2] + [i + d for i in starts for d in range(3)])
                Hc = np.zeros((m, len(cols)))
                for k, (i, Jp, Jf) in enumerate(rows_H):
                    Hc[3 * k:3 * k + 3, :POSE_DIM] = Jp
                    Hc[3 * k:3 * k + 3, at[i]:at[i] + 3] += Jf
                K = ekf_update_in_place(self.mean, self.cov, innovation, Hc, cols, R,
                                        self._scratch)
                if self.consider:
                    consider_update_in_place(self.consider_cov, K, Hc, cols, R_true,
                                             self.consider, self._scratch)
        self.mean[2] = np.radians(wrap_deg(np.degrees(self.mean[2])))
        return out

    def pose_estimate(self, method: str = "fused") -> PoseEstimate:
        """The pose as the walk's other code takes it: the left camera, the axes, and
        the 6x6 (left camera position, rotation vector) covariance from the floor
        pose's (height and tilt known: zero)."""
        pose = self.mean[:POSE_DIM]
        left, M = _left_and_M(pose, self.pitch_deg)
        J = np.zeros((6, 3))
        J[0, 0] = 1.0
        J[2, 1] = 1.0
        hi, lo = pose.copy(), pose.copy()
        hi[2] += _DH
        lo[2] -= _DH
        J[:3, 2] = (_left_and_M(hi, self.pitch_deg)[0] - _left_and_M(lo, self.pitch_deg)[0]) / (2 * _DH)
        J[4, 2] = 1.0                      # heading = rotation about room Y
        cov6 = J @ self.pose_cov @ J.T
        return PoseEstimate(method, left, M, np.zeros(0, bool), covariance6=(cov6 + cov6.T) / 2)


__all__ = ["JointFilter", "ekf_predict", "ekf_augment", "ekf_update", "ekf_update_with_gain",
           "consider_joint_update", "ekf_update_in_place", "consider_update_in_place", "camera_point",
           "room_point", "camera_point_jacobians", "room_point_jacobians"]
