"""Feature matching: MASL.FR, MARF.FR, BMCP.FR, ICBIT.FR.

Edge k is the left end of left-slice feature k, edge 50+k its right end.  For
every pair of same-side edges whose grey levels (left grey for left edges, right
grey for right edges) differ by at most 1, MARF fetches both 16x16 edge bit maps
from the NOVA (once per edge per line) and slides them against each other within
a shift bound; the best shift and its mismatch become one entry of the edge's
match list, kept sorted by quality (smaller is better), at most 10 entries.
"""

from __future__ import annotations

from dataclasses import dataclass, field

# MASL reads NPIX1/NPIX2, which nothing sets; Appendix D (edge 62 matched at 71,
# a shift of +1 past the last feature) shows they acted as the slice length.
NPIX1 = NPIX2 = 128


@dataclass
class Options:
    """Deliberate departures from 1985, each off by default."""
    marf_sign_fix: bool = False      # store LOC2 = x - shift, consistent with the geometry


def icbit(iword: int) -> int:
    """ICBIT — number of bits set in a 16-bit word."""
    return bin(int(iword) & 0xFFFF).count("1")


def bmcp(inum: int, ibm1, ibm2) -> tuple[int, int, int]:
    """BMCP — compare INUM column words: bits in each map and bits that differ.
    A non-positive INUM compares nothing (zero-trip DO, RIG-NOTES §1)."""
    n1 = n2 = nd = 0
    for iloc in range(max(inum, 0)):
        w1, w2 = int(ibm1[iloc]) & 0xFFFF, int(ibm2[iloc]) & 0xFFFF
        n1 += icbit(w1)
        n2 += icbit(w2)
        nd += icbit(w1 ^ w2)          # IXOR=(.NOT. IAND) .AND. IOR
    return n1, n2, nd


def marf_shift(ibm1, ibm2, iwst: int) -> tuple[int, int, list[tuple[int, int]]]:
    """MARF's search — for shifts -IWST..IWST, the mismatch ``(ND*256)/NTOT``
    (256 when no bits, or when ND >= 128 would overflow 16 bits); the smallest
    wins, ties going to the shift nearest zero (the earlier one when equally
    near).  ``ibm1``/``ibm2`` are the 17-word maps (word 1 the flag).
    Returns (MLOC, MNVAL, [(shift, value), ...])."""
    mnval, mloc = 256, 0
    tried = []
    for ipos in range(-iwst, iwst + 1):
        ioff = abs(ipos)
        inum = 16 - ioff
        if ipos < 0:
            n1, n2, nd = bmcp(inum, ibm1[1:], ibm2[ioff + 1:])
        else:
            n1, n2, nd = bmcp(inum, ibm1[ioff + 1:], ibm2[1:])
        ntot = n1 + n2
        ival = 256
        if ntot != 0 and nd < 128:
            ival = (nd * 256) // ntot
        tried.append((ipos, ival))
        if mnval < ival:
            continue
        if mnval == ival and abs(mloc) <= abs(ipos):
            continue
        mnval, mloc = ival, ipos
    return mloc, mnval, tried


@dataclass
class MatchTables:
    """COMMON /MATCH/: NMATCH(100) and IMATCH(100,10,4), kept across lines as in
    1985 (only the first NMATCH entries of a list are ever read)."""
    nmatch: list[int] = field(default_factory=lambda: [0] * 100)
    imatch: list[list[list[int]]] = field(
        default_factory=lambda: [[[0, 0, 0, 0] for _ in range(10)] for _ in range(100)])

    def entries(self, edge: int) -> list[tuple[int, int, int, int]]:
        """Match list of edge ``edge`` (1-based): (INDX, QUAL, LOC1, LOC2) rows."""
        return [tuple(e) for e in self.imatch[edge - 1][:self.nmatch[edge - 1]]]


def _insert(table: list[list[int]], count: int, lmatch: list[int]) -> int:
    """MASL labels 100-210 (and 600-710): insert LMATCH(1..4) into a match list
    of ``count`` entries sorted by quality, at most 10; returns the new count."""
    iqm = lmatch[1]
    if count < 1:
        count, ispt = 1, 1
    elif iqm >= table[count - 1][1]:
        if count >= 10:
            return count                      # worse than a full list's bottom: dropped
        count += 1
        ispt = count
    else:
        inum = count
        if count < 10:
            count += 1
        ispt = 1
        for i in range(1, inum + 1):
            ispt = inum - i + 1
            if ispt != 10:
                table[ispt] = list(table[ispt - 1])      # move entry down
            if ispt >= 2 and iqm >= table[ispt - 2][1]:
                break
        else:
            ispt = 1
    table[ispt - 1] = list(lmatch[:4])
    return count


def _search_bounds(ifeat, nfeat: int, indx: int, npix: int) -> tuple[int, int]:
    """Shift bounds IRGDL/IRGDR of feature INDX: half the gap to the neighbouring
    feature (or to the slice end), at most half the feature's width, at least 0."""
    start, stop = ifeat[0][indx - 1], ifeat[1][indx - 1]
    half_width = _div(stop - start, 2)
    left = start if indx == 1 else _div(start - ifeat[1][indx - 2], 2)
    right = npix - stop + 1 if indx >= nfeat else _div(ifeat[0][indx] - stop, 2)
    left = max(min(left, half_width), 0)
    right = max(min(right, half_width), 0)
    return left, right


def _div(a: int, b: int) -> int:
    """FORTRAN INTEGER division: truncates toward zero."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def masl(iyloc: int, nfeat1: int, ifeat1, nfeat2: int, ifeat2, iblb1, iblb2,
         tables: MatchTables, link, debug: int = 0, listing=None, console=None,
         options: Options | None = None) -> None:
    """MASL — build the match lists of every edge of slice 1 against slice 2.

    ``ifeat1``/``ifeat2``: IFEAT(50,4) as four columns; ``iblb1``/``iblb2``:
    100 lists of 17 words (the per-line bit-map caches, flag word first)."""
    options = options or Options()
    say = console.type if console is not None else (lambda *a: None)
    for indx in range(1, nfeat1 + 1):
        kndx = indx + 50
        inuml = inumr = 0
        ilocl, ilocr = ifeat1[0][indx - 1], ifeat1[1][indx - 1]
        irgdl, irgdr = _search_bounds(ifeat1, nfeat1, indx, NPIX1)
        igryl, igryr = ifeat1[2][indx - 1], ifeat1[3][indx - 1]
        for jndx in range(1, nfeat2 + 1):
            lndx = jndx + 50
            jlocl, jlocr = ifeat2[0][jndx - 1], ifeat2[1][jndx - 1]
            jrgdl, jrgdr = _search_bounds(ifeat2, nfeat2, jndx, NPIX2)
            jgryl, jgryr = ifeat2[2][jndx - 1], ifeat2[3][jndx - 1]
            for side, (inum_ref, edge1, edge2, loc1, loc2, rg1, rg2, g1, g2) in (
                    (-1, (None, indx, jndx, ilocl, jlocl, irgdl, jrgdl, igryl, jgryl)),
                    (+1, (None, kndx, lndx, ilocr, jlocr, irgdr, jrgdr, igryr, jgryr))):
                if abs(g1 - g2) > 1:
                    continue
                lmatch = [edge2, 9999, loc1, loc2, rg1, rg2, side, iyloc]
                say(" Comparing ", edge1, " and ", edge2)
                if debug & 32 and listing is not None:
                    listing.records(["", (" Comparing left sides of " if side < 0 else
                                          " Comparing right sides of ")
                                     + f"{edge1:3d} and {edge2:3d}"])
                marf(lmatch, iblb1[edge1 - 1], iblb2[edge2 - 1], link, debug, listing, options)
                if debug & 32 and listing is not None:
                    listing.records(["", "", " "])
                if lmatch[2] <= lmatch[3]:
                    continue                          # LOC1 must lie right of LOC2
                table = tables.imatch[edge1 - 1]
                if side < 0:
                    inuml = _insert(table, inuml, lmatch)
                else:
                    inumr = _insert(table, inumr, lmatch)
        if debug & 32 and listing is not None:
            listing.records([" Match lists generated.",
                             f" INDX={indx:4d}  INUML={inuml:4d}",
                             f" KNDX={kndx:4d}  INUMR={inumr:4d}", ""])
        tables.nmatch[indx - 1] = inuml
        tables.nmatch[kndx - 1] = inumr


def marf(lmatch: list[int], ibm1: list[int], ibm2: list[int], link, debug: int = 0,
         listing=None, options: Options | None = None) -> None:
    """MARF — refine one match guess: fetch missing edge maps from the NOVA,
    find the best shift, store the quality in LMATCH(2) and the shifted slice-2
    location in LMATCH(4).

    The 1985 sign is kept (RIG-NOTES §5, QUIRKS E7): for shift s >= 0 map-1
    column c+s is paired with map-2 column c, which puts the edge at x - s in
    slice 2, yet LOC2 = x + s is stored; ``marf_sign_fix`` stores x - s."""
    iyloc = lmatch[7]
    ies = lmatch[6]
    if ibm1[0] != 1:
        link.nblob(1, lmatch[2], iyloc, ies, ibm1)
    if ibm2[0] != 1:
        link.nblob(2, lmatch[3], iyloc, ies, ibm2)
    if debug & 32 and listing is not None:
        listing.records(compared_maps(ibm1, ibm2))
    iwst = min(lmatch[4], lmatch[5])
    mloc, mnval, _ = marf_shift(ibm1, ibm2, iwst)
    if debug & 32 and listing is not None:
        listing.records(["", f" Best match is at shift = {mloc:2d} Quality ={mnval:4d}", "", ""])
    if options is not None and options.marf_sign_fix:
        lmatch[3] -= mloc
    else:
        lmatch[3] += mloc
    lmatch[1] = mnval


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
