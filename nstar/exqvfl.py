"""EXQVFL — the procedural "Queen Victoria" edge extractor (EXQVFL.FR, Appendix F).

Scans one line of pixels (an epipolar slice or a radial ray) for intervals of
consistent slope ("edge features") and returns, for each, its start and stop
index (1-based, as in the listing) and the grey level on either side.

The control flow is the listing's, label by label, because its quirks are the
specification: a gentle change (|step| <= ITHR) must be confirmed by a second
step of the same sign, one flat pixel is tolerated there; a running slope
survives one small opposite or flat step; the grey level beside a feature is
the mean of up to three pixels of the flat run next to it (REAL arithmetic,
truncated); touching features both at most one pixel wide are merged.
"""

from __future__ import annotations

import numpy as np

from diskfmt.jit import jit

NFMAX = 50
TOO_MANY = "-- EXIDEG -- TOO MANY FEATURES."


@jit
def _isgn(i):
    """ISGN (called, not listed): the sign of an INTEGER, -1, 0 or +1."""
    return 1 if i > 0 else (-1 if i < 0 else 0)


@jit
def mean_plus_half(total, count):
    """``IVAVE=(SUM/INUM)+.5`` truncated to INTEGER, for INUM = 1, 2 or 3.

    On the NOVA this is DG REAL arithmetic: SUM/INUM truncated to six hex
    digits, +.5 truncated, then truncated to INTEGER.  For these divisors the
    fractional part of SUM/INUM is 0, 1/3, 1/2 or 2/3, so truncation never
    carries the sum across an integer and the result is exactly
    ``floor((2*SUM + INUM) / (2*INUM))`` — checked for every reachable SUM
    against :class:`diskfmt.dgreal.Real` in tests/test_exqvfl_kernel.py.  Integer
    arithmetic lets the kernel compile."""
    return (2 * total + count) // (2 * count)


def new_ifeat() -> np.ndarray:
    """IFEAT(50,4) as a (4, 50) array: row j-1 holds IFEAT(.,j) — all starts,
    all stops, all left greys, all right greys (column-major, as on disk); zero
    like an uninitialised COMMON."""
    return np.zeros((4, NFMAX), dtype=np.int32)


@jit
def exqvfl_kernel(ipix, ilast, ithr, ifeat):
    """EXQVFL(ILAST, IPIX, NFEAT, IFEAT, ITHR) on arrays: ``ipix[k-1]`` is IPIX(k),
    ``ifeat[j-1, k-1]`` is IFEAT(k, j), updated in place.  Returns
    ``(NFEAT, too_many)``; ``too_many`` is the listing's label-500 exit."""
    jloc = 1
    ipre = 1
    nfeat = 0
    inum = 0
    iloc = 0
    ivle = ivre = ivpre = inext = islp = ipass = ivave = iv1 = 0

    label = 100
    while True:
        if label == 100:                                 # start a new slope search
            iloc = ipre
            ivle = ipix[iloc - 1]
            ipre = iloc + 1
            if ipre > ilast:
                label = 300
                continue
            ivre = ipix[ipre - 1]
            ichg = ivre - ivle
            islp = _isgn(ichg)
            if islp == 0:
                continue                                 # GOTO 100
            inext = ipre
            if abs(ichg) > ithr:
                label = 120
                continue
            ipass = 0                                    # gentle: allow one flat
            ivpre = ivre
            label = 110
        elif label == 110:
            inext += 1
            if inext > ilast:
                label = 300
                continue
            ivre = ipix[inext - 1]
            idiff = ivre - ivpre
            if _isgn(idiff) == islp:
                label = 120
            elif idiff != 0 or ipass == 1:
                label = 100
            else:
                ipass = 1                                # GOTO 110
        elif label == 120:                               # valid slope: how far?
            ivpre = ivre
            ipre = inext
            inext += 1
            if inext > ilast:
                label = 200
                continue
            ivre = ipix[inext - 1]
            idiff = ivre - ivpre
            if _isgn(idiff) == islp:
                continue                                 # GOTO 120
            if abs(idiff) > ithr:
                label = 200
                continue
            inext += 1                                   # does the slope resume?
            if inext > ilast:
                label = 200
                continue
            ivre = ipix[inext - 1]
            idiff = ivre - ivpre
            label = 120 if _isgn(idiff) == islp else 200
        elif label == 200:                               # store the feature
            inum = iloc - jloc + 1
            if inum <= 3:
                isum = 0
                for k in range(jloc, iloc + 1):
                    isum += ipix[k - 1]
                ivave = mean_plus_half(isum, inum)
                iv1 = ivave
            else:
                is1 = 0
                is2 = 0
                for k in range(3):
                    is1 += ipix[jloc + k - 1]
                    is2 += ipix[iloc - k - 1]
                ivave = mean_plus_half(is1, 3)
                iv1 = mean_plus_half(is2, 3)
            if nfeat >= NFMAX:                           # label 500
                return nfeat, True
            nfeat += 1
            ifeat[0, nfeat - 1] = iloc
            ifeat[1, nfeat - 1] = ipre
            ifeat[2, nfeat - 1] = iv1
            ifeat[3, nfeat - 1] = ivpre
            if nfeat > 1:
                ifeat[3, nfeat - 2] = ivave
            if inext > ilast:
                label = 300
                continue
            inext = ipre
            jloc = ipre
            label = 100
        else:                                            # label 300: end of the line
            if nfeat <= 0:
                return nfeat, False
            end_of_line_grey(ipix, ilast, ifeat, nfeat, jloc, iloc, inum)
            break
    return suppress_overlaps(ifeat, nfeat), False


@jit
def end_of_line_grey(ipix, ilast, ifeat, nfeat, jloc, iloc, inum):
    """Label 300 (end of the line, NFEAT > 0): the last feature's right grey
    IFEAT(NFEAT,4), the mean of up to three pixels from JLOC to ILOC.  Shared
    with the eyes' EXQVFL (eyes/exqvfl.py)."""
    if inum >= 1:
        isum = 0
        inum = 0
        for k in range(3):
            if jloc + k > iloc:
                continue
            inum += 1
            isum += ipix[jloc + k - 1]
        ifeat[3, nfeat - 1] = mean_plus_half(isum, inum)
    else:                                        # unreachable once a feature exists
        ifeat[3, nfeat - 1] = ipix[ilast - 1]


@jit
def suppress_overlaps(ifeat, nfeat):
    """Label 410: suppress overlapping edge features (merge touching narrow
    ones) in IFEAT's first NFEAT entries; returns the new NFEAT.  Shared with
    the eyes' EXQVFL (eyes/exqvfl.py)."""
    ifloc = 1
    for k in range(2, nfeat + 1):        # DO 490 ILOC=2,NFEAT (zero trips if NFEAT=1)
        merge = False
        if ifeat[1, ifloc - 1] >= ifeat[0, k - 1]:
            iwd1 = ifeat[1, k - 1] - ifeat[0, k - 1]
            iwd2 = ifeat[1, ifloc - 1] - ifeat[0, ifloc - 1]
            merge = not (iwd1 > 1 or iwd2 > 1)
        if merge:
            ifeat[1, ifloc - 1] = ifeat[1, k - 1]
            ifeat[3, ifloc - 1] = ifeat[3, k - 1]
        else:
            ifloc += 1
            for j in range(4):
                ifeat[j, ifloc - 1] = ifeat[j, k - 1]
    return ifloc


def exqvfl(ipix, ithr: int, ifeat=None, ilast: int | None = None, warn=None):
    """EXQVFL(ILAST, IPIX, NFEAT, IFEAT, ITHR).

    ``ipix``: the pixels, ``ipix[0]`` being IPIX(1).  ``ifeat``: the caller's
    IFEAT table — a (4, 50) array (or four 50-word lists), updated in place;
    entries past NFEAT keep older values, as in NSTAR's COMMON buffer; a fresh
    zero table when omitted.  Returns ``(NFEAT, IFEAT)``.  ``warn`` receives
    the listing's TYPE message when more than 50 features are found (the list
    is then returned unmerged, NFEAT = 50)."""
    pix = np.ascontiguousarray(ipix, dtype=np.int64)
    if ilast is None:
        ilast = len(pix)
    table = ifeat
    if table is None:
        table = new_ifeat()
    arr = table if isinstance(table, np.ndarray) else np.array(table, dtype=np.int64)
    nfeat, too_many = exqvfl_kernel(pix, int(ilast), int(ithr), arr)
    if arr is not table:                      # write back into the caller's lists
        for j in range(4):
            table[j][:] = [int(v) for v in arr[j]]
    if too_many and warn is not None:
        warn(TOO_MANY)
    return int(nfeat), table


def feature_list(nfeat: int, ifeat: list[list[int]]) -> list[tuple[int, int, int, int]]:
    """The first NFEAT rows of IFEAT as (start, stop, left grey, right grey)."""
    return [tuple(ifeat[j][k] for j in range(4)) for k in range(nfeat)]
