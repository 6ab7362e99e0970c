"""Running the rig as 1985 did: ``nstar`` as its own process on a JHDATA
directory, ESTAR speaking to it only through files.

:func:`start_nstar` is the one way this project starts an ``nstar`` process
(rig, bench and tests); :func:`file_link_eclipse` pairs it with an ESTAR in
this process, started by the one start-up protocol
(:func:`estar.link.start_file_link`)."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from pathlib import Path

from estar.link import start_file_link
from estar.masl import Options as MaslOptions
from estar.program import file_link_estar

REPO = Path(__file__).resolve().parent.parent
# Every name a scan's two programs write in jhdata/ but POSIT.DT (the last
# line's result, kept): the temporaries ECONT.DT, NDAT.DT and EDAT.DT (PNPL's,
# between its write and its rename over POSIT.DT) included, and the terminate's
# reply when the end itself was interrupted.
_IN_FLIGHT = ("ECONT.DT", "NCONT.DT", "NDAT.DT", "SLICE.DT", "SL.DT", "WBMAP.DT", "BLOCK.DT",
              "EDAT.DT", "TRM.DT", "TERM.DT")


def tidy_link_files(jhdata: Path) -> None:
    """Delete every protocol file an interrupted scan's two programs may have
    left in ``jhdata`` (both killed, so each is theirs); POSIT.DT stays.  An
    unlink removes a link found there, never what it points to."""
    for name in _IN_FLIGHT:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(Path(jhdata) / name)


def child_env() -> dict:
    """The environment for a child program: this checkout first on the path."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def nstar_command(jhdata: Path, left: Path | None, right: Path | None, *extra: str,
                  debug: int | None = 0, idle_timeout: float | None = 300,
                  quiet: bool = False, starter: bool = False) -> list[str]:
    """The argument list of an ``nstar`` on ``jhdata`` serving the pair;
    ``starter``: it stops when this process has ended (``--starter-pid``)."""
    args = [sys.executable, "-m", "nstar.main", "--jhdata", str(jhdata)]
    if debug is not None:
        args += ["--debug", str(debug)]
    if left is not None:
        args += ["--left", str(left), "--right", str(right)]
    if idle_timeout is not None:
        args += ["--idle-timeout", f"{idle_timeout:g}"]
    if quiet:
        args.append("--quiet")
    if starter:
        args += ["--starter-pid", str(os.getpid())]
    return args + [str(a) for a in extra]


def start_nstar(jhdata: Path, left: Path | None, right: Path | None, *extra: str,
                debug: int | None = 0, idle_timeout: float | None = 300, quiet: bool = False,
                stdin=subprocess.DEVNULL, stdout=None, stderr=None, text: bool = True,
                env: dict | None = None, own_session: bool = False) -> subprocess.Popen:
    """Start an ``nstar`` process (the one constructor: rig, bench and tests).
    Its console goes to ``stdout``/``stderr`` (inherited when None).
    ``own_session``: a session (process group) of its own, which a Ctrl-C at
    the terminal does not reach — for an NSTAR its starter stops itself.
    It also stops within a second once this process has ended, however it
    ended (``--starter-pid``)."""
    if env is None:
        env = child_env()
        env.pop("JHDATA", None)        # --jhdata names the directory, always
    return subprocess.Popen(nstar_command(jhdata, left, right, *extra, debug=debug,
                                          idle_timeout=idle_timeout, quiet=quiet,
                                          starter=True),
                            stdin=stdin, stdout=stdout, stderr=stderr, text=text, env=env,
                            start_new_session=own_session)


def stop_process(proc: subprocess.Popen, grace: float = 10.0) -> None:
    """Wait up to ``grace`` seconds for ``proc`` to end, then kill it."""
    if proc.poll() is None:
        try:
            proc.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@contextlib.contextmanager
def nstar_process(jhdata: Path, left: Path, right: Path, *extra: str, quiet: bool = True,
                  grace: float = 10.0):
    """An ``nstar`` on the pair for a ``with`` block; on exit it is given
    ``grace`` seconds to end (after a terminate command), then killed."""
    jhdata.mkdir(parents=True, exist_ok=True)
    proc = start_nstar(jhdata, left, right, *extra, quiet=quiet)
    try:
        yield proc
    finally:
        stop_process(proc, grace)


@contextlib.contextmanager
def file_link_eclipse(jhdata: Path, left: Path, right: Path, ds: str = "0.75",
                      dv: str = "180", options: MaslOptions | None = None,
                      timeout: float = 30.0, say=None, matcher=None):
    """An ESTAR in this process and an NSTAR process, talking through ``jhdata``;
    NSTAR is told to terminate at the end (killed at once when the block ends
    with an exception: an interrupted scan must not wait).  The Ctrl-C is
    ours alone: NSTAR runs in a session of its own, or it would get the
    terminal's SIGINT too and race us to the console with its own
    "nstar: interrupted" (or a traceback, when it came during its start)."""
    jhdata.mkdir(parents=True, exist_ok=True)
    link = start_file_link(jhdata, timeout=timeout, say=say)
    try:
        proc = start_nstar(jhdata, left, right, quiet=True, own_session=True)
        ok = ended = False
        try:
            ecl = file_link_estar(link, ds, dv, options=options, matcher=matcher)
            yield ecl
            ok = True
        finally:
            try:
                if ok and proc.poll() is None:
                    ecl.terminate()
                    stop_process(proc)
                    ended = True
            finally:                       # interrupted or failed (the terminate too):
                if not ended:                  # stop now, and tidy the directory (every
                    if proc.poll() is None:    # protocol file in it is ours or our NSTAR's)
                        proc.kill()
                    proc.wait()
                    tidy_link_files(jhdata)
    finally:
        link.close()


@contextlib.contextmanager
def rig_jhdata(given: str | Path | None):
    """The jhdata/ a ``rig`` command runs its own NSTAR on: a private temporary
    directory, removed afterwards, unless one is ``given`` — and
    then only if no NSTAR runs there already: rig never talks to an NSTAR it
    did not start."""
    import shutil
    import tempfile
    from diskfmt.rdos import JHData, LockedError, NSTAR_LOCK
    if given is None:
        d = Path(tempfile.mkdtemp(prefix="rig-jhdata-"))
        try:
            yield d
        finally:
            shutil.rmtree(d, ignore_errors=True)
        return
    d = Path(given)
    d.mkdir(parents=True, exist_ok=True)
    probe = JHData(d, me="rig", peer="NSTAR", use_events=False)
    try:
        if probe.held(NSTAR_LOCK):
            raise LockedError(f"an nstar is already running on {d}; rig starts its own "
                              f"NSTAR — stop that one, or leave out --jhdata (rig then uses "
                              f"a private temporary directory)")
    finally:
        probe.close()
    yield d
