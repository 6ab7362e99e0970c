"""Pictures: the OCTEK monitor, one ESTAR line, the top-down map, save_png.

Positions are computed here from the geometry the modules document (numbers
typed in, not taken from the modules' own helpers), and checked by pixel colour.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import cv2
import numpy as np
import pytest

from diskfmt.layouts import decode_bi
from estar.program import in_process_rig
from octek_sim import Octek
from octek_sim.monitor import render_monitor, CURSOR_COLOUR
from rig.pictures import (line_picture, topdown_map, save_png, used_matches, MATCH_PALETTE,
                          POINT_COLOUR, BAR_COLOUR, ROW_COLOUR)
from rig.scene import bundled_path

BEZEL, CAPTION_H = 10, 30            # docs of octek_sim.monitor
RED = tuple(CURSOR_COLOUR)


def _pair():
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    return left, right


@pytest.fixture(scope="module")
def lab():
    left, right = _pair()
    ecl = in_process_rig(left, right)
    res = ecl.lcln(60)
    return left, right, ecl.link.nova, res


# --- monitor -----------------------------------------------------------------

def _screen_px(img, x, y, s):
    """The s x s block of frame-store pixel (x, y)."""
    return img[BEZEL + y * s:BEZEL + y * s + s, BEZEL + x * s:BEZEL + x * s + s]


def _is(block, colour):
    return bool(np.all(block.reshape(-1, 3) == np.array(colour, np.uint8)))


@pytest.mark.parametrize("s", [1, 2, 3])
def test_monitor_size(s):
    img = render_monitor(Octek(), scale=s)
    assert img.dtype == np.uint8
    assert img.shape == (240 * s + 20 + 30, 320 * s + 20, 3)


def test_monitor_shows_frame_store_greys(lab):
    left, right, nova, _ = lab
    s = 3
    img = render_monitor(nova.octek, scale=s)
    # left picture at x 26.., right at x 166.., rows 0..119; elsewhere white
    for (r, c) in ((50, 40), (10, 5), (119, 127), (60, 64)):
        assert _is(_screen_px(img, 26 + c, r, s), (17 * int(left[r, c]),) * 3)
        assert _is(_screen_px(img, 166 + c, r, s), (17 * int(right[r, c]),) * 3)
    assert _is(_screen_px(img, 10, 200, s), (255, 255, 255))
    assert _is(_screen_px(img, 160, 60, s), (255, 255, 255))      # between the pictures


def test_monitor_grey_of_written_pixels():
    o = Octek()
    o.frame[:] = 0
    for k in range(16):
        o.frame[7, 20 + k] = k
    img = render_monitor(o, scale=2)
    for k in range(16):
        assert _is(_screen_px(img, 20 + k, 7, 2), (17 * k,) * 3)
    assert not np.any(np.all(img == np.array(RED, np.uint8), axis=2))   # no cursor


def test_monitor_box_cursor():
    o = Octek()
    o.frame[:] = 5
    before = o.frame.copy()
    o.boxcur(18, 18)
    o.hctab(100, 50)
    s = 3
    img = render_monitor(o, scale=s)
    for x, y in ((100, 50), (117, 50), (100, 67), (117, 67), (108, 50), (100, 60), (117, 60),
                 (108, 67)):
        assert _is(_screen_px(img, x, y, s), RED), (x, y)
    for x, y in ((101, 51), (116, 66), (108, 58), (99, 50), (118, 67), (100, 68)):
        assert _is(_screen_px(img, x, y, s), (85, 85, 85)), (x, y)
    red = np.all(img == np.array(RED, np.uint8), axis=2)
    assert red.sum() == (4 * 17) * s * s                      # the border and nothing else
    assert np.array_equal(o.frame, before)                    # the board is not changed


def test_monitor_crosshair():
    o = Octek()
    o.frame[:] = 15
    o.xhair()
    o.hctab(160, 120)
    s = 2
    img = render_monitor(o, scale=s)
    for x, y in ((165, 120), (155, 120), (160, 115), (160, 125), (162, 120), (160, 127)):
        assert _is(_screen_px(img, x, y, s), RED), (x, y)
    for x, y in ((160, 120), (161, 120), (160, 119), (161, 121), (170, 120), (161, 115)):
        assert _is(_screen_px(img, x, y, s), (255, 255, 255)), (x, y)


def test_monitor_parked_cursor_marked_on_bottom_edge(lab):
    _, _, nova, _ = lab
    d = nova.octek.display
    assert d.cursor_y == 255                 # lcln's last edge map parked the box
    s = 3
    img = render_monitor(nova.octek, scale=s)
    bottom = BEZEL + 240 * s - 1
    assert tuple(img[bottom, BEZEL + d.cursor_x * s + s // 2]) == RED
    ys, xs = np.nonzero(np.all(img == np.array(RED, np.uint8), axis=2))
    assert ys.size > 0
    assert ys.min() >= bottom - 4 * s and ys.max() == bottom
    assert abs(xs.mean() - (BEZEL + d.cursor_x * s + s // 2)) <= 1


# --- line_picture ------------------------------------------------------------

def _colour(img, y, x):
    return tuple(int(v) for v in img[y, x])


def test_line_picture_size_and_pictures(lab):
    left, right, _, res = lab
    s = 4
    img = line_picture(left, right, res, scale=s)
    assert img.shape == (1206, 1128, 3) and img.dtype == np.uint8
    img2 = line_picture(left, right, res, scale=2)
    assert img2.shape == (518 + 172 * 2, 64 + 266 * 2, 3)
    # enlarged pictures: left at x 48, right at x 48 + 138*s, both at y 64
    for r, c in ((10, 5), (100, 100), (0, 0), (119, 127)):
        for x0, pic in ((48, left), (48 + 138 * s, right)):
            block = img[64 + r * s:64 + r * s + s, x0 + c * s:x0 + c * s + s]
            assert np.all(block == 17 * int(pic[r, c])), (r, c)
    # row IY bracketed just above and below row 60
    assert _colour(img, 64 + 60 * s - 1, 48 + 3) == ROW_COLOUR
    assert _colour(img, 64 + 61 * s, 48 + 138 * s + 3) == ROW_COLOUR


def test_line_picture_matched_edges_join_the_pair(lab):
    left, right, _, res = lab
    s = 4
    img = line_picture(left, right, res, scale=s)
    used = used_matches(res)
    assert len(used) == sum(p is not None for p in res.positions.values()) > 10
    # band rows: after pictures (64+480), gap 10, caption 22, numbers 26,
    # profile 128, gap 4, strip 24
    band0 = 64 + 120 * s + 10 + 22 + 26 + 128 + 4 + 6 * s
    band1 = band0 + 40 * s - 1
    palette = {tuple(c) for c in MATCH_PALETTE}
    panel_x = 48 + 5 * s
    for edge, loc1, loc2 in used:
        xa = panel_x + 2 * s * (loc1 - 1) + s
        xb = panel_x + 2 * s * (loc2 - 1) + s
        assert _colour(img, band0, xa) in palette, (edge, loc1)
        assert _colour(img, band1, xb) in palette, (edge, loc2)
        # and ticked in the pictures just above row IY's bracket
        assert _colour(img, 64 + 60 * s - 2, 48 + s * (loc1 - 1) + s // 2) in palette
        assert _colour(img, 64 + 60 * s - 2, 48 + 138 * s + s * (loc2 - 1) + s // 2) in palette
    # the strips are the slices: column c of row 60, 2s pixels wide
    for c in (0, 30, 64, 127):
        assert np.all(img[band0 - 1, panel_x + 2 * s * c:panel_x + 2 * s * c + 2 * s]
                      == 17 * int(left[60, c]))
        assert np.all(img[band1 + 1, panel_x + 2 * s * c:panel_x + 2 * s * c + 2 * s]
                      == 17 * int(right[60, c]))


@dataclass
class _Line:
    iyloc: int
    features1: list
    features2: list
    matches: dict
    positions: dict = field(default_factory=dict)
    used: dict = field(default_factory=dict)


def test_used_matches_reads_the_entry_lcsl_recorded():
    # Edge 1's first entry with disparity > 1 is (40, 30), but LCSL recorded
    # (40, 20) (as it does when the first gives a range of 1.0 or less).
    line = _Line(30, [(40, 42, 3, 12), (50, 52, 12, 3)], [(30, 32, 3, 12)],
                 {1: [(1, 5, 40, 40), (1, 9, 40, 39), (1, 20, 40, 30), (2, 3, 40, 20)],
                  51: [(51, 0, 42, 32)], 2: [(1, 0, 50, 31)], 52: []},
                 {1: (13.5, -2.0, 0.0, 1.5, 0.4, 0.04), 51: (13.5, -1.7, 0.0, 1.5, 0.4, 0.04),
                  2: None, 52: None},
                 {1: (2, 3, 40, 20), 51: (51, 0, 42, 32)})
    assert used_matches(line) == [(1, 40, 20), (51, 42, 32)]


def test_line_picture_joins_the_recorded_entry_at_separation_025(lab):
    # Line 20 at ds 0.25: edge 58's range came from entry (128, 110), not from
    # the first entry with disparity > 1, (128, 30).
    left, right = lab[0], lab[1]
    res = in_process_rig(left, right, "0.25", "180").lcln(20)
    assert res.matches[58][0][2:] == (128, 30)
    assert (58, 128, 110) in used_matches(res)
    s = 4
    img = line_picture(left, right, res, scale=s)
    band1 = 64 + 120 * s + 10 + 22 + 26 + 128 + 4 + 6 * s + 40 * s - 1
    palette = {tuple(c) for c in MATCH_PALETTE}
    assert _colour(img, band1, 48 + 5 * s + 2 * s * (110 - 1) + s) in palette


def test_line_picture_single_match_exact_positions():
    """A hand-made line: one match, LOC1 40 -> LOC2 30, at scale 2."""
    left = np.full((120, 128), 8, np.uint8)
    right = np.full((120, 128), 8, np.uint8)
    left[:, 40:] = 2
    right[:, 30:] = 2
    line = _Line(30, [(40, 41, 8, 2)], [(30, 31, 8, 2)],
                 {1: [(1, 0, 40, 30)], 51: []},
                 {1: (13.5, -2.7, 0.0, 1.5, 0.4, 0.04), 51: None},
                 {1: (1, 0, 40, 30)})
    s = 2
    img = line_picture(left, right, line, scale=s)
    assert img.shape == (518 + 172 * s, 64 + 266 * s, 3)
    band0 = 64 + 120 * s + 10 + 22 + 26 + 128 + 4 + 6 * s
    band1 = band0 + 40 * s - 1
    panel_x = 48 + 5 * s
    first = tuple(MATCH_PALETTE[0])
    assert _colour(img, band0, panel_x + 2 * s * 39 + s) == first
    assert _colour(img, band1, panel_x + 2 * s * 29 + s) == first
    # nothing at the wrong columns: a line that starts at LOC1 40 ends nowhere near LOC2 80
    assert _colour(img, band0, panel_x + 2 * s * 79 + s) == (255, 255, 255)
    assert _colour(img, band1, panel_x + 2 * s * 79 + s) == (255, 255, 255)
    assert _colour(img, band1, panel_x + 2 * s * 39 + s) != first


def test_line_picture_rejects_wrong_shapes(lab):
    left, right, _, res = lab
    with pytest.raises(ValueError):
        line_picture(left[:100], right, res)


# --- topdown_map -------------------------------------------------------------

def _map_xy(dx, dp, R=25):
    return int(round(70 + 320 + dx * 800 / R)), int(round(60 + 800 - dp * 800 / R))


def test_topdown_point_at_computed_pixel():
    img = topdown_map([(10.0, 0.0, 0.5, 0.1)])
    assert img.shape == (1010, 740, 3) and img.dtype == np.uint8
    x, y = _map_xy(0, 10)
    assert (x, y) == (390, 540)
    assert _colour(img, y, x) == POINT_COLOUR
    empty = topdown_map([])
    assert _colour(empty, y, x) != POINT_COLOUR
    # another range scale: dp 10 of 20 ft is half way up
    img20 = topdown_map([{"dp": 10, "dx": 0, "ep": 0.5, "ex": 0.1}], max_range=20)
    assert _colour(img20, 460, 390) == POINT_COLOUR
    assert _colour(img20, 540, 390) != POINT_COLOUR


def test_topdown_error_bars_and_truth():
    # a 6-tuple as in LineResult.positions: (dp, dx, dy, ep, ex, ey)
    img = topdown_map([(10.0, 1.0, 0.0, 2.0, 0.5, 0.05)], truth=[14.0])
    x, y = _map_xy(1, 10)
    assert _colour(img, y, x) == POINT_COLOUR
    assert _colour(img, _map_xy(1, 12)[1], x) == BAR_COLOUR          # dp + ep
    assert _colour(img, _map_xy(1, 8)[1], x) == BAR_COLOUR           # dp - ep
    assert _colour(img, y, _map_xy(0.5, 10)[0]) == BAR_COLOUR        # dx - ex
    assert _colour(img, y, _map_xy(1.5, 10)[0]) == BAR_COLOUR        # dx + ex
    assert _colour(img, _map_xy(1, 12.5)[1], x) != BAR_COLOUR        # bar stops at +ep
    b, g, r = _colour(img, *_map_xy(1, 14)[::-1])                    # true 14: outside
    assert r > 150 and g < 100 and b < 100
    ok = topdown_map([(10.0, 1.0, 0.0, 2.0, 0.5, 0.05)], truth=[11.0])
    b, g, r = _colour(ok, *_map_xy(1, 11)[::-1])                     # true 11: inside
    assert g > 100 and r < 100 and b < 100


def test_topdown_bad_points():
    with pytest.raises(ValueError):
        topdown_map([(1.0, 2.0, 3.0)])
    with pytest.raises(ValueError):
        topdown_map([(10.0, 0.0, 1.0, 0.1)], truth=[9.0, 8.0])


# --- save_png ----------------------------------------------------------------

def test_save_png_round_trip(tmp_path):
    img = np.zeros((40, 60, 3), np.uint8)
    img[..., 0] = np.arange(60, dtype=np.uint8)[None, :] * 4
    img[..., 2] = np.arange(40, dtype=np.uint8)[:, None] * 6
    out = save_png(tmp_path / "a.png", img)
    assert out == tmp_path / "a.png"
    back = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert back is not None and np.array_equal(back, img)
    assert sorted(os.listdir(tmp_path)) == ["a.png"]


def test_save_png_failure_leaves_no_partial_file(tmp_path, monkeypatch):
    target = tmp_path / "pic.png"
    old = np.full((8, 8, 3), 7, np.uint8)
    save_png(target, old)

    def boom(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OSError):
        save_png(target, np.full((8, 8, 3), 200, np.uint8))
    with pytest.raises(OSError):
        save_png(tmp_path / "new.png", np.full((8, 8, 3), 200, np.uint8))
    monkeypatch.undo()
    assert sorted(os.listdir(tmp_path)) == ["pic.png"]            # no temporary left
    assert np.array_equal(cv2.imread(str(target)), old)           # old file intact


def test_save_png_rejects_non_images(tmp_path):
    with pytest.raises(ValueError):
        save_png(tmp_path / "f.png", np.zeros((4, 4), np.float64))
    assert os.listdir(tmp_path) == []


# --- topdown_map: units, fitted axes, bars, legend ------------------------------

def _has(img, colour, rows=slice(None), cols=slice(None)):
    return bool(np.all(img[rows, cols] == np.array(colour, np.uint8), axis=-1).any())


def test_topdown_error_bars_are_optional_and_long_ones_are_cut():
    pt = [(10.0, 1.0, 0.0, 2.0, 0.5, 0.05)]
    assert _has(topdown_map(pt), BAR_COLOUR)
    bare = topdown_map(pt, error_bars=False)
    assert not _has(bare, BAR_COLOUR)
    assert _colour(bare, *_map_xy(1, 10)[::-1]) == POINT_COLOUR
    # ep = 9 ft at R = 25: the bar is cut at 0.2 R = 5 ft each way
    long_bar = topdown_map([(10.0, 1.0, 9.0, 0.5)])
    x = _map_xy(1, 10)[0]
    assert _colour(long_bar, _map_xy(1, 14.8)[1], x) == BAR_COLOUR
    assert _colour(long_bar, _map_xy(1, 15.5)[1], x) != BAR_COLOUR
    assert _colour(long_bar, _map_xy(1, 5.2)[1], x) == BAR_COLOUR
    assert _colour(long_bar, _map_xy(1, 4.5)[1], x) != BAR_COLOUR


def test_topdown_legend_lists_only_what_is_drawn():
    from rig.pictures import TRUTH_IN_COLOUR, TRUTH_OUT_COLOUR
    legend = slice(60 + 800 + 40, None)
    plain = topdown_map([(10.0, 1.0, 2.0, 0.5)], error_bars=False)
    assert not _has(plain, TRUTH_IN_COLOUR, legend) and not _has(plain, TRUTH_OUT_COLOUR, legend)
    assert not _has(plain, BAR_COLOUR, legend)
    assert _has(plain, POINT_COLOUR, legend)
    with_truth = topdown_map([(10.0, 1.0, 2.0, 0.5)], truth=[11.0])
    assert _has(with_truth, TRUTH_IN_COLOUR, legend) and _has(with_truth, BAR_COLOUR, legend)
    assert not _has(topdown_map([]), POINT_COLOUR, legend)


def test_topdown_unit_is_the_separations():
    pt = [(10.0, 1.0, 2.0, 0.5)]
    ft, m = topdown_map(pt, unit="ft"), topdown_map(pt, unit="m")
    plot = (slice(60, 860), slice(70, 710))
    assert np.array_equal(ft[plot], m[plot])          # the same map ...
    assert not np.array_equal(ft, m)                  # ... labelled in another unit


def test_topdown_cameras_are_at_the_origin_and_one_separation_right():
    img = topdown_map([], max_range=5, separation=1.0)          # 160 px per unit
    y = 60 + 800 - 4
    assert _colour(img, y, 70 + 320) == (0, 0, 0)
    assert _colour(img, y, 70 + 320 + 160) == (0, 0, 0)
    assert _colour(img, y, 70 + 320 + 80) != (0, 0, 0)


def test_fitted_range_is_a_nice_value_above_the_bulk_of_the_ranges():
    from rig.pictures import fitted_range
    assert fitted_range([1.0, 2.0, 3.0]) == 4           # 1.1 * 2.9 = 3.19 -> 4
    assert fitted_range([0.2] * 99 + [50.0]) == 0.25    # one far point is an arrow
    assert fitted_range([]) == 1
    left, right = _pair()
    ecl = in_process_rig(left, right)
    dps = [p[0] for y in range(8, 113) for p in ecl.lcln(y).positions.values() if p]
    assert fitted_range(dps) == 25


def test_monitor_picture_labels_left_right_and_the_rows_worked_on(lab):
    from rig.pictures import monitor_picture, MON_HEAD, MON_SIDE
    _, _, nova, _ = lab
    s = 3
    img = monitor_picture(nova.octek, [40, 60], scale=s)
    mon = render_monitor(nova.octek, s)
    assert np.array_equal(img[MON_HEAD:, MON_SIDE:], mon)          # the monitor unchanged
    for x0 in (26, 166):                                            # a label over each picture
        span = slice(MON_SIDE + BEZEL + x0 * s, MON_SIDE + BEZEL + (x0 + 128) * s)
        assert (img[:MON_HEAD, span] < 100).all(axis=-1).sum() > 200
    for y in (40, 60, 59 + 2):
        yc = MON_HEAD + BEZEL + y * s + s // 2
        marked = _colour(img, yc, MON_SIDE - 4) == ROW_COLOUR
        assert marked == (y in (40, 60)), y
