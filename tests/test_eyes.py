"""The eyes (one compiled frame scan) against the reference path — ESTAR's
Eclipse over the direct link to NSTAR's Nova, and the two-process file link:
feature lists, match lists, located positions, NBLOB counts and the POSIT.DT
image after every line, bit for bit, with and without marf_sign_fix; and each
compiled piece against the routine it replaces."""

import numpy as np
import pytest

from diskfmt.dgreal import Real
from diskfmt.layouts import decode_bi
from estar.lcsl import locate
from estar.masl import Options
try:
    from estar.marf import marf_kernel
except ImportError:                    # before MARF had its own module
    from estar.masl import marf_kernel
from eyes import Eyes, scan_pair as eyes_scan_pair
from eyes.kernels import (OFFSET0, build_frame, level_windows, lcsl_offset, lcsl_range,
                          _quality, marf_best_shift, marf_best_shift_stepwise, marf_no_shift,
                          nblob_many, new_tables, new_windows)
from nstar.bitmaps import command_geometry, edge_map_kernel
from nstar.program import Nova
from rig import scan as scanmod
from rig.scene import bundled_path
from rig.session import file_link_eclipse

LINES = list(range(8, 113))
FIELDS = ("iyloc", "features1", "features2", "matches", "positions", "posit", "requests")


def bundled_pair():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def synthetic_pair(seed: int):
    """A seeded stereo pair: a textured background at disparity 2 and a few
    rectangles of flat grey or stripes nearer (disparity 3..20), each drawn
    in the right picture shifted left by its disparity, with grey-level
    noise."""
    rng = np.random.default_rng(seed)
    h, w = 120, 128
    margin = 32
    world = np.repeat(rng.integers(0, 16, size=(h, (w + margin) // 4 + 1)), 4, axis=1)
    world = world[:, :w + margin]
    disp = np.full((h, w + margin), 2)
    for _ in range(rng.integers(3, 8)):
        y0, x0 = rng.integers(0, h - 10), rng.integers(0, w + margin - 20)
        hh, ww = rng.integers(8, 60), rng.integers(6, 50)
        if rng.random() < 0.5:
            patch = rng.integers(0, 16)
        else:
            patch = np.where((np.arange(ww) // rng.integers(2, 6)) % 2, rng.integers(0, 8),
                             rng.integers(8, 16))[None, :]
        region = (slice(y0, y0 + hh), slice(x0, x0 + ww))
        world[region] = np.broadcast_to(patch, (hh, ww))[:world[region].shape[0],
                                                        :world[region].shape[1]]
        disp[region] = rng.integers(3, 21)
    left = world[:, :w]
    right = np.empty((h, w), dtype=np.int64)
    cols = np.arange(w)
    for y in range(h):
        # right(x) = world(x + d) where d is the disparity of the point seen there
        right[y] = world[y, np.minimum(cols + disp[y, cols], w + margin - 1)]
    noise = lambda pic: np.clip(pic + (rng.random(pic.shape) < 0.05)
                                * rng.choice([-1, 1], pic.shape), 0, 15)
    return noise(left).astype(np.uint8), noise(right).astype(np.uint8)


def assert_same_scan(left, right, lines=LINES, **options):
    ref = scanmod.scan_pair(left, right, lines, options=Options(**options))
    fast = Eyes(options=Options(**options)).scan(left, right, lines, keep_posit=True)
    got = fast.line_results()
    assert len(got) == len(ref.results) == len(lines)
    for a, b in zip(ref.results, got):
        for name in FIELDS:
            assert getattr(a, name) == getattr(b, name), f"line {a.iyloc}: {name} differs"
    assert fast.requests.sum() == ref.requests
    return ref, fast


# --- whole scans ----------------------------------------------------------------

@pytest.mark.parametrize("sign_fix", [False, True])
def test_bundled_pair_every_line_identical_to_the_reference(sign_fix):
    ref, fast = assert_same_scan(*bundled_pair(), marf_sign_fix=sign_fix)
    assert len(ref.points) > 2000 and ref.requests > 5000      # a real workload
    assert fast.posit() == ref.last_posit


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5])
@pytest.mark.parametrize("sign_fix", [False, True])
def test_generated_scenes_identical_to_the_reference(seed, sign_fix):
    left, right = synthetic_pair(seed)
    ref, _ = assert_same_scan(left, right, marf_sign_fix=sign_fix)
    assert len(ref.points) > 100


def test_motorcycle_identical_to_the_reference():
    pytest.importorskip("skimage")
    from bench.accuracy import motorcycle
    left, right, *_ = motorcycle()
    for sign_fix in (False, True):
        assert_same_scan(left, right, marf_sign_fix=sign_fix)


def test_any_set_of_lines_in_any_order():
    # COMMON /MATCH/ and /POSIT/ carry from line to line, so order matters
    assert_same_scan(*bundled_pair(), lines=[60, 8, 60, 119, 0, 112, 33])


def test_one_eyes_object_scans_many_frames_from_fresh_commons():
    left, right = bundled_pair()
    eyes = Eyes()
    other_l, other_r = synthetic_pair(9)
    eyes.scan(other_l, other_r)
    again = eyes.scan(left, right, keep_posit=True).line_results()
    ref = scanmod.scan_pair(left, right)
    assert [r.posit for r in again] == [r.posit for r in ref.results]


def test_scan_result_and_csv_equal_rig_scan():
    left, right = bundled_pair()
    ref = scanmod.scan_pair(left, right)
    fast = eyes_scan_pair(left, right)
    assert fast.points == ref.points
    assert fast.requests == ref.requests and fast.lines == ref.lines
    assert Eyes().scan(left, right).csv_text() == scanmod.csv_text(ref.points)


def test_file_link_gives_what_the_eyes_give(tmp_path):
    lines = list(range(8, 113, 13))
    with file_link_eclipse(tmp_path / "jhdata", bundled_path("LAB-L.BI"),
                           bundled_path("LAB-R.BI")) as ecl:
        via_files = scanmod.run_lines(ecl, lines)
    fast = Eyes().scan(*bundled_pair(), lines, keep_posit=True).line_results()
    for a, b in zip(via_files.results, fast):
        for name in FIELDS:
            assert getattr(a, name) == getattr(b, name), f"line {a.iyloc}: {name}"
    assert (tmp_path / "jhdata" / "POSIT.DT").read_bytes() == fast[-1].posit


def test_bad_pictures_and_lines_are_refused():
    left, right = bundled_pair()
    with pytest.raises(ValueError, match="right picture"):
        Eyes().scan(left, right[:100])
    with pytest.raises(ValueError, match="0..119"):
        Eyes().scan(left, right, [120])


# --- the compiled pieces ----------------------------------------------------------

def test_frame_store_is_novas_after_label_800():
    left, right = synthetic_pair(7)
    nova = Nova()
    nova.load_pair(left, right)
    assert np.array_equal(build_frame(left, right), nova.octek.frame)
    # refilled in place after another pair, and from other integer and float types
    reused = build_frame(*synthetic_pair(8))
    assert build_frame(left, right, reused) is reused
    assert np.array_equal(reused, nova.octek.frame)
    for dtype in (np.int64, np.int16, np.float64):
        assert np.array_equal(build_frame(left.astype(dtype) + 32, right.astype(dtype) - 16,
                                          reused), nova.octek.frame), dtype
    assert np.array_equal(build_frame(left + 0.75, right + 0.25), nova.octek.frame)


def test_level_windows_are_the_rows_at_most_each_grey_level():
    """Every word of the level windows against their definition, computed
    plainly; written over a window store that held another pair's."""
    windows = new_windows()
    level_windows(build_frame(*synthetic_pair(3)), windows)
    for left, right in (synthetic_pair(13), bundled_pair()):
        frame = build_frame(left, right)
        level_windows(frame, windows)
        for i, pic in enumerate((frame[0:120, 26:154], frame[0:120, 166:294])):
            for q in range(4):
                rows = np.arange(32 * q, 32 * q + 64)
                inside = rows < 120
                for g in range(17):
                    below = np.zeros((64, 128), dtype=bool)
                    below[inside] = pic[rows[inside]] <= g - 1
                    want = (below.astype(np.uint64) << np.arange(64, dtype=np.uint64)[:, None]
                            ).sum(axis=0, dtype=np.uint64)
                    assert np.array_equal(windows[i, q, g, 8:136], want), (i, q, g)
                    assert not windows[i, q, g, :8].any() and not windows[i, q, g, 136:].any()


def test_edge_maps_equal_nstar_label_500_everywhere():
    """Every edge map ESTAR can ask for (X 1..128 and the clamped 0, 129; every
    third line and the lines near the windows' seams and the picture's edges;
    both sides; both pictures) against NSTAR's edge_map_kernel, and each map's
    bit count."""
    left, right = synthetic_pair(11)
    frame = build_frame(left, right)
    windows = new_windows()
    level_windows(frame, windows)
    maps = np.zeros((2, 100, 4), dtype=np.uint64)
    bits = np.zeros((2, 100), dtype=np.int64)
    grey = np.full((2, 320), 99, dtype=np.uint8)           # stale work space
    ref = np.zeros(16, dtype=np.int64)
    seams = [y for t in (0, 32, 64, 96, 120) for y in range(t - 1 + 7 - 16, t + 8)]
    for y in sorted(set(range(0, 120, 3)) | {y for y in seams if 0 <= y < 120}):
        requests = np.array([(image, 1 + (x + 130 * (ies > 0)) % 100, x, ies)
                             for image in (1, 2) for ies in (-1, 1) for x in range(130)])
        for start in range(0, len(requests), 100):
            chunk = requests[start:start + 100]
            nblob_many(frame, windows, y, chunk, len(chunk), maps, bits, grey)
            for image, edge, x, ies in chunk:
                _, x0, x1, y0, y1, _, _, ixc, iyc = command_geometry(image, x, y)
                edge_map_kernel(frame, ixc, iyc, ies, x0, x1, y0, y1, ref)
                limbs = maps[image - 1, edge - 1]
                words = [(int(limbs[c // 4]) >> (16 * (c % 4))) & 0xFFFF for c in range(16)]
                assert words == [w & 0xFFFF for w in ref], (image, x, y, ies)
                assert bits[image - 1, edge - 1] == sum(bin(w).count("1") for w in words)


def limbs_of(words) -> list:
    limbs = [0, 0, 0, 0]
    for c, w in enumerate(words):
        limbs[c // 4] |= int(w) << (16 * (c % 4))
    return [np.uint64(v) for v in limbs]


def test_marf_best_shift_equals_marf_kernel():
    rng = np.random.default_rng(5)
    values = np.zeros(257, dtype=np.int64)
    for trial in range(3000):
        density = rng.random()
        cols = (rng.random((2, 16, 16)) < density) * (1 << np.arange(16))
        words = cols.sum(axis=2)
        if trial % 7 == 0:
            words[1] = np.roll(words[0], rng.integers(-4, 5))     # a true match nearby
        m17 = [np.concatenate(([1], w - 65536 * (w > 32767))).astype(np.int64) for w in words]
        iwst = int(rng.integers(0, 20))
        want = marf_kernel(m17[0], m17[1], iwst, values)
        got = marf_best_shift(*limbs_of(words[0]), *limbs_of(words[1]), iwst)
        assert tuple(got) == tuple(want), (trial, iwst)


def test_quality_through_a_double_is_the_integer_quotient():
    """Every ND 0..127 and NTOT 1..512 MARF can meet (two 256-bit maps)."""
    for ntot in range(1, 513):
        for nd in range(0, 128):
            assert _quality(nd, ntot) == (nd * 256) // ntot, (nd, ntot)


def test_marf_stepwise_equals_marf_best_shift():
    """The stepped MARF (the one the frame scan uses) against the plain one:
    maps empty, sparse, dense, full and near-matches, every IWST 0..20 (16 and
    beyond compare nothing), ties between shifts left and right."""
    rng = np.random.default_rng(8)
    for trial in range(4000):
        kind = trial % 5
        density = (0.0, 0.05, rng.random(), 1.0, 0.5)[kind]
        words = ((rng.random((2, 16, 16)) < density) * (1 << np.arange(16))).sum(axis=2)
        if kind == 4:
            words[1] = np.roll(words[0], rng.integers(-6, 7))   # a true match nearby
            words[1, rng.integers(0, 16)] ^= int(rng.integers(0, 65536))
        if trial % 11 == 0:
            words[1] = words[0][::-1]                           # mirror: equal shifts tie
        a, b = limbs_of(words[0]), limbs_of(words[1])
        for iwst in range(0, 21):
            assert marf_best_shift_stepwise(*a, *b, iwst) == marf_best_shift(*a, *b, iwst), \
                (trial, iwst)


def test_marf_no_shift_equals_marf_kernel_at_iwst_0():
    """The one-shift MARF the frame scan uses when IWST = 0 against MARF
    itself: empty, sparse, dense and full maps, equal maps, near-equal ones."""
    rng = np.random.default_rng(12)
    values = np.zeros(257, dtype=np.int64)
    for trial in range(3000):
        density = (0.0, 0.03, rng.random(), 1.0, 0.5)[trial % 5]
        words = ((rng.random((2, 16, 16)) < density) * (1 << np.arange(16))).sum(axis=2)
        if trial % 3 == 0:
            words[1] = words[0]
            words[1, rng.integers(0, 16)] ^= int(rng.integers(0, 65536))
        m17 = [np.concatenate(([1], w - 65536 * (w > 32767))).astype(np.int64) for w in words]
        want = marf_kernel(m17[0], m17[1], 0, values)
        a, b = limbs_of(words[0]), limbs_of(words[1])
        ta, tb = (int(sum(bin(int(w)).count("1") for w in ws)) for ws in words)
        assert want[0] == 0 and marf_no_shift(*a, ta, *b, tb) == want[1], trial


@pytest.mark.parametrize("ds, dv", [("0.75", "180"), ("1.3", "97.5"), ("0.1", "1000")])
def test_lcsl_terms_equal_dg_real_locate(ds, dv):
    """Every (disparity, offset) term table against estar.lcsl.locate in
    diskfmt.dgreal arithmetic: disparities 2..199, LOC1 1..128, lines 0..119."""
    eyes = Eyes(ds, dv)
    t = new_tables()
    dsep, dvirt = Real.const(ds), Real.const(dv)
    for disp in range(2, 200):
        lcsl_range(disp, eyes.consts, t["range_done"], t["range_mq"])
        dpm, dpq, epm, epq, dpw, epw = t["range_mq"][disp]
        for offset in range(-60, 69):
            lcsl_offset(offset, disp, dpm, dpq, epm, epq, eyes.consts, t["offset_done"],
                        t["offset_words"])
        for loc1 in range(1, 129, 5 if disp % 7 else 1):
            iy = (loc1 * 7 + disp) % 120
            want = locate(loc1, loc1 - disp, iy, dsep, dvirt)
            row_x = t["offset_words"][disp, loc1 - 60 + OFFSET0]
            row_y = t["offset_words"][disp, iy - 60 + OFFSET0]
            got = [dpw, row_x[0], row_y[0], epw, row_x[1], row_y[1]]
            assert [int.from_bytes(r.to_bytes(), "big") for r in want] == got, (disp, loc1, iy)


def test_a_flat_pair_locates_nothing_and_writes_just_the_header():
    flat = np.full((120, 128), 7, dtype=np.uint8)
    fast = Eyes().scan(flat, flat)
    assert len(fast.point_rows) == 0
    assert fast.csv_text() == scanmod.csv_text([]) == ",".join(scanmod.CSV_COLUMNS) + "\n"


def test_the_eyes_as_plain_python_equal_the_compiled_scan():
    """``RIG_NO_JIT=1``: the same kernels run as plain Python (no numba) give
    every array the compiled scan gives, on three lines of the bundled pair."""
    import json
    import subprocess
    import sys
    from rig.session import child_env
    lines = [20, 60, 100]
    code = ("import json\n"
            "from diskfmt.jit import ENABLED\n"
            "assert not ENABLED\n"
            "from tests.test_eyes import bundled_pair\n"
            "from eyes import Eyes\n"
            f"f = Eyes().scan(*bundled_pair(), {lines!r}, keep_posit=True)\n"
            "print(json.dumps({k: getattr(f, k).tolist() for k in "
            "('nfeat', 'ifeat', 'requests', 'match_start', 'match_rows', 'point_start', "
            "'point_rows', 'point_words', 'posit_words')}))\n")
    env = dict(child_env(), RIG_NO_JIT="1")
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    plain = json.loads(run.stdout)
    compiled = Eyes().scan(*bundled_pair(), lines, keep_posit=True)
    assert len(compiled.point_rows) > 30
    for name, value in plain.items():
        assert value == getattr(compiled, name).tolist(), name
