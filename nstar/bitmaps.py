"""NSTAR's two bit maps: the scaled 16x16 block map of a region (command 1,
labels 290-390) and the unscaled 16x16 edge bit map (command 4, label 500).

A map is 16 column words, column 1 leftmost, bit 0 the top row.
"""

from __future__ import annotations

from diskfmt.dgreal import Real
from diskfmt.layouts import wrap16
from .radial import ilcm

ITHRB = 80                      # a bit is set when more than 80% of its samples are in range


def block_map(octek, ixs: int, iys: int, ixl: int, iyl: int, igmn: int, igmx: int,
              wrap: bool = True, chatter=None) -> list[int]:
    """Labels 290-390 — map an IXL x IYL block at (IXS, IYS) onto 16x16 bits on
    the grid of LCM(IXL,16) x LCM(IYL,16) samples: a bit is set when more than
    80% of its samples lie in the grey range IGMN..IGMX.

    Kept as in 1985 (QUIRKS N5, N6): each column's samples are read from
    ``IDAT(IYII)`` from IYII = 1, i.e. the RVBLK header word comes first and the
    column's last pixel is never used; ``ICNT*100`` wraps at 16 bits, so a bit
    covering more than 327 in-range samples can read as empty (``wrap=False``
    is the named fix)."""
    ixdv = ilcm(ixl, 16)
    ixd = ixdv // ixl
    ixb = ixdv // 16
    iydv = ilcm(iyl, 16)
    iyd = iydv // iyl
    iyb = iydv // 16
    ixip = ixs - 1
    ixbi = 0
    ibmap = [0] * 16
    isum = [0] * 16
    icnt = [0] * 16
    idat = None
    ipix = 0
    for ixdvi in range(1, ixdv + 1):
        if ixdvi % ixb == 1 or ixb == 1:
            ixbi += 1
            if chatter:
                chatter(" New bit column, IXBI=", ixbi)
            isum = [0] * 16
            icnt = [0] * 16
        if ixdvi % ixd == 1 or ixd == 1:
            ixip += 1
            idat = octek.rvblk(ixip, 1, iys, iyl)
        iybi = 0
        iyii = 0
        for iydvi in range(1, iydv + 1):
            if iydvi % iyb == 1 or iyb == 1:
                iybi += 1
            if iydvi % iyd == 1 or iyd == 1:
                iyii += 1
                ipix = int(idat[iyii - 1])          # IDAT(IYII): word 1 is the header
            isum[iybi - 1] += 1
            if igmn <= ipix <= igmx:
                icnt[iybi - 1] += 1
        if ixdvi % ixb == 0:
            word = 0
            for b in range(16):
                product = icnt[b] * 100
                if wrap:
                    product = wrap16(product)
                iper = int(product / isum[b])       # INTEGER division truncates toward zero
                if chatter:
                    chatter(" SUM=", isum[b], " CNT=", icnt[b], " Percent=", iper)
                if iper > ITHRB:
                    word |= 1 << b
            ibmap[ixbi - 1] = wrap16(word)
    return ibmap


def scale_factors(ixl: int, iyl: int) -> tuple[Real, Real]:
    """``SFX=IXL/16.0``, ``SFY=IYL/16.0``."""
    sixteen = Real.const("16.0")
    return Real.from_int(ixl) / sixteen, Real.from_int(iyl) / sixteen


def edge_map(octek, ixc: int, iyc: int, idn: int, bounds) -> tuple[list[int], int, int]:
    """Label 500 — the 16x16 window centred at (IXC, IYC) (frame-store
    coordinates) as bits: a pixel is set when its grey level lies within the
    range of the six pixels sampled beside the edge — two columns starting at
    ``MIN0(IXC, IXC+2*IDN)`` (IDN = -1 left side, +1 right side), rows IYC to
    IYC+2.  (The listing computes ``IYM=IYC-1`` and never uses it: kept, QUIRKS
    N8.)  Columns and rows outside the picture stay 0.

    ``bounds`` = IXMIN, IXMAX, IYMIN, IYMAX of the current image.  Returns the
    16 column words and the window's top-left corner (for the box cursor)."""
    ixmin, ixmax, iymin, iymax = bounds
    ixlft = ixc - 7
    ixrgt = ixlft + 15
    iytop = iyc - 7
    iybot = iytop + 15
    ixm = min(ixc, ixc + idn + idn)
    grey = octek.rvblk(ixm, 2, iyc, 3)
    igmn = min(15, *[int(v) for v in grey[1:7]])
    igmx = max(0, *[int(v) for v in grey[1:7]])
    ibmap = []
    for ixloc in range(ixlft, ixrgt + 1):
        iword = 0
        if ixmin <= ixloc <= ixmax:
            col = octek.rvblk(ixloc, 1, iytop, 16)
            for k, iyloc in enumerate(range(iytop, iybot + 1)):
                if iyloc < iymin or iymax < iyloc:
                    continue
                ipix = int(col[1 + k])
                if igmn <= ipix <= igmx:
                    iword |= 1 << k
        ibmap.append(wrap16(iword))
    return ibmap, ixlft, iytop
