"""Data General REAL as plain integers, for compiled code (QUIRKS M1).

The same model as :class:`diskfmt.dgreal.Real` — each operation exact, then
truncated toward zero to six hex digits — on a value held as two integers
``(m, q)``: ``m * 2**q`` with ``2**20 <= |m| < 2**24`` and ``q`` a multiple of
4.  Everything fits in 64 bits:

* a product of two 24-bit fractions has 48 bits;
* a quotient needs only ``floor(a * 2**28 / b)``: of normalised fractions
  ``a/b`` lies in (1/16, 16), so the six-hex-digit result keeps at most 28
  fraction bits, and truncating a floor again is the floor of the exact value;
* a sum whose exponents differ by more than 36 bits replaces the smaller term
  by a one-bit "sticky" stand-in of the same sign 36 bits below the larger:
  both lie strictly inside the same truncation step of the result, so the
  truncated sum is the same.

tests/test_eyes_dgint.py checks every operation against ``Real``.
"""

from __future__ import annotations

from diskfmt.dgreal import Real
from diskfmt.jit import jit

STICKY = 36


@jit
def dg_norm(n, q):
    """Truncate the exact value ``n * 2**q`` toward zero to six hex digits."""
    if n == 0:
        return 0, 0
    a = -n if n < 0 else n
    bits = 0
    t = a
    while t >= 16:
        t >>= 4
        bits += 4
    while t:
        t >>= 1
        bits += 1
    top = bits - 1 + q
    qn = -((23 - top) // 4) * 4
    if qn >= q:
        a >>= qn - q
    else:
        a <<= q - qn
    return (-a if n < 0 else a), qn


@jit
def dg_from_int(i):
    return dg_norm(i, 0)


@jit
def dg_mul(m1, q1, m2, q2):
    return dg_norm(m1 * m2, q1 + q2)


@jit
def dg_div(m1, q1, m2, q2):
    """``m1*2**q1 / m2*2**q2``; the caller never divides by zero (LCSL's
    divisors are disparities above 1 and a non-zero DVIRT)."""
    if m1 == 0:
        return 0, 0
    a = -m1 if m1 < 0 else m1
    b = -m2 if m2 < 0 else m2
    n = (a << 28) // b
    if (m1 < 0) != (m2 < 0):
        n = -n
    return dg_norm(n, q1 - q2 - 28)


@jit
def dg_add(m1, q1, m2, q2):
    if m1 == 0:
        return m2, q2
    if m2 == 0:
        return m1, q1
    if q1 >= q2:
        mb, qb, ms, qs = m1, q1, m2, q2
    else:
        mb, qb, ms, qs = m2, q2, m1, q1
    d = qb - qs
    if d <= STICKY:
        return dg_norm((mb << d) + ms, qs)
    return dg_norm((mb << STICKY) + (1 if ms > 0 else -1), qb - STICKY)


@jit
def dg_gt(m1, q1, m2, q2):
    """``a > b`` for normalised values (a larger exponent is a larger magnitude)."""
    s1 = int(m1 > 0) - int(m1 < 0)            # int(): plain Python (RIG_NO_JIT) too
    s2 = int(m2 > 0) - int(m2 < 0)
    if s1 != s2:
        return s1 > s2
    if s1 == 0:
        return False
    if q1 != q2:
        return q1 > q2 if s1 > 0 else q1 < q2
    return m1 > m2


@jit
def dg_word(m, q):
    """The REAL's 32-bit storage word (sign, excess-64 hex exponent, fraction);
    -1 when the exponent does not fit (``Real.to_bytes`` raises there)."""
    if m == 0:
        return 0
    exp = (q + 24) // 4 + 64
    if exp < 0 or exp > 127:
        return -1
    a = -m if m < 0 else m
    return (0x80000000 if m < 0 else 0) | (exp << 24) | a


def mq(r: Real) -> tuple[int, int]:
    """A :class:`Real` as ``(m, q)`` (normalised, as every Real result is)."""
    return int(r.m), int(r.q)
