"""The bundled laboratory stereo pair (rig/scene.py) and edge scoring (rig/truth.py)."""

import numpy as np
import pytest

from diskfmt.layouts import decode_bi, decode_vd, encode_bi, encode_vd
from pre.condense import condense
from rig import scene, truth
from rig.scene import FOCAL_128, LEFT_X, RIGHT_X


@pytest.fixture(scope="module")
def pair():
    return scene.render_pair()


def _files(pair):
    return {
        "LAB-L.VD": encode_vd(pair.left), "LAB-R.VD": encode_vd(pair.right),
        "LAB-L.BI": encode_bi(pair.left_bi), "LAB-R.BI": encode_bi(pair.right_bi),
        "LAB-RANGE.npy": scene.range_npy_bytes(pair.range_left),
    }


def _u128(x, z, cam_x):
    """Continuous 128-px column (pixel j spans [j, j+1)) of a point at X=x, Z=z."""
    return 64.0 + FOCAL_128 * (x - cam_x) / z


def _v128(y, z):
    return 60.0 + FOCAL_128 * y / z


# --- determinism and the shipped files -----------------------------------------

def test_render_twice_gives_identical_bytes(pair):
    again = scene.render_pair()
    assert _files(again) == _files(pair)


def test_a_different_seed_changes_only_the_noise(pair):
    other = scene.render_pair(seed=7)
    assert not np.array_equal(other.left, pair.left)
    assert np.abs(other.left.astype(int) - pair.left.astype(int)).max() <= 2
    assert np.array_equal(other.range_left, pair.range_left)


def test_shipped_files_equal_a_fresh_render(pair, tmp_path):
    written = scene.make_files(tmp_path, pair=pair)
    assert sorted(written) == sorted(scene.FILES)
    for name in scene.FILES:
        shipped = scene.bundled_path(name).read_bytes()
        assert shipped == written[name].read_bytes(), name
        assert shipped == _files(pair)[name], name


def test_bundled_path_rejects_unknown_names():
    with pytest.raises(ValueError):
        scene.bundled_path("LAB-X.VD")


def test_make_files_renders_when_no_pair_given(pair, tmp_path):
    written = scene.make_files(tmp_path / "new")
    assert written["LAB-L.BI"].read_bytes() == encode_bi(pair.left_bi)


# --- pictures -------------------------------------------------------------------

def test_grey_levels_within_0_to_15_and_well_spread(pair):
    for pic in (pair.left, pair.right, pair.left_bi, pair.right_bi):
        assert pic.dtype == np.uint8
        assert pic.min() >= 0 and pic.max() <= 15
    assert pair.left.shape == pair.right.shape == (240, 256)
    assert pair.left_bi.shape == pair.right_bi.shape == (120, 128)
    counts = np.bincount(pair.left.ravel(), minlength=16)
    assert (counts > 0).sum() >= 14          # most of the 16 levels are used


def test_shipped_bi_is_condense_of_shipped_vd():
    for side in "LR":
        vd = decode_vd(scene.bundled_path(f"LAB-{side}.VD").read_bytes())
        bi = decode_bi(scene.bundled_path(f"LAB-{side}.BI").read_bytes())
        assert np.array_equal(bi, condense(vd))


def test_antialiasing_gives_intermediate_levels_at_edges():
    """Noise-free render: a vertical check boundary of the crate falls inside a
    256-px column, which then holds a grey strictly between the two checks'."""
    z, x = scene.CRATE_Z[0], scene.CRATE_X[0] + 0.35
    u = 128 + 360 * (x - LEFT_X) / z               # 256-px continuous column
    assert 0.1 < u - np.floor(u) < 0.9              # not on a pixel boundary
    col, row = int(u), int(120 + 360 * 1.0 / z)
    clean = scene.quantise(scene.render_view(LEFT_X)).astype(int)
    a, m, b = clean[row, col - 3], clean[row, col], clean[row, col + 3]
    assert abs(a - b) >= 5
    assert min(a, b) < m < max(a, b)


def test_noise_is_small_and_sparse(pair):
    clean = scene.quantise(scene.render_view(LEFT_X)).astype(int)
    diff = pair.left.astype(int) - clean
    assert np.abs(diff).max() <= 1
    assert 0.01 < np.count_nonzero(diff) / diff.size < 0.05


# --- truth ----------------------------------------------------------------------

def test_range_file_shape_type_and_span(pair):
    z = scene.bundled_range()
    assert z.dtype == np.float32 and z.shape == (120, 128)
    assert np.array_equal(z, pair.range_left)
    assert 3.0 <= z.min() and z.max() <= 20.0
    assert z.min() == pytest.approx(scene.BIN_Z[0])       # the nearest thing
    assert z.max() == pytest.approx(scene.BACK_Z)          # the back wall
    d = pair.disparity_left
    assert np.allclose(d, 0.75 * 180.0 / z)
    assert d.min() == pytest.approx(135 / 19, rel=1e-6)


@pytest.mark.parametrize("name, x, y, z", [
    ("waste bin", np.mean(scene.BIN_X), 1.0, scene.BIN_Z[0]),
    ("crate", np.mean(scene.CRATE_X), 1.5, scene.CRATE_Z[0]),
    ("striped box", np.mean(scene.SBOX_X), scene.TABLE_TOP_Y - 0.6, scene.SBOX_Z[0]),
    ("carton", scene.CARTON_X[0] + 0.2, 2.5, scene.CARTON_Z[0]),
    ("bookcase", 3.5, -1.0, scene.BOOKCASE_Z[0]),
    ("door", -2.0, -2.0, scene.BACK_Z),
])
def test_range_of_known_object_faces_matches_their_placement(pair, name, x, y, z):
    col = int(_u128(x, z, LEFT_X))
    row = int(_v128(y, z))
    assert pair.range_left[row, col] == pytest.approx(z), name
    assert pair.disparity_left[row, col] == pytest.approx(135.0 / z, rel=1e-6), name


def _edge_column(row_pixels, guess, half=2):
    """Subpixel column of the strongest grey step near ``guess`` (continuous
    128-px coordinates): the |difference|-weighted mean of the step positions
    (a step between pixels j and j+1 lies at j+1)."""
    lo = int(guess) - half
    seg = row_pixels[lo:lo + 2 * half + 1].astype(float)
    steps = np.abs(np.diff(seg))
    strong = steps >= 0.5 * steps.max()
    pos = lo + 1 + np.arange(steps.size)
    return float((steps * strong * pos).sum() / (steps * strong).sum())


@pytest.mark.parametrize("name, x, y, z", [
    ("crate check boundary", scene.CRATE_X[0] + 0.35, 1.0, scene.CRATE_Z[0]),
    ("crate check boundary", scene.CRATE_X[0] + 0.70, 0.7, scene.CRATE_Z[0]),
    ("striped box stripe", scene.SBOX_X[0] + 0.4, scene.TABLE_TOP_Y - 0.6, scene.SBOX_Z[0]),
    ("door panel, right edge", scene.DOOR_PANEL_X[1], -2.5, scene.BACK_Z),
    ("door panel, left edge", scene.DOOR_PANEL_X[0], -2.5, scene.BACK_Z),
    ("carton tape", scene.CARTON_X[0] + 0.5 - 0.12, 2.2, scene.CARTON_Z[0]),
])
def test_edge_shift_between_pictures_equals_disparity_of_its_range(pair, name, x, y, z):
    """Measure an edge in both 128x120 pictures with plain numpy; the shift
    LOC1 - LOC2 equals ds*dv/Z for the truth range there, within 1 px."""
    row = int(_v128(y, z))
    cl = _edge_column(pair.left_bi[row], _u128(x, z, LEFT_X))
    cr = _edge_column(pair.right_bi[row], _u128(x, z, RIGHT_X))
    shift = cl - cr
    assert shift > 0
    z_true = float(pair.range_left[row, int(cl) - 1: int(cl) + 1].min())
    assert z_true == pytest.approx(z), name
    assert abs(shift - 0.75 * 180.0 / z_true) <= 1.0, (name, shift)
    # the edge also sits where the camera model puts it
    assert abs(cl - _u128(x, z, LEFT_X)) <= 0.75, name


def test_rows_are_epipolar_lines(pair):
    """Horizontal boundaries (the crate's rows of checks) fall on the same
    picture rows in both pictures."""
    z, x = scene.CRATE_Z[0], scene.CRATE_X[0] + 0.5     # inside the 2nd check column
    col_l, col_r = int(_u128(x, z, LEFT_X)), int(_u128(x, z, RIGHT_X))
    rows = slice(70, 100)                               # front face, above the bin
    steps_l = np.flatnonzero(np.abs(np.diff(pair.left_bi[rows, col_l].astype(int))) >= 3)
    steps_r = np.flatnonzero(np.abs(np.diff(pair.right_bi[rows, col_r].astype(int))) >= 3)
    assert len(steps_l) >= 2
    assert np.array_equal(steps_l, steps_r)


# --- truth.py on hand-made edge lists -------------------------------------------

def _toy_truth():
    t = np.full((120, 128), 19.0)
    t[:, 40:60] = 5.0          # a near object on columns 40..59 (LOC1 41..60)
    t[:, 90:100] = 10.0
    return t


def test_truth_column_is_loc1_minus_one_rounded():
    assert truth.truth_column(1) == 0
    assert truth.truth_column(128) == 127
    assert truth.truth_column(41.4) == 40
    assert truth.truth_column(41.5) == 41


def test_plain_lookup_and_occluding_boundary():
    t = _toy_truth()
    assert truth.true_range_at(t, 10, 50, halfwidth=0) == 5.0
    # LOC1=40 names column 39 (background); the step is between columns 39 and 40
    assert truth.true_range_at(t, 10, 40, halfwidth=0) == 19.0
    assert truth.true_range_at(t, 10, 40) == 5.0          # default: nearer surface
    assert truth.true_range_at(t, 10, 1) == 19.0           # clipped at the border
    with pytest.raises(ValueError):
        truth.true_range_at(t, 120, 50)
    with pytest.raises(ValueError):
        truth.true_range_at(t, 5, 129)


def test_edge_errors_on_hand_made_edges():
    t = _toy_truth()
    edges = [
        (10, 50, 23, 5.2, 0.3),                              # tuple
        {"IY": 11, "LOC1": 95, "LOC2": 81.5, "DP": 9.0, "EP": 0.5},   # mapping
        truth.Edge(12, 120, 113, 19.0, 1.0),                 # Edge
    ]
    s = truth.edge_errors(edges, t)
    assert [r.true_range for r in s] == [5.0, 10.0, 19.0]
    assert s[0].error == pytest.approx(0.2) and s[0].within_bound
    assert s[1].error == pytest.approx(-1.0) and not s[1].within_bound
    assert s[2].error == 0.0 and s[2].within_bound
    assert s[0].true_disparity == pytest.approx(27.0)
    assert s[0].disparity_error == pytest.approx(0.0)
    assert s[1].disparity_error == pytest.approx(0.0)
    assert s[2].disparity_error == pytest.approx(7 - 135 / 19)
    assert s[0].column == 49


def test_accuracy_table_on_hand_made_edges():
    t = _toy_truth()
    edges = [
        (0, 45, 18, 5.5, 0.2),     # true 5: |err| 0.5 > 0.2
        (1, 46, 19, 4.9, 0.2),     # true 5: 0.1 ok
        (2, 47, 20, 5.3, 0.5),     # true 5: 0.3 ok
        (3, 91, 77, 11.0, 2.0),    # true 10: 1.0 ok
        (4, 10, 3, 17.0, 1.0),     # true 19: 2.0 > 1.0
        (5, 12, 5, 20.0, 1.0),     # true 19: 1.0 ok
    ]
    rows = truth.accuracy_table(edges, truth=t)
    assert [(r.lo, r.hi, r.count) for r in rows] == [
        (0, 5, 0), (5, 10, 3), (10, 15, 1), (15, 25, 2)]
    assert np.isnan(rows[0].median_abs_error) and np.isnan(rows[0].share_within_bound)
    assert rows[1].median_abs_error == pytest.approx(0.3)
    assert rows[1].share_within_bound == pytest.approx(2 / 3)
    assert rows[2].median_abs_error == pytest.approx(1.0)
    assert rows[2].share_within_bound == 1.0
    assert rows[3].median_abs_error == pytest.approx(1.5)
    assert rows[3].share_within_bound == 0.5
    text = truth.format_table(rows)
    assert "67%" in text and text.count("\n") == 5


def test_accuracy_table_uses_the_shipped_truth_by_default(pair):
    """Perfect edges at the crate's check boundary score zero error."""
    z = scene.CRATE_Z[0]
    x = scene.CRATE_X[0] + 0.35
    edges = []
    for y in (0.5, 0.8, 1.1, 1.4):
        row = int(_v128(y, z))
        loc1 = _u128(x, z, LEFT_X) + 0.5      # the pixel right of the step, 1-based
        edges.append((row, loc1, loc1 - 135 / z, z, 0.1))
    rows = truth.accuracy_table(edges)
    assert rows[1].count == 4
    assert rows[1].median_abs_error == pytest.approx(0.0, abs=1e-5)
    assert rows[1].share_within_bound == 1.0
