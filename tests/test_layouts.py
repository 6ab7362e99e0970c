"""Acceptance tests for the JHDATA disk formats (diskfmt/layouts.py).

External truth (copied here; the tests read nothing outside the repository):

Appendix E and docs/formats.md --
  * every word is a 16-bit two's-complement INTEGER, big-endian; a REAL is two
    words in DG format (1.0 = 41100000, 0.5 = 40800000, -1.0 = C1100000).
  * .VD      32768 bytes: 256x240 pixels, 4 bits, four to a word, first pixel in
             the high nibble; 64 blocks of 4 rows, blocks 60-63 zero.
  * .BI      30720 bytes: 128x120 pixels, one per INTEGER word, rows top to bottom.
  * NCONT.DT 12 bytes: CODE, IMAGE (1 left, 2 right), X-centre, Y-centre,
             max radius / count, IDN.  CFEAT sends 2,1,0,IYLOC,128,0 for a slice.
  * SLICE.DT 1024 bytes: block 0 zero, block 1 = IFBUF(256); EQUIVALENCE
             (IFBUF(8), NFEAT), (IFBUF(11), IFEAT(1,1)); IFEAT(50,4) column-major;
             IDIR words 1-7, IFIRST word 9, ILAST word 10.  A bare 512-byte file
             is accepted.  NFEAT is at most 50 (NFMAX in EXQVFL).
  * WBMAP.DT 34 bytes: the constant 1, then 16 column words.
  * BLOCK.DT 54 bytes: IDN, SFX, SFY (REAL), ICNTR(6), IBMAP(16).
  * POSIT.DT 2560 bytes: NP, then POS(640) REALs, cut at 5 blocks (so POS(640)
             keeps only its high word); POS(1..6,1) first.  NP = NFEAT1 <= 50.

All byte strings below are written out literally (or patched at hand-computed
offsets) -- never produced by the writer under test.
"""

import struct

import numpy as np
import pytest

from diskfmt import layouts as L
from diskfmt.dgreal import Real
from diskfmt.layouts import FormatError


def _assert_format_error(excinfo, name, *words):
    err = excinfo.value
    assert isinstance(err, FormatError)
    assert err.name == name
    msg = str(err)
    assert name in msg
    for w in words:
        assert w in msg, (w, msg)


# --- NCONT.DT ----------------------------------------------------------------

def test_ncont_hand_built_slice_command():
    # CFEAT: INOVAC = 2 (slice), 1 (left), 0, IYLOC=60, 128, 0
    data = b"\x00\x02\x00\x01\x00\x00\x00\x3c\x00\x80\x00\x00"
    cmd = L.decode_ncont(data)
    assert (cmd.code, cmd.image, cmd.x, cmd.y, cmd.radius, cmd.idn) == (2, 1, 0, 60, 128, 0)


def test_ncont_negative_words():
    # terminate (-1 = FFFF) and an NBLOB request with IDN = -1 (left side of edge)
    data = b"\xff\xff\x00\x02\x00\x7f\x00\x77\x00\x00\xff\xff"
    cmd = L.decode_ncont(data)
    assert cmd.words() == (-1, 2, 127, 119, 0, -1)
    data = b"\x00\x04\x00\x01\x00\x0d\x00\x3c\x00\x00\xff\xff"
    assert L.decode_ncont(data).words() == (4, 1, 13, 60, 0, -1)


def test_ncont_round_trip():
    for cmd in (L.Command(2, 2, 0, 60, 128, 0), L.Command(-1), L.Command(4, 1, 71, 60, 0, 1),
                L.Command(1, 2, 127, 0, 60, -1), L.Command(3, 1, -32768, 32767, 5, 0)):
        raw = L.encode_ncont(cmd)
        assert len(raw) == 12
        assert L.decode_ncont(raw) == cmd


def test_ncont_writer_layout_is_the_literal_one():
    assert L.encode_ncont(L.Command(2, 1, 0, 60, 128, 0)) == \
        b"\x00\x02\x00\x01\x00\x00\x00\x3c\x00\x80\x00\x00"


@pytest.mark.parametrize("size", [0, 11, 13, 24])
def test_ncont_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_ncont(bytes(size))
    _assert_format_error(ei, "NCONT.DT", str(size), "12")


def test_error_names_the_given_file():
    with pytest.raises(FormatError) as ei:
        L.decode_ncont(bytes(11), name="/tmp/jh/NCONT.DT")
    _assert_format_error(ei, "/tmp/jh/NCONT.DT", "11")


# --- SLICE.DT -----------------------------------------------------------------

def _put(buf: bytearray, offset: int, value: int) -> None:
    buf[offset:offset + 2] = struct.pack(">h", value)


def _hand_slice() -> bytearray:
    """1024 bytes; block 1 starts at byte 512.  IFBUF word n (1-based) is at byte
    512 + 2*(n-1).  IFEAT(k,j) is IFBUF word 10 + (j-1)*50 + k."""
    buf = bytearray(1024)
    for i, v in enumerate([4, 64, 60, 127, 60, 128, 2]):   # IDIR(1..7): words 1-7
        _put(buf, 512 + 2 * i, v)
    _put(buf, 512 + 14, 2)          # NFEAT  = word 8
    _put(buf, 512 + 16, 15)         # IFIRST = word 9
    _put(buf, 512 + 18, 7)          # ILAST  = word 10
    _put(buf, 512 + 20, 4)          # IFEAT(1,1) word 11
    _put(buf, 512 + 22, 13)         # IFEAT(2,1) word 12
    _put(buf, 512 + 120, 5)         # IFEAT(1,2) word 61
    _put(buf, 512 + 122, 14)        # IFEAT(2,2) word 62
    _put(buf, 512 + 220, 15)        # IFEAT(1,3) word 111
    _put(buf, 512 + 222, 7)         # IFEAT(2,3) word 112
    _put(buf, 512 + 320, 9)         # IFEAT(1,4) word 161
    _put(buf, 512 + 322, 10)        # IFEAT(2,4) word 162
    _put(buf, 512 + 24, 99)         # IFEAT(3,1) word 13: stale, past NFEAT
    _put(buf, 1022, -5)             # word 256, last unused word
    return buf


def test_slice_hand_built():
    sl = L.decode_slice(bytes(_hand_slice()))
    assert sl.idir == [4, 64, 60, 127, 60, 128, 2]
    assert sl.nfeat == 2
    assert sl.ifirst == 15
    assert sl.ilast == 7
    assert sl.features() == [(4, 5, 15, 9), (13, 14, 7, 10)]
    assert sl.feature(2)[2] == 7                     # IFEAT(2,3)
    assert sl.feature(3) == (99, 0, 0, 0)            # stale entry kept
    assert len(sl.ifbuf) == 256
    assert sl.ifbuf[255] == -5
    assert L.ifeat_word(2, 3) == 111                 # 0-based: word 112 is index 111
    assert L.ifeat_word(1, 1) == 10
    assert L.ifeat_word(50, 4) == 209                # word 210; 46 unused follow


def test_slice_bare_block_accepted():
    sl = L.decode_slice(bytes(_hand_slice()[512:]))
    assert sl.nfeat == 2
    assert sl.features() == [(4, 5, 15, 9), (13, 14, 7, 10)]


def test_slice_is_read_from_block_1_not_block_0():
    buf = _hand_slice()
    _put(buf, 14, 33)               # a NFEAT-like word in block 0 must be ignored
    _put(buf, 20, 77)
    sl = L.decode_slice(bytes(buf))
    assert sl.nfeat == 2
    assert sl.feature(1) == (4, 5, 15, 9)


def test_slice_round_trip_and_block_0_zero():
    sl = L.decode_slice(bytes(_hand_slice()))
    raw = L.encode_slice(sl)
    assert len(raw) == 1024
    assert raw[:512] == bytes(512)
    assert raw == bytes(_hand_slice())
    again = L.decode_slice(raw)
    assert again.ifbuf == sl.ifbuf


@pytest.mark.parametrize("nfeat", [51, 100, -1, -32768])
def test_slice_impossible_nfeat(nfeat):
    buf = _hand_slice()
    _put(buf, 512 + 14, nfeat)
    with pytest.raises(FormatError) as ei:
        L.decode_slice(bytes(buf))
    _assert_format_error(ei, "SLICE.DT", "NFEAT", str(nfeat))


def test_slice_nfeat_50_and_0_are_fine():
    for n in (0, 50):
        buf = _hand_slice()
        _put(buf, 512 + 14, n)
        for k in range(3, 51):          # features 3..50 as NSTAR could write them
            for j, v in enumerate((2 * k, 2 * k + 1, 3, 4)):
                _put(buf, 512 + 2 * L.ifeat_word(k, j + 1), v)
        assert L.decode_slice(bytes(buf)).nfeat == n


@pytest.mark.parametrize("size", [0, 256, 511, 513, 1023, 1025, 1536])
def test_slice_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_slice(bytes(size))
    _assert_format_error(ei, "SLICE.DT", str(size))


# --- .VD ---------------------------------------------------------------------------

def test_vd_first_byte_gives_two_pixels():
    buf = bytearray(32768)
    buf[0] = 0x1F                    # pixel (0,0) high nibble 1, (0,1) low nibble 15
    buf[1] = 0xA0                    # (0,2)=10, (0,3)=0
    buf[128] = 0x70                  # row 1 starts at pixel 256 = byte 128: (1,0)=7
    buf[30719] = 0x0C                # last pixel of row 239: byte 240*128-1
    pic = L.decode_vd(bytes(buf))
    assert pic.shape == (240, 256)
    assert pic[0, 0] == 1 and pic[0, 1] == 15
    assert pic[0, 2] == 10 and pic[0, 3] == 0
    assert pic[1, 0] == 7
    assert pic[239, 254] == 0 and pic[239, 255] == 12
    assert int(pic.sum()) == 1 + 15 + 10 + 7 + 12


def test_vd_round_trip_and_blocks_60_to_63_zero():
    rng = np.random.default_rng(1985)
    pic = rng.integers(0, 16, size=(240, 256), dtype=np.uint8)
    raw = L.encode_vd(pic)
    assert len(raw) == 32768
    assert raw[60 * 512:] == bytes(4 * 512)
    assert raw[0] == (pic[0, 0] << 4) | pic[0, 1]
    assert np.array_equal(L.decode_vd(raw), pic)


@pytest.mark.parametrize("size", [0, 30720, 32767, 32769])
def test_vd_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_vd(bytes(size), name="SCENE.VD")
    _assert_format_error(ei, "SCENE.VD", str(size), "32768")


# --- .BI -----------------------------------------------------------------------

def test_bi_hand_built():
    buf = bytearray(30720)
    buf[0:2] = b"\x00\x0f"            # (0,0) = 15
    buf[260:262] = b"\x00\x07"        # row 1, column 2: word 128+2 = byte 260
    buf[30718:30720] = b"\x00\x03"    # row 119, column 127
    pic = L.decode_bi(bytes(buf))
    assert pic.shape == (120, 128)
    assert pic[0, 0] == 15 and pic[1, 2] == 7 and pic[119, 127] == 3
    assert int(pic.sum()) == 25


@pytest.mark.parametrize("word, value", [(b"\x00\x10", 16), (b"\xff\xff", -1),
                                         (b"\x01\x00", 256), (b"\x80\x00", -32768)])
def test_bi_word_out_of_range(word, value):
    buf = bytearray(30720)
    buf[260:262] = word               # row 1, column 2
    with pytest.raises(FormatError) as ei:
        L.decode_bi(bytes(buf), name="LEFT.BI")
    _assert_format_error(ei, "LEFT.BI", str(value), "row 1", "column 2")


def test_bi_all_values_0_to_15_accepted():
    pic = (np.arange(120 * 128) % 16).reshape(120, 128)
    raw = b"".join(struct.pack(">h", int(v)) for v in pic.reshape(-1))
    assert np.array_equal(L.decode_bi(raw), pic)
    assert L.encode_bi(pic) == raw


@pytest.mark.parametrize("size", [0, 30718, 30722, 32768, 15360])
def test_bi_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_bi(bytes(size))
    _assert_format_error(ei, ".BI file", str(size), "30720")


# --- WBMAP.DT --------------------------------------------------------------------

def test_wbmap_hand_built():
    data = (b"\x00\x01"                          # the constant 1
            + b"\x00\x01"                        # column 1: top row only
            + b"\x80\x00"                        # column 2: bit 15 (bottom row)
            + b"\xff\xff"                        # column 3: all rows
            + bytes(13 * 2))
    words = L.decode_wbmap(data)
    assert len(words) == 17
    assert words[0] == 1
    assert words[1] == 1 and words[2] == -32768 and words[3] == -1
    assert words[4:] == [0] * 13


def test_wbmap_round_trip():
    cols = [0, 1, 2, 4, 8, 0x7FFF, -1, -32768, 5, 6, 7, 8, 9, 10, 11, 12]
    raw = L.encode_wbmap(cols)
    assert len(raw) == 34
    assert raw[:2] == b"\x00\x01"
    assert L.decode_wbmap(raw) == [1] + cols


@pytest.mark.parametrize("first", [b"\x00\x00", b"\x00\x02", b"\xff\xff", b"\x01\x00"])
def test_wbmap_first_word_not_1(first):
    with pytest.raises(FormatError) as ei:
        L.decode_wbmap(first + bytes(32))
    _assert_format_error(ei, "WBMAP.DT", "first word")


@pytest.mark.parametrize("size", [0, 32, 33, 35, 36])
def test_wbmap_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_wbmap(b"\x00\x01" + bytes(max(0, size - 2)) if size >= 2 else bytes(size))
    _assert_format_error(ei, "WBMAP.DT", str(size), "34")


# --- BLOCK.DT ----------------------------------------------------------------------

_BLOCK = (b"\xff\xff"                                   # IDN = -1
          + b"\x41\x10\x00\x00"                         # SFX = 1.0
          + b"\x40\x80\x00\x00"                         # SFY = 0.5
          + b"\x00\x0c\x00\x03\x00\x09\x00\x04\x00\x0a\x00\x02"   # ICNTR(1..6)
          + b"\x00\x01\x00\x03" + bytes(12 * 2) + b"\x80\x00\x00\x00")  # IBMAP(16)


def test_block_hand_built():
    assert len(_BLOCK) == 54
    b = L.decode_block(_BLOCK)
    assert b.idn == -1
    assert b.sfx.fraction() == 1
    assert b.sfy.fraction() * 2 == 1
    assert b.icntr == [12, 3, 9, 4, 10, 2]
    assert b.ibmap == [1, 3] + [0] * 12 + [-32768, 0]


def test_block_round_trip():
    b = L.decode_block(_BLOCK)
    assert L.encode_block(b) == _BLOCK
    b2 = L.BlockMap(7, Real.from_int(1) / 3, Real.from_int(-180), [1, 2, 3, 4, 5, 6],
                    list(range(-8, 8)))
    raw = L.encode_block(b2)
    assert len(raw) == 54
    assert raw[2:6] == b"\x40\x55\x55\x55" and raw[6:10] == b"\xc2\xb4\x00\x00"
    back = L.decode_block(raw)
    assert (back.idn, back.icntr, back.ibmap) == (7, [1, 2, 3, 4, 5, 6], list(range(-8, 8)))
    assert back.sfx == b2.sfx and back.sfy == b2.sfy


@pytest.mark.parametrize("size", [0, 52, 53, 55, 56])
def test_block_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_block(bytes(size))
    _assert_format_error(ei, "BLOCK.DT", str(size), "54")


# --- POSIT.DT --------------------------------------------------------------------

def _hand_posit() -> bytearray:
    buf = bytearray(2560)
    buf[0:2] = b"\x00\x03"                    # NP = 3
    buf[2:6] = b"\xc1\x10\x00\x00"            # POS(1,1) = -1.0 ("no data point")
    buf[6:10] = b"\x42\xb4\x00\x00"           # POS(2,1) = 180.0
    buf[22:26] = b"\x40\x80\x00\x00"          # POS(6,1) = 0.5: REAL #6, bytes 2+5*4
    buf[26:30] = b"\x41\x10\x00\x00"          # POS(1,2) = 1.0: REAL #7
    buf[2554:2558] = b"\x40\x55\x55\x55"      # POS(639): bytes 2+638*4
    buf[2558:2560] = b"\x41\x10"              # POS(640): high word only
    return buf


def test_posit_hand_built():
    p = L.decode_posit(bytes(_hand_posit()))
    assert p.np_ == 3
    assert len(p.pos) == 640
    assert p.pos[0].fraction() == -1
    assert p.pos[1].fraction() == 180
    assert p.pos[5].fraction() * 2 == 1
    assert [r.fraction() for r in p.entry(1)] == [-1, 180, 0, 0, 0, p.pos[5].fraction()]
    assert p.entry(2)[0].fraction() == 1
    assert p.pos[638].to_bytes() == b"\x40\x55\x55\x55"
    assert p.pos[639].fraction() == 1          # 4110 + lost low word 0000
    assert all(r.fraction() == 0 for r in p.pos[6 + 1:638])


def test_posit_round_trip_and_cut():
    pos = [Real.from_int(i - 320) / 7 for i in range(640)]
    raw = L.encode_posit(L.Positions(50, pos))
    assert len(raw) == 2560
    assert raw[:2] == b"\x00\x32"
    assert raw[2:6] == pos[0].to_bytes()
    assert raw[-2:] == pos[639].to_bytes()[:2]
    back = L.decode_posit(raw)
    assert back.np_ == 50
    assert [r.to_bytes() for r in back.pos[:639]] == [r.to_bytes() for r in pos[:639]]
    assert back.pos[639].to_bytes() == pos[639].to_bytes()[:2] + b"\x00\x00"
    assert L.encode_posit(back) == raw


@pytest.mark.parametrize("np_word, np_", [(b"\x00\x33", 51), (b"\xff\xff", -1)])
def test_posit_impossible_np(np_word, np_):
    buf = _hand_posit()
    buf[0:2] = np_word
    with pytest.raises(FormatError) as ei:
        L.decode_posit(bytes(buf))
    _assert_format_error(ei, "POSIT.DT", "NP", str(np_))


@pytest.mark.parametrize("size", [0, 2558, 2559, 2561, 2562, 2564])
def test_posit_wrong_size(size):
    with pytest.raises(FormatError) as ei:
        L.decode_posit(bytes(size))
    _assert_format_error(ei, "POSIT.DT", str(size), "2560")


# --- read_file ----------------------------------------------------------------

def test_read_file(tmp_path):
    f = tmp_path / "NCONT.DT"
    f.write_bytes(b"\x00\x02\x00\x01\x00\x00\x00\x3c\x00\x80\x00\x00")
    assert L.decode_ncont(L.read_file(f)).y == 60
    with pytest.raises(FormatError) as ei:
        L.read_file(tmp_path / "SLICE.DT")
    assert "SLICE.DT" in str(ei.value)
    with pytest.raises(FormatError) as ei:
        L.read_file(tmp_path)
    assert str(tmp_path) in str(ei.value)
