"""MASL (estar/masl.py), hand-derived from the Appendix F listing: insertion
into a match list, shift bounds, the bit-map requests and the lists built."""

import numpy as np

from estar.masl import MatchTables, masl

from masl_wrappers import OneByOneLink, bounds as _search_bounds, insert as _insert

F = -1          # 0xFFFF as a signed 16-bit word: a full column


def bmap(cols):
    """A 17-word map with the given 1-based columns full."""
    return [1] + [F if c in cols else 0 for c in range(1, 17)]


class RecordingLink(OneByOneLink):
    """NBLOB stand-in: records (image, x, y, ies) and stores a full map."""

    def __init__(self):
        self.calls = []

    def nblob(self, image, x, y, ies, ibm):
        self.calls.append((image, x, y, ies))
        ibm[:] = [1] + [F] * 16


# --- MASL: insertion into a match list ------------------------------------------

def entry(edge, qual):
    return [edge, qual, 100 + edge, edge, 0, 0, -1, 60]


def listed(table, count):
    return [(row[0], row[1]) for row in table[:count]]


def blank():
    return [[0, 0, 0, 0] for _ in range(10)]


def test_insert_into_empty_list():
    t = blank()
    n = _insert(t, 0, entry(7, 30))
    assert n == 1 and t[0] == [7, 30, 107, 7]          # LMATCH(1..4) only


def test_insert_equal_quality_goes_after_existing_equals():
    t = blank()
    n = 0
    for e, q in ((1, 5), (2, 5), (3, 5)):
        n = _insert(t, n, entry(e, q))
    # IQM >= bottom -> appended: 1, 2, 3 in arrival order
    assert listed(t, n) == [(1, 5), (2, 5), (3, 5)]
    t = blank()
    n = 0
    for e, q in ((1, 3), (2, 5), (3, 7), (4, 5)):
        n = _insert(t, n, entry(e, q))
    # 5 < bottom 7: scan up; ISPT=3: move 3 -> 4; IQM 5 >= entry 2 (5) -> insert at 3
    assert listed(t, n) == [(1, 3), (2, 5), (4, 5), (3, 7)]


def full_list():
    t = blank()
    n = 0
    for k in range(1, 11):
        n = _insert(t, n, entry(k, 10 * k))
    assert n == 10
    return t


def test_insert_worse_or_equal_into_full_list_is_dropped():
    t = full_list()
    before = [list(r) for r in t]
    assert _insert(t, 10, entry(11, 110)) == 10       # IF (INUML .GE. 10) GOTO 500
    assert _insert(t, 10, entry(12, 100)) == 10       # equal to the bottom: also dropped
    assert t == before


def test_insert_better_into_full_list_pushes_the_tenth_out():
    t = full_list()
    # q=25: INUM=10, list stays 10; ISPT=10 not moved (dropped), 9..3 move down,
    # at ISPT=3: 25 >= entry 2 (20) -> insert at 3.
    assert _insert(t, 10, entry(11, 25)) == 10
    assert listed(t, 10) == [(1, 10), (2, 20), (11, 25), (3, 30), (4, 40), (5, 50),
                             (6, 60), (7, 70), (8, 80), (9, 90)]
    # the best so far goes to the top (loop ends, ISPT=1)
    assert _insert(t, 10, entry(12, 1)) == 10
    assert listed(t, 10)[:3] == [(12, 1), (1, 10), (2, 20)]
    assert listed(t, 10)[-1] == (8, 80)


# --- MASL: shift bounds ------------------------------------------------------------

def test_search_bounds():
    # features (start, stop): (40,50), (60,61), (70,90); NPIX1 = 128
    ifeat = [[40, 60, 70] + [0] * 47, [50, 61, 90] + [0] * 47, [0] * 50, [0] * 50]
    # f1: ILOCD=(50-40)/2=5; IRGDL=ILOCL=40 -> 5; IRGDR=(60-50)/2=5 -> 5
    assert _search_bounds(ifeat, 3, 1, 128) == (5, 5)
    # f2: ILOCD=(61-60)/2=0 -> both 0
    assert _search_bounds(ifeat, 3, 2, 128) == (0, 0)
    # f3: ILOCD=10; IRGDL=(70-61)/2=4; IRGDR=NPIX1-ILOCR+1=39 -> 10
    assert _search_bounds(ifeat, 3, 3, 128) == (4, 10)
    # overlapping neighbours: (10,20), (15,30): f2 IRGDL=(15-20)/2 = -2 -> 0
    ifeat = [[10, 15] + [0] * 48, [20, 30] + [0] * 48, [0] * 50, [0] * 50]
    assert _search_bounds(ifeat, 2, 2, 128) == (0, 7)


# --- MASL: bit-map caching and the lists it builds --------------------------------

def test_masl_requests_each_edge_map_once_per_line():
    # Two features a slice, all grey levels 8, so every same-side pair passes
    # IABS(grey difference) <= 1: 4 left and 4 right comparisons, 8 distinct maps.
    ifeat1 = [[40, 80] + [0] * 48, [41, 81] + [0] * 48, [8, 8] + [0] * 48, [8, 8] + [0] * 48]
    ifeat2 = [[34, 74] + [0] * 48, [35, 75] + [0] * 48, [8, 8] + [0] * 48, [8, 8] + [0] * 48]
    iblb1 = [[0] * 17 for _ in range(100)]
    iblb2 = [[0] * 17 for _ in range(100)]
    link = RecordingLink()
    tables = MatchTables()
    masl(60, 2, ifeat1, 2, ifeat2, iblb1, iblb2, tables, link)
    # INDX=1: JNDX=1 left (1,40), (2,34); right (1,41), (2,35);
    #         JNDX=2 left map 1 cached, (2,74); right (2,75);
    # INDX=2: JNDX=1 left (1,80); right (1,81); JNDX=2 all cached.
    assert link.calls == [(1, 40, 60, -1), (2, 34, 60, -1), (1, 41, 60, 1), (2, 35, 60, 1),
                          (2, 74, 60, -1), (2, 75, 60, 1), (1, 80, 60, -1), (1, 81, 60, 1)]
    assert [k + 1 for k in range(100) if iblb1[k][0] == 1] == [1, 2, 51, 52]
    assert [k + 1 for k in range(100) if iblb2[k][0] == 1] == [1, 2, 51, 52]
    # Identical full maps: every shift IVAL=0, MLOC=0, LOC2 unchanged.  Kept only
    # where LOC1 > LOC2: 40>34 yes, 40>74 no; 80>34, 80>74 yes.  Equal qualities
    # keep arrival order.  Right edges carry LNDX = JNDX+50.
    assert tables.entries(1) == [(1, 0, 40, 34)]
    assert tables.entries(2) == [(1, 0, 80, 34), (2, 0, 80, 74)]
    assert tables.entries(51) == [(51, 0, 41, 35)]
    assert tables.entries(52) == [(51, 0, 81, 35), (52, 0, 81, 75)]
    # The same caches again (same line): nothing new is requested.
    masl(60, 2, ifeat1, 2, ifeat2, iblb1, iblb2, tables, link)
    assert len(link.calls) == 8


def test_masl_grey_rule_limits_comparisons():
    # Left greys 8 and 12 in each slice: only pairs with |difference| <= 1 are
    # compared (8-8, 12-12); right greys likewise (12-12, 8-8).
    ifeat1 = [[40, 80] + [0] * 48, [41, 81] + [0] * 48, [8, 12] + [0] * 48, [12, 8] + [0] * 48]
    ifeat2 = [[34, 74] + [0] * 48, [35, 75] + [0] * 48, [9, 12] + [0] * 48, [12, 7] + [0] * 48]
    iblb1 = [[0] * 17 for _ in range(100)]
    iblb2 = [[0] * 17 for _ in range(100)]
    link = RecordingLink()
    tables = MatchTables()
    masl(60, 2, ifeat1, 2, ifeat2, iblb1, iblb2, tables, link)
    assert link.calls == [(1, 40, 60, -1), (2, 34, 60, -1), (1, 41, 60, 1), (2, 35, 60, 1),
                          (1, 80, 60, -1), (2, 74, 60, -1), (1, 81, 60, 1), (2, 75, 60, 1)]
    assert tables.entries(1) == [(1, 0, 40, 34)]
    assert tables.entries(2) == [(2, 0, 80, 74)]
    assert tables.entries(51) == [(51, 0, 41, 35)]
    assert tables.entries(52) == [(52, 0, 81, 75)]


def test_wide_features_give_shift_bounds_past_31_without_overrunning():
    # Two features 70 pixels wide starting at 40 and 36: left-edge bounds
    # min(40, 70/2) = 35 and min(36, 35) = 35, so IWST = 35 and MARF tries 71
    # shifts.  (A 64-entry work array overran
    # here; the compiled kernel does not check bounds, so run it as Python too.)
    from estar.masl import masl_kernel
    ifeat1 = np.zeros((4, 50), dtype=np.int64)
    ifeat2 = np.zeros((4, 50), dtype=np.int64)
    ifeat1[:, 0] = (40, 110, 8, 8)
    ifeat2[:, 0] = (36, 106, 8, 8)
    maps = np.zeros((100, 17), dtype=np.int64)
    maps[:, 0] = 1
    maps[:, 1:] = 0x00FF
    for kernel in (masl_kernel, getattr(masl_kernel, "py_func", masl_kernel)):
        tables = MatchTables()
        log = np.zeros((10, 5), dtype=np.int64)
        n = kernel(60, 1, ifeat1, 1, ifeat2, maps.copy(), maps.copy(), tables.nmatch,
                   tables.imatch, False, log)
        assert n == 2
        # identical maps: quality 0 at shift 0, LOC2 unchanged, LOC1 > LOC2 kept
        assert tables.entries(1) == [(1, 0, 40, 36)]
        assert tables.entries(51) == [(51, 0, 110, 106)]
