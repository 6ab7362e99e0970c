"""The accuracy benchmark's helpers (bench/accuracy.py): the ground truth goes
through the same crop and scale as PRE's import path, and the metrics count
what they say."""

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from pre.condense import condense
from pre.digitize import digitize, fit

_PATH = Path(__file__).resolve().parent.parent / "bench" / "accuracy.py"
_spec = importlib.util.spec_from_file_location("bench_accuracy", _PATH)
acc = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("bench_accuracy", acc)      # dataclasses look their module up
_spec.loader.exec_module(acc)


# --- the crop mapping is PRE's ---------------------------------------------------

@pytest.mark.parametrize("h, w", [(500, 741), (480, 640), (300, 200), (240, 256), (720, 1280)])
def test_crop_map_size_matches_pre_fit(h, w):
    """Cutting the crop out of the picture and scaling gives what fit() gives."""
    rng = np.random.default_rng(h * w)
    g = rng.uniform(0, 255, (h, w))
    c = acc.crop_map(h, w)
    assert 0 <= c.x0 and c.x0 + c.cw <= w and 0 <= c.y0 and c.y0 + c.ch <= h
    cut = g[c.y0:c.y0 + c.ch, c.x0:c.x0 + c.cw]
    np.testing.assert_array_equal(fit(cut, "stretch"), fit(g, "crop"))


def test_crop_map_of_the_motorcycle_shape():
    c = acc.crop_map(500, 741)
    assert (c.x0, c.y0, c.cw, c.ch) == (104, 0, 533, 500)
    assert c.disparity_scale == pytest.approx(128 / 533)


def test_a_stripe_lands_where_the_mapping_says():
    """A white band between two 128-px column boundaries of the original comes
    out of digitize + condense on exactly those columns."""
    h, w = 500, 741
    c = acc.crop_map(h, w)
    img = np.zeros((h, w), dtype=np.uint8)
    a = c.x0 + 40 * c.col_step
    b = c.x0 + 60 * c.col_step
    img[:, int(math.ceil(a)):int(math.floor(b))] = 255
    small = condense(digitize(img))
    profile = small[60]
    assert (profile[41:59] == 15).all()
    assert (profile[:39] == 0).all() and (profile[61:] == 0).all()
    # a horizontal band on rows 30..49 likewise
    img = np.zeros((h, w), dtype=np.uint8)
    img[int(math.ceil(30 * c.row_step)):int(math.floor(50 * c.row_step)), :] = 255
    col = condense(digitize(img))[:, 64]
    assert (col[31:49] == 15).all()
    assert (col[:29] == 0).all() and (col[51:] == 0).all()


# --- ground truth at the rig's scale ------------------------------------------------

def test_gt_scaled_to_128_columns_through_the_crop():
    h, w = 500, 741
    c = acc.crop_map(h, w)
    d = np.full((h, w), 999.0)                       # the cut margins: must not leak in
    mid = c.x0 + c.cw // 2
    d[:, c.x0:mid] = 40.0
    d[:, mid:c.x0 + c.cw] = 80.0
    d[:100, c.x0:c.x0 + c.cw] = np.inf               # Middlebury's "unknown"
    gt = acc.gt_at_rig_scale(d, c)
    assert gt.shape == (120, 128)
    s = 128 / 533
    np.testing.assert_allclose(gt[40:, :60], 40 * s)
    np.testing.assert_allclose(gt[40:, 68:], 80 * s)
    assert np.isnan(gt[:23]).all()                   # rows 0..99 -> lines 0..23 invalid
    assert np.nanmax(gt) == pytest.approx(80 * s)


def test_gt_invalid_values_and_half_valid_rule():
    d = np.full((240, 256), 10.0)                    # no crop: 2x2 footprints
    d[0, 0] = np.nan
    d[0, 1] = 0.0                                    # 0 is invalid too
    d[2, 2] = np.inf                                 # one of four: still valid
    d[4:6, 4:5] = np.inf                             # two of four: half, still valid
    d[6:8, 6:8] = np.inf                             # all four: invalid
    d[8, 8:10] = np.inf
    d[9, 8] = np.nan                                 # three of four: invalid
    gt = acc.gt_at_rig_scale(d)
    assert gt[0, 0] == pytest.approx(5.0)            # half valid -> the valid median, x 0.5
    assert gt[1, 1] == pytest.approx(5.0)
    assert gt[2, 2] == pytest.approx(5.0)
    assert np.isnan(gt[3, 3]) and np.isnan(gt[4, 4])
    assert np.isfinite(gt).sum() == 120 * 128 - 2


def test_gt_median_picks_the_majority_surface():
    d = np.full((240, 256), 20.0)
    d[0:2, 0:2] = [[20.0, 60.0], [20.0, 20.0]]
    assert acc.gt_at_rig_scale(d)[0, 0] == pytest.approx(10.0)


def test_true_disparity_at_takes_the_nearest_surface():
    gt = np.full((3, 6), np.nan)
    gt[1] = [2.0, 3.0, 7.0, np.nan, 4.0, np.nan]
    assert acc.true_disparity_at(gt, 1, 1, 0) == 3.0
    assert acc.true_disparity_at(gt, 1, 1, 1) == 7.0
    assert acc.true_disparity_at(gt, 1, 3, 1) == 7.0          # invalid centre, valid neighbour
    assert acc.true_disparity_at(gt, 1, 3, 0) != acc.true_disparity_at(gt, 1, 3, 0)  # NaN
    assert acc.true_disparity_at(gt, 1, 5, 1) == 4.0          # clipped at the border
    assert math.isnan(acc.true_disparity_at(gt, 0, 2, 1))
    assert math.isnan(acc.true_disparity_at(gt, 1, 6, 1))     # outside the picture


# --- metrics ---------------------------------------------------------------------

def test_metrics_on_hand_made_errors():
    m = acc.metrics([0.0, 0.5, -1.5, 2.5, np.nan, 1.0, -2.0])
    assert m.n == 6
    assert m.bad1 == pytest.approx(3 / 6)            # |e| > 1: -1.5, 2.5, -2.0 (1.0 is not)
    assert m.bad2 == pytest.approx(1 / 6)            # |e| > 2: 2.5 (-2.0 is not)
    assert m.median_abs == pytest.approx(1.25)       # 0, .5, 1, 1.5, 2, 2.5


def test_metrics_of_nothing():
    m = acc.metrics([np.nan])
    assert m.n == 0 and math.isnan(m.bad1) and math.isnan(m.median_abs)


def test_within_bound():
    # disparity 2 -> range 67.5; ep of the rig at disparity 2 is 67.5
    # true range = 0.75*180 / true disparity: 67.5, 90, 33.75
    r = acc.within_bound([67.5, 67.5, 33.75], [1.0, 10.0, 1.0], [2.0, 1.5, 4.0])
    assert r.tolist() == [True, False, True]          # |67.5 - 90| = 22.5 > 10
    assert acc.within_bound([67.5], [22.5], [1.5]).tolist() == [True]   # the bound is inclusive


def test_disp_above():
    class P:
        def __init__(self, d):
            self.disparity = d
    assert acc.disp_above([P(3), P(16), P(15)], 15.4).tolist() == [False, True, False]


# --- matchers -----------------------------------------------------------------

def test_matchers_find_a_known_shift_on_4_bit_texture():
    pytest.importorskip("cv2")
    rng = np.random.default_rng(5)
    tex = rng.integers(0, 16, (120, 160), dtype=np.uint8)
    left = tex[:, 16:144]
    right = tex[:, 20:148]                            # left column x is right column x - 4
    for make in (acc.make_bm, acc.make_sgbm):
        d = acc.matcher_disparity(make(), left, right)
        assert d.shape == (120, 128)
        inner = d[20:100, 40:110]
        assert np.nanmedian(inner) == pytest.approx(4.0, abs=0.25)
        assert np.isnan(d[:, :5]).all()                # no answer at the left border


# --- the marked block in the docs -------------------------------------------------

def test_write_out_replaces_only_the_marked_block(tmp_path):
    p = tmp_path / "a.md"
    p.write_text(f"intro\n{acc.BEGIN}\nold\n{acc.END}\nafter\n")
    acc.write_out(p, "| new |")
    assert p.read_text() == f"intro\n{acc.BEGIN}\n| new |\n{acc.END}\nafter\n"
    q = tmp_path / "b.md"
    acc.write_out(q, "T")
    assert q.read_text() == f"{acc.BEGIN}\nT\n{acc.END}\n"


# --- the real pair (needs scikit-image) ------------------------------------------

def test_motorcycle_through_pre():
    pytest.importorskip("skimage")
    left, right, l256, gt, c = acc.motorcycle()
    assert left.shape == right.shape == gt.shape == (120, 128)
    assert l256.shape == (240, 256) and left.max() <= 15
    np.testing.assert_array_equal(condense(l256), left)
    assert (c.cw, c.x0) == (533, 104)
    lo, hi = np.nanmin(gt), np.nanmax(gt)
    assert 1.5 < lo < hi < 15.0                       # 7.2..59.9 px in the original x 128/533
    assert np.isfinite(gt).mean() > 0.9
