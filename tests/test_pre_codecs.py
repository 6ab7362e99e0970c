"""The .VD and .BI layouts against hand-built bytes, through both the codecs
PRE's subcommands use and the menu's block loops (commands 4, 5, 10, 11)."""

import numpy as np

from diskfmt.layouts import decode_bi, decode_vd, encode_bi, encode_vd
from octek_sim.board import Octek
from pre import framestore


def _vd_bytes():
    data = bytearray(32768)
    data[0:2] = bytes([0x12, 0x34])        # row 0: pixels 1, 2, 3, 4 (first in the high nibble)
    data[128:130] = bytes([0xA0, 0x05])    # row 1 starts at word 64: pixels 10, 0, 0, 5
    data[30719] = 0x0F                     # row 239, last pixel = 15 (block 59 ends at 30720)
    return bytes(data)


def _vd_picture():
    pic = np.zeros((240, 256), dtype=np.uint8)
    pic[0, 0:4] = [1, 2, 3, 4]
    pic[1, 0:4] = [10, 0, 0, 5]
    pic[239, 255] = 15
    return pic


def _bi_bytes():
    data = bytearray(30720)
    data[0:4] = bytes([0x00, 0x07, 0x00, 0x0F])     # row 0: 7, 15, one word each
    data[256:258] = bytes([0x00, 0x03])             # row 1 starts at word 128
    data[30718:30720] = bytes([0x00, 0x09])         # row 119, column 127
    return bytes(data)


def _bi_picture():
    pic = np.zeros((120, 128), dtype=np.uint8)
    pic[0, 0:2] = [7, 15]
    pic[1, 0] = 3
    pic[119, 127] = 9
    return pic


def test_vd_codec_against_hand_built_bytes():
    assert len(_vd_bytes()) == 32768
    assert encode_vd(_vd_picture()) == _vd_bytes()
    assert np.array_equal(decode_vd(_vd_bytes()), _vd_picture())
    assert _vd_bytes()[30720:] == bytes(2048)       # blocks 60-63 zero


def test_bi_codec_against_hand_built_bytes():
    assert encode_bi(_bi_picture()) == _bi_bytes()
    assert np.array_equal(decode_bi(_bi_bytes()), _bi_picture())


def test_menu_command_11_packs_like_the_hand_built_file():
    ict = Octek()
    ict.frame[:, :] = 0
    ict.frame[:240, 32:288] = _vd_picture()
    ict.frame[5, 0:32] = 9                # outside the picture: not in the file
    assert framestore.store_vd_frame(ict) == _vd_bytes()


def test_menu_command_10_unpacks_at_x_32_and_whitens_the_rest():
    ict = Octek()
    framestore.load_vd_frame(ict, _vd_bytes())
    assert np.array_equal(ict.frame[:, 32:288], _vd_picture())
    assert (ict.frame[:, :32] == 15).all() and (ict.frame[:, 288:] == 15).all()


def test_menu_command_10_ignores_blocks_60_to_63():
    data = bytearray(_vd_bytes())
    data[30720:] = b"\xff" * 2048
    ict = Octek()
    framestore.load_vd_frame(ict, bytes(data))
    assert np.array_equal(ict.frame[:, 32:288], _vd_picture())


def test_menu_commands_4_and_5_against_hand_built_bytes():
    ict = Octek()
    ict.frame[60:180, 96:224] = _bi_picture()
    assert framestore.store_bi_frame(ict) == _bi_bytes()
    other = Octek()
    framestore.load_bi_frame(other, _bi_bytes())
    assert np.array_equal(other.frame[60:180, 96:224], _bi_picture())
    assert other.frame[:60].sum() == 0 and other.frame[180:].sum() == 0
