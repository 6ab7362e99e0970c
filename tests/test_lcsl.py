"""LCSL's walk down a match list, and the entry it records as the one its
position came from (what the CSV, PLY and pictures report)."""

from diskfmt.dgreal import Real, ZERO
from estar.lcsl import lcsl
from estar.masl import MatchTables

DS, DV = Real.const("0.25"), Real.const("180")     # DS*DV = 45


def _tables(lists: dict[int, list[tuple[int, int, int, int]]]) -> MatchTables:
    t = MatchTables()
    for edge, entries in lists.items():
        t.nmatch[edge - 1] = len(entries)
        for i, e in enumerate(entries):
            t.imatch[edge - 1][i] = e
    return t


def test_an_entry_with_range_at_most_one_is_passed_over_for_a_later_one():
    # Edge 1: disparity 98 gives range 45/98 = 0.459 (<= 1.0, walk goes on);
    # disparity 18 gives 2.5 and stops the walk.  Edge 51: only disparities
    # 1 (not above EDISP) and 90 (range 0.5): the last usable entry stays.
    t = _tables({1: [(1, 63, 128, 30), (2, 143, 128, 110), (3, 150, 100, 95)],
                 51: [(1, 5, 40, 39), (1, 9, 120, 30)]})
    pos = [ZERO] * 640
    used = lcsl(20, 1, t, pos, DS, DV)
    assert used == {1: (2, 143, 128, 110), 51: (1, 9, 120, 30)}
    assert float(pos[0]) == 2.5                     # 45 / 18
    assert abs(float(pos[50 * 6]) - 0.5) < 1e-6     # 45 / 90


def test_an_edge_with_no_usable_entry_is_not_recorded():
    t = _tables({1: [(1, 0, 40, 40), (1, 0, 40, 39), (1, 0, 30, 40)], 51: []})
    pos = [ZERO] * 640
    assert lcsl(20, 1, t, pos, DS, DV) == {}
    assert float(pos[0]) == -1.0 and float(pos[50 * 6]) == -1.0
