"""Bad input: one clear message naming the file or value, a non-zero exit,
nothing lost."""

import subprocess

import pytest
import sys
import time

from diskfmt.layouts import Command, encode_ncont, encode_slice, Slice, decode_posit

from rigtools import (make_pair, start_nstar, run_estar, env, hold_estar_lock, lock_held,
                      wait_until)

pytestmark = pytest.mark.processes


def test_bi_of_wrong_size_is_refused_by_nstar(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    right.write_bytes(right.read_bytes()[:-1])
    before = right.read_bytes()
    p = start_nstar(jh, left, right)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 1
    assert str(right) in err and "not a .BI picture: 30,719 bytes; make a pair with `pre pair" in err
    assert right.read_bytes() == before


def _wait_exit(p, timeout=60):
    out, err = p.communicate(timeout=timeout)
    return p.returncode, out, err


def test_ncont_of_11_bytes_stops_nstar_and_is_kept(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    live = hold_estar_lock(jh)
    p = start_nstar(jh, left, right)
    bad = encode_ncont(Command(2, 1, 0, 60, 128, 0))[:11]
    (jh / "X.DT").write_bytes(bad)
    (jh / "X.DT").rename(jh / "NCONT.DT")
    rc, out, err = _wait_exit(p)
    live.close()
    assert rc == 1
    assert "NCONT.DT: 11 bytes, expected 12" in err
    assert (jh / "NCONT.DT").read_bytes() == bad          # left for inspection


def test_unknown_code_is_ignored_and_nstar_keeps_serving(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    live = hold_estar_lock(jh)
    p = start_nstar(jh, left, right)
    try:
        for code in (7, 2):
            tmp = jh / "ECONT.DT"
            tmp.write_bytes(encode_ncont(Command(code, 1, 0, 45, 128, 0)))
            deadline = time.monotonic() + 120             # a hang detector
            while (jh / "NCONT.DT").exists() and time.monotonic() < deadline:
                time.sleep(0.01)
            tmp.rename(jh / "NCONT.DT")
        deadline = time.monotonic() + 120             # a hang detector
        while not (jh / "SLICE.DT").exists() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert (jh / "SLICE.DT").stat().st_size == 1024    # the code-2 command was served
    finally:
        p.kill()
        out, err = p.communicate()
        live.close()
    assert "Ignored command code 7" in out


def test_estar_without_nstar_times_out_naming_nstar(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    done = run_estar(jh, "--line", "60", "--timeout", "1")
    assert done.returncode == 1
    assert "NSTAR" in done.stderr and "NCONT.DT" in done.stderr
    assert "is nstar running on this jhdata directory" in done.stderr
    assert "Traceback" not in done.stderr


def test_stale_slice_at_start_is_set_aside_not_read(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    stale = Slice([0] * 256)
    stale.ifbuf[0:8] = [-1, 0, 60, 127, 60, 128, 1, 0]
    (jh / "SLICE.DT").write_bytes(encode_slice(stale))
    p = start_nstar(jh, left, right)
    try:
        done = run_estar(jh, "--line", "45", "--terminate")
    finally:
        p.wait(timeout=60)
    assert done.returncode == 0, done.stderr
    assert "Found SLICE.DT from an earlier run; moved it to" in done.stdout
    kept = list((jh / "STALE").iterdir())
    assert len(kept) == 1 and kept[0].read_bytes() == encode_slice(stale)
    assert decode_posit((jh / "POSIT.DT").read_bytes()).np_ == 6


def test_second_estar_on_one_directory_is_refused(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    first = subprocess.Popen(
        [sys.executable, "-m", "estar.main", "--jhdata", str(jh), "--separation", "0.75",
         "--virtual-distance", "180", "--debug", "0"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env=env())
    try:
        wait_until(lambda: lock_held(jh, "ESTAR.LCK"), 120, "the first ESTAR's lock")
        second = run_estar(jh, "--line", "60", "--timeout", "1")
        assert second.returncode == 1
        assert "another ESTAR is already running" in second.stderr
    finally:
        first.communicate(input="-1\n", timeout=60)
    assert first.returncode == 0


def test_bad_separation_flag_is_one_clear_error(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    done = subprocess.run(
        [sys.executable, "-m", "estar.main", "--jhdata", str(jh), "--separation", "abc",
         "--virtual-distance", "180", "--debug", "0", "--line", "60"],
        capture_output=True, text=True, env=env(), timeout=60)
    assert done.returncode == 1
    assert done.stderr.strip() == "estar: --separation 'abc' is not a number"


def test_second_nstar_on_one_directory_is_refused(tmp_path):
    jh = tmp_path / "jh"
    jh.mkdir()
    left, right = make_pair(tmp_path)
    first = start_nstar(jh, left, right)
    try:
        wait_until(lambda: lock_held(jh, "NSTAR.LCK"), 120, "the first NSTAR's lock")
        second = start_nstar(jh, left, right)
        out, err = second.communicate(timeout=60)
        assert second.returncode == 1
        assert "another NSTAR is already running" in err
        assert first.poll() is None                      # the first keeps serving
    finally:
        first.kill()
        first.wait()
