"""LCSL.FR — locate matched edges in 3-D relative to the left camera, with error
bounds (Appendix A), in Data General REAL arithmetic.

For each edge the match list is walked in order; every entry with a disparity
greater than EDISP = 1 pixel overwrites the edge's POS column, and the walk
stops at the first whose range exceeds 1.0 (so at a small separation an entry
giving a range of 1.0 or less is passed over for a later one).  Range ``dp = ds*dv/disp``; offsets ``dx = DL*dp/dv``,
``dy = DD*dp/dv`` with DL, DD measured from pixel 60 (not 64: kept,
QUIRKS E6); range error ``ep = ds*dv*EDISP / (disp^2 - disp*EDISP)``; offset errors
from the location errors ELMAX = ERMAX = EDMAX = 0.5.  POS(1,k) = -1 marks
"no data point"; the other five values of such an edge are left as they were
(COMMON /POSIT/ persists across lines, QUIRKS E8).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from diskfmt.dgreal import Real
from .printouts import RIGHT_EDGE

MINUS_ONE = Real.from_int(-1)
ONE = Real.const("1.0")
ELMAX = ERMAX = EDMAX = Real.const("0.5")
EDISP = ELMAX + ERMAX
EDISP_WHOLE = int(EDISP)               # 0.5 + 0.5 is exactly 1.0 in DG REAL too
assert EDISP == EDISP_WHOLE


# Each POS value is a fixed expression of a few small integers (the disparity,
# the offsets DL and DD) and the calibration, so the truncating arithmetic is
# done once per distinct argument and remembered: exact, and it keeps a
# whole-picture scan from redoing the same REAL operations thousands of times.

@lru_cache(maxsize=None)
def _constants(dsep: Real, dvirt: Real) -> tuple[Real, Real]:
    """DCONS=DSEP*DVIRT, DVI=1.0/DVIRT."""
    return dsep * dvirt, ONE / dvirt


@lru_cache(maxsize=None)
def _range_terms(disp: int, dsep: Real, dvirt: Real) -> tuple[Real, Real]:
    """DP=DCONS/DISP; DENOM=DISP*DISP-DISP*EDISP; EPMAX=DCONS*EDISP/DENOM."""
    dcons, _ = _constants(dsep, dvirt)
    d = Real.from_int(disp)
    denom = d * d - d * EDISP
    return dcons / d, dcons * EDISP / denom


@lru_cache(maxsize=None)
def _offset_terms(offset: int, disp: int, emax: Real, dsep: Real, dvirt: Real) -> tuple[Real, Real]:
    """DX=DL*DP*DVI and EXMAX=(ABS(DL)*EPMAX+DP*ELMAX+EPMAX*ELMAX)*DVI (or the
    same for DY, EYMAX with DD and EDMAX), left to right as FORTRAN does."""
    _, dvi = _constants(dsep, dvirt)
    dp, epmax = _range_terms(disp, dsep, dvirt)
    o = Real.from_int(offset)
    return o * dp * dvi, (abs(o) * epmax + dp * emax + epmax * emax) * dvi


def locate(loc1: int, loc2: int, iyloc: int, dsep: Real, dvirt: Real) -> tuple[Real, ...] | None:
    """One match entry: (dp, dx, dy, ep, ex, ey), or None when the disparity is
    not above EDISP (``IF (DISP1 .LT. 1) … IF (EDISP .GE. DISP1)``)."""
    disp = loc1 - loc2
    if disp <= EDISP_WHOLE:            # IF (DISP1 .LT. 1) / IF (EDISP .GE. DISP1)
        return None
    dp, ep = _range_terms(disp, dsep, dvirt)
    dx, ex = _offset_terms(loc1 - 60, disp, ELMAX, dsep, dvirt)
    dy, ey = _offset_terms(iyloc - 60, disp, EDMAX, dsep, dvirt)
    return dp, dx, dy, ep, ex, ey


def lcsl(iyloc: int, nfeat1: int, tables, pos: list[Real], dsep: Real, dvirt: Real
         ) -> dict[int, tuple[int, int, int, int]]:
    """LCSL(IYLOC, NFEAT1, NMATCH, IMATCH, POS) — fill POS(6,100) (a flat list
    of 640 REALs, POS(i,k) at ``(k-1)*6 + i-1``) in place.

    Returns, for every located edge, the match entry (INDX, QUAL, LOC1, LOC2)
    whose values ended in POS: the last usable entry before the walk stopped
    (not part of 1985's output; CSV, PLY and pictures read it)."""
    used = {}
    for indx in range(1, nfeat1 + 1):
        for edge in (indx, indx + RIGHT_EDGE):
            base = (edge - 1) * 6
            pos[base] = MINUS_ONE
            for entry in tables.entries(edge):
                located = locate(entry[2], entry[3], iyloc, dsep, dvirt)
                if located is not None:
                    pos[base:base + 6] = located
                    used[edge] = entry
                if pos[base] > ONE:          # IF (POS(1,INDX) .GT. 1.0) GOTO 15
                    break
    return used


@dataclass(frozen=True)
class Point:
    """One located edge: where LCSL put it, in the left camera's axes (X right,
    Y down, Z forward along the optical axis, in the unit of the camera
    separation), with its error bounds and the match entry it came from.

    The covariance (Appendix A, A-19/A-20) takes the error bounds as two
    standard deviations of independent errors:
    ``C = diag((ep/2)^2, (ex/2)^2, (ey/2)^2)`` in (range, horizontal,
    vertical) order."""
    line: int            # IY, 0..119
    edge: int            # 1..50 left end of feature k, 51..100 right end
    loc1: int            # left-picture index (1-based) of the match LCSL used
    loc2: int            # right-picture index
    dp: float            # range (Z)
    dx: float            # horizontal offset (X, right)
    dy: float            # vertical offset (Y, down)
    ep: float            # error bounds (two standard deviations)
    ex: float
    ey: float

    @property
    def disparity(self) -> int:
        return self.loc1 - self.loc2

    def covariance(self) -> np.ndarray:
        """Equation A-20: diag((Ep/2)^2, (Ex/2)^2, (Ey/2)^2), (range, x, y) order."""
        return np.diag([(self.ep / 2) ** 2, (self.ex / 2) ** 2, (self.ey / 2) ** 2])
