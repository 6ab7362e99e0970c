"""rig.session: an nstar it starts stops once its starter has ended, however
it ended (``nstar --starter-pid``, beyond 1985)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from diskfmt.rdos import JHData, LinkTimeout, NSTAR_LOCK
from nstar.main import Abort, wait_for_command
from rig.session import nstar_command
from rigtools import REPO, env, make_pair, wait_until


def _jh(tmp_path: Path) -> JHData:
    d = tmp_path / "jhdata"
    d.mkdir()
    return JHData(d, me="NSTAR", peer="ESTAR", timeout=5)


def test_the_wait_for_a_command_ends_when_its_starter_is_not_its_parent(tmp_path):
    with pytest.raises(Abort, match=r"pid 1234567\) has ended"):
        wait_for_command(_jh(tmp_path), None, 1234567)


def test_the_wait_for_a_command_keeps_its_idle_timeout_while_the_starter_runs(tmp_path):
    jh = _jh(tmp_path)
    with pytest.raises(LinkTimeout, match="no NCONT.DT from ESTAR after 0.3 s"):
        wait_for_command(jh, 0.3, os.getppid())


def test_the_wait_for_a_command_takes_the_command_while_the_starter_runs(tmp_path):
    jh = _jh(tmp_path)
    (jh.dir / "NCONT.DT").write_bytes(bytes(12))
    wait_for_command(jh, 5, os.getppid())          # returns: the file is there


def test_only_the_project_s_own_starts_pass_the_starter():
    plain = nstar_command(Path("jh"), None, None)
    assert "--starter-pid" not in plain            # a user's nstar waits on, as in 1985
    own = nstar_command(Path("jh"), None, None, starter=True)
    assert own[own.index("--starter-pid") + 1] == str(os.getpid())


def _ended(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return True
    return state in ("Z", "X")                     # a zombie nobody reaps has ended too


@pytest.mark.processes
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")
def test_an_nstar_stops_soon_after_its_starter_is_killed(tmp_path):
    left, right = make_pair(tmp_path)
    jh = tmp_path / "jhdata"
    err = tmp_path / "nstar.stderr"
    starter = subprocess.Popen(
        [sys.executable, "-c", f"""
import subprocess, sys, time
from pathlib import Path
sys.path.insert(0, {str(REPO)!r})
from rig.session import start_nstar
Path({str(jh)!r}).mkdir()
p = start_nstar(Path({str(jh)!r}), Path({str(left)!r}), Path({str(right)!r}), quiet=True,
                idle_timeout=300, stdout=subprocess.DEVNULL, stderr=open({str(err)!r}, "w"))
print(p.pid, flush=True)
time.sleep(600)
"""], stdout=subprocess.PIPE, text=True, env=env())
    try:
        pid = int(starter.stdout.readline())
        watcher = JHData(jh, me="ESTAR", peer="NSTAR", timeout=5)
        wait_until(lambda: watcher.held(NSTAR_LOCK), timeout=60, what="nstar holding its lock")
        starter.kill()                             # no terminate command can be sent
        starter.wait()
        # far inside the 300 s idle timeout it would otherwise wait out
        wait_until(lambda: _ended(pid), timeout=60, what="the orphaned nstar ending")
    finally:
        starter.kill()
        starter.wait()
    assert "has ended; stopping" in err.read_text()
