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
from functools import partial

import numpy as np

from diskfmt.jit import jit
from .link import Link

# MASL reads NPIX1/NPIX2, which nothing sets; Appendix D (edge 62 matched at 71,
# a shift of +1 past the last feature) shows they acted as the slice length.
NPIX1 = NPIX2 = 128


@dataclass
class Options:
    """Deliberate departures from 1985, each off by default."""
    marf_sign_fix: bool = False      # store LOC2 = x - shift, consistent with the geometry


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
    A non-positive INUM compares nothing (zero-trip DO, RIG-NOTES §1)."""
    a = np.asarray(ibm1, dtype=np.int64)
    b = np.asarray(ibm2, dtype=np.int64)
    inum = min(int(inum), len(a), len(b))
    return tuple(int(v) for v in _bmcp(inum, a, b))


@jit
def marf_kernel(ibm1, ibm2, iwst, values):
    """MARF labels 70-200 on the 17-word maps: for shifts -IWST..IWST the
    mismatch of the overlapping columns; ``values[ipos+IWST]`` receives each.
    Returns (MLOC, MNVAL)."""
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


def marf_shift(ibm1, ibm2, iwst: int) -> tuple[int, int, list[tuple[int, int]]]:
    """MARF's search — for shifts -IWST..IWST, the mismatch ``(ND*256)/NTOT``
    (256 when no bits, or when ND >= 128 would overflow 16 bits); the smallest
    wins, ties going to the shift nearest zero (the earlier one when equally
    near).  ``ibm1``/``ibm2`` are the 17-word maps (word 1 the flag).
    Returns (MLOC, MNVAL, [(shift, value), ...])."""
    values = np.zeros(2 * max(iwst, 0) + 1, dtype=np.int64)
    mloc, mnval = marf_kernel(_as_words(ibm1), _as_words(ibm2), int(iwst), values)
    return int(mloc), int(mnval), [(p, int(values[p + iwst])) for p in range(-iwst, iwst + 1)]


def _as_words(ibm) -> np.ndarray:
    return ibm if isinstance(ibm, np.ndarray) else np.asarray(ibm, dtype=np.int64)


@jit
def marf_refine(lmatch, ibm1, ibm2, sign_fix, values):
    """MARF after its NBLOB calls: the best shift within min(LMATCH(5),
    LMATCH(6)); LMATCH(2) = its quality, LMATCH(4) moved by it — with the 1985
    sign (QUIRKS E7) unless ``sign_fix``.  Returns (MLOC, MNVAL)."""
    iwst = min(lmatch[4], lmatch[5])
    mloc, mnval = marf_kernel(ibm1, ibm2, iwst, values)
    lmatch[3] += -mloc if sign_fix else mloc
    lmatch[1] = mnval
    return mloc, mnval


# Room for every shift MARF can try: a bound is at most half a 128-pixel feature.
MAX_SHIFTS = 2 * 128 + 1


@dataclass
class MatchTables:
    """COMMON /MATCH/: NMATCH(100) and IMATCH(100,10,4), kept across lines as in
    1985 (only the first NMATCH entries of a list are ever read)."""
    nmatch: np.ndarray = field(default_factory=lambda: np.zeros(100, dtype=np.int64))
    imatch: np.ndarray = field(default_factory=lambda: np.zeros((100, 10, 4), dtype=np.int64))

    def entries(self, edge: int) -> list[tuple[int, int, int, int]]:
        """Match list of edge ``edge`` (1-based): (INDX, QUAL, LOC1, LOC2) rows."""
        return [tuple(e) for e in self.imatch[edge - 1, :self.nmatch[edge - 1]].tolist()]


@jit
def _insert_kernel(table, count, lmatch):
    """MASL labels 100-210 (and 600-710): insert LMATCH(1..4) into a match list
    of ``count`` entries sorted by quality, at most 10; returns the new count.
    An equal quality goes after the entries already there (QUIRKS E19)."""
    iqm = lmatch[1]
    if count < 1:
        count = 1
        ispt = 1
    elif iqm >= table[count - 1, 1]:
        if count >= 10:
            return count                      # worse than a full list's bottom: dropped
        count += 1
        ispt = count
    else:
        inum = count
        if count < 10:
            count += 1
        ispt = 1
        placed = False
        for i in range(1, inum + 1):
            ispt = inum - i + 1
            if ispt != 10:
                for j in range(4):            # move the entry down
                    table[ispt, j] = table[ispt - 1, j]
            if ispt >= 2 and iqm >= table[ispt - 2, 1]:
                placed = True
                break
        if not placed:
            ispt = 1
    for j in range(4):
        table[ispt - 1, j] = lmatch[j]
    return count


@jit
def _div(a, b):
    """FORTRAN INTEGER division: truncates toward zero."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


@jit
def _search_bounds_kernel(ifeat, nfeat, indx, npix):
    """Shift bounds IRGDL/IRGDR of feature INDX: half the gap to the neighbouring
    feature (or to the slice end), at most half the feature's width, at least 0."""
    start = ifeat[0][indx - 1]
    stop = ifeat[1][indx - 1]
    half_width = _div(stop - start, 2)
    left = start if indx == 1 else _div(start - ifeat[1][indx - 2], 2)
    right = npix - stop + 1 if indx >= nfeat else _div(ifeat[0][indx] - stop, 2)
    left = max(min(left, half_width), 0)
    right = max(min(right, half_width), 0)
    return left, right


def _insert(table, count: int, lmatch) -> int:
    """:func:`_insert_kernel` for a list-of-lists table (tests, hand traces)."""
    arr = np.asarray(table, dtype=np.int64)
    count = int(_insert_kernel(arr, int(count), np.asarray(lmatch, dtype=np.int64)))
    if arr is not table:
        for row, values in zip(table, arr):
            row[:] = [int(v) for v in values]
    return count


def _search_bounds(ifeat, nfeat: int, indx: int, npix: int) -> tuple[int, int]:
    """:func:`_search_bounds_kernel` for any IFEAT table (four columns)."""
    left, right = _search_bounds_kernel(np.asarray(ifeat, dtype=np.int64), int(nfeat),
                                        int(indx), int(npix))
    return int(left), int(right)


@jit
def masl_requests(nfeat1, ifeat1, nfeat2, ifeat2, have1, have2, out):
    """The NBLOB requests MASL makes for one line, in the order it makes them
    (MARF asks for the slice-1 map, then the slice-2 map, of every same-side
    pair passing the grey rule, unless the edge's map is cached: ``have1``,
    ``have2`` are the flag words of IBLB1/IBLB2, updated).  Rows of ``out``:
    image, edge (1..100), X (the edge's 1-based slice index), IES.  Returns the
    count."""
    n = 0
    for indx in range(1, nfeat1 + 1):
        for jndx in range(1, nfeat2 + 1):
            for side in range(2):             # left edges, then right edges
                g1 = ifeat1[2 + side][indx - 1]
                g2 = ifeat2[2 + side][jndx - 1]
                if abs(g1 - g2) > 1:
                    continue
                e1 = indx + 50 * side
                e2 = jndx + 50 * side
                ies = -1 if side == 0 else 1
                if not have1[e1 - 1]:
                    have1[e1 - 1] = True
                    out[n, 0] = 1
                    out[n, 1] = e1
                    out[n, 2] = ifeat1[side][indx - 1]
                    out[n, 3] = ies
                    n += 1
                if not have2[e2 - 1]:
                    have2[e2 - 1] = True
                    out[n, 0] = 2
                    out[n, 1] = e2
                    out[n, 2] = ifeat2[side][jndx - 1]
                    out[n, 3] = ies
                    n += 1
    return n


@jit
def masl_kernel(iyloc, nfeat1, ifeat1, nfeat2, ifeat2, iblb1, iblb2, nmatch, imatch,
                sign_fix, log):
    """MASL's loops with MARF inlined, on bit maps already fetched.  Every
    comparison is logged in ``log`` (side, slice-1 edge, slice-2 edge, MLOC,
    MNVAL) for the debug printouts; returns the number of comparisons."""
    nlog = 0
    lmatch = np.zeros(8, dtype=np.int64)
    values = np.zeros(MAX_SHIFTS, dtype=np.int64)
    for indx in range(1, nfeat1 + 1):
        kndx = indx + 50
        inum_side = np.zeros(2, dtype=np.int64)
        irgd = _search_bounds_kernel(ifeat1, nfeat1, indx, NPIX1)   # QUIRKS E4
        for jndx in range(1, nfeat2 + 1):
            jrgd = _search_bounds_kernel(ifeat2, nfeat2, jndx, NPIX2)
            for side in range(2):
                if abs(ifeat1[2 + side][indx - 1] - ifeat2[2 + side][jndx - 1]) > 1:
                    continue
                e1 = indx + 50 * side
                e2 = jndx + 50 * side
                lmatch[0] = e2
                lmatch[1] = 9999
                lmatch[2] = ifeat1[side][indx - 1]
                lmatch[3] = ifeat2[side][jndx - 1]
                lmatch[4] = irgd[side]
                lmatch[5] = jrgd[side]
                lmatch[6] = -1 if side == 0 else 1
                lmatch[7] = iyloc
                mloc, mnval = marf_refine(lmatch, iblb1[e1 - 1], iblb2[e2 - 1], sign_fix, values)
                log[nlog, 0] = side
                log[nlog, 1] = e1
                log[nlog, 2] = e2
                log[nlog, 3] = mloc
                log[nlog, 4] = mnval
                nlog += 1
                if lmatch[2] <= lmatch[3]:
                    continue                           # LOC1 must lie right of LOC2
                inum_side[side] = _insert_kernel(imatch[e1 - 1], inum_side[side], lmatch)
        nmatch[indx - 1] = inum_side[0]
        nmatch[kndx - 1] = inum_side[1]
    return nlog


def masl(iyloc: int, nfeat1: int, ifeat1, nfeat2: int, ifeat2, iblb1, iblb2,
         tables: MatchTables, link, debug: int = 0, listing=None, console=None,
         options: Options | None = None) -> None:
    """MASL — build the match lists of every edge of slice 1 against slice 2.

    ``ifeat1``/``ifeat2``: IFEAT(50,4) as four columns; ``iblb1``/``iblb2``:
    the per-line bit-map caches, 100 rows of 17 words (flag word first).

    In 1985 MARF fetched each missing map from the NOVA as it met it.  The
    maps depend only on the pictures, so the same NBLOB requests are sent here
    first, in the same order and with the same bytes (:func:`masl_requests`),
    then the comparisons run compiled (:func:`masl_kernel`); the lists, and
    the debug printouts, are those of the listing's interleaved loop."""
    options = options or Options()
    f1 = np.asarray(ifeat1, dtype=np.int64)
    f2 = np.asarray(ifeat2, dtype=np.int64)
    requests = np.zeros((200, 4), dtype=np.int64)
    have1 = np.asarray(iblb1, dtype=np.int64)[:, 0] == 1
    have2 = np.asarray(iblb2, dtype=np.int64)[:, 0] == 1
    count = masl_requests(nfeat1, f1, nfeat2, f2, have1, have2, requests)
    # A link with only NBLOB (a test stand-in) gets the requests one by one.
    fetch = getattr(link, "nblob_many", None) or partial(Link.nblob_many, link)
    fetch(requests[:count], iyloc, iblb1, iblb2)
    b1 = iblb1 if isinstance(iblb1, np.ndarray) else np.asarray(iblb1, dtype=np.int64)
    b2 = iblb2 if isinstance(iblb2, np.ndarray) else np.asarray(iblb2, dtype=np.int64)
    log = np.zeros((2 * 50 * 50, 5), dtype=np.int64)
    nlog = masl_kernel(iyloc, nfeat1, f1, nfeat2, f2, b1, b2, tables.nmatch,
                       tables.imatch, options.marf_sign_fix, log)
    if console is not None or (debug & 32 and listing is not None):
        _print_comparisons(log[:nlog], b1, b2, tables, nfeat1, debug, listing, console)


def _print_comparisons(log, b1, b2, tables, nfeat1, debug, listing, console) -> None:
    """MASL's TYPE lines and the flag-32 printout of MASL/MARF, in loop order."""
    printing = debug & 32 and listing is not None
    k = 0
    for indx in range(1, nfeat1 + 1):
        while k < len(log) and (log[k, 1] - 1) % 50 + 1 == indx:
            side, e1, e2, mloc, mnval = (int(v) for v in log[k])
            if console is not None:
                console.type(" Comparing ", e1, " and ", e2)
            if printing:
                listing.records(["", (" Comparing left sides of " if side == 0 else
                                      " Comparing right sides of ") + f"{e1:3d} and {e2:3d}"])
                listing.records(compared_maps(b1[e1 - 1], b2[e2 - 1]))
                listing.records(["", f" Best match is at shift = {mloc:2d} Quality ={mnval:4d}",
                                 "", "", "", "", " "])
            k += 1
        if printing:
            listing.records([" Match lists generated.",
                             f" INDX={indx:4d}  INUML={int(tables.nmatch[indx - 1]):4d}",
                             f" KNDX={indx + 50:4d}  INUMR={int(tables.nmatch[indx + 49]):4d}",
                             ""])


def marf(lmatch: list[int], ibm1, ibm2, link, debug: int = 0,
         listing=None, options: Options | None = None) -> None:
    """MARF — refine one match guess: fetch missing edge maps from the NOVA,
    find the best shift, store the quality in LMATCH(2) and the shifted slice-2
    location in LMATCH(4).  (MASL runs the same steps inside
    :func:`masl_kernel`; this is the routine as the listing has it, for one
    comparison.)

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
    words = np.asarray(lmatch, dtype=np.int64)
    mloc, mnval = marf_refine(words, _as_words(ibm1), _as_words(ibm2),
                              options is not None and options.marf_sign_fix,
                              np.zeros(MAX_SHIFTS, dtype=np.int64))
    lmatch[1], lmatch[3] = int(words[1]), int(words[3])
    if debug & 32 and listing is not None:
        listing.records(["", f" Best match is at shift = {mloc:2d} Quality ={mnval:4d}", "", ""])


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
