"""NSTAR's two bit maps: the scaled 16x16 block map of a region (command 1,
labels 290-390) and the unscaled 16x16 edge bit map (command 4, label 500).

A map is 16 column words, column 1 leftmost, bit 0 the top row.
"""

from __future__ import annotations

import numpy as np

from diskfmt.dgreal import Real
from diskfmt.jit import jit
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


@jit
def edge_map_kernel(frame, ixc, iyc, idn, ixmin, ixmax, iymin, iymax, out):
    """Label 500 on the frame-store array (the RVBLK reads of the listing are
    slices of ``frame``; a sample off the frame store reads 0, QUIRKS M8).
    Fills ``out`` with the 16 column words."""
    ixlft = ixc - 7
    iytop = iyc - 7
    # IXC+IDN+IDN in 16-bit INTEGER arithmetic (QUIRKS M5): a wild IDN from a
    # peer wraps as on the NOVA, and an RVBLK off the frame store reads 0 (M8,
    # N22) -- the same reply from both kernels, never memory outside ``frame``.
    ixm = min(ixc, ((ixc + idn + idn + 32768) & 65535) - 32768)
    igmn = 15
    igmx = 0
    for r in range(iyc, iyc + 3):                # RVBLK(ICT,IDAT,IXM,2,IYC,3)
        for c in range(ixm, ixm + 2):
            v = 0
            if 0 <= r < frame.shape[0] and 0 <= c < frame.shape[1]:
                v = frame[r, c]
            igmn = min(igmn, v)
            igmx = max(igmx, v)
    for col in range(16):
        ixloc = ixlft + col
        iword = 0
        if ixmin <= ixloc <= ixmax:
            for k in range(16):
                iyloc = iytop + k
                if iyloc < iymin or iymax < iyloc:
                    continue
                ipix = 0
                if 0 <= iyloc < frame.shape[0] and 0 <= ixloc < frame.shape[1]:
                    ipix = frame[iyloc, ixloc]
                if igmn <= ipix <= igmx:
                    iword |= 1 << k
        out[col] = iword - 65536 if iword > 32767 else iword    # 16-bit word
    return ixlft, iytop


@jit
def command_geometry(imf, ixctr, iyctr):
    """NSTAR label 100 after reading NCONT.DT: the picture's frame-store offset
    (26 for image 1, else 166), its bounds, and the centre clamped to the
    picture and moved to frame-store coordinates.  Returns
    (IXOFF, IXMIN, IXMAX, IYMIN, IYMAX, IXCTR, IYCTR, IXC, IYC)."""
    ixoff = 26 if imf == 1 else 26 + 140
    ixmin = 0 + ixoff
    ixmax = 127 + ixoff
    iyoff = 0
    iymin = 0 + iyoff
    iymax = 119 + iyoff
    ixctr = min(max(ixctr, 0), 127)
    iyctr = min(max(iyctr, 0), 119)
    return ixoff, ixmin, ixmax, iymin, iymax, ixctr, iyctr, ixctr + ixoff, iyctr + iyoff


@jit
def edge_map_batch(frame, words, out, corners):
    """Many code-4 commands (rows of NCONT.DT words) at once: row k of ``out``
    receives WBMAP.DT's 17 words (1, then the map), ``corners[k]`` the window's
    top-left corner."""
    for k in range(words.shape[0]):
        _, ixmin, ixmax, iymin, iymax, _, _, ixc, iyc = command_geometry(
            words[k, 1], words[k, 2], words[k, 3])
        out[k, 0] = 1
        ixlft, iytop = edge_map_kernel(frame, ixc, iyc, words[k, 5], ixmin, ixmax,
                                       iymin, iymax, out[k, 1:])
        corners[k, 0] = ixlft
        corners[k, 1] = iytop


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
    out = np.zeros(16, dtype=np.int64)
    ixlft, iytop = edge_map_kernel(octek.frame, int(ixc), int(iyc), int(idn),
                                   int(ixmin), int(ixmax), int(iymin), int(iymax), out)
    return out.tolist(), int(ixlft), int(iytop)
