"""Chapter IV, "Path and Trajectory Generation": the searches over the floor map.

* :func:`clearance_map` — the configuration space of the vehicle's cross
  section: a cell is passable when a disc of the vehicle's radius centred
  anywhere in it touches no blocked cell.  Unknown (and uncertain) cells are
  blocked or free as the caller states (``unknown="blocked"|"free"``).
* :func:`hierarchical_search` — **the dissertation's search**: "the search
  starts at the vehicle position and 'grows' empty space areas, giving priority
  to those voxels at the higher levels which (1) are nearer the goal, and (2)
  allow the vehicle cross section to pass freely along the volume toward the
  goal".  The passable map is decomposed into a quadtree (the floor map's
  hierarchy: uniform blocks merged level by level); growth is best-first over
  adjacent passable blocks, keyed by the distance from the block's edge to the
  goal (so bigger blocks nearer the goal come first); only blocks wholly
  passable are grown into, so the cross section passes anywhere in them.
  Waypoints are the midpoints of the shared sides of consecutive blocks.
* :func:`astar` — the baseline: A* over the same cells (8-connected, no
  corner cutting, octile heuristic), optimal on the grid.
* :func:`cross_section_test` — "once a path is found ... it is tested for
  minimum cross section to ensure the path can be traversed": the smallest
  clearance along the polyline, refused when below the vehicle's radius.

No path raises :class:`NoPath` naming what is in the way.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import cv2
import numpy as np

from .floormap import FloorMap
from .octree import OCCUPIED, UNCERTAIN, UNKNOWN

SQRT2 = math.sqrt(2.0)


class NoPath(Exception):
    """No path for the vehicle; the message says which part is blocked or unknown."""


@dataclass
class Passable:
    """The configuration space on a floor map."""
    ok: np.ndarray            # (nz, nx) bool: the vehicle's centre may be in this cell
    clearance: np.ndarray     # (nz, nx) float: lower bound, ft, from any point of the cell to a blocked cell
    blocked: np.ndarray       # (nz, nx) bool: blocked cells before growing (occupied [+ unknown])
    fmap: FloorMap
    radius: float
    unknown: str
    at: str = "anywhere"      # where in a passable cell the vehicle's centre may be (CLEARANCE_AT)
    narrow: np.ndarray | None = None   # (nz, nx) bool or None: cells a forward move may cross
                                       # with only the grown half width clear
                                       # (DriveConfig.passage, planner.passage)


CLEARANCE_AT = ("anywhere", "centre", "anywhere-exact")


def clearance_map(fm: FloorMap, radius: float, unknown: str = "blocked",
                  uncertain: str | None = None, at: str = "anywhere") -> Passable:
    """Grow the blocked cells by ``radius`` (the vehicle's cross section).  The
    map's border counts as blocked.  Uncertain cells follow ``unknown`` unless
    ``uncertain`` says otherwise; ``"core"``: only those within one standard
    deviation of an uncertain feature (``fm.uncertain_core``; all of them on a
    map without it) block.

    ``at="anywhere"`` (the dissertation's: the cross section passes anywhere in
    a passable block): a cell is passable when the distance from any point of
    it to the nearest blocked cell's square is at least ``radius`` (a lower
    bound: centre distance less a cell diagonal).  On 0.25 ft cells that costs
    up to a cell on each side of a passage: a vehicle of 2r = 1.58 ft needs 9
    free cells (2.25 ft) between two walls of cells.  The bound is loose by up
    to 0.41 cell off the diagonals: bench seed 4's goal cell, 0.7906 ft from
    the nearest blocked square, has 0.76 ft by it, under the radius 0.7903 ft.

    ``at="anywhere-exact"`` (a named option, not the default): the same test
    with the exact distance between the two squares (:func:`square_gap_cells`).

    ``at="centre"`` (a named option beside it): a cell is passable when its
    centre is at least ``radius`` from every blocked square (a lower bound:
    centre distance less half a diagonal), and every point the vehicle's
    centre is then put on (the path's samples, the executed moves) is tested
    by its own exact distance to the blocked squares (:func:`point_clearance`),
    so no position is accepted that the map shows within ``radius`` of a
    blocked cell: 7 free cells (1.75 ft) pass the same vehicle."""
    if unknown not in ("blocked", "free"):
        raise ValueError(f"unknown must be 'blocked' or 'free', not {unknown!r}")
    if at not in CLEARANCE_AT:
        raise ValueError(f"at must be one of {CLEARANCE_AT}, not {at!r}")
    uncertain = unknown if uncertain is None else uncertain
    blocked = fm.cells == OCCUPIED
    if unknown == "blocked":
        blocked = blocked | (fm.cells == UNKNOWN)
    if uncertain == "blocked" or (uncertain == "core" and fm.uncertain_core is None):
        blocked = blocked | (fm.cells == UNCERTAIN)
    elif uncertain == "core":
        blocked = blocked | ((fm.cells == UNCERTAIN) & fm.uncertain_core)
    if at == "anywhere-exact":
        clearance = square_gap_cells(blocked) * fm.cell
    else:
        # centre-to-centre in cells; the nearest point of a blocked square is at
        # most half a diagonal nearer, and any point of this cell another half
        # diagonal: so the vehicle may stand ANYWHERE in a passable cell
        clearance = np.maximum(_centre_distance_cells(blocked) - _SHRINK[at], 0.0) * fm.cell
    return Passable(clearance >= radius - 1e-9, clearance, blocked, fm, radius, unknown, at)


_SHRINK = {"anywhere": SQRT2, "centre": SQRT2 / 2}


def _centre_distance_cells(blocked: np.ndarray) -> np.ndarray:
    """Centre-to-centre distance (cells) to the nearest blocked cell, the border blocked."""
    padded = np.pad(~blocked, 1, constant_values=False).astype(np.uint8)
    return cv2.distanceTransform(padded, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[1:-1, 1:-1]


def square_gap_cells(blocked: np.ndarray) -> np.ndarray:
    """The exact distance (in cells) from every point of each cell's square to
    the nearest blocked cell's square, the map's border counting as blocked.

    Two unit squares whose centres are (a, b) cells apart are
    hypot(max(|a| - 1, 0), max(|b| - 1, 0)) apart; per axis, max(|a| - 1, 0)
    is the offset to the nearest of the blocked cell's 3 x 3 neighbourhood, so
    the gap is the centre-to-centre distance to the blocked cells dilated by
    one cell (0 for a cell touching a blocked one)."""
    padded = np.pad(blocked, 1, constant_values=True).astype(np.uint8)
    grown = cv2.dilate(padded, np.ones((3, 3), np.uint8), borderType=cv2.BORDER_CONSTANT,
                       borderValue=1)
    free = (grown == 0).astype(np.uint8)
    return cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[1:-1, 1:-1]


def point_clearance(p: Passable, pts) -> np.ndarray:
    """The distance (ft) from each room point (x, z) to the nearest blocked
    cell's square (the map's border blocked; 0 outside the map): exact where
    it is below the radius, a lower bound of at least the radius elsewhere
    (all that the tests against the radius need)."""
    from scipy.spatial import cKDTree
    fm = p.fmap
    pts = np.asarray(pts, float).reshape(-1, 2)
    if not len(pts):
        return np.zeros(0)
    cache = p.__dict__.setdefault("_blocked_squares", {})
    if "tree" not in cache:
        bi, bj = np.nonzero(np.pad(p.blocked, 1, constant_values=True))
        cache["xz"] = np.stack([fm.x0 + (bj - 0.5) * fm.cell, fm.z0 + (bi - 0.5) * fm.cell], 1)
        cache["tree"] = cKDTree(cache["xz"])
    xz, h = cache["xz"], fm.cell / 2
    # a square whose centre is farther than radius + half a diagonal is at least the radius away
    near = cache["tree"].query_ball_point(pts, p.radius + h * SQRT2 + 1e-9)
    out = np.full(len(pts), float(p.radius))
    for k, idx in enumerate(near):
        if idx:
            d = np.maximum(np.abs(xz[idx] - pts[k]) - h, 0.0)
            out[k] = min(float(np.sqrt((d * d).sum(1)).min()), p.radius)
    return out


def clearance_at(p: Passable, pts) -> np.ndarray:
    """The clearance (ft) the map gives the vehicle's centre at each point:
    its cell's (``at="anywhere"``) or its own exact one (``at="centre"``)."""
    fm = p.fmap
    s = np.asarray(pts, float).reshape(-1, 2)
    if p.at == "centre":
        return point_clearance(p, s)
    i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
    j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
    inside = (i >= 0) & (i < fm.shape[0]) & (j >= 0) & (j < fm.shape[1])
    cl = np.zeros(len(s))
    cl[inside] = p.clearance[i[inside], j[inside]]
    return cl


def _explain(p: Passable, x: float, z: float, what: str) -> str | None:
    fm = p.fmap
    i, j = fm.index(x, z)
    if not fm.inside(i, j):
        return f"the {what} ({x:.2f}, {z:.2f}) ft is outside the map"
    s = fm.cells[i, j]
    if s == OCCUPIED:
        return f"the {what} ({x:.2f}, {z:.2f}) ft is inside an obstacle (occupied cell)"
    if s in (UNKNOWN, UNCERTAIN) and p.unknown == "blocked":
        return f"the {what} ({x:.2f}, {z:.2f}) ft is in unknown space (unknown treated as blocked)"
    if not p.ok[i, j]:
        # the exact gap from the cell's square (bench/goal_blockers.py's), beside the bound
        gap = square_gap_cells(p.blocked)[i, j] * fm.cell
        if p.at == "anywhere-exact":
            where = "its cell's nearest point"
        else:
            part = "cell" if p.at == "anywhere" else "cell's centre"
            where = f"the map's bound for its {part}; its cell's nearest point {gap:.2f} ft"
        return (f"the {what} ({x:.2f}, {z:.2f}) ft is {p.clearance[i, j]:.2f} ft ({where}) "
                f"from an obstacle; the vehicle needs {p.radius:.2f} ft")
    return None


def check_ends(p: Passable, start, goal) -> None:
    for what, (x, z) in (("start", start), ("goal", goal)):
        why = _explain(p, x, z, what)
        if why:
            raise NoPath(why)


def _bottleneck(p: Passable, start, goal) -> tuple[float, tuple[float, float]]:
    """The widest clearance w at which start and goal still connect (cells with
    clearance >= w), and the cell of that width nearest the straight route."""
    fm = p.fmap
    si, sj = fm.index(*start)
    gi, gj = fm.index(*goal)
    free = ~p.blocked
    levels = np.unique(p.clearance[free])
    lo, hi = 0, len(levels) - 1                  # levels[lo] connects; find the largest
    while lo < hi:
        mid = (lo + hi + 1) // 2
        _, comp = cv2.connectedComponents((free & (p.clearance >= levels[mid])).astype(np.uint8),
                                          connectivity=8)
        if comp[si, sj] > 0 and comp[si, sj] == comp[gi, gj]:
            lo = mid
        else:
            hi = mid - 1
    w = float(levels[lo])
    _, comp = cv2.connectedComponents((free & (p.clearance >= w)).astype(np.uint8), connectivity=8)
    nxt = levels[lo + 1] if lo + 1 < len(levels) else np.inf
    ii, jj = np.nonzero((comp == comp[si, sj]) & (p.clearance < nxt))
    xs, zs = fm.centre(ii, jj)
    detour = np.hypot(xs - start[0], zs - start[1]) + np.hypot(xs - goal[0], zs - goal[1])
    k = int(np.argmin(detour))
    return w, (float(xs[k]), float(zs[k]))


def _no_connection(p: Passable, reached: np.ndarray, start, goal) -> NoPath:
    """Say why the goal cannot be reached: a way exists for a point but is
    narrower than the vehicle somewhere, or occupied / unknown cells close the
    reachable region off."""
    fm = p.fmap
    n_comp, comp = cv2.connectedComponents((~p.blocked).astype(np.uint8), connectivity=8)
    si, sj = fm.index(*start)
    gi, gj = fm.index(*goal)
    if comp[si, sj] == comp[gi, gj] and comp[si, sj] > 0:
        w, (x, z) = _bottleneck(p, start, goal)
        return NoPath(f"no path: the way from the start to the goal is narrower than the "
                      f"vehicle ({2 * p.radius:.2f} ft) near ({x:.2f}, {z:.2f}) ft, where it "
                      f"leaves {2 * w:.2f} ft")
    reach = int(math.ceil(p.radius / fm.cell)) + 2
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1, 2 * reach + 1))
    zone = cv2.dilate(reached.astype(np.uint8), kernel).astype(bool)
    occ = int((zone & (fm.cells == OCCUPIED)).sum())
    unk = int((zone & ((fm.cells == UNKNOWN) | (fm.cells == UNCERTAIN)) & p.blocked).sum())
    parts = []
    if occ:
        parts.append(f"{occ} occupied cells")
    if unk:
        parts.append(f"{unk} unknown cells (unknown treated as blocked)")
    return NoPath(f"no path: the {int(reached.sum())} cells reachable from the start are "
                  f"closed off by " + (" and ".join(parts) or "the map's edge"))


# --- the A* baseline ------------------------------------------------------------

_STEPS = [(-1, 0, 1.0), (1, 0, 1.0), (0, -1, 1.0), (0, 1, 1.0),
          (-1, -1, SQRT2), (-1, 1, SQRT2), (1, -1, SQRT2), (1, 1, SQRT2)]


def astar(p: Passable, start, goal, extra: np.ndarray | None = None
          ) -> list[tuple[float, float]]:
    """A* over the passable cells from the start's cell to the goal's cell;
    returns the polyline start, cell centres..., goal (room x, z).  ``extra``
    (an (nz, nx) array >= 0, or None) makes a step into a cell cost its length
    times 1 + ``extra`` there (the octile heuristic stays a lower bound, so
    the path is the cheapest on the grid)."""
    check_ends(p, start, goal)
    fm = p.fmap
    si, sj = fm.index(*start)
    gi, gj = fm.index(*goal)
    ok = p.ok
    nz, nx = ok.shape
    g = np.full(ok.shape, np.inf)
    parent = np.full(ok.shape + (2,), -1, np.int32)
    closed = np.zeros(ok.shape, bool)
    g[si, sj] = 0.0

    def h(i, j):
        di, dj = abs(i - gi), abs(j - gj)
        return (di + dj) + (SQRT2 - 2) * min(di, dj)

    heap = [(h(si, sj), 0.0, si, sj)]
    while heap:
        _, gc, i, j = heapq.heappop(heap)
        if closed[i, j]:
            continue
        closed[i, j] = True
        if (i, j) == (gi, gj):
            break
        for di, dj, w in _STEPS:
            a, b = i + di, j + dj
            if not (0 <= a < nz and 0 <= b < nx) or not ok[a, b] or closed[a, b]:
                continue
            if di and dj and not (ok[i + di, j] and ok[i, j + dj]):
                continue
            ng = gc + (w if extra is None else w * (1.0 + extra[a, b]))
            if ng < g[a, b]:
                g[a, b] = ng
                parent[a, b] = (i, j)
                heapq.heappush(heap, (ng + h(a, b), ng, a, b))
    if not closed[gi, gj]:
        raise _no_connection(p, closed, start, goal)
    cells = [(gi, gj)]
    while cells[-1] != (si, sj):
        cells.append(tuple(parent[cells[-1]]))
    cells.reverse()
    xs, zs = fm.centre(np.array([c[0] for c in cells]), np.array([c[1] for c in cells]))
    pts = [tuple(map(float, start))] + list(zip(xs[1:-1].tolist(), zs[1:-1].tolist())) \
        + [tuple(map(float, goal))]
    return pts


# --- the dissertation's hierarchical search -------------------------------------

@dataclass
class Quadtree:
    """Leaves of the passable map's quadtree: block ``k`` covers rows
    ``i0[k] .. i0[k]+size[k]-1`` and the same run of columns from ``j0[k]``."""
    i0: np.ndarray
    j0: np.ndarray
    size: np.ndarray
    label: np.ndarray          # (nz, nx) int: block id of each passable cell, -1 elsewhere
    levels: int


def quadtree(ok: np.ndarray) -> Quadtree:
    """Merge passable cells into the largest aligned uniform square blocks,
    level by level (a block is kept at a level when its four children are all
    wholly passable)."""
    nz, nx = ok.shape
    uniform = uniform_levels(ok)
    levels, n = len(uniform) - 1, uniform[0].shape[0]
    taken = np.zeros((n, n), bool)
    label = np.full((n, n), -1, np.int64)
    I0, J0, S = [], [], []
    for lev in range(levels, -1, -1):
        s = 2 ** lev
        u = uniform[lev]
        cover = taken.reshape(n // s, s, n // s, s).any(axis=(1, 3))
        new = u & ~cover
        ii, jj = np.nonzero(new)
        # this level's blocks, numbered on from the larger ones' in row order
        ids = np.full(new.shape, -1, np.int64)
        ids[ii, jj] = np.arange(len(I0), len(I0) + len(ii))
        cells = np.repeat(np.repeat(ids, s, 0), s, 1)
        label = np.where(cells >= 0, cells, label)
        taken |= cells >= 0
        I0.extend((ii * s).tolist())
        J0.extend((jj * s).tolist())
        S.extend([s] * len(ii))
    return Quadtree(np.array(I0, int), np.array(J0, int), np.array(S, int),
                    label[:nz, :nx], levels)


def uniform_levels(ok: np.ndarray) -> list[np.ndarray]:
    """The quadtree's levels: level 0 the passable map padded to a power of two
    (at least 2) square, level L+1 true where a 2x2 block of level L is."""
    nz, nx = ok.shape
    levels = max(1, int(math.ceil(math.log2(max(nz, nx)))))
    n = 2 ** levels
    full = np.zeros((n, n), bool)
    full[:nz, :nx] = ok
    uniform = [full]
    for _ in range(levels):
        m = uniform[-1].shape[0] // 2
        uniform.append(uniform[-1].reshape(m, 2, m, 2).all(axis=(1, 3)))
    return uniform


def _adjacency(label: np.ndarray) -> dict[int, set[int]]:
    """Each block's neighbours (blocks sharing a side) from the label map."""
    m = int(label.max()) + 1 if label.size else 0
    if m == 0:
        return {}
    keys = [np.zeros(0, np.int64)]
    for a, b in ((label[:, :-1], label[:, 1:]), (label[:-1, :], label[1:, :])):
        side = (a >= 0) & (b >= 0) & (a != b)
        keys += [a[side] * m + b[side], b[side] * m + a[side]]
    keys = np.unique(np.concatenate(keys))
    adj: dict[int, set[int]] = {}
    for u, v in zip((keys // m).tolist(), (keys % m).tolist()):
        adj.setdefault(u, set()).add(v)
    return adj


def _portal(qt: Quadtree, fm: FloorMap, u: int, v: int) -> tuple[float, float]:
    """Midpoint of the side shared by blocks u and v, room (x, z)."""
    ui, uj, us = qt.i0[u], qt.j0[u], qt.size[u]
    vi, vj, vs = qt.i0[v], qt.j0[v], qt.size[v]
    c = fm.cell
    if uj + us == vj or vj + vs == uj:                 # side by side in X
        xe = (vj if uj + us == vj else uj) * c + fm.x0
        lo, hi = max(ui, vi), min(ui + us, vi + vs)
        return xe, fm.z0 + (lo + hi) / 2 * c
    ze = (vi if ui + us == vi else ui) * c + fm.z0
    lo, hi = max(uj, vj), min(uj + us, vj + vs)
    return fm.x0 + (lo + hi) / 2 * c, ze


def hierarchical_search(p: Passable, start, goal, qt: Quadtree | None = None
                        ) -> list[tuple[float, float]]:
    """The dissertation's search (see the module docstring); returns the
    polyline start, portals..., goal."""
    check_ends(p, start, goal)
    fm = p.fmap
    qt = quadtree(p.ok) if qt is None else qt
    si, sj = fm.index(*start)
    gi, gj = fm.index(*goal)
    s_blk, g_blk = int(qt.label[si, sj]), int(qt.label[gi, gj])
    adj = _adjacency(qt.label)
    gx, gz = goal
    c = fm.cell

    def key(k):
        # distance from the block's nearest point to the goal: larger blocks
        # reach nearer, so they are preferred at equal centre distance
        x0 = fm.x0 + qt.j0[k] * c
        z0 = fm.z0 + qt.i0[k] * c
        s = qt.size[k] * c
        dx = max(x0 - gx, 0.0, gx - (x0 + s))
        dz = max(z0 - gz, 0.0, gz - (z0 + s))
        return math.hypot(dx, dz), -int(qt.size[k])

    parent = {s_blk: -1}
    heap = [(key(s_blk), s_blk)]
    done = set()
    while heap:
        _, k = heapq.heappop(heap)
        if k in done:
            continue
        done.add(k)
        if k == g_blk:
            break
        for v in adj.get(k, ()):
            if v not in parent:
                parent[v] = k
                heapq.heappush(heap, (key(v), v))
    if g_blk not in done:
        reached = np.isin(qt.label, np.fromiter(done, int))
        raise _no_connection(p, reached, start, goal)
    chain = [g_blk]
    while parent[chain[-1]] != -1:
        chain.append(parent[chain[-1]])
    chain.reverse()
    pts = [tuple(map(float, start))]
    pts += [_portal(qt, fm, u, v) for u, v in zip(chain[:-1], chain[1:])]
    pts.append(tuple(map(float, goal)))
    return pts


# --- tests on paths ---------------------------------------------------------------

def path_length(pts) -> float:
    a = np.asarray(pts, float)
    return float(np.hypot(*np.diff(a, axis=0).T).sum()) if len(a) > 1 else 0.0


def segment_samples(a, b, step: float) -> np.ndarray:
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = max(2, int(math.ceil(np.linalg.norm(b - a) / step)) + 1)
    return a + np.linspace(0, 1, n)[:, None] * (b - a)


def min_clearance(p: Passable, pts) -> tuple[float, tuple[float, float]]:
    """The smallest clearance (ft) sampled along the polyline, and where."""
    fm = p.fmap
    best, where = math.inf, tuple(pts[0])
    for a, b in zip(pts[:-1], pts[1:]):
        s = segment_samples(a, b, fm.cell / 4)
        cl = clearance_at(p, s)
        k = int(np.argmin(cl))
        if cl[k] < best:
            best, where = float(cl[k]), (float(s[k, 0]), float(s[k, 1]))
    return best, where


def line_of_sight(p: Passable, a, b) -> bool:
    """Every cell the segment a-b passes (sampled at a quarter cell) is passable."""
    fm = p.fmap
    s = segment_samples(a, b, fm.cell / 4)
    i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
    j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
    if (i < 0).any() or (j < 0).any() or (i >= fm.shape[0]).any() or (j >= fm.shape[1]).any():
        return False
    if p.at == "centre":
        # a passable cell's centre has the radius; every point between needs its
        # own, except in cells passable for another reason (leading the vehicle
        # away from a spot nearer an obstacle than its radius: planning.escape_start)
        escape = p.ok[i, j] & (p.clearance[i, j] < p.radius - 1e-9)
        return bool((escape | (point_clearance(p, s) >= p.radius - 1e-9)).all())
    return bool(p.ok[i, j].all())


def cross_section_test(p: Passable, pts) -> None:
    """Refuse a path whose clearance anywhere is below the vehicle's radius."""
    cl, (x, z) = min_clearance(p, pts)
    if cl < p.radius - 1e-9:
        raise NoPath(f"the path's cross section at ({x:.2f}, {z:.2f}) ft is {2 * cl:.2f} ft, "
                     f"narrower than the vehicle ({2 * p.radius:.2f} ft)")
