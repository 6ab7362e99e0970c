"""Vertical edges grouped over consecutive scan lines, and their end points as
vertex observations (Chapter III, "Three Dimensional Models and Model
Updates"; Appendix A, A-6 to A-20).

The rig locates an edge on each epipolar line it scans (ESTAR's LCSL: one
point per matched edge, relative to the left camera).  A straight vertical
boundary of a box, a door or a poster shows up as a column of such points on
consecutive lines; this module chains them (same or neighbouring column,
disparity within one pixel) into one :class:`EdgeObservation` — the "straight
line approximation" of a boundary the symbolic model stores — and turns the
two ends of each edge into :class:`VertexObservation`\\ s, the features that
Chapter III says "can be located and characterized giving location and error
updates using camera relative data".  An end that reaches the first or last
scanned line is cut off by the picture, not a vertex, and is not reported.

Each vertex gets its camera-relative location by A-6 to A-8 and its error
bounds by A-13, A-17 and A-18 (left/right location errors 0.5 px as LCSL; the
vertical error is the half-pixel plus half the spacing of the scanned lines,
since the true corner lies between the last line that saw the edge and the
next one scanned), and the covariance of A-19/A-20 with the bounds as two
standard deviations, in (p, x, y) order.

Offsets are measured from the true picture centre (column 64, row 60 in
continuous 128x120 coordinates; a 1-based index ``k`` names the pixel whose
centre is ``k - 0.5``).  The 1985 LCSL measures from pixel 60 across
(QUIRKS E6), 4.5 pixels off, which would turn every look by 1.4 degrees;
the faithful scan output is left untouched and this module recomputes the
offsets from the indices.  Float64 here: the model is new work, not the 1985
arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

CENTRE_COL = 64.0      # continuous column of the picture centre (128 wide)
CENTRE_ROW = 60.0      # continuous row of the picture centre (120 high)
E_LR = 0.5             # ELMAX = ERMAX of LCSL, px
E_D = 0.5              # EDMAX of LCSL, px
# Measured, not assumed (bench/walk.py --calibrate): against the world's true corners the rig's
# vertex columns are off with a standard deviation of 0.99 px (bundled walk) and 0.96 px (ten
# generated rooms), nearly uniform over +-1.5 px, where LCSL's ELMAX = 0.5 px bound (two sigma)
# claims 0.25 px; the disparity's core is as LCSL assumes (68 % within 0.37-0.43 px against
# its 0.5 px sigma).  The calibrated column bound is two measured sigmas.
CALIBRATED_COLUMN_ERROR_PX = 2.0
# The measured 95.4 % points (bench/walk.py --calibrate), the two-sigma bounds of the consider
# covariance (model.kalman.consider_update): disparity 1.70 px on the bundled lab's loop once
# round (1.21 px twice round; LCSL's bound 1 px, the excess the tail of wrong stereo matches;
# the larger kept) and the end row 1.84 px (1.80 twice round; A-18 with half the line
# spacing: 1.5 px at every 2nd line)
MEASURED_DISPARITY_ERROR_PX = 1.7
MEASURED_ROW_ERROR_PX = 1.84


@dataclass(frozen=True)
class Camera:
    """The rig's characterisation (Appendix A, "Camera Characterization")."""
    ds: float = 0.75        # camera separation, ft
    dv: float = 180.0       # virtual image distance, px at 128 wide
    centre_col: float = CENTRE_COL
    centre_row: float = CENTRE_ROW


@dataclass(frozen=True)
class VertexObservation:
    """One end of a vertical edge as the rig sees it, relative to the left camera."""
    q: np.ndarray            # (p, x, y): range, right, down (ft)
    cov: np.ndarray          # A-20, (p, x, y) order
    kind: str                # "top" or "bottom"
    col: float               # continuous column of the end in the left picture
    row: float               # continuous row estimate of the end
    disparity: float         # mean disparity used for the range
    grey: tuple[int, int]    # grey level left and right of the edge (left picture)
    edge: int                # index of its EdgeObservation in the look
    line: int = -1           # the scanned line at that end (the last one that saw the edge)
    shape: tuple | None = None   # Appendix B 16x16 rectangular map of the corner (left picture)


@dataclass(frozen=True)
class EdgeObservation:
    """A vertical edge: the located points of consecutive lines, chained."""
    lines: tuple[int, ...]           # scanned lines it appears on
    cols: tuple[float, ...]          # continuous column per line
    disparities: tuple[float, ...]   # mean disparity per line
    centre: np.ndarray               # (p, x, y) of its middle
    centre_cov: np.ndarray
    grey: tuple[int, int]
    top_clipped: bool
    bottom_clipped: bool
    vertices: list = field(default_factory=list)    # VertexObservation(s)
    ends: tuple = ()                 # (line, QV feature k, "L"/"R") of its located points


@dataclass(frozen=True)
class SurfaceObservation:
    """A QV feature interval bounded left and right by two vertical edges on
    several lines: a surface of Chapter III seen in one look."""
    left_edge: int                   # index of the EdgeObservation on its left
    right_edge: int
    lines: tuple[int, ...]
    grey_extremes: tuple[int, int]   # darkest and lightest grey inside (left picture)
    centre: np.ndarray               # (p, x, y): middle of the two edges' centres


def locate(col: float, row: float, disparity: float, camera: Camera, e_d: float = E_D,
           e_col: float = E_LR, e_disp: float | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """A-6..A-8 and A-13, A-17, A-18 in float64, offsets from the picture centre:
    ``(q, C)`` with C of A-20, or None when the disparity is not above the
    disparity error (1 px), as LCSL refuses.

    ``e_col`` is the column's location bound in A-17 (as written LCSL's
    ELMAX, 0.5 px; the named alternative :data:`CALIBRATED_COLUMN_ERROR_PX`
    is the measured one).  The disparity bound of A-13 is LCSL's (1 px); ``e_disp``
    replaces it in the covariance only (the consider covariance's measured bound),
    None where the disparity is not above it."""
    e = 2 * E_LR
    if disparity <= e:
        return None
    if e_disp is not None:
        if disparity <= e_disp:
            return None
        e = e_disp
    dl = col - camera.centre_col
    dd = row - camera.centre_row
    dp = camera.ds * camera.dv / disparity
    dx = dl * dp / camera.dv
    dy = dd * dp / camera.dv
    ep = camera.ds * camera.dv * e / (disparity ** 2 - disparity * e)
    ex = (abs(dl) * ep + dp * e_col + ep * e_col) / camera.dv
    ey = (abs(dd) * ep + dp * e_d + ep * e_d) / camera.dv
    return np.array([dp, dx, dy]), np.diag([(ep / 2) ** 2, (ex / 2) ** 2, (ey / 2) ** 2])


def group_vertical_edges(points, lines, left_picture=None, camera: Camera = Camera(),
                         min_lines: int = 4, max_gap: int = 2,
                         require_corner: bool = True, right_picture=None,
                         grey_check: int | None = 2,
                         column_error: float = E_LR) -> list[EdgeObservation]:
    """Chain the rig's located points (``rig.scan.Point``) into vertical edges.

    Two points join when they are on the same scanned line or on scanned lines
    at most ``max_gap + 1`` positions apart, their columns differ by at most
    1.5 px, their disparities by at most 1 px, and the grey level steps the
    same way across them (dark to light or light to dark, in the left
    picture; a checkerboard's column of edges splits at every corner).

    With ``require_corner`` an end counts as a vertex only where the picture
    agrees that the boundary ends there: two rows beyond it the left picture no
    longer shows the same grey step.  Where the rig merely lost the edge (a
    line it could not match) the end is not a corner and is not reported.

    With a ``right_picture`` and ``grey_check``, a located point is kept only
    if the grey levels two pixels either side of it agree (within
    ``grey_check``) between the left picture at LOC1 and the right picture at
    LOC2: a wrong stereo match of the rig (MASL paired two different edges)
    usually fails this, and would otherwise enter the model at a wrong range.  Chains covering fewer than
    ``min_lines`` scanned lines are dropped.  ``lines`` is the set of lines
    that were scanned (their spacing sets the vertical uncertainty of a
    vertex).  ``column_error`` is the column bound passed to :func:`locate`."""
    lines = sorted(set(int(y) for y in lines))
    if not lines or not points:
        return []
    pos = {y: k for k, y in enumerate(lines)}
    step = float(np.median(np.diff(lines))) if len(lines) > 1 else 1.0
    pts = [p for p in points if p.line in pos and p.disparity > 1]
    if right_picture is not None and left_picture is not None and grey_check is not None and pts:
        keep = _stereo_agrees(left_picture, right_picture, pts, grey_check)
        pts = [p for p, k in zip(pts, keep) if k]
    n = len(pts)
    col = np.array([p.loc1 - 0.5 for p in pts])
    disp = np.array([float(p.disparity) for p in pts])
    k = np.array([pos[p.line] for p in pts], dtype=np.int64)
    sign = _step_signs(left_picture, [p.line for p in pts], col)
    pairs_i, pairs_j = [np.arange(n)], [np.arange(n)]
    by_k: dict[int, np.ndarray] = {}
    for kk in np.unique(k):
        by_k[int(kk)] = np.flatnonzero(k == kk)
    for kk, here in by_k.items():
        for dk in range(0, max_gap + 2):
            there = by_k.get(kk - dk)
            if there is None:
                continue
            near = ((np.abs(col[here][:, None] - col[there][None, :]) <= 1.5)
                    & (np.abs(disp[here][:, None] - disp[there][None, :]) <= 1)
                    & (sign[here][:, None] == sign[there][None, :]))
            a, b = np.nonzero(near)
            pairs_i.append(here[a])
            pairs_j.append(there[b])
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    i_all, j_all = np.concatenate(pairs_i), np.concatenate(pairs_j)
    graph = coo_matrix((np.ones(len(i_all)), (i_all, j_all)), shape=(n, n))
    _, root = connected_components(graph, directed=False)
    root = root.astype(np.int64)
    # one row per (edge, scanned line): mean column and disparity of its points
    key, inv = np.unique(root * (len(lines) + 1) + k, return_inverse=True)
    cnt = np.bincount(inv)
    line_col = np.bincount(inv, col) / cnt
    line_disp = np.bincount(inv, disp) / cnt
    line_root, line_k = key // (len(lines) + 1), key % (len(lines) + 1)
    starts = np.flatnonzero(np.r_[True, line_root[1:] != line_root[:-1]])
    stops = np.r_[starts[1:], len(key)]
    out = []
    for a, b in zip(starts, stops):
        if b - a < min_lines:
            continue
        ks = line_k[a:b]
        cols, disps = line_col[a:b], line_disp[a:b]
        ys = tuple(lines[int(kk)] for kk in ks)
        grey = _greys(left_picture, ys, cols)
        centre = locate(float(cols.mean()), (ys[0] + ys[-1]) / 2 + 0.5,
                        float(disps.mean()), camera, e_d=E_D + (ys[-1] - ys[0]) / 2,
                        e_col=column_error)
        if centre is None:
            continue
        members = np.flatnonzero(root == line_root[a])
        ends = tuple((pts[i].line, pts[i].edge if pts[i].edge <= 50 else pts[i].edge - 50,
                      "L" if pts[i].edge <= 50 else "R") for i in members)
        edge = EdgeObservation(ys, tuple(cols.tolist()), tuple(disps.tolist()), centre[0],
                               centre[1], grey, top_clipped=bool(ks[0] == 0),
                               bottom_clipped=bool(ks[-1] == len(lines) - 1), ends=ends)
        for kind, end in (("top", slice(0, 3)), ("bottom", slice(-3, None))):
            if (edge.top_clipped if kind == "top" else edge.bottom_clipped):
                continue
            y_end = ys[0] if kind == "top" else ys[-1]
            # the corner lies between this line and the next scanned one outward
            row = y_end + 0.5 + (-step / 2 if kind == "top" else step / 2)
            c_end, d_end = float(cols[end].mean()), float(disps[end].mean())
            if require_corner and _continues(left_picture, y_end, c_end,
                                             -1 if kind == "top" else 1, grey):
                continue
            located = locate(c_end, row, d_end, camera, e_d=E_D + step / 2, e_col=column_error)
            if located is None:
                continue
            edge.vertices.append(VertexObservation(located[0], located[1], kind, c_end, row,
                                                   d_end, grey, len(out), y_end))
        out.append(edge)
    out.sort(key=lambda e: (np.mean(e.cols), e.lines[0]))
    for i, e in enumerate(out):
        e.vertices[:] = [VertexObservation(v.q, v.cov, v.kind, v.col, v.row, v.disparity,
                                           v.grey, i, v.line,
                                           corner_map(left_picture, v.col, v.row, v.kind, v.grey))
                         for v in e.vertices]
    return out


def _stereo_agrees(left, right, pts, tol) -> np.ndarray:
    L = np.asarray(left).astype(np.int64)
    Rp = np.asarray(right).astype(np.int64)
    h, w = L.shape
    r = np.clip(np.array([p.line for p in pts]), 0, h - 1)
    c1 = np.array([p.loc1 for p in pts], dtype=np.int64) - 1
    c2 = np.array([p.loc2 for p in pts], dtype=np.int64) - 1
    ok = np.ones(len(pts), bool)
    for d in (-2, 2):
        a = L[r, np.clip(c1 + d, 0, w - 1)]
        b = Rp[r, np.clip(c2 + d, 0, w - 1)]
        ok &= np.abs(a - b) <= tol
    return ok


def _continues(picture, y_end, col, direction, grey) -> bool:
    """Does the left picture still show the edge's grey step beyond its end?"""
    if picture is None:
        return False
    pic = np.asarray(picture).astype(np.int64)
    h, w = pic.shape
    c0 = int(np.floor(col))
    left_g, right_g = grey
    for d in (1, 2):
        y = y_end + direction * d
        if not 0 <= y < h:
            return False
        a = pic[y, min(max(c0 - 2, 0), w - 1)]
        b = pic[y, min(max(c0 + 2, 0), w - 1)]
        if abs(a - left_g) > 1 or abs(b - right_g) > 1:
            return False
    return True


def _step_signs(picture, rows, cols) -> np.ndarray:
    """+1 where the left picture gets lighter across the edge, -1 darker, 0 flat/unknown."""
    if picture is None or len(cols) == 0:
        return np.zeros(len(cols), dtype=np.int64)
    pic = np.asarray(picture).astype(np.int64)
    h, w = pic.shape
    r = np.clip(np.asarray(rows, dtype=np.int64), 0, h - 1)
    c0 = np.floor(np.asarray(cols)).astype(np.int64)
    a = pic[r, np.clip(c0 - 2, 0, w - 1)]
    b = pic[r, np.clip(c0 + 2, 0, w - 1)]
    return np.sign(b - a)


def _greys(picture, ys, cols) -> tuple[int, int]:
    """Median grey level two pixels left and right of the edge (left picture)."""
    if picture is None:
        return (-1, -1)
    pic = np.asarray(picture)
    h, w = pic.shape
    r = np.clip(np.asarray(ys, dtype=np.int64), 0, h - 1)
    c0 = np.floor(np.asarray(cols)).astype(np.int64)
    left = pic[r, np.clip(c0 - 2, 0, w - 1)]
    right = pic[r, np.clip(c0 + 2, 0, w - 1)]
    return int(np.median(left)), int(np.median(right))


def corner_map(picture, col: float, row: float, kind: str, grey) -> tuple | None:
    """The corner's shape as an Appendix B rectangular map (16 column words, bit 0
    the top row; ``model.bitmaps``): the 16x16 pixels of the left picture with the
    vertex at the middle of the top (a "top" vertex) or bottom row, set where the
    grey level is nearer the edge's right-side grey than its left-side one."""
    if picture is None or grey[0] < 0:
        return None
    pic = np.asarray(picture).astype(np.int64)
    h, w = pic.shape
    c0 = int(np.floor(col)) - 8
    r0 = int(np.floor(row)) if kind == "top" else int(np.floor(row)) - 16
    rr = np.clip(np.arange(r0, r0 + 16), 0, h - 1)
    cc = np.clip(np.arange(c0, c0 + 16), 0, w - 1)
    win = pic[np.ix_(rr, cc)]
    left_g, right_g = grey
    bits = np.abs(win - right_g) < np.abs(win - left_g)
    words = (bits.astype(np.int64) << np.arange(16)[:, None]).sum(axis=0)
    return tuple(int(x) for x in words)


def surface_observations(edges: list[EdgeObservation], left_picture=None,
                         min_lines: int = 3) -> list[SurfaceObservation]:
    """Surfaces: a QV feature whose left end lies on one vertical edge and its
    right end on another, on at least ``min_lines`` lines."""
    by_feature: dict[tuple[int, int], dict[str, int]] = {}
    for i, e in enumerate(edges):
        for line, k, side in e.ends:
            by_feature.setdefault((line, k), {})[side] = i
    pairs: dict[tuple[int, int], list[int]] = {}
    for (line, _), sides in by_feature.items():
        if "L" in sides and "R" in sides and sides["L"] != sides["R"]:
            pairs.setdefault((sides["L"], sides["R"]), []).append(line)
    out = []
    pic = None if left_picture is None else np.asarray(left_picture)
    for (a, b), ls in sorted(pairs.items()):
        if len(ls) < min_lines:
            continue
        ls = sorted(ls)
        if pic is not None:
            # the pixels of the interval: from the one at its left end to the one at its right
            c0 = int(np.floor(min(np.mean(edges[a].cols), np.mean(edges[b].cols))))
            c1 = int(np.floor(max(np.mean(edges[a].cols), np.mean(edges[b].cols))))
            inside = pic[np.ix_(ls, range(max(c0, 0), min(c1, pic.shape[1] - 1) + 1))]
            grey = (int(inside.min()), int(inside.max()))
        else:
            grey = (-1, -1)
        out.append(SurfaceObservation(a, b, tuple(ls), grey,
                                      (edges[a].centre + edges[b].centre) / 2))
    return out


def vertex_observations(edges: list[EdgeObservation]) -> list[VertexObservation]:
    """All vertex observations of a look, edge by edge."""
    return [v for e in edges for v in e.vertices]


# the stereo ambiguity test's fixed rule (chosen before it was measured, not tuned): another
# disparity fits "as well" when its mean absolute grey difference over the edge's patch is
# within half a grey level (half of PRE's 4-bit step) of the rig's own disparity's; offsets of
# up to AMBIGUITY_SAME_PX from the rig's disparity are the same match
AMBIGUITY_MARGIN_GREY = 0.5
AMBIGUITY_SAME_PX = 2
AMBIGUITY_HALF_WIDTH_PX = 3


def stereo_ambiguity(left, right, edge: EdgeObservation, disparity_range: tuple[float, float],
                     half_width: int = AMBIGUITY_HALF_WIDTH_PX,
                     same_px: int = AMBIGUITY_SAME_PX) -> tuple[float, float, float] | None:
    """How uniquely the pair of pictures fixes an edge's disparity (the dissertation's "picket
    fence": a periodic texture — checks, stripes, binders — matches itself a whole period
    away, and MASL/MARF may take the wrong period, look after look).

    The left picture's patch of the edge (its scanned lines, ``half_width`` pixels either
    side of its column on each) is compared with the right picture's patch at every whole
    disparity in ``disparity_range`` (px; each line offset from its own disparity), by the
    mean absolute grey difference.  Returns (difference at the rig's disparity, the best
    difference at a disparity more than ``same_px`` away, that disparity), or None when no
    other disparity fits inside the picture."""
    profile = _disparity_profile(left, right, edge, disparity_range, half_width)
    if profile is None:
        return None
    offsets, diff = profile
    d0 = int(np.rint(np.median(edge.disparities)))
    own = np.abs(offsets) <= 1
    other = np.abs(offsets) > same_px
    if not own.any() or not np.isfinite(diff[own]).any() or not np.isfinite(diff[other]).any():
        return None
    j = int(np.flatnonzero(other)[np.argmin(diff[other])])
    return float(diff[own].min()), float(diff[j]), float(d0 + offsets[j])


def is_ambiguous(score, margin: float = AMBIGUITY_MARGIN_GREY) -> bool:
    """A :func:`stereo_ambiguity` score: another disparity fits within ``margin`` grey levels
    of the rig's own."""
    return score is not None and score[1] <= score[0] + margin


def alternative_disparities(left, right, edge: EdgeObservation,
                            disparity_range: tuple[float, float],
                            margin: float = AMBIGUITY_MARGIN_GREY,
                            half_width: int = AMBIGUITY_HALF_WIDTH_PX,
                            same_px: int = AMBIGUITY_SAME_PX) -> list[int]:
    """The whole-pixel offsets from an edge's disparity at which the right picture's patch
    fits the left's within ``margin`` grey levels of the rig's own fit (the "picket
    fence"'s other periods, :func:`stereo_ambiguity`'s profile): each run of such offsets
    more than ``same_px`` from the rig's gives its best one, nearest first.  Each is a
    candidate 3-D point for the edge (Chapter III: the model's relative geometry chooses).
    Empty when the edge is not ambiguous."""
    profile = _disparity_profile(left, right, edge, disparity_range, half_width)
    if profile is None:
        return []
    offsets, diff = profile
    own = np.abs(offsets) <= 1
    if not own.any() or not np.isfinite(diff[own]).any():
        return []
    fits = (np.abs(offsets) > same_px) & (diff <= diff[own].min() + margin)
    out = []
    for run in np.split(np.flatnonzero(fits), np.flatnonzero(np.diff(np.flatnonzero(fits)) > 1) + 1):
        if run.size:
            out.append(int(offsets[run[np.argmin(diff[run])]]))
    return sorted(out, key=abs)


def _disparity_profile(left, right, edge: EdgeObservation, disparity_range, half_width):
    """(offsets from the edge's median whole disparity, mean absolute grey difference at
    each; inf where the patch leaves the picture), or None (as :func:`stereo_ambiguity`)."""
    L = np.asarray(left, dtype=np.int64)
    Rp = np.asarray(right, dtype=np.int64)
    h, w = L.shape
    ys = np.clip(np.asarray(edge.lines, dtype=np.int64), 0, h - 1)
    c = np.floor(np.asarray(edge.cols)).astype(np.int64)
    d = np.rint(np.asarray(edge.disparities)).astype(np.int64)
    d0 = int(np.rint(np.median(edge.disparities)))
    k = np.arange(-half_width, half_width + 1)
    lc = c[:, None] + k[None, :]
    if lc.min() < 0 or lc.max() >= w:
        return None
    patch = L[ys[:, None], lc]
    lo, hi = int(np.ceil(disparity_range[0])), int(np.floor(disparity_range[1]))
    offsets = np.arange(lo - d0, hi - d0 + 1)
    if offsets.size == 0:
        return None
    rc = lc[None, :, :] - d[None, :, None] - offsets[:, None, None]
    valid = (rc >= 0).all(axis=(1, 2)) & (rc < w).all(axis=(1, 2))
    diff = np.abs(Rp[ys[None, :, None], np.clip(rc, 0, w - 1)] - patch[None]).mean(axis=(1, 2))
    return offsets, np.where(valid, diff, np.inf)


def shifted_vertex(v: VertexObservation, offset: float, camera: Camera = Camera(),
                   e_d: float = E_D + 1.0, e_col: float = E_LR) -> VertexObservation | None:
    """The same picture corner located at ``offset`` more pixels of disparity (another period
    of a picket fence): A-6..A-20 again, or None where :func:`locate` refuses.  ``e_d``
    and ``e_col`` as :func:`group_vertical_edges` gave them (every 2nd line: E_D + 1)."""
    located = locate(v.col, v.row, v.disparity + offset, camera, e_d=e_d, e_col=e_col)
    if located is None:
        return None
    return VertexObservation(located[0], located[1], v.kind, v.col, v.row,
                             v.disparity + offset, v.grey, v.edge, v.line, v.shape)
