"""NSTAR's debug printouts, shared with ESTAR as in 1985 (PRQVFL.FR and PRBM.FR
are "listed under NSTAR" and linked into both programs)."""

from __future__ import annotations

from enum import IntFlag

from diskfmt.listing import fi


class Debug(IntFlag):
    """NSTAR's debug flags: which listings its commands print."""
    RAY_VALUES = 1         # RADSP: each Star ray's IDIR and feature count
    FEATURE_LISTS = 2      # PRQVFL of each ray
    CENTRE_BLOB = 4        # command 1's centre blob
    BLOB_MAP = 8           # command 1's block bit map (PRBM)
    EDGE_MAPS = 16         # command 4's edge bit maps (PREM)


def prqvfl(nfeat: int, features) -> list[str]:
    """PRQVFL — print the Queen Victoria feature list (FORMAT 1000, 1001).

    ``features``: (start, stop, left grey, right grey) rows, at least NFEAT."""
    out = [" 1-Dimensional Slice Feature List",
           " There are " + fi(nfeat, 3) + " features in the slice.",
           " INDEX   START   STOP    GRYL   GRYR"]
    for indx in range(1, nfeat + 1):
        s, e, gl, gr = features[indx - 1]
        # FORMAT(4X,I3,6X,2(I3,5X),2(I2,5X)): the first of the 4X is carriage control.
        out.append("    " + fi(indx, 3) + " " * 6 + fi(s, 3) + " " * 5 + fi(e, 3) + " " * 5
                   + fi(gl, 2) + " " * 5 + fi(gr, 2))
    return out


BORDER = "." * 18


def prbm(columns) -> list[str]:
    """PRBM / PREM — print one 16x16 bit map: row 1 is bit 0 of every column
    word, column 1 the leftmost word; a set bit prints '*' (IOUT="**" through
    A1 shows one character)."""
    out = ["", "", " Bit map.", "      " + BORDER]     # FORMAT(6X,...)
    for row in range(16):
        mask = 1 << row
        cells = "".join("*" if (int(c) & 0xFFFF) & mask else " " for c in columns[:16])
        out.append(" " + fi(row + 1, 3) + " ." + cells + ".")
    out += ["      " + BORDER, "", " "]
    return out
