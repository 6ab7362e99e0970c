"""Acceptance tests for the Data General REAL model (diskfmt/dgreal.py).

External truth used here (copied; the tests read nothing outside the repository):

* QUIRKS M1: REAL is the IBM S/360 layout -- sign bit, 7-bit exponent
  (power of 16, excess 64), 24-bit fraction (6 hex digits), sign-magnitude.
  1.0 = 41100000, -1.0 = C1100000, 0.5 = 40800000, 0 = 00000000.
* QUIRKS M1: every operation is computed exactly, then truncated toward zero
  to a normalised 6-hex-digit fraction; REAL -> INTEGER truncates toward zero
  (``IVAVE=(SUM/INUM)+.5``); ``Fw.d`` rounds the *stored* value half away
  from zero; a field too narrow prints asterisks.
* Appendix D prints F-format values with a leading zero ("0.125", "0.000").

Expected bit patterns are written out literally (worked by hand, see comments)
and, where a value comes out of a computation, re-derived by ``_dg_hex`` below,
which implements the storage definition directly with ``fractions`` and never
calls the code under test.
"""

from fractions import Fraction

import pytest
from hypothesis import given, settings, strategies as st

from diskfmt.dgreal import Real, fortran_f, DGRealError


# --- an independent model of the format ---------------------------------------

def _dg_hex(x) -> str:
    """The DG REAL bit pattern of the exact rational x truncated toward zero, by
    definition: find e with 16**(e-1) <= |x| < 16**e, keep floor(|x|*16**(6-e))."""
    x = Fraction(x)
    if x == 0:
        return "00000000"
    neg = x < 0
    a = abs(x)
    e = 0
    while a >= 1:
        a /= 16
        e += 1
    while a < Fraction(1, 16):
        a *= 16
        e -= 1
    frac = int(a * 16**6)            # floor of a positive number = truncation
    word = (0x80000000 if neg else 0) | ((e + 64) << 24) | frac
    return f"{word:08X}"


def _hex(r: Real) -> str:
    return r.to_bytes().hex().upper()


def _from_hex(h: str) -> Real:
    return Real.from_bytes(bytes.fromhex(h))


def test_independent_model_agrees_with_the_documented_patterns():
    # Guard on the helper itself: the four patterns of docs/formats.md (REAL).
    assert _dg_hex(1) == "41100000"
    assert _dg_hex(-1) == "C1100000"
    assert _dg_hex(Fraction(1, 2)) == "40800000"
    assert _dg_hex(0) == "00000000"


# --- storage -------------------------------------------------------------------

@pytest.mark.parametrize("make, expected", [
    (lambda: Real.from_int(1), "41100000"),      # 1 = .1 hex * 16**1 -> exp 65
    (lambda: Real.from_int(-1), "C1100000"),     # sign bit set, same magnitude
    (lambda: Real.const("0.5"), "40800000"),     # .8 hex * 16**0 -> exp 64
    (lambda: Real.const(".5"), "40800000"),
    (lambda: Real.from_int(180), "42B40000"),    # 180 = B4 hex = .B4 * 16**2
    (lambda: Real.const("180.0"), "42B40000"),
    (lambda: Real.from_int(0), "00000000"),
    (lambda: Real.const("0.75"), "40C00000"),    # .C hex
    (lambda: Real.from_int(-32768), "C4800000"),  # 8000 hex = .8 * 16**4
    (lambda: Real.from_int(15), "41F00000"),
    (lambda: Real.from_int(16), "42100000"),
])
def test_known_bit_patterns(make, expected):
    assert _hex(make()) == expected


@pytest.mark.parametrize("h, value", [
    ("41100000", Fraction(1)),
    ("C1100000", Fraction(-1)),
    ("40800000", Fraction(1, 2)),
    ("42B40000", Fraction(180)),
    ("41210000", Fraction(33, 16)),            # 2.1 hex
    ("3F16C16C", Fraction(0x16C16C, 16**7)),
    ("00000000", Fraction(0)),
])
def test_decoding_bit_patterns(h, value):
    r = _from_hex(h)
    assert r.fraction() == value
    assert _hex(r) == h                         # and back


def test_words_are_big_endian_high_word_first():
    assert Real.from_int(1).to_words() == (0x4110, 0x0000)
    assert Real.from_words(0xC110, 0x0000).fraction() == -1
    assert Real.from_words(0x42B4, 0).fraction() == 180


def test_dirty_zero_reads_as_zero():
    # A zero fraction with a stray sign/exponent is still zero.
    assert _from_hex("C1000000").fraction() == 0
    assert _from_hex("41000000") == 0


def test_wrong_length_is_rejected():
    with pytest.raises(DGRealError):
        Real.from_bytes(b"\x41\x10\x00")
    with pytest.raises(DGRealError):
        Real.from_bytes(b"\x41\x10\x00\x00\x00")


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 0xFFFFFFFF))
def test_every_bit_pattern_has_the_defined_value(word):
    """value = (-1)**sign * fraction/16**6 * 16**(exponent-64), by definition."""
    frac = word & 0xFFFFFF
    exp = (word >> 24) & 0x7F
    neg = bool(word & 0x80000000)
    want = Fraction(frac, 16**6) * Fraction(16) ** (exp - 64)
    if neg:
        want = -want
    r = Real.from_bytes(word.to_bytes(4, "big"))
    assert r.fraction() == want
    if frac >= 0x100000:                        # normalised: exact round trip
        assert r.to_bytes() == word.to_bytes(4, "big")
    elif frac == 0:
        assert r.to_bytes() == b"\x00\x00\x00\x00"


# --- truncation of constants and arithmetic -------------------------------------

def test_one_third_truncates():
    # 1/3 = .555555|555... hex: truncated, not rounded (rounding gives the same
    # digits here, so 2/3 below is the sharper case).
    third = Real.from_int(1) / Real.from_int(3)
    assert _hex(third) == "40555555"
    assert _hex(Real.from_int(-1) / 3) == "C0555555"
    assert _hex(Real.from_int(1) / -3) == "C0555555"


def test_two_thirds_truncates_toward_zero_not_to_nearest():
    # 2/3 = .AAAAAA|AAA... hex; round-to-nearest would give ...AB.
    assert _hex(Real.from_int(2) / 3) == "40AAAAAA"
    assert _hex(Real.from_int(-2) / 3) == "C0AAAAAA"   # toward zero, not floor


def test_one_over_180():
    # 256/180 = 64/45 = 1 + 19/45; 19/45*16 = 6 r 34/45; 34/45*16 = 12 (C) r 4/45;
    # 4/45*16 = 1 r 19/45 -> repeats: 1/180 = .016C16C16C... hex
    # = .16C16C|16C * 16**-1 -> exponent 63 = 3F, fraction 16C16C (truncated).
    assert _hex(Real.from_int(1) / Real.from_int(180)) == "3F16C16C"
    assert _hex(Real.from_int(-1) / 180) == "BF16C16C"
    assert _dg_hex(Fraction(1, 180)) == "3F16C16C"


def test_decimal_constants_truncate():
    # 0.1 = .1999999... hex -> 40199999 (nearest would be 4019999A).
    assert _hex(Real.const("0.1")) == "40199999"
    assert _hex(Real.const("-0.1")) == "C0199999"
    # 3.1415926 (the listing's constant): 3.243F6... hex.
    assert _hex(Real.const("3.1415926")) == _dg_hex(Fraction("3.1415926")) == "413243F6"


def test_product_of_truncated_third_and_three_is_below_one():
    # .555555 hex * 3 = .FFFFFF hex exactly: the truncation of 1/3 shows.
    r = (Real.from_int(1) / 3) * 3
    assert _hex(r) == "40FFFFFF"
    assert r < 1
    # and 1 - that = 16**-6 = .1 hex * 16**-5 -> exponent 59 = 3B.
    assert _hex(Real.from_int(1) - r) == "3B100000"


def test_product_truncation_matches_definition():
    a = _from_hex("40AAAAAA")
    exact = a.fraction() * a.fraction()            # needs 48 bits
    assert _hex(a * a) == _dg_hex(exact)
    assert _hex(a * -a) == _dg_hex(-exact)
    # 4/9 = .71C71C... hex, but 2/3 was already truncated, so the square
    # falls just below: .71C71B|...
    assert _hex(a * a) == "4071C71B"


def test_sum_truncates_toward_zero():
    # Near 1.0 the last hex digit is worth 16**-5 = 2**-20.
    tiny = Real.from_fraction(Fraction(1, 2**21))  # half a unit in the last place
    assert _hex(tiny) == "3B800000"                # 2**-21 = .8 hex * 16**-5
    assert _hex(Real.from_int(1) + tiny) == "41100000"        # dropped
    assert _hex(Real.from_int(-1) - tiny) == "C1100000"       # toward zero, not floor
    unit = Real.from_fraction(Fraction(1, 2**20))
    assert _hex(Real.from_int(1) + unit) == "41100001"
    assert _hex(Real.from_int(-1) - unit) == "C1100001"


def test_sum_with_carry_into_new_hex_digit_truncates():
    # F.FFFFF hex + .08 hex = 10.07FFF hex exactly; renormalised to
    # .1007FF|F * 16**2 the last digit is cut: 421007FF.
    a = _from_hex("41FFFFFF")                      # 16 - 16**-5
    b = Real.const("0.03125")                      # 2**-5 = .08 hex
    exact = a.fraction() + b.fraction()
    assert _hex(a + b) == _dg_hex(exact) == "421007FF"


@settings(max_examples=200, deadline=None)
@given(st.integers(-10**6, 10**6), st.integers(1, 10**4), st.integers(-10**6, 10**6),
       st.integers(1, 10**4))
def test_arithmetic_is_exact_then_truncated(n1, d1, n2, d2):
    a = Real.from_fraction(Fraction(n1, d1))
    b = Real.from_fraction(Fraction(n2, d2))
    assert _hex(a) == _dg_hex(Fraction(n1, d1))
    fa, fb = a.fraction(), b.fraction()
    assert _hex(a + b) == _dg_hex(fa + fb)
    assert _hex(a - b) == _dg_hex(fa - fb)
    assert _hex(a * b) == _dg_hex(fa * fb)
    if fb != 0:
        assert _hex(a / b) == _dg_hex(fa / fb)


# --- REAL -> INTEGER -------------------------------------------------------------

@pytest.mark.parametrize("h, expected", [
    ("41280000", 2),      # 2.5
    ("C1280000", -2),     # -2.5 -> -2 (toward zero, not floor -3)
    ("C0800000", 0),      # -0.5 -> 0
    ("40FFFFFF", 0),      # 0.99999994
    ("C0FFFFFF", 0),
    ("41FFFFFF", 15),     # 15.99999
    ("C1FFFFFF", -15),
    ("42B40000", 180),
])
def test_int_truncates_toward_zero(h, expected):
    assert int(_from_hex(h)) == expected


def test_ivave_expression():
    # IVAVE=(SUM/INUM)+.5 with SUM=14, INUM=3: 4.666|..+.5 = 5.1666 -> 5.
    assert int(Real.from_int(14) / 3 + Real.const(".5")) == 5
    # SUM=13: 4.333..+.5 = 4.8333 -> 4.
    assert int(Real.from_int(13) / 3 + Real.const(".5")) == 4
    # SUM=9, INUM=2: 4.5+.5 = 5.0 exactly -> 5.
    assert int(Real.from_int(9) / 2 + Real.const(".5")) == 5
    # negative: -14/3+.5 = -4.1666 -> -4 (floor would be -5).
    assert int(Real.from_int(-14) / 3 + Real.const(".5")) == -4


# --- Fw.d ---------------------------------------------------------------------------

@pytest.mark.parametrize("h, w, d, text", [
    # 2.0625 = 2.1 hex is exactly representable: 2062.5 -> half away -> 2.063
    ("41210000", 6, 3, " 2.063"),
    ("C1210000", 6, 3, "-2.063"),
    # one unit (16**-5) below: 2.06249904... -> 2.062
    ("4120FFFF", 6, 3, " 2.062"),
    ("C120FFFF", 6, 3, "-2.062"),
    # Appendix D's -4.312 vs -4.313: 4.3125 = 4.5 hex exactly
    ("C1450000", 6, 3, "-4.313"),
    ("C144FFFF", 6, 3, "-4.312"),
    # leading zero, as Appendix D prints 0.125 and 0.000
    ("40200000", 7, 3, "  0.125"),
    ("00000000", 7, 3, "  0.000"),
    ("40800000", 5, 3, "0.500"),
    ("42B40000", 8, 3, " 180.000"),
    # 1/3 truncated = 0.33333331... -> 0.333
    ("40555555", 6, 3, " 0.333"),
    # .FFFFFF = 0.99999994 -> rounds up to 1.000
    ("40FFFFFF", 6, 3, " 1.000"),
    # field overflow -> asterisks (1234.5 = 4D2.8 hex, exact)
    ("434D2800", 7, 2, "1234.50"),
    ("434D2800", 6, 2, "******"),
    # -10.0 in F5.2 needs 6 characters
    ("C1A00000", 6, 2, "-10.00"),
    ("C1A00000", 5, 2, "*****"),
    # 9.9996 (= 9.FFE5C|... hex, truncated) rounds to 10.000, which no longer
    # fits F5.3
    ("419FFE5C", 6, 3, "10.000"),
    ("419FFE5C", 5, 3, "*****"),
])
def test_fortran_f(h, w, d, text):
    assert fortran_f(_from_hex(h), w, d) == text


def test_fortran_f_pattern_helpers_are_what_the_comments_say():
    # guard the literal patterns used above against typos
    assert _from_hex("434D2800").fraction() == Fraction(24690, 20)
    assert _from_hex("C1A00000").fraction() == -10
    assert _from_hex("C1450000").fraction() == Fraction(-69, 16)
    assert _from_hex("40200000").fraction() == Fraction(1, 8)
    # 9.9996 truncated: within one unit (16**-5) below 9.9996, above 9.9995
    assert Fraction("9.9996") > _from_hex("419FFE5C").fraction() > Fraction("9.9995")
    assert _from_hex("419FFE5C").fraction() > Fraction("9.9996") - Fraction(1, 16**5)
