"""OCTEK 2000 frame-store model: hand-checked RVBLK/WVBLK/PXFILL/IRDPIX/GVECT.

Conventions checked (from the listings and QUIRKS M7, M8):
- the frame store is 320 x 240, addressed frame[y, x];
- RVBLK(ICT, IDAT, X, W, Y, H) fills IDAT(1) with a header (our model: the pixel
  count W*H) and IDAT(2..) with the block row by row (NSTAR label 600 takes
  IFIRST=IDAT(2), ILAST=IDAT(IXL1) from a one-row read; label 500 reads a 2x3
  grey sample as IDAT(2..7));
- WVBLK(ICT, IDAT, ...) writes from IDAT(2) on (label 800 reads the file with
  RDBLK into IDAT(2) and passes IDAT), the frame store holds 4-bit pixels.
"""

import numpy as np

from octek_sim.board import Octek, HEIGHT, WIDTH


def numbered_board():
    """A board whose pixel (x, y) holds (x + 3*y) mod 16: distinct neighbours."""
    o = Octek()
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH]
    o.frame[:, :] = (xs + 3 * ys) % 16
    return o


def test_frame_store_is_320_wide_240_high():
    o = Octek()
    assert o.frame.shape == (240, 320)


def test_rvblk_header_is_pixel_count_then_rows_top_to_bottom():
    o = Octek()
    # A 3 wide x 2 high block at x=10, y=20 with hand-placed values.
    o.frame[20, 10:13] = [1, 2, 3]
    o.frame[21, 10:13] = [4, 5, 6]
    buf = o.rvblk(10, 3, 20, 2)
    # IDAT(1) = 3*2 = 6 (header), IDAT(2..4) = row y=20, IDAT(5..7) = row y=21.
    assert list(buf) == [6, 1, 2, 3, 4, 5, 6]


def test_rvblk_single_column_reads_downwards():
    o = numbered_board()
    buf = o.rvblk(5, 1, 7, 4)
    # header 1*4 = 4; then (5+3*7)%16=10, (5+24)%16=13, (5+27)%16=0, (5+30)%16=3
    assert list(buf) == [4, 10, 13, 0, 3]


def test_rvblk_outside_frame_reads_zero():
    o = Octek()
    o.frame[:, :] = 9
    # 4 wide x 3 high at (318, 238): only x 318,319 and y 238,239 exist.
    buf = o.rvblk(318, 4, 238, 3)
    assert buf[0] == 12
    assert list(buf[1:5]) == [9, 9, 0, 0]       # y = 238
    assert list(buf[5:9]) == [9, 9, 0, 0]       # y = 239
    assert list(buf[9:13]) == [0, 0, 0, 0]      # y = 240: off the store
    # Negative coordinates: x = -2, -1 are off the store, x = 0 is on it.
    buf = o.rvblk(-2, 3, -1, 2)
    assert list(buf) == [6, 0, 0, 0, 0, 0, 9]


def test_wvblk_skips_header_and_keeps_low_four_bits():
    o = Octek()
    # Header word 999 must not be written anywhere; 17 -> 1, 31 -> 15,
    # -1 (all bits) -> 15, 0x25 -> 5.
    o.wvblk([999, 17, 31, -1, 0x25], 100, 2, 50, 2)
    assert o.frame[50, 100] == 1 and o.frame[50, 101] == 15
    assert o.frame[51, 100] == 15 and o.frame[51, 101] == 5
    # nothing else touched
    assert int(o.frame.sum()) == 1 + 15 + 15 + 5


def test_wvblk_then_rvblk_round_trip():
    o = Octek()
    pixels = list(range(16))
    o.wvblk([16] + pixels, 40, 4, 30, 4)
    assert list(o.rvblk(40, 4, 30, 4)) == [16] + pixels


def test_pxfill_fills_exactly_the_rectangle():
    o = Octek()
    o.pxfill(7, 10, 3, 20, 2)            # x 10..12, y 20..21
    assert (o.frame[20:22, 10:13] == 7).all()
    assert int((o.frame == 7).sum()) == 6
    o.pxfill(15, 0, 320, 0, 240)         # NSTAR label 800 clears the store to white
    assert (o.frame == 15).all()


def test_irdpix_reads_one_pixel_and_zero_off_the_store():
    o = numbered_board()
    assert o.irdpix(5, 7) == (5 + 21) % 16
    assert o.irdpix(319, 239) == (319 + 717) % 16
    assert o.irdpix(320, 0) == 0
    assert o.irdpix(0, -1) == 0


def test_gvect_box_corners_and_edges():
    o = Octek()
    o.frame[:, :] = 15
    # PRE-style box from four vectors, corners (10,20) and (30,40), grey 0.
    x1, y1, x2, y2 = 10, 20, 30, 40
    o.gvect(x1, y1, x2, y1, 0)
    o.gvect(x2, y1, x2, y2, 0)
    o.gvect(x2, y2, x1, y2, 0)
    o.gvect(x1, y2, x1, y1, 0)
    for x, y in ((10, 20), (30, 20), (30, 40), (10, 40)):
        assert o.frame[y, x] == 0
    assert (o.frame[20, 10:31] == 0).all() and (o.frame[40, 10:31] == 0).all()
    assert (o.frame[20:41, 10] == 0).all() and (o.frame[20:41, 30] == 0).all()
    # outline only: interior and outside unchanged;
    # 21 + 21 + 19 + 19 = 80 outline pixels
    assert (o.frame[21:40, 11:30] == 15).all()
    assert int((o.frame == 0).sum()) == 80


def test_cursor_state_is_kept_for_the_monitor():
    o = Octek()
    o.boxcur(18, 18)
    o.hctab(82, 52)
    d = o.display
    assert (d.cursor_kind, d.box_w, d.box_h, d.cursor_x, d.cursor_y) == ("box", 18, 18, 82, 52)
    o.xhair()
    o.hctab(128, 255)                  # NSTAR label 100 parks the cursor at y 255
    assert (o.display.cursor_kind, o.display.cursor_x, o.display.cursor_y) == ("crosshair", 128, 255)
