"""MASL.FR — feature matching (the MARF, BMCP, ICBIT it calls: :mod:`estar.marf`).

Edge k is the left end of left-slice feature k, edge 50+k its right end.  For
every pair of same-side edges whose grey levels (left grey for left edges, right
grey for right edges) differ by at most 1, MARF compares both 16x16 edge bit
maps from the NOVA (fetched once per edge per line) within a shift bound; the
best shift and its mismatch become one entry of the edge's match list, kept
sorted by quality (smaller is better), at most 10 entries.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from diskfmt.jit import jit
from diskfmt.layouts import BI_COLS
from .marf import MAX_SHIFTS, compared_maps, marf_refine
from .printouts import RIGHT_EDGE, Debug

# MASL reads NPIX1/NPIX2, which nothing sets; Appendix D (edge 62 matched at 71,
# a shift of +1 past the last feature) shows they acted as the slice length.
NPIX1 = NPIX2 = BI_COLS


@dataclass
class Options:
    """Deliberate departures from 1985, each off by default."""
    marf_sign_fix: bool = False      # store LOC2 = x - shift, consistent with the geometry


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
def insert_entry(table, count, lmatch):
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
def search_bounds(ifeat, nfeat, indx, npix):
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
                e1 = indx + RIGHT_EDGE * side
                e2 = jndx + RIGHT_EDGE * side
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
        kndx = indx + RIGHT_EDGE
        inum_side = np.zeros(2, dtype=np.int64)
        irgd = search_bounds(ifeat1, nfeat1, indx, NPIX1)   # QUIRKS E4
        for jndx in range(1, nfeat2 + 1):
            jrgd = search_bounds(ifeat2, nfeat2, jndx, NPIX2)
            for side in range(2):
                if abs(ifeat1[2 + side][indx - 1] - ifeat2[2 + side][jndx - 1]) > 1:
                    continue
                e1 = indx + RIGHT_EDGE * side
                e2 = jndx + RIGHT_EDGE * side
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
                inum_side[side] = insert_entry(imatch[e1 - 1], inum_side[side], lmatch)
        nmatch[indx - 1] = inum_side[0]
        nmatch[kndx - 1] = inum_side[1]
    return nlog


def masl(iyloc: int, nfeat1: int, ifeat1, nfeat2: int, ifeat2, iblb1, iblb2,
         tables: MatchTables, link, debug: int = 0, listing=None, console=None,
         options: Options | None = None) -> None:
    """MASL — build the match lists of every edge of slice 1 against slice 2.

    ``ifeat1``/``ifeat2``: IFEAT(50,4) as four columns; ``iblb1``/``iblb2``:
    the per-line bit-map caches, 100 rows of 17 words (flag word first);
    ``link``: NSTAR's side, anything with ``nblob_many(requests, iyloc, iblb1,
    iblb2)`` (the matcher does not know which link it is).

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
    link.nblob_many(requests[:count], iyloc, iblb1, iblb2)
    b1 = iblb1 if isinstance(iblb1, np.ndarray) else np.asarray(iblb1, dtype=np.int64)
    b2 = iblb2 if isinstance(iblb2, np.ndarray) else np.asarray(iblb2, dtype=np.int64)
    log = np.zeros((2 * RIGHT_EDGE * RIGHT_EDGE, 5), dtype=np.int64)   # every pair, both sides
    nlog = masl_kernel(iyloc, nfeat1, f1, nfeat2, f2, b1, b2, tables.nmatch,
                       tables.imatch, options.marf_sign_fix, log)
    if console is not None or (debug & Debug.COMPARED_MAPS and listing is not None):
        _print_comparisons(log[:nlog], b1, b2, tables, nfeat1, debug, listing, console)


def _print_comparisons(log, b1, b2, tables, nfeat1, debug, listing, console) -> None:
    """MASL's TYPE lines and the flag-32 printout of MASL/MARF, in loop order."""
    printing = debug & Debug.COMPARED_MAPS and listing is not None
    k = 0
    for indx in range(1, nfeat1 + 1):
        while k < len(log) and (log[k, 1] - 1) % RIGHT_EDGE + 1 == indx:
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
                             f" KNDX={indx + RIGHT_EDGE:4d}  INUMR={int(tables.nmatch[indx + RIGHT_EDGE - 1]):4d}",
                             ""])
