"""ICBIT, BMCP and MARF (estar/marf.py), hand-derived from the Appendix F listing.

Bit maps as MARF sees them: 17 words, word 1 the "map present" flag (1), words
2..17 the 16 columns (column 1 leftmost).  For IPOS >= 0 MARF calls
BMCP(INUM, IBM1(IOFF+2), IBM2(2)): map-1 column c+IPOS against map-2 column c;
for IPOS < 0 BMCP(INUM, IBM1(2), IBM2(IOFF+2)): map-1 column c against map-2
column c+|IPOS|; INUM = 16-|IPOS|.  IVAL = (ND*256)/NTOT, or 256 when NTOT = 0
or ND >= 128.  A new IVAL replaces the best when smaller, or when equal and
nearer zero (IABS(MLOC) .LE. IABS(IPOS) keeps the old one).
"""

import pytest

from estar.marf import bmcp, icbit
from estar.masl import Options

from masl_wrappers import OneByOneLink, marf, marf_shift

F = -1          # 0xFFFF as a signed 16-bit word: a full column


def bmap(cols):
    """A 17-word map with the given 1-based columns full."""
    return [1] + [F if c in cols else 0 for c in range(1, 17)]


# --- ICBIT / BMCP --------------------------------------------------------------

@pytest.mark.parametrize("word, bits", [
    (0, 0), (1, 1), (-1, 16),           # -1 = 0xFFFF
    (-32768, 1),                         # 0x8000: only the sign bit
    (-2, 15), (0x5555, 8), (-21846, 8),  # -21846 = 0xAAAA
    (32767, 15), (0x0F0F, 8),
])
def test_icbit(word, bits):
    assert icbit(word) == bits


def test_bmcp_counts_bits_and_differences():
    # columns: (0x000F, -1) against (0x0003, 0):
    # N1 = 4 + 16 = 20, N2 = 2, ND = ICBIT(0x000C) + ICBIT(0xFFFF) = 2 + 16 = 18
    assert bmcp(2, [0x000F, -1], [0x0003, 0]) == (20, 2, 18)
    # only INUM words are compared
    assert bmcp(1, [0x000F, -1], [0x0003, 0]) == (4, 2, 2)


@pytest.mark.parametrize("inum", [0, -1, -16])
def test_bmcp_zero_trip(inum):
    # DO 100 ILOC=1,INUM with INUM <= 0 runs no times (QUIRKS M18)
    assert bmcp(inum, [-1] * 16, [0] * 16) == (0, 0, 0)


# --- MARF's shift search ----------------------------------------------------------

def test_marf_shift_finds_the_shift_and_its_values():
    # map 1: columns 1..8 full; map 2: columns 1..6 full = map 1 moved left by 2.
    # IPOS=+2: map-1 cols 3..16 vs map-2 cols 1..14: both 6 full then empty -> ND=0,
    #   IVAL = 0.
    # IPOS=+3: map-1 4..8 (5 cols) vs map-2 1..6 (6) -> 1 col differs: ND=16,
    #   NTOT=80+96=176 -> 4096/176 = 23.
    # IPOS=+1: 7 cols vs 6 -> ND=16, NTOT=112+96=208 -> 19.
    # IPOS= 0: 8 vs 6 -> ND=32, NTOT=224 -> 8192/224 = 36.
    # IPOS=-1: map-1 1..15 (8 full) vs map-2 2..16 (5 full) -> ND=48, NTOT=208 -> 59.
    # IPOS=-2: 8 vs 4 -> ND=64, NTOT=192 -> 85.   IPOS=-3: 8 vs 3 -> ND=80, NTOT=176 -> 116.
    mloc, mnval, tried = marf_shift(bmap(range(1, 9)), bmap(range(1, 7)), 3)
    assert tried == [(-3, 116), (-2, 85), (-1, 59), (0, 36), (1, 19), (2, 0), (3, 23)]
    assert (mloc, mnval) == (2, 0)


def test_marf_shift_tie_goes_to_the_shift_nearer_zero():
    # map 1: column 8; map 2: columns 7 and 10; IWST=2.
    # IPOS=-2: map-1 c=8 vs map-2 c+2 set at c=5,8: one column differs: ND=16,
    #   NTOT=48 -> 85.  IPOS=+1: map-1 c+1 set at c=7, map-2 at 7,10: ND=16 -> 85.
    # IPOS=-1, 0, +2: no overlap, ND=48=NTOT -> 256.
    # -2 is found first (85 < 256); +1 ties and |−2| > |+1| -> +1 wins.
    mloc, mnval, tried = marf_shift(bmap({8}), bmap({7, 10}), 2)
    assert tried == [(-2, 85), (-1, 256), (0, 256), (1, 85), (2, 256)]
    assert (mloc, mnval) == (1, 85)


def test_marf_shift_tie_equally_near_keeps_the_earlier():
    # map 1: column 8; map 2: columns 7 and 9; IWST=1: IPOS=-1 and +1 both ND=16,
    # NTOT=48 -> 85; IPOS=0 -> 256.  At +1: IABS(-1) .LE. IABS(1) -> keep -1.
    mloc, mnval, tried = marf_shift(bmap({8}), bmap({7, 9}), 1)
    assert tried == [(-1, 85), (0, 256), (1, 85)]
    assert (mloc, mnval) == (-1, 85)


def test_marf_shift_nd_128_or_more_counts_as_256():
    # map 1 all 256 bits, map 2 columns 1..8 (128 bits): ND=128 -> 256 although
    # (128*256)/384 would be 85.
    assert marf_shift(bmap(range(1, 17)), bmap(range(1, 9)), 0)[:2] == (0, 256)
    # one bit more in map 2 (column 9 = 0x0001): ND=127 -> (127*256)/385 = 84.
    m2 = bmap(range(1, 9))
    m2[9] = 1
    assert marf_shift(bmap(range(1, 17)), m2, 0)[:2] == (0, 84)


def test_marf_shift_empty_maps():
    # NTOT=0 everywhere -> 256; every tie keeps MLOC=0 (IABS(0) <= IABS(IPOS)).
    mloc, mnval, tried = marf_shift(bmap(()), bmap(()), 3)
    assert (mloc, mnval) == (0, 256)
    assert [v for _, v in tried] == [256] * 7


# --- MARF: LOC2 sign and map fetching ---------------------------------------------

class NoLink:
    def nblob(self, *args):
        raise AssertionError("a cached map was fetched again")


def lmatch_for(loc1=80, loc2=70, rg1=3, rg2=4):
    # LMATCH: JNDX, 9999, LOC1, LOC2, IRGD (slice 1), JRGD (slice 2), side, IYLOC
    return [5, 9999, loc1, loc2, rg1, rg2, -1, 60]


def test_marf_1985_sign_adds_the_shift():
    # Best shift +2 (see test_marf_shift_finds_the_shift_and_its_values), IWST =
    # MIN0(3, 4) = 3.  1985: LMATCH(4)=LMATCH(4)+MLOC = 70+2 = 72, LMATCH(2)=0.
    lm = lmatch_for()
    marf(lm, bmap(range(1, 9)), bmap(range(1, 7)), NoLink())
    assert lm[:4] == [5, 0, 80, 72]
    # LOC1 and the rest untouched
    assert lm[4:] == [3, 4, -1, 60]


def test_marf_sign_fix_subtracts_the_shift():
    lm = lmatch_for()
    marf(lm, bmap(range(1, 9)), bmap(range(1, 7)), NoLink(), options=Options(marf_sign_fix=True))
    assert lm[:4] == [5, 0, 80, 68]


def test_marf_shift_bound_is_the_smaller_range():
    # IWST = MIN0(LMATCH(5), LMATCH(6)) = MIN0(1, 4) = 1: of -1 (59), 0 (36), +1 (19)
    # the best is +1 -> LOC2 = 71, quality 19.
    lm = lmatch_for(rg1=1, rg2=4)
    marf(lm, bmap(range(1, 9)), bmap(range(1, 7)), NoLink())
    assert lm[:4] == [5, 19, 80, 71]


class RecordingLink(OneByOneLink):
    """NBLOB stand-in: records (image, x, y, ies) and stores a full map."""

    def __init__(self):
        self.calls = []

    def nblob(self, image, x, y, ies, ibm):
        self.calls.append((image, x, y, ies))
        ibm[:] = [1] + [F] * 16


def test_marf_fetches_only_missing_maps_with_the_guesses():
    link = RecordingLink()
    m1, m2 = [0] * 17, [0] * 17
    lm = [5, 9999, 80, 70, 3, 4, +1, 60]
    marf(lm, m1, m2, link)
    # IF (IBM1(1) .NE. 1) CALL NBLOB(1, LMATCH(3), IYLOC, IES, IBM1(1)); same for map 2
    assert link.calls == [(1, 80, 60, +1), (2, 70, 60, +1)]
    assert m1[0] == 1 and m2[0] == 1
    marf(lm, m1, m2, link)                      # both present now: no request
    assert len(link.calls) == 2
