"""MARF.FR, BMCP.FR, ICBIT.FR — how well two 16x16 edge bit maps match.

A bit map as MARF sees it is 17 words: word 1 the "map present" flag (1), words
2..17 the 16 columns (column 1 leftmost), one bit per row.  MARF slides map 1
against map 2 by -IWST..IWST columns; for each shift BMCP counts the bits of
the overlapping columns of each map and the bits that differ (ICBIT counts the
bits of a word), and the mismatch ``(ND*256)/NTOT`` is its quality (smaller is
better).  The NBLOB calls MARF makes for a missing map are sent by MASL
beforehand (:func:`estar.masl.masl_requests`), so the routines here are pure.
"""

from __future__ import annotations

import numpy as np

from diskfmt.jit import jit

# Room for every shift MARF can try: a bound is at most half a 128-pixel feature.
MAX_SHIFTS = 2 * 128 + 1


@jit
def _icbit(iword):
    n = 0
    w = iword & 0xFFFF
    while w:
        w &= w - 1
        n += 1
    return n


def icbit(iword: int) -> int:
    """ICBIT — number of bits set in a 16-bit word."""
    return int(_icbit(int(iword)))


@jit
def _bmcp(inum, ibm1, ibm2):
    n1 = 0
    n2 = 0
    nd = 0
    for iloc in range(max(inum, 0)):
        w1 = ibm1[iloc] & 0xFFFF
        w2 = ibm2[iloc] & 0xFFFF
        n1 += _icbit(w1)
        n2 += _icbit(w2)
        nd += _icbit(w1 ^ w2)         # IXOR=(.NOT. IAND) .AND. IOR
    return n1, n2, nd


def bmcp(inum: int, ibm1, ibm2) -> tuple[int, int, int]:
    """BMCP — compare INUM column words: bits in each map and bits that differ.
    A non-positive INUM compares nothing (an empty DO runs zero times, QUIRKS M18)."""
    a = np.asarray(ibm1, dtype=np.int64)
    b = np.asarray(ibm2, dtype=np.int64)
    inum = min(int(inum), len(a), len(b))
    return tuple(int(v) for v in _bmcp(inum, a, b))


@jit
def marf_kernel(ibm1, ibm2, iwst, values):
    """MARF labels 70-200 on the 17-word maps: for shifts -IWST..IWST the
    mismatch ``(ND*256)/NTOT`` of the overlapping columns (256 when no bits, or
    when ND >= 128 would overflow 16 bits); ``values[ipos+IWST]`` receives
    each.  The smallest wins, ties going to the shift nearest zero (the earlier
    one when equally near).  Returns (MLOC, MNVAL)."""
    mnval = 256
    mloc = 0
    for ipos in range(-iwst, iwst + 1):
        ioff = abs(ipos)
        inum = 16 - ioff
        if ipos < 0:
            n1, n2, nd = _bmcp(inum, ibm1[1:], ibm2[ioff + 1:])
        else:
            n1, n2, nd = _bmcp(inum, ibm1[ioff + 1:], ibm2[1:])
        ntot = n1 + n2
        ival = 256
        if ntot != 0 and nd < 128:                   # ND*256 would overflow 16 bits
            ival = (nd * 256) // ntot
        if ipos + iwst < values.shape[0]:            # a wild slice must not write past it
            values[ipos + iwst] = ival
        if mnval < ival:
            continue
        if mnval == ival and abs(mloc) <= abs(ipos):
            continue
        mnval = ival
        mloc = ipos
    return mloc, mnval


@jit
def marf_refine(lmatch, ibm1, ibm2, sign_fix, values):
    """MARF after its NBLOB calls: the best shift within IWST = min(LMATCH(5),
    LMATCH(6)); LMATCH(2) = its quality, LMATCH(4) moved by it.

    The 1985 sign is kept (QUIRKS E7): for a shift s >= 0 map-1 column c+s is
    paired with map-2 column c, which puts the edge at x - s in slice 2, yet
    LOC2 = x + s is stored; ``sign_fix`` stores x - s.  Returns (MLOC, MNVAL)."""
    iwst = min(lmatch[4], lmatch[5])
    mloc, mnval = marf_kernel(ibm1, ibm2, iwst, values)
    lmatch[3] += -mloc if sign_fix else mloc
    lmatch[1] = mnval
    return mloc, mnval


def compared_maps(ibm1, ibm2) -> list[str]:
    """MARF's flag-32 printout: the two 17-word maps side by side (FORMAT 1000-1003)."""
    border = " " + 2 * ("    " + "." * 18)
    out = [" Comparing bit maps.", border]
    for row in range(16):
        mask = 1 << row
        halves = []
        for ibm in (ibm1, ibm2):
            halves.append("    ." + "".join("*" if (int(w) & 0xFFFF) & mask else " "
                                             for w in ibm[1:17]) + ".")
        out.append(" " + "".join(halves))
    out.append(border)
    return out
