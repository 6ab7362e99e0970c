"""NSTAR's bit-map extensions (codes 11-13, beyond 1985): off by default (the 1985 NSTAR
ignores them), and with the option the radial map of hand-made regions, worked out by hand."""

import numpy as np
import pytest

from diskfmt.bitmap_files import (OPMAP_BYTES, RBMAP_BYTES, decode_opmap, decode_rbmap,
                                  encode_rbmap, RadialMap)
from diskfmt.dgreal import Real
from diskfmt.layouts import Command, FormatError, decode_block, decode_wbmap, encode_ncont
from model import bitmaps as bm
from nstar.extensions import radial_map
from nstar.program import Nova, Options


def _quadrant_frame():
    f = np.zeros((64, 64), dtype=np.int32)
    f[16:32, 16:32] = 9          # the lower-right quadrant of the box 0..31 around (16, 16)
    return f


def test_radial_map_of_a_quadrant_worked_by_hand():
    """Box columns and rows 0..31, region = its lower-right quadrant x, y >= 16.  Centre
    (16, 16); R = hypot(15.5, 15.5) + 0.5 = 22.4203, rings of R/16 = 1.40127.

    Sectors 4..15 (angles 90..360 degrees, clockwise from +x, y down) sample x < 16 or y < 16:
    never in the region, so 0.  Sectors 0..3 sample x, y > 16, in the region while inside the
    box: rho * max(cos, sin) < 16.  Sector 0's sample angles 2.8125, 8.4375, 14.0625, 19.6875
    give rho < 16.019, 16.175, 16.494, 16.993; ring 10 (rho 14.19..15.24) is all in, ring 11
    (15.59, 15.94, 16.29, 16.64) has 2+2+3+4 = 11 of 16 in (69 % <= 80 %): rings 0..10, 0x7FF.
    Sector 1 (25.3..42.2 degrees): limits 17.699, 18.654, 19.920, 21.594; ring 12 (16.99,
    17.34, 17.69, 18.04) has 3+4+4+4 = 15 in (94 %), ring 13 (18.39..19.44) 0+1+4+4 = 9:
    rings 0..12, 0x1FFF.  Sectors 3 and 2 mirror 0 and 1 about 45 degrees."""
    words, cx, cy, radius = radial_map(_quadrant_frame(), (0, 31, 0, 31), (9, 9))
    assert (cx, cy) == (16.0, 16.0)
    assert radius == pytest.approx(22.4203, abs=1e-4)
    assert words == [0x7FF, 0x1FFF, 0x1FFF, 0x7FF] + [0] * 12
    stored, k = bm.radial_canonical(words)
    assert k == 1 and stored[:3] == (0x1FFF, 0x1FFF, 0x7FF) and stored[15] == 0x7FF


def test_radial_map_turns_with_the_region():
    """The same quadrant turned 90 degrees clockwise on screen (lower-left): the raw sectors move
    4 places, the stored map is the same, and the comparison finds rotation 4 with 0 bits."""
    f = np.zeros((64, 64), dtype=np.int32)
    f[16:32, 0:16] = 9
    words, *_ = radial_map(f, (0, 31, 0, 31), (9, 9))
    assert words == [0] * 4 + [0x7FF, 0x1FFF, 0x1FFF, 0x7FF] + [0] * 8
    ref, *_ = radial_map(_quadrant_frame(), (0, 31, 0, 31), (9, 9))
    assert bm.radial_canonical(words)[0] == bm.radial_canonical(ref)[0]
    assert bm.radial_compare(ref, words) == (0, 4)


def test_empty_region():
    words, cx, cy, radius = radial_map(np.zeros((8, 8)), (0, 7, 0, 7), (5, 9))
    assert words == [0] * 16 and radius == 0.0


def _nova(ext=True):
    pic = np.full((120, 128), 2, dtype=np.uint8)
    pic[40:60, 50:70] = 12                             # a bright 20x20 square
    n = Nova(options=Options(bitmap_extensions=ext))
    n.load_pair(pic, pic)
    return n


def _run(n, *words):
    return n.execute(encode_ncont(Command(*words)))


@pytest.mark.parametrize("code", [11, 12, 13])
def test_extension_codes_are_ignored_by_default(code):
    n = _nova(ext=False)
    before = n.octek.frame.copy()
    assert _run(n, code, 1, 60, 50, 30, 1) == []
    assert (n.octek.frame == before).all()


def test_code_11_radial_map_of_the_star_region():
    n = _nova()
    block = decode_block(_run(n, 1, 1, 60, 50, 30, 1)[0].data)
    assert block.icntr == [50, 69, 40, 59, 12, 12]      # the Star finds the square
    (reply,) = _run(n, 11, 1, 60, 50, 30, 1)
    assert reply.name == "RBMAP.DT" and len(reply.data) == RBMAP_BYTES
    rm = decode_rbmap(reply.data)
    assert rm.icntr == block.icntr
    assert (rm.icx, rm.icy) == (60, 50)                 # centre of columns 50..69, rows 40..59
    # the square in frame columns 26+50.. : the same map as radial_map on the frame
    raw, _, _, radius = radial_map(n.octek.frame, (76, 95, 40, 59), (12, 12))
    assert tuple(rm.irmap) == bm.radial_canonical(raw)[0]
    assert rm.orientation == bm.radial_canonical(raw)[1]
    assert float(rm.sfr) == pytest.approx(radius / 16, rel=1e-6)
    # a square centred on its box: 90-degree symmetry, sector s equals sector s+4
    assert all(raw[s] == raw[(s + 4) % 16] for s in range(16))


def test_codes_12_and_13_operations_of_the_1985_maps():
    n = _nova()
    a4 = decode_wbmap(_run(n, 4, 1, 50, 50, 0, 1)[0].data)[1:]
    (reply,) = _run(n, 12, 1, 50, 50, 0, 1)
    assert reply.name == "OPMAP.DT" and len(reply.data) == OPMAP_BYTES
    code, maps = decode_opmap(reply.data)
    assert code == 12
    assert maps["A"] == tuple(w & 0xFFFF for w in a4)
    assert maps == bm.all_operations(a4)
    # the edge window at the square's left edge: the left half dark, the right half the square
    assert maps["L"] != (0,) * 16
    block = decode_block(_run(n, 1, 1, 60, 50, 30, 1)[0].data)
    code, maps = decode_opmap(_run(n, 13, 1, 60, 50, 30, 1)[0].data)
    assert code == 13 and maps == bm.all_operations(block.ibmap)


def test_reply_layouts_reject_bad_files():
    good = encode_rbmap(RadialMap(3, Real.from_float(1.5), 10, 20, [0] * 6, [1] * 16))
    assert decode_rbmap(good).orientation == 3
    with pytest.raises(FormatError, match="bytes"):
        decode_rbmap(good[:-2])
    with pytest.raises(FormatError, match="orientation"):
        decode_rbmap(good[:2] + b"\x00\x20" + good[4:])
    with pytest.raises(FormatError, match="first word"):
        decode_opmap(b"\x00\x05" + bytes(OPMAP_BYTES - 2))
