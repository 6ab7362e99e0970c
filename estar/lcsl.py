"""LCSL.FR — locate matched edges in 3-D relative to the left camera, with error
bounds (Appendix A), in Data General REAL arithmetic.

For each edge the first entry of its match list with a disparity greater than
EDISP = 1 pixel is used: range ``dp = ds*dv/disp``; offsets ``dx = DL*dp/dv``,
``dy = DD*dp/dv`` with DL, DD measured from pixel 60 (not 64: kept, RIG-NOTES
§5); range error ``ep = ds*dv*EDISP / (disp^2 - disp*EDISP)``; offset errors
from the location errors ELMAX = ERMAX = EDMAX = 0.5.  POS(1,k) = -1 marks
"no data point"; the other five values of such an edge are left as they were
(COMMON /POSIT/ persists across lines, RIG-NOTES §4).
"""

from __future__ import annotations

from diskfmt.dgreal import Real

MINUS_ONE = Real.from_int(-1)
ONE = Real.const("1.0")


def lcsl(iyloc: int, nfeat1: int, tables, pos: list[Real], dsep: Real, dvirt: Real) -> None:
    """LCSL(IYLOC, NFEAT1, NMATCH, IMATCH, POS) — fill POS(6,100) (a flat list
    of 640 REALs, POS(i,k) at ``(k-1)*6 + i-1``) in place."""
    dcons = dsep * dvirt
    dvi = ONE / dvirt
    dd = Real.from_int(iyloc - 60)
    elmax = Real.const("0.5")
    ermax = Real.const("0.5")
    edisp = elmax + ermax
    edmax = Real.const("0.5")
    for indx in range(1, nfeat1 + 1):
        for edge in (indx, indx + 50):
            base = (edge - 1) * 6
            pos[base] = MINUS_ONE
            for _, _, loc1, loc2 in tables.entries(edge):
                dl = Real.from_int(loc1 - 60)
                dr = Real.from_int(loc2 - 60)
                disp = dl - dr
                if disp >= ONE and not edisp >= disp:
                    dp = dcons / disp
                    pos[base] = dp
                    pos[base + 1] = dl * dp * dvi
                    pos[base + 2] = dd * dp * dvi
                    denom = disp * disp - disp * edisp
                    epmax = dcons * edisp / denom
                    pos[base + 3] = epmax
                    pos[base + 4] = (abs(dl) * epmax + dp * elmax + epmax * elmax) * dvi
                    pos[base + 5] = (abs(dd) * epmax + dp * edmax + epmax * edmax) * dvi
                if pos[base] > ONE:
                    break
