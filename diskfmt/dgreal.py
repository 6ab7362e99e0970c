"""Data General single-precision REAL: storage format and truncating arithmetic.

The Eclipse and the NOVA stored REAL in the IBM S/360 layout: a sign bit, a 7-bit
exponent (power of 16, excess 64) and a 24-bit fraction (six hex digits),
sign-magnitude.  Their floating-point units *truncated* every result toward zero
to six hex digits.  QUIRKS M1 settles the model: each operation is computed
exactly, then truncated.  That model reproduces every row of the Appendix D
position table; IEEE arithmetic misses nine of them by one in the last digit.

A value is kept as ``m * 2**q`` with ``2**20 <= |m| < 2**24`` (a normalised hex
fraction) and ``q`` a multiple of 4, so every step is plain integer arithmetic.
"""

from __future__ import annotations

from fractions import Fraction
import math
import struct

__all__ = ["Real", "ZERO", "ONE", "HALF", "DGRealError", "fortran_f"]


class DGRealError(ValueError):
    """A bit pattern or value that a Data General REAL cannot hold."""


def _normalise(n: int, q: int) -> tuple[int, int]:
    """Truncate the exact value ``n * 2**q`` toward zero to a 6-hex-digit fraction."""
    if n == 0:
        return 0, 0
    a = -n if n < 0 else n
    top = a.bit_length() - 1 + q          # binary position of the leading 1
    qn = -((23 - top) // 4) * 4           # ceil((top-23)/4)*4: leading hex digit non-zero
    if qn >= q:
        a >>= qn - q                       # truncation toward zero happens here
    else:
        a <<= q - qn
    return (-a if n < 0 else a), qn


class Real:
    """One Data General REAL.  Arithmetic with ``Real`` or ``int`` operands
    (INTEGER is converted exactly, as the FORTRAN compiler did) truncates."""

    __slots__ = ("m", "q", "_bytes")

    def __init__(self, m: int = 0, q: int = 0, *, _raw: bool = False):
        if _raw:
            self.m, self.q = m, q
        else:
            self.m, self.q = _normalise(m, q)
        self._bytes = None

    # --- construction -------------------------------------------------------
    @classmethod
    def from_int(cls, i: int) -> "Real":
        return cls(int(i), 0)

    @classmethod
    def from_fraction(cls, x: Fraction) -> "Real":
        """Exact rational -> REAL, truncated (decimal constants, library results)."""
        x = Fraction(x)
        if x == 0:
            return ZERO
        num, den = x.numerator, x.denominator
        k = max(0, den.bit_length() - num.bit_length() + 30)
        n = (abs(num) << k) // den           # floor of the magnitude = truncation
        return cls(n if num > 0 else -n, -k)

    @classmethod
    def const(cls, text: str) -> "Real":
        """A FORTRAN constant such as ``.5`` or ``3.1415926`` (truncated to 6 hex digits)."""
        return cls.from_fraction(Fraction(text))

    @classmethod
    def from_float(cls, x: float) -> "Real":
        """A library result (SQRT, COS) computed in double precision, then truncated."""
        if not math.isfinite(x):
            raise DGRealError(f"{x!r} is not a finite number")
        return cls.from_fraction(Fraction(x))

    @staticmethod
    def of(x) -> "Real":
        if isinstance(x, Real):
            return x
        if isinstance(x, int):
            return Real(x, 0)
        raise TypeError(f"cannot mix {type(x).__name__} with a DG REAL")

    # --- arithmetic (each result truncated) ---------------------------------
    def __add__(self, other):
        o = Real.of(other)
        if self.m == 0:
            return o
        if o.m == 0:
            return self
        q = min(self.q, o.q)
        return Real((self.m << (self.q - q)) + (o.m << (o.q - q)), q)

    __radd__ = __add__

    def __neg__(self):
        return Real(-self.m, self.q, _raw=True)

    def __sub__(self, other):
        return self + (-Real.of(other))

    def __rsub__(self, other):
        return Real.of(other) + (-self)

    def __mul__(self, other):
        o = Real.of(other)
        return Real(self.m * o.m, self.q + o.q)

    __rmul__ = __mul__

    def __truediv__(self, other):
        o = Real.of(other)
        if o.m == 0:
            raise ZeroDivisionError("DG REAL division by zero")
        if self.m == 0:
            return ZERO
        a, b = abs(self.m), abs(o.m)
        n = (a << 60) // b                   # 36+ significant bits, floored
        if (self.m < 0) != (o.m < 0):
            n = -n
        return Real(n, self.q - o.q - 60)

    def __rtruediv__(self, other):
        return Real.of(other) / self

    def __abs__(self):
        return Real(abs(self.m), self.q, _raw=True)

    # --- conversion and comparison -----------------------------------------
    def __int__(self) -> int:
        """REAL -> INTEGER truncates toward zero (``IVAVE=(SUM/INUM)+.5``)."""
        if self.q >= 0:
            return self.m << self.q
        a = abs(self.m) >> (-self.q)
        return -a if self.m < 0 else a

    def fraction(self) -> Fraction:
        return Fraction(self.m) * (Fraction(2) ** self.q)

    def __float__(self) -> float:
        return math.ldexp(self.m, self.q)

    def _key(self, other) -> tuple[int, int]:
        o = Real.of(other)
        q = min(self.q, o.q)
        return self.m << (self.q - q), o.m << (o.q - q)

    def __eq__(self, other):
        if not isinstance(other, (Real, int)):
            return NotImplemented
        a, b = self._key(other)
        return a == b

    def __lt__(self, other):
        a, b = self._key(other)
        return a < b

    def __le__(self, other):
        a, b = self._key(other)
        return a <= b

    def __gt__(self, other):
        a, b = self._key(other)
        return a > b

    def __ge__(self, other):
        a, b = self._key(other)
        return a >= b

    def __hash__(self):
        return hash((self.m, self.q))

    def __repr__(self):
        return f"Real({float(self)!r}, hex={self.to_bytes().hex().upper()})"

    # --- storage -------------------------------------------------------------
    def to_bytes(self) -> bytes:
        """Two big-endian 16-bit words: sign, excess-64 hex exponent, 24-bit fraction."""
        if self._bytes is None:
            self._bytes = self._encode()
        return self._bytes

    def _encode(self) -> bytes:
        if self.m == 0:
            return b"\x00\x00\x00\x00"
        exp = (self.q + 24) // 4 + 64
        if not 0 <= exp <= 127:
            raise DGRealError(f"{float(self)!r} is outside the DG REAL exponent range")
        word = (0x80000000 if self.m < 0 else 0) | (exp << 24) | abs(self.m)
        return struct.pack(">I", word)

    @classmethod
    def from_bytes(cls, data: bytes) -> "Real":
        if len(data) != 4:
            raise DGRealError(f"a DG REAL is 4 bytes, got {len(data)}")
        (word,) = struct.unpack(">I", data)
        frac = word & 0xFFFFFF
        exp = (word >> 24) & 0x7F
        if frac == 0:
            return ZERO                      # true zero and "dirty zeros" alike
        if frac < 0x100000:
            # An unnormalised fraction: keep its exact value (the hardware would
            # normalise on the next operation, which is what Real() does).
            pass
        m = -frac if word & 0x80000000 else frac
        return cls(m, 4 * (exp - 64) - 24)

    @classmethod
    def from_words(cls, hi: int, lo: int) -> "Real":
        return cls.from_bytes(struct.pack(">HH", hi & 0xFFFF, lo & 0xFFFF))

    def to_words(self) -> tuple[int, int]:
        hi, lo = struct.unpack(">HH", self.to_bytes())
        return hi, lo


ZERO = Real(0, 0, _raw=True)
ONE = Real(1, 0)
HALF = Real.const(".5")


def fortran_f(value, w: int, d: int) -> str:
    """Format like FORTRAN ``Fw.d``: the stored value rounded half away from zero;
    a field too narrow is filled with asterisks, as the runtime did."""
    x = value.fraction() if isinstance(value, Real) else Fraction(value)
    neg = x < 0
    scaled = abs(x) * 10**d
    n = int(scaled)
    if scaled - n >= Fraction(1, 2):
        n += 1
    digits = str(n).rjust(d + 1, "0")
    text = digits[:-d] + "." + digits[-d:] if d > 0 else digits + "."
    if neg and n != 0:
        text = "-" + text
    if len(text) > w:
        return "*" * w
    return text.rjust(w)
