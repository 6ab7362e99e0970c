"""``pre import``: pictures made by the test, through the documented
digitizer model (BT.601 grey, fit to 256x240, floor(Y/16))."""

import cv2
import numpy as np
import pytest

from diskfmt.layouts import decode_vd
from pre.digitize import Levels, digitize
from pre.main import main


def _import(tmp_path, img, *extra, name="in.png"):
    src = tmp_path / name
    assert cv2.imwrite(str(src), img)
    out = tmp_path / "OUT.VD"
    assert main(["import", str(src), "-o", str(out), *extra]) == 0
    return decode_vd(out.read_bytes())


def test_grey_png_levels(tmp_path):
    img = np.tile(np.arange(256, dtype=np.uint8), (240, 1))   # column c has grey c
    pic = _import(tmp_path, img)
    assert pic.shape == (240, 256)
    assert list(pic[0, [0, 15, 16, 31, 32, 127, 128, 240, 255]]) == [0, 0, 1, 1, 2, 7, 8, 15, 15]
    assert (pic == pic[0]).all()


def test_colour_png_luma(tmp_path):
    img = np.zeros((240, 256, 3), dtype=np.uint8)              # OpenCV order B, G, R
    img[:, 0:64] = (0, 0, 255)       # red:   0.299*255 = 76.2  -> 4
    img[:, 64:128] = (0, 255, 0)     # green: 0.587*255 = 149.7 -> 9
    img[:, 128:192] = (255, 0, 0)    # blue:  0.114*255 = 29.1  -> 1
    img[:, 192:256] = (255, 255, 255)  # white 255              -> 15
    pic = _import(tmp_path, img)
    assert list(pic[100, [0, 64, 128, 192]]) == [4, 9, 1, 15]


def test_crop_is_the_default_and_keeps_the_centre(tmp_path):
    # 640x480: the 256:240 centre is 512x480, x 64..575; it halves exactly.
    img = np.full((480, 640), 255, dtype=np.uint8)              # margins white
    img[:, 64:576] = 100                                       # centre 100 -> 6
    img[0:2, 64:66] = [[0, 32], [32, 0]]                       # 2x2 mean 16 -> 1
    pic = _import(tmp_path, img)
    assert pic[0, 0] == 1
    assert (pic.reshape(-1)[1:] == 6).all()


def test_stretch_averages_pairs(tmp_path):
    img = np.zeros((240, 512), dtype=np.uint8)
    img[:, 0::2] = 64
    img[:, 1::2] = 128                                          # pair mean 96 -> 6
    pic = _import(tmp_path, img, "--fit", "stretch")
    assert (pic == 6).all()


def test_pad_fills_black(tmp_path):
    img = np.full((120, 256), 200, dtype=np.uint8)              # 200 -> 12
    pic = _import(tmp_path, img, "--fit", "pad")
    assert (pic[:60] == 0).all() and (pic[180:] == 0).all()
    assert (pic[60:180] == 12).all()


def test_sixteen_bit_png(tmp_path):
    img = np.zeros((240, 256), dtype=np.uint16)
    img[:, :128] = 65535                                       # 255 -> 15
    img[:, 128:] = 128 * 257                                   # 128 -> 8
    pic = _import(tmp_path, img)
    assert pic[0, 0] == 15 and pic[0, 200] == 8


@pytest.mark.parametrize("suffix", [".pgm", ".bmp", ".tif", ".jpg"])
def test_other_formats(tmp_path, suffix):
    img = np.full((240, 256), 136, dtype=np.uint8)             # 136 -> 8 (JPEG keeps a flat field)
    pic = _import(tmp_path, img, name="in" + suffix)
    assert (pic == 8).all()


def test_brightness_and_contrast_are_options_not_default():
    grey = np.full((240, 256), 100, dtype=np.uint8)
    assert (digitize(grey) == 6).all()
    # contrast 2 about mid-range: (100-127.5)*2+127.5 = 72.5 -> 4
    assert (digitize(grey, levels=Levels(contrast=2.0)) == 4).all()
    # brightness +32: 132 -> 8
    assert (digitize(grey, levels=Levels(brightness=32.0)) == 8).all()


def test_auto_levels_spread_a_dull_picture():
    grey = np.tile(np.linspace(100, 140, 256).round().astype(np.uint8), (240, 1))  # levels 6..8
    assert set(np.unique(digitize(grey))) == {6, 7, 8}
    auto = digitize(grey, levels=Levels(auto=True))
    assert auto.min() == 0 and auto.max() == 15


def test_video_frame(tmp_path):
    path = tmp_path / "clip.avi"
    w = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 5, (256, 240), False)
    if not w.isOpened():
        pytest.skip("this OpenCV build cannot write MJPG video")
    for v in (0, 136, 255):
        w.write(np.full((240, 256), v, dtype=np.uint8))
    w.release()
    out = tmp_path / "F.VD"
    assert main(["import", str(path), "--frame", "1", "-o", str(out)]) == 0
    pic = decode_vd(out.read_bytes())
    assert abs(int(np.median(pic)) - 8) <= 1
    assert main(["import", str(path), "--frame", "50", "-o", str(tmp_path / "G.VD")]) == 1
    assert not (tmp_path / "G.VD").exists()
