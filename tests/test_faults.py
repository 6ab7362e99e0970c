"""The file protocol under faults, with real ``nstar``/``estar``
processes: stale files at start, ``kill -9`` of either program mid-line,
corrupt or truncated files, two ESTARs on one directory.

Each test checks the result against the in-process reference (``DirectLink``):
a run that survived a fault must write the POSIT.DT bytes a clean run writes.
docs/robustness.md describes each case.
"""

from __future__ import annotations

import os
import select
import signal
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from diskfmt.layouts import (Command, FormatError, decode_bi, decode_block,
                             decode_posit, encode_ncont, encode_slice, encode_wbmap,
                             Slice, CODE_EDGE_MAP, CODE_SLICE, BLOCK_DT_BYTES,
                             POSIT_BYTES)
from diskfmt.rdos import JHData
from nstar.program import Nova

from rigtools import (BOX_LINES, FakeNova, cleanup, command_in, env, estar, finish, freeze,
                      freeze_when, hold_estar_lock, nstar, nstar_ready, output, reference, send_raw, stale,
                      wait_until)

pytestmark = pytest.mark.processes

PUBLIC = ("NCONT.DT", "SLICE.DT", "SL.DT", "WBMAP.DT", "BLOCK.DT", "POSIT.DT", "TERM.DT")


class WriteWatch:
    """Every inotify event on jhdata/ during a test, read in a thread: a file
    published by rename is never *written* under its public name, so an
    IN_MODIFY or IN_CLOSE_WRITE on NCONT.DT, SLICE.DT, ... would mean a reader
    could have seen it half written."""

    def __init__(self, directory: Path):
        from watchdog.observers.inotify_c import (inotify_init, inotify_add_watch,
                                                  InotifyConstants as C)
        self.C = C
        self.fd = inotify_init()
        inotify_add_watch(self.fd, os.fsencode(directory),
                          C.IN_MODIFY | C.IN_CLOSE_WRITE | C.IN_CREATE | C.IN_MOVED_TO)
        self.events: list[tuple[int, str]] = []
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        poller = select.poll()
        poller.register(self.fd, select.POLLIN)
        while self.running:
            if not poller.poll(50):
                continue
            buf = os.read(self.fd, 1 << 16)
            off = 0
            while off < len(buf):
                _, mask, _, length = struct.unpack_from("iIII", buf, off)
                name = buf[off + 16:off + 16 + length].rstrip(b"\0").decode()
                self.events.append((mask, name))
                off += 16 + length

    def stop(self):
        self.running = False
        self.thread.join(5)
        os.close(self.fd)

    def written(self, name: str) -> int:
        return sum(1 for m, n in self.events
                   if n == name and m & (self.C.IN_MODIFY | self.C.IN_CLOSE_WRITE))

    def appeared(self, name: str) -> int:
        return sum(1 for m, n in self.events
                   if n == name and m & (self.C.IN_CREATE | self.C.IN_MOVED_TO))


# --- stale files at start ----------------------------------------------------------

def test_stale_files_from_an_earlier_run_are_set_aside_and_said(rig):
    tmp, jh = rig
    junk = {   # what an interrupted earlier session can leave; none of it must be read
        "NCONT.DT": encode_ncont(Command(CODE_EDGE_MAP, 1, 40, 45, 0, 1)),
        "ECONT.DT": encode_ncont(Command(CODE_SLICE, 2, 0, 45, 128, 0)),
        "SLICE.DT": encode_slice(Slice([-1, 0, 45, 127, 45, 128, 1, 3] + [7] * 248)),
        "SL.DT": b"\x00" * 1000,
        "WBMAP.DT": encode_wbmap([0xFFFF] * 16),
        "BLOCK.DT": b"\x01" * BLOCK_DT_BYTES,
        "EDAT.DT": b"\x02" * POSIT_BYTES,
        "NDAT.DT": encode_wbmap([0x5555] * 16),
        "TRM.DT": b" NOVA proc",
        "TERM.DT": b" NOVA processing termin",   # not a clean end's (that one is just removed)
    }
    for name, data in junk.items():
        (jh / name).write_bytes(data)
    e = n = None
    try:
        # ESTAR first: it sweeps its names, then its first command waits for NSTAR.
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", "10", "--terminate")
        wait_until(lambda: (c := command_in(jh)) is not None and c.code == CODE_SLICE,
                   10, "ESTAR's first slice command")
        n = nstar(tmp, jh, "nstar")
        assert finish(e) == 0, output(tmp, "estar")
        assert finish(n) == 0, output(tmp, "nstar")
    finally:
        cleanup(e, n)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45])
    eout, nout = output(tmp, "estar")[0], output(tmp, "nstar")[0]
    for name in ("NCONT.DT", "ECONT.DT", "SLICE.DT", "SL.DT", "WBMAP.DT", "BLOCK.DT", "EDAT.DT"):
        assert f"Found {name} from an earlier run; moved it to {jh / 'STALE' / name}." in eout
    for name in ("NDAT.DT", "TRM.DT"):
        assert f"Found {name} from an earlier run; moved it to {jh / 'STALE' / name}." in nout
    # TERM.DT: NSTAR set the old one aside; the one in jhdata is this run's.
    assert "Found TERM.DT from an earlier run" in nout
    kept = {p.name.split(".2")[0]: p.read_bytes() for p in (jh / "STALE").iterdir()}
    assert kept == junk                       # every stale file kept, byte for byte


def test_reply_to_a_dead_estar_published_after_the_sweep_is_not_read(rig):
    """The race of QUIRKS M14: NSTAR is still busy with a command of a dead ESTAR
    (here: blocked publishing its WBMAP.DT because the dead ESTAR never took the
    previous one, and slow — stopped — as a loaded machine can be) while a new
    ESTAR starts.  Before QUIRKS M14 the new ESTAR swept the old WBMAP.DT, sent
    its commands, and NSTAR then published the dead ESTAR's WBMAP.DT, which the
    new ESTAR read as the answer to its first edge-map request: every map after
    it shifted by one and POSIT.DT was wrong, silently."""
    tmp, jh = rig
    n = e = None
    dead = hold_estar_lock(jh)                         # the ESTAR that will die
    try:
        n = nstar(tmp, jh, "nstar", "--timeout", "20")
        first, second = Command(CODE_EDGE_MAP, 1, 30, 45, 0, 1), Command(CODE_EDGE_MAP, 2, 70, 45, 0, 2)
        send_raw(jh, first)
        wait_until(lambda: (jh / "WBMAP.DT").exists(), 10, "the first WBMAP.DT")
        send_raw(jh, second)
        wait_until(lambda: not (jh / "NCONT.DT").exists() and (jh / "NDAT.DT").exists(),
                   10, "NSTAR to wait with its second WBMAP.DT")
        freeze(n)
        dead.close()
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", "10")
        wait_until(lambda: any(s.startswith("WBMAP.DT") for s in stale(jh)), 10,
                   "ESTAR's sweep")
        try:   # without the busy lock ESTAR sends its command at once
            wait_until(lambda: command_in(jh) is not None, 1.5)
        except AssertionError:
            pass
        os.kill(n.pid, signal.SIGCONT)
        assert finish(e) == 0, output(tmp, "estar")
        assert n.poll() is None                       # NSTAR keeps serving
    finally:
        cleanup(e, n)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45])
    assert not (jh / "WBMAP.DT").exists()
    nova = Nova()
    nova.load_pair(decode_bi((tmp / "L.BI").read_bytes()), decode_bi((tmp / "R.BI").read_bytes()))
    maps = sorted(p.read_bytes() for p in (jh / "STALE").iterdir())
    assert maps == sorted(nova.execute(encode_ncont(c))[0].data for c in (first, second))
    assert output(tmp, "estar")[0].count("Found WBMAP.DT from an earlier run") == 2


# --- kill -9 of NSTAR -------------------------------------------------------------

def _kill_nstar_while_estar_waits_for_wbmap(tmp, jh, n, e):
    """Stop NSTAR while ESTAR's edge-map command is in NCONT.DT (ESTAR is then
    in NWAIT for WBMAP.DT), and kill it."""
    freeze_when(n, lambda: (c := command_in(jh)) is not None and c.code == CODE_EDGE_MAP)
    n.kill()
    n.wait(10)
    assert (jh / "NCONT.DT").exists() and not (jh / "WBMAP.DT").exists()
    assert e.poll() is None


def _served_once(tmp, jh, tag):
    """Wait until NSTAR serves, and have it serve one slice command by hand
    (its reply taken away): NSTAR's start and its first command, which a
    loaded machine can make slow, are over before an ESTAR with a short
    --timeout talks to it."""
    nstar_ready(tmp, tag, 120)
    send_raw(jh, Command(CODE_SLICE, 1, 0, 45, 128, 0))
    wait_until(lambda: (jh / "SLICE.DT").exists() and not (jh / "NCONT.DT").exists(), 120,
               "NSTAR's first reply")
    (jh / "SLICE.DT").unlink()


def test_kill_nstar_estar_reports_then_both_restarted_complete_the_line(rig):
    tmp, jh = rig
    n = e = n2 = e2 = None
    try:
        n = nstar(tmp, jh, "nstar")
        # ESTAR's 5 s are for the killed NSTAR, not for NSTAR's start
        _served_once(tmp, jh, "nstar")
        e = estar(tmp, jh, "estar", "--line", *BOX_LINES, "--timeout", "5")
        _kill_nstar_while_estar_waits_for_wbmap(tmp, jh, n, e)
        t = time.monotonic()
        assert finish(e) == 1
        assert time.monotonic() - t < 25                 # its 5 s, not the default 30
        err = output(tmp, "estar")[1]
        assert err.strip() == (f"estar: no WBMAP.DT from NSTAR after 5 s — is nstar running "
                               f"on this jhdata directory ({jh})?")
        assert not JHData(jh, me="NSTAR", peer="ESTAR", use_events=False).held("ESTAR.LCK")
        # Restart both at once, NSTAR first: it finds the dead ESTAR's command
        # and answers it; the new ESTAR must read none of that.
        n2 = nstar(tmp, jh, "nstar2")
        e2 = estar(tmp, jh, "estar2", "--line", "45", "60", "--timeout", "120", "--terminate")
        assert finish(e2) == 0, output(tmp, "estar2")
        assert finish(n2) == 0, output(tmp, "nstar2")
    finally:
        cleanup(n, e, n2, e2)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45, 60])
    # the dead ESTAR's command, or its answer, was set aside and said -- by the
    # new ESTAR, or by NSTAR when it started before the new ESTAR held its lock
    said = output(tmp, "estar2")[0] + output(tmp, "nstar2")[0]
    assert "Found NCONT.DT from an earlier run" in said or "Found WBMAP.DT from an earlier run" in said


def test_estar_still_waiting_completes_the_line_after_nstar_restart(rig):
    tmp, jh = rig
    n = e = n2 = None
    try:
        n = nstar(tmp, jh, "nstar")
        nstar_ready(tmp, "nstar")
        e = estar(tmp, jh, "estar", "--line", *BOX_LINES, "--timeout", "120", "--terminate")
        _kill_nstar_while_estar_waits_for_wbmap(tmp, jh, n, e)
        time.sleep(0.5)
        assert e.poll() is None                           # still waiting for WBMAP.DT
        n2 = nstar(tmp, jh, "nstar2")                     # takes the waiting NCONT.DT
        assert finish(e) == 0, output(tmp, "estar")
        assert finish(n2) == 0, output(tmp, "nstar2")
    finally:
        cleanup(n, e, n2)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [int(y) for y in BOX_LINES])


# --- kill -9 of ESTAR -------------------------------------------------------------

def test_kill_estar_during_edge_maps_nstar_serves_the_next_estar(rig):
    tmp, jh = rig
    watch = WriteWatch(jh)
    n = e = e2 = None
    try:
        n = nstar(tmp, jh, "nstar", "--timeout", "2")
        e = estar(tmp, jh, "estar", "--line", *BOX_LINES, "--timeout", "10")
        # kill while the WBMAP.DT for its request is being made or waits unread
        freeze_when(e, lambda: (c := command_in(jh)) is not None and c.code == CODE_EDGE_MAP,
                    recheck=False)
        e.kill()
        e.wait(10)
        e2 = estar(tmp, jh, "estar2", "--line", "60", "45", "--timeout", "10", "--terminate")
        assert finish(e2) == 0, output(tmp, "estar2")
        assert finish(n) == 0, output(tmp, "nstar")
    finally:
        cleanup(n, e, e2)
        watch.stop()
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [60, 45])
    assert output(tmp, "nstar")[1] == ""
    assert watch.appeared("WBMAP.DT") > 20 and watch.appeared("SLICE.DT") >= 4
    for name in PUBLIC:                       # published by link/rename only
        assert watch.written(name) == 0, name


def test_kill_estar_between_slices_nstar_reports_the_untaken_reply_and_keeps_serving(rig):
    """ESTAR sends both slice commands before it reads the first SLICE.DT; killed
    in between, NSTAR's second SLICE.DT waits for a name nobody frees.  NSTAR
    says so after --timeout, keeps that reply in STALE/ and goes on serving
    (QUIRKS M15).  The window between ESTAR's second command and its taking of
    the first reply is too short to hit with a signal, so ESTAR is killed just
    after its first command and this test sends the second one, the very bytes
    ESTAR sends next — the state a kill inside the window leaves."""
    tmp, jh = rig
    watch = WriteWatch(jh)
    n = e = e2 = None
    try:
        n = nstar(tmp, jh, "nstar", "--timeout", "2")
        # NSTAR serving first: one that starts after the ESTAR died would rightly
        # set its command aside as stale
        wait_until(lambda: "Ready for the ECLIPSE" in output(tmp, "nstar")[0], 30, "NSTAR")
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", "10")
        freeze_when(e, lambda: command_in(jh) == Command(CODE_SLICE, 1, 0, 45, 128, 0))
        e.kill()
        e.wait(10)
        send_raw(jh, Command(CODE_SLICE, 2, 0, 45, 128, 0))
        wait_until(lambda: "Waiting for the next command" in output(tmp, "nstar")[1], 10,
                   "NSTAR's report")
        assert n.poll() is None
        err = output(tmp, "nstar")[1]
        assert err.startswith(f"nstar: SLICE.DT not taken by ESTAR after 2 s — is estar running "
                              f"on this jhdata directory ({jh})? This SLICE.DT reply was not "
                              f"published; kept as {jh / 'STALE' / 'SLICE.DT'}.")
        e2 = estar(tmp, jh, "estar2", "--line", "45", "--timeout", "10", "--terminate")
        assert finish(e2) == 0, output(tmp, "estar2")
        assert finish(n) == 0, output(tmp, "nstar")
    finally:
        cleanup(n, e, e2)
        watch.stop()
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45])
    assert "Found SLICE.DT from an earlier run" in output(tmp, "estar2")[0]
    slices = [p for p in (jh / "STALE").iterdir() if p.name.startswith("SLICE.DT")]
    assert len(slices) == 2 and all(p.stat().st_size == 1024 for p in slices)
    for name in PUBLIC:
        assert watch.written(name) == 0, name


# --- corrupt or truncated files -------------------------------------------------------

@pytest.mark.parametrize("name,damage,problem", [
    ("SLICE.DT", lambda d: d[:1000], "1000 bytes, expected 1024 or 512"),
    ("SLICE.DT", lambda d: d[:526] + b"\x00\x63" + d[528:], "NFEAT (word 8) is 99, not 0..50"),
    ("WBMAP.DT", lambda d: d[:33], "33 bytes, expected 34"),
    ("WBMAP.DT", lambda d: b"\x00\x00" + d[2:], "first word is 0, expected the constant 1"),
])
def test_damaged_reply_is_one_clear_error_and_nothing_is_overwritten(rig, name, damage, problem):
    tmp, jh = rig
    (jh / "POSIT.DT").write_bytes(b"an earlier POSIT.DT")
    fake = FakeNova(tmp, jh, name, damage)
    fake.start()
    try:
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", "3")
        rc = finish(e)
    finally:
        cleanup(e)
        fake.stop()
    err = output(tmp, "estar")[1]
    kept = jh / "STALE" / f"{name}.bad.0"
    assert rc == 1
    assert err == f"estar: {jh / name}: {problem}; kept as {kept}\n"
    assert kept.read_bytes() == fake.sent                  # the bad bytes, for inspection
    assert (jh / "POSIT.DT").read_bytes() == b"an earlier POSIT.DT"


@pytest.mark.parametrize("size", [0, 13])
def test_damaged_ncont_stops_nstar_and_is_left_in_place(rig, size):
    tmp, jh = rig
    bad = (encode_ncont(Command(CODE_SLICE, 1, 0, 45, 128, 0)) * 2)[:size]
    (jh / "NCONT.DT").write_bytes(bad)
    live = hold_estar_lock(jh)          # an ESTAR waits for it: not stale
    n = nstar(tmp, jh, "nstar")
    try:
        assert finish(n) == 1
    finally:
        cleanup(n)
        live.close()
    assert output(tmp, "nstar")[1] == (f"nstar: {jh / 'NCONT.DT'}: {size} bytes, expected 12 — "
                                       f"not a command file; left in place for inspection\n")
    assert (jh / "NCONT.DT").read_bytes() == bad


@pytest.mark.parametrize("damage,problem", [
    (lambda d: b"", "not a .BI picture: an empty file; make a pair with `pre pair LEFT.jpg "
                    "RIGHT.jpg -o NAME` (NAME-L.BI, NAME-R.BI)"),
    (lambda d: d[:200] + b"\x00\x10" + d[202:], "pixel at row 0, column 100 is 16, not a 4-bit "
                                                "grey level 0..15 (1 such words)"),
])
def test_damaged_bi_stops_nstar_before_it_serves(rig, damage, problem):
    tmp, jh = rig
    right = tmp / "R.BI"
    right.write_bytes(damage(right.read_bytes()))
    before = right.read_bytes()
    n = nstar(tmp, jh, "nstar")
    try:
        assert finish(n) == 1
    finally:
        cleanup(n)
    assert output(tmp, "nstar")[1] == f"nstar: {right}: {problem}\n"
    assert right.read_bytes() == before
    assert sorted(p.name for p in jh.iterdir()) == []   # pictures checked before jhdata/ is touched


def test_truncated_vd_is_one_clear_error_from_pre(tmp_path):
    vd = tmp_path / "SCENE.VD"
    vd.write_bytes(bytes(32767))
    out = tmp_path / "SCENE.BI"
    done = subprocess.run([sys.executable, "-m", "pre", "shrink", str(vd), "-o", str(out)],
                          capture_output=True, text=True, env=env(), timeout=60)
    assert done.returncode == 1
    assert f"{vd}: 32767 bytes, expected 32768" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["SCENE.VD"]


@pytest.mark.parametrize("reader,name,data,problem", [
    (decode_block, "BLOCK.DT", bytes(53), "53 bytes, expected 54"),
    (decode_posit, "POSIT.DT", bytes(2559), "2559 bytes, expected 2560"),
])
def test_block_and_posit_readers_name_the_file(reader, name, data, problem):
    """No rig program reads BLOCK.DT or POSIT.DT back (ESTAR only writes
    POSIT.DT); their readers give the one documented error."""
    with pytest.raises(FormatError) as exc:
        reader(data)
    assert str(exc.value) == f"{name}: {problem}"


# --- two ESTARs ---------------------------------------------------------------------

def test_second_estar_is_refused_while_the_first_works_and_the_first_is_unharmed(rig):
    tmp, jh = rig
    n = e = None
    lines = BOX_LINES
    try:
        n = nstar(tmp, jh, "nstar")
        e = estar(tmp, jh, "estar", "--line", *lines, "--timeout", "10", "--terminate")
        # hold the first one still mid-line (stopped, as a busy machine can leave it)
        freeze_when(e, lambda: (c := command_in(jh)) is not None and c.code == CODE_EDGE_MAP,
                    recheck=False)
        second = subprocess.run(
            [sys.executable, "-m", "estar.main", "--jhdata", str(jh), "--separation", "0.75",
             "--virtual-distance", "180", "--debug", "0", "--line", "45", "--timeout", "2"],
            capture_output=True, text=True, env=env(), timeout=60)
        os.kill(e.pid, signal.SIGCONT)
        assert finish(e) == 0, output(tmp, "estar")
        assert finish(n) == 0
    finally:
        cleanup(n, e)
    assert second.returncode == 1
    assert second.stderr == (f"estar: another ESTAR is already running on {jh} (it holds "
                             f"ESTAR.LCK); stop it first\n")
    assert "Found" not in second.stdout                  # it touched nothing
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [int(y) for y in lines])
    assert not (jh / "STALE").exists()


# --- a timed-out file link in rig --------------------------------------------------

def test_rig_file_scan_with_a_frozen_nstar_times_out_in_one_line_and_tidies(rig):
    """rig's own NSTAR stops answering mid-scan (frozen, as a stalled machine
    leaves it): after --timeout, one line naming the file it waited for, exit 1,
    the frozen NSTAR killed and no command left in jhdata/."""
    import types
    tmp, jh = rig

    def nstar_pid():
        try:
            return int((jh / "NSTAR.LCK").read_text() or 0)
        except (FileNotFoundError, ValueError):
            return 0

    p = subprocess.Popen([sys.executable, "-m", "rig.main", "scan", "--link", "file",
                          "--jhdata", str(jh), "--timeout", "2", "--quiet", "--left",
                          str(tmp / "L.BI"), "--right", str(tmp / "R.BI"), "--line",
                          *BOX_LINES], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=env())
    try:
        wait_until(lambda: nstar_pid() != 0, 120, "rig's NSTAR")
        served = types.SimpleNamespace(pid=nstar_pid())
        # frozen while a command waits for it: it can never be taken
        freeze_when(served, lambda: (jh / "NCONT.DT").exists(), timeout=120)
        out, err = p.communicate(timeout=120)
    finally:
        cleanup(p)
    assert p.returncode == 1, err
    assert "Traceback" not in err
    assert err == (f"rig: NCONT.DT not taken by NSTAR after 2 s — is nstar running on this "
                   f"jhdata directory ({jh})?\n")
    with pytest.raises(ProcessLookupError):           # killed and reaped by rig
        os.kill(served.pid, 0)
    left = {x.name for x in jh.iterdir()}
    assert left <= {"ESTAR.LCK", "NSTAR.LCK", "NSTAR.BSY", "POSIT.DT"}, left
