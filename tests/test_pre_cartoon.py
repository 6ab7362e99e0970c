"""PRE command 3: the cartoon keeps region boundaries, its feature code
decodes to the cartoon, and the production QV against EXQVFL."""

import numpy as np

from pre.cartoon import Code, cartoon, cartoon_line, code_bits, decode_line
from pre.compare import compare_line, compare_picture
from pre.qv_production import EXTENDED_RULES, qv_line


def _regions():
    pic = np.full((120, 128), 3, dtype=np.uint8)
    pic[20:70, 10:60] = 12          # a bright rectangle
    pic[50:110, 40:120] = 7         # a mid-grey one overlapping it
    pic[90:100, 5:25] = 14
    return pic


def _noise(shape):
    # deterministic +-1 "camera noise", below the threshold T = 2
    y, x = np.mgrid[0:shape[0], 0:shape[1]]
    return ((x * 7 + y * 13) % 5 == 0).astype(int) - ((x * 11 + y * 3) % 7 == 0).astype(int)


def test_cartoon_of_a_clean_picture_is_itself():
    pic = _regions()
    assert np.array_equal(cartoon(pic).picture, pic)


def test_cartoon_keeps_region_boundaries_through_noise():
    clean = _regions()
    noisy = np.clip(clean.astype(int) + _noise(clean.shape), 0, 15).astype(np.uint8)
    assert (noisy != clean).sum() > 1000
    out = cartoon(noisy).picture
    # every boundary of the clean picture is a grey-level change in the cartoon
    # at the same place, and the cartoon has no other changes
    assert np.array_equal(out[:, 1:] != out[:, :-1], clean[:, 1:] != clean[:, :-1])
    assert np.array_equal(out[1:, :] != out[:-1, :], clean[1:, :] != clean[:-1, :])
    assert np.abs(out.astype(int) - clean).max() <= 1


def test_step_bits_count():
    codes = [Code("S", 2, 2), Code("G+", 3, 11, 1), Code("S", 2, 11)]
    assert code_bits(codes, 8) == 4 + 3 * (2 + 3 + 4) + 2     # length 3 -> 2 step bits


def test_ramp_becomes_a_sharp_step():
    # 2 2 2 5 8 11 11 11: S G+ S; the edge interval 3..6 (2 5 8 11) steps
    # where it crosses half-way (6.5): 5 stays left, 8 goes right
    line, start, codes = cartoon_line([2, 2, 2, 5, 8, 11, 11, 11])
    assert list(line) == [2, 2, 2, 2, 11, 11, 11, 11]
    assert start == 2
    assert codes == [Code("S", 2, 2), Code("G+", 3, 11, 1), Code("S", 2, 11)]


def test_codes_decode_and_count_bits():
    codes = [Code("S", 63, 3), Code("G+", 1, 12), Code("S", 63, 12)]
    line = decode_line(3, codes, 128)
    assert list(line) == [3] * 64 + [12] * 64
    assert code_bits(codes, 128) == 4 + 3 * (2 + 7 + 4)


def test_peak_between_two_edges():
    # 1 1 9 1 1: S G+ G- S, the peak pixel keeps its grey
    line, _, codes = cartoon_line([1, 1, 9, 1, 1])
    assert list(line) == [1, 1, 9, 1, 1]
    assert [c.kind for c in codes] == ["S", "G+", "G-", "S"]


def test_bits_per_pixel_of_a_two_region_picture():
    pic = np.full((120, 128), 3, dtype=np.uint8)
    pic[:, 64:] = 12
    r = cartoon(pic)
    assert r.bits_h == 120 * 43 and r.bits_v == 128 * 17
    assert abs(r.bpp - 128 * 17 / 15360) < 1e-12


def test_step_edge_agrees_with_exqvfl():
    a = compare_line([5] * 10 + [12] * 10, 2)
    assert (a.n_ex, a.n_qv, a.exact, a.exact_grey, a.rows_same) == (1, 1, 1, 1, 1)


def test_gentle_bump_differs_from_exqvfl():
    # s g+ g- g- s: EXQVFL sees a falling gentle slope (two g- confirm it);
    # the production system smooths the bump (R24: s g+ g- -> S)
    px = [3, 3, 3, 5, 4, 3, 3, 3]
    a = compare_line(px, 2)
    assert a.n_ex == 1 and a.n_qv == 0 and a.missed == 1
    assert [s.kind for s in qv_line(px, 2)] == ["S"]


def test_flat_pause_inside_an_edge():
    # G- s g- G-: EXQVFL carries the slope over the flat step; the fifty
    # rules leave two edges; the X-rules (an option) make it one.
    px = [13, 13, 11, 8, 8, 7, 4, 4, 4]
    assert [s.kind for s in qv_line(px, 2)] == ["S", "G-", "S", "G-", "S"]
    assert [s.kind for s in qv_line(px, 2, EXTENDED_RULES)] == ["S", "G-", "S"]
    assert compare_line(px, 2, rules=EXTENDED_RULES).exact == 1


def test_compare_picture_counts_rows():
    a = compare_picture(_regions(), 2)
    assert a.rows == 120 and a.rows_same == 120 and a.exact == a.n_ex
