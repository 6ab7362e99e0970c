"""Chapter VI's 2-D floor map: "the 3-dimensional model, then ... the
2-dimensional projection over the interval volume through which the robot must
pass".

A :class:`FloorMap` is a grid over the floor (room X across, room Z along;
row ``i`` is Z, column ``j`` is X) whose cells are FREE, OCCUPIED or UNKNOWN.
:func:`project_octree` projects the octree over the vehicle's height band
(room Y from the top of the vehicle down to a floor clearance; Y is down):
a column is OCCUPIED if any leaf in the band is occupied, else UNCERTAIN if
any is uncertain, else FREE if a leaf in ``free_band`` (default the band) is
free, else UNKNOWN.  The closed loop takes ``free_band`` as the lowest part of
the band: a camera 3 ft up looking level sees nothing of the floor nearer
than 9 ft and looks over a low box, so a sight line at camera height proves
nothing about the floor below it.
:func:`true_floor_map` draws the true room (obstacle footprints, walls) on
the same grid: the reference the true optimum is measured on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, classify, unpack, free_below, leaves, \
    logodds_at

FLOOR_Y = 3.0          # the floor plane in room coordinates (Y down, cameras at Y = 0)


def split_in_four(a: np.ndarray) -> np.ndarray:
    """(2 nz, 2 nx): each cell of the (nz, nx) grid ``a`` as the four cells of half
    its side, each with its value."""
    return np.repeat(np.repeat(a, 2, 0), 2, 1)


@dataclass
class FloorMap:
    cells: np.ndarray          # (nz, nx) uint8 of FREE / OCCUPIED / UNKNOWN / UNCERTAIN
    x0: float                  # room X of the left edge of column 0
    z0: float                  # room Z of the near edge of row 0
    cell: float                # cell side, ft
    assumed: np.ndarray | None = None   # (nz, nx) bool: FREE only by assumption, no look's
                                        # proof nor the track (Perception.pivot_proof); a
                                        # pivot's cells must not be (motion._pivot_ok)
    drift_kept: np.ndarray | None = None   # (nz, nx) bool: FREE until the drift's erosion took
                                        # it (DriveConfig.free_drift="moves"): a pivot's cells
                                        # may be these where still UNKNOWN (motion._proven_free)
    uncertain_core: np.ndarray | None = None   # (nz, nx) bool: the UNCERTAIN cells an
                                        # uncertain floor feature covers within ONE standard
                                        # deviation (or its span): what plan(uncertain="core")
                                        # still plans round (Perception._draw_features)
    move_ring: np.ndarray | None = None    # (nz, nx) bool: never seen, nothing a look placed
                                        # within the planning radius (motion.clear_unseen;
                                        # DriveConfig.move_ring="known"): a forward move's
                                        # band beyond the bare footprint may cross these
    move_ring_start: bool = False          # (DriveConfig.move_ring="start") only where the
                                        # grown footprint stands at the move's start

    @property
    def shape(self):
        return self.cells.shape

    def index(self, x: float, z: float) -> tuple[int, int]:
        """(row, column) of the cell holding room point (x, z) (may be outside)."""
        return int(np.floor((z - self.z0) / self.cell)), int(np.floor((x - self.x0) / self.cell))

    def centre(self, i, j):
        return self.x0 + (np.asarray(j) + 0.5) * self.cell, self.z0 + (np.asarray(i) + 0.5) * self.cell

    def square_around(self, i: int, j: int, n: int):
        """(rows, columns) index grids of the cells at most ``n`` rows and
        columns from cell (i, j), cut to the map."""
        return np.mgrid[max(i - n, 0):min(i + n + 1, self.cells.shape[0]),
                        max(j - n, 0):min(j + n + 1, self.cells.shape[1])]

    def inside(self, i: int, j: int) -> bool:
        return 0 <= i < self.cells.shape[0] and 0 <= j < self.cells.shape[1]

    def halved(self) -> FloorMap:
        """The same map on cells of half the side: each cell, and each of its
        masks, split in four (:func:`split_in_four`)."""
        def split(a):
            return None if a is None else split_in_four(a)
        return FloorMap(split(self.cells), self.x0, self.z0, self.cell / 2, split(self.assumed),
                        split(self.drift_kept), split(self.uncertain_core),
                        split(self.move_ring), self.move_ring_start)

    def state_at(self, x: float, z: float) -> int:
        i, j = self.index(x, z)
        return int(self.cells[i, j]) if self.inside(i, j) else UNKNOWN

    def extent(self):
        nz, nx = self.cells.shape
        return self.x0, self.x0 + nx * self.cell, self.z0, self.z0 + nz * self.cell


def empty_map(bounds, cell: float, margin: float = 0.0, fill: int = UNKNOWN) -> FloorMap:
    """A grid covering ``bounds`` = (x0, x1, z0, z1) plus ``margin``, aligned to
    multiples of ``cell`` so that it coincides with the octree's cells."""
    x0, x1, z0, z1 = bounds
    gx0 = np.floor((x0 - margin) / cell) * cell
    gz0 = np.floor((z0 - margin) / cell) * cell
    nx = int(np.ceil((x1 + margin - gx0) / cell))
    nz = int(np.ceil((z1 + margin - gz0) / cell))
    return FloorMap(np.full((nz, nx), fill, np.uint8), float(gx0), float(gz0), float(cell))


def _paint(mask: np.ndarray, fm: FloorMap, cx, cz, half) -> None:
    """Set ``mask`` over every grid cell that the squares (centre, half side) overlap."""
    j0 = np.floor((cx - half - fm.x0) / fm.cell + 1e-9).astype(int)
    j1 = np.ceil((cx + half - fm.x0) / fm.cell - 1e-9).astype(int)
    i0 = np.floor((cz - half - fm.z0) / fm.cell + 1e-9).astype(int)
    i1 = np.ceil((cz + half - fm.z0) / fm.cell - 1e-9).astype(int)
    nz, nx = mask.shape
    for a, b, c, d in zip(np.clip(i0, 0, nz), np.clip(i1, 0, nz), np.clip(j0, 0, nx),
                          np.clip(j1, 0, nx)):
        mask[a:b, c:d] = True


class TouchedCells:
    """The log-odds of every finest cell an :class:`~planner.octree.Octree`'s
    logged updates have touched, read back from the tree: the cells whose
    union is the tree's leaves (a cell is only created by an update, and a
    pruned leaf covers only cells that were), kept up to date one look at a
    time (:meth:`refresh` reads only the cells touched since the last)."""

    def __init__(self):
        self.keys = np.zeros(0, np.int64)        # packed keys, sorted
        self.logodds = np.zeros(0)

    def refresh(self, tree) -> int:
        """Read back the cells touched since the last refresh; returns how many."""
        if not tree.touched:
            return 0
        new = np.unique(np.concatenate(tree.touched))
        tree.touched.clear()
        lo = logodds_at(tree, new)
        pos = np.searchsorted(self.keys, new)
        known = (pos < len(self.keys)) & (self.keys[np.minimum(pos, len(self.keys) - 1)] == new) \
            if len(self.keys) else np.zeros(len(new), bool)
        self.logodds[pos[known]] = lo[known]
        if (~known).any():
            keys = np.concatenate([self.keys, new[~known]])
            order = np.argsort(keys, kind="stable")
            self.keys = keys[order]
            self.logodds = np.concatenate([self.logodds, lo[~known]])[order]
        return len(new)


def _project_touched(tree, fm: FloorMap, band, free_band, free_looks: int) -> dict:
    """:func:`project_octree`'s masks from the tree's touched cells (equal to
    the masks from all leaves: tested)."""
    cache = tree.__dict__.setdefault("_touched_cells", TouchedCells())
    cache.refresh(tree)
    res = tree.getResolution()
    masks = {st: np.zeros(fm.shape, bool) for st in (FREE, UNCERTAIN, OCCUPIED)}
    if not len(cache.keys):
        return masks
    k = unpack(cache.keys)
    lo = cache.logodds
    y = (k[:, 1] + 0.5) * res
    h = res / 2
    inband = (y + h > band[0]) & (y - h < band[1]) & ~np.isnan(lo)
    fb = band if free_band is None else free_band
    infree = inband & (y + h > fb[0]) & (y - h < fb[1])
    i = k[:, 2] - int(round(fm.z0 / res))
    j = k[:, 0] - int(round(fm.x0 / res))
    inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    state = np.full(len(lo), UNKNOWN, np.uint8)
    state[inband] = classify(lo[inband], tree.getOccupancyThresLog(), free_below(free_looks))
    for st, mask in masks.items():
        m = (infree if st == FREE else inband) & inside & (state == st)
        mask[i[m], j[m]] = True
    return masks


def project_octree(tree, bounds, band=(-0.5, FLOOR_Y - 0.25), margin: float = 1.0,
                   free_looks: int = 1, free_band=None, from_leaves: bool = False) -> FloorMap:
    """The octree projected over the height band ``band`` = (Y top, Y bottom)
    of the vehicle's passage (room Y, down positive) onto a grid over ``bounds``.

    A tree whose updates are all logged (:class:`~planner.octree.Octree`, as
    :func:`~planner.octree.new_octree` makes) is projected from the cells
    those updates touched, read back a look at a time; any other tree, or
    ``from_leaves``, from all its leaves (the reference: the same map)."""
    res = tree.getResolution()
    fm = empty_map(bounds, res, margin)
    if not from_leaves and getattr(tree, "log_complete", False):
        masks = _project_touched(tree, fm, band, free_band, free_looks)
        for st in (FREE, UNCERTAIN, OCCUPIED):           # later wins
            fm.cells[masks[st]] = st
        return fm
    ex = fm.extent()
    lo = np.array([ex[0], band[0], ex[2]])
    hi = np.array([ex[1], band[1], ex[3]])
    centres, sizes, state = leaves(tree, lo, hi, free_looks)
    masks = {st: np.zeros(fm.shape, bool) for st in (FREE, UNCERTAIN, OCCUPIED)}
    if len(centres):
        half = sizes / 2
        inband = (centres[:, 1] + half > band[0]) & (centres[:, 1] - half < band[1])
        fb = band if free_band is None else free_band
        infree = (centres[:, 1] + half > fb[0]) & (centres[:, 1] - half < fb[1])
        for st, mask in masks.items():
            m = (infree if st == FREE else inband) & (state == st)
            _paint(mask, fm, centres[m, 0], centres[m, 2], half[m])
    for st in (FREE, UNCERTAIN, OCCUPIED):           # later wins
        fm.cells[masks[st]] = st
    return fm


def one_cell_gaps(cells: np.ndarray) -> np.ndarray:
    """(rows, cols) bool: the UNKNOWN cells whose two neighbours across a row, or
    across a column, are both FREE: a gap one cell wide in space seen free
    (``DriveConfig.free_gaps="fill"``; not 1985).

    Why it is safe: what stands in the generated rooms is an axis-aligned box at
    least 0.8 ft on each side (or a wall), more than a cell of 0.25 ft.  A box
    that reaches into such a cell is wider than the cell, so it reaches out of
    it across the row (or column) too, into one of the two neighbours on that
    line, which are free: were they truly free, the gap is.  Only the
    two neighbours across a row or a column are trusted, not a diagonal pair: a
    box reaching into the cell from the other diagonal's corner misses both.
    The map's free cells themselves can be wrong (a cell the grid rounds at a
    box's foot, the estimate's drift): a gap filled next to such a cell carries
    the error one cell on.  Why it is needed: the floor in view proves its floor
    column by column, and a column whose proof ends sooner than its neighbours'
    (a pixel of noise, its own bound) leaves a stripe one cell wide, along the
    sight lines, unknown between their proofs (room 57, docs/planner.md)."""
    free = np.asarray(cells) == FREE
    p = np.pad(free, 1)
    across_row = p[1:-1, :-2] & p[1:-1, 2:]
    across_col = p[:-2, 1:-1] & p[2:, 1:-1]
    return (np.asarray(cells) == UNKNOWN) & (across_row | across_col)


def fill_one_cell_gaps(cells: np.ndarray) -> np.ndarray:
    """A copy of ``cells`` with every :func:`one_cell_gaps` cell FREE, again until none
    is left: a filled cell may close the next gap, and by the same argument it is free
    where its two neighbours are."""
    out = np.array(cells, copy=True)
    gaps = one_cell_gaps(out)
    while gaps.any():
        out[gaps] = FREE
        gaps = one_cell_gaps(out)
    return out


def true_floor_map(obstacles, bounds, cell: float, margin: float = 1.0) -> FloorMap:
    """The true room on the grid: OCCUPIED where any obstacle footprint
    (x0, x1, z0, z1) overlaps a cell or the cell reaches outside the walls
    ``bounds``, FREE elsewhere (nothing unknown)."""
    fm = empty_map(bounds, cell, margin, fill=FREE)
    nz, nx = fm.shape
    xs = fm.x0 + np.arange(nx + 1) * cell          # cell edges
    zs = fm.z0 + np.arange(nz + 1) * cell
    bx0, bx1, bz0, bz1 = bounds
    tol = 1e-9
    outside_x = (xs[:-1] < bx0 - tol) | (xs[1:] > bx1 + tol)
    outside_z = (zs[:-1] < bz0 - tol) | (zs[1:] > bz1 + tol)
    occ = outside_z[:, None] | outside_x[None, :]
    for ox0, ox1, oz0, oz1 in np.asarray(obstacles, float).reshape(-1, 4):
        cols = (xs[1:] > ox0 + tol) & (xs[:-1] < ox1 - tol)
        rows = (zs[1:] > oz0 + tol) & (zs[:-1] < oz1 - tol)
        occ |= rows[:, None] & cols[None, :]
    fm.cells[occ] = OCCUPIED
    return fm


def map_losses(fm: FloorMap, truth: FloorMap, radius: float) -> dict:
    """Where a floor map loses free space and width against the TRUE room's
    map on the same grid (both aligned to multiples of one cell; the true map
    must cover the map).  Cells the map blocks (occupied or uncertain) that are
    free in the room are sorted by their distance to the nearest true obstacle
    cell: ``rounding`` (a neighbour of it: the cell rounding of a hit on its
    face), ``growth`` (within the feature growth cap of 1.5 ft and a cell:
    a hit grown by its covariance, or its range error) and ``false`` (farther:
    a false match).  ``passable_*`` count the cells where the vehicle of
    ``radius`` may stand (:func:`planner.search.clearance_map`, unknown free,
    uncertain blocked): in the true room, and lost on the map as the blocked
    cells of each kind are added in that order.  ``seen_*`` count the true free
    cells the map shows free / leaves unknown; ``passable_lost_uncertain_only``
    the lost passable cells that only the uncertain cells cost."""
    import cv2

    from .octree import MAX_GROWTH_FT
    from .search import clearance_map
    if abs(fm.cell - truth.cell) > 1e-12:
        raise ValueError(f"cells differ: {fm.cell} and {truth.cell} ft")
    di = int(round((fm.z0 - truth.z0) / fm.cell))
    dj = int(round((fm.x0 - truth.x0) / fm.cell))
    nz, nx = fm.shape
    if di < 0 or dj < 0 or di + nz > truth.shape[0] or dj + nx > truth.shape[1]:
        raise ValueError("the true map does not cover the map")
    occ_true = truth.cells[di:di + nz, dj:dj + nx] == OCCUPIED
    dt = cv2.distanceTransform((~occ_true).astype(np.uint8), cv2.DIST_L2,
                               cv2.DIST_MASK_PRECISE) * fm.cell     # centre to centre, ft
    blocked = (fm.cells == OCCUPIED) | (fm.cells == UNCERTAIN)
    wrong = blocked & ~occ_true
    kinds = {"rounding": wrong & (dt <= 1.5 * fm.cell),
             "growth": wrong & (dt > 1.5 * fm.cell) & (dt <= MAX_GROWTH_FT + 1.5 * fm.cell),
             "false": wrong & (dt > MAX_GROWTH_FT + 1.5 * fm.cell)}
    free_true = ~occ_true
    out = {"cell_ft": fm.cell, "true_free": int(free_true.sum()),
           "seen_free": int((free_true & (fm.cells == FREE)).sum()),
           "seen_unknown": int((free_true & (fm.cells == UNKNOWN)).sum()),
           "true_obstacle_mapped_free": int((occ_true & (fm.cells == FREE)).sum())}
    for k, m in kinds.items():
        out[f"blocked_{k}"] = int(m.sum())
        out[f"blocked_{k}_uncertain"] = int((m & (fm.cells == UNCERTAIN)).sum())

    def passable(block):
        cells = np.where(block, OCCUPIED, FREE).astype(np.uint8)
        return clearance_map(FloorMap(cells, fm.x0, fm.z0, fm.cell), radius, "free").ok
    p_true = passable(occ_true)
    out["passable_true"] = int(p_true.sum())
    block = occ_true & blocked
    prev = p_true & passable(block)
    for k, m in kinds.items():
        block = block | m
        now = p_true & passable(block)
        out[f"passable_lost_{k}"] = int((prev & ~now).sum())
        prev = now
    out["passable_map"] = int((p_true & prev).sum())
    # of the cells lost, those that only the uncertain (unconfirmed) cells cost
    out["passable_lost_uncertain_only"] = int((p_true & ~prev & passable(
        fm.cells == OCCUPIED)).sum())
    return out
