"""EXQVFL's kernel: the integer form of its REAL averages, and the compiled
kernel against the same code run as plain Python."""

import numpy as np
import pytest

from diskfmt.dgreal import Real, HALF
from diskfmt import jit
from nstar.exqvfl import exqvfl_kernel, mean_plus_half


@pytest.mark.parametrize("count", [1, 2, 3])
def test_integer_mean_equals_dg_real_arithmetic_for_every_reachable_sum(count):
    # SUM is at most 3 pixels x 15; IVAVE=(SUM/INUM)+.5 in truncating DG REAL.
    for total in range(0, 3 * 15 + 1):
        dg = int(Real.from_int(total) / Real.from_int(count) + HALF)
        assert mean_plus_half(total, count) == dg, (total, count)


@pytest.mark.skipif(not jit.ENABLED, reason="numba not installed")
def test_compiled_kernel_equals_plain_python_on_random_rows():
    rng = np.random.default_rng(1985)
    plain = exqvfl_kernel.py_func
    for trial in range(400):
        n = int(rng.integers(1, 129))
        kind = trial % 4
        if kind == 0:
            row = rng.integers(0, 16, n)
        elif kind == 1:                       # smooth-ish rows with gentle slopes
            row = np.clip(np.cumsum(rng.integers(-1, 2, n)) + 8, 0, 15)
        elif kind == 2:                       # flat runs with steps
            row = np.repeat(rng.integers(0, 16, n // 4 + 1), 4)[:n]
        else:
            row = np.clip(np.round(8 + 7 * np.sin(np.arange(n) / rng.uniform(1, 9))), 0, 15)
        row = row.astype(np.int64)
        for thr in (1, 2):
            a = np.full((4, 50), 7, np.int32)
            b = a.copy()
            ra = exqvfl_kernel(row, n, thr, a)
            rb = plain(row, n, thr, b)
            assert (int(ra[0]), bool(ra[1])) == (int(rb[0]), bool(rb[1]))
            assert np.array_equal(a, b)
