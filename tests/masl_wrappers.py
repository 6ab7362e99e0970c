"""Test-only forms of MASL/MARF pieces: the kernels on plain lists, one MARF
comparison with its NBLOB calls as the listing has them, and a link base
for stand-ins that answer NBLOB one map at a time."""

from __future__ import annotations

import numpy as np

from estar.marf import MAX_SHIFTS, compared_maps, marf_kernel, marf_refine
from estar.masl import Options, insert_entry, search_bounds


class OneByOneLink:
    """A stand-in link with only NBLOB: MASL's block of requests, one by one."""

    def nblob_many(self, requests, iyloc, iblb1, iblb2):
        for image, edge, x, ies in requests:
            self.nblob(int(image), int(x), iyloc, int(ies),
                       (iblb1 if image == 1 else iblb2)[edge - 1])


def marf_shift(ibm1, ibm2, iwst: int) -> tuple[int, int, list[tuple[int, int]]]:
    """MARF's search on 17-word maps: (MLOC, MNVAL, [(shift, value), ...])."""
    values = np.zeros(2 * max(iwst, 0) + 1, dtype=np.int64)
    mloc, mnval = marf_kernel(np.asarray(ibm1, dtype=np.int64),
                              np.asarray(ibm2, dtype=np.int64), int(iwst), values)
    return int(mloc), int(mnval), [(p, int(values[p + iwst])) for p in range(-iwst, iwst + 1)]


def marf(lmatch: list[int], ibm1, ibm2, link, debug: int = 0,
         listing=None, options: Options | None = None) -> None:
    """MARF as the listing has it, for one comparison: fetch missing edge maps
    (``IF (IBM1(1) .NE. 1) CALL NBLOB(...)``), find the best shift, store the
    quality in LMATCH(2) and the moved location in LMATCH(4)."""
    iyloc = lmatch[7]
    ies = lmatch[6]
    if ibm1[0] != 1:
        link.nblob(1, lmatch[2], iyloc, ies, ibm1)
    if ibm2[0] != 1:
        link.nblob(2, lmatch[3], iyloc, ies, ibm2)
    if debug & 32 and listing is not None:
        listing.records(compared_maps(ibm1, ibm2))
    words = np.asarray(lmatch, dtype=np.int64)
    mloc, mnval = marf_refine(words, np.asarray(ibm1, dtype=np.int64),
                              np.asarray(ibm2, dtype=np.int64),
                              options is not None and options.marf_sign_fix,
                              np.zeros(MAX_SHIFTS, dtype=np.int64))
    lmatch[1], lmatch[3] = int(words[1]), int(words[3])
    if debug & 32 and listing is not None:
        listing.records(["", f" Best match is at shift = {mloc:2d} Quality ={mnval:4d}", "", ""])


def insert(table, count: int, lmatch) -> int:
    """:func:`estar.masl.insert_entry` on a list-of-lists table."""
    arr = np.asarray(table, dtype=np.int64)
    count = int(insert_entry(arr, int(count), np.asarray(lmatch, dtype=np.int64)))
    for row, values in zip(table, arr):
        row[:] = [int(v) for v in values]
    return count


def bounds(ifeat, nfeat: int, indx: int, npix: int) -> tuple[int, int]:
    """:func:`estar.masl.search_bounds` for any IFEAT table (four columns)."""
    left, right = search_bounds(np.asarray(ifeat, dtype=np.int64), int(nfeat), int(indx),
                                int(npix))
    return int(left), int(right)
