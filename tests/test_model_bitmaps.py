"""model.bitmaps: Appendix B's B-1..B-8 and the radial map's storage on hand-made maps, the
expected words worked out by hand in the comments (16 column words, column 0 leftmost, bit 0
the top row)."""

import pytest

from model import bitmaps as bm


def _map(cols: dict) -> tuple:
    return tuple(cols.get(j, 0) for j in range(16))


# A 2x2 square in columns 3-4, rows 2-3: each of its columns is bits 2,3 = 0b1100 = 12.
SQUARE = _map({3: 12, 4: 12})


def test_square_b2_to_b8():
    ops = bm.all_operations(SQUARE)
    # V(j) = A(j) XOR A(j+1): column 2 (0 vs 12) and column 4 (12 vs 0)
    assert ops["V"] == _map({2: 12, 4: 12})
    # L = A AND RSHIFT(V): column 3 gets V(2); R = A AND V: column 4
    assert ops["L"] == _map({3: 12})
    assert ops["R"] == _map({4: 12})
    # H = w XOR (w >> 1) = 12 ^ 6 = 10 (rows 1 and 3)
    assert ops["H"] == _map({3: 10, 4: 10})
    # T = A AND DSHIFT(H): 12 & 20 = 4 (row 2); B = A AND H: 12 & 10 = 8 (row 3)
    assert ops["T"] == _map({3: 4, 4: 4})
    assert ops["B"] == _map({3: 8, 4: 8})
    # every pixel of a 2x2 square is a corner
    assert ops["P"] == SQUARE


# An L shape: rows 4-7 over columns 4-9, rows 8-9 over columns 4-5.
# Columns 4, 5: bits 4..9 = 0x3F0 = 1008; columns 6..9: bits 4..7 = 0xF0 = 240.
ELL = _map({4: 1008, 5: 1008, 6: 240, 7: 240, 8: 240, 9: 240})


def test_l_shape_b2_to_b8():
    ops = bm.all_operations(ELL)
    # V: column 3 = 0^1008, column 5 = 1008^240 = 768 (rows 8, 9), column 9 = 240^0
    assert ops["V"] == _map({3: 1008, 5: 768, 9: 240})
    assert ops["L"] == _map({4: 1008})                 # 1008 & V(3)
    assert ops["R"] == _map({5: 768, 9: 240})          # A & V
    # H: 1008 ^ 504 = rows 3, 9 = 8 + 512 = 520; 240 ^ 120 = rows 3, 7 = 8 + 128 = 136
    assert ops["H"] == _map({4: 520, 5: 520, 6: 136, 7: 136, 8: 136, 9: 136})
    # T: the top row 4 (16) everywhere; B: row 9 (512) in columns 4-5, row 7 (128) in 6-9
    assert ops["T"] == _map({j: 16 for j in range(4, 10)})
    assert ops["B"] == _map({4: 512, 5: 512, 6: 128, 7: 128, 8: 128, 9: 128})
    # P: column 4 L&T 16 | L&B 512 = 528; column 5 R&B 768&512 = 512; column 9 R&T | R&B = 144
    assert ops["P"] == _map({4: 528, 5: 512, 9: 144})
    assert bm.to_rows(ops["P"])[4] == "....#....#......"
    assert bm.from_rows(bm.to_rows(ELL)) == ELL


def test_region_on_the_borders_has_edges_there():
    """Columns 0-1 full height: the zero extension gives a left edge in column 0 and a top edge
    in row 0, as the right and bottom ones; V and H have no bit for the step at the left and
    top border (column and row -1 are not stored)."""
    a = _map({0: 0xFFFF, 1: 0xFFFF})
    ops = bm.all_operations(a)
    assert ops["V"] == _map({1: 0xFFFF})
    assert ops["L"] == _map({0: 0xFFFF}) and ops["R"] == _map({1: 0xFFFF})
    assert ops["H"] == _map({0: 0x8000, 1: 0x8000})                # 0xFFFF ^ 0x7FFF
    assert ops["T"] == _map({0: 1, 1: 1}) and ops["B"] == _map({0: 0x8000, 1: 0x8000})
    assert ops["P"] == _map({0: 0x8001, 1: 0x8001})


@pytest.mark.parametrize("a", [SQUARE, ELL, _map({0: 0xFFFF, 15: 0x8001}),
                               _map({j: (0x5A5A * (j + 1)) & 0xFFFF for j in range(16)})])
def test_b3_b4_b6_b7_reduce_to_neighbour_tests(a):
    """With the zero extension: L = A AND NOT RSHIFT(A), R = A AND NOT LSHIFT(A),
    T = A AND NOT DSHIFT(A), B = A AND NOT USHIFT(A)."""
    inv = lambda m: tuple(~w & 0xFFFF for w in m)                  # noqa: E731
    andm = lambda p, q: tuple(x & y for x, y in zip(p, q))         # noqa: E731
    assert bm.left_edges(a) == andm(a, inv(bm.rshift(a)))
    assert bm.right_edges(a) == andm(a, inv(bm.lshift(a)))
    assert bm.top_edges(a) == andm(a, inv(bm.dshift(a)))
    assert bm.bottom_edges(a) == andm(a, inv(bm.ushift(a)))


def test_b1_difference_and_shifted_compare():
    assert bm.xor(SQUARE, ELL)[4] == 12 ^ 1008
    assert bm.difference(SQUARE, SQUARE) == 0
    # they do not overlap: 4 bits of the square + 2*6 + 4*4 of the L
    assert bm.difference(SQUARE, ELL) == 4 + 12 + 16
    moved = bm.lshift(bm.lshift(ELL))                  # the L two columns further left
    assert bm.shifted_compare(ELL, moved) == (0, 2)
    assert bm.shifted_compare(ELL, ELL) == (0, 0)
    # negative words from a file are the same 16-bit patterns
    assert bm.ones([-1] + [0] * 15) == 16


def test_cyclic_shifts_for_radial_maps():
    a = _map({0: 1, 15: 3})
    assert bm.vertical_edges(a, cyclic=True) == _map({0: 1, 14: 3, 15: 2})   # 15 vs 0 wraps
    # sector 0's row 0 has sector 15's row 0 on its left when the map wraps round: no edge
    assert bm.left_edges(a, cyclic=True) == _map({15: 3})
    assert bm.left_edges(a) == _map({0: 1, 15: 3})


# --- radial maps -------------------------------------------------------------------------

RAW = [0x7FF, 0x1FFF, 0x1FFF, 0x7FF] + [0] * 12        # sectors clockwise from +x


def test_radial_storage_most_ones_first_clockwise():
    stored, k = bm.radial_canonical(RAW)
    # sectors 1 and 2 have 13 ones; the first clockwise from sector 0 is sector 1
    assert k == 1
    assert stored == tuple([0x1FFF, 0x1FFF, 0x7FF] + [0] * 12 + [0x7FF])
    assert bm.rotate(stored, -k) == tuple(RAW)          # rotation is a change of index


def test_radial_compare_over_all_16_rotations():
    turned = bm.rotate(RAW, -5)                         # the shape 5 sectors further clockwise
    assert turned[5:9] == tuple(RAW[:4])
    assert bm.radial_compare(RAW, turned) == (0, 5)
    assert bm.radial_canonical(turned)[0] == bm.radial_canonical(RAW)[0]
    other = list(RAW)
    other[0] = 0xFF                                     # three bits fewer in one sector
    assert bm.radial_compare(other, turned) == (3, 5)


def test_bad_maps():
    with pytest.raises(ValueError, match="16 words"):
        bm.vertical_edges([0] * 15)
    with pytest.raises(ValueError):
        bm.from_rows(["#" * 16] * 15)
