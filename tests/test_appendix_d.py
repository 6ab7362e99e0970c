"""The external functional test: Appendix D's sample run (line 60, ds 0.75,
dv 180) — LCSL + PRFPOS print the 3-D position table exactly, and MASL's
candidates, LOC1 values and shift bounds agree with the printed match lists."""

import io
from fractions import Fraction

import pytest

from diskfmt.dgreal import Real, ZERO, fortran_f
from diskfmt.listing import Listing
from estar.lcsl import lcsl
from estar.masl import MatchTables, masl
from estar.printouts import prfpos
from nstar.printouts import prqvfl

from masl_wrappers import OneByOneLink, bounds as _search_bounds
from appendix_d import (IYLOC, DSEP, DVIRT, LEFT_FEATURES, RIGHT_FEATURES, MATCHES,
                        POSITION_TABLE, TITLE)


def tables_from_appendix() -> MatchTables:
    t = MatchTables()
    for edge, entries in MATCHES.items():
        t.nmatch[edge - 1] = len(entries)
        for i, (indx, qual, loc1, loc2) in enumerate(entries):
            t.imatch[edge - 1][i] = [indx, qual or 0, loc1, loc2 or 0]
    return t


def printed_table() -> list[str]:
    pos = [ZERO] * 640
    ds, dv = Real.const(DSEP), Real.const(DVIRT)
    lcsl(IYLOC, 12, tables_from_appendix(), pos, ds, dv)
    buf = io.StringIO()
    Listing(buf).records(prfpos(12, pos, ds, dv))
    return buf.getvalue().split("\n")      # not splitlines(): it splits at the form feed


def test_position_table_rows_exactly_as_printed_in_1985():
    lines = printed_table()
    ours = [" ".join(l.split()) for l in lines if l.strip() and l.split()[0].isdigit()]
    assert ours == POSITION_TABLE.splitlines()


def test_position_table_title_and_layout():
    lines = printed_table()
    assert lines[0] == "\f " + TITLE        # "1 Feature…": page eject, then the blank
    row3 = next(l for l in lines if l.startswith("  3 "))
    # FORMAT(" ",I3,5X,6(F7.3,3X)): fixed columns, trailing blanks dropped.
    assert row3 == "  3      16.875    -4.312     0.000     2.411     0.670     0.054"
    assert "  1          No data point." in lines


def test_ieee_arithmetic_would_not_reproduce_the_table():
    """Why the table is a sharp test: in double precision edge 3's dx is exactly
    -4.3125, which F7.3 prints as -4.313 (the table says -4.312): only the
    truncating DG arithmetic lands below the half."""
    dl, disp = 14 - 60, 8.0
    dp = 0.75 * 180 / disp
    assert fortran_f(Fraction(dl * dp * (1 / 180)), 7, 3) == " -4.313"


def _columns(features):
    cols = [[0] * 50 for _ in range(4)]
    for k, f in enumerate(features):
        for j in range(4):
            cols[j][k] = f[j]
    return cols


class SameMapsLink(OneByOneLink):
    """Every edge gets the same bit map, so MARF's best shift is 0 and every
    grey-level candidate with LOC1 > LOC2 enters the list."""

    def __init__(self):
        self.requests = []

    def nblob(self, image, x, y, ies, ibm):
        self.requests.append((image, x, y, ies))
        ibm[:] = [1] + [0x0FF0] * 16


def test_masl_candidates_are_exactly_appendix_d_lists():
    t = MatchTables()
    link = SameMapsLink()
    masl(IYLOC, 12, _columns(LEFT_FEATURES), 11, _columns(RIGHT_FEATURES),
         [[0] * 17 for _ in range(100)], [[0] * 17 for _ in range(100)], t, link)
    for edge, entries in MATCHES.items():
        ours = {e[0] for e in t.entries(edge)}
        printed = {e[0] for e in entries}
        if edge == 11:
            # Only (8, .., 55, 52) is legible; the grey rule also admits right
            # feature 7 (GRYL 2 vs 3), which the OCR may have lost.
            assert printed <= ours <= {7, 8}
        else:
            assert ours == printed, f"edge {edge}"
        for indx, qual, loc1, loc2 in t.entries(edge):
            ref = LEFT_FEATURES[(edge - 1) % 50]
            assert loc1 == (ref[0] if edge <= 50 else ref[1])
    # Each edge map is requested once per line and side, edges at their 1-based index.
    assert len(link.requests) == len(set(link.requests))
    assert (1, 14, IYLOC, -1) in link.requests and (2, 6, IYLOC, -1) in link.requests


# Shift bounds worked by hand from MASL's formulas, for the entries whose printed
# LOC2 is off the right edge's own location (the MARF shift is non-zero):
#   edge, left bound, right-feature bound, printed LOC2 - right edge location
HAND_BOUNDS = [
    (55, 2, 1, 22 - 23),   # left f5 stop 25: min((29-25)/2, (25-19)/2); right f4 stop 23: min((30-23)/2, 1)
    (7, 1, 1, 29 - 30),    # left f7 start 34: min((34-32)/2, (36-34)/2); right f5 start 30: min((30-23)/2, 1)
    (8, 1, 1, 22 - 21),    # left f8 start 39: min(3/2, 3/2); right f4 start 21: min((21-17)/2, 1)
    (60, 1, 1, 34 - 33),   # left f10 stop 49: min((55-49)/2, 1); right f5 stop 33: min((36-33)/2, 1)
    (62, 2, 1, 71 - 70),   # left f12 last: min(128-77+1, 2); right f9 stop 70: min((110-70)/2, 1)
]


@pytest.mark.parametrize("edge,bound1,bound2,shift", HAND_BOUNDS)
def test_printed_shifts_lie_within_masl_bounds(edge, bound1, bound2, shift):
    k = (edge - 1) % 50 + 1
    side = 0 if edge <= 50 else 1
    assert _search_bounds(_columns(LEFT_FEATURES), 12, k, 128)[side] == bound1
    right_feature = {55: 4, 7: 5, 8: 4, 60: 5, 62: 9}[edge]
    assert _search_bounds(_columns(RIGHT_FEATURES), 11, right_feature, 128)[side] == bound2
    assert abs(shift) <= min(bound1, bound2)


def test_every_printed_list_is_sorted_by_quality_and_loc1_right_of_loc2():
    for edge, entries in MATCHES.items():
        quals = [q for _, q, _, _ in entries if q is not None]
        assert quals == sorted(quals), edge
        for _, _, loc1, loc2 in entries:
            assert loc2 is None or loc1 > loc2


def test_prqvfl_prints_appendix_d_feature_list():
    buf = io.StringIO()
    Listing(buf).records(prqvfl(12, LEFT_FEATURES))
    lines = buf.getvalue().splitlines()
    assert lines[0] == "1-Dimensional Slice Feature List"
    assert lines[1] == "There are  12 features in the slice."
    rows = [tuple(int(v) for v in l.split()) for l in lines[3:]]
    assert rows == [(i + 1,) + f for i, f in enumerate(LEFT_FEATURES)]
