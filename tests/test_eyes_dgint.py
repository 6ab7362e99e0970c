"""eyes.dgint: Data General REAL on integers, against diskfmt.dgreal.Real
(each operation exact, then truncated toward zero to six hex digits)."""

from fractions import Fraction

import numpy as np
import pytest

from diskfmt.dgreal import Real
from eyes.dgint import dg_add, dg_div, dg_from_int, dg_gt, dg_mul, dg_word, mq


def reals(rng, n):
    """Normalised REALs over a wide range of magnitudes, both signs, and the
    small integers LCSL meets."""
    out = [Real.from_int(i) for i in range(-130, 131)]
    for _ in range(n):
        m = int(rng.integers(1 << 20, 1 << 24)) * (1 if rng.random() < 0.5 else -1)
        out.append(Real(m, 4 * int(rng.integers(-30, 10))))
    out += [Real.const(t) for t in ("0.5", "0.75", "180", "3.1415926", "1e-9", "97.5")]
    return out


def word(r: Real) -> int:
    return int.from_bytes(r.to_bytes(), "big")


@pytest.mark.parametrize("op, fn", [("mul", dg_mul), ("div", dg_div), ("add", dg_add)])
def test_binary_operations_equal_real(op, fn):
    rng = np.random.default_rng(12)
    xs = reals(rng, 300)
    idx = rng.integers(0, len(xs), size=(6000, 2))
    for i, j in idx:
        a, b = xs[i], xs[j]
        if op == "div" and b.m == 0:
            continue
        want = a * b if op == "mul" else a / b if op == "div" else a + b
        got = fn(*mq(a), *mq(b))
        assert tuple(got) == mq(want), (op, a, b)


def test_sums_far_apart_use_the_sticky_bit_correctly():
    one = Real.from_int(1)
    for tiny_q in (-40, -60, -80, -120):
        for m in (1 << 20, (1 << 24) - 1):
            for s in (1, -1):
                tiny = Real(s * m, tiny_q)
                for big in (one, -one, Real.from_int(16), Real.const("0.0625")):
                    want = big + tiny
                    assert tuple(dg_add(*mq(big), *mq(tiny))) == mq(want)
                    assert tuple(dg_add(*mq(tiny), *mq(big))) == mq(want)


def test_from_int_compare_and_word_equal_real():
    rng = np.random.default_rng(3)
    xs = reals(rng, 200)
    for i in range(-300, 300, 7):
        assert tuple(dg_from_int(i)) == mq(Real.from_int(i))
    for a in xs:
        assert dg_word(*mq(a)) == word(a)
        for b in xs[::17]:
            assert bool(dg_gt(*mq(a), *mq(b))) == (a > b), (a, b)


def test_word_out_of_range_is_flagged():
    assert dg_word(1 << 20, 4 * 70) == -1
    with pytest.raises(Exception):
        Real(1 << 20, 4 * 70).to_bytes()
    assert Fraction(1) == Real.from_int(1).fraction()
