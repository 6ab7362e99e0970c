"""The shared directory as a trust boundary: this test plays a hostile
peer — anyone who can write into ``jhdata/`` — against the real programs.
Each test failed before its fix (the note under each says how).
docs/robustness.md, "A hostile peer", lists the cases."""

from __future__ import annotations

import multiprocessing
import os
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from diskfmt.layouts import (Command, Slice, decode_wbmap, encode_bi, encode_ncont,
                             encode_slice, CODE_EDGE_MAP, CODE_SLICE, CODE_TERMINATE,
                             TERM_TEXT)
from diskfmt.rdos import JHData, ESTAR_LOCK
from nstar.program import Nova
from rig.session import nstar_command, start_nstar as start_nstar_process

from rigtools import (BOX_LINES, FakeNova, cleanup, command_in, env, estar, finish, freeze,
                      hold_estar_lock, load_pair, make_pair, nstar, nstar_ready, output,
                      reference, run_estar, send_raw, wait_until)

pytestmark = pytest.mark.processes


def one_line(err: str) -> str:
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def damaged_run(tmp, jh, name, damage, *extra, timeout="3"):
    """ESTAR (a real process) for line 45 against a fake NSTAR whose first
    ``name`` reply is ``damage``d; returns (exit code, stderr, the fake)."""
    fake = FakeNova(tmp, jh, name, damage)
    fake.start()
    e = None
    try:
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", timeout, *extra)
        rc = finish(e, 60)
    finally:
        cleanup(e)
        fake.stop()
    return rc, output(tmp, "estar")[1], fake


# --- 1. symlinks in STALE/ ------------------------------------------------------------
# Before: ESTAR wrote the peer's bytes through the link (creating the outside
# file) and said "kept as …/STALE/SLICE.DT.bad.0".

@pytest.mark.parametrize("label,damage", [
    ("SLICE.DT.bad", lambda d: d[:1000]),                                  # damaged
    ("SLICE.DT.skipped", lambda d: d[:516] + b"\x00\x50" + d[518:]),      # for line 80
])
def test_a_link_planted_in_stale_is_never_written_through(rig, label, damage):
    tmp, jh = rig
    outside = tmp / "outside" / "victim"
    (jh / "STALE").mkdir()
    os.symlink(outside, jh / "STALE" / f"{label}.0")
    rc, err, fake = damaged_run(tmp, jh, "SLICE.DT", damage, timeout="2")
    assert rc == 1
    assert not outside.exists() and not outside.parent.exists()
    assert os.readlink(jh / "STALE" / f"{label}.0") == str(outside)     # left as it was
    kept = jh / "STALE" / f"{label}.1"
    assert kept.is_file() and not kept.is_symlink() and kept.read_bytes() == fake.sent
    if label.endswith("bad"):
        assert one_line(err).endswith(f"; kept as {kept}")
    else:
        assert f"kept as {kept}" in output(tmp, "estar")[0]


def test_a_stale_directory_that_is_a_link_is_refused(rig):
    tmp, jh = rig
    outside = tmp / "outside"
    outside.mkdir()
    os.symlink(outside, jh / "STALE")
    (jh / "SLICE.DT").write_bytes(b"left by an earlier run")
    done = run_estar(jh, "--line", "45", "--timeout", "2")
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: {jh / 'STALE'} is a symbolic link, not a plain "
                                     f"directory; nothing is kept through it — remove it")
    assert list(outside.iterdir()) == []                      # before: SLICE.DT moved there
    assert (jh / "SLICE.DT").read_bytes() == b"left by an earlier run"


# --- 2. slice fields outside what NSTAR can write ---------------------------------------
# Before: a feature (200, 600) gave a shift bound above 128, the MARF kernel
# wrote past its work array and ESTAR died of SIGABRT ("double free or corruption").

def _wild_slice(data: bytes) -> bytes:
    sl = Slice(list(np.frombuffer(data[512:], dtype=">i2").astype(int)))
    sl.ifbuf[7] = 1                                   # NFEAT
    sl.ifbuf[10], sl.ifbuf[60], sl.ifbuf[110], sl.ifbuf[160] = 200, 600, 3, 3
    return encode_slice(sl)


def test_a_slice_with_columns_outside_1_128_is_refused_naming_the_file(rig):
    tmp, jh = rig
    rc, err, fake = damaged_run(tmp, jh, "SLICE.DT", _wild_slice)
    kept = jh / "STALE" / "SLICE.DT.bad.0"
    assert rc == 1                                     # not -6 (SIGABRT)
    assert one_line(err) == (f"estar: {jh / 'SLICE.DT'}: feature 1 spans columns 200..600, "
                             f"not a span within 1..128; kept as {kept}")
    assert kept.read_bytes() == fake.sent


def test_the_marf_kernel_bound_checks_its_work_array():
    """A shift bound past the work array (only a wild slice makes one): the
    compiled kernel and the plain Python agree, and neither writes past it
    (before, the plain one raised IndexError; the compiled one corrupted memory)."""
    from estar.marf import marf_kernel, MAX_SHIFTS
    rng = np.random.default_rng(9)
    m1 = np.concatenate(([1], rng.integers(-32768, 32768, 16))).astype(np.int64)
    m2 = np.concatenate(([1], rng.integers(-32768, 32768, 16))).astype(np.int64)
    plain = getattr(marf_kernel, "py_func", marf_kernel)
    results = []
    for kernel in (plain, marf_kernel):
        values = np.full(MAX_SHIFTS + 8, -7, dtype=np.int64)      # 8 guard words
        work = values[:MAX_SHIFTS]
        results.append((tuple(kernel(m1, m2, 400, work)), values.copy()))
    assert results[0][0] == results[1][0]
    assert (results[0][1] == results[1][1]).all()
    assert (results[0][1][MAX_SHIFTS:] == -7).all()                # guard untouched
    # the best shift is what a search over the 31 shifts that overlap finds
    small = np.zeros(31, dtype=np.int64)
    assert results[0][0] == tuple(plain(m1, m2, 15, small))


# --- 3. temporaries opened through symlinks -------------------------------------------
# Before: both programs wrote reply bytes into the link's target and exited 0.

def test_links_planted_as_temporary_names_are_never_written_through(rig):
    tmp, jh = rig
    victims = {name: tmp / f"victim-{name}" for name in ("NDAT.DT", "TRM.DT", "ECONT.DT",
                                                         "EDAT.DT")}
    for v in victims.values():
        v.write_bytes(b"precious")
    n = e = None
    try:
        n = nstar(tmp, jh, "nstar")
        nstar_ready(tmp, "nstar")
        e = estar(tmp, jh, "estar", "--line", *BOX_LINES[:6], "--timeout", "10",
                  "--terminate")
        wait_until(lambda: command_in(jh) is not None, 30, "ESTAR's first command")
        planted = set()
        deadline = time.monotonic() + 20
        while len(planted) < len(victims) and time.monotonic() < deadline:
            for name, v in victims.items():
                if name not in planted:
                    try:
                        os.symlink(v, jh / name)
                        planted.add(name)
                    except FileExistsError:           # the program's own, just now
                        pass
        assert planted == set(victims)
        assert finish(e, 60) == 0, output(tmp, "estar")
        assert finish(n, 60) == 0, output(tmp, "nstar")
    finally:
        cleanup(e, n)
    for v in victims.values():
        assert v.read_bytes() == b"precious"
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, BOX_LINES[:6])
    assert not (jh / "POSIT.DT").is_symlink() and not (jh / "TERM.DT").is_symlink()
    assert (jh / "TERM.DT").read_bytes() == TERM_TEXT.encode()
    links = [p for p in (jh / "STALE").iterdir() if p.is_symlink()]
    assert sorted(os.readlink(p) for p in links) == sorted(str(v) for v in victims.values())


# --- 4. a wild IDN in an edge-map command -----------------------------------------------
# Before: replies differed from run to run (the compiled kernel read foreign
# memory); with RIG_NO_JIT=1 NSTAR died of an IndexError.

def _zero_patch_pair(tmp):
    left, right = load_pair(tmp)
    left = left.copy()
    left[40:50, 10:20] = 0                               # grey 0 inside the window
    (tmp / "L.BI").write_bytes(encode_bi(left))
    return left, right


@pytest.mark.parametrize("idn", [-200, -32768, 32767, -9])
def test_a_wild_idn_reads_off_the_store_as_zero_in_both_kernels(tmp_path, idn):
    from nstar.bitmaps import edge_map_kernel
    make_pair(tmp_path)
    left, right = _zero_patch_pair(tmp_path)
    cmd = encode_ncont(Command(CODE_EDGE_MAP, 1, 12, 44, 0, idn))
    nova = Nova()
    nova.load_pair(left, right)
    compiled = decode_wbmap(nova.execute(cmd)[0].data)
    again = Nova()                                     # the same reply every time
    again.load_pair(left, right)
    assert decode_wbmap(again.execute(cmd)[0].data) == compiled
    assert decode_wbmap(nova.execute(cmd)[0].data) == compiled
    # the plain kernel, on the same frame store
    plain = getattr(edge_map_kernel, "py_func", edge_map_kernel)
    out = np.zeros(16, dtype=np.int64)
    plain(nova.octek.frame, 12 + 26, 44, idn, 26, 26 + 127, 0, 119, out)
    assert compiled[1:] == out.tolist()
    # hand-derived: IXM = IXC + 2*IDN in 16 bits; off the store the six samples
    # read 0, so exactly the grey-0 pixels of the 16x16 window are set
    ixm = ((38 + 2 * idn + 32768) & 65535) - 32768
    ixm = min(38, ixm)
    if ixm < 0 or ixm + 1 >= 320:
        want = [sum(1 << k for k in range(16) if 0 <= 37 + k <= 119
                    and left[37 + k, 12 - 7 + c] == 0) if 0 <= 12 - 7 + c <= 127 else 0
                for c in range(16)]
        assert [w & 0xFFFF for w in compiled[1:]] == want
        assert any(want)


def test_a_wild_idn_gets_the_same_reply_from_nstar_with_and_without_compilation(rig):
    tmp, jh = rig
    _zero_patch_pair(tmp)
    replies = {}
    for tag, extra_env in (("jit", {}), ("plain", {"RIG_NO_JIT": "1"})):
        live = hold_estar_lock(jh)
        e = dict(env(), **extra_env)
        n = nstar(tmp, jh, tag, env=e)
        try:
            got = []
            for idn in (-200, -32768, 32767, -200):
                send_raw(jh, Command(CODE_EDGE_MAP, 1, 12, 44, 0, idn))
                wait_until(lambda: (jh / "WBMAP.DT").exists(), 30, "WBMAP.DT")
                got.append((jh / "WBMAP.DT").read_bytes())
                (jh / "WBMAP.DT").unlink()
            send_raw(jh, Command(CODE_TERMINATE))
            assert finish(n, 30) == 0, output(tmp, tag)
        finally:
            cleanup(n)
            live.close()
        assert got[0] == got[3]                           # the same every time
        replies[tag] = got
    assert replies["jit"] == replies["plain"]


# --- 5. a dangling link under a public name ---------------------------------------------
# Before: not swept at start; the publisher spun at 100 % CPU forever, past --timeout.

def test_a_dangling_ncont_link_is_swept_by_estar_and_its_timeout_holds(rig):
    tmp, jh = rig
    os.symlink(tmp / "nowhere", jh / "NCONT.DT")
    done = run_estar(jh, "--line", "45", "--timeout", "1", timeout=60)
    assert done.returncode == 1
    assert f"Found NCONT.DT from an earlier run; moved it to {jh / 'STALE'}" in done.stdout
    assert "no SLICE.DT from NSTAR after 1 s" in one_line(done.stderr) or \
        "NCONT.DT not taken by NSTAR after 1 s" in one_line(done.stderr)


def test_a_dangling_wbmap_link_makes_nstar_report_after_its_timeout_and_keep_serving(rig):
    tmp, jh = rig
    live = hold_estar_lock(jh)
    n = nstar(tmp, jh, "nstar", "--timeout", "1")
    try:
        nstar_ready(tmp, "nstar")
        os.symlink(tmp / "nowhere", jh / "WBMAP.DT")
        send_raw(jh, Command(CODE_EDGE_MAP, 1, 30, 45, 0, 1))
        wait_until(lambda: "Waiting for the next command" in output(tmp, "nstar")[1], 20,
                   "NSTAR's report")
        assert output(tmp, "nstar")[1].startswith("nstar: WBMAP.DT not taken by ESTAR after 1 s")
        send_raw(jh, Command(CODE_SLICE, 1, 0, 45, 128, 0))           # still serving
        wait_until(lambda: (jh / "SLICE.DT").exists(), 20, "the slice")
    finally:
        cleanup(n)
        live.close()


# --- 6. FIFOs as protocol files ---------------------------------------------------------
# Before: the reader blocked in open() forever, past --timeout.

def _fifo_reply(jh):
    def damage(data):
        os.mkfifo(jh / "FIFO.TMP")
        os.rename(jh / "FIFO.TMP", jh / "SLICE.DT")
        return None
    return damage


def test_a_fifo_as_slice_is_refused_by_estar_not_waited_on(rig):
    tmp, jh = rig
    rc, err, _ = damaged_run(tmp, jh, "SLICE.DT", _fifo_reply(jh))
    kept = jh / "STALE" / "SLICE.DT.bad.0"
    assert rc == 1
    assert one_line(err) == (f"estar: {jh / 'SLICE.DT'}: not a regular file (a FIFO); "
                             f"kept as {kept}")
    assert stat.S_ISFIFO(os.lstat(kept).st_mode)


def test_a_fifo_as_ncont_is_set_aside_and_nstar_keeps_serving(rig):
    tmp, jh = rig
    live = hold_estar_lock(jh)
    n = nstar(tmp, jh, "nstar")
    try:
        nstar_ready(tmp, "nstar")
        os.mkfifo(jh / "FIFO.TMP")
        os.rename(jh / "FIFO.TMP", jh / "NCONT.DT")
        send_raw(jh, Command(CODE_SLICE, 1, 0, 45, 128, 0))
        wait_until(lambda: (jh / "SLICE.DT").exists(), 20, "the slice after the FIFO")
        err = output(tmp, "nstar")[1]
        assert err.startswith(f"nstar: {jh / 'NCONT.DT'}: not a regular file (a FIFO) — not a "
                              f"command file; moved it to {jh / 'STALE' / 'NCONT.DT'}")
    finally:
        cleanup(n)
        live.close()


# --- 7. a stale NCONT.DT at NSTAR start ---------------------------------------------------
# Before: a terminate left by a dead `estar --terminate` made the next NSTAR quit
# at once (the following ESTAR timed out); a damaged one stopped it.

@pytest.mark.parametrize("left_behind", [encode_ncont(Command(CODE_TERMINATE)), b"\x00\x02\x00"])
def test_a_command_nobody_waits_for_is_set_aside_at_nstar_start(rig, left_behind):
    tmp, jh = rig
    (jh / "NCONT.DT").write_bytes(left_behind)
    n = e = None
    try:
        n = nstar(tmp, jh, "nstar")
        nstar_ready(tmp, "nstar")
        e = estar(tmp, jh, "estar", "--line", "45", "--timeout", "10", "--terminate")
        assert finish(e, 60) == 0, output(tmp, "estar")
        assert finish(n, 30) == 0, output(tmp, "nstar")
    finally:
        cleanup(n, e)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45])
    assert (f"Found NCONT.DT from an earlier run and no ESTAR waiting for it (none holds "
            f"ESTAR.LCK); moved it to {jh / 'STALE' / 'NCONT.DT'}") in output(tmp, "nstar")[0]
    kept = [p for p in (jh / "STALE").iterdir() if p.name.startswith("NCONT.DT")]
    assert [p.read_bytes() for p in kept] == [left_behind]


def test_estar_giving_up_withdraws_its_command(rig):
    """`estar --terminate` with no NSTAR used to leave its terminate behind."""
    tmp, jh = rig
    done = run_estar(jh, "--line", "-1", "--terminate", "--timeout", "1", timeout=60)
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: NCONT.DT not taken by NSTAR after 1 s — is nstar "
                                     f"running on this jhdata directory ({jh})?")
    assert not (jh / "NCONT.DT").exists() and not (jh / "ECONT.DT").exists()
    done = run_estar(jh, "--line", "45", "--timeout", "1", timeout=60)
    assert done.returncode == 1
    assert not (jh / "NCONT.DT").exists() and not (jh / "ECONT.DT").exists()


# --- 8. the lock held twice ----------------------------------------------------------------
# Before: the holder unlinked ESTAR.LCK on exit; two holders overlapped
# thousands of times in a 3-process stress test.

def _contend(directory, seconds, counts):
    from diskfmt.rdos import LockedError
    marker = os.path.join(directory, "HOLDER")
    held = overlaps = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        jh = JHData(directory, me="ESTAR", peer="NSTAR", use_events=False)
        try:
            jh.lock(ESTAR_LOCK)
        except LockedError:
            jh.close()
            continue
        held += 1
        try:
            fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            os.close(fd)
            os.unlink(marker)
        except FileExistsError:
            overlaps += 1
        jh.close()
    counts.put((held, overlaps))


def test_the_estar_lock_is_never_held_by_two_processes(tmp_path):
    ctx = multiprocessing.get_context("fork")
    counts = ctx.Queue()
    procs = [ctx.Process(target=_contend, args=(str(tmp_path), 2.0, counts)) for _ in range(3)]
    for p in procs:
        p.start()
    results = [counts.get(timeout=60) for _ in procs]
    for p in procs:
        p.join(30)
    assert sum(h for h, _ in results) > 100                 # the test did contend
    assert sum(o for _, o in results) == 0


def test_a_lock_file_hard_linked_to_another_file_is_refused_untouched(rig):
    tmp, jh = rig
    victim = tmp / "victim"
    victim.write_bytes(b"precious")
    os.chmod(victim, 0o600)
    os.link(victim, jh / "ESTAR.LCK")
    done = run_estar(jh, "--line", "45", "--timeout", "1")
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: {jh / 'ESTAR.LCK'}: has 2 hard links; a lock "
                                     f"file has one — remove it")
    assert victim.read_bytes() == b"precious"                  # not truncated to a pid
    assert stat.S_IMODE(victim.stat().st_mode) == 0o600        # nor made 0664


# --- 9. a shared, multi-user jhdata/ ---------------------------------------------------------
# Before: lock files were 0644 (another user's program ended in a PermissionError
# traceback).  Another user is played by this root process without its
# permission-override capabilities (setpriv), on files owned by uid 65534.

def _as_other_user():
    if os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to play a second user")
    return ["setpriv", "--bounding-set", "-dac_override,-dac_read_search,-fowner,-chown"]


def test_lock_files_and_stale_are_group_writable_whatever_the_umask(rig):
    tmp, jh = rig
    old = os.umask(0o077)
    try:
        for name in (ESTAR_LOCK, "NSTAR.BSY"):
            j = JHData(jh, me="ESTAR", peer="NSTAR", use_events=False)
            j.lock(name) if name == ESTAR_LOCK else j.open_busy(name)
            j.close()
            assert stat.S_IMODE(os.stat(jh / name).st_mode) == 0o664
        (jh / "NCONT.DT").write_bytes(b"stale")
        j = JHData(jh, me="ESTAR", peer="NSTAR", use_events=False)
        j.set_aside("NCONT.DT")
        j.close()
        assert stat.S_IMODE(os.stat(jh / "STALE").st_mode) == 0o775   # the group's too
    finally:
        os.umask(old)


def test_a_second_user_takes_over_the_first_users_lock_file(rig):
    tmp, jh = rig
    prefix = _as_other_user()
    for name in ("ESTAR.LCK", "NSTAR.LCK", "NSTAR.BSY"):   # left by the first user, 0644
        (jh / name).write_text("4242\n")
        os.chown(jh / name, 65534, 65534)
        os.chmod(jh / name, 0o644)
    n = nstar(tmp, jh, "nstar")
    try:
        done = subprocess.run(prefix + [sys.executable, "-m", "estar.main", "--jhdata",
                                        str(jh), "--separation", "0.75", "--virtual-distance",
                                        "180", "--debug", "0", "--line", "45", "--terminate"],
                              capture_output=True, text=True, env=env(), timeout=120,
                              stdin=subprocess.DEVNULL)
        assert done.returncode == 0, done.stderr
        assert finish(n, 30) == 0
    finally:
        cleanup(n)
    assert (jh / "POSIT.DT").read_bytes() == reference(tmp, [45])


def test_an_unwritable_jhdata_is_one_line_before_any_question(rig):
    tmp, jh = rig
    prefix = _as_other_user()
    os.chown(jh, 65534, 65534)
    os.chmod(jh, 0o755)
    done = subprocess.run(prefix + [sys.executable, "-m", "estar.main", "--jhdata", str(jh)],
                          capture_output=True, text=True, env=env(), timeout=60, input="")
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: jhdata directory {jh} is not writable by this "
                                     f"user (see jhdata/README.md for a shared setup)")
    assert done.stdout == ""                                  # nothing asked


def test_permissions_removed_mid_run_stop_nstar_with_one_line(rig):
    """NSTAR (as a user without the override) takes a command, then cannot
    delete it: before, a traceback killed it and the reply was lost unsaid."""
    tmp, jh = rig
    prefix = _as_other_user()
    live = hold_estar_lock(jh)
    err_file = tmp / "nstar.stderr"
    n = subprocess.Popen(prefix + nstar_command(jh, tmp / "L.BI", tmp / "R.BI",
                                                idle_timeout=60),
                         stdin=subprocess.DEVNULL, stdout=open(tmp / "nstar.stdout", "w"),
                         stderr=open(err_file, "w"), env=env())
    try:
        nstar_ready(tmp, "nstar", 120)                     # its start-up sweep done
        freeze(n)
        send_raw(jh, Command(CODE_SLICE, 1, 0, 45, 128, 0))
        os.chmod(jh, 0o555)                                # permissions removed
        os.kill(n.pid, signal.SIGCONT)
        assert finish(n, 60) == 1
    finally:
        os.chmod(jh, 0o755)
        cleanup(n)
        live.close()
    err = err_file.read_text()
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert lines[0] == (f"nstar: cannot publish SLICE.DT: {jh / 'NDAT.DT'}: Permission denied. "
                        f"This reply is lost.")
    assert lines[-1] == (f"nstar: cannot delete {jh / 'NCONT.DT'} after carrying it out "
                         f"(Permission denied); stopping, as the same command would be "
                         f"carried out again")


# --- 10. inputs without a size or type limit ----------------------------------------------------
# Before: /dev/zero grew until MemoryError; a FIFO blocked nstar, rig and pre;
# a 200 MiB sparse SLICE.DT was read whole and copied non-sparse into STALE/.

@pytest.mark.parametrize("kind", ["dev-zero", "fifo"])
def test_a_picture_that_is_not_a_file_is_one_line_from_nstar_rig_and_pre(tmp_path, kind):
    left, _ = make_pair(tmp_path)
    bad = Path("/dev/zero") if kind == "dev-zero" else tmp_path / "PIPE.BI"
    if kind == "fifo":
        os.mkfifo(bad)
    what = "a character device" if kind == "dev-zero" else "a FIFO"
    jh = tmp_path / "jh"
    jh.mkdir()
    for argv, who in ((nstar_command(jh, left, bad, idle_timeout=None), "nstar"),
                      ([sys.executable, "-m", "rig.main", "scan", "--left", str(left),
                        "--right", str(bad), "--line", "45"], "rig"),
                      ([sys.executable, "-m", "pre", "cartoon", str(bad), "-o",
                        str(tmp_path / "C.BI")], "pre")):
        done = subprocess.run(argv, capture_output=True, text=True, env=env(), timeout=60,
                              stdin=subprocess.DEVNULL)
        assert done.returncode != 0, who
        assert f"{bad}: not a regular file ({what})" in one_line(done.stderr), who
    assert list(jh.iterdir()) == []


def test_a_huge_sparse_slice_is_moved_aside_unread_and_stays_sparse(rig):
    """9.10's "keep at most what the format allows plus a note": the file is
    moved by rename (the same inode: not one byte read, copied or written, so
    nothing beyond the peer's own blocks is kept) and the one line is the note
    (docs/robustness.md, QUIRKS M19)."""
    tmp, jh = rig
    planted = {}

    def huge(data):
        with open(jh / "HUGE.TMP", "wb") as fh:
            fh.truncate(200 << 20)
        planted["ino"] = os.stat(jh / "HUGE.TMP").st_ino
        os.rename(jh / "HUGE.TMP", jh / "SLICE.DT")
        return None

    rc, err, _ = damaged_run(tmp, jh, "SLICE.DT", huge)
    kept = jh / "STALE" / "SLICE.DT.bad.0"
    assert rc == 1
    assert one_line(err) == (f"estar: {jh / 'SLICE.DT'}: 209715200 bytes, expected 1024 or "
                             f"512; kept as {kept}")
    st = os.stat(kept)
    assert st.st_ino == planted["ino"]                                  # moved, not copied
    assert st.st_size == 200 << 20 and st.st_blocks * 512 < 1 << 20     # still sparse
    assert sorted(x.name for x in (jh / "STALE").iterdir()) == ["SLICE.DT.bad.0"]


# --- 11. one line, not a traceback ----------------------------------------------------------------

def test_posit_that_is_a_directory_is_one_line_from_estar(rig):
    tmp, jh = rig
    (jh / "POSIT.DT").mkdir()
    n = nstar(tmp, jh, "nstar")
    try:
        done = run_estar(jh, "--line", "45", "--terminate", "--timeout", "10")
    finally:
        time.sleep(0.5)
        cleanup(n)
    assert done.returncode == 1
    line = one_line(done.stderr)
    assert line.startswith("estar: ") and "POSIT.DT" in line and "directory" in line


def test_slice_that_is_a_directory_is_one_line_from_estar(rig):
    tmp, jh = rig

    def directory(data):
        (jh / "DIR.TMP").mkdir()
        os.rename(jh / "DIR.TMP", jh / "SLICE.DT")
        return None

    rc, err, _ = damaged_run(tmp, jh, "SLICE.DT", directory)
    assert rc == 1
    assert one_line(err) == (f"estar: {jh / 'SLICE.DT'}: not a regular file (a directory); "
                             f"kept as {jh / 'STALE' / 'SLICE.DT.bad.0'}")


def test_listing_that_is_a_directory_is_one_line(rig):
    tmp, jh = rig
    for argv in (["nstar.main", "--left", tmp / "L.BI", "--right", tmp / "R.BI"],
                 ["estar.main", "--separation", "1", "--virtual-distance", "180", "--debug",
                  "0", "--line", "45"]):
        done = subprocess.run([sys.executable, "-m", *map(str, argv), "--jhdata", str(jh),
                               "--listing", str(tmp)], capture_output=True, text=True,
                              env=env(), timeout=60, stdin=subprocess.DEVNULL)
        assert done.returncode == 1
        assert one_line(done.stderr).endswith(f"{tmp}: Is a directory")
        assert list(jh.iterdir()) == []


@pytest.mark.parametrize("name", ["BAD\0NAME.BI", "/no/such/dir/X.BI", "EXISTS"])
def test_a_save_name_that_cannot_be_written_keeps_nstar_serving(rig, name):
    """Code 3's dialogue: "Save the current image?" yes, then a bad name."""
    tmp, jh = rig
    if name == "EXISTS":
        name = str(tmp / "L.BI")
    live = hold_estar_lock(jh)
    p = start_nstar_process(jh, tmp / "L.BI", tmp / "R.BI", idle_timeout=30, text=False,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env())
    try:
        send_raw(jh, Command(3))
        p.stdin.write(b"1\n" + name.encode() + b"\n" + str(tmp / "R2.BI").encode() + b"\n0\n")
        p.stdin.flush()
        send_raw(jh, Command(CODE_SLICE, 1, 0, 45, 128, 0))
        wait_until(lambda: (jh / "SLICE.DT").exists(), 30, "a slice after the dialogue")
        send_raw(jh, Command(CODE_TERMINATE))
        out, err = p.communicate(timeout=30)
    finally:
        cleanup(p)
        live.close()
    assert p.returncode == 0, err
    out = out.decode()
    assert "Traceback" not in err.decode()
    assert "Saved." not in out                        # 13: not after a refusal
    if name.endswith("L.BI"):
        assert f" {name} exists; not overwritten." in out
    else:
        assert " Cannot save the image: " in out and "; not saved." in out


_DISK_FULL = r"""
import json, os, subprocess, sys, time
sys.path.insert(0, sys.argv[2])
from rigtools import env, hold_estar_lock, wait_until
from rig.session import nstar_command
from diskfmt.layouts import Command
tmp = sys.argv[1]
jh = os.path.join(tmp, "full")
os.mkdir(jh)
subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", jh], check=True)
live = hold_estar_lock(__import__("pathlib").Path(jh))
n = subprocess.Popen(nstar_command(jh, os.path.join(tmp, "L.BI"), os.path.join(tmp, "R.BI"),
                                   idle_timeout=60), stdin=subprocess.DEVNULL,
                     stdout=open(os.path.join(tmp, "full.stdout"), "w"), stderr=subprocess.PIPE,
                     text=True, env=env())
wait_until(lambda: "Ready for the ECLIPSE" in open(os.path.join(tmp, "full.stdout")).read(),
           120, "NSTAR to serve")                  # its start-up sweep done
from diskfmt.layouts import encode_ncont
for k, c in enumerate((Command(2, 1, 0, 45, 128, 0), Command(-1))):   # before the disk fills
    with open(os.path.join(jh, f"C{k}.DT"), "wb") as fh:
        fh.write(encode_ncont(c))
    os.link(os.path.join(jh, f"C{k}.DT"), os.path.join(jh, f"KEEP{k}"))  # its DELETE frees nothing
fill = os.open(os.path.join(jh, "FILL"), os.O_WRONLY | os.O_CREAT)     # the disk full
try:
    while True:
        os.write(fill, bytes(4096))
except OSError:
    os.close(fill)
for k in range(2):
    wait_until(lambda: not os.path.lexists(os.path.join(jh, "NCONT.DT")), 20, "NSTAR to take")
    os.rename(os.path.join(jh, f"C{k}.DT"), os.path.join(jh, "NCONT.DT"))
rc = n.wait(timeout=60)
nerr = n.stderr.read()
live.close()
e = subprocess.run([sys.executable, "-m", "estar.main", "--jhdata", jh, "--separation", "0.75",
                    "--virtual-distance", "180", "--debug", "0", "--line", "45", "--timeout", "2"],
                   capture_output=True, text=True, env=env(), stdin=subprocess.DEVNULL, timeout=60)
subprocess.run(["umount", jh])
print(json.dumps({"nstar_rc": rc, "nstar_err": nerr, "estar_rc": e.returncode,
                  "estar_err": e.stderr}))
"""


def test_a_full_disk_is_one_line_and_nstar_keeps_serving(rig):
    """jhdata/ on a 256 KiB file system, filled up (in a private mount namespace)."""
    import json
    tmp, jh = rig
    if os.geteuid() != 0 or shutil.which("unshare") is None:
        pytest.skip("needs root and unshare to mount a small file system")
    probe = subprocess.run(["unshare", "-m", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("no mount namespaces here")
    script = tmp / "full.py"
    script.write_text(_DISK_FULL)
    done = subprocess.run(["unshare", "-m", sys.executable, str(script), str(tmp),
                           str(Path(__file__).parent)], capture_output=True, text=True,
                          env=env(), timeout=240)
    assert done.returncode == 0, done.stderr
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert "Traceback" not in got["nstar_err"] + got["estar_err"]
    full = tmp / "full"
    assert got["nstar_err"].splitlines() == [
        f"nstar: cannot publish SLICE.DT: {full / 'NDAT.DT'}: No space left on device. This "
        f"reply is lost. Waiting for the next command.",          # and it served the next:
        f"nstar: cannot publish TERM.DT: {full / 'TRM.DT'}: No space left on device. This "
        f"reply is lost. Waiting for the next command."]
    assert got["nstar_rc"] == 0
    assert got["estar_rc"] == 1
    assert one_line(got["estar_err"]) == (f"estar: {full / 'ECONT.DT'}: No space left on "
                                          f"device")


# --- 12. REALs outside the Data General range ------------------------------------------------------
# Before: 1e400 failed with an OverflowError traceback after the first line's traffic.

@pytest.mark.parametrize("value", ["1e400", "1e-400"])
def test_a_real_outside_the_dg_range_is_refused_at_input(rig, value):
    tmp, jh = rig
    done = run_estar(jh, "--line", "45", "--terminate", "--timeout", "1", "--separation", value)
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: --separation {value} is outside the Data General "
                                     f"REAL range (about 5.4e-79 to 7.2e75)")
    assert list(jh.iterdir()) == []
    asked = subprocess.run([sys.executable, "-m", "estar.main", "--jhdata", str(jh)],
                           input=f"{value}\n0.75\n180\n0\n-1\n", capture_output=True, text=True,
                           env=env(), timeout=60)
    assert asked.returncode == 0
    assert "is outside the Data General REAL range" in asked.stdout
    assert asked.stdout.count(" Camera seperation = ") == 2


# --- 13. small ---------------------------------------------------------------------------------------

def test_jhdata_that_is_a_file_says_so(tmp_path):
    f = tmp_path / "jhdata"
    f.write_text("")
    done = run_estar(f, "--line", "45")
    assert done.returncode == 1
    assert one_line(done.stderr) == (f"estar: jhdata {f} is not a directory (give --jhdata DIR)")


_READ_ONLY = r"""
import json, os, signal, subprocess, sys, time
sys.path.insert(0, sys.argv[2])
from pathlib import Path
from rigtools import env, freeze, hold_estar_lock, send_raw, wait_until
from rig.session import nstar_command
from diskfmt.layouts import Command


def read_only(d):           # a read-only bind mount over the directory itself
    subprocess.run(["mount", "--bind", str(d), str(d)], check=True)
    subprocess.run(["mount", "-o", "remount,bind,ro", str(d)], check=True)


def run(argv):
    d = subprocess.run(argv, capture_output=True, text=True, env=env(), timeout=120,
                       stdin=subprocess.DEVNULL)
    return {"rc": d.returncode, "out": d.stdout, "err": d.stderr}


tmp = Path(sys.argv[1])
got = {}
# 1. read-only from the start (a lock file left by an earlier run in it)
ro = tmp / "ro"
ro.mkdir()
(ro / "NSTAR.LCK").write_text("")
read_only(ro)
got["nstar"] = run(nstar_command(ro, tmp / "L.BI", tmp / "R.BI", idle_timeout=10))
got["estar"] = run([sys.executable, "-m", "estar.main", "--jhdata", str(ro), "--separation",
                    "0.75", "--virtual-distance", "180", "--debug", "0", "--line", "45"])
got["rig"] = run([sys.executable, "-m", "rig.main", "scan", "--link", "file", "--jhdata",
                  str(ro), "--line", "45"])
# 2. made read-only under a serving NSTAR, a command just found
mid = tmp / "mid"
mid.mkdir()
live = hold_estar_lock(mid)
n = subprocess.Popen(nstar_command(mid, tmp / "L.BI", tmp / "R.BI", idle_timeout=60),
                     stdin=subprocess.DEVNULL, stdout=open(tmp / "mid.stdout", "w"),
                     stderr=subprocess.PIPE, text=True, env=env())
wait_until(lambda: "Ready for the ECLIPSE" in (tmp / "mid.stdout").read_text(), 120,
           "NSTAR to serve")                       # its start-up sweep done
freeze(n)
send_raw(mid, Command(2, 1, 0, 45, 128, 0))
read_only(mid)
os.kill(n.pid, signal.SIGCONT)
got["mid"] = {"rc": n.wait(timeout=60), "err": n.stderr.read(),
              "left": sorted(p.name for p in mid.iterdir())}
live.close()
print(json.dumps(got))
"""


def test_a_read_only_jhdata_is_one_line_from_each_program(rig):
    """jhdata/ on a read-only mount (EROFS, root included), from the start and
    made so under a serving NSTAR (a read-only bind mount in a private mount
    namespace).  Before: "not writable by this user", the wrong cause."""
    import json
    tmp, jh = rig
    if os.geteuid() != 0 or shutil.which("unshare") is None:
        pytest.skip("needs root and unshare to mount")
    if subprocess.run(["unshare", "-m", "true"], capture_output=True).returncode != 0:
        pytest.skip("no mount namespaces here")
    script = tmp / "ro.py"
    script.write_text(_READ_ONLY)
    done = subprocess.run(["unshare", "-m", sys.executable, str(script), str(tmp),
                           str(Path(__file__).parent)], capture_output=True, text=True,
                          env=env(), timeout=400)
    assert done.returncode == 0, done.stderr
    got = json.loads(done.stdout.strip().splitlines()[-1])
    ro, mid = tmp / "ro", tmp / "mid"
    for program in ("nstar", "estar"):
        assert got[program]["rc"] == 1, got[program]
        assert one_line(got[program]["err"]) == (
            f"{program}: jhdata directory {ro} is on a read-only file system (remount it "
            f"read-write, or give --jhdata DIR)")
        assert got[program]["out"] == ""                         # nothing asked first
    assert got["rig"]["rc"] == 1
    assert one_line(got["rig"]["err"]) == (f"rig: --jhdata {ro}: directory is on a read-only "
                                           f"file system")
    assert sorted(p.name for p in ro.iterdir()) == ["NSTAR.LCK"]         # nothing written
    # under a serving NSTAR: the reply cannot be published nor the command deleted
    assert got["mid"]["rc"] == 1
    lines = got["mid"]["err"].strip().splitlines()
    assert "Traceback" not in got["mid"]["err"]
    assert lines == [
        f"nstar: cannot publish SLICE.DT: {mid / 'NDAT.DT'}: Read-only file system. This "
        f"reply is lost.",
        f"nstar: cannot delete {mid / 'NCONT.DT'} after carrying it out (Read-only file "
        f"system); stopping, as the same command would be carried out again"]
    assert got["mid"]["left"] == ["ESTAR.LCK", "NCONT.DT", "NSTAR.BSY", "NSTAR.LCK"]
