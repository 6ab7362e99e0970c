"""RDOS semantics of the shared directory: publish by rename, never over an
unread file; waits that end in a message naming the file and the program."""

import os
import threading
import time

import pytest

from diskfmt import rdos
from diskfmt.rdos import JHData, LinkTimeout, LockedError


def test_rename_noreplace_refuses_an_existing_target(tmp_path):
    (tmp_path / "NDAT.DT").write_bytes(b"new")
    (tmp_path / "SLICE.DT").write_bytes(b"unread")
    with pytest.raises(FileExistsError):
        rdos._rename_noreplace(tmp_path / "NDAT.DT", tmp_path / "SLICE.DT")
    assert (tmp_path / "SLICE.DT").read_bytes() == b"unread"
    (tmp_path / "SLICE.DT").unlink()
    rdos._rename_noreplace(tmp_path / "NDAT.DT", tmp_path / "SLICE.DT")
    assert (tmp_path / "SLICE.DT").read_bytes() == b"new"
    assert not (tmp_path / "NDAT.DT").exists()


@pytest.mark.parametrize("use_events", [True, False])
def test_publish_waits_until_the_unread_file_is_taken(tmp_path, use_events):
    jh = JHData(tmp_path, me="NSTAR", peer="ESTAR", timeout=10, use_events=use_events)
    (tmp_path / "SLICE.DT").write_bytes(b"first")
    taken = []

    def reader():
        time.sleep(0.3)
        taken.append((tmp_path / "SLICE.DT").read_bytes())
        (tmp_path / "SLICE.DT").unlink()

    t = threading.Thread(target=reader)
    t.start()
    jh.publish("NDAT.DT", "SLICE.DT", b"second")
    t.join()
    jh.close()
    assert taken == [b"first"]                    # the unread file was never replaced
    assert (tmp_path / "SLICE.DT").read_bytes() == b"second"
    assert not (tmp_path / "NDAT.DT").exists()


def test_wait_for_times_out_naming_the_file_and_the_program(tmp_path):
    jh = JHData(tmp_path, me="ESTAR", peer="NSTAR", timeout=0.2)
    with pytest.raises(LinkTimeout) as exc:
        jh.wait_for("WBMAP.DT")
    jh.close()
    assert str(exc.value) == (f"no WBMAP.DT from NSTAR after 0.2 s — is nstar running on "
                              f"this jhdata directory ({tmp_path})?")


def test_wait_for_wakes_on_the_file_event(tmp_path):
    jh = JHData(tmp_path, me="ESTAR", peer="NSTAR", timeout=120)
    threading.Timer(0.2, lambda: (tmp_path / "SLICE.DT").write_bytes(b"x")).start()
    t0 = time.monotonic()
    jh.wait_for("SLICE.DT")
    jh.close()
    # woken by the file, long before its timeout (the margin: a loaded machine)
    assert (tmp_path / "SLICE.DT").exists() and time.monotonic() - t0 < 60


def test_lock_refuses_a_second_holder_and_is_released_on_close(tmp_path):
    a = JHData(tmp_path, me="ESTAR", peer="NSTAR")
    b = JHData(tmp_path, me="ESTAR", peer="NSTAR")
    a.lock("ESTAR.LCK")
    with pytest.raises(LockedError, match="another ESTAR is already running"):
        b.lock("ESTAR.LCK")
    assert b.held("ESTAR.LCK")
    a.close()
    assert not b.held("ESTAR.LCK")                # released; the file is kept
    assert (tmp_path / "ESTAR.LCK").is_file()
    b.lock("ESTAR.LCK")
    b.close()


def test_lock_waits_out_a_peers_momentary_probe(tmp_path):
    """A peer asking held() takes a shared lock for an instant; a process
    starting just then must not take it for a holder (a starting NSTAR gave up
    "already running" while the test's watcher polled held())."""
    import fcntl
    a = JHData(tmp_path, me="NSTAR", peer="ESTAR")
    (tmp_path / "NSTAR.LCK").write_bytes(b"")
    probe = os.open(tmp_path / "NSTAR.LCK", os.O_RDONLY)
    fcntl.flock(probe, fcntl.LOCK_SH | fcntl.LOCK_NB)        # a probe caught mid-way
    threading.Timer(0.05, lambda: os.close(probe)).start()   # ... and let go
    a.lock("NSTAR.LCK")                                      # before the fix: LockedError
    b = JHData(tmp_path, me="NSTAR", peer="ESTAR")
    assert b.held("NSTAR.LCK")
    with pytest.raises(LockedError, match="another NSTAR is already running"):
        b.lock("NSTAR.LCK")                                  # a real holder still refuses
    a.close()
    b.close()


def test_missing_directory_is_one_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        JHData(tmp_path / "nope", me="ESTAR", peer="NSTAR")


needs_inotify = pytest.mark.skipif(rdos.inotify_init is None, reason="inotify (Linux) only")


@needs_inotify
@pytest.mark.skipif(rdos._RENAMEAT2 is None, reason="publishes by link(2) here: IN_CREATE armed")
def test_a_wait_for_a_name_is_woken_by_its_rename_not_by_temporaries(tmp_path):
    w = rdos._InotifyWaiter(tmp_path)
    try:
        w.arm(w.APPEAR)
        (tmp_path / "NDAT.DT").write_bytes(b"reply")     # the peer's temporary
        (tmp_path / "SL.DT").write_bytes(b"x")
        (tmp_path / "SL.DT").unlink()                     # a take
        assert not w.poller.poll(0)                       # none of it wakes
        os.rename(tmp_path / "NDAT.DT", tmp_path / "WBMAP.DT")
        assert w.poller.poll(5000)
        w.arm(w.GONE)                                     # queued events dropped
        assert not w.poller.poll(0)
        (tmp_path / "ECONT.DT").write_bytes(b"cmd")
        assert not w.poller.poll(0)                       # a gone-wait: no new file wakes
        (tmp_path / "WBMAP.DT").unlink()
        assert w.poller.poll(5000)
    finally:
        w.close()


@needs_inotify
def test_the_earlier_wait_wakes_on_any_event(tmp_path):
    w = rdos._InotifyWaiter(tmp_path, named=False)
    try:
        w.arm(w.APPEAR)
        (tmp_path / "NDAT.DT").write_bytes(b"reply")
        assert w.poller.poll(5000)
    finally:
        w.close()


def test_a_name_made_without_a_rename_is_still_seen_by_the_poll(tmp_path):
    # A hand-made NCONT.DT (written in place, or linked) wakes no named wait;
    # the poll backstop finds it.
    jh = JHData(tmp_path, me="NSTAR", peer="ESTAR", timeout=10)
    t = threading.Timer(0.1, lambda: (tmp_path / "NCONT.DT").write_bytes(b"x" * 12))
    t.start()
    try:
        jh.wait_for("NCONT.DT")
        assert (tmp_path / "NCONT.DT").exists()
    finally:
        t.join()
        jh.close()


def test_publish_written_renames_what_write_temp_wrote_once_the_name_is_free(tmp_path):
    jh = JHData(tmp_path, me="ESTAR", peer="NSTAR", timeout=10)
    (tmp_path / "NCONT.DT").write_bytes(b"old command")
    jh.write_temp("ECONT.DT", b"new command")
    t = threading.Timer(0.2, (tmp_path / "NCONT.DT").unlink)
    t.start()
    try:
        jh.publish_written("ECONT.DT", "NCONT.DT")
    finally:
        t.join()
        jh.close()
    assert (tmp_path / "NCONT.DT").read_bytes() == b"new command"
    assert not (tmp_path / "ECONT.DT").exists()
    with pytest.raises(LinkTimeout, match="NCONT.DT not taken by NSTAR after 0.2 s"):
        jh2 = JHData(tmp_path, me="ESTAR", peer="NSTAR", timeout=10)
        try:
            jh2.publish("ECONT.DT", "NCONT.DT", b"third", timeout=0.2)
        finally:
            jh2.close()
    assert (tmp_path / "NCONT.DT").read_bytes() == b"new command"   # never replaced
