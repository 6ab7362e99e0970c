"""Side by side: the production-system QV (Chapter II) against EXQVFL (NSTAR).

Both reduce one line of pixels to edge intervals with 1-based pixel indices:
EXQVFL gives (start, stop, left grey, right grey) for each edge feature; the
production system gives G+ and G- terminal symbols with their intervals and
end greys.  For every row of a picture we count

* ``exact``: EXQVFL features whose (start, stop) is a QV edge interval;
* ``near``: features whose two ends are each within one pixel of a QV edge
  interval's (and not exact);
* ``overlap``: features that only overlap some QV edge interval;
* ``missed``: EXQVFL features with no QV edge interval overlapping them;
* ``qv_only``: QV edge intervals that overlap no EXQVFL feature;
* ``rows_same``: rows whose two interval lists are identical.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from nstar.exqvfl import exqvfl, feature_list

from .qv_production import RULES, edge_intervals, qv_line


@dataclass
class Agreement:
    rows: int = 0
    rows_same: int = 0
    n_ex: int = 0
    n_qv: int = 0
    exact: int = 0
    exact_grey: int = 0
    near: int = 0
    overlap: int = 0
    missed: int = 0
    qv_only: int = 0
    examples: list = field(default_factory=list)

    def pct(self, n: int, of: int | None = None) -> float:
        d = self.n_ex if of is None else of
        return 100.0 * n / d if d else 0.0


def compare_line(pixels, t: int, agg: Agreement | None = None, row: int | None = None,
                 rules=RULES) -> Agreement:
    """Compare one line; accumulates into ``agg``."""
    agg = agg if agg is not None else Agreement()
    px = [int(v) for v in pixels]
    nfeat, ifeat = exqvfl(px, t)
    ex = feature_list(nfeat, ifeat)
    qv = edge_intervals(qv_line(px, t, rules))
    agg.rows += 1
    agg.n_ex += len(ex)
    agg.n_qv += len(qv)
    ex_iv = [(a, b) for a, b, _, _ in ex]
    qv_iv = [(a, b) for a, b, _, _ in qv]
    if ex_iv == qv_iv:
        agg.rows_same += 1
    elif len(agg.examples) < 5:
        agg.examples.append((row, ex_iv, qv_iv))
    for a, b, gl, gr in ex:
        if (a, b) in qv_iv:
            agg.exact += 1
            k = qv_iv.index((a, b))
            if (qv[k][2], qv[k][3]) == (gl, gr):
                agg.exact_grey += 1
        elif any(abs(a - c) <= 1 and abs(b - d) <= 1 for c, d in qv_iv):
            agg.near += 1
        elif any(c <= b and a <= d for c, d in qv_iv):
            agg.overlap += 1
        else:
            agg.missed += 1
    for c, d in qv_iv:
        if not any(c <= b and a <= d for a, b in ex_iv):
            agg.qv_only += 1
    return agg


def compare_picture(picture: np.ndarray, t: int, rules=RULES) -> Agreement:
    """Compare every row of a picture (NSTAR's slices are rows)."""
    agg = Agreement()
    for r, row in enumerate(np.asarray(picture)):
        compare_line(row, t, agg, r, rules)
    return agg


def report(a: Agreement, name: str = "picture") -> str:
    lines = [
        f"{name}: {a.rows} rows; EXQVFL {a.n_ex} edge features, production QV {a.n_qv} edge intervals",
        f"  identical rows: {a.rows_same} ({a.pct(a.rows_same, a.rows):.1f}%)",
        f"  EXQVFL features matched exactly: {a.exact} ({a.pct(a.exact):.1f}%), "
        f"with the same grey levels: {a.exact_grey} ({a.pct(a.exact_grey):.1f}%)",
        f"  ends within one pixel: {a.near} ({a.pct(a.near):.1f}%); only overlapping: "
        f"{a.overlap} ({a.pct(a.overlap):.1f}%); missed by QV: {a.missed} ({a.pct(a.missed):.1f}%)",
        f"  QV edge intervals EXQVFL does not have: {a.qv_only} ({a.pct(a.qv_only, a.n_qv):.1f}% of QV)",
    ]
    return "\n".join(lines)
