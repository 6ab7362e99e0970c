"""Running the rig as 1985 did: ``nstar`` as its own process on a JHDATA
directory, ESTAR speaking to it only through files."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from pathlib import Path

from diskfmt.dgreal import Real
from diskfmt.rdos import JHData
from estar.link import FileLink, ESTAR_STALE
from estar.masl import Options as MaslOptions
from estar.program import Eclipse

REPO = Path(__file__).resolve().parent.parent


def child_env() -> dict:
    """The environment for a child program: this checkout first on the path."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


@contextlib.contextmanager
def nstar_process(jhdata: Path, left: Path, right: Path, *extra: str, quiet: bool = True):
    """Start ``nstar`` on the pair; stop it (terminate command, then kill) on exit."""
    jhdata.mkdir(parents=True, exist_ok=True)
    args = [sys.executable, "-m", "nstar.main", "--jhdata", str(jhdata), "--debug", "0",
            "--left", str(left), "--right", str(right), "--idle-timeout", "300", *extra]
    if quiet:
        args.append("--quiet")
    proc = subprocess.Popen(args, env=child_env(), stdin=subprocess.DEVNULL)
    try:
        yield proc
    finally:
        if proc.poll() is None:
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


@contextlib.contextmanager
def file_link_eclipse(jhdata: Path, left: Path, right: Path, ds: str = "0.75",
                      dv: str = "180", options: MaslOptions | None = None,
                      timeout: float = 30.0, say=None):
    """An ESTAR in this process and an NSTAR process, talking through ``jhdata``;
    NSTAR is told to terminate at the end."""
    jhdata.mkdir(parents=True, exist_ok=True)
    jh = JHData(jhdata, me="ESTAR", peer="NSTAR", timeout=timeout)
    try:
        jh.lock("ESTAR.LCK")
        for name in ESTAR_STALE:
            where = jh.set_aside(name, "stale")
            if where and say:
                say(f" Found {name} from an earlier run; moved it to {where}")

        def publish(data: bytes) -> None:
            jh.path("EDAT.DT").write_bytes(data)
            jh.rename("EDAT.DT", "POSIT.DT")

        with nstar_process(jhdata, left, right) as proc:
            ecl = Eclipse(FileLink(jh), Real.const(ds), Real.const(dv), options=options,
                          publish=publish)
            try:
                yield ecl
            finally:
                if proc.poll() is None:
                    ecl.terminate()
    finally:
        jh.close()
