"""PRE command 3: "Cartoon the image using horizontal and verical QV".

The PRE listing keeps only the command's menu line and one TYPE line
("using passes of horizontal and vertical QV processing."); Chapter II says
what it did: the Queen Victoria production system (:mod:`pre.qv_production`)
reduces each line to smooth and edge intervals, and "an edge enhancing
reconstruction technique" rebuilds the pixels from them, which allows "low bit
rate image transmission".

Our reconstruction of one line from its terminal string:

* a smooth interval ``S`` is filled with its grey level (the mean of its
  pixels, rounded);
* an edge interval ``G+``/``G-`` becomes a sharp step from the level on its
  left (the neighbouring smooth level, or the edge's own end grey where it
  touches another edge or the line's end) to the level on its right -- a ramp
  of the original is sharpened into a step.  The step is put where the
  original crosses half-way: before the first pixel of the interval that is
  nearer the right level than the left one.

A picture is cartooned by a horizontal pass (every row) and then a vertical
pass (every column of the horizontal result).  Each line's feature string is
coded as: a 4-bit start grey, then per terminal symbol 2 bits of kind, 7 bits
of length (lines are at most 128 pixels) and 4 bits of grey level, and for
an edge of length n > 1 the step position in ceil(log2 n) bits; the final
picture is exactly what decoding the vertical pass's codes gives, so those bits
are what a transmission needs (:func:`bits_report`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .qv_production import RULES, Rule, Sym, qv_line, smooth_level

DEFAULT_T = 2           # NSTAR's slice threshold: CALL EXQVFL(IXL, IDAT(2), NFEAT, IFEAT, 2)
KIND_BITS = 2           # S, G+, G-
GREY_BITS = 4           # 16 grey levels


@dataclass(frozen=True)
class Code:
    """One terminal symbol as transmitted: kind, length in pixel steps
    (``stop - start``; shared boundary pixels are not counted twice) and its
    grey level (S: its level; G: the level on its right)."""
    kind: str
    length: int
    grey: int
    step: int = 0      # edges: pixels after the first that keep the left level


def line_codes(pixels: Sequence[int], syms: Sequence[Sym]) -> tuple[int, list[Code]]:
    """The transmitted form of a line's terminal string: (start grey, codes)."""
    px = np.asarray(pixels, dtype=np.int64)
    levels = [smooth_level(px, s) if s.kind == "S" else None for s in syms]
    codes = []
    for k, s in enumerate(syms):
        if s.kind == "S":
            grey = levels[k]
            codes.append(Code(s.kind, s.stop - s.start, int(grey)))
        else:
            nxt = levels[k + 1] if k + 1 < len(syms) else None
            grey = nxt if nxt is not None else s.right
            prev = codes[-1].grey if codes else s.left
            codes.append(Code(s.kind, s.stop - s.start, int(grey),
                              _step(px, s, int(prev), int(grey))))
    if not syms:
        return int(px[0]) if px.size else 0, codes
    first = syms[0]
    start = levels[0] if first.kind == "S" else first.left
    return int(start), codes


def _step(px: np.ndarray, s: Sym, left: int, right: int) -> int:
    """Where the sharp step goes: the number of pixels after the interval's
    first that keep the left level (the first pixel nearer the right level
    than the left one starts the right side)."""
    n = s.stop - s.start
    for k in range(1, n + 1):
        v = int(px[s.start - 1 + k])
        if abs(v - right) < abs(v - left):
            return k - 1
    return n - 1


def decode_line(start: int, codes: Sequence[Code], n: int) -> np.ndarray:
    """Rebuild n pixels from a line's codes (the receiving end)."""
    out = np.full(n, start, dtype=np.uint8)
    pos = 0                          # 0-based index of the current symbol's first pixel
    level = start                    # level on the left of the current symbol
    for c in codes:
        a, b = pos, pos + c.length   # inclusive pixel range of this symbol
        if c.kind == "S":
            out[a:b + 1] = c.grey
        else:
            mid = a + c.step         # sharp step: a..mid left, mid+1..b right
            out[a:mid + 1] = level
            out[mid + 1:b + 1] = c.grey
        level = c.grey
        pos = b
    return out


def cartoon_line(pixels: Sequence[int], t: int = DEFAULT_T,
                 rules: Sequence[Rule] = RULES) -> tuple[np.ndarray, int, list[Code]]:
    """One line through QV and the edge-enhancing reconstruction:
    (new pixels, start grey, codes)."""
    px = [int(v) for v in pixels]
    syms = qv_line(px, t, rules)
    start, codes = line_codes(px, syms)
    return decode_line(start, codes, len(px)), start, codes


def code_bits(codes: Sequence[Code], n: int) -> int:
    """Bits of one line: 4 start bits, (kind + length + grey) per symbol, and
    ceil(log2 n) bits of step position for an edge of length n."""
    length_bits = max(1, int(n - 1).bit_length())
    step_bits = sum(int(c.length - 1).bit_length() for c in codes if c.kind != "S")
    return GREY_BITS + len(codes) * (KIND_BITS + length_bits + GREY_BITS) + step_bits


@dataclass
class CartoonResult:
    picture: np.ndarray          # the cartoon
    horizontal: np.ndarray       # after the horizontal pass only
    bits_h: int                  # feature strings of the horizontal pass
    bits_v: int                  # feature strings of the vertical pass (what is sent)
    symbols_h: int
    symbols_v: int

    @property
    def pixels(self) -> int:
        return int(self.picture.size)

    @property
    def bpp(self) -> float:
        return self.bits_v / self.pixels

    @property
    def bpp_h(self) -> float:
        return self.bits_h / self.pixels


def _pass(pic: np.ndarray, t: int, rules: Sequence[Rule]) -> tuple[np.ndarray, int, int]:
    out = np.empty_like(pic)
    bits = nsym = 0
    for r in range(pic.shape[0]):
        line, _, codes = cartoon_line(pic[r], t, rules)
        out[r] = line
        bits += code_bits(codes, pic.shape[1])
        nsym += len(codes)
    return out, bits, nsym


def cartoon(picture: np.ndarray, t: int = DEFAULT_T, passes: str = "hv",
            rules: Sequence[Rule] = RULES) -> CartoonResult:
    """PRE command 3 on a picture (normally the 120x128 condensed one):
    horizontal QV pass, then vertical QV pass on its result."""
    pic = np.asarray(picture, dtype=np.uint8)
    if pic.ndim != 2:
        raise ValueError("a picture is two-dimensional")
    if passes not in ("hv", "h", "v"):
        raise ValueError("passes: 'hv', 'h' or 'v'")
    h, bits_h, nsym_h = (_pass(pic, t, rules) if "h" in passes else (pic.copy(), 0, 0))
    if "v" in passes:
        vt, bits_v, nsym_v = _pass(h.T.copy(), t, rules)
        final = vt.T.copy()
    else:
        final, bits_v, nsym_v = h, bits_h, nsym_h
    return CartoonResult(final, h, bits_h, bits_v, nsym_h, nsym_v)


def bits_report(result: CartoonResult, name: str = "picture") -> str:
    raw = 4.0
    return (f"{name}: {result.picture.shape[1]}x{result.picture.shape[0]} pixels; "
            f"horizontal pass {result.symbols_h} symbols, {result.bpp_h:.3f} bits/pixel; "
            f"after the vertical pass {result.symbols_v} symbols, {result.bpp:.3f} bits/pixel "
            f"(raw {raw:.0f} bits/pixel, ratio {raw / result.bpp if result.bpp else float('inf'):.1f}:1)")
