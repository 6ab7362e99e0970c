"""The eyes' EXQVFL (eyes/exqvfl.py) against the listing's label-by-label
kernel (nstar.exqvfl.exqvfl_kernel, the reference: tests/test_exqvfl.py holds
it to feature lists worked out by hand from the listing): NFEAT, the too-many exit and the whole IFEAT table,
entries past NFEAT included, from the same stale table."""

from __future__ import annotations

import numpy as np
import pytest

from diskfmt.layouts import decode_bi
from eyes.exqvfl import exqvfl_fast, new_work
from nstar.exqvfl import NFMAX, exqvfl_kernel
from rig.scene import bundled_path


def run_both(pix, ilast, ithr, stale):
    """Both kernels on one line from copies of the same (4, 50) table."""
    pix = np.ascontiguousarray(pix, dtype=np.int64)
    ref_t, fast_t = stale.copy(), stale.copy()
    ref = exqvfl_kernel(pix, ilast, ithr, ref_t)
    fast = exqvfl_fast(pix, ilast, ithr, fast_t, new_work(len(pix)))
    return ref, ref_t, fast, fast_t


def assert_rows_equal(rows, ithrs=(2,), ilasts=(128,), seed=0):
    """Every row through both kernels; returns how many hit label 500."""
    rng = np.random.default_rng(seed)
    too_many = 0
    for i, row in enumerate(rows):
        stale = rng.integers(-5, 200, size=(4, NFMAX)).astype(np.int32)
        for ithr in ithrs:
            for ilast in ilasts:
                ref, ref_t, fast, fast_t = run_both(row, ilast, ithr, stale)
                assert (int(fast[0]), bool(fast[1])) == (int(ref[0]), bool(ref[1])), \
                    (i, ithr, ilast, row.tolist())
                np.testing.assert_array_equal(fast_t, ref_t, err_msg=f"row {i}, ithr {ithr}, "
                                                                     f"ilast {ilast}")
                too_many += bool(ref[1])
    return too_many


def slices(left, right):
    """The 128-pixel slices NSTAR label 600 reads: every row, both pictures, low 4 bits."""
    return [np.asarray(p, dtype=np.int64)[y] & 15 for p in (left, right) for y in range(120)]


def test_every_row_of_the_bundled_pair():
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    assert_rows_equal(slices(left, right), ithrs=(0, 1, 2, 3, 6), ilasts=(128, 127, 64, 3))


def test_every_row_of_the_motorcycle_pair():
    pytest.importorskip("skimage")
    from bench.accuracy import motorcycle
    left, right, *_ = motorcycle()
    assert_rows_equal(slices(left, right), ithrs=(0, 1, 2, 3, 6), ilasts=(128, 127, 64, 3))


def test_random_4bit_rows():
    rng = np.random.default_rng(1985)
    uniform = rng.integers(0, 16, size=(3000, 128))
    # grey ramps with flats, gentle steps and plateaus: labels 110/120's slow paths
    walks = np.clip(8 + np.cumsum(rng.choice([-2, -1, 0, 0, 0, 1, 2], size=(3000, 128)),
                                  axis=1), 0, 15)
    steps = np.repeat(rng.integers(0, 16, size=(1000, 43)), 3, axis=1)[:, :128]
    zigzag = np.tile([0, 15], (4, 64))                 # a feature a pixel: label 500
    zigzag[1] = np.tile([0, 1, 2], 43)[:128]
    zigzag[2] = np.tile([7, 8], 64)
    zigzag[3] = np.tile([0, 0, 15, 15], 32)
    rows = list(uniform) + list(walks) + list(steps) + list(zigzag)
    hit = assert_rows_equal(rows, ithrs=(2,), ilasts=(128,))
    hit += assert_rows_equal(rows[::10], ithrs=(0, 1, 4, 15), ilasts=(128, 100, 2, 1), seed=1)
    assert hit > 0                                    # the too-many exit was compared too


def test_a_few_hand_lines():
    """Lines read off the listing: one steep edge; a gentle ramp; all flat."""
    stale = np.zeros((4, NFMAX), dtype=np.int32)
    ramp = np.array([5] * 10 + [6, 7, 8, 9] + [9] * 10)
    _, _, fast, table = run_both(ramp, len(ramp), 2, stale)
    assert int(fast[0]) == 1 and table[:, 0].tolist() == [10, 14, 5, 9]
    _, _, fast, _ = run_both(np.full(128, 7), 128, 2, stale)
    assert int(fast[0]) == 0
