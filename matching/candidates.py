"""The candidate partners of every edge of a line: the 1985 evidence, kept whole.

MASL (estar/masl.py) pairs every left-slice edge with every right-slice edge
of the same side whose grey level differs by at most 1, and MARF scores the
pair by sliding the two 16x16 edge bit maps against each other.  The 1985
program keeps the ten best partners of each edge and LCSL takes the first with
a disparity above one pixel: "the best match available" (Chapter V,
"Matches").  Here the same evidence is computed for every pair, in both
directions, so that the constraints of :mod:`matching.assign` can weigh it:

* the shape cost is MARF's mismatch ``(ND*256)/NTOT`` at the best shift within
  MASL's shift bound (half the gap to the neighbouring feature, at most half
  the feature's width), ties to the shift nearest zero, as MARF breaks them
  (:func:`shape_cost` equals MARF's shift search (``estar.marf.marf_kernel``) with ``cap_overflow``);
  the 1985 16-bit overflow (ND >= 128 counts as 256) is not kept by default;
  :func:`candidates` runs the same search compiled, pair by pair
  (:func:`best_shift`: a slice has a few edges, too few for array steps to pay);
* the right-slice location is ``x2 - shift`` (the sign the geometry implies,
  the E7 fix; the 1985 sign is ``x2 + shift``) when ``use_shift``, else the
  feature index itself;
* a candidate needs a disparity above EDISP = 1 pixel (LCSL could not locate
  it otherwise).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from diskfmt.jit import jit

NPIX = 128
EDISP = 1
GREY_TOLERANCE = 1                 # MASL: |IGREY1 - IGREY2| <= 1

_POP = np.array([bin(v).count("1") for v in range(1 << 16)], dtype=np.int64)


@dataclass(frozen=True)
class SliceEdges:
    """The edges of one slice, in MASL's numbering: edge k (1..50) is the left
    end of feature k, edge 50+k its right end.  Arrays are indexed in the
    order of the edges along the line (x, then left ends before right ends)."""
    edge: np.ndarray          # MASL edge number 1..100
    x: np.ndarray             # 1-based slice index of the edge (IFEAT start or stop)
    side: np.ndarray          # 0 left end, 1 right end
    grey: np.ndarray          # the grey level MASL compares (left grey / right grey)
    feature: np.ndarray       # feature number 1..50
    bound: np.ndarray         # MASL's shift bound on this edge's side (IRGDL/IRGDR)
    width: np.ndarray         # its feature's width (stop - start)
    # (5, n) rows x, side, grey, bound, width: what admissible_pairs reads
    pair_rows: np.ndarray | None = field(default=None, repr=False, compare=False)

    def __len__(self) -> int:
        return len(self.edge)


def _half(a: int) -> int:
    """FORTRAN integer /2 (truncates toward zero)."""
    return int(a / 2)


def slice_edges(features) -> SliceEdges:
    """The edges of a slice's feature list ``[(start, stop, lgrey, rgrey), ...]``
    (``Slice.features()``), with MASL's shift bounds.

    Remembered by the list's content (the arrays read-only): a look's rows
    often repeat a slice (a blank wall, a box's sides)."""
    return _slice_edges(tuple(tuple(f) for f in features))


@lru_cache(maxsize=4096)
def _slice_edges(features: tuple) -> SliceEdges:
    n = len(features)
    rows = []
    for k, (start, stop, lg, rg) in enumerate(features, start=1):
        width = _half(stop - start)
        left = start if k == 1 else _half(start - features[k - 2][1])
        right = NPIX - stop + 1 if k >= n else _half(features[k][0] - stop)
        left = max(min(left, width), 0)
        right = max(min(right, width), 0)
        rows.append((start, 0, k, lg, k, left, stop - start))
        rows.append((stop, 1, k + 50, rg, k, right, stop - start))
    rows.sort()                           # by (x, side, edge): the edge numbers are unique
    arr = np.array(rows, dtype=np.int64).reshape(-1, 7).T.copy()
    arr.flags.writeable = False
    pair_rows = arr[[0, 1, 3, 5, 6]]
    pair_rows.flags.writeable = False
    return SliceEdges(edge=arr[2], x=arr[0], side=arr[1], grey=arr[3], feature=arr[4],
                      bound=arr[5], width=arr[6], pair_rows=pair_rows)


def shape_cost(map1, map2, bound: int, cap_overflow: bool = False) -> tuple[int, int]:
    """MARF's search on two 17-word maps (word 0 the flag, words 1..16 the
    columns): ``(shift, mismatch)`` of the best shift in ``-bound..bound``."""
    s, v = shape_costs(np.asarray(map1, dtype=np.int64)[None, 1:17],
                       np.asarray(map2, dtype=np.int64)[None, 1:17],
                       np.array([bound]), cap_overflow)
    return int(s[0]), int(v[0])


def shape_costs(cols1: np.ndarray, cols2: np.ndarray, bounds: np.ndarray,
                cap_overflow: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """:func:`shape_cost` for K pairs at once: ``cols1``/``cols2`` (K, 16)
    column words, ``bounds`` (K,).  Returns (shift, mismatch) arrays."""
    k = len(bounds)
    best_v = np.full(k, 256, dtype=np.int64)
    best_s = np.zeros(k, dtype=np.int64)
    if k == 0:
        return best_s, best_v
    c1 = cols1 & 0xFFFF
    c2 = cols2 & 0xFFFF
    top = int(min(int(bounds.max()), 15))
    # visit shifts in MARF's order of preference: |s| ascending, negative first,
    # and replace only on a strictly smaller mismatch
    order = [0] + [s for a in range(1, top + 1) for s in (-a, a)]
    for s in order:
        off = abs(s)
        n = 16 - off
        if s < 0:
            a, b = c1[:, :n], c2[:, off:off + n]
        else:
            a, b = c1[:, off:off + n], c2[:, :n]
        n1 = _POP[a].sum(axis=1)
        n2 = _POP[b].sum(axis=1)
        nd = _POP[a ^ b].sum(axis=1)
        ntot = n1 + n2
        ok = ntot != 0
        if cap_overflow:
            ok &= nd < 128
        val = np.where(ok, (nd * 256) // np.maximum(ntot, 1), 256)
        better = (val < best_v) & (off <= bounds)
        best_v = np.where(better, val, best_v)
        best_s = np.where(better, s, best_s)
    return best_s, best_v


@dataclass(frozen=True)
class Candidates:
    """Every admissible (left edge, right edge) pair of a line.  ``i``/``j``
    index :class:`SliceEdges` of the left / right slice (positions along the
    line); ``cost`` = shape mismatch + grey penalty; ``loc1``/``loc2`` the
    locations a match would give; ``disp`` = loc1 - loc2."""
    left: SliceEdges
    right: SliceEdges
    i: np.ndarray
    j: np.ndarray
    cost: np.ndarray
    shape: np.ndarray
    shift: np.ndarray
    loc1: np.ndarray
    loc2: np.ndarray

    @property
    def disp(self) -> np.ndarray:
        return self.loc1 - self.loc2

    def __len__(self) -> int:
        return len(self.i)

    def subset(self, keep: np.ndarray) -> "Candidates":
        return Candidates(self.left, self.right, self.i[keep], self.j[keep], self.cost[keep],
                          self.shape[keep], self.shift[keep], self.loc1[keep], self.loc2[keep])

    def with_cost(self, cost: np.ndarray) -> "Candidates":
        """The same pairs at other costs (a constraint's penalty or bonus)."""
        return Candidates(self.left, self.right, self.i, self.j, cost, self.shape, self.shift,
                          self.loc1, self.loc2)


@jit
def best_shift(map1, map2, bound, cap_overflow, pop):
    """:func:`shape_costs` of one pair, as a loop: ``map1``/``map2`` the two
    17-word maps (flag word first).  Returns (shift, mismatch)."""
    best_s, best_v = 0, 256
    for k in range(2 * min(bound, 15) + 1):
        off = (k + 1) // 2
        s = off if k % 2 == 0 else -off         # MARF's order: 0, -1, 1, -2, 2 ...
        n1 = n2 = nd = 0
        for t in range(16 - off):
            a = map1[1 + t + (off if s > 0 else 0)] & 0xFFFF
            b = map2[1 + t + (off if s < 0 else 0)] & 0xFFFF
            n1 += pop[a]
            n2 += pop[b]
            nd += pop[a ^ b]
        val = 256
        if n1 + n2 != 0 and not (cap_overflow and nd >= 128):
            val = (nd * 256) // (n1 + n2)
        if val < best_v:                        # only a strictly smaller mismatch
            best_s, best_v = s, val
    return best_s, best_v


@jit
def admissible_pairs(left, maps1, right, maps2, use_shift, grey_penalty, width_penalty,
                     max_disparity, cap_overflow, pop, pairs, scores):
    """The pairs :func:`candidates` keeps, in the order of the left edges then
    the right ones: ``left``/``right`` rows (x, side, grey, bound, width) of
    the two slices' edges, ``maps1``/``maps2`` their 17-word maps.  Writes
    rows (i, j, shift, mismatch) into ``pairs`` and (cost, loc1, loc2) into
    ``scores`` (cost = mismatch + grey_penalty x the grey difference, +
    width_penalty x the features' difference in width); returns how many."""
    n = 0
    for i in range(left.shape[1]):
        for j in range(right.shape[1]):
            grey_diff = abs(left[2, i] - right[2, j])
            if (left[1, i] != right[1, j] or grey_diff > GREY_TOLERANCE
                    or maps1[i, 0] != 1 or maps2[j, 0] != 1
                    or left[0, i] - right[0, j] <= -16):     # cannot come back above EDISP
                continue
            shift, mismatch = best_shift(maps1[i], maps2[j], min(left[3, i], right[3, j]),
                                         cap_overflow, pop)
            loc2 = right[0, j] - (shift if use_shift else 0)
            d = left[0, i] - loc2
            if not (d > EDISP and d <= max_disparity):
                continue
            cost = mismatch + grey_penalty * grey_diff
            if width_penalty != 0.0:
                cost = cost + width_penalty * abs(left[4, i] - right[4, j])
            pairs[n, 0], pairs[n, 1], pairs[n, 2], pairs[n, 3] = i, j, shift, mismatch
            scores[n, 0], scores[n, 1], scores[n, 2] = cost, left[0, i], loc2
            n += 1
    return n


def candidates(features1, features2, maps1, maps2, use_shift: bool = True,
               grey_penalty: float = 16.0, max_disparity: float = NPIX,
               cap_overflow: bool = False, width_penalty: float = 0.0) -> Candidates:
    """All same-side pairs passing MASL's grey rule whose two edge maps were
    fetched (flag word 1), scored by shape; only those with a disparity above
    EDISP (and at most ``max_disparity``) are kept."""
    left, right = slice_edges(features1), slice_edges(features2)
    if len(left) == 0 or len(right) == 0:
        empty = np.zeros(0, dtype=np.int64)
        return Candidates(left, right, empty, empty, empty.astype(float), empty, empty,
                          empty.astype(float), empty.astype(float))
    # a few edges a slice: one compiled pass over the pairs, not array steps
    # on arrays of a few elements
    pairs = np.empty((len(left) * len(right), 4), dtype=np.int64)
    scores = np.empty((len(left) * len(right), 3), dtype=np.float64)
    n = admissible_pairs(left.pair_rows, np.asarray(maps1, dtype=np.int64)[left.edge - 1],
                         right.pair_rows,
                         np.asarray(maps2, dtype=np.int64)[right.edge - 1],
                         use_shift, float(grey_penalty), float(width_penalty),
                         float(max_disparity), cap_overflow, _POP, pairs, scores)
    ii, jj, shift, shape = pairs[:n].T.copy()
    cost, loc1, loc2 = scores[:n].T.copy()
    return Candidates(left, right, ii, jj, cost, shape, shift, loc1, loc2)
