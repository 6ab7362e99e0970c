"""The 1985 dialogues driven through standard input, and the debug printouts
each flag turns on (FORTRAN unit 12)."""

import io
import subprocess

import pytest
import sys

from diskfmt.layouts import decode_bi, decode_posit, Command, encode_ncont
from diskfmt.listing import Listing
from estar.program import in_process_rig
from nstar.program import Nova

from rig.session import start_nstar as start_nstar_process
from rigtools import make_pair, env, start_nstar, hold_estar_lock


@pytest.mark.processes
def test_estar_asks_as_in_1985_and_stops_on_a_line_outside_0_119(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    nstar = start_nstar(jh, left, right)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "estar.main", "--jhdata", str(jh)],
            input="0.75\n180\n8\n45\n120\n", capture_output=True, text=True, env=env(),
            timeout=120)
    finally:
        nstar.kill()
        nstar.wait()
    out = done.stdout
    assert done.returncode == 0, done.stderr
    for prompt in ("ROBOT VISION SYSTEM", " Camera seperation = ", " Virtual image distance = ",
                   " 32--Print compared bit maps.", " Desired debug flags (0 for none) = ",
                   " Which horizontal line? (0 to 119) IY="):
        assert prompt in out
    assert out.count(" Which horizontal line? (0 to 119) IY=") == 2     # 45, then 120 stops
    assert "Feature 3-D positions." in out and "NP=  6 dv=180.00 ds= 0.750" in out
    assert decode_posit((jh / "POSIT.DT").read_bytes()).np_ == 6


@pytest.mark.processes
def test_estar_asks_again_after_an_answer_that_is_not_a_number(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    done = subprocess.run(
        [sys.executable, "-m", "estar.main", "--jhdata", str(jh)],
        input="feet\n0.75\n180\n0\n-1\n", capture_output=True, text=True, env=env(), timeout=60)
    assert done.returncode == 0
    assert "camera separation 'feet' is not a number; answer again." in done.stdout
    assert done.stdout.count(" Camera seperation = ") == 2


@pytest.mark.processes
def test_nstar_dialogue_loads_the_pair_from_typed_file_names(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    live = hold_estar_lock(jh)                     # the test plays the ESTAR
    p = start_nstar_process(jh, None, None, debug=None, idle_timeout=30, stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env())
    try:
        # debug flags, save? no, new images? yes, a missing file (asked again), L, R
        p.stdin.write(f"0\n0\n1\nNOSUCH.BI\n{left}\n{right}\n")
        p.stdin.flush()
        (jh / "ECONT.DT").write_bytes(encode_ncont(Command(-1)))
        (jh / "ECONT.DT").rename(jh / "NCONT.DT")
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
        live.close()
    assert p.returncode == 0, err
    for text in (" NOVA half of stereo vision system", " 16-Edge bit map.",
                 " Input the debug flags. (=0 for no flags.) ", "Save the current image? (0=NO) ",
                 "Input new images? (0=NO) ", " Input the LEFT image file name.",
                 " Input the RIGHT image file name.", " Ready for the ECLIPSE command file.",
                 "COMMAND= Terminate processing."):
        assert text in out
    assert "Open error on input file: NOSUCH.BI: no such file" in out
    assert out.count(" Image loaded.") == 2


def _eclipse(tmp_path, debug, nova_debug=0):
    left, right = make_pair(tmp_path)
    nova_listing, listing = io.StringIO(), io.StringIO()
    nova = Nova(debug=nova_debug, listing=Listing(nova_listing))
    nova.load_pair(decode_bi(left.read_bytes()), decode_bi(right.read_bytes()))
    ecl = in_process_rig(None, None, nova=nova, debug=debug, listing=Listing(listing))
    return nova, ecl, listing, nova_listing


def test_each_estar_debug_flag_prints_its_listing(tmp_path):
    expected = {1: "1-Dimensional Slice Feature List", 2: "MAP #", 4: "Feature matches",
                8: "Feature 3-D positions.", 16: "Bit map.", 32: "Comparing left sides of"}
    for flag, marker in expected.items():
        _, ecl, listing, _ = _eclipse(tmp_path, flag)
        ecl.lcln(45)
        text = listing.getvalue()
        assert marker in text, flag
        for other, other_marker in expected.items():
            if other != flag and other_marker not in ("Bit map.",):
                assert other_marker not in text, (flag, other)


def test_debug_flags_do_not_change_posit(tmp_path):
    _, quiet, _, _ = _eclipse(tmp_path, 0)
    _, loud, _, _ = _eclipse(tmp_path, -1 & 0xFFFF)
    for y in (30, 45, 60):
        assert quiet.lcln(y).posit == loud.lcln(y).posit


def test_nstar_debug_flags_print_their_listing(tmp_path):
    nova, ecl, _, nova_listing = _eclipse(tmp_path, 0, nova_debug=16)
    ecl.lcln(45)
    assert nova_listing.getvalue().count("Bit map.") == ecl.requests
    nova, _, _, nova_listing = _eclipse(tmp_path, 0, nova_debug=1 | 2 | 4 | 8)
    nova.execute(encode_ncont(Command(1, 1, 60, 45, 20, 7)))
    text = nova_listing.getvalue()
    assert text.count("-- RADSP -- IDIR = ") == 16                  # 4 quadrants x 4 rays
    assert "1-Dimensional Slice Feature List" in text
    assert "---ICNTR =" in text and "LCM( 16," in text and "Bit map." in text
