"""ESTAR's debug printouts: PMAL.FR (match lists) and PRFPOS.FR (3-D positions).
PRQVFL and PRBM are NSTAR's (:mod:`nstar.printouts`), linked into both in 1985.

Header lines the OCR cut off are reconstructed from Appendix D's printout
(QUIRKS E12, E13).
"""

from __future__ import annotations

from enum import IntFlag

from diskfmt.listing import fi, ff


class Debug(IntFlag):
    """ESTAR's debug flags (its DEBUG_MENU): which listings LCLN prints."""
    FEATURE_LISTS = 1      # PRQVFL of both slices
    BLOB_MAPS = 2          # the stored edge bit maps (PRBM)
    MATCH_LISTS = 4        # PMAL
    POSITIONS = 8          # PRFPOS, the 3-D position table
    BIT_MAPS = 16          # each map as NBLOB receives it (QUIRKS E11)
    COMPARED_MAPS = 32     # MARF's compared maps and best shifts


RIGHT_EDGE = 50
"""Edge k is the left end of feature k, edge k + RIGHT_EDGE its right end
(IMATCH(100,10,4): two edges for each of at most 50 features)."""


def pmal(nfeat: int, tables) -> list[str]:
    """PMAL — the match lists of the left and right edges of every feature."""
    out = ["1 Feature matches, left and right edges.   Number of features=" + fi(nfeat, 3),
           " IM#1",
           " INDX",
           " # OF",
           " FEATS ID     1    2    3    4    5    6    7    8    9   10"]

    def cells(values):
        return "".join(" " + fi(v, 3) + " " for v in values)

    for indx in range(1, nfeat + 1):
        for edge in (indx, indx + RIGHT_EDGE):
            out.append("")                                  # FORMAT 1020 / 1021
            rows = tables.entries(edge)
            n = len(rows)
            if n >= 1:
                out.append(" " + fi(edge, 3) + " INDX " + cells(r[0] for r in rows))
                out.append("     QUAL " + cells(r[1] for r in rows))
                out.append(" " + fi(n, 3) + " LOC1 " + cells(r[2] for r in rows))
                out.append("     LOC2 " + cells(r[3] for r in rows))
            else:
                out.append(" " + fi(edge, 3) + " INDX *** NO MATCHES ****")
                out.append("     QUAL")
                out.append(" " + fi(n, 3) + " LOC1")
                out.append("     LOC2")
    out.append("")
    return out


def prfpos(np_: int, pos, dsep, dvirt) -> list[str]:
    """PRFPOS — the table of feature positions (Appendix D's last page)."""
    out = ["1 Feature 3-D positions.  NP=" + fi(np_, 3) + " dv=" + ff(dvirt, 6, 2)
           + " ds=" + ff(dsep, 6, 3),
           " INDX      dp        dx        dy        ep        ex        ey",
           ""]
    for indx in range(1, np_ + 1):
        for j in (1, 2):
            jndx = (j - 1) * RIGHT_EDGE + indx
            base = (jndx - 1) * 6
            if pos[base] > 0:
                out.append(" " + fi(jndx, 3) + " " * 5
                           + "".join(ff(v, 7, 3) + " " * 3 for v in pos[base:base + 6]))
            else:
                out.append(" " + fi(jndx, 3) + " " * 10 + "No data point.")
        out.append("")                                      # FORMAT 1004
    out += ["", "", "1 "]                                   # FORMAT(//,"1 ")
    return out
