"""PRE command 2: the 2x2 average with its rounding, the centre-out order of
the listing, and the frame store it leaves (docs/pre.md; QUIRKS P1)."""

import numpy as np
import pytest

from octek_sim.board import Octek
from pre import framestore
from pre.condense import condense


# (2x2 block, hand-computed (a+b+c+d+2)/4 truncated)
BLOCKS = [
    ([[0, 0], [0, 0]], 0),
    ([[0, 0], [0, 1]], 0),      # mean 0.25 -> 0
    ([[0, 0], [1, 1]], 1),      # mean 0.5  -> 1 (rounds up)
    ([[0, 1], [1, 1]], 1),      # mean 0.75 -> 1
    ([[1, 1], [2, 1]], 1),      # 1.25 -> 1
    ([[1, 2], [2, 1]], 2),      # 1.5  -> 2
    ([[2, 3], [2, 3]], 3),      # 2.5  -> 3
    ([[3, 4], [5, 6]], 5),      # 4.5  -> 5
    ([[15, 15], [15, 14]], 15),  # 14.75 -> 15
    ([[15, 15], [15, 15]], 15),
    ([[0, 15], [15, 0]], 8),    # 7.5  -> 8
]


@pytest.mark.parametrize("block,want", BLOCKS)
def test_two_by_two(block, want):
    pic = np.zeros((240, 256), dtype=np.uint8)
    pic[10:12, 20:22] = block
    assert condense(pic)[5, 10] == want
    # the listing's in-place, centre-out version on the frame store agrees
    ict = Octek()
    ict.frame[:, 32:288] = pic
    framestore.condense_frame(ict)
    assert ict.frame[60 + 5, 96 + 10] == want


def _frame_with(pic):
    ict = Octek()
    ict.frame[:, :] = 5                       # something other than white or black
    ict.frame[:, 32:288] = pic
    return ict


def test_frame_store_after_command_2():
    rng = np.random.default_rng(7)
    pic = rng.integers(0, 16, (240, 256)).astype(np.uint8)
    ict = _frame_with(pic)
    framestore.condense_frame(ict)
    f = ict.frame
    assert np.array_equal(f[60:180, 96:224], condense(pic))
    # black box one pixel outside: x 95 and 224, rows 59 and 180
    assert (f[59, 95:225] == 0).all() and (f[180, 95:225] == 0).all()
    assert (f[59:181, 95] == 0).all() and (f[59:181, 224] == 0).all()
    # everything else white (15)
    rest = np.ones(f.shape, dtype=bool)
    rest[59:181, 95:225] = False
    assert (f[rest] == 15).all()


def test_command_2_reads_centre_out():
    rows = []

    class Spy(Octek):
        def rvblk(self, x, width, y, height):
            rows.append((y, height))
            return super().rvblk(x, width, y, height)

    ict = Spy()
    framestore.condense_frame(ict)
    assert rows[:4] == [(120, 2), (118, 2), (122, 2), (116, 2)]
    assert rows[-2:] == [(238, 2), (0, 2)]
    assert len(rows) == 120


def test_command_2_agrees_with_condense_on_many_pictures():
    rng = np.random.default_rng(11)
    for _ in range(3):
        pic = rng.integers(0, 16, (240, 256)).astype(np.uint8)
        ict = _frame_with(pic)
        framestore.condense_frame(ict)
        assert np.array_equal(ict.frame[60:180, 96:224], condense(pic))
