"""Helpers for tests that run the rig: a small synthetic stereo pair with known
disparities, and the nstar/estar programs as real processes."""

import subprocess
import sys
from pathlib import Path

import numpy as np

from diskfmt.layouts import encode_bi
from rig.session import child_env

REPO = Path(__file__).resolve().parent.parent

# (left x of the box in the right picture, width, grey, disparity in pixels):
# the left picture shows each box `disparity` pixels further right.
BOXES = [(20, 15, 2, 10), (50, 20, 13, 6), (90, 12, 4, 3)]
BACKGROUND = 8


def make_pair(directory: Path) -> tuple[Path, Path]:
    """Write L.BI and R.BI: three flat boxes (rows 30..89) on a flat background."""
    left = np.full((120, 128), BACKGROUND, np.uint8)
    right = left.copy()
    for x0, w, g, d in BOXES:
        left[30:90, x0 + d:x0 + d + w] = g
        right[30:90, x0:x0 + w] = g
    lp, rp = directory / "L.BI", directory / "R.BI"
    lp.write_bytes(encode_bi(left))
    rp.write_bytes(encode_bi(right))
    return lp, rp


def env() -> dict:
    """The child environment of rig.session, without a JHDATA that could
    point the programs away from the test's directory."""
    e = child_env()
    e.pop("JHDATA", None)
    return e


def start_nstar(jhdata: Path, left: Path, right: Path, *extra) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "nstar.main", "--jhdata", str(jhdata), "--debug", "0",
         "--left", str(left), "--right", str(right), "--idle-timeout", "60", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env(),
        stdin=subprocess.DEVNULL)


def run_estar(jhdata: Path, *extra, timeout=120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "estar.main", "--jhdata", str(jhdata), "--separation", "0.75",
         "--virtual-distance", "180", "--debug", "0", *extra],
        capture_output=True, text=True, env=env(), timeout=timeout, stdin=subprocess.DEVNULL)


def hold_estar_lock(jhdata: Path):
    """Play a live ESTAR's part in the protocol: hold ESTAR.LCK (NSTAR obeys a
    command found at its start only while an ESTAR holds it, issue 9.7).
    ``.close()`` the result to die."""
    from diskfmt.rdos import JHData, ESTAR_LOCK
    jh = JHData(jhdata, me="ESTAR", peer="NSTAR", use_events=False)
    jh.lock(ESTAR_LOCK)
    return jh
