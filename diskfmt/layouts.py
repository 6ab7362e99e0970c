"""Byte layouts of the files on the shared JHDATA disk (Appendix E, made exact by
the listings; docs/formats.md).

Every word is a 16-bit two's-complement INTEGER stored big-endian; a REAL is two
words in Data General format (:mod:`diskfmt.dgreal`).  Readers take ``bytes`` and
a name for messages; every problem raises :class:`FormatError` naming the file
and what is wrong.  Writers return ``bytes``; publishing them is the job of
:mod:`diskfmt.rdos`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
import struct

import numpy as np

from .dgreal import Real, DGRealError

BLOCK_BYTES = 512
VD_ROWS, VD_COLS = 240, 256      # a .VD picture: PRE's 256x240 frame
BI_ROWS, BI_COLS = 120, 128      # a .BI picture: the 128x120 NSTAR works on
VD_BYTES = 32768
BI_BYTES = 30720
NCONT_BYTES = 12
SLICE_BYTES = 1024
WBMAP_BYTES = 34
BLOCK_DT_BYTES = 54
POSIT_BYTES = 2560
TERM_TEXT = " NOVA processing terminated.\n"

# NCONT.DT command codes (NSTAR.FR header and label 100 dispatch).
CODE_TERMINATE = -1
CODE_STAR = 1
CODE_SLICE = 2
CODE_NEW_PAIR = 3
CODE_EDGE_MAP = 4
KNOWN_CODES = (CODE_TERMINATE, CODE_STAR, CODE_SLICE, CODE_NEW_PAIR, CODE_EDGE_MAP)


class FormatError(ValueError):
    """A file whose size or content cannot be what the 1985 programs wrote."""

    def __init__(self, name: str, problem: str):
        super().__init__(f"{name}: {problem}")
        self.name = name
        self.problem = problem


# --- words -------------------------------------------------------------------

def words_from_bytes(data: bytes) -> list[int]:
    """Big-endian 16-bit signed words (odd trailing byte is the caller's problem)."""
    return list(struct.unpack(f">{len(data) // 2}h", data[: len(data) // 2 * 2]))


def bytes_from_words(words) -> bytes:
    return struct.pack(f">{len(words)}H", *[int(w) & 0xFFFF for w in words])


def wrap16(value: int) -> int:
    """16-bit two's complement, as the NOVA's INTEGER arithmetic wraps."""
    return ((int(value) + 0x8000) & 0xFFFF) - 0x8000


def _need_size(name: str, data: bytes, *sizes: int) -> None:
    if len(data) not in sizes:
        want = " or ".join(str(s) for s in sizes)
        raise FormatError(name, f"{len(data)} bytes, expected {want}")


def read_file(path, limit: int | None = None) -> bytes:
    """Read a whole file, turning a missing or unreadable file into FormatError.
    Only a regular file is read (a FIFO or device would block or never end), and
    with ``limit`` one larger than ``limit`` bytes is refused before reading."""
    from .rdos import NotAProtocolFile, read_regular
    p = Path(path)
    try:
        return read_regular(p, (1 << 30) if limit is None else limit,
                            f"{limit}" if limit is not None else "at most 1 GiB",
                            follow=True)
    except FileNotFoundError:
        raise FormatError(str(p), "no such file") from None
    except NotAProtocolFile as exc:
        if exc.problem == "not a regular file (a directory)":
            raise FormatError(str(p), "is a directory, not a file") from None
        raise FormatError(str(p), exc.problem) from None
    except IsADirectoryError:
        raise FormatError(str(p), "is a directory, not a file") from None
    except OSError as exc:
        raise FormatError(str(p), f"cannot be read ({exc.strerror})") from None


# --- pictures ----------------------------------------------------------------

def decode_vd(data: bytes, name: str = ".VD file") -> np.ndarray:
    """A .VD packed video file: 256x240 4-bit pixels, four to a word, first pixel in
    the high nibble; 64 blocks of 4 rows, of which PRE writes blocks 60-63 as zero."""
    _need_size(name, data, VD_BYTES)
    raw = np.frombuffer(data, dtype=np.uint8)
    nibbles = np.empty(raw.size * 2, dtype=np.uint8)
    nibbles[0::2] = raw >> 4
    nibbles[1::2] = raw & 15
    return nibbles[: 256 * 240].reshape(240, 256).copy()


def encode_vd(picture: np.ndarray) -> bytes:
    pic = np.asarray(picture)
    if pic.shape != (240, 256):
        raise ValueError(f"a .VD picture is 240x256, got {pic.shape}")
    if pic.min(initial=0) < 0 or pic.max(initial=0) > 15:
        raise ValueError("a .VD picture holds 4-bit values 0..15")
    flat = pic.astype(np.uint8).reshape(-1)
    packed = (flat[0::2] << 4) | flat[1::2]
    return packed.tobytes() + bytes(VD_BYTES - packed.size)


def decode_bi(data: bytes, name: str = ".BI file") -> np.ndarray:
    """A .BI picture: 128x120 pixels, one per word, rows top to bottom."""
    _need_size(name, data, BI_BYTES)
    pic = np.frombuffer(data, dtype=">i2").reshape(120, 128)
    bad = np.flatnonzero((pic < 0) | (pic > 15))
    if bad.size:
        r, c = divmod(int(bad[0]), 128)
        raise FormatError(name, f"pixel at row {r}, column {c} is {int(pic[r, c])}, "
                                f"not a 4-bit grey level 0..15 ({bad.size} such words)")
    return pic.astype(np.uint8)


def encode_bi(picture: np.ndarray) -> bytes:
    pic = np.asarray(picture)
    if pic.shape != (120, 128):
        raise ValueError(f"a .BI picture is 120x128, got {pic.shape}")
    if pic.min(initial=0) < 0 or pic.max(initial=0) > 15:
        raise ValueError("a .BI picture holds 4-bit values 0..15")
    return pic.astype(">i2").tobytes()


# --- NCONT.DT ----------------------------------------------------------------

@dataclass(frozen=True)
class Command:
    """NCONT.DT: CODE, IMAGE (1 left, 2 right), X-centre, Y-centre, max radius, IDN."""
    code: int
    image: int = 1
    x: int = 0
    y: int = 0
    radius: int = 0
    idn: int = 0

    def words(self) -> tuple[int, ...]:
        return (self.code, self.image, self.x, self.y, self.radius, self.idn)


_NCONT = struct.Struct(">6h")
_WBMAP = struct.Struct(">17h")


def encode_ncont(cmd: Command) -> bytes:
    return _NCONT.pack(*(wrap16(w) for w in cmd.words()))


def decode_ncont(data: bytes, name: str = "NCONT.DT") -> Command:
    _need_size(name, data, NCONT_BYTES)
    return Command(*_NCONT.unpack(data))


# --- SLICE.DT ----------------------------------------------------------------

@dataclass
class Slice:
    """IFBUF(256) of NSTAR, EQUIVALENCEd: IDIR(7), NFEAT, IFIRST, ILAST, IFEAT(50,4)
    column-major (all starts, all stops, all left greys, all right greys), 46 unused.

    ``ifbuf`` keeps all 256 words, so entries past NFEAT (left over from earlier
    slices, as in 1985) survive a round trip."""
    ifbuf: list[int] = field(default_factory=lambda: [0] * 256)

    @property
    def idir(self) -> list[int]:
        return self.ifbuf[0:7]

    @property
    def nfeat(self) -> int:
        return self.ifbuf[7]

    @property
    def ifirst(self) -> int:
        return self.ifbuf[8]

    @property
    def ilast(self) -> int:
        return self.ifbuf[9]

    def feature(self, k: int) -> tuple[int, int, int, int]:
        """IFEAT(k,1..4) for 1-based k: start, stop, left grey, right grey."""
        return tuple(self.ifbuf[10 + (j * 50) + (k - 1)] for j in range(4))

    def features(self) -> list[tuple[int, int, int, int]]:
        n = self.nfeat
        cols = [self.ifbuf[10 + 50 * j:10 + 50 * j + n] for j in range(4)]
        return list(zip(*cols))


def ifeat_word(k: int, j: int) -> int:
    """0-based IFBUF offset of IFEAT(k, j) (both 1-based), column-major."""
    return 10 + (j - 1) * 50 + (k - 1)


def encode_slice(sl: Slice) -> bytes:
    """SLICE.DT as RDOS leaves it: NSTAR writes IFBUF at block 1, block 0 is zero."""
    return bytes(BLOCK_BYTES) + bytes_from_words(sl.ifbuf)


def decode_slice(data: bytes, name: str = "SLICE.DT") -> Slice:
    _need_size(name, data, SLICE_BYTES, BLOCK_BYTES)
    block = data[-BLOCK_BYTES:]
    words = words_from_bytes(block)
    sl = Slice(words)
    if not 0 <= sl.nfeat <= 50:
        raise FormatError(name, f"NFEAT (word 8) is {sl.nfeat}, not 0..50")
    _check_slice(sl, name)
    return sl


def _check_slice(sl: Slice, name: str) -> None:
    """Every word ESTAR takes from a slice, against what NSTAR's label 600 can
    write: the line (IDIR 3 and 5) 0..119 and the slice 128 pixels long (IDIR 4
    and 6); IFIRST, ILAST and the features' grey levels 0..15; each feature's
    start and stop columns in 1..128, start <= stop.  IDIR(1) and IDIR(7) are
    checked by ESTAR itself (a slice for another line or image is set aside,
    not refused).  Entries past NFEAT are history (QUIRKS N4) and never read."""
    w = sl.ifbuf
    for word, lo, hi, what in ((3, 0, 119, "the line IDIR(3)"), (5, 0, 119, "the line IDIR(5)"),
                               (4, 127, 127, "IDIR(4)"), (6, 128, 128, "the length IDIR(6)"),
                               (9, 0, 15, "IFIRST"), (10, 0, 15, "ILAST")):
        if not lo <= w[word - 1] <= hi:
            want = f"{lo}..{hi}" if lo != hi else str(lo)
            raise FormatError(name, f"{what} (word {word}) is {w[word - 1]}, not {want}")
    for k, (start, stop, left, right) in enumerate(sl.features(), start=1):
        if not (1 <= start <= 128 and 1 <= stop <= 128 and start <= stop):
            raise FormatError(name, f"feature {k} spans columns {start}..{stop}, not a "
                                    f"span within 1..128")
        if not (0 <= left <= 15 and 0 <= right <= 15):
            raise FormatError(name, f"feature {k} has grey levels {left}, {right}, not "
                                    f"0..15")


# --- WBMAP.DT ----------------------------------------------------------------

def encode_wbmap(columns) -> bytes:
    cols = list(columns)
    if len(cols) != 16:
        raise ValueError("an edge bit map has 16 column words")
    return _WBMAP.pack(1, *(wrap16(c) for c in cols))


def decode_wbmap(data: bytes, name: str = "WBMAP.DT") -> list[int]:
    """17 words as NBLOB stores them into IBLB: 1 ("map present"), 16 columns
    (column 1 leftmost, bit 0 the top row)."""
    _need_size(name, data, WBMAP_BYTES)
    words = list(_WBMAP.unpack(data))
    if words[0] != 1:
        raise FormatError(name, f"first word is {words[0]}, expected the constant 1")
    return words


# --- BLOCK.DT ----------------------------------------------------------------

@dataclass
class BlockMap:
    """COMMON /BLOB/ IBLOB(27): IDN, SFX, SFY (REAL), ICNTR(6), IBMAP(16)."""
    idn: int
    sfx: Real
    sfy: Real
    icntr: list[int]
    ibmap: list[int]


def encode_block(b: BlockMap) -> bytes:
    return (bytes_from_words([b.idn]) + b.sfx.to_bytes() + b.sfy.to_bytes()
            + bytes_from_words(list(b.icntr) + list(b.ibmap)))


def decode_block(data: bytes, name: str = "BLOCK.DT") -> BlockMap:
    _need_size(name, data, BLOCK_DT_BYTES)
    words = words_from_bytes(data)
    try:
        sfx = Real.from_bytes(data[2:6])
        sfy = Real.from_bytes(data[6:10])
    except DGRealError as exc:
        raise FormatError(name, f"scale factor is not a DG REAL ({exc})") from None
    return BlockMap(words[0], sfx, sfy, words[5:11], words[11:27])


# --- POSIT.DT ----------------------------------------------------------------

POS_REALS = 640
POSIT_WHOLE_REALS = (POSIT_BYTES - 2) // 4      # 639 whole REALs fit in 5 blocks


@dataclass
class Positions:
    """COMMON /POSIT/ NP, POS(640) as PNPL writes it: 5 blocks, so POS(640) loses
    its second word.  POS(6,100) column-major: POS(1..6, k) for edge k."""
    np_: int
    pos: list[Real]                  # 640 values; POS(640) low word is not on disk

    def entry(self, k: int) -> list[Real]:
        """POS(1..6, k) for edge index k (1..100): dp, dx, dy, ep, ex, ey."""
        return self.pos[(k - 1) * 6:(k - 1) * 6 + 6]


def encode_posit(p: Positions) -> bytes:
    body = b"".join(r.to_bytes() for r in p.pos)
    return (bytes_from_words([p.np_]) + body)[:POSIT_BYTES]


def decode_posit(data: bytes, name: str = "POSIT.DT") -> Positions:
    _need_size(name, data, POSIT_BYTES)
    (np_,) = struct.unpack(">h", data[:2])
    if not 0 <= np_ <= 50:
        raise FormatError(name, f"NP (word 1) is {np_}, not 0..50")
    pos = []
    try:
        for i in range(POSIT_WHOLE_REALS):
            pos.append(Real.from_bytes(data[2 + 4 * i: 6 + 4 * i]))
        pos.append(Real.from_bytes(data[-2:] + b"\x00\x00"))
    except DGRealError as exc:
        raise FormatError(name, f"not a DG REAL ({exc})") from None
    return Positions(np_, pos)
