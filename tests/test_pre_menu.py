"""The 1985 menu driven through standard input."""

import io

import numpy as np

from diskfmt.layouts import encode_bi, encode_vd
from octek_sim.board import Octek
from pre.main import main
from pre.menu import MENU, PreMenu


def _run(lines, board=None, **kw):
    out = io.StringIO()
    menu = PreMenu(board or Octek(), io.StringIO("".join(l + "\n" for l in lines)), out, **kw)
    rc = menu.run()
    return rc, out.getvalue(), menu.ict


def _picture():
    # a 240x256 picture whose 2x2 blocks average to known values
    y, x = np.mgrid[0:240, 0:256]
    return ((x // 16 + y // 30) % 16).astype(np.uint8)


def test_menu_text_is_the_listing(tmp_path):
    rc, out, _ = _run(["-1"])
    assert rc == 0
    assert "Robot Vision Image Preprocessor" in out
    for line in MENU:
        assert line + "\n" in out
    assert " 3 Cartoon the image using horizontal and verical QV\n" in out
    assert out.endswith("Enter function number (0 for help): ")


def test_load_condense_store_equals_pre_shrink(tmp_path):
    vd = tmp_path / "A.VD"
    vd.write_bytes(encode_vd(_picture()))
    bi_menu = tmp_path / "MENU.BI"
    rc, out, _ = _run(["10", str(vd), "2", "4", str(bi_menu), "-1"])
    assert rc == 0
    assert "FILE DISPLAYED" in out
    assert "Condense the current image to 128x120" in out
    bi_cli = tmp_path / "CLI.BI"
    assert main(["shrink", str(vd), "-o", str(bi_cli)]) == 0
    assert bi_menu.read_bytes() == bi_cli.read_bytes()
    assert len(bi_menu.read_bytes()) == 30720


def test_uniform_picture_condenses_to_uniform_words(tmp_path):
    vd = tmp_path / "U.VD"
    vd.write_bytes(bytes([0x66]) * 30720 + bytes(2048))     # every pixel 6
    bi = tmp_path / "U.BI"
    _run(["10", str(vd), "2", "4", str(bi), "-1"])
    assert bi.read_bytes() == bytes([0x00, 0x06]) * 15360


def test_store_and_reload_vd_round_trip(tmp_path):
    vd = tmp_path / "A.VD"
    vd.write_bytes(encode_vd(_picture()))
    out_vd = tmp_path / "B.VD"
    rc, out, _ = _run(["10", str(vd), "11", str(out_vd), "-1"])
    assert "THE FILE IS SAVED." in out
    assert out_vd.read_bytes() == vd.read_bytes()


def test_load_bi_shows_it_at_96_60(tmp_path):
    pic = (np.arange(120 * 128).reshape(120, 128) % 16).astype(np.uint8)
    bi = tmp_path / "P.BI"
    bi.write_bytes(encode_bi(pic))
    _, out, ict = _run(["5", str(bi), "-1"])
    assert "Loading a 128x120 image from disk." in out
    assert np.array_equal(ict.frame[60:180, 96:224], pic)


def test_not_a_number_keeps_the_menu_going(tmp_path):
    rc, out, _ = _run(["abc", "", "2.5", "0", "-1"])
    assert rc == 0
    assert "** 'abc' is not a number" in out
    assert "** an empty line is not a number" in out
    assert "** '2.5' is not a number" in out
    assert out.count("Image Preprocessor Command List") == 2    # help (0) showed it again


def test_out_of_range_numbers_show_the_menu_and_negative_exits():
    rc, out, _ = _run(["12", "-5", "2"])
    assert rc == 0
    assert out.count("Image Preprocessor Command List") == 2
    assert "Condense" not in out                                 # -5 exited first


def test_dummied_out_commands_do_nothing():
    board = Octek()
    board.frame[:] = 7
    _, out, ict = _run(["6", "7", "8", "9", "-1"], board=board)
    assert (ict.frame == 7).all()
    assert out.count("Enter function number (0 for help): ") == 5


def test_camera_is_missing_on_the_simulated_board():
    _, out, ict = _run(["1", "1", "-1"])
    assert "Video Input Control\nCamera on (1), Camera off (2)\n" in out
    assert "** Camera Input is missing (unable to find video sync)" in out
    assert ict.display.interlaced is False and ict.display.external_sync is False


def test_camera_menu_other_answers():
    _, out, ict = _run(["1", "7", "2", "-1"])
    assert out.count("Video Input Control") == 2                 # 7: GOTO 10
    assert ict.display.camera_on is False


def test_stand_in_camera_fills_the_picture():
    pic = _picture()
    _, out, ict = _run(["1", "1", "-1", "-1"], camera=lambda: pic)
    assert "missing" not in out
    assert np.array_equal(ict.frame[:, 32:288], pic)
    assert ict.display.camera_on is True


def test_missing_file_message_and_screen_unchanged(tmp_path):
    board = Octek()
    board.frame[:] = 3
    _, out, ict = _run(["10", str(tmp_path / "NONE.VD"), "2", "-1"], board=board)
    assert f" File open error- {tmp_path / 'NONE.VD'}: no such file" in out
    assert "Condense the current image" in out                   # the menu went on


def test_wrong_size_vd_leaves_the_screen(tmp_path):
    bad = tmp_path / "BAD.VD"
    bad.write_bytes(bytes(30720))
    board = Octek()
    board.frame[:] = 3
    _, out, ict = _run(["10", str(bad), "-1"], board=board)
    assert "30720 bytes, expected 32768" in out and "BAD.VD" in out
    assert (ict.frame == 3).all()


def test_wrong_size_bi(tmp_path):
    bad = tmp_path / "BAD.BI"
    bad.write_bytes(bytes(100))
    _, out, _ = _run(["5", str(bad), "-1"])
    assert "100 bytes, expected 30720" in out


def test_store_refuses_an_existing_file(tmp_path):
    keep = tmp_path / "KEEP.BI"
    keep.write_bytes(b"precious")
    _, out, _ = _run(["4", str(keep), "11", str(keep), "-1"])
    assert "already exists; not overwritten" in out
    assert keep.read_bytes() == b"precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["KEEP.BI"]


def test_store_with_force_replaces(tmp_path):
    old = tmp_path / "OLD.BI"
    old.write_bytes(b"old")
    _run(["4", str(old), "-1"], force=True)
    assert len(old.read_bytes()) == 30720


def test_end_of_input_ends_the_session():
    rc, out, ict = _run(["2"])
    assert rc == 0 and ict.open is False


def test_cartoon_command_works_on_the_condensed_picture(tmp_path):
    board = Octek()
    board.frame[60:180, 96:224] = 4
    board.frame[60:180, 160:224] = 11
    board.frame[100, 120] = 5                    # one-pixel noise, below T
    _, out, ict = _run(["3", "-1"], board=board)
    assert " using passes of horizontal and vertical QV processing." in out
    want = np.full((120, 128), 4, dtype=np.uint8)
    want[:, 64:] = 11
    assert np.array_equal(ict.frame[60:180, 96:224], want)
