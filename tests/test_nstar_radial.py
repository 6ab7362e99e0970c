"""IGCD/ILCM, NSTAR's direction cosines, RADLN and RADSP, hand-derived.

REAL arithmetic is the DG hex float (QUIRKS M1): every operation exact, then
truncated to 6 hex digits; REAL -> INTEGER truncates toward zero.  The values
used below, worked out by hand:

  PI=3.1415926 -> 0x3.243F6 (truncated); PID8=PI/8.0 -> 0x0.6487EC (exact: a
  3-bit shift fits in 6 hex digits); PID8*2.0 = 0x0.C90FD8; PID8*3.0 =
  0x1.2D97C4 -> 0x1.2D97C.
  CA1(2)=COS(PID8)     = 0.92387956.. -> 0x0.EC835E
  CA1(3)=COS(PID8*2.0) = 0.70710689.. -> 0x0.B504F5 (true cos 45 is ...B504F3:
                          the short PI makes it larger)
  CA1(4)=COS(PID8*3.0) = 0.38268387.. -> 0x0.61F791 (true ...61F78A)
  SQRT2 = 1.41421356 -> 0x1.6A09E = 1.41421318.
  HYP=(I-1)*SQRT2: 0, 1.414, 2.828, 4.243, 5.657, 7.071, 8.485, 9.899, 11.314, 12.728
  HYP*CA1(3) for I=2..10 is just below 1, 2, .., 9 (e.g. 0.99999988, 8.9999981).
"""

import numpy as np
import pytest

from diskfmt.dgreal import Real
from nstar.radial import direction_cosines, igcd, ilcm, radln, radsp
from nstar.program import Nova

LEFT = (26, 153, 0, 119)          # /IMAGE/ as RADLN sees it: IXOFF, IXMAX, IYOFF, IYMAX
RIGHT = (166, 293, 0, 119)


@pytest.mark.parametrize("a, b, gcd", [
    (16, 16, 16), (26, 16, 2), (16, 26, 2), (19, 16, 1), (120, 16, 8),
    (128, 16, 16), (1, 16, 1), (48, 18, 6), (38, 16, 2),
])
def test_igcd(a, b, gcd):
    # Euclid by MOD: e.g. IGCD(26,16): 26 mod 16 = 10; 16 mod 10 = 6; 10 mod 6 = 4;
    # 6 mod 4 = 2; 4 mod 2 = 0 -> 2.
    assert igcd(a, b) == gcd


@pytest.mark.parametrize("a, b, lcm", [
    (16, 16, 16), (26, 16, 208), (8, 16, 16), (19, 16, 304), (127, 16, 2032),
    (120, 16, 240), (38, 16, 304), (12, 16, 48),
])
def test_ilcm(a, b, lcm):
    # ILCM(IX,IY)=(IX*IY)/IGCD(IX,IY), e.g. 26*16/2 = 208, 127*16/1 = 2032.
    assert ilcm(a, b) == lcm


def test_direction_cosines_hex():
    ca1, ca2 = direction_cosines()
    assert [c.to_bytes().hex().upper() for c in ca1] == [
        "41100000", "40EC835E", "40B504F5", "4061F791"]
    # CA2(1)=0, CA2(2)=CA1(4), CA2(3)=CA1(3), CA2(4)=CA1(2)
    assert [c.to_bytes().hex().upper() for c in ca2] == [
        "00000000", "4061F791", "40B504F5", "40EC835E"]


def board(pic=None):
    nova = Nova()
    if pic is None:
        pic = (np.arange(120)[:, None] * 7 + np.arange(128)[None, :]) % 16
    nova.load_pair(pic, pic)
    return nova.octek, np.asarray(pic)


ONE = Real.from_int(1)
ZERO = Real.from_int(0)


def test_horizontal_ray_samples_every_sqrt2():
    octek, pic = board()
    idir = [1, 64, 60, 0, 0, 10, 1]
    irad, np_ = radln(octek, idir, 10, ONE, ZERO, LEFT)
    # offsets int(HYP): 0, 1, 2, 4, 5, 7, 8, 9, 11, 12
    cols = [64, 65, 66, 68, 69, 71, 72, 73, 75, 76]
    assert irad == [int(pic[60, c]) for c in cols]
    assert np_ == 10
    assert idir == [1, 64, 60, 76, 60, 10, 1]       # IDIR(4..6): end x, end y, count


def test_ray_stops_at_the_right_picture_edge():
    octek, pic = board()
    idir = [1, 125, 60, 0, 0, 10, 1]
    irad, _ = radln(octek, idir, 10, ONE, ZERO, LEFT)
    # IXCTR = 125+26 = 151; x 151, 152, 153 (2.83 -> 153); 4.24 -> 155 > IXMAX=153: stop
    assert irad == [int(pic[60, c]) for c in (125, 126, 127)]
    assert idir[3:6] == [127, 60, 3]
    # the same in the right picture (IXMIN=166, IXMAX=293)
    idir = [1, 125, 60, 0, 0, 10, 2]
    irad, _ = radln(octek, idir, 10, ONE, ZERO, RIGHT)
    assert irad == [int(pic[60, c]) for c in (125, 126, 127)]
    assert idir[3:6] == [127, 60, 3]


def test_ray_stops_at_the_left_picture_edge():
    octek, pic = board()
    idir = [9, 2, 60, 0, 0, 10, 1]
    irad, _ = radln(octek, idir, 10, -ONE, ZERO, LEFT)
    # IXCTR=28: 28, 28-1.414=26.59 -> 26, 28-2.83=25.17 -> 25 < 26: stop
    assert irad == [int(pic[60, 2]), int(pic[60, 0])]
    assert idir[3:6] == [0, 60, 2]


def test_ray_upwards_truncates_toward_zero_at_row_0():
    octek, pic = board()
    idir = [13, 64, 1, 0, 0, 10, 1]
    irad, _ = radln(octek, idir, 10, ZERO, -ONE, LEFT)
    # y = 1, 1-1.414 = -0.41 -> 0 (INTEGER truncates toward zero, still on the
    # picture), 1-2.83 = -1.83 -> -1: stop.
    assert irad == [int(pic[1, 64]), int(pic[0, 64])]
    assert idir[3:6] == [64, 0, 2]


def test_diagonal_rays_are_not_symmetric():
    ca1, _ = direction_cosines()
    c45 = ca1[2]
    octek, pic = board()
    # Down-right: HYP*CA1(3) is 0, 0.99999988, 1.9999990, ..., 8.9999981; +90 and
    # +60 truncate to offsets 0, 0, 1, ..., 8: the centre is read twice.
    idir = [3, 64, 60, 0, 0, 10, 1]
    irad, _ = radln(octek, idir, 10, c45, c45, LEFT)
    offs = [0, 0, 1, 2, 3, 4, 5, 6, 7, 8]
    assert irad == [int(pic[60 + d, 64 + d]) for d in offs]
    assert idir[3:6] == [72, 68, 10]
    # Up-left: 90-0.99999988 = 89.00000012 -> 89 (6 hex digits: 89.0), so offsets
    # 0, -1, ..., -9: one pixel further than down-right.
    idir = [11, 64, 60, 0, 0, 10, 1]
    irad, _ = radln(octek, idir, 10, -c45, -c45, LEFT)
    assert irad == [int(pic[60 - d, 64 - d]) for d in range(10)]
    assert idir[3:6] == [55, 51, 10]


@pytest.mark.parametrize("np_in, np_out, count, end_y", [
    (0, 1, 1, 0),          # NP < 1 -> 1: the centre only
    (-5, 1, 1, 0),
    (100, 60, 60, 83),     # NP > 60 -> 60: last HYP = 59*SQRT2 = 83.44 -> row 83
    (60, 60, 60, 83),
])
def test_ray_length_is_limited_to_1_to_60(np_in, np_out, count, end_y):
    octek, pic = board()
    idir = [5, 64, 0, 0, 0, np_in, 1]
    irad, np_ = radln(octek, idir, np_in, ZERO, ONE, LEFT)
    assert np_ == np_out
    assert idir[3:6] == [64, end_y, count]
    assert len(irad) == count and irad[0] == int(pic[0, 64]) and irad[-1] == int(pic[end_y, 64])


def test_radsp_quadrant_1_on_a_vertical_step():
    # Picture: cols 0..69 grey 4, cols 70..127 grey 12; centre (64, 60), NP=10.
    # Quadrant 1: ISX=ISY=+1, CAX=CA1, CAY=CA2.
    #  ray 1 (CX=1, CY=0): cols 64,65,66,68,69 | 71,72,73,75,76, rows 60 -> pixels
    #    4x5, 12x5.  EXQVFL(ITHR=1): feature (5, 6, 4, 12).  End (76, 60).
    #    INDX=5-1=4, XRAT=12/10.0=0x1.33333 (1.1999998), IX2=64+4.7999992 -> 68;
    #    YRAT=0 -> IY2=60; IG2=IFEAT(1,3)=4.
    #  ray 2 (CX=CA1(2), CY=CA2(2)=CA1(4)): x 64,65,66,67,69 | 70,71,73,74,75,
    #    y 60,60,61,61,62,62,63,63,64,64 -> again 4x5, 12x5: feature (5,6,4,12).
    #    End (75, 64): XRAT=1.0999999 -> 64+4.3999996 -> 68; YRAT=0.39999998 ->
    #    60+1.5999999 -> 61.
    #  ray 3 (45 deg): x 64,64,65..72, y 60,60,61..68 -> cols <70 seven times, then
    #    70,71,72: feature (7, 8, 4, 12), end (72, 68); INDX=6, XRAT=YRAT=0.8 ->
    #    4.7999997: IX2=68, IY2=64.
    #  ray 4 (CX=CA1(4), CY=CA2(4)=CA1(2)): x 64,64,65,65,..,68,68 (all grey 4),
    #    y 60,61,62,63,65,66,67,69,70,71: no feature, end (68, 71).
    #  Extremes: x 64..68, y 60..71, grey 4..4.
    pic = np.full((120, 128), 12, np.uint8)
    pic[:, :70] = 4
    octek, _ = board(pic)
    ca1, ca2 = direction_cosines()
    ifbuf = np.zeros(256, dtype=np.int32)
    ifbuf[0:7] = [0, 64, 60, 0, 0, 10, 1]
    icntr = [127, 0, 119, 0, 15, 0]
    radsp(octek, +1, +1, ca1, ca2, icntr, ifbuf, LEFT)
    assert icntr == [64, 68, 60, 71, 4, 4]
    # IFBUF left by the last ray: IDIR = (0+4, 64, 60, 68, 71, 10, 1), NFEAT=0,
    # IFIRST=ILAST=4; IFEAT(1,.) still holds ray 3's feature.
    assert list(ifbuf[0:10]) == [4, 64, 60, 68, 71, 10, 1, 0, 4, 4]
    assert [int(ifbuf[10 + 50 * j]) for j in range(4)] == [7, 8, 4, 12]


def test_radsp_only_narrows_icntr_in_its_direction():
    # The same picture, quadrant 3 (ISX=ISY=-1, CAX=CA1, CAY=CA2): all rays go left
    # and up over grey 4 only: no features.  Ray 1 ends at 90-12.73 = 77.27 -> 77
    # (rel 51), ray 3 (up-left 45 deg) at offset -9 (rel 55, 51), ray 4 (CX=-CA1(4),
    # CY=-CA1(2)): x 90-4.87 = 85.13 -> 85 (rel 59), y 60-11.76 = 48.24 -> 48.
    # So x 51..64, y 48..60; ICNTR starts from quadrant-1 values and widens.
    pic = np.full((120, 128), 12, np.uint8)
    pic[:, :70] = 4
    octek, _ = board(pic)
    ca1, ca2 = direction_cosines()
    ifbuf = np.zeros(256, dtype=np.int32)
    ifbuf[0:7] = [8, 64, 60, 0, 0, 10, 1]
    icntr = [64, 68, 60, 71, 4, 4]
    radsp(octek, -1, -1, ca1, ca2, icntr, ifbuf, LEFT)
    assert icntr == [51, 68, 48, 71, 4, 4]
    assert list(ifbuf[0:8]) == [12, 64, 60, 59, 48, 10, 1, 0]
