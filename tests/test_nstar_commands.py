"""NSTAR.FR commands, hand-traced from the Appendix F listing.

Every expected word below is worked out by hand from the listing (label 100
dispatch, 200-400 Star + block map, 500 edge bit map, 600 slice, 900 terminate)
and EXQVFL (ITHR = 2 for slices); the trace is in the comment beside it.

Frame-store geometry (label 100/800): left picture at x 26..153, right at
x 166..293, rows 0..119, everything else white (15) after PXFILL.  Feature
indices are 1-based (index 1 = picture column 0).
"""

import numpy as np
import pytest

from diskfmt.dgreal import Real
from diskfmt.layouts import (Command, encode_ncont, decode_slice, decode_wbmap,
                             decode_block, words_from_bytes, TERM_TEXT)
from nstar.bitmaps import block_map, scale_factors
from nstar.program import Nova, Options
from octek_sim.board import Octek


def run(nova, *words):
    return nova.execute(encode_ncont(Command(*words)))


def only(replies, name):
    assert [r.name for r in replies] == [name]
    return replies[0]


def pair(left, right=None):
    nova = Nova()
    nova.load_pair(left, right if right is not None else np.full((120, 128), 8, np.uint8))
    return nova


# --- pictures for the slice tests ---------------------------------------------

def slice_pictures():
    left = np.full((120, 128), 8, np.uint8)
    left[:, 40:80] = 12                  # rows 1..118: 8 | 12 | 8
    left[0, :] = 8
    left[0, 60:] = 3                     # row 0: 8 | 3
    left[119, :100] = 5
    left[119, 100:] = 14                 # row 119: 5 | 14
    right = np.full((120, 128), 8, np.uint8)
    right[:, 34:74] = 12                 # 8 | 12 | 8, six columns further left
    return left, right


def expected_ifbuf(iy, imf, nfeat, ifirst, ilast, feats, base=None):
    """IFBUF(256) as NSTAR label 600 leaves it: IDIR(1..7) = -1, 0, IY, IXL-1=127,
    IY, IXL=128, IMF; NFEAT; IFIRST; ILAST; IFEAT(50,4) column-major."""
    w = list(base) if base is not None else [0] * 256
    w[0:10] = [-1, 0, iy, 127, iy, 128, imf, nfeat, ifirst, ilast]
    for k, f in enumerate(feats):
        for j in range(4):
            w[10 + 50 * j + k] = f[j]
    return w


# Hand trace of EXQVFL(128, row, NFEAT, IFEAT, 2) on "8 (cols 0..39) | 12 (40..79) | 8":
#  label 100 walks the flat run until ILOC=40 (col 39, 8), IPRE=41 (col 40, 12),
#  ICHG=+4 > ITHR -> 120: IVPRE=12, IPRE=41; pixels 42, 43 flat -> 200.
#  INUM=ILOC-JLOC+1=40 > 3 -> IS1=IPIX(1..3)=24, IS2=IPIX(40,39,38)=24,
#  IVAVE=IV1=(24/3.0)+.5=8 -> feature 1 = (40, 41, IV1=8, IVPRE=12); JLOC=41.
#  Again at ILOC=80 (col 79, 12), IPRE=81 (col 80, 8), ICHG=-4 -> feature 2 =
#  (80, 81, 12, 8), and IFEAT(1,4)=IVAVE=(36/3.0)+.5=12.  End (label 300/400):
#  IFEAT(2,4) = mean of IPIX(81..83) = 8.  Merge: IFEAT(1,2)=41 < IFEAT(2,1)=80, none.
LEFT_ROW60 = [(40, 41, 8, 12), (80, 81, 12, 8)]
# The right picture: same shape six columns left: (34, 35, 8, 12), (74, 75, 12, 8).
RIGHT_ROW60 = [(34, 35, 8, 12), (74, 75, 12, 8)]
# Row 0 "8 (0..59) | 3 (60..127)": ILOC=60, IPRE=61, IV1=8, IVPRE=3; end grey
# (3+3+3)/3.0+.5 -> 3.  One feature.
LEFT_ROW0 = [(60, 61, 8, 3)]
# Row 119 "5 (0..99) | 14 (100..127)": ILOC=100, IPRE=101, IV1=(15/3.0)+.5 -> 5,
# right grey (42/3.0)+.5 -> 14.
LEFT_ROW119 = [(100, 101, 5, 14)]


def test_slice_left_and_right_words():
    left, right = slice_pictures()
    nova = pair(left, right)
    rep = only(run(nova, 2, 1, 0, 60, 128, 0), "SLICE.DT")
    assert rep.temp == "NDAT.DT"
    assert len(rep.data) == 1024 and rep.data[:512] == bytes(512)   # WRBLK block 1
    sl = decode_slice(rep.data)
    # IFIRST = IDAT(2) = col 0 = 8, ILAST = IDAT(129) = col 127 = 8
    assert sl.ifbuf == expected_ifbuf(60, 1, 2, 8, 8, LEFT_ROW60)

    nova = pair(left, right)
    sl = decode_slice(only(run(nova, 2, 2, 0, 60, 128, 0), "SLICE.DT").data)
    # IMF=2: IX = 26+140 = 166, the right picture
    assert sl.ifbuf == expected_ifbuf(60, 2, 2, 8, 8, RIGHT_ROW60)


@pytest.mark.parametrize("ycentre, line, feats, ifirst, ilast", [
    (200, 119, LEFT_ROW119, 5, 14),       # IF (IYCTR .GT. IVMAX) IYCTR=IVMAX
    (-5, 0, LEFT_ROW0, 8, 3),             # IF (IYCTR .LT. IVMIN) IYCTR=IVMIN
    (0, 0, LEFT_ROW0, 8, 3),
    (119, 119, LEFT_ROW119, 5, 14),
])
def test_slice_centre_is_clamped_to_the_picture(ycentre, line, feats, ifirst, ilast):
    left, right = slice_pictures()
    nova = pair(left, right)
    sl = decode_slice(only(run(nova, 2, 1, 0, ycentre, 128, 0), "SLICE.DT").data)
    assert sl.ifbuf == expected_ifbuf(line, 1, 1, ifirst, ilast, feats)


def test_slice_image_flag_other_than_2_reads_the_left_picture():
    # IX=26; IF (IMF .EQ. 2) IX=IX+140: IMF=3 reads x 26, yet IDIR(7)=3.
    left, right = slice_pictures()
    nova = pair(left, right)
    sl = decode_slice(only(run(nova, 2, 3, 0, 60, 128, 0), "SLICE.DT").data)
    assert sl.ifbuf == expected_ifbuf(60, 3, 2, 8, 8, LEFT_ROW60)


def test_slice_keeps_stale_features_past_nfeat():
    left, right = slice_pictures()
    nova = pair(left, right)
    first = decode_slice(run(nova, 2, 1, 0, 60, 128, 0)[0].data)
    second = decode_slice(run(nova, 2, 1, 0, 0, 128, 0)[0].data)
    # Line 0 writes only IFEAT(1,.); IFEAT(2,.) = (80, 81, 12, 8) from line 60 survives.
    words = [0] * 256
    words[0:10] = [-1, 0, 0, 127, 0, 128, 1, 1, 8, 3]
    words[10], words[60], words[110], words[160] = 60, 61, 8, 3      # IFEAT(1,1..4)
    words[11], words[61], words[111], words[161] = 80, 81, 12, 8     # IFEAT(2,1..4), stale
    assert second.ifbuf == words
    assert second.nfeat == 1 and second.feature(2) == first.feature(2)
    # a third, longer slice overwrites them again
    third = decode_slice(run(nova, 2, 2, 0, 60, 128, 0)[0].data)
    assert third.ifbuf == expected_ifbuf(60, 2, 2, 8, 8, RIGHT_ROW60)


# --- label 500: edge bit maps ----------------------------------------------------

def step_picture(split=64, lo=4, hi=10):
    pic = np.full((120, 128), hi, np.uint8)
    pic[:, :split] = lo
    return pic


def edge(nova, imf, x, y, idn):
    rep = only(run(nova, 4, imf, x, y, 0, idn), "WBMAP.DT")
    assert rep.temp == "NDAT.DT" and len(rep.data) == 34
    words = decode_wbmap(rep.data)
    assert words[0] == 1                       # IFIG=1
    return words[1:]


FULL = -1            # 0xFFFF as a signed 16-bit word: all 16 rows in range


def test_edge_map_vertical_step_both_sides():
    nova = pair(step_picture())                # cols 0..63 = 4, 64..127 = 10
    # X=64, Y=60: IXC=90, IYC=60, window x 83..98 (cols 57..72), rows 53..68.
    # IDN=-1: IXM=MIN0(90, 88)=88 -> cols 62,63 rows 60..62 all 4 -> IGMN=IGMX=4:
    # cols 57..63 (7 words) full, cols 64..72 (9 words) empty.
    assert edge(nova, 1, 64, 60, -1) == [FULL] * 7 + [0] * 9
    # IDN=+1: IXM=MIN0(90, 92)=90 -> cols 64,65 = 10 -> range 10..10.
    assert edge(nova, 1, 64, 60, +1) == [0] * 7 + [FULL] * 9
    # Label 500 leaves an 18x18 box cursor parked at HCTAB(IXLFT, 255), IXLFT = 83.
    d = nova.octek.display
    assert (d.cursor_kind, d.box_w, d.box_h, d.cursor_x, d.cursor_y) == ("box", 18, 18, 83, 255)


def test_edge_map_left_border_samples_white_outside_the_picture():
    pic = np.full((120, 128), 4, np.uint8)
    pic[:, 0:4] = 15
    nova = pair(pic, pic)
    # X=0, IDN=-1: IXC=26, IXM=24: frame x 24,25 are PXFILL white -> range 15..15.
    # Window x 19..34: x 19..25 < IXMIN=26 -> 0 words; x 26..29 (cols 0..3, 15) full;
    # x 30..34 (grey 4) empty.
    assert edge(nova, 1, 0, 60, -1) == [0] * 7 + [FULL] * 4 + [0] * 5
    # Right picture: IXC=166, IXM=164: x 164,165 lie between the pictures, white too;
    # x 159..165 < IXMIN=166 give 0 words.
    assert edge(nova, 2, 0, 60, -1) == [0] * 7 + [FULL] * 4 + [0] * 5
    # A negative X-centre is clamped to 0 first.
    assert edge(nova, 1, -30, 60, -1) == [0] * 7 + [FULL] * 4 + [0] * 5


def test_edge_map_right_border_columns_outside_give_zero_words():
    nova = pair(step_picture())
    # X=127, IDN=+1: IXC=153, IXM=MIN0(153,155)=153 -> frame x 153 (col 127, 10) and
    # x 154 (white 15) -> range 10..15.  Window x 146..161: 146..153 (grey 10) full,
    # 154..161 > IXMAX=153 -> 0 words.
    assert edge(nova, 1, 127, 60, +1) == [FULL] * 8 + [0] * 8
    # X=300 is clamped to 127: same map.
    assert edge(nova, 1, 300, 60, +1) == [FULL] * 8 + [0] * 8


def test_edge_map_top_rows_outside_give_zero_bits():
    nova = pair(step_picture())
    # Y=0: IYTOP=-7, rows -7..8: rows -7..-1 (bits 0..6) skipped, rows 0..8 set
    # -> 0xFF80 = -128.  Grey sample cols 62,63 rows 0..2 = 4.
    assert edge(nova, 1, 64, 0, -1) == [-128] * 7 + [0] * 9


def test_edge_map_bottom_grey_sample_reads_rows_below_the_picture():
    nova = pair(step_picture())
    # Y=119: the grey sample reads rows IYC..IYC+2 = 119, 120, 121 (QUIRKS N8):
    # row 119 cols 62,63 = 4, rows 120,121 are PXFILL white 15 -> range 4..15, so
    # both sides of the step (4 and 10) are in range.  Window rows 112..127:
    # rows 112..119 -> bits 0..7, rows 120..127 > IYMAX skipped -> 0x00FF = 255.
    assert edge(nova, 1, 64, 119, -1) == [255] * 16
    assert edge(nova, 1, 64, 500, -1) == [255] * 16     # Y clamped to 119
    # Y=117 samples rows 117..119 only (all 4): range 4..4, window rows 110..125,
    # rows 110..119 -> bits 0..9 = 0x03FF.
    assert edge(nova, 1, 64, 117, -1) == [0x03FF] * 7 + [0] * 9


def test_edge_map_one_column_shift_of_feature_index():
    # cols 0..59 = 4, 60..127 = 10.
    nova = pair(step_picture(split=60))
    sl = decode_slice(run(nova, 2, 1, 0, 60, 128, 0)[0].data)
    # EXQVFL: ILOC=60 (col 59), IPRE=61 (col 60): feature (60, 61, 4, 10).
    assert sl.features() == [(60, 61, 4, 10)]
    # ESTAR sends IFEAT(1,1)=60 as the X-centre; NSTAR takes it as column 60, the first
    # pixel right of the edge (QUIRKS E20).  IDN=-1: sample cols 58,59 = 4; window
    # cols 53..68: 53..59 full (7 words) and the centre word (8th, col 60) empty.
    # (Read as column 59 there would be 8 full words.)
    assert edge(nova, 1, 60, 60, -1) == [FULL] * 7 + [0] * 9
    # The right edge is sent as IFEAT(1,2)=61 -> column 61; IDN=+1 samples cols 61,62
    # (10); window cols 54..69: 54..59 empty (6), 60..69 full (10).
    assert edge(nova, 1, 61, 60, +1) == [0] * 6 + [FULL] * 10


# --- labels 290-390: block map -----------------------------------------------------

def board_with(block, x, y):
    o = Octek()
    block = np.asarray(block)
    o.frame[y:y + block.shape[0], x:x + block.shape[1]] = block
    return o


def test_block_map_one_sample_per_bit_header_first_last_row_unused():
    # IXL=IYL=16: IXDV=IYDV=ILCM(16,16)=16, IXD=IXB=IYD=IYB=1: each bit one sample.
    # Column reads RVBLK(IXIP,1,IYS,16): IDAT(1)=header 16, IDAT(k)=row k-2.
    # Bit k uses IDAT(k+1): bit 0 the header (16, never a grey), bit k>=1 row k-1;
    # row 15 is never read.
    block = np.full((16, 16), 9, np.uint8)
    block[0:8, :] = 5
    block[15, :] = 5
    block[:, 3] = 9
    o = board_with(block, 40, 10)
    words = block_map(o, 40, 10, 16, 16, 5, 5)
    # rows 0..7 -> bits 1..8 = 0x1FE = 510 (row 15 = 5 would be bit 16: not read)
    assert words == [510, 510, 510, 0] + [510] * 12


def test_block_map_narrow_block_feeds_two_bit_columns_per_image_column():
    # IXL=8: IXDV=ILCM(8,16)=16, IXD=2 (new image column at odd IXDVI), IXB=1.
    # Column j: grey 5 in row j only -> bit j+1 -> 1<<(j+1), twice.
    block = np.full((16, 8), 9, np.uint8)
    for j in range(8):
        block[j, j] = 5
    o = board_with(block, 100, 50)
    words = block_map(o, 100, 50, 8, 16, 5, 5)
    assert words == [w for j in range(8) for w in (1 << (j + 1),) * 2]


def test_block_map_short_block_header_falls_inside_the_grey_range():
    # IYL=8: header = 1*8 = 8; IYDV=16, IYD=2, IYB=1: bits 0,1 read IDAT(1) (the
    # header), bits 2k,2k+1 read row k-1 (k=1..7), row 7 never.
    o = board_with(np.full((8, 16), 8, np.uint8), 60, 30)
    # range 8..8: the header 8 counts as in range -> all 16 bits: 0xFFFF = -1
    assert block_map(o, 60, 30, 16, 8, 8, 8) == [-1] * 16
    o = board_with(np.full((8, 16), 3, np.uint8), 60, 30)
    # range 3..3: header 8 out -> bits 0,1 clear: 0xFFFC = -4
    assert block_map(o, 60, 30, 16, 8, 3, 3) == [-4] * 16


def test_block_map_percent_wraps_at_16_bits():
    # IXL=IYL=19: ILCM(19,16)=304, IXD=IYD=16, IXB=IYB=19: 19*19 = 361 samples a bit.
    # Bit 0: per grid column IYDVI 1..16 read the header (19, out of 5..5), 17..19
    # row 0 -> CNT 3*19=57 -> 5700/361 = 15%: clear.
    # Bits 1..15: CNT 361 -> 361*100 = 36100 wraps to 36100-65536 = -29436,
    # /361 = -81 (truncated) -> not > 80: clear.  Without the wrap: 100% -> set.
    o = board_with(np.full((19, 19), 5, np.uint8), 30, 20)
    assert block_map(o, 30, 20, 19, 19, 5, 5, wrap=True) == [0] * 16
    assert block_map(o, 30, 20, 19, 19, 5, 5, wrap=False) == [-2] * 16   # 0xFFFE


def test_scale_factors_are_dg_reals():
    # SFX=IXL/16.0: 26/16 = 1.625 = 0x1.A -> 41 1A0000; 8/16 = 0.5 -> 40 800000.
    sfx, sfy = scale_factors(26, 8)
    assert sfx.to_bytes() == bytes.fromhex("411A0000")
    assert sfy.to_bytes() == bytes.fromhex("40800000")


def test_star_block_command_on_a_uniform_picture():
    # Uniform grey 8, centre (64, 60) -> IXC=90, IYC=60, IRAD=10 -> NP=10.
    # No ray has a feature, so RADSP widens ICNTR with the ray end points.  The
    # axial rays end at HYP = 9*SQRT2 = 12.7279 (DG): right 90+12.73 -> 102 (rel 76),
    # left 90-12.73 = 77.27 -> 77 (rel 51), down 60+12.73 -> 72, up 47.27 -> 47; the
    # slanted rays reach less far.  Greys: IFIRST=ILAST=8.
    # ICNTR = 51, 76, 47, 72, 8, 8 -> IXS=77, IXL=26, IYS=47, IYL=26.
    # SFX=SFY=26/16.0=1.625 = 411A0000.
    # Block map: ILCM(26,16)=208, IXD=IYD=8, IXB=IYB=13.  Bit 0: IYDVI 1..8 read
    # the header (26), 9..13 row 0 -> 65/169 = 38%: clear; bits 1..15 all grey 8:
    # 100% -> 0xFFFE = -2 in every column.
    nova = pair(np.full((120, 128), 8, np.uint8))
    rep = only(run(nova, 1, 1, 64, 60, 10, 7), "BLOCK.DT")
    assert rep.temp == "NDAT.DT" and len(rep.data) == 54
    words = words_from_bytes(rep.data)
    assert words[0] == 7                                     # IDN echoed
    assert rep.data[2:6] == bytes.fromhex("411A0000")
    assert rep.data[6:10] == bytes.fromhex("411A0000")
    assert words[5:11] == [51, 76, 47, 72, 8, 8]
    assert words[11:27] == [-2] * 16
    b = decode_block(rep.data)
    assert b.sfx == Real.const("1.625") and b.sfy == Real.const("1.625")


def test_star_block_command_percent_wrap_and_its_fix():
    # IRAD=14: HYP = 13*SQRT2 = 18.385: x 90+18.38 -> 108 (rel 82), 71.6 -> 71 (rel
    # 45); y 78.38 -> 78, 41.6 -> 41.  ICNTR = 45, 82, 41, 78, 8, 8; IXL=IYL=38,
    # SFX = 38/16 = 2.375 = 0x2.6 -> 41 260000.
    # ILCM(38,16)=304, IXD=IYD=8, IXB=IYB=19: 361 samples a bit.  Bit 0: IYDVI
    # 1..8 header (38), 9..19 rows -> 11*19=209 of 361 = 57%: clear.  Bits 1..15:
    # CNT=361, 36100 wraps -> -81%: clear (1985); 100% with the named fix.
    pic = np.full((120, 128), 8, np.uint8)
    for options, bmap in ((Options(), [0] * 16), (Options(no_wrap_percent=True), [-2] * 16)):
        nova = Nova(options=options)
        nova.load_pair(pic, pic)
        rep = only(run(nova, 1, 1, 64, 60, 14, 3), "BLOCK.DT")
        words = words_from_bytes(rep.data)
        assert words[0] == 3
        assert rep.data[2:10] == bytes.fromhex("41260000") * 2
        assert words[5:11] == [45, 82, 41, 78, 8, 8]
        assert words[11:27] == bmap


# --- label 900 and the dispatch ---------------------------------------------------

def test_terminate_writes_term_dt():
    nova = Nova()
    replies = run(nova, -1, 0, 0, 0, 0, 0)
    assert [(r.name, r.temp) for r in replies] == [("TERM.DT", "TRM.DT")]
    # FORMAT(" NOVA processing terminated."), one record
    assert replies[0].data == b" NOVA processing terminated.\n"
    assert TERM_TEXT == " NOVA processing terminated.\n"
    assert nova.terminated


@pytest.mark.parametrize("code", [0, 5, -2, 99, -32768, 32767])
def test_codes_outside_the_dispatch_are_ignored(code):
    # IF ((ICODE .LT. -1) .OR. (ICODE .GT. 4)) GOTO 100; code 0 falls through the
    # computed GOTO to GOTO 100: no reply, NSTAR waits again.
    nova = pair(step_picture())
    before = nova.octek.frame.copy()
    assert run(nova, code, 1, 64, 60, 10, -1) == []
    assert not nova.terminated
    assert (nova.octek.frame == before).all()
    # NSTAR still answers afterwards
    assert only(run(nova, 4, 1, 64, 60, 0, -1), "WBMAP.DT")


def test_code_3_new_pair_publishes_nothing():
    nova = pair(step_picture())
    assert run(nova, 3, 1, 0, 0, 0, 0) == []
