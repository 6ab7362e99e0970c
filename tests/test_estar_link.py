"""ESTAR's file link (estar/link.py): the edge-map requests of a line sent
ahead — request k+1 published the moment reply k appears — carry the same
bytes in the same order as one NBLOB at a time, give the same maps, and
never put two commands in flight (WBMAP.DT carries no request tag, M14).
Checked against the kernel's own record of the directory (inotify) and
against the in-process rig."""

import os
import select
import struct
import subprocess

import numpy as np
import pytest

from diskfmt.layouts import decode_bi
from diskfmt.rdos import JHData, link_wait
from estar.link import FileLink, start_file_link
from estar.program import file_link_estar, in_process_rig
from rig.scene import bundled_path
from rig.session import child_env, start_nstar, stop_process

from watchdog.observers.inotify_c import inotify_init, inotify_add_watch, InotifyConstants as C

LINE = 60


class Journal:
    """Every rename into, and delete from, a directory, in the kernel's order."""

    def __init__(self, directory):
        self.fd = inotify_init()
        inotify_add_watch(self.fd, os.fsencode(directory),
                          C.IN_MOVED_TO | C.IN_DELETE | C.IN_CREATE)
        self.events: list[tuple[str, str]] = []

    def read(self):
        poller = select.poll()
        poller.register(self.fd, select.POLLIN)
        while poller.poll(200):
            buf = os.read(self.fd, 1 << 16)
            off = 0
            while off < len(buf):
                _, mask, _, length = struct.unpack_from("iIII", buf, off)
                name = buf[off + 16:off + 16 + length].rstrip(b"\0").decode()
                kind = ("in" if mask & C.IN_MOVED_TO else "gone" if mask & C.IN_DELETE
                        else "made")
                self.events.append((kind, name))
                off += 16 + length
        os.close(self.fd)
        return self.events


def run_line(tmp_path, wake):
    """One line over the file link (a real nstar process, both sides waiting
    the ``wake`` way): its LineResult and the directory's journal."""
    jh = tmp_path / "jhdata"
    jh.mkdir()
    link = start_file_link(jh, timeout=30, wake=wake)
    env = child_env()
    env.pop("JHDATA", None)
    env["RIG_LINK_WAIT"] = wake
    proc = start_nstar(jh, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"), quiet=True,
                       idle_timeout=60, env=env)
    try:
        ecl = file_link_estar(link)
        journal = Journal(jh)
        result = ecl.lcln(LINE)
        events = journal.read()
        ecl.terminate()
        stop_process(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        link.close()
    return result, events


@pytest.mark.processes
@pytest.mark.parametrize("wake", ["named", "any"])
def test_file_link_line_equals_the_in_process_rig_and_keeps_one_command_in_flight(
        tmp_path, wake):
    result, events = run_line(tmp_path, wake)
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    direct = in_process_rig(left, right).lcln(LINE)
    assert result.requests == direct.requests > 20
    assert result.posit == direct.posit
    assert np.array_equal(result.maps1, direct.maps1)
    assert np.array_equal(result.maps2, direct.maps2)
    # The kernel's order of the public names: command in, command taken, reply
    # in, reply taken.  Never a second command before the reply to the first.
    public = [(k, n) for k, n in events if n in ("NCONT.DT", "WBMAP.DT") and k != "made"]
    commands = [i for i, e in enumerate(public) if e == ("in", "NCONT.DT")]
    assert len(commands) == 2 + result.requests       # CFEAT's two slices first
    commands = commands[2:]
    replies = [i for i, e in enumerate(public) if e == ("in", "WBMAP.DT")]
    assert len(replies) == result.requests
    for a, b in zip(commands, commands[1:]):
        between = public[a + 1:b]
        assert ("gone", "NCONT.DT") in between and ("in", "WBMAP.DT") in between
    # Sent ahead (the default): each next command is in before the last
    # reply is taken; one at a time (RIG_LINK_WAIT=any): after.
    ahead = 0
    for r, c in zip(replies, commands[1:]):
        taken = public.index(("gone", "WBMAP.DT"), r)
        ahead += c < taken
    assert ahead == (result.requests - 1 if wake == "named" else 0)


def test_link_wait_is_named_unless_any_is_asked_for(monkeypatch, tmp_path):
    monkeypatch.delenv("RIG_LINK_WAIT", raising=False)
    assert link_wait() == "named"
    monkeypatch.setenv("RIG_LINK_WAIT", "any")
    assert link_wait() == "any"
    jh = JHData(tmp_path, me="ESTAR", peer="NSTAR")
    try:
        assert jh.wake == "any" and not FileLink(jh).pipeline
    finally:
        jh.close()
    monkeypatch.setenv("RIG_LINK_WAIT", "sometimes")
    with pytest.raises(OSError) as err:
        link_wait()
    assert str(err.value) == "RIG_LINK_WAIT='sometimes': expected one of named, any"


@pytest.mark.processes
def test_a_bad_link_wait_is_one_line_from_nstar(tmp_path):
    env = child_env()
    env["RIG_LINK_WAIT"] = "sometimes"
    proc = start_nstar(tmp_path, None, None, quiet=True, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, env=env)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1
    assert err == "nstar: RIG_LINK_WAIT='sometimes': expected one of named, any\n"
