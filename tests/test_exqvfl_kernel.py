"""EXQVFL's kernel: the integer form of its REAL averages."""

import pytest

from diskfmt.dgreal import Real, HALF
from nstar.exqvfl import mean_plus_half


@pytest.mark.parametrize("count", [1, 2, 3])
def test_integer_mean_equals_dg_real_arithmetic_for_every_reachable_sum(count):
    # SUM is at most 3 pixels x 15; IVAVE=(SUM/INUM)+.5 in truncating DG REAL.
    for total in range(0, 3 * 15 + 1):
        dg = int(Real.from_int(total) / Real.from_int(count) + HALF)
        assert mean_plus_half(total, count) == dg, (total, count)


# The compiled kernel against the same code run as plain Python (a separate
# interpreter with RIG_NO_JIT=1, helpers included): tests/test_no_jit.py.
