"""The camera estimate fixed against the floor plan's walls (``DriveConfig.pose="walls"``,
``rig drive --pose walls``; a named option, not 1985, not the default).

The loop already assumes the room's walls known as a floor plan (``known_walls``:
``Room.bounds`` = (x0, x1, z0, z1), an axis-aligned rectangle; Chapter IV's "the
environment ... partially known").  A look's located points that lie on those walls
say where the camera is: each such point, carried into the room by a pose (x, z,
heading), must land on its wall, so its signed perpendicular distance from the wall is
a measurement of the pose with expected value 0.  :func:`fix_against_walls` fuses
every point that passes a chi-square gate with the prior pose (the dead reckoning and
its covariance) by an iterated extended Kalman filter (Gauss-Newton with the prior as a
measurement): one wall seen fixes only the distance to it and the heading, two
perpendicular walls fix all three; what the walls do not constrain stays the prior's,
by the filter's own algebra.

Why here (``planner/``) and not in :mod:`model.pose` beside the Appendix A fixes:
those solve a 3-D camera pose from correspondences with the symbolic model's located
vertices (A-33 to A-50); this one needs no correspondence and no model, only the
planner's floor plan and the loop's (x, z, heading) state with the odometry's
covariance (:func:`vehicle.sim.odometry_covariance`), which is the planner's.

Points not on a wall (the boxes, false matches) must not pull the fix: each is tried
against its nearest wall only, gated at the chi-square 99 % point (1 degree of freedom)
of its residual under the point's covariance plus the pose's, and in any case no
farther than :data:`MAX_RESIDUAL_FT` from it (the generated rooms keep every box
1.8 ft from the walls, so a box face is never within that of a wall); the iterations
weigh the survivors by Huber's rule, and after the first solve every point is gated
again at the solution with the solution's (much smaller) covariance and the fix solved
again from the prior on the survivors.  Fewer than :data:`MIN_POINTS` survivors: no
fix (the prior returned unchanged).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from world.pose import BASELINE_FT, wrap_deg
from .perception import MIN_RANGE_FT

CHI2_1DOF_99 = 6.635          # chi-square 99 % point, 1 degree of freedom
MAX_RESIDUAL_FT = 0.9         # no point farther than this from its wall is on it (half the
                              # generated rooms' 1.8 ft box-to-wall gap)
MIN_POINTS = 5                # fewer survivors than this: no fix
HUBER_K = 1.345               # Huber's constant (95 % efficiency under Gaussian errors)
ITERATIONS = 8                # iterated EKF steps per solve (it converges in 2-3)
VOTE_FT = 0.15                # the consensus: a point agrees with a wall this near it
VOTE_STEP_DEG = 0.5           # the consensus's heading step
VOTE_SPAN_DEG = 20.0          # ... at most this far either side of the prior
FAR_SIGMAS = 3.0              # far_turn: a fix this far from the prior's heading is far
HEADING_SIGMAS = 2.0          # a fix's heading within this many of the prior's standard
                              # deviations (3 before 2026-12-05: room 684's floor-grey
                              # skirting turned it 4-6 deg, 2.4-3.3 sigma, look after look)
CORNER_FT = 0.5               # a point this near a second wall is left out (which one is it on?)
FLOOR_CLEAR_FT = 0.1          # depth pixels this near the floor plane are the floor


@dataclass
class WallFix:
    """The result of :func:`fix_against_walls`: the pose (x, z ft, heading deg), its
    (x, z, heading rad) covariance, the points used (a mask over the input) and
    whether there was a fix at all (False: the prior returned unchanged)."""
    x: float
    z: float
    heading_deg: float
    cov: np.ndarray
    used: np.ndarray
    fixed: bool
    walls: tuple = ()         # the walls the used points lie on ("x0", "x1", "z0", "z1")


def level_points(q_cam, cov_cam, pitch_deg: float):
    """Left-camera points (N, 3: x right, y down, z forward) and their covariances in the
    rig's LEVEL frame (the heading not yet applied), relative to the rig centre: the
    pitch (profile plus tilt, known exactly) turned out and the left camera's offset
    (half the baseline to the left) added.  Returns ((N, 3) points, (N, 3, 3) covs)."""
    c, s = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
    Rp = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])      # world.pose._rot_pitch
    q = np.asarray(q_cam, float).reshape(-1, 3) @ Rp.T
    q[:, 0] -= BASELINE_FT / 2
    C = Rp @ np.asarray(cov_cam, float).reshape(-1, 3, 3) @ Rp.T
    return q, C


def _place(state, a, b):
    """Room (x, z) of level-frame horizontal offsets (a right, b forward) placed at
    ``state`` (x, z, heading rad)."""
    x, z, h = state
    ch, sh = math.cos(h), math.sin(h)
    return x + ch * a + sh * b, z - sh * a + ch * b      # world.pose._rot_heading


def _residuals(state, a, b, bounds):
    """For level-frame horizontal offsets (a right, b forward) placed at ``state`` (x, z,
    heading rad): room (x, z), each point's nearest wall (0..3: x0, x1, z0, z1), its
    signed residual (room coordinate less the wall's) and the wall's normal axis."""
    px, pz = _place(state, a, b)
    x0, x1, z0, z1 = bounds
    r = np.stack([px - x0, px - x1, pz - z0, pz - z1], 1)
    wall = np.argmin(np.abs(r), 1)
    res = r[np.arange(len(a)), wall]
    return px, pz, wall, res, np.sort(np.abs(r), 1)[:, 1]


def _jacobian(state, a, b, wall):
    """d residual / d (x, z, heading rad) per point: (N, 3)."""
    h = state[2]
    ch, sh = math.cos(h), math.sin(h)
    on_x = wall < 2
    H = np.zeros((len(a), 3))
    H[on_x, 0] = 1.0
    H[~on_x, 1] = 1.0
    H[on_x, 2] = (-sh * a + ch * b)[on_x]          # d px / dh
    H[~on_x, 2] = (-ch * a - sh * b)[~on_x]        # d pz / dh
    return H


def _point_var(state, C, wall):
    """Each residual's variance from its point's own error: the level-frame covariance
    turned by the heading, along the wall's normal."""
    h = state[2]
    ch, sh = math.cos(h), math.sin(h)
    nx = np.where(wall < 2, 1.0, 0.0)
    nz = 1.0 - nx
    # the normal in the level frame: n_level = Rh^T n_room (x, z components)
    na = nx * ch - nz * sh
    nb = nx * sh + nz * ch
    return na * na * C[:, 0, 0] + 2 * na * nb * C[:, 0, 2] + nb * nb * C[:, 2, 2]


def _gate(state, P, a, b, C, bounds, gate: float, max_residual: float):
    """The points that pass at ``state`` with pose covariance ``P``: (mask, wall)."""
    _, _, wall, res, second = _residuals(state, a, b, bounds)
    H = _jacobian(state, a, b, wall)
    S = np.einsum("ni,ij,nj->n", H, P, H) + _point_var(state, C, wall)
    ok = (res * res <= gate * np.maximum(S, 1e-12)) & (np.abs(res) <= max_residual) & \
        (second > CORNER_FT)
    return ok, wall


def _window(P, max_residual: float, heading_sigmas: float = HEADING_SIGMAS):
    """How far from the prior (x, z ft, heading rad) the consensus looks, and so how far a
    fix may lie: 3 sigma of the prior, x and z at most ``max_residual`` (never farther
    than a point may be from its wall: a box face stands twice that from the wall it
    faces), the heading ``heading_sigmas`` sigma, at most :data:`VOTE_SPAN_DEG`."""
    sd = np.sqrt(np.maximum(np.diag(P), 0.0))
    return (min(3 * sd[0], max_residual), min(3 * sd[1], max_residual),
            min(heading_sigmas * sd[2], math.radians(VOTE_SPAN_DEG)))


def _mode(values, tol: float):
    """The value with the most others within ``tol`` of it, and that count (0, None
    when there are none)."""
    if len(values) == 0:
        return None, 0
    v = np.sort(values)
    n = np.searchsorted(v, v + tol, "right") - np.searchsorted(v, v - tol, "left")
    k = int(np.argmax(n))
    return float(v[k]), int(n[k])


def consensus(prior, P, a, b, bounds, max_residual: float = MAX_RESIDUAL_FT,
              tol: float = VOTE_FT, min_votes: int = MIN_POINTS,
              heading_sigmas: float = HEADING_SIGMAS):
    """Where to start the association: the pose (x, z, heading rad) most points agree
    lie on the walls.  For each heading within ``heading_sigmas`` sigma of the prior (at
    most :data:`VOTE_SPAN_DEG`, steps of :data:`VOTE_STEP_DEG`) each point votes for the x that
    would put it on either side wall and the z on either end wall; within 3 sigma of the
    prior's x (z), at most ``max_residual``, the value with the most votes within ``tol``
    wins, if it has ``min_votes`` (else the prior's x or z stands, and its votes do not
    count); the heading whose two winners gather the most votes wins (the nearest the
    prior's on a tie).  Why: at the prior, with the
    heading off several degrees, the points of one wall near a corner are nearer the
    other wall, and the nearest-wall association pulls the fix into a false minimum
    (measured: the tiny room under five times the default noise).  Returns (state,
    votes)."""
    x0, x1, z0, z1 = bounds
    wx, wz, span = _window(P, max_residual, heading_sigmas)
    n = int(span // math.radians(VOTE_STEP_DEG))
    wx, wz = wx + tol, wz + tol
    best = (np.asarray(prior, float), -1)
    for k in sorted(range(-n, n + 1), key=abs):
        h = prior[2] + k * math.radians(VOTE_STEP_DEG)
        dx, dz = _place((0.0, 0.0, h), a, b)
        vx = np.concatenate([x0 - dx, x1 - dx])
        vz = np.concatenate([z0 - dz, z1 - dz])
        x, nx = _mode(vx[np.abs(vx - prior[0]) <= wx], tol)
        z, nz = _mode(vz[np.abs(vz - prior[1]) <= wz], tol)
        if nx < min_votes:
            x, nx = None, 0
        if nz < min_votes:
            z, nz = None, 0
        if nx + nz > best[1]:
            best = (np.array([prior[0] if x is None else x, prior[1] if z is None else z, h]),
                    nx + nz)
    return best


def _gain(P, H, Rv):
    """The Kalman gain ``P H^T (H P H^T + R)^-1`` for a diagonal ``R`` (variances
    ``Rv``), as ``(I + P H^T R^-1 H)^-1 P H^T R^-1``: a 3x3 solve instead of an N x N
    one, and still right for a singular ``P``."""
    PHt = P @ H.T / Rv                                   # P H^T R^-1, (3, N)
    return np.linalg.solve(np.eye(3) + PHt @ H, PHt)


def _solve(prior, P, a, b, C, bounds, wall, start=None):
    """The iterated EKF from ``prior`` (x, z, h rad) with covariance ``P`` on the points
    given, each on its wall ``wall``, linearised first at ``start`` (default: the
    prior); Huber weights on the residuals at each iterate.  Returns (state,
    covariance)."""
    s0 = np.asarray(prior, float)
    s = s0.copy() if start is None else np.asarray(start, float).copy()
    w = np.ones(len(a))
    wc = np.asarray(bounds, float)[wall]
    for _ in range(ITERATIONS):
        px, pz = _place(s, a, b)
        res = np.where(wall < 2, px, pz) - wc
        H = _jacobian(s, a, b, wall)
        Rv = np.maximum(_point_var(s, C, wall), 1e-8) / w
        K = _gain(P, H, Rv)
        s_new = s0 + K @ (-res - H @ (s0 - s))
        e = np.abs(res) / np.sqrt(np.maximum(_point_var(s, C, wall), 1e-8))
        w = np.minimum(1.0, HUBER_K / np.maximum(e, 1e-12))
        done = np.max(np.abs(s_new - s)) < 1e-7
        s = s_new
        if done:
            break
    H = _jacobian(s, a, b, wall)
    Rv = np.maximum(_point_var(s, C, wall), 1e-8) / w
    K = _gain(P, H, Rv)
    IKH = np.eye(3) - K @ H
    cov = IKH @ P @ IKH.T + (K * Rv) @ K.T                  # Joseph form: stays symmetric PSD
    return s, (cov + cov.T) / 2


def _within_prior(s, s0, P, max_residual: float,
                  heading_sigmas: float = HEADING_SIGMAS) -> bool:
    """Whether the fix ``s`` lies where the consensus looked: each of x, z within 3 sigma
    of the prior (at most ``max_residual``) plus :data:`VOTE_FT`, the heading within
    ``heading_sigmas`` sigma (at most :data:`VOTE_SPAN_DEG`) plus :data:`VOTE_STEP_DEG`.
    A fix beyond is the points' word against the prior's by more than the prior allows: a
    few false matches the gate took for a wall (measured: room 12, the 1985 eyes, a 14.6
    deg jump against a prior of 1.8 deg), so no fix."""
    wx, wz, wh = _window(P, max_residual, heading_sigmas)
    d = np.abs(np.asarray(s, float) - np.asarray(s0, float))
    d[2] = abs((d[2] + math.pi) % (2 * math.pi) - math.pi)
    return bool(d[0] <= wx + VOTE_FT and d[1] <= wz + VOTE_FT
                and d[2] <= wh + math.radians(VOTE_STEP_DEG))


def fix_against_walls(q_cam, cov_cam, prior, prior_cov, bounds, pitch_deg: float,
                      pan_deg: float = 0.0, gate: float = CHI2_1DOF_99,
                      max_residual: float = MAX_RESIDUAL_FT,
                      min_points: int = MIN_POINTS,
                      heading_sigmas: float = HEADING_SIGMAS) -> WallFix:
    """The body pose fused with one look's points on the floor plan's walls (the module
    docstring).

    ``q_cam`` (N, 3): points in the LEFT camera's axes (x right, y down, z forward, ft;
    :func:`planner.perception.camera_points`), ``cov_cam`` (N, 3, 3) their A-19/A-20
    covariances; ``prior`` (x, z, heading deg) the body's estimate, ``prior_cov`` its
    (x, z, heading rad) covariance; ``bounds`` (x0, x1, z0, z1) the walls; the rig is
    pitched ``pitch_deg`` (the profile's plus the head's tilt) and turned ``pan_deg``
    right of the body, about the vertical through the rig centre (both exact).

    The consensus looks, and the fix may lie, ``heading_sigmas`` of the prior's heading
    sigma round it (:data:`HEADING_SIGMAS`; x and z 3 sigma).

    Returns a :class:`WallFix`; with fewer than ``min_points`` points on the walls, or a
    singular problem, the prior unchanged (``fixed`` False)."""
    P = np.asarray(prior_cov, float).reshape(3, 3)
    x, z, hdeg = (float(v) for v in prior)
    none = WallFix(x, z, hdeg, P.copy(), np.zeros(len(np.atleast_2d(q_cam)), bool), False)
    q = np.asarray(q_cam, float).reshape(-1, 3)
    if len(q) < min_points or not np.all(np.isfinite(P)) or np.trace(P) <= 0:
        return none
    lev, C = level_points(q, cov_cam, pitch_deg)       # (_point_var reads its x, z part)
    a, b = lev[:, 0], lev[:, 2]
    s0 = np.array([x, z, math.radians(hdeg + pan_deg)])
    try:
        sc, votes = consensus(s0, P, a, b, bounds, max_residual, min_votes=min_points,
                              heading_sigmas=heading_sigmas)
        if votes < min_points:
            return none
        # gated at the consensus by its own resolution, the fix solved from the prior
        Pc = np.diag([VOTE_FT ** 2, VOTE_FT ** 2, math.radians(VOTE_STEP_DEG) ** 2])
        ok, wall = _gate(sc, Pc, a, b, C, bounds, gate, max_residual)
        if ok.sum() < min_points:
            return none
        s1, P1 = _solve(s0, P, a[ok], b[ok], C[ok], bounds, wall[ok], sc)
        # gated again at the first solution, by its own covariance: what only the
        # consensus's spread let through (a box face near a wall) drops out now
        ok, wall = _gate(s1, P1, a, b, C, bounds, gate, max_residual)
        if ok.sum() < min_points:
            return none
        s2, P2 = _solve(s0, P, a[ok], b[ok], C[ok], bounds, wall[ok], s1)
    except np.linalg.LinAlgError:
        return none
    if not np.all(np.isfinite(s2)) or not np.all(np.isfinite(P2)):
        return none
    if not _within_prior(s2, s0, P, max_residual, heading_sigmas):
        return none
    heading = (math.degrees(s2[2]) - pan_deg + 180.0) % 360.0 - 180.0
    names = tuple(n for k, n in enumerate(("x0", "x1", "z0", "z1")) if np.any(wall[ok] == k))
    return WallFix(float(s2[0]), float(s2[1]), heading, P2, ok, True, names)


def far_turn(fix: WallFix, prior_heading_deg: float, prior_cov, far_points: int,
             far_sigmas: float = FAR_SIGMAS):
    """How far (deg) the wall fix ``fix`` turns the prior's heading where that is more
    than ``far_sigmas`` (:data:`FAR_SIGMAS`) of the prior's standard deviation
    (``prior_cov`` (x, z, heading rad)) on fewer than ``far_points`` points; None
    otherwise (or no fix).
    ``DriveConfig.wall_fix_far`` (not 1985) takes such a fix only when a second look
    from elsewhere shows one turning it as far the same way.  The odometry's heading is
    honest (about one fix in a hundred lies 2.5 sigma off, as a normal law says), but
    the false fixes logged on seeds 1-76 and 451-531 turned it 3.1-4.1 sigma on 8-26
    points of one wall (docs/planner.md)."""
    if not fix.fixed or not far_points or int(fix.used.sum()) >= far_points:
        return None
    turn = wrap_deg(fix.heading_deg - prior_heading_deg)
    sd = math.degrees(math.sqrt(float(np.asarray(prior_cov, float).reshape(3, 3)[2, 2])))
    return turn if abs(turn) > far_sigmas * sd else None


def fix_in_windows(q_cam, cov_cam, prior, prior_cov, bounds, pitch_deg: float,
                   pan_deg: float, windows) -> WallFix:
    """:func:`fix_against_walls` with the heading windows ``windows`` (standard
    deviations of the prior's heading) tried in order: the first fix found, else the
    last try (``fixed`` False).  ``DriveConfig.wall_fix_first="base"`` (not 1985) tries
    the base window before the widened one: a consensus is the heading most points
    agree on anywhere in its window, so a wide window lets points that agree on a heading
    many sigmas off outvote the few true wall points near the prior (room 866: 75 points
    at 10 deg off against 10 on the far wall)."""
    for sigmas in windows:
        fix = fix_against_walls(q_cam, cov_cam, prior, prior_cov, bounds, pitch_deg, pan_deg,
                                heading_sigmas=sigmas)
        if fix.fixed:
            break
    return fix


def depth_wall_points(range_left, pitch_deg: float, floor_y: float, step: int = 4,
                      sigma_ft: float = 0.05):
    """Candidate wall points of the depth eyes (``Look.range_left``, the true range per
    pixel): every ``step``-th pixel each way whose point stands more than
    :data:`FLOOR_CLEAR_FT` above the floor plane (its height is exact: the camera's
    pitch is known and the range true; the floor would pass the gate beside every wall
    and pull the fix inward).  Not the rows above the tallest box: the rig looks down
    25 deg and the head tilts only down, so no pixel sees above the camera's own 3 ft
    and boxes stand up to 5 ft; the boxes' points are left to the gate.  Each point's
    covariance is ``sigma_ft`` each way (the truth has no error; this stands for the
    pixel's footprint and keeps a fix from claiming more than a few hundredths of a
    foot).  Returns ((N, 3) left-camera points, (N, 3, 3) covariances)."""
    from .depth_eyes import camera_points
    pts = camera_points(range_left)[::step, ::step].reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), 1) & (pts[:, 2] > 0)]
    c, s = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
    y_room = c * pts[:, 1] - s * pts[:, 2]          # the rig centre's y is 0 (world.pose)
    pts = pts[y_room < floor_y - FLOOR_CLEAR_FT]
    cov = np.broadcast_to(np.eye(3) * sigma_ft ** 2, (len(pts), 3, 3)).copy()
    return pts, cov


def rig_wall_points(points, min_range: float = MIN_RANGE_FT):
    """Candidate wall points of the rig's eyes: the located points of the look
    (:func:`planner.perception.camera_points`, their A-20 covariances) the
    dissertation trusts (:func:`planner.perception.filter_points`: ``min_range``, 2.5 ft
    unless given, to 12 ft, error bound within a quarter of the range).  Every height:
    the poster and door edges, the wall's foot and the room's corners are on walls, the
    box edges are left to the gate.  Returns ((N, 3), (N, 3, 3))."""
    from .perception import camera_points, filter_points
    if not len(points):
        return np.zeros((0, 3)), np.zeros((0, 3, 3))
    xyz, cov, _, _, ep = camera_points(points)
    keep = filter_points(xyz, ep, min_range=min_range)
    return xyz[keep], cov[keep]


def floor_end_points(picture, greys, pitch_deg: float, floor_y: float, step: int = 2,
                     min_sigma_ft: float = 0.03):
    """Candidate wall points of the floor in view (``DriveConfig.wall_points="floor-ends"``,
    not 1985): where each ``step``-th column's floor run ends inside the picture
    (:func:`planner.appearance.floor_run` on the greys ``greys``), the floor point at the
    run's top edge.  The floor ends at whatever stands on it, so beside a wall that point is
    the wall's foot: the edge-based eyes locate few points on blank walls, but the floor's end
    shows along all of them.  A box's foot is left to the gate (the generated rooms keep
    boxes 1.8 ft from the walls, twice :data:`MAX_RESIDUAL_FT`); a run up to the picture's
    top shows no end and is dropped here.  What it cannot tell: a surface of the floor's
    grey standing at the wall (a skirting, a wall of that grey) moves the run's end up it,
    and the point past the wall (room 276, docs/planner.md).

    A lone pixel of another grey in the run is bridged (the sensor noise moves single
    pixels).  The run's top row ``r`` (rows r - 1 .. 119 show the floor) ends at the pixel edge
    between rows r - 2 and r - 1 of the 128 x 120 picture; the point is that edge's ray
    met with the floor plane ``floor_y`` below the camera (the rig pitched ``pitch_deg``,
    exact).  Its covariance: half a row each way along the ray (the condensed picture
    averages 2 x 2 pixels, so the edge is known to a row), at least ``min_sigma_ft`` each
    way.  Returns ((N, 3) points in the left camera's axes, (N, 3, 3) covariances)."""
    from .appearance import CX, CY, FOCAL, ROWS, floor_run
    top = floor_run(picture, greys, bridge=True)
    cols = np.arange(0, top.shape[0], step)
    cols = cols[(top[cols] > 1) & (top[cols] < ROWS)]
    if not len(cols):
        return np.zeros((0, 3)), np.zeros((0, 3, 3))
    c, s = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
    px = (cols + 0.5 - CX) / FOCAL

    def on_floor(edge_row):
        py = (edge_row - CY) / FOCAL
        down = c * py - s * 1.0                    # the ray's level-frame y per unit z_cam
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(down > 1e-6, floor_y / down, np.nan)
        return np.stack([px * t, py * t, t], 1)

    edge = (top[cols] - 1).astype(float)
    p = on_floor(edge)
    lo, hi = on_floor(edge + 0.5), on_floor(edge - 0.5)
    keep = np.all(np.isfinite(p), 1) & np.all(np.isfinite(lo), 1) & np.all(np.isfinite(hi), 1)
    p, d = p[keep], (hi - lo)[keep]
    cov = np.einsum("ni,nj->nij", d, d) / 4.0 + np.eye(3)[None] * min_sigma_ft ** 2
    return p, cov
