"""The Star filter: radial lines around a point (RADLN.FR, RADSP.FR), the
direction cosines NSTAR sets up, and IGCD.FR.

All REAL work is Data General arithmetic (truncating), as on the NOVA: the ray
ratios ``XRAT`` and the pixel positions ``(HYP*CAX)+IXCTR`` decide which pixel
a ray visits, so IEEE rounding would visit different pixels.
"""

from __future__ import annotations

import math

from diskfmt.dgreal import Real
from .exqvfl import exqvfl, feature_list
from .printouts import Debug, prqvfl
from diskfmt.listing import fi

SQRT2 = Real.from_float(math.sqrt(2.0))          # SQRT(2.0), truncated (QUIRKS M3)


def direction_cosines() -> tuple[list[Real], list[Real]]:
    """NSTAR's CA1/CA2: cosines and sines of 0, 22.5, 45, 67.5 degrees.

    ``PI=3.1415926``, ``PID8=PI/8.0``, ``CA1(k)=COS(PID8*(k-1))`` with CA1(1)=1
    and CA2 the same values in reverse (CA2(1)=0)."""
    pi = Real.const("3.1415926")
    pid8 = pi / Real.const("8.0")
    ca1 = [Real.from_int(1),
           Real.from_float(math.cos(pid8.fraction())),
           Real.from_float(math.cos((pid8 * Real.const("2.0")).fraction())),
           Real.from_float(math.cos((pid8 * Real.const("3.0")).fraction()))]
    ca2 = [Real.from_int(0), ca1[3], ca1[2], ca1[1]]
    return ca1, ca2


def igcd(ix: int, iy: int) -> int:
    """IGCD — greatest common divisor by repeated remainders (the listing calls
    it the Chinese remainder theorem; it is Euclid)."""
    ix1, iy1 = max(ix, iy), min(ix, iy)
    while True:
        irem = ix1 % iy1          # both positive here, so Python % agrees with MOD
        if irem <= 0:
            return iy1
        ix1, iy1 = max(irem, iy1), min(irem, iy1)


def ilcm(ix: int, iy: int) -> int:
    """The statement function ``ILCM(IX,IY)=(IX*IY)/IGCD(IX,IY)``."""
    return (ix * iy) // igcd(ix, iy)


def radln(octek, idir: list[int], np_: int, cax: Real, cay: Real, bounds) -> tuple[list[int], int]:
    """RADLN — read one radial line of pixels from the frame store.

    ``idir`` is IDIR(1..7) as a 0-based list, updated in place (end point and
    count, image-relative).  ``bounds`` is COMMON /IMAGE/ as RADLN names it —
    IXMIN, IXMAX, IYMIN, IYMAX — which positionally is NSTAR's IXOFF, IXMAX,
    IYOFF, IYMAX (COMMON is positional, QUIRKS N1).  Returns the pixels and the clamped NP."""
    ixmin, ixmax, iymin, iymax = bounds
    ixctr = idir[1] + ixmin
    iyctr = idir[2] + iymin
    ndp = 0
    ix, iy = ixctr, iyctr
    np_ = min(max(np_, 1), 60)                   # actions cut off in the OCR (QUIRKS N11)
    irad: list[int] = []
    for i in range(1, np_ + 1):
        hyp = Real.from_int(i - 1) * SQRT2
        ixloc = int(hyp * cax + ixctr)           # REAL -> INTEGER truncates toward zero
        iyloc = int(hyp * cay + iyctr)
        if ixloc < ixmin or ixloc > ixmax or iyloc < iymin or iyloc > iymax:
            break
        ix, iy = ixloc, iyloc
        ndp += 1
        irad.append(octek.irdpix(ix, iy))
    idir[3] = ix - ixmin
    idir[4] = iy - iymin
    idir[5] = ndp
    return irad, np_


def radsp(octek, isx: int, isy: int, cax, cay, icntr: list[int], ifbuf, bounds,
          debug: int = 0, listing=None, console=None) -> None:
    """RADSP — one quadrant of the Star pattern: four rays, each through EXQVFL
    (threshold 1); the region extremes met along the rays widen ICNTR
    (leftmost, rightmost, top, bottom, min grey, max grey) in place.

    ``ifbuf`` is NSTAR's COMMON buffer IFBUF(256) (a numpy int array): IDIR is
    words 1-7, NFEAT 8, IFIRST 9, ILAST 10, IFEAT from 11 — the rays leave their
    features there, as in 1985."""
    idir = [int(v) for v in ifbuf[0:7]]
    if console is not None:
        console.type(" RADSP called, quadrant=", idir[0], " IMAGE ", idir[6])
    iqoff = idir[0]
    np_ = idir[5]
    ixmn = ixmx = idir[1]
    iymn = iymx = idir[2]
    igmn, igmx = 15, 0
    ifeat = ifbuf[10:210].reshape(4, 50)
    for ident in range(1, 5):
        cx = cax[ident - 1] * isx
        cy = cay[ident - 1] * isy
        idir[0] = iqoff + ident
        idat, np_ = radln(octek, idir, np_, cx, cy, bounds)
        ixl = idir[5]
        nfeat, _ = exqvfl(idat, 1, ifeat, ilast=ixl,
                          warn=console.type if console is not None else None)
        ifbuf[0:7] = idir
        ifbuf[7] = nfeat
        if debug & Debug.RAY_VALUES and listing is not None:
            listing.record(" -- RADSP -- IDIR = " + "".join(fi(v, 5) for v in idir)
                           + " NFEAT= " + fi(nfeat, 3))
        if debug & Debug.FEATURE_LISTS and listing is not None:
            listing.records(prqvfl(nfeat, feature_list(nfeat, ifeat)))
        ifirst, ilast = idat[0], idat[ixl - 1]
        ifbuf[8], ifbuf[9] = ifirst, ilast
        ix1, ix2, iy1, iy2 = idir[1], idir[3], idir[2], idir[4]
        ig1, ig2 = ifirst, ilast
        if nfeat >= 1:
            indx = int(ifeat[0][0]) - 1
            rp = Real.from_int(idir[5])
            xrat = Real.from_int(idir[3] - ix1) / rp
            ix2 = int(ix1 + xrat * indx)
            yrat = Real.from_int(idir[4] - iy1) / rp
            iy2 = int(iy1 + yrat * indx)
            ig2 = int(ifeat[2][0])
        ixmn, ixmx = min(ixmn, ix1, ix2), max(ixmx, ix1, ix2)
        iymn, iymx = min(iymn, iy1, iy2), max(iymx, iy1, iy2)
        igmn, igmx = min(igmn, ig1, ig2), max(igmx, ig1, ig2)
    icntr[0] = min(icntr[0], ixmn)
    icntr[1] = max(icntr[1], ixmx)
    icntr[2] = min(icntr[2], iymn)
    icntr[3] = max(icntr[3], iymx)
    icntr[4] = min(icntr[4], igmn)
    icntr[5] = max(icntr[5], igmx)
