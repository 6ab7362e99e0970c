"""Score located edges against the bundled scene's true range.

An edge, as ESTAR locates it, is ``(IY, LOC1, LOC2, dp, ep)``: the row IY
(0..119) of the 128x120 pictures, the left-image feature index LOC1 and the
right-image index LOC2 (1-based, as in the listing; they may be fractional),
the computed range dp (ft) and its computed error bound ep (ft).

Column convention: a 1-based index LOC1 names array column ``LOC1 - 1`` of the
120x128 truth array (``rig/data/LAB-RANGE.npy``, Z in ft at the centre of
each pixel of the LEFT picture); a fractional LOC1 is rounded to the nearest
index first (halves up).  An edge lies *between* two pixels, and at an
occluding boundary the two sides have different ranges; the edge itself
belongs to the nearer (occluding) surface - the farther surface only stops
there because it is hidden.  EXQVFL's feature indices name a pixel next to the
step on either side, so by default the true range of an edge is the MINIMUM
over columns ``LOC1-1-halfwidth .. LOC1-1+halfwidth`` of its row with
``halfwidth=1``.  Inside a surface (texture, markings) this equals the plain
lookup; ``halfwidth=0`` gives the plain lookup at ``(IY, LOC1-1)``.

All functions are pure; the truth array is passed in or read from the shipped
file, never typed in.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

DEFAULT_BANDS = ((0, 5), (5, 10), (10, 15), (15, 25))


@dataclass(frozen=True)
class Edge:
    """A located edge: row IY 0..119, LOC1/LOC2 1-based, dp and ep in ft."""
    iy: int
    loc1: float
    loc2: float
    dp: float
    ep: float


@dataclass(frozen=True)
class EdgeError:
    """One edge scored against the truth."""
    edge: Edge
    column: int             # 0-based truth column named by LOC1
    true_range: float       # ft
    error: float            # dp - true range, ft
    within_bound: bool      # |error| <= ep
    true_disparity: float   # 0.75*180/true range, 128-px columns
    disparity_error: float  # (LOC1 - LOC2) - true disparity

    @property
    def abs_error(self) -> float:
        return abs(self.error)


def as_edge(e) -> Edge:
    """Accept an :class:`Edge`, a 5-sequence ``(IY, LOC1, LOC2, dp, ep)``, a
    mapping with those keys (any case) or an object with those attributes."""
    if isinstance(e, Edge):
        return e
    names = ("iy", "loc1", "loc2", "dp", "ep")
    if isinstance(e, dict):
        low = {str(k).lower(): v for k, v in e.items()}
        vals = [low[n] for n in names]
    elif isinstance(e, (tuple, list)):
        if len(e) != 5:
            raise ValueError(f"an edge is (IY, LOC1, LOC2, dp, ep), got {len(e)} values")
        vals = list(e)
    else:
        vals = [getattr(e, n) if hasattr(e, n) else getattr(e, n.upper()) for n in names]
    return Edge(int(vals[0]), float(vals[1]), float(vals[2]), float(vals[3]), float(vals[4]))


def load_truth() -> np.ndarray:
    """The shipped true range of the bundled pair (120x128, ft)."""
    from rig.scene import bundled_range
    return bundled_range()


def truth_column(loc1: float) -> int:
    """0-based truth column named by the 1-based index LOC1 (rounded, halves up)."""
    return int(math.floor(float(loc1) + 0.5)) - 1


def true_range_at(truth: np.ndarray, iy: int, loc1: float, halfwidth: int = 1) -> float:
    """True range of an edge at row ``iy``, 1-based left index ``loc1`` (see the
    module docstring for the column convention)."""
    rows, cols = truth.shape
    col = truth_column(loc1)
    if not 0 <= iy < rows:
        raise ValueError(f"row IY={iy} is outside 0..{rows - 1}")
    if not 0 <= col < cols:
        raise ValueError(f"LOC1={loc1} names column {col}, outside 0..{cols - 1}")
    lo, hi = max(0, col - halfwidth), min(cols, col + halfwidth + 1)
    return float(np.min(truth[iy, lo:hi]))


def edge_errors(edges, truth: np.ndarray | None = None, halfwidth: int = 1,
                baseline: float = 0.75, focal: float = 180.0) -> list[EdgeError]:
    """Score each edge: true range, range error dp - Z, whether |error| <= ep,
    and the disparity error (LOC1 - LOC2) - ds*dv/Z."""
    truth = load_truth() if truth is None else np.asarray(truth, dtype=np.float64)
    out = []
    for raw in edges:
        e = as_edge(raw)
        z = true_range_at(truth, e.iy, e.loc1, halfwidth)
        err = e.dp - z
        d_true = baseline * focal / z
        out.append(EdgeError(e, truth_column(e.loc1), z, err, abs(err) <= e.ep,
                             d_true, (e.loc1 - e.loc2) - d_true))
    return out


@dataclass(frozen=True)
class BandRow:
    """One line of the accuracy table: edges whose TRUE range is in [lo, hi)."""
    lo: float
    hi: float
    count: int
    median_abs_error: float      # ft; NaN when count is 0
    share_within_bound: float    # 0..1; NaN when count is 0


def accuracy_table(edges, bands=DEFAULT_BANDS, truth: np.ndarray | None = None,
                   halfwidth: int = 1) -> list[BandRow]:
    """Per true-range band: how many edges, the median |range error| and the
    share of edges whose |error| is within their computed bound ep."""
    scored = edge_errors(edges, truth, halfwidth)
    rows = []
    for lo, hi in bands:
        inside = [s for s in scored if lo <= s.true_range < hi]
        if inside:
            med = float(np.median([s.abs_error for s in inside]))
            share = sum(s.within_bound for s in inside) / len(inside)
        else:
            med = share = float("nan")
        rows.append(BandRow(float(lo), float(hi), len(inside), med, share))
    return rows


def format_table(rows: list[BandRow]) -> str:
    """The accuracy table as fixed-width text."""
    lines = ["range band ft   edges   median |error| ft   |error| <= ep",
             "-------------   -----   -----------------   -------------"]
    for r in rows:
        med = "-" if r.count == 0 else f"{r.median_abs_error:.2f}"
        share = "-" if r.count == 0 else f"{100 * r.share_within_bound:.0f}%"
        lines.append(f"{r.lo:5g} - {r.hi:<5g}   {r.count:5d}   {med:>17}   {share:>13}")
    return "\n".join(lines)
