"""The one set of helpers for tests that run the rig: a small synthetic stereo
pair with known disparities, the in-process reference, ``nstar``/``estar`` as
real processes (through :func:`rig.session.start_nstar`, the project's one way
to start an nstar), waiting until something holds, and playing a peer's part
in the JHDATA protocol.  Fixtures built on them are in conftest.py."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

from diskfmt.layouts import decode_bi, encode_bi, encode_ncont, decode_ncont, Command, FormatError
from diskfmt.rdos import JHData, LinkTimeout, ESTAR_LOCK
from estar.program import in_process_rig
from nstar.program import Nova
from planner.loop import DriveConfig
from rig.session import child_env, start_nstar as _start_nstar

REPO = Path(__file__).resolve().parent.parent

# (left x of the box in the right picture, width, grey, disparity in pixels):
# the left picture shows each box `disparity` pixels further right.
BOXES = [(20, 15, 2, 10), (50, 20, 13, 6), (90, 12, 4, 3)]
BACKGROUND = 8
# lines crossing the boxes, each with edge maps to ask for: enough round trips
# for a poll to catch a given moment
BOX_LINES = [str(y) for y in range(30, 90, 3)]


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


def ctrl_c_default() -> None:
    """``preexec_fn`` for a child a test sends a Ctrl-C: the default SIGINT, as
    at a terminal — a suite started with SIGINT ignored (nohup, ``cmd &`` in a
    script) would hand its children an ignored SIGINT, and the Ctrl-C would
    never come."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def wait_until(cond, timeout=15.0, what="condition"):
    deadline = time.monotonic() + timeout
    while not cond():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.002)


# --- the programs as processes, console through pipes ------------------------------

def start_nstar(jhdata: Path, left: Path, right: Path, *extra) -> subprocess.Popen:
    return _start_nstar(jhdata, left, right, *extra, idle_timeout=60,
                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env())


def run_estar(jhdata: Path, *extra, timeout=120, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "estar.main", "--jhdata", str(jhdata), "--separation", "0.75",
         "--virtual-distance", "180", "--debug", "0", *map(str, extra)],
        capture_output=True, text=True, env=env(), timeout=timeout, stdin=subprocess.DEVNULL,
        **kw)


# --- the programs as processes, console into files ---------------------------------

def spawn(module: str, out: Path, *args, **kw) -> subprocess.Popen:
    """A program as a real process; its console goes to ``out``.stdout/.stderr
    files (a pipe nobody reads could block it)."""
    return subprocess.Popen([sys.executable, "-m", module, *map(str, args)],
                            stdout=open(f"{out}.stdout", "w"), stderr=open(f"{out}.stderr", "w"),
                            stdin=subprocess.DEVNULL, env=env(), text=True, **kw)


def nstar(tmp: Path, jh: Path, tag: str, *extra, **kw) -> subprocess.Popen:
    kw.setdefault("env", env())
    return _start_nstar(jh, tmp / "L.BI", tmp / "R.BI", *map(str, extra), idle_timeout=60,
                        stdout=open(tmp / f"{tag}.stdout", "w"),
                        stderr=open(tmp / f"{tag}.stderr", "w"), **kw)


def estar(tmp: Path, jh: Path, tag: str, *extra, **kw) -> subprocess.Popen:
    return spawn("estar.main", tmp / tag, "--jhdata", jh, "--separation", "0.75",
                 "--virtual-distance", "180", "--debug", "0", *extra, **kw)


def output(tmp: Path, tag: str) -> tuple[str, str]:
    return ((tmp / f"{tag}.stdout").read_text(), (tmp / f"{tag}.stderr").read_text())


def nstar_ready(tmp: Path, tag: str, timeout=60.0) -> None:
    """Wait until the nstar started as ``tag`` serves (its start-up sweep done)."""
    wait_until(lambda: "Ready for the ECLIPSE" in output(tmp, tag)[0], timeout,
               f"{tag} to serve")


def finish(p: subprocess.Popen, timeout=120) -> int:
    """``p``'s exit code; the timeout is a hang detector (a loaded machine can
    take many seconds to start a program), not a speed limit."""
    return p.wait(timeout=timeout)


def cleanup(*procs) -> None:
    for p in procs:
        if p is not None and p.poll() is None:
            p.kill()                      # SIGKILL also ends a stopped process
            p.wait(timeout=10)


def stopped(pid: int) -> bool:
    with open(f"/proc/{pid}/stat") as fh:
        return fh.read().rsplit(")", 1)[1].split()[0] in "tT"


def freeze(p: subprocess.Popen) -> None:
    os.kill(p.pid, signal.SIGSTOP)
    wait_until(lambda: stopped(p.pid), 5, "SIGSTOP to take effect")


def freeze_when(p: subprocess.Popen, cond, timeout=120.0, recheck=True) -> None:
    """Stop ``p`` at a moment when ``cond()`` holds (with ``recheck``, checked
    again while it is stopped, so the state cannot move on under us)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            freeze(p)
            if not recheck or cond():
                return
            os.kill(p.pid, signal.SIGCONT)
        time.sleep(0.0005)
    raise AssertionError("the wanted moment never came")


# --- the reference and the protocol by hand ----------------------------------------

def load_pair(tmp: Path):
    return decode_bi((tmp / "L.BI").read_bytes()), decode_bi((tmp / "R.BI").read_bytes())


def reference(tmp: Path, lines) -> bytes:
    """POSIT.DT of one clean ESTAR run over ``lines`` (the in-process rig)."""
    ecl = in_process_rig(*load_pair(tmp))
    return [ecl.lcln(int(y)) for y in lines][-1].posit


def command_in(jh: Path) -> Command | None:
    try:
        return decode_ncont((jh / "NCONT.DT").read_bytes())
    except (FileNotFoundError, FormatError):
        return None


def send_raw(jh: Path, cmd: Command) -> None:
    """Publish one NCONT.DT as ESTAR does: temp name, wait for the name, link."""
    wait_until(lambda: not (jh / "NCONT.DT").exists(), 10, "NSTAR to take NCONT.DT")
    tmp = jh / "XCONT.DT"
    tmp.write_bytes(encode_ncont(cmd))
    os.link(tmp, jh / "NCONT.DT")
    tmp.unlink()


def stale(jh: Path) -> list[str]:
    d = jh / "STALE"
    return sorted(p.name for p in d.iterdir()) if d.is_dir() else []


def lock_held(jhdata: Path, name: str) -> bool:
    """Does a process hold the lock file ``name`` (its file can exist a moment
    before it is held)?"""
    probe = JHData(jhdata, me="test", peer="test", use_events=False)
    try:
        return probe.held(name)
    finally:
        probe.close()


def hold_estar_lock(jhdata: Path):
    """Play a live ESTAR's part in the protocol: hold ESTAR.LCK (NSTAR obeys a
    command found at its start only while an ESTAR holds it).
    ``.close()`` the result to die."""
    jh = JHData(jhdata, me="ESTAR", peer="NSTAR", use_events=False)
    jh.lock(ESTAR_LOCK)
    return jh


class FakeNova(threading.Thread):
    """NSTAR's loop in this process (the real program's replies from
    nstar.program.Nova), with one reply replaced by ``damage(bytes)``; a damage
    may also put the reply in place itself (returning None: nothing to publish)."""

    def __init__(self, tmp: Path, jh: Path, name: str, damage):
        super().__init__(daemon=True)
        self.nova = Nova()
        self.nova.load_pair(*load_pair(tmp))
        self.jh = JHData(jh, me="NSTAR", peer="ESTAR", timeout=5)
        self.name, self.damage, self.sent = name, damage, None
        self.running = True

    def run(self):
        while self.running:
            try:
                self.jh.wait_for("NCONT.DT", timeout=0.2)
            except LinkTimeout:
                continue
            for reply in self.nova.execute(self.jh.take("NCONT.DT")):
                data = reply.data
                if reply.name == self.name and self.sent is None:
                    data = self.sent = self.damage(data)
                    if data is None:
                        self.sent = b""
                        continue
                try:
                    self.jh.publish(reply.temp, reply.name, data)
                except LinkTimeout:
                    return

    def stop(self):
        self.running = False
        self.join(5)
        self.jh.close()


def drive_config(monkeypatch, out, *options):
    """The planner.loop.DriveConfig that ``rig drive --out OUT OPTIONS`` hands
    the loop (which is stopped before its first look)."""
    import pytest

    import planner.loop
    from rig.main import main
    seen = {}

    class Caught(Exception):
        pass

    def fake_run(room, start, cfg, **kw):
        seen["cfg"] = cfg
        raise Caught                                  # stop before any look
    monkeypatch.setattr(planner.loop, "run", fake_run)
    with pytest.raises(Caught):
        main(["drive", "--out", str(out), *options])
    return seen["cfg"]


def bench_task(seed: int):
    """(room, start State, goal) of ``bench/drive.py``'s room ``seed``: the generated room,
    its start, and the goal drawn for the default vehicle with the same seed."""
    from planner.planning import random_goal
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.room import generate_room
    room = generate_room(seed)
    s = room.start
    start = State(s.x, s.z, s.heading_deg)
    return room, start, random_goal(room, start, DEFAULT, np.random.default_rng(seed))


def bench_drives(seed: int, option: str, values, **fixed):
    """``bench/drive.py``'s room ``seed`` (:func:`bench_task`) driven once for each of
    ``values`` of the DriveConfig field ``option``, the other fields ``fixed`` or the
    defaults, under the room's own odometry noise (seed ``seed``), as the bench drives it:
    (goal, {value: DriveResult})."""
    from planner.loop import DriveConfig, run
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(seed)
    return goal, {v: run(room, start, DriveConfig(goal=goal, **{option: v}, **fixed),
                         noise=OdometryNoise(seed=seed), keep_maps=False) for v in values}


def assert_reached_by_the_truth(res, goal) -> None:
    """A drive's result reached ``goal`` without a collision, and its TRUE end (the world's
    exact geometry, not the estimate it stopped on) lies within the goal's tolerance."""
    assert res.reached and res.collisions == 0, res.reason
    end = res.true_track[-1]
    assert math.hypot(end.x - goal[0], end.z - goal[1]) <= DriveConfig.tolerance_ft


# What the step back that learns the floor's grey (DriveConfig.learn_floor "step-back", the
# default since 2026-12-05 09:30) adds to a drive's travel at most: the step itself and
# the way back to where it began.  A path's optimum from the start does not hold it.
STEP_BACK_FT = 2 * DriveConfig.learn_back_ft

# The drive's defaults before 2026-12-04 (docs/planner.md, "Fetching the evidence, the
# drift and the grown walls"): a test that traced a drive under them pins them, so that
# what it shows (a collision and the rule that prevents it, a fix's accuracy) stays the
# drive it traced.  (Each dict also turns back what came after it: the step back that
# learns the floor's grey, the fix's widening window and the swept pivot, 2026-12-05 09:30;
# the goal's disc planned to, 2026-12-05 11:10; 16 looks without progress, not 8, 12:00;
# the occupied cells drawn from the fused floor features, not every look's hits, 13:45;
# forward to where a pivot is allowed, 15:00; the map out to the walls where the seen map
# has no way, 16:30; the plan past the once-seen features' outer sigma, 22:40; the floor's
# tiles seen up to a face of their grey, a move's start where its pivot may sweep, a move
# by its width and a leg steered where the vehicle would look round, 2026-12-06; the fix's
# widened window bounded, 11:45; the half cells where no map has a way, 15:40; the goal's
# once-seen blocker let go and a far turn held, 16:45; the hits the plan's walls explain
# and a tiled floor's one-grey runs proved only near seen floor, 20:30; the run on inside
# the goal's disc, 2026-12-07; 90 looks, not 60, 06:30; 24 looks without progress, not 16,
# 08:30; backing along its own way where it cannot turn, 12:15.)
DRIVE_BEFORE_2026_12_04 = dict(look_around="sweep", free_drift="off", plan_walls="plan",
                               learn_floor="off", wall_fix_widen=0.0, pivot="disc",
                               goal_region="point", max_stuck=8, occupied="looks",
                               turn_room="off", map_extent="seen", fine_map="off",
                               goal_evidence="off", wall_fix_far=0, uncertain="blocked",
                               wall_runs="none", move_ring="seen", passage="circle",
                               steer="off", wall_fix_most=None,
                               wall_hits="feature", one_grey_runs="prove", finish="edge",
                               max_looks=60, backing="map")

# The drive's defaults before 2026-12-05 (docs/planner.md, "The estimate held to the walls,
# the floor in view kept out of the boxes" and "The improved matcher"): the 1985 matcher,
# one-cell gaps of free space kept unknown, the dead-reckoned estimate, each range laid
# along the pitched axis, located points trusted from 2.5 ft, the floor in view cut by
# none of the three safety rules.
DRIVE_BEFORE_2026_12_05 = dict(match="1985", free_gaps="keep", pose="dead_reckoning",
                               wall_points="edges", hit_at="axis", min_range_ft=2.5,
                               wall_fix_sigmas=3.0, proof_heading="estimate",
                               floor_end_check="off", proof_hits="trace", min_pivot_deg=0.0,
                               learn_floor="off", wall_fix_widen=0.0, pivot="disc",
                               goal_region="point", max_stuck=8, occupied="looks",
                               turn_room="off", map_extent="seen", fine_map="off",
                               goal_evidence="off", wall_fix_far=0, uncertain="blocked",
                               wall_runs="none", move_ring="seen", passage="circle",
                               steer="off", wall_fix_most=None,
                               wall_hits="feature", one_grey_runs="prove", finish="edge",
                               max_looks=60, backing="map")
# The drive's defaults of 2026-12-05 01:35-04:30 differ from today's in the matcher (1985),
# in the one-cell gaps of free space (kept unknown) and in every turn being a pivot.
DRIVE_BEFORE_2026_12_05_0430 = dict(match="1985", free_gaps="keep", min_pivot_deg=0.0,
                                    learn_floor="off", wall_fix_widen=0.0, pivot="disc",
                                    goal_region="point", max_stuck=8, occupied="looks",
                                    turn_room="off", map_extent="seen", fine_map="off",
                                    goal_evidence="off", wall_fix_far=0, uncertain="blocked",
                                    wall_runs="none", move_ring="seen", passage="circle",
                                    steer="off", wall_fix_most=None,
                                    wall_hits="feature", one_grey_runs="prove", finish="edge",
                                    max_looks=60, backing="map")

# The drive's defaults before 2026-12-06 15:40 (docs/planner.md, "A floor end that moves
# with the camera"): no half cells where no map has a way, and a run's end that moved with
# the camera not drawn as an edge above the floor (and what came at 16:45 and 20:30 turned
# back too).
# A test that traced a drive under the defaults before then pins them.
DRIVE_BEFORE_2026_12_06_1540 = dict(fine_map="off", floor_end_check="stereo",
                                    goal_evidence="off", wall_fix_far=0,
                                    wall_hits="feature", one_grey_runs="prove", finish="edge",
                                    max_looks=60, max_stuck=16, backing="map",
                                    wall_runs="texture")

# The drive's defaults before 2026-12-06 16:45 (docs/planner.md, "A once-seen blocker at the
# goal let go, a far turn held for a second look"): no once-seen blocker at the goal let go,
# and no far turn on few points held back.  A test that traced a drive under the defaults
# before then pins them (with DRIVE_BEFORE_2026_12_06_1540 for the drives before 15:40);
# it turns back what came at 20:30 too.
DRIVE_BEFORE_2026_12_06_1645 = dict(goal_evidence="off", wall_fix_far=0,
                                    wall_hits="feature", one_grey_runs="prove", finish="edge",
                                    max_looks=60, max_stuck=16, backing="map",
                                    wall_runs="texture")

# The drive's defaults before 2026-12-06 20:30 (docs/planner.md, "Hits the plan's walls
# explain"): a floor hit the plan's walls explain still starts a feature, and a tiled
# floor's run of one of its greys proves the floor as any run.  A test that traced a drive
# under the defaults before then pins them.
DRIVE_BEFORE_2026_12_06_2030 = dict(wall_hits="feature", one_grey_runs="prove", finish="edge",
                                    max_looks=60, max_stuck=16, backing="map",
                                    wall_runs="texture")

# The drive's defaults before 2026-12-07 (docs/planner.md, "The run's end inside the goal's
# disc"): the run ends as soon as the estimate enters the goal's disc.  A test that traced a
# drive's last looks under the defaults before then pins it (and what came at 06:30,
# 08:30 and 12:15 turned back too).
DRIVE_BEFORE_2026_12_07 = dict(finish="edge", max_looks=60, max_stuck=16, backing="map",
                               wall_runs="texture")

# The drive's defaults before 2026-12-07 12:15 (docs/planner.md, "Back along its own
# way"): where it cannot turn at all, the vehicle stands and looks again.  A test that
# traced a drive's stand-still under the defaults before then pins it.  (These dicts since
# 2026-12-06 15:40 also turn back the flat floor's runs to the walls' foot, 2026-12-08.)
DRIVE_BEFORE_2026_12_07_1215 = dict(backing="map", wall_runs="texture")
