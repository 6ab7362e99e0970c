"""The walk: look after look into one symbolic model (Chapter III, "Three
Dimensional Models and Model Updates", "Stochastic Updates", "Camera
Position Estimation").

For every look:

1. the rig scans the pair (ESTAR over the direct link, every line of the
   scanned range) and its located edges are grouped into vertical edges and
   vertex observations (:mod:`model.edges`);
2. the prior pose is the last estimate moved by the odometry's step (dead
   reckoning between looks);
3. the observations are matched to the model (:mod:`model.matching`);
4. every pose method runs on the SAME correspondences (:mod:`model.pose`);
5. the pose of the *driving* method (``robust`` unless chosen otherwise) is
   used to update the matched vertices by the static Kalman filter
   (:mod:`model.kalman`, A-30 or A-29) and to add the unmatched ones as new
   vertices; vertices out of view are kept as they are;
6. the velocity follows from the driving method's successive positions.

The first look's pose is given (the model's frame is the room's, anchored
where the robot starts); every later pose is estimated.  A look whose pose
the driving method refuses (too few matches, colinear points ...) keeps the
prior, changes nothing in the model, and says why.

The world's truth (the renderer's range per pixel, the room's true corners) is
used only for scoring: which correspondences are wrong, how far each feature
is from its true place, whether the truth is inside 2 sigma.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .edges import (CALIBRATED_COLUMN_ERROR_PX, E_D, E_LR, MEASURED_DISPARITY_ERROR_PX,
                    MEASURED_ROW_ERROR_PX, Camera, group_vertical_edges, is_ambiguous, locate,
                    stereo_ambiguity, surface_observations, vertex_observations,
                    alternative_disparities, shifted_vertex)
from .geometry import axes_matrix, left_centre, rotation_from_angles, wrap_deg
from .kalman import (consider_update, covariance_intersection, kalman_gain,
                     measurement_covariance_a29, measurement_covariance_a30,
                     feature_variance_factors, normalised_innovation, robust_variance_factor,
                     static_update)
from .joint import JointFilter
from .matching import MATCHERS, MatchResult
from .pose import ESTIMATORS, PoseEstimate, PoseRefused, estimate
from .symbolic import SymbolicModel
from .velocity import Velocity, velocity

# the fused pose's error on the bundled walk under A-29 (bench/walk.py): median 0.157 ft on
# the floor (a 2-D Gaussian's median radius is 1.177 sigma) and 0.57 degrees of heading (a
# Gaussian's median absolute value is 0.674 sigma), where the pose's own covariance claims
# 0.032 ft per axis and 0.47 degrees: only 13 % of the looks' true poses lie inside its 95 %
# region (bench/walk.py --calibrate)
MEASURED_POSE_SIGMA_FLOOR = (0.13, 0.85)
# the fused pose's height and tilt are the driving fix's alone (the odometry knows neither):
# on the bundled walk (A-29, twice round; bench/walk.py --calibrate) its height is off by
# 0.216 ft at the median (0.32 ft sigma; 3.9 ft at the 95.4 % point) and its tilt (about the
# two horizontal room axes together) by 3.7 degrees (a 2-D Gaussian's median radius is 1.177
# sigma: 3.2 degrees), where it claims 1.7 degrees; every feature a look places or updates
# inherits that error, vertically.  The consider covariance's floor for them (--tilt-floor):
MEASURED_TILT_SIGMA_FLOOR = (0.32, 3.2)
CHI2_3DOF_2SIGMA = 8.0249     # the 3-D ellipsoid holding 95.45 % (the share of +-2 sigma in 1-D)
TRUTH_SNAP_FT = 0.3           # an observation within this of a true corner IS that corner
WRONG_MATCH_FT = 0.3          # a pair whose true points differ by more is a wrong correspondence
FEATURE_GATE_CHI2 = 16.27     # the feature gate's default: chi-square 99.9 %, 3 degrees of freedom
CONSIDER_MODES = ("bound", "joseph")
# the static update as written (a30), its alternatives (a29, ci), and the joint filter of
# pose and features (model.joint)
KALMAN_CHOICES = ("a30", "a29", "ci", "joint")
AMBIGUITY_NEAREST_FT = 1.0   # the ambiguity gate searches disparities from max_range_ft to this
CONSISTENT_CHI2 = 11.345      # a look consistent with its feature: chi-square 99 %, 3 degrees of freedom


def _ambiguity_disparities(config) -> tuple[float, float]:
    """The disparities (px) the ambiguity gate searches: from ``max_range_ft`` in to
    AMBIGUITY_NEAREST_FT."""
    cam = config.camera
    return cam.ds * cam.dv / config.max_range_ft, cam.ds * cam.dv / AMBIGUITY_NEAREST_FT


@dataclass
class WalkConfig:
    methods: tuple[str, ...] = ESTIMATORS
    driver: str = "robust"
    kalman: str = "a30"                 # "a30" as written, "a29" camera error propagated
    match: str = "1985"                 # the rig's stereo matcher: "1985" or "improved"
    model_matcher: str = "text"         # look-to-model matching (model.matching.MATCHERS)
    lines: tuple[int, ...] = tuple(range(8, 113, 2))      # every 2nd line (rig walk --line-step)
    look_interval_s: float = 1.0
    # Chapter V: "the range estimates were fairly accurate for ranges of 15 feet or less";
    # beyond, one pixel of disparity is feet of range and a wrong match lands anywhere
    max_range_ft: float = 15.0
    # Chapter III: "approximate matches in grey level, then approximate matches in shape";
    # corner maps differing in more than a quarter of their 256 bits are not the same corner
    shape_max_bits: int | None = 64
    odometry_distance_fraction: float = 0.02
    odometry_turn_deg: float = 1.0
    # the rig's known mounting pitch, for the prior's rotation (0: level, as the walk; the
    # drive's vehicle carries the rig pitched down)
    camera_pitch_deg: float = 0.0
    camera: Camera = Camera()
    # the column bound of A-17, px: LCSL's ELMAX 0.5 as written; model.edges.
    # CALIBRATED_COLUMN_ERROR_PX (2.0) is the one measured against the world's corners
    column_error_px: float = E_LR
    # a floor (ft, degrees) under the camera pose's sigma in A-29's camera term (kalman a29/ci
    # only); None: the fused pose's covariance as computed.  MEASURED_POSE_SIGMA_FLOOR is the
    # driving pose's measured error on the bundled walk (docs/model.md)
    pose_sigma_floor: tuple[float, float] | None = None
    # the feature gate (named alternative; None: every pair the driving pose kept is fused, as
    # written): a pair whose innovation lies outside this chi-square bound of the feature's and
    # the observation's covariance (the consider covariances where kept) is a wrong merge: not
    # fused; the observation starts a feature of its own (a split), and a feature contradicted
    # in as many looks as it was confirmed, and in two at least, leaves the model
    feature_gate: float | None = None
    # the consider covariance (named alternative; None: off): beside the filter's covariance
    # every feature carries the covariance of its mean under the MEASURED errors (the
    # calibrated column error, the measured pose floor in A-29's camera term), "bound" holding
    # whatever the looks' correlation, "joseph" for independent looks
    # (model.kalman.consider_update).  Reported and scored; the matcher and the pose keep
    # using the filter's own.  With kalman "joint": the joint state's second covariance
    # (model.joint.consider_joint_update), the same gains, the measured camera-axes bounds
    consider: str | None = None
    # with the consider covariance: a floor (ft, degrees) under the camera's height and tilt
    # sigma in its camera term (None: the pose's own; MEASURED_TILT_SIGMA_FLOOR measured)
    tilt_floor: tuple[float, float] | None = None
    # retiring the unseen (named alternative; None: off, the model remembers everything): a
    # vertex that looks whose pose was fixed predicted well inside their view (8 px in from
    # the picture's edges, within max_range_ft) did not match, this many times per look it
    # was seen in, leaves the model (a phantom of a wrong stereo match is seen once and never
    # again where it claims to be)
    retire_unseen: int | None = None
    # track confirmation (named alternative; None: off, every feature is the model's): a
    # feature is CONFIRMED once this many of its looks (its first included) were consistent
    # with it (the innovation inside CONSISTENT_CHI2 of the covariances it reports) and no
    # fewer than the looks that should have seen it and did not; until then it is TENTATIVE:
    # matched and updated like any other, reported apart (WalkResult.feature_scores)
    confirm: int | None = None
    # the a-posteriori variance factor (named alternative; False: off): the reported
    # covariance (the consider covariance where kept) scaled by the variance of unit weight of
    # the feature's own innovations, pooled with a robust global one (model.kalman.
    # feature_variance_factors); scoring and reporting only
    variance_factor: bool = False
    # the ambiguity gate (named alternative; None: off, every vertex the rig located is
    # used): a vertical edge whose picture patch fits another disparity as well as the rig's
    # (model.edges.stereo_ambiguity, is_ambiguous: a periodic texture matched a period off,
    # the dissertation's "picket fence") is AMBIGUOUS.  "drop": its vertices are not used in
    # that look at all; "track": they may match features the model already holds (the
    # prediction from the prior pose picks the period) but start no feature
    ambiguity_gate: str | None = None
    # --kalman joint only: the joint filter's own validation gate (chi-square, 3 degrees of
    # freedom) on each used pair's innovation against its JOINT covariance (pose, feature and
    # their cross terms; model.joint.JointFilter.update); None: every used pair is fused
    joint_gate: float | None = FEATURE_GATE_CHI2


@dataclass
class LookRecord:
    look: int
    true_pose: object
    dead_reckoned: object
    prior_xzh: tuple[float, float, float]
    estimates: dict[str, tuple[float, float, float] | None]
    refusals: dict[str, str]
    seen: int
    matched: int
    wrong: int
    used: int
    used_wrong: int
    added: int
    model_size: int
    predicted_in_view: int
    times_ms: dict[str, float]
    velocity: Velocity | None = None
    driver_refused: str | None = None
    pose_covariance: np.ndarray | None = None      # the robot's (x, z, heading rad) covariance
    pose: PoseEstimate | None = None               # the pose the model was updated with (all six)
    ambiguous: int = 0                             # vertices the ambiguity gate found ambiguous
    resolved: int = 0                              # ambiguous edges "resolve" moved to another period

    def errors(self, name: str) -> tuple[float, float] | None:
        est = self.estimates.get(name)
        if est is None:
            return None
        t = self.true_pose
        return (float(np.hypot(est[0] - t.x, est[1] - t.z)),
                float(abs(wrap_deg(est[2] - t.heading_deg))))


@dataclass
class WalkResult:
    config: WalkConfig
    records: list[LookRecord]
    model: SymbolicModel
    error_history: dict[int, list[float]] = field(default_factory=dict)   # vertex -> error after each look

    def variance_factors(self) -> tuple[float, dict[int, float]]:
        """The a-posteriori variance factors (adjustment theory's variance of unit
        weight): the robust global one from every innovation of the walk, and one per
        vertex pooled from its own innovations and the global one
        (:func:`model.kalman.feature_variance_factors`, never below 1)."""
        every = [*self.model.vertices.values(), *self.model.retired.values()]
        g = robust_variance_factor([x for v in every for x in v.nis])
        vs = list(self.model.vertices.values())
        f = feature_variance_factors([v.nis for v in vs], g)
        return g, {v.id: float(x) for v, x in zip(vs, f)}

    def reported_covariance(self, v, factors: dict[int, float] | None = None) -> np.ndarray:
        """The covariance a vertex reports: the consider covariance where kept, else
        the filter's; scaled by its variance factor where ``factors`` are given."""
        C = v.cov if v.report_cov is None else v.report_cov
        return C if factors is None else C * factors[v.id]

    def confirmed_by_track(self, v) -> bool:
        """Track confirmation (``WalkConfig.confirm`` = M): at least M of the vertex's
        looks, its first included, consistent with it (the innovation inside
        CONSISTENT_CHI2 of the covariances it reports), and they no fewer than the
        looks that should have seen it and did not (``missed``)."""
        hits = 1 + sum(1 for x in v.nis if x <= CONSISTENT_CHI2)
        return hits >= (self.config.confirm or 2) and hits >= v.missed

    def feature_scores(self) -> dict:
        """RMS error (ft) and share of truths inside 2 sigma over the vertices
        with a truth; the Mahalanobis-2 radius share too.  With
        ``WalkConfig.variance_factor`` the reported covariances are scaled; with
        ``WalkConfig.confirm`` the track-confirmed and the tentative vertices are
        scored apart as well (``track_confirmed_*``, ``tentative_*``)."""
        factors = None
        out_extra = {}
        if self.config.variance_factor:
            g, factors = self.variance_factors()
            out_extra["variance_factor_global"] = g
            out_extra["variance_factor_median"] = (float(np.median(list(factors.values())))
                                                   if factors else None)
        errs, inside, inside_r2, confirmed, inside_filter, track = [], [], [], [], [], []
        for v in self.model.vertices.values():
            if v.truth is None:
                continue
            d = v.mean - v.truth
            errs.append(float(d @ d))
            m2 = float(d @ np.linalg.solve(self.reported_covariance(v, factors), d))
            inside.append(m2 <= CHI2_3DOF_2SIGMA)
            inside_r2.append(m2 <= 4.0)
            inside_filter.append(float(d @ np.linalg.solve(v.cov, d)) <= CHI2_3DOF_2SIGMA)
            confirmed.append(v.looks >= 2)
            track.append(self.confirmed_by_track(v))
        if self.config.confirm is not None:
            t = np.array(track, dtype=bool)
            e, i = np.array(errs).reshape(-1), np.array(inside, dtype=bool)
            for name, sel in (("track_confirmed", t), ("tentative", ~t)):
                out_extra[name] = int(sel.sum())
                out_extra[f"{name}_inside_2sigma"] = float(np.mean(i[sel])) if sel.any() else None
                out_extra[f"{name}_rms_error_ft"] = (float(np.sqrt(np.mean(e[sel])))
                                                     if sel.any() else None)
        if not errs:
            return {"features": len(self.model.vertices), "scored": 0, "rms_error_ft": None,
                    "inside_2sigma": None, "inside_mahalanobis_2": None, "confirmed": 0,
                    "confirmed_rms_error_ft": None, "confirmed_median_error_ft": None,
                    "confirmed_inside_2sigma": None, "median_error_ft": None,
                    "filter_inside_2sigma": None, "retired": len(self.model.retired),
                    **out_extra}
        errs, inside, confirmed = np.array(errs), np.array(inside), np.array(confirmed)
        return {**out_extra, "features": len(self.model.vertices), "scored": len(errs),
                "rms_error_ft": float(np.sqrt(np.mean(errs))),
                "median_error_ft": float(np.sqrt(np.median(errs))),
                "inside_2sigma": float(np.mean(inside)),
                "inside_mahalanobis_2": float(np.mean(inside_r2)),
                # with the consider covariance on: the share inside the filter's own covariance
                "filter_inside_2sigma": float(np.mean(inside_filter)),
                "retired": len(self.model.retired),
                "confirmed": int(confirmed.sum()),
                "confirmed_rms_error_ft": float(np.sqrt(np.mean(errs[confirmed])))
                if confirmed.any() else None,
                "confirmed_median_error_ft": float(np.sqrt(np.median(errs[confirmed])))
                if confirmed.any() else None,
                "confirmed_inside_2sigma": float(np.mean(inside[confirmed]))
                if confirmed.any() else None}

    def rms_by_looks(self, max_looks: int = 20) -> list[tuple[int, int, float]]:
        """(n, features seen at least n times, RMS error after their n-th look)."""
        out = []
        for n in range(1, max_looks + 1):
            e = [h[n - 1] for h in self.error_history.values() if len(h) >= n]
            if e:
                out.append((n, len(e), float(np.sqrt(np.mean(np.square(e))))))
        return out


# --- truth, for scoring only ------------------------------------------------------

def truth_points(room) -> np.ndarray:
    pts = [np.asarray(room.vertices, float).reshape(-1, 3)]
    ve = np.asarray(room.vertical_edges, float)
    if ve.size:
        pts.append(ve.reshape(-1, 3))
    return np.concatenate(pts) if pts else np.zeros((0, 3))


def observed_truth(obs, range_left, true_left, true_R, corners, camera: Camera):
    """The world's true location of each observation: the pixel the rig named,
    at the renderer's range on the last scanned line that saw the edge (the
    nearer of the columns either side, as rig.truth scores an edge), in room
    axes; snapped to a true corner when one lies within TRUTH_SNAP_FT.
    Returns (points (N,3), corner index or -1 (N,))."""
    h, w = range_left.shape
    pts, idx = [], []
    for o in obs:
        r = int(np.clip(o.line if o.line >= 0 else np.floor(o.row), 0, h - 1))
        c = int(np.clip(np.floor(o.col), 0, w - 1))
        z = float(np.min(range_left[r, max(c - 1, 0):c + 2]))
        v = np.array([z * (o.col - camera.centre_col) / camera.dv,
                      z * (o.row - camera.centre_row) / camera.dv, z])
        p = true_left + true_R @ v
        k = -1
        if len(corners):
            d = np.linalg.norm(corners - p, axis=1)
            j = int(np.argmin(d))
            if d[j] <= TRUTH_SNAP_FT:
                p, k = corners[j].copy(), j
        pts.append(p)
        idx.append(k)
    return np.array(pts).reshape(-1, 3), np.array(idx, dtype=int)


# --- the loop ------------------------------------------------------------------------

def compose_step(prev_est_xzh, dr_prev, dr_now):
    """The prior: the previous estimate moved by the odometry's step, i.e. the
    dead-reckoned motion from dr_prev to dr_now expressed in the vehicle frame."""
    h0 = np.radians(dr_prev.heading_deg)
    dx, dz = dr_now.x - dr_prev.x, dr_now.z - dr_prev.z
    fwd = dx * np.sin(h0) + dz * np.cos(h0)          # along the old heading
    side = dx * np.cos(h0) - dz * np.sin(h0)         # to its right
    turn = float(wrap_deg(dr_now.heading_deg - dr_prev.heading_deg))
    x, z, h = prev_est_xzh
    hr = np.radians(h)
    return (x + fwd * np.sin(hr) + side * np.cos(hr), z + fwd * np.cos(hr) - side * np.sin(hr),
            float(wrap_deg(h + turn))), float(np.hypot(dx, dz)), abs(turn)


_compose_step = compose_step          # the name the walk's tests know


def _rotation(heading, pitch=0.0, roll=0.0):
    return rotation_from_angles(heading, pitch, roll)


def run_walk(room, poses, dead_reckoned, render: Callable, config: WalkConfig = WalkConfig(),
             progress: Callable[[int], None] | None = None, seed: int = 0) -> WalkResult:
    """Walk the poses: ``render(room, pose, look_index)`` gives the world's Look
    (``left_bi``, ``right_bi``, ``range_left``, ``pose``); each look goes
    through :meth:`Walker.step`."""
    walker = Walker(room, config)
    for k, true_pose in enumerate(poses):
        look = render(room, true_pose, k)
        walker.step(look, true_pose, dead_reckoned[k], dead_reckoned[k - 1] if k else None)
        if progress is not None:
            progress(k)
    return walker.result()


class Walker:
    """One look at a time into one symbolic model: the per-look step of the
    walk (:func:`run_walk`) and of the closed loop (``rig drive``'s
    ``--pose fused``).  The first look's pose is given (the true pose), every
    later one is the driving method's fix fused with the odometry's prior."""

    def __init__(self, room, config: WalkConfig = WalkConfig()):
        if config.driver not in ESTIMATORS:
            raise ValueError(f"unknown driving method {config.driver!r}; one of {', '.join(ESTIMATORS)}")
        self.methods = tuple(dict.fromkeys((*config.methods, config.driver)))
        for m in self.methods:
            if m not in ESTIMATORS:
                raise ValueError(f"unknown pose method {m!r}; one of {', '.join(ESTIMATORS)}")
        if config.kalman not in KALMAN_CHOICES:
            raise ValueError(f"unknown Kalman mode {config.kalman!r}; one of "
                             f"{', '.join(KALMAN_CHOICES)}")
        if config.kalman == "joint" and config.tilt_floor is not None:
            raise ValueError("the tilt floor widens the static consider covariance's camera "
                             "term; the joint filter carries the pose in its state: not with "
                             "--kalman joint")
        self.matcher = MATCHERS.get(config.model_matcher)
        if self.matcher is None:
            raise ValueError(f"unknown model matcher {config.model_matcher!r}; one of "
                             f"{', '.join(MATCHERS)}")
        if config.consider is not None and config.consider not in CONSIDER_MODES:
            raise ValueError(f"unknown consider covariance {config.consider!r}; one of "
                             f"{', '.join(CONSIDER_MODES)}")
        if config.consider is not None and config.kalman == "ci":
            raise ValueError("the consider covariance follows the Kalman gain: use it with "
                             "--kalman a30 or a29, not ci")
        if config.retire_unseen is not None and config.retire_unseen < 1:
            raise ValueError(f"retire unseen {config.retire_unseen!r}: must be at least 1")
        if config.tilt_floor is not None and config.consider is None:
            raise ValueError("the tilt floor widens the consider covariance: use it with "
                             "--consider")
        if config.confirm is not None and config.confirm < 2:
            raise ValueError(f"confirm {config.confirm!r}: at least 2 consistent looks")
        if config.feature_gate is not None and not config.feature_gate > 0:
            raise ValueError(f"feature gate {config.feature_gate!r}: must be a positive "
                             "chi-square bound")
        if config.match not in ("1985", "improved"):
            raise ValueError(f"--match {config.match!r}: choose 1985 or improved")
        self.config = config
        self.model = SymbolicModel()
        self.corners = truth_points(room)
        self.history: dict[int, list[float]] = {}
        self.records: list[LookRecord] = []
        self.lines = list(config.lines)
        self.rows = (min(self.lines), max(self.lines) + 1)
        self.prev_xzh = None
        self.prev_cov = None
        self.P = np.zeros((3, 3))         # covariance of the pose (x, z, heading rad) carried on
        self.last_dead = None             # the dead-reckoned pose at the last look
        self.pending = SymbolicModel()    # --ambiguity-gate resolve: last look's unresolved candidates
        self.resolved = 0                 # ambiguous edges moved to another period by the model
        self.joint = None                 # --kalman joint: the stochastic map (model.joint)

    def result(self) -> WalkResult:
        return WalkResult(self.config, self.records, self.model, self.history)

    def predict(self, dead_now) -> tuple[float, float, float]:
        """The last estimate moved by the odometry's step since the last look."""
        return compose_step(self.prev_xzh, self.last_dead, dead_now)[0]

    def scan(self, look):
        """The rig's scan of the look's pair (the eyes for the 1985 matcher)."""
        from eyes import scan_pair as eyes_scan_pair
        from matching.mode import make_matcher
        from rig.scan import scan_pair
        config = self.config
        ds, dv = str(config.camera.ds), f"{config.camera.dv:g}"
        if config.match == "1985":        # the compiled 1985 frame scan (the eyes), bit for bit
            return eyes_scan_pair(look.left_bi, look.right_bi, self.lines, ds, dv)
        # the improved stereo matcher (package matching)
        return scan_pair(look.left_bi, look.right_bi, self.lines, ds, dv,
                         matcher=make_matcher("improved"))

    def step(self, look, true_pose, dr, dr_prev=None, scan=None) -> LookRecord:
        """One look: scan (unless ``scan`` is given, the rig's ScanResult of
        this look over ``config.lines``), group, match to the model, estimate
        the pose, update the model.  ``dr``/``dr_prev``: the dead-reckoned
        poses at this look and the last (None at the first look)."""
        config, model, methods, matcher = self.config, self.model, self.methods, self.matcher
        corners, history, lines, rows = self.corners, self.history, self.lines, self.rows
        prev_xzh, prev_cov, P = self.prev_xzh, self.prev_cov, self.P
        k = len(self.records)
        t_start = time.perf_counter()
        if scan is None:
            scan = self.scan(look)
        t_scan = time.perf_counter()
        edges = group_vertical_edges(scan.points, lines, look.left_bi, config.camera,
                                     right_picture=look.right_bi,
                                     column_error=config.column_error_px)
        ambiguous_ids: set[int] = set()
        ambiguous_edges: list = []
        resolved_before = self.resolved
        unresolved: list = []
        if config.ambiguity_gate is not None:
            d_range = _ambiguity_disparities(config)
            for e in edges:
                if e.vertices and is_ambiguous(stereo_ambiguity(look.left_bi, look.right_bi,
                                                                e, d_range)):
                    if config.ambiguity_gate == "drop":
                        ambiguous_ids.update(id(o) for o in e.vertices)
                        e.vertices[:] = []
                    elif config.ambiguity_gate == "resolve":
                        ambiguous_edges.append(e)
                    else:
                        ambiguous_ids.update(id(o) for o in e.vertices)
        early_prior = None
        if ambiguous_edges:
            early_prior = _predict(prev_xzh, P, dr_prev, dr, config) if k > 0 else None
            ambiguous_ids, unresolved = self._resolve(look, ambiguous_edges, early_prior)
        obs = [o for o in vertex_observations(edges) if o.q[0] <= config.max_range_ft]
        for e in edges:
            e.vertices[:] = [o for o in e.vertices if o.q[0] <= config.max_range_ft]
        # "track": an ambiguous vertex may match a feature the model holds (the prediction
        # gate picks the period) but starts none
        no_new = {i for i, o in enumerate(obs) if id(o) in ambiguous_ids}
        ambiguous = (sum(len(e.vertices) for e in ambiguous_edges)
                     if config.ambiguity_gate == "resolve" else len(ambiguous_ids))
        t_group = time.perf_counter()
        R_true = np.asarray(true_pose.rotation(), float)
        true_left = left_centre((true_pose.x, getattr(true_pose, "y", 0.0), true_pose.z), R_true)
        obs_truth, obs_truth_id = observed_truth(obs, np.asarray(look.range_left, float),
                                                 true_left, R_true, corners, config.camera)
        times = {"scan": (t_scan - t_start) * 1e3, "group": (t_group - t_scan) * 1e3}
        estimates: dict[str, tuple | None] = {}
        refusals: dict[str, str] = {}
        driver_refused = None
        pairs_used: list[tuple[int, int]] = []
        if k == 0:
            # the start is given: the model's frame is anchored here
            prior_xzh = (true_pose.x, true_pose.z, true_pose.heading_deg)
            pose_est = PoseEstimate("given", true_left, axes_matrix(R_true), np.zeros(0, bool),
                                    covariance6=np.zeros((6, 6)))
            match = MatchResult([], 0, 0)
            for m in (*methods, "fused"):
                estimates[m] = prior_xzh
            times["match"] = (time.perf_counter() - t_group) * 1e3
        else:
            prior_xzh, P = early_prior if early_prior is not None else _predict(
                prev_xzh, P, dr_prev, dr, config)
            if self.joint is not None:
                self.joint.drop([vid for vid in self.joint.ids if vid not in model.vertices])
                _, F_step, Q_step = _odometry_step(prev_xzh, dr_prev, dr, config)
                self.joint.predict(prior_xzh, F_step, Q_step)
            prior_R = _rotation(prior_xzh[2], config.camera_pitch_deg)
            prior_left = left_centre((prior_xzh[0], 0.0, prior_xzh[1]), prior_R)
            cov6 = _cov6(P)
            match = matcher(model, obs, prior_left, prior_R, cov6, rows=rows,
                            shape_max_bits=config.shape_max_bits)
            times["match"] = (time.perf_counter() - t_group) * 1e3
            vid = [p[0] for p in match.pairs]
            oi = [p[1] for p in match.pairs]
            q = np.array([obs[i].q for i in oi]).reshape(-1, 3)
            Cq = np.array([obs[i].cov for i in oi]).reshape(-1, 3, 3)
            X = np.array([model.vertices[v].mean for v in vid]).reshape(-1, 3)
            CX = np.array([model.vertices[v].cov for v in vid]).reshape(-1, 3, 3)
            results: dict[str, PoseEstimate] = {}
            for m in methods:
                t0 = time.perf_counter()
                try:
                    est = estimate(m, q, Cq, X, CX, prior_left, prior_R)
                    results[m] = est
                    estimates[m] = (float(est.centre[0]), float(est.centre[2]), est.heading_deg)
                except PoseRefused as exc:
                    refusals[m] = str(exc)
                    estimates[m] = None
                times[m] = (time.perf_counter() - t0) * 1e3
            fix = results.get(config.driver)
            driver_refused = refusals.get(config.driver)
            pose_est = None
            if fix is not None:
                fused = _fuse(fix, prior_xzh, P)
                if isinstance(fused, str):
                    driver_refused = fused
                else:
                    pose_est, P = fused
                    pairs_used = [p for p, ok in zip(match.pairs, fix.inliers) if ok]
            if pose_est is None:
                # no fix: the pose stays the prior; nothing is updated, but what the robot
                # sees for the first time enters at the prior, carrying the prior's own
                # uncertainty (A-29's P_i N_Y term; without it these features would
                # claim a fix never made)
                pose_est = PoseEstimate("prior", prior_left, axes_matrix(prior_R),
                                        np.zeros(0, bool), covariance6=cov6)
            estimates["fused"] = (float(pose_est.centre[0]), float(pose_est.centre[2]),
                                  pose_est.heading_deg)
        estimates["dead_reckoning"] = (dr.x, dr.z, dr.heading_deg)
        t_up = time.perf_counter()
        kalman = config.kalman if pose_est.method != "prior" else "a29"
        joint_log = None
        if config.kalman == "joint":
            # the joint filter: the fused fix decided which pairs are used; the model is
            # placed and bookkept at the prior, the joint state then moves everything
            kalman, joint_log = "joint", {"pairs": [], "new": []}
            if k == 0:
                self.joint = JointFilter(prior_xzh, np.zeros((3, 3)), config.camera_pitch_deg,
                                         consider=config.consider)
            fused_est, pose_est = pose_est, self.joint.pose_estimate(
                "given" if k == 0 else "prior")
        # scored before the update: the feature gate may retire a vertex of these pairs
        wrong = _wrong(model, match.pairs, obs_truth)
        used_wrong = _wrong(model, pairs_used, obs_truth)
        honest = None
        if config.consider is not None and joint_log is None:
            honest = _measured_covariances(obs, pose_est, config, lines, given=k == 0)
        added = _update_model(model, edges, obs, match.pairs, pairs_used, pose_est,
                              kalman, k, obs_truth, obs_truth_id, history,
                              surface_observations(edges, look.left_bi),
                              pose_floor=config.pose_sigma_floor if k > 0 else None,
                              honest=honest,
                              consider=config.consider if joint_log is None else None,
                              feature_gate=config.feature_gate, no_new=no_new,
                              joint_log=joint_log)
        if joint_log is not None:
            pose_est, P = self._joint_update(obs, joint_log, k, fused_est.method)
            estimates["fused"] = (float(pose_est.centre[0]), float(pose_est.centre[2]),
                                  pose_est.heading_deg)
        if ((config.retire_unseen is not None or config.confirm is not None) and k > 0
                and pose_est.method == "fused"):
            _retire_unseen(model, match.pairs, pose_est, k, rows, config)
        if config.ambiguity_gate == "resolve":
            self._remember_unresolved(unresolved, pose_est)
        est_xzh = estimates["fused"]
        est_cov = P.copy()
        times["update"] = (time.perf_counter() - t_up) * 1e3
        times["look"] = (times["scan"] + times["group"] + times["match"]
                         + times.get(config.driver, 0.0) + times["update"])
        vel = None
        if prev_xzh is not None:
            vel = velocity(prev_xzh, prev_cov, est_xzh, est_cov, config.look_interval_s)
        prev_xzh, prev_cov = est_xzh, est_cov
        rec = LookRecord(
            k, true_pose, dr, tuple(float(v) for v in prior_xzh), estimates, refusals,
            len(obs), len(match.pairs), wrong, len(pairs_used), used_wrong, added,
            len(model.vertices), match.predicted_in_view, times, vel, driver_refused, est_cov,
            pose_est, ambiguous)
        rec.resolved = self.resolved - resolved_before
        self.prev_xzh, self.prev_cov, self.P, self.last_dead = prev_xzh, prev_cov, P, dr
        self.records.append(rec)
        return rec

    def _joint_update(self, obs, log, k, fused_method):
        """``--kalman joint``: the look's new features augmented at the prior pose, then
        the used pairs' observations in one update of the joint state (model.joint); every
        feature's mean and covariance written back to the symbolic model.  Returns the
        pose (a PoseEstimate of method "fused" where a fix was used, else the prior's) and
        its (x, z, heading) covariance."""
        joint, model = self.joint, self.model
        # --consider: the observations' camera-axes covariances under the measured errors
        # (the pose is in the joint state: no camera term)
        honest = (_measured_camera_covariances(obs, self.config, self.lines)
                  if joint.consider else None)
        new = log["new"]
        joint.add_many([(vid, obs[i].q, obs[i].cov) for vid, i in new],
                       None if honest is None else [honest[i] for _, i in new])
        used = [(vid, i) for vid, i in log["pairs"] if vid in model.vertices and vid in joint]
        joint.update([(vid, obs[i].q, obs[i].cov) for vid, i in used], self.config.joint_gate,
                     None if honest is None else [honest[i] for _, i in used])
        joint.drop([vid for vid in joint.ids if vid not in model.vertices])
        means, covs, considered = joint.marginals()
        for j, vid in enumerate(joint.ids):
            v = model.vertices[vid]
            v.mean, v.cov = means[j], covs[j]
            if considered is not None:
                # reported and scored; never gated with
                v.report_cov = considered[j]
        for vid, _ in [*log["pairs"], *log["new"]]:
            v = model.vertices.get(vid)
            if v is None or v.truth is None:
                continue
            err = float(np.linalg.norm(v.mean - v.truth))
            if v.first_look == k:
                self.history[vid] = [err]
            else:
                self.history.setdefault(vid, []).append(err)
        method = "given" if k == 0 else ("fused" if fused_method == "fused" else "prior")
        return joint.pose_estimate(method), joint.pose_cov

    def _resolve(self, look, edges, prior):
        """``--ambiguity-gate resolve``: Chapter III's cure for the picket fence, "resolve
        ambiguities by the relative geometric position".  Each ambiguous edge's other
        whole disparities (:func:`model.edges.alternative_disparities`) are candidate 3-D
        points; at the prior pose (``prior``: the odometry's (x, z, heading) and
        covariance; None at the start) the candidate the model predicts (inside
        :func:`model.matching.gated_distances`'s gate, the least distance over the edge's
        vertices) replaces the rig's.  Where the model predicts none, a candidate that
        agrees with one of the last look's unresolved candidates (the same corner seen
        from two places: only the true period stays put as the robot moves) may start a
        feature; an edge agreeing with neither starts none (model5's track rule) and its
        candidates are remembered for the next look.  Returns (ids of the vertices that
        start no feature, the unresolved edges' candidate vertices)."""
        from .matching import gated_distances
        config, cam = self.config, self.config.camera
        d_range = _ambiguity_disparities(config)
        step = float(np.median(np.diff(self.lines))) if len(self.lines) > 1 else 1.0
        no_new: set[int] = set()
        unresolved: list = []
        if prior is not None:
            prior_xzh, P = prior
            prior_R = _rotation(prior_xzh[2], config.camera_pitch_deg)
            prior_left = left_centre((prior_xzh[0], 0.0, prior_xzh[1]), prior_R)
            cov6 = _cov6(P)
        for e in edges:
            offsets = [0, *alternative_disparities(look.left_bi, look.right_bi, e, d_range)]
            variants = {}
            for off in offsets:
                vs = [shifted_vertex(v, off, cam, e_d=E_D + step / 2,
                                     e_col=config.column_error_px) if off else v
                      for v in e.vertices]
                vs = [v for v in vs if v is not None and v.q[0] <= config.max_range_ft]
                if vs:
                    variants[off] = vs
            chosen = None
            if prior is not None and variants:
                for store in (self.model, self.pending):
                    best = (np.inf, None)
                    for off, vs in variants.items():
                        d2 = gated_distances(store, vs, prior_left, prior_R, cov6, rows=self.rows)
                        if d2.min() < best[0]:
                            best = (float(d2.min()), off)
                        if off == 0 and np.isfinite(best[0]):
                            break          # the rig's own period agrees with the model: kept
                    if best[1] is not None:
                        chosen = best[1]
                        break
            if chosen is not None:
                self.resolved += chosen != 0
                e.vertices[:] = variants[chosen]
                if store is self.model:
                    # matched to the model or nothing: letting the edge's unmatched end start
                    # a feature (measured) pulled the bundled walk's pose to 0.40 ft
                    no_new.update(id(v) for v in e.vertices)
            else:
                no_new.update(id(v) for v in e.vertices)
                unresolved.extend(v for vs in variants.values() for v in vs)
        return no_new, unresolved

    def _remember_unresolved(self, candidates, est: PoseEstimate) -> None:
        """The unresolved edges' candidate points in room axes (A-23, A-30), kept one look."""
        self.pending = SymbolicModel()
        if not candidates:
            return
        q = np.array([v.q for v in candidates])
        z = est.transform(q)
        Rm = measurement_covariance_a30(est.M, np.array([v.cov for v in candidates]))
        if est.method != "given":
            Rm = measurement_covariance_a29(est.M, np.array([v.cov for v in candidates]),
                                            est.pose_covariance_at(q))
        for i, v in enumerate(candidates):
            self.pending.add_vertex(z[i], Rm[i], v.kind, v.grey, len(self.records))


ODOMETRY_GATE_CHI2 = 16.27     # 99.9 %, 3 degrees of freedom
MIN_POS_SIGMA_FT = 0.1         # the prior is never surer than this for gating ...
MIN_ROT_SIGMA_DEG = 1.0        # ... and this


def _predict(prev_xzh, P, dr_prev, dr_now, config: WalkConfig):
    """The prior pose and its covariance: the last pose moved by the odometry's
    step; the step's noise (a share of the distance, degrees per turn) and the
    heading's uncertainty carried into position by the usual linearisation."""
    xzh, F, Q = _odometry_step(prev_xzh, dr_prev, dr_now, config)
    return xzh, F @ P @ F.T + Q


def _odometry_step(prev_xzh, dr_prev, dr_now, config: WalkConfig):
    """The odometry's step composed on the last pose: (the new pose, the Jacobian F of
    the step w.r.t. the last (x, z, heading rad), the process noise G Q G^T)."""
    xzh, step_ft, turn = compose_step(prev_xzh, dr_prev, dr_now)
    h = np.radians(xzh[2])
    F = np.array([[1.0, 0.0, step_ft * np.cos(h)], [0.0, 1.0, -step_ft * np.sin(h)], [0, 0, 1.0]])
    G = np.array([[np.sin(h), 0.0], [np.cos(h), 0.0], [0.0, 1.0]])
    sd = config.odometry_distance_fraction * step_ft
    st = np.radians(config.odometry_turn_deg) if turn > 0 else 0.0
    Q = np.diag([sd ** 2 + 0.01 ** 2, st ** 2 + np.radians(0.1) ** 2])
    return xzh, F, G @ Q @ G.T


def _cov6(P) -> np.ndarray:
    """6x6 (position, rotation vector) gating covariance from the (x, z, heading) one."""
    pos = max(P[0, 0], P[1, 1], MIN_POS_SIGMA_FT ** 2)
    rot = max(P[2, 2], np.radians(MIN_ROT_SIGMA_DEG) ** 2)
    return np.diag([pos, MIN_POS_SIGMA_FT ** 2, pos, np.radians(MIN_ROT_SIGMA_DEG) ** 2, rot,
                    np.radians(MIN_ROT_SIGMA_DEG) ** 2])


def _fuse(fix: PoseEstimate, prior_xzh, P):
    """The fix combined with the odometry's prior (x, z, heading) by their
    covariances — the text's "combining multiple sensor inputs ... stochastically"
    (Appendix A, after A-29).  A fix outside the prior's 99.9 % region is not
    used (its matches are taken to be wrong): returns the reason instead."""
    z = np.array([fix.centre[0], fix.centre[2], np.radians(fix.heading_deg)])
    m = np.array([prior_xzh[0], prior_xzh[1], np.radians(prior_xzh[2])])
    d = z - m
    d[2] = np.radians(wrap_deg(np.degrees(d[2])))
    C = fix.xz_heading_covariance()
    if C is None:
        C = np.diag([MIN_POS_SIGMA_FT ** 2] * 2 + [np.radians(MIN_ROT_SIGMA_DEG) ** 2])
    Pg = np.diag(np.diag(_cov6(P))[[0, 2, 4]])
    m2 = float(d @ np.linalg.solve(Pg + C, d))
    if m2 > ODOMETRY_GATE_CHI2:
        return (f"{fix.method} fix disagrees with the odometry's prior by {np.hypot(d[0], d[1]):.2f} "
                f"ft and {np.degrees(abs(d[2])):.1f} deg (chi-square {m2:.0f}); prior kept")
    K = P @ np.linalg.inv(P + C)
    post = m + K @ d
    P_post = (np.eye(3) - K) @ P
    P_post = (P_post + P_post.T) / 2
    # the fix's own tilt (pitch, roll) is kept; its heading and floor position are the fused ones
    turn = np.degrees(post[2]) - fix.heading_deg
    R = _rotation(turn) @ fix.R
    U, _, Vt = np.linalg.svd(R)
    R = U @ Vt                                   # a48's axes are not orthonormal: the nearest rotation
    centre = np.array([post[0], fix.centre[1], post[1]])
    at = [0, 2, 4]                               # x, z, heading (rotation about room Y)
    if fix.covariance6 is not None:
        # the fix's 6x6 conditioned on the prior's (x, z, heading): writing P_post into the
        # block and keeping the fix's cross terms made an indefinite matrix (negative
        # variances in A-29's camera term, measured in docs/model.md)
        C6 = fix.covariance6
        A = C6[:, at]
        cov6 = C6 - A @ np.linalg.solve(C6[np.ix_(at, at)] + P, A.T)
        cov6 = (cov6 + cov6.T) / 2
    else:
        cov6 = np.zeros((6, 6))
        if fix.Cc is not None:
            cov6[:3, :3] = fix.Cc[:3, :3]
        cov6[np.ix_(at, at)] = P_post
    est = PoseEstimate("fused", left_centre(centre, R), axes_matrix(R), fix.inliers,
                       covariance6=cov6)
    return est, P_post


def floored_pose(est: PoseEstimate, position_ft: float, heading_deg: float,
                 height_ft: float = 0.0, tilt_deg: float = 0.0) -> PoseEstimate:
    """The pose with its 6x6 covariance raised, where smaller, to ``position_ft`` on
    the floor (x, z), ``heading_deg`` about the vertical, ``height_ft`` in y and
    ``tilt_deg`` about each horizontal room axis: a diagonal added, so it stays a
    covariance and never shrinks."""
    import dataclasses
    cov6 = np.zeros((6, 6)) if est.covariance6 is None else est.covariance6
    tilt = np.radians(tilt_deg) ** 2
    floor = np.array([position_ft ** 2, height_ft ** 2, position_ft ** 2, tilt,
                      np.radians(heading_deg) ** 2, tilt])
    cov6 = cov6 + np.diag(np.maximum(floor - np.diag(cov6), 0.0))
    return dataclasses.replace(est, covariance6=cov6, Cc=None)


def _measured_covariances(obs, est: PoseEstimate, config: WalkConfig, lines,
                          given: bool = False) -> np.ndarray:
    """The observations' covariances in room axes under the MEASURED errors: the
    calibrated column bound (model.edges.CALIBRATED_COLUMN_ERROR_PX), the measured
    disparity and row bounds (MEASURED_DISPARITY_ERROR_PX, MEASURED_ROW_ERROR_PX) and A-29's camera
    term with the measured pose floor (MEASURED_POSE_SIGMA_FLOOR, or the walk's own
    ``pose_sigma_floor``); ``given``: the start, whose pose is known (no camera term).
    For the consider covariance."""
    if not obs:
        return np.zeros((0, 3, 3))
    cq = _measured_camera_covariances(obs, config, lines)
    if given:
        return measurement_covariance_a30(est.M, cq)
    q = np.array([o.q for o in obs])
    camera = floored_pose(est, *(config.pose_sigma_floor or MEASURED_POSE_SIGMA_FLOOR),
                          *(config.tilt_floor or (0.0, 0.0)))
    return measurement_covariance_a29(est.M, cq, camera.pose_covariance_at(q))


def _measured_camera_covariances(obs, config: WalkConfig, lines) -> np.ndarray:
    """The observations' camera-axes (A-19/A-20) covariances under the measured bounds:
    the calibrated column error, the measured disparity and row errors (N, 3, 3)."""
    if not obs:
        return np.zeros((0, 3, 3))
    step = float(np.median(np.diff(lines))) if len(lines) > 1 else 1.0
    cq = []
    for o in obs:
        # the row bound: the measured one at every 2nd line, scaled with the line spacing
        located = locate(o.col, o.row, o.disparity, config.camera,
                         e_d=MEASURED_ROW_ERROR_PX * (0.5 + step / 2) / 1.5,
                         e_col=max(config.column_error_px, CALIBRATED_COLUMN_ERROR_PX),
                         e_disp=MEASURED_DISPARITY_ERROR_PX)
        cq.append(o.cov if located is None else located[1])
    return np.array(cq)


def _retire_unseen(model, pairs, est: PoseEstimate, look: int, rows, config: WalkConfig) -> None:
    """Count a miss for every vertex the fixed pose predicts well inside the view that
    no observation matched (the evidence of ``confirm`` too); with ``retire_unseen``,
    retire those missed that many times per look seen."""
    from .matching import in_view
    ids, means, _, _, _ = model.vertex_arrays()
    if not len(ids):
        return
    near = np.linalg.norm(means - est.left, axis=1) <= config.max_range_ft
    inside = in_view(means, est.left, est.R, rows[0], rows[1], margin=-8.0) & near
    matched = {vid for vid, _ in pairs}
    for vid in ids[inside]:
        v = model.vertices[int(vid)]
        if int(vid) in matched or v.first_look == look:
            continue
        v.missed += 1
        if config.retire_unseen is not None and v.missed >= config.retire_unseen * v.looks:
            model.retire(int(vid))


def _wrong(model, pairs, obs_truth) -> int:
    n = 0
    for vid, i in pairs:
        t = model.vertices[vid].truth
        if t is None or np.linalg.norm(obs_truth[i] - t) > WRONG_MATCH_FT:
            n += 1
    return n


def _update_model(model, edges, obs, pairs, pairs_used, est: PoseEstimate, kalman: str,
                  look: int, obs_truth, obs_truth_id, history, surfaces=(), pose_floor=None,
                  honest=None, consider: str | None = None,
                  feature_gate: float | None = None, no_new=frozenset(),
                  joint_log: dict | None = None) -> int:
    """Kalman-update the vertices the driving pose kept, add the observations
    no model vertex claimed, link boundary lines.  Returns how many were added.
    ``pose_floor`` (ft, degrees): the least sigma of the pose's floor position
    and heading in A-29's camera term.  ``honest`` (N,3,3): the observations'
    measured covariances, for the ``consider`` covariance (``WalkConfig``);
    ``feature_gate``: the chi-square bound of the feature gate (``WalkConfig``).
    ``joint_log`` (``kalman`` "joint"): no feature is moved here; the pairs to fuse
    and the new vertices (vertex id, observation index) are listed in it for
    :class:`model.joint.JointFilter`, which updates them all."""
    if not obs:
        return 0
    q = np.array([o.q for o in obs])
    Cq = np.array([o.cov for o in obs])
    z = est.transform(q)
    Rm = measurement_covariance_a30(est.M, Cq)
    if kalman in ("a29", "ci", "joint"):
        camera = est if pose_floor is None else floored_pose(est, *pose_floor)
        Rm = measurement_covariance_a29(est.M, Cq, camera.pose_covariance_at(q))
    claimed = {i for _, i in pairs}
    vertex_of: dict[int, int] = {}
    for vid, i in pairs_used:
        v = model.vertices[vid]
        # the innovation against what the feature and the observation claim (their
        # consider covariances where kept): the feature gate's test, the variance factor's
        # and confirmation's evidence
        # (joint: the filter's own, so --consider leaves which pairs are fused unchanged)
        nis = normalised_innovation(v.mean, v.cov if v.report_cov is None or joint_log is not None
                                    else v.report_cov, z[i], Rm[i] if honest is None else honest[i])
        if feature_gate is not None:
            # far outside, the pair is a wrong merge
            if nis > feature_gate:
                v.contradicted += 1
                claimed.discard(i)                 # the observation starts its own feature
                if v.contradicted >= max(2, v.looks):
                    model.retire(vid)
                continue
        if consider is not None:
            K = kalman_gain(v.cov, Rm[i])
            v.report_cov = consider_update(K, v.report_cov, honest[i],
                                           correlated=consider == "bound")
        if kalman == "joint":
            joint_log["pairs"].append((vid, i))
        elif kalman == "ci":
            m, P = covariance_intersection(v.mean, v.cov, z[i], Rm[i])
            v.mean, v.cov = m[0], P[0]
        else:
            v.mean, v.cov = static_update(v.mean, v.cov, z[i], Rm[i])
        v.nis.append(nis)
        v.looks += 1
        v.last_look = look
        v.shape = obs[i].shape
        vertex_of[i] = vid
        if v.truth is not None and joint_log is None:
            history.setdefault(vid, []).append(float(np.linalg.norm(v.mean - v.truth)))
    added = 0
    for i, o in enumerate(obs):
        if i in claimed or i in no_new:
            continue
        v = model.add_vertex(z[i], Rm[i], o.kind, o.grey, look)
        if honest is not None:
            v.report_cov = honest[i].copy()
        v.shape = o.shape
        v.truth = obs_truth[i].copy()
        v.truth_id = int(obs_truth_id[i])
        v.seen_at = (float(o.col), float(o.row), int(o.line), float(o.disparity))
        history[v.id] = [float(np.linalg.norm(v.mean - v.truth))]
        vertex_of[i] = v.id
        if joint_log is not None:
            joint_log["new"].append((v.id, i))
        added += 1
    # boundary lines: one per vertical edge, its ends the vertices just placed
    index = {id(o): i for i, o in enumerate(obs)}
    line_of: dict[int, int] = {}
    for n_edge, e in enumerate(edges):
        ends: list[int | None] = [None, None]
        for vo in e.vertices:
            i = _find_obs(obs, vo, index)
            if i is not None and i in vertex_of:
                ends[0 if vo.kind == "top" else 1] = vertex_of[i]
        known = [ln for vid in ends if vid is not None for ln in model.vertices[vid].lines]
        if known:
            line = model.lines[known[0]]
            line.looks += 1
            merged = list(line.ends)
            for slot in (0, 1):
                if merged[slot] is None and ends[slot] is not None:
                    merged[slot] = ends[slot]
                    model.vertices[ends[slot]].lines.append(line.id)
            line.ends = tuple(merged)
            model.refresh_line(line)
            line_of[n_edge] = line.id
        elif any(vid is not None for vid in ends):
            c = est.transform(e.centre[None])[0]
            C = measurement_covariance_a30(est.M, e.centre_cov)
            pts = np.array([model.vertices[vid].mean if vid is not None else c for vid in ends])
            line = model.add_line(c, C, ends, pts, e.grey)
            model.refresh_line(line)
            line_of[n_edge] = line.id
    _update_surfaces(model, surfaces, line_of, est)
    return added


def _update_surfaces(model, surfaces, line_of, est: PoseEstimate) -> None:
    """Chapter III surfaces: a feature interval between two known boundary lines.
    Its centre follows its lines; the normal is horizontal, across the two
    lines, facing the camera; the grey extremes widen with each look."""
    for so in surfaces:
        a, b = line_of.get(so.left_edge), line_of.get(so.right_edge)
        if a is None or b is None or a == b:
            continue
        la, lb = model.lines[a], model.lines[b]
        known = [sid for sid, srf in model.surfaces.items() if set(srf.lines[:2]) == {a, b}]
        centre = (la.centre + lb.centre) / 2
        along = lb.centre - la.centre
        normal = np.array([along[2], 0.0, -along[0]])
        n = np.linalg.norm(normal)
        normal = normal / n if n > 0 else np.array([0.0, 0.0, -1.0])
        if normal @ (est.left - centre) < 0:
            normal = -normal
        if known:
            srf = model.surfaces[known[0]]
            srf.centre, srf.normal = centre, normal
            srf.grey_extremes = (min(srf.grey_extremes[0], so.grey_extremes[0]),
                                 max(srf.grey_extremes[1], so.grey_extremes[1]))
            continue
        from .symbolic import Surface
        sid = len(model.surfaces)
        model.surfaces[sid] = Surface(sid, centre, normal, so.grey_extremes, [a, b])
        la.surface = lb.surface = sid
        la.next_line = b


def _find_obs(obs, vo, index):
    i = index.get(id(vo))
    if i is not None:
        return i
    for j, o in enumerate(obs):
        if o.edge == vo.edge and o.kind == vo.kind:
            return j
    return None
