"""Files of NSTAR's bit-map extensions (beyond 1985; docs/formats.md, "Extensions").

The 1985 NSTAR ignores these command codes and the faithful ESTAR never sends them; NSTAR
answers them only when started with its ``bitmap_extensions`` option.  NCONT.DT is the 1985
layout (code, IMF, IXCTR, IYCTR, IRAD, IDN); the replies:

* ``RBMAP.DT`` (code 11, radial bit map), 28 words = 56 bytes: 11, IORNT (the sector, 0..15,
  stored first: the orientation in steps of 22.5 degrees clockwise from the +x axis), SFR
  (REAL, pixels per ring), ICX, ICY (the map's centre, image columns and rows, truncated),
  ICNTR(6) (the Star region, as BLOCK.DT), IRMAP(16) (the sectors, the word with most ones first,
  clockwise; bit 0 the innermost ring);
* ``OPMAP.DT`` (codes 12 and 13, a rectangular map and its operations), 129 words = 258 bytes:
  the code, then eight 16-word maps in the order A, V, L, R, H, T, B, P (Appendix B's
  equations B-2..B-8 of the map A; columns and bits as WBMAP.DT).
"""

from __future__ import annotations

from dataclasses import dataclass

from diskfmt.dgreal import DGRealError, Real
from diskfmt.layouts import FormatError, _need_size, bytes_from_words, words_from_bytes

CODE_RADIAL_MAP = 11          # the Star region's radial bit map -> RBMAP.DT
CODE_EDGE_OPERATIONS = 12     # label 500's edge map, then B-2..B-8 -> OPMAP.DT
CODE_BLOCK_OPERATIONS = 13    # code 1's block map, then B-2..B-8 -> OPMAP.DT
EXTENSION_CODES = (CODE_RADIAL_MAP, CODE_EDGE_OPERATIONS, CODE_BLOCK_OPERATIONS)
RBMAP_BYTES = 56
OPMAP_BYTES = 258
OPERATION_ORDER = ("A", "V", "L", "R", "H", "T", "B", "P")


@dataclass
class RadialMap:
    orientation: int
    sfr: Real
    icx: int
    icy: int
    icntr: list[int]
    irmap: list[int]


def encode_rbmap(m: RadialMap) -> bytes:
    return (bytes_from_words([CODE_RADIAL_MAP, m.orientation]) + m.sfr.to_bytes()
            + bytes_from_words([m.icx, m.icy] + list(m.icntr) + list(m.irmap)))


def decode_rbmap(data: bytes, name: str = "RBMAP.DT") -> RadialMap:
    _need_size(name, data, RBMAP_BYTES)
    w = words_from_bytes(data)
    if w[0] != CODE_RADIAL_MAP:
        raise FormatError(name, f"first word is {w[0]}, expected {CODE_RADIAL_MAP}")
    if not 0 <= w[1] <= 15:
        raise FormatError(name, f"orientation (word 2) is {w[1]}, not 0..15")
    try:
        sfr = Real.from_bytes(data[4:8])
    except DGRealError as exc:
        raise FormatError(name, f"scale factor is not a DG REAL ({exc})") from None
    return RadialMap(w[1], sfr, w[4], w[5], w[6:12], [v & 0xFFFF for v in w[12:28]])


def encode_opmap(code: int, maps: dict) -> bytes:
    words = [code]
    for k in OPERATION_ORDER:
        m = list(maps[k])
        if len(m) != 16:
            raise ValueError(f"map {k} has {len(m)} words, expected 16")
        words += m
    return bytes_from_words(words)


def decode_opmap(data: bytes, name: str = "OPMAP.DT") -> tuple[int, dict]:
    _need_size(name, data, OPMAP_BYTES)
    w = [v & 0xFFFF for v in words_from_bytes(data)]
    code = w[0]
    if code not in (CODE_EDGE_OPERATIONS, CODE_BLOCK_OPERATIONS):
        raise FormatError(name, f"first word is {code}, expected 12 or 13")
    return code, {k: tuple(w[1 + 16 * i:17 + 16 * i]) for i, k in enumerate(OPERATION_ORDER)}
