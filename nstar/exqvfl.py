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

from diskfmt.dgreal import Real, HALF

NFMAX = 50
THREE = Real.from_int(3)


def _isgn(i: int) -> int:
    """ISGN (called, not listed): the sign of an INTEGER, -1, 0 or +1."""
    return (i > 0) - (i < 0)


def _mean_plus_half(total: int, count) -> int:
    """``IVAVE=(SUM/INUM)+.5`` with DG REAL arithmetic, truncated to INTEGER."""
    return int(Real.from_int(total) / count + HALF)


def new_ifeat() -> list[list[int]]:
    """IFEAT(50,4) as a Python list of four 50-word columns (all starts, all
    stops, all left greys, all right greys), zero like an uninitialised COMMON."""
    return [[0] * NFMAX for _ in range(4)]


def exqvfl(ipix, ithr: int, ifeat: list[list[int]] | None = None,
           ilast: int | None = None, warn=None) -> tuple[int, list[list[int]]]:
    """EXQVFL(ILAST, IPIX, NFEAT, IFEAT, ITHR).

    ``ipix``: the pixels, ``ipix[0]`` being IPIX(1).  ``ifeat``: the caller's
    IFEAT table, updated in place (entries past NFEAT keep older values, as in
    NSTAR's COMMON buffer); a fresh zero table when omitted.  Returns
    ``(NFEAT, IFEAT)``.  ``warn`` receives the listing's TYPE message when more
    than 50 features are found (the list is then returned unmerged, NFEAT = 50).
    """
    if ifeat is None:
        ifeat = new_ifeat()
    if ilast is None:
        ilast = len(ipix)

    def pix(k: int) -> int:              # IPIX(k), 1-based
        return int(ipix[k - 1])

    start, stop, grey_l, grey_r = ifeat   # IFEAT(.,1) .. IFEAT(.,4), 0-based rows
    jloc = 1
    ipre = 1
    nfeat = 0
    inum = 0
    iloc = ivpre = inext = 0

    label = 100
    while True:
        if label == 100:                                 # start a new slope search
            iloc = ipre
            ivle = pix(iloc)
            ipre = iloc + 1
            if ipre > ilast:
                label = 300
                continue
            ivre = pix(ipre)
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
            ivre = pix(inext)
            idiff = ivre - ivpre
            if _isgn(idiff) == islp:
                label = 120
            elif idiff != 0 or ipass == 1:
                label = 100
            else:
                ipass = 1                                # GOTO 110
        elif label == 120:                               # valid slope: how far?
            ichg = ivre - ivle
            ivpre = ivre
            ipre = inext
            inext += 1
            if inext > ilast:
                label = 200
                continue
            ivre = pix(inext)
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
            ivre = pix(inext)
            idiff = ivre - ivpre
            label = 120 if _isgn(idiff) == islp else 200
        elif label == 200:                               # store the feature
            inum = iloc - jloc + 1
            if inum <= 3:
                isum = sum(pix(k) for k in range(jloc, iloc + 1))
                ivave = _mean_plus_half(isum, inum)
                iv1 = ivave
            else:
                is1 = sum(pix(jloc + k) for k in range(3))
                is2 = sum(pix(iloc - k) for k in range(3))
                ivave = _mean_plus_half(is1, THREE)
                iv1 = _mean_plus_half(is2, THREE)
            if nfeat >= NFMAX:                           # label 500
                if warn is not None:
                    warn("-- EXIDEG -- TOO MANY FEATURES.")
                return nfeat, ifeat
            nfeat += 1
            start[nfeat - 1] = iloc
            stop[nfeat - 1] = ipre
            grey_l[nfeat - 1] = iv1
            grey_r[nfeat - 1] = ivpre
            if nfeat > 1:
                grey_r[nfeat - 2] = ivave
            if inext > ilast:
                label = 300
                continue
            inext = ipre
            jloc = ipre
            label = 100
        elif label == 300:                               # end of the line
            if nfeat <= 0:
                return nfeat, ifeat
            if inum >= 1:
                isum = 0
                inum = 0
                for k in range(3):
                    if jloc + k > iloc:
                        continue
                    inum += 1
                    isum += pix(jloc + k)
                grey_r[nfeat - 1] = _mean_plus_half(isum, inum)
            else:                                        # unreachable once a feature exists
                grey_r[nfeat - 1] = pix(ilast)
            break

    # Label 410: suppress overlapping edge features (merge touching narrow ones).
    ifloc = 1
    for k in range(2, nfeat + 1):        # DO 490 ILOC=2,NFEAT (zero trips if NFEAT=1)
        if stop[ifloc - 1] < start[k - 1]:
            merge = False
        else:
            iwd1 = stop[k - 1] - start[k - 1]
            iwd2 = stop[ifloc - 1] - start[ifloc - 1]
            merge = not (iwd1 > 1 or iwd2 > 1)
        if merge:
            stop[ifloc - 1] = stop[k - 1]
            grey_r[ifloc - 1] = grey_r[k - 1]
        else:
            ifloc += 1
            for col in ifeat:
                col[ifloc - 1] = col[k - 1]
    return ifloc, ifeat


def feature_list(nfeat: int, ifeat: list[list[int]]) -> list[tuple[int, int, int, int]]:
    """The first NFEAT rows of IFEAT as (start, stop, left grey, right grey)."""
    return [tuple(ifeat[j][k] for j in range(4)) for k in range(nfeat)]
