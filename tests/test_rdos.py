"""RDOS semantics of the shared directory: publish by rename, never over an
unread file; waits that end in a message naming the file and the program."""

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


def test_missing_directory_is_one_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        JHData(tmp_path / "nope", me="ESTAR", peer="NSTAR")
