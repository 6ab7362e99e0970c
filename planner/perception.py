"""The closed loop's perception step, until the symbolic model takes it over:
one stereo scan of a look turned into room points for the volumetric model.

The rig's LCSL gives each located edge in the left camera's axes (x right,
y down, z forward).  Its dx, dy are measured from pixel 60 (QUIRKS E6, kept in
the rig); here the direction is taken from the match's own picture position
instead — column ``loc1`` (1-based) and line ``IY`` at their pixel centres
against the principal point (64, 60) of the 128x120 picture, focal 180 px —
and scaled by LCSL's range dp.  A pose (the prior / dead-reckoned estimate)
carries the points into room coordinates: ``p_room = R @ p_cam + c_left``.

:func:`filter_points` keeps what the dissertation trusts: ranges up to 15 ft
("for ranges of 15 feet or less" the estimates were "fairly accurate", Ch. V)
and error bounds within a fraction of the range, from 2.5 ft on.  :func:`surface_spans` joins
consecutive edges of one scan line at the same range within their error
bounds: the surface between two boundary lines (Chapter IV: occupied where
"the surfaces between their boundary lines are").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from world.pose import BASELINE_FT

FOCAL_128 = 180.0
CX_128, CY_128 = 64.0, 60.0
MAX_RANGE_FT = 12.0
MIN_RANGE_FT = 2.5


@dataclass
class RoomPoints:
    xyz: np.ndarray          # (N, 3) room coordinates
    cov: np.ndarray          # (N, 3, 3) room-frame covariance (A-20 rotated)
    line: np.ndarray         # (N,) scan line
    loc1: np.ndarray         # (N,) left column (1-based)
    origin: np.ndarray       # (3,) left camera centre in the room


def camera_points(points) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(xyz_cam (N,3), cov_cam (N,3,3), line, loc1, ep) from rig.scan Points."""
    n = len(points)
    line = np.array([p.line for p in points], int).reshape(n)
    loc1 = np.array([p.loc1 for p in points], float).reshape(n)
    dp = np.array([p.dp for p in points], float).reshape(n)
    ep = np.array([p.ep for p in points], float).reshape(n)
    ex = np.array([p.ex for p in points], float).reshape(n)
    ey = np.array([p.ey for p in points], float).reshape(n)
    x = (loc1 - 0.5 - CX_128) * dp / FOCAL_128
    y = (line + 0.5 - CY_128) * dp / FOCAL_128
    xyz = np.stack([x, y, dp], -1)
    # the bounds are two standard deviations, (range, x, y) -> (x, y, z)
    cov = np.zeros((n, 3, 3))
    cov[:, 0, 0] = (ex / 2) ** 2
    cov[:, 1, 1] = (ey / 2) ** 2
    cov[:, 2, 2] = (ep / 2) ** 2
    return xyz, cov, line, loc1, ep


def filter_points(xyz_cam, ep, max_range: float = MAX_RANGE_FT, max_rel_error: float = 0.25,
                  min_range: float = MIN_RANGE_FT):
    """Mask of points worth modelling: within range, bounded error.  Nearer than
    ``min_range`` (a disparity above 54 px) the 1985 matcher's locations are
    mostly false matches (a repeated false match at 2.3 ft stands in front of
    the bundled lab's start); the vehicle never needs them, as it only drives into
    space seen free from farther away."""
    z = xyz_cam[:, 2]
    return (z >= min_range) & (z <= max_range) & (ep <= max_rel_error * z)


def vertical_support(xyz_cam, ep, line, max_line_gap: int = 8, tol_ft: float = 0.15):
    """Mask of points with a partner on another scan line at most
    ``max_line_gap`` lines away whose position agrees across (x) within
    ``tol_ft`` and in range within both error bounds: a vertical edge (the
    dissertation's boundary lines) shows on line after line, while a false
    match rarely repeats at the same place."""
    n = len(xyz_cam)
    if n == 0:
        return np.zeros(0, bool)
    dl = np.abs(line[:, None] - line[None, :])
    dx = np.abs(xyz_cam[:, None, 0] - xyz_cam[None, :, 0])
    dz = np.abs(xyz_cam[:, None, 2] - xyz_cam[None, :, 2])
    tol_z = np.maximum(ep[:, None] + ep[None, :], tol_ft)
    ok = (dl > 0) & (dl <= max_line_gap) & (dx <= tol_ft) & (dz <= tol_z)
    return ok.any(1)


def to_room(xyz_cam, cov_cam, R, left_centre):
    """Camera points and covariances into room coordinates."""
    R = np.asarray(R, float)
    xyz = xyz_cam @ R.T + np.asarray(left_centre, float)
    cov = R @ cov_cam @ R.T
    return xyz, cov


def surface_spans(xyz_cam, ep, line, loc1, max_gap_ft: float = 3.0):
    """Pairs (a, b) of point indices: neighbours along one scan line (in left
    column order) whose ranges agree within their summed error bounds (and at
    least 5 % of the range) and that are at most ``max_gap_ft`` apart."""
    pairs = []
    for y in np.unique(line):
        idx = np.flatnonzero(line == y)
        idx = idx[np.argsort(loc1[idx], kind="stable")]
        for a, b in zip(idx[:-1], idx[1:]):
            za, zb = xyz_cam[a, 2], xyz_cam[b, 2]
            tol = max(ep[a] + ep[b], 0.05 * min(za, zb))
            if abs(za - zb) <= tol and np.linalg.norm(xyz_cam[a] - xyz_cam[b]) <= max_gap_ft:
                pairs.append((int(a), int(b)))
    return pairs


def look_to_room(points, R, left_centre, max_range: float = MAX_RANGE_FT, vertical: bool = True):
    """rig.scan Points of one look -> (RoomPoints kept, surface span pairs)."""
    xyz_c, cov_c, line, loc1, ep = camera_points(points)
    keep = filter_points(xyz_c, ep, max_range)
    xyz_c, cov_c, line, loc1, ep = xyz_c[keep], cov_c[keep], line[keep], loc1[keep], ep[keep]
    if vertical:
        keep = vertical_support(xyz_c, ep, line)
        xyz_c, cov_c, line, loc1, ep = xyz_c[keep], cov_c[keep], line[keep], loc1[keep], ep[keep]
    spans = surface_spans(xyz_c, ep, line, loc1)
    xyz, cov = to_room(xyz_c, cov_c, R, left_centre)
    return RoomPoints(xyz, cov, line, loc1, np.asarray(left_centre, float)), spans


@dataclass
class FloorScan:
    """One look projected onto the floor plane (Chapter VI's projection over
    the vehicle's height band), as a range per picture column."""
    origin: np.ndarray       # (3,) left camera centre in the room
    hits: np.ndarray         # (H, 3) nearest located point of each column that has one
    hit_cov: np.ndarray      # (H, 3, 3)
    free_ends: np.ndarray    # (F, 3) ends of the free sight lines of the columns between
    spans: list              # index pairs into hits: one surface between two boundary lines
    assumed: np.ndarray | None = None   # (F,) bool: free end carved by the blank-column
                                        # assumption (``blank_ft``), not bounded by hits
    hit_cols: np.ndarray | None = None  # (H,) picture column (1-based) of each hit
    free_cols: np.ndarray | None = None # (F,) picture column (1-based) of each free end
    far_ends: np.ndarray | None = None  # (K, 3) under ``blank_px``: the free ends of the side
                                        # columns it cut off (more than ``blank_px`` beside the
                                        # outermost located one), not in ``free_ends``
    far_cols: np.ndarray | None = None  # (K,) their picture columns (1-based)
    hit_start: np.ndarray | None = None  # under ``low_y``: (H,) the horizontal distance from
                                         # which each hit's sight line runs low enough to
                                         # prove the band free (inf: nowhere)
    free_start: np.ndarray | None = None  # (F,) the same for each free end (its bounding hits')
    far_start: np.ndarray | None = None   # (K,) the same for each far end
    hit_short: np.ndarray | None = None   # under ``low_y``: (H,) each hit's error bound (LCSL's
                                          # two-sigma ep) in horizontal feet along its line:
                                          # its line proves the band no nearer than that to it
    hit_drop: np.ndarray | None = None    # under ``low_y``: (H,) how far below the camera
                                          # (ft) the lowest supported point of each hit's
                                          # column lies (``Perception.refute_hits``)
    hit_xyz: np.ndarray | None = None     # (H, 3) the located point each hit stands on, in
                                          # the room (3-D, before the floor projection)
    hit_range: np.ndarray | None = None   # (H,) its range (LCSL's dp, along the camera's axis)


CARVE = ("range", "error")
PLACES = ("axis", "point")
BLANK_LIMITS = ("all", "sides")   # where floor_scan's blank_px applies
SIGHT_LINES = ("band", "low", "low-all")   # what a sight line frees (floor_scan's low_y;
                                           # "low-all": its blind_low too)


def low_start(points_room, origin, low_y: float) -> np.ndarray:
    """The horizontal distance from ``origin`` (a camera centre, room Y down)
    at which the ray to each of ``points_room`` has dropped to room Y
    ``low_y`` (the top of the lowest obstacle the vehicle must not meet):
    from there on an obstacle that tall standing on the ray's floor track
    would cross the ray, so a ray that reached its point proves the band
    free; nearer, such an obstacle could stand under the ray unseen.  A ray
    level or rising never gets there (inf)."""
    p = np.asarray(points_room, float).reshape(-1, 3)
    o = np.asarray(origin, float)
    drop = p[:, 1] - o[1]
    run = np.hypot(p[:, 0] - o[0], p[:, 2] - o[2])
    need = float(low_y) - o[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(drop > 0, need * run / np.where(drop > 0, drop, 1.0), np.inf)
    return np.where(need <= 0, 0.0, out)


def stereo_depth(cols) -> np.ndarray:
    """The nearest depth (ft, along the camera axis) at which a point in left
    picture column ``cols`` (1-based, 128 px wide) is also in the right
    camera's picture: its right column ``c - f B / z`` must be a picture
    column (at least 1), so ``z >= f B / (c - 1)``; inf for column 1."""
    c = np.asarray(cols, float) - 1.0
    with np.errstate(divide="ignore"):
        return np.where(c > 0, FOCAL_128 * BASELINE_FT / np.maximum(c, 1e-12), np.inf)


def floor_scan(points, R, left_centre, band, max_range: float = MAX_RANGE_FT,
               max_gap_px: int = 32, min_votes: int = 2, blank_ft: float | None = None,
               carve: str = "range", blank_alone: bool = True, place: str = "axis",
               blank_px: int | None = None, blank_limit: str = "all",
               low_y: float | None = None, blind_low: bool = False,
               stereo_margin: bool = False, min_range: float = MIN_RANGE_FT) -> FloorScan:
    """The look as a floor range scan: for every picture column the NEAREST
    range that at least ``min_votes`` of its located points (in the height
    band) agree on within their error bounds — a vertical boundary line shows
    on line after line at one range, a false match seldom twice; the nearest,
    because the camera looks over low boxes at the wall behind them — moved to
    the camera's height; between two such
    columns at most ``max_gap_px`` apart, the columns between are free up to
    the nearer of the two (the surface between two boundary lines, or a gap
    whose far side is not seen); two neighbours at one range are joined by a
    surface span.

    ``carve`` says how far the columns with no range of their own are free:
    ``"range"`` up to the range of the bounding column (or ``blank_ft``);
    ``"error"`` (a named option) only up to the near end of that range's
    error bound (LCSL's two-sigma ``ep``): a located edge may lie up to its
    bound farther than the surface it bounds, and a blank face between two
    such edges, carved to their range, is carved into.

    ``blank_alone=False`` (a named option) applies ``blank_ft`` only to a look
    that located something: a look that located nothing at all may face a
    blank surface nearer than anything (or nearer than the lowest obstacle
    shows), and carving its whole view to ``blank_ft`` carves through it.

    ``blank_px`` (a named option) keeps the blank-column assumption beside
    what the look located: only columns at most ``blank_px`` columns from
    the nearest located column (beside the outermost ones, or inside a gap
    wider than ``max_gap_px``) are carved by it.  A located edge bounds only
    the surfaces it belongs to; a blank run far from any located column may
    be a box whose own edges the look did not locate, nearer than the edge
    that bounds the run (room 45: a box 4.5 ft away, 20-60 columns beside
    an edge at 7.6 ft, carved through).  A look that located nothing is
    governed by ``blank_alone`` alone.

    ``blank_limit`` says where ``blank_px`` applies: ``"all"`` (the default)
    both beside the outermost located columns and inside a wide gap;
    ``"sides"`` (a named option) only beside the outermost ones (toward the
    picture's edges), and a gap wider than ``max_gap_px`` between two located
    columns is carved whole as without ``blank_px`` (a blank run bounded on
    both sides; room 45's carving came from the sides).

    The side columns that ``blank_px`` cuts off (more than ``blank_px``
    beside the outermost located column, out to the picture's edge) are
    returned apart, in ``FloorScan.far_ends`` / ``far_cols``, at the reach
    they would have had: a caller may carve them on more evidence
    (:class:`TwoLookSides`).

    ``place`` says where a column's range is put on the floor plane:
    ``"axis"`` (the default) along the column's ray through the picture's
    centre line, at depth ``range`` in the camera's axes, then moved to the
    camera's height — for a pitched camera (the drive's looks 25 deg down)
    that lays the range along the tilted optical axis, so its horizontal
    distance is short by up to the pitch's cosine (oracle eyes: the hits a
    median 0.5 ft, up to 1.25 ft, in front of the true surface); ``"point"``
    (a named option) at the located point's own horizontal position, and the
    columns between and beside at the same horizontal distances (the forward
    one, ``range`` or ``blank_ft``, along the vehicle's horizontal heading:
    the same as ``"axis"`` for a level camera).

    ``low_y`` (a named option, ``DriveConfig.sight_lines="low"``; None: off)
    is the room Y of the lowest obstacle's top (the floor less
    ``lowest_obstacle_ft``).  A column's nearest point bounds the column only
    along its own ray: where the ray runs above ``low_y`` an obstacle lower
    than the ray may stand under it unseen (over a box lower than the camera
    the point is the wall above it: the 1985 eyes match along scan lines and
    do not locate the box's horizontal top edge).  So each hit gets
    ``hit_start``: the horizontal distance from which the ray of the lowest
    of its column's supported points at its horizontal distance (the
    steepest one that reached that surface) runs below ``low_y``
    (:func:`low_start`); the columns between two hits
    get the larger of the two, the blank columns beside the outermost hit
    (free ends and far ends) its own: the free sight lines prove the band
    only from there on, and a hit's own line ends ``hit_short`` before it
    (the near end of its error bound, as ``carve="error"`` ends the columns
    between: a low point on a box face may be located up to its bound behind
    the face).  A look that located nothing has no start (0),
    unless ``blind_low`` (``sight_lines="low-all"``): then its blank view is
    taken as a surface at ``blank_ft`` seen down to the band's bottom, and
    frees only where that surface's lowest ray would, from
    ``blank_ft * (low_y - camera Y) / (band bottom - camera Y)`` on (6.4 of
    8 ft for the drive's camera).

    ``stereo_margin`` (a named option, ``DriveConfig.stereo_margin``; with
    ``low_y``): a surface only the left camera sees cannot be located.  A
    point at depth z in left column c shows in the right picture d = f B / z
    columns further left (f = 180 px, B = 0.75 ft), so in the leftmost
    columns everything nearer than ``f B / (c - 1)`` (:func:`stereo_depth`)
    is out of the right camera's view and a box there shows no edge however
    plain its outline: column 20 proves nothing nearer than 7.1 ft, column
    54 nothing nearer than 2.5 ft.  Each free column (between edges or blank)
    then frees its line only from that depth on (its ``free_start`` raised to
    it; a column whose start passes its end frees nothing).  Room 177: box 1
    at the left edge of looks 3 and 5, 3.4-5 ft away, its faces blank, its
    corner edges out of the right camera's view, carved free by the
    blank-column assumption; the vehicle drove into it.

    ``min_range`` (:func:`filter_points`): located points nearer than this are
    left out (the loop passes ``DriveConfig.min_range_ft``: 3 ft since 2026-12-05,
    where a third of the 1985 matcher's points lie in front of the truth)."""
    if carve not in CARVE:
        raise ValueError(f"carve must be one of {CARVE}, not {carve!r}")
    if place not in PLACES:
        raise ValueError(f"place must be one of {PLACES}, not {place!r}")
    if blank_limit not in BLANK_LIMITS:
        raise ValueError(f"blank_limit must be one of {BLANK_LIMITS}, not {blank_limit!r}")
    R = np.asarray(R, float)
    origin = np.asarray(left_centre, float)
    xyz_c, cov_c, line, loc1, ep = camera_points(points)
    keep = filter_points(xyz_c, ep, max_range, min_range=min_range)
    room = xyz_c @ R.T + origin
    keep &= (room[:, 1] >= band[0]) & (room[:, 1] <= band[1])
    xyz_c, cov_c, loc1, ep = xyz_c[keep], cov_c[keep], np.rint(loc1[keep]).astype(int), ep[keep]
    line, room = line[keep], room[keep]
    empty = np.zeros((0, 3))
    if not len(xyz_c) and not blank_ft:
        return FloorScan(origin, empty, np.zeros((0, 3, 3)), empty, [], np.zeros(0, bool))
    cols_all = np.unique(loc1)
    cols, near, lowest = [], [], []
    for c in cols_all:
        idx = np.flatnonzero(loc1 == c)
        z = xyz_c[idx, 2]
        tol = np.maximum(ep[idx], 0.05 * z)
        votes = (np.abs(z[:, None] - z[None, :]) <= tol[:, None]).sum(1)
        supported = np.flatnonzero(votes >= min_votes)
        if not len(supported):
            continue
        cols.append(c)
        k = supported[np.argmin(z[supported])]
        near.append(idx[k])
        # the lowest line of the column's supported points as far away on the floor (a
        # vertical edge's points lie at one horizontal distance; their ranges along the
        # pitched axis grow downward): the steepest ray that reached the surface
        hd = np.hypot(room[idx, 0] - origin[0], room[idx, 2] - origin[2])
        same = supported[np.abs(hd[supported] - hd[k]) <= tol[k]]
        lowest.append(idx[same[np.argmax(line[idx[same]])]])
    if not cols and (not blank_ft or not blank_alone):
        return FloorScan(origin, empty, np.zeros((0, 3, 3)), empty, [], np.zeros(0, bool))
    cols, near = np.array(cols, int), np.array(near, int)
    rng = xyz_c[near, 2]
    start = low_start(room[np.array(lowest, int)], origin, low_y) if low_y is not None \
        and len(cols) else np.zeros(len(cols))
    # how far a column bounded by this one is free
    reach = rng if carve == "range" else np.maximum(rng - ep[near], 0.0)

    if place == "axis":
        def to_room(col, z):
            x = (col - 0.5 - CX_128) * z / FOCAL_128
            p = np.stack([x, np.zeros_like(z), z], -1) @ R.T + origin
            p[:, 1] = origin[1]
            return p
        hits = to_room(cols.astype(float), rng)
    else:
        # the horizontal axes of the camera: forward and right, levelled
        fwd = np.array([R[0, 2], 0.0, R[2, 2]])
        fwd /= max(np.linalg.norm(fwd), 1e-12)
        right = np.array([fwd[2], 0.0, -fwd[0]])
        if right @ R[:, 0] < 0:
            right = -right

        def to_room(col, d):
            # at forward distance d along the column's levelled bearing
            x = (col - 0.5 - CX_128) * d / FOCAL_128
            p = origin + d[:, None] * fwd[None] + x[:, None] * right[None]
            p[:, 1] = origin[1]
            return p
        hits = xyz_c[near] @ R.T + origin
        hits[:, 1] = origin[1]
        ahead = (hits - origin) @ fwd
        reach = reach * ahead / np.maximum(rng, 1e-12)       # in forward feet, as the hit
    hit_cov = R @ cov_c[near] @ R.T
    free_cols, free_rng, spans, assumed, far, free_st = [], [], [], [], [], []
    far_ends = far_cols = None
    gap_px = 128 if blank_ft else max_gap_px
    for k in range(len(cols) - 1):
        a, b = cols[k], cols[k + 1]
        if b - a > 1 and b - a <= gap_px:
            between = np.arange(a + 1, b)
            wide = b - a > max_gap_px
            if wide and blank_px is not None and blank_limit == "all":
                # by assumption only near the two edges
                between = between[np.minimum(between - a, b - between) <= blank_px]
            free_cols.append(between)
            free_rng.append(np.full(len(between), min(reach[k], reach[k + 1])))
            free_st.append(np.full(len(between), max(start[k], start[k + 1])))
            # a gap wider than max_gap_px is free only by the blank-column assumption
            assumed.append(np.full(len(between), wide))
            far.append(np.zeros(len(between), bool))
        if b - a <= max_gap_px:
            tol = max(ep[near[k]] + ep[near[k + 1]], 0.05 * min(rng[k], rng[k + 1]))
            if abs(rng[k] - rng[k + 1]) <= tol:
                spans.append((k, k + 1))
    if blank_ft:
        # outside the outermost columns that show something: free up to
        # blank_ft, or up to the outermost hit's range if nearer (an
        # assumption, off by default: a blank wall shows nothing either, and
        # a box face wider than the picture too)
        lo_c = cols[0] if len(cols) else 129
        hi_c = cols[-1] if len(cols) else 0
        sides = (np.arange(1, lo_c), np.arange(hi_c + 1, 129)) if len(cols) else \
            (np.arange(1, 129),)                      # (not the whole view twice)
        edges = (reach[0], reach[-1]) if len(cols) else (blank_ft,)
        starts = (start[0], start[-1]) if len(cols) else \
            (float(blank_ft) * (low_y - origin[1]) / (band[1] - origin[1])
             if low_y is not None and blind_low else 0.0,)
        side_far = [np.zeros(len(s), bool) for s in sides]
        if len(cols) and blank_px is not None:
            side_far = [sides[0] < lo_c - blank_px, sides[1] > hi_c + blank_px]
        for side, edge_r, is_far, st in zip(sides, edges, side_far, starts):
            if len(side):
                free_cols.append(side)
                free_st.append(np.full(len(side), st))
                free_rng.append(np.full(len(side), min(float(blank_ft), float(edge_r))))
                assumed.append(np.ones(len(side), bool))
                far.append(is_far)
    if free_cols:
        fcols = np.concatenate(free_cols).astype(int)
        free_ends = to_room(fcols.astype(float), np.concatenate(free_rng))
        assumed = np.concatenate(assumed)
        far = np.concatenate(far)
        fstart = np.concatenate(free_st)
        if stereo_margin and low_y is not None:
            # nearer than the right camera's view of the column: not seen by both
            zmin = stereo_depth(fcols)
            seen_from = to_room(fcols.astype(float), np.minimum(zmin, 1e6))
            fstart = np.maximum(fstart, np.where(np.isfinite(zmin), np.hypot(
                seen_from[:, 0] - origin[0], seen_from[:, 2] - origin[2]), np.inf))
        far_start = None
        if blank_px is not None and len(cols):
            far_ends, far_cols, far_start = free_ends[far], fcols[far], fstart[far]
            free_ends, assumed, fcols = free_ends[~far], assumed[~far], fcols[~far]
            fstart = fstart[~far]
    else:
        free_ends, assumed, fcols = empty, np.zeros(0, bool), np.zeros(0, int)
        fstart, far_start = np.zeros(0), None
    located = dict(hit_xyz=room[near] if len(cols) else empty,
                   hit_range=rng if len(cols) else np.zeros(0))
    if low_y is None:
        return FloorScan(origin, hits, hit_cov, free_ends, spans, assumed, cols, fcols,
                         far_ends, far_cols, **located)
    return FloorScan(origin, hits, hit_cov, free_ends, spans, assumed, cols, fcols,
                     far_ends, far_cols, start, fstart,
                     far_start if far_ends is not None else None,
                     ep[near] * np.hypot(hits[:, 0] - origin[0], hits[:, 2] - origin[2])
                     / np.maximum(rng, 1e-12),
                     room[np.array(lowest, int), 1] - origin[1] if len(cols) else np.zeros(0),
                     **located)


BLANK_SIDES = ("cut", "two-looks")   # what becomes of the side columns blank_px cuts off


class TwoLookSides:
    """The far side columns of a look (``FloorScan.far_ends``: more
    than ``blank_px`` beside the outermost located edge, toward the picture's
    edge) carve a cell only when two looks from poses at least ``apart_ft``
    apart, or turned at least ``apart_deg`` from each other, both had it in
    such a blank column.  An assumption of this project, not the
    dissertation's: one look's blank side may be a box face running out of
    the picture whose edges that look did not locate (room 45, seeds 41-60);
    a second viewpoint brings the face's edges to other columns, or into the
    picture, and one located there stops the carving (a hit ends every
    assumed line before it).  Not proof: a face no look ever locates stays
    blank from everywhere.

    ``confirm(keys, pose)`` takes the packed keys of the cells this look's far
    sides would carve (:func:`planner.octree.assumed_free_keys`: unknown, not
    past a hit) and the look's (x, z, heading deg); it returns the keys a
    look far enough from this one had already held back, and holds back the
    others under this look's pose (the first look's pose is kept)."""

    def __init__(self, apart_ft: float = 1.0, apart_deg: float = 20.0):
        if not (apart_ft > 0 and apart_deg > 0):
            raise ValueError(f"two looks apart by a positive distance and turn, "
                             f"not {apart_ft!r} ft, {apart_deg!r} deg")
        self.apart_ft = float(apart_ft)
        self.apart_deg = float(apart_deg)
        self.first: dict[int, tuple[float, float, float]] = {}   # key -> first look's pose
        self.confirmed = 0

    def apart(self, a, b) -> bool:
        turn = abs((a[2] - b[2] + 180.0) % 360.0 - 180.0)
        return math.hypot(a[0] - b[0], a[1] - b[1]) >= self.apart_ft or turn >= self.apart_deg

    def confirm(self, keys, pose) -> np.ndarray:
        pose = tuple(float(v) for v in pose)
        out = []
        for k in np.asarray(keys, np.int64).tolist():
            seen = self.first.get(k)
            if seen is None:
                self.first[k] = pose
            elif self.apart(seen, pose):
                out.append(k)
                del self.first[k]
        self.confirmed += len(out)
        return np.array(out, np.int64)


class BearingsApart:
    """Cells a look would prove held back until a look from another bearing proves
    them too: ``confirm(keys, centres, origin)`` takes the packed keys of the cells
    (their (N, 2) floor centres x, z) and the camera's floor position; it returns
    the keys an earlier look had held back from a bearing at least ``apart_deg``
    away from this one's (each cell's bearing from the camera), and holds the
    others back under this look's position (the first look's is kept).
    ``wall_runs="flat-foot"`` (not 1985): a box face of a flat floor's grey, seen
    head on against a wall of that grey, looks like the wall; from another bearing
    its box shows a side of another grey, whose edges the eyes locate and whose
    run ends there."""

    def __init__(self, apart_deg: float = 20.0):
        if not apart_deg > 0:
            raise ValueError(f"two bearings apart by a positive angle, not {apart_deg!r} deg")
        self.apart_deg = float(apart_deg)
        self.first: dict[int, tuple[float, float]] = {}    # key -> first camera position
        self.confirmed = 0

    def confirm(self, keys, centres, origin) -> np.ndarray:
        keys = np.asarray(keys, np.int64)
        centres = np.asarray(centres, float).reshape(-1, 2)
        ox, oz = (float(v) for v in origin)
        out = []
        for k, (cx, cz) in zip(keys.tolist(), centres.tolist()):
            seen = self.first.get(k)
            if seen is None:
                self.first[k] = (ox, oz)
                continue
            now = math.atan2(cx - ox, cz - oz)
            then = math.atan2(cx - seen[0], cz - seen[1])
            turn = abs((math.degrees(now - then) + 180.0) % 360.0 - 180.0)
            if turn >= self.apart_deg:
                out.append(k)
                del self.first[k]
        self.confirmed += len(out)
        return np.array(out, np.int64)
