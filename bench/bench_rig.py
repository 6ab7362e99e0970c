"""Benchmark: the rig on the bundled laboratory pair.

* one slice pair over the file link — ``nstar`` as a separate process, ESTAR in
  this process speaking only through files in a fresh jhdata directory — the
  time of one LCLN (both slices, every edge-map request, POSIT.DT), median over
  the lines;
* the same lines over the direct (in-process) link, as the reference in the
  same run, and the ratio;
* whole-picture scans (lines 8..112) per second over the direct link — the first
  scan in the process (cold: compiled kernels loaded, LCSL terms computed) and
  the best of the following ones (warm) — and over the file link (the sum of
  its lines), with OpenCV's StereoBM and StereoSGBM on the same 128x120 4-bit
  pair timed in the same run for comparison.

Run:  python bench/bench_rig.py [--lines 8 112] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from diskfmt.dgreal import Real                      # noqa: E402
from diskfmt.layouts import decode_bi                # noqa: E402
from estar.link import start_file_link              # noqa: E402
from estar.program import file_link_estar, in_process_rig  # noqa: E402
from diskfmt.rdos import LINK_WAIT_ENV               # noqa: E402
from rig.session import child_env, start_nstar       # noqa: E402
from rig.scene import bundled_path                   # noqa: E402

DS, DV = Real.const("0.75"), Real.const("180")
RUSAGE = getattr(resource, "RUSAGE_THREAD", resource.RUSAGE_SELF)


def pair():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def time_lines(ecl, lines) -> list[float]:
    out = []
    for y in lines:
        t = time.perf_counter()
        ecl.lcln(y)
        out.append(time.perf_counter() - t)
    return out


WAITS = {"named": "named events, next request sent while NSTAR answers (the default)",
         "any": "any event wakes, one request at a time (RIG_LINK_WAIT=any, before)"}


def schedstat(pid="thread-self") -> tuple[float, float, int]:
    """(seconds on a core, seconds runnable but waiting for a core, times run)
    of a process (``pid``) or this thread, from /proc (zeros where there is none)."""
    try:
        with open(f"/proc/{pid}/schedstat") as f:
            on, queued, runs = (int(x) for x in f.read().split()[:3])
        return on / 1e9, queued / 1e9, runs
    except (OSError, ValueError):
        return 0.0, 0.0, 0


class FileRig:
    """One ESTAR (this process) and one ``nstar`` process on a fresh jhdata in
    ``parent``, both waiting the ``wait`` way (see diskfmt.rdos.link_wait)."""

    def __init__(self, parent, wait: str):
        self.tmp = tempfile.TemporaryDirectory(dir=parent)
        jh_dir = Path(self.tmp.name) / "jhdata"
        jh_dir.mkdir()
        self.link = start_file_link(jh_dir, timeout=60, wake=wait)
        env = child_env()
        env.pop("JHDATA", None)
        env[LINK_WAIT_ENV] = wait
        self.nstar = start_nstar(jh_dir, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"),
                                 quiet=True, idle_timeout=300, env=env)
        self.ecl = file_link_estar(self.link, DS, DV)
        self.times: list[float] = []
        self.switches = 0                 # this process's sleeps (voluntary switches)
        self.preempted = 0                # and the times it was put off a core
        self.cpu = [0.0, 0.0]             # user and system CPU seconds
        self.sched = [0.0, 0.0]           # ESTAR on a core, waiting for one
        self.nstar_sched = None
        self.nstar_usage = None
        self.requests0 = 0

    def line(self, y: int) -> None:
        r0, s0 = resource.getrusage(RUSAGE), schedstat()
        t = time.perf_counter()
        self.ecl.lcln(y)
        self.times.append(time.perf_counter() - t)
        r1, s1 = resource.getrusage(RUSAGE), schedstat()
        self.sched[0] += s1[0] - s0[0]
        self.sched[1] += s1[1] - s0[1]
        self.switches += r1.ru_nvcsw - r0.ru_nvcsw
        self.preempted += r1.ru_nivcsw - r0.ru_nivcsw
        self.cpu[0] += r1.ru_utime - r0.ru_utime
        self.cpu[1] += r1.ru_stime - r0.ru_stime

    def close(self) -> None:
        try:
            if self.nstar.poll() is None:
                end = schedstat(self.nstar.pid)
                self.nstar_sched = [end[0] - self.nstar_sched[0], end[1] - self.nstar_sched[1]]
                self.ecl.terminate()
                _, status, self.nstar_usage = os.wait4(self.nstar.pid, 0)
                self.nstar.returncode = os.waitstatus_to_exitcode(status)
        finally:
            self.link.close()
            if self.nstar.returncode is None:
                self.nstar.kill()
                self.nstar.wait()
            self.tmp.cleanup()


def file_link_times(lines, places: dict, waits, rounds: int = 1) -> dict:
    """Every (place, wait) rig, the lines timed interleaved: line y on each rig
    in turn (the order rotating), so each sees the same load."""
    rigs = {}
    try:
        for place, parent in places.items():
            for wait in waits:
                rigs[place, wait] = FileRig(parent, wait)
        for rig in rigs.values():          # the first command's start-up, untimed
            rig.ecl.lcln(lines[0])
            rig.times.clear()
            rig.switches = rig.preempted = 0
            rig.cpu = [0.0, 0.0]
            rig.sched = [0.0, 0.0]
            rig.nstar_sched = schedstat(rig.nstar.pid)
            rig.requests0 = rig.ecl.requests
        order = list(rigs.values())
        for _ in range(rounds):
            for y in lines:
                for rig in order:
                    rig.line(y)
                order.append(order.pop(0))
    finally:
        for rig in rigs.values():
            rig.close()
    return rigs


def spread(times) -> str:
    """Median, p90, quartiles, min and max of ``times`` (seconds) in ms."""
    t = sorted(times)
    q = statistics.quantiles(t, n=20, method="inclusive")    # 5 % steps
    return (f"median {statistics.median(t) * 1000:.1f} ms, p90 {q[17] * 1000:.1f}, "
            f"quartiles {q[4] * 1000:.1f}-{q[14] * 1000:.1f}, min {t[0] * 1000:.1f}, "
            f"max {t[-1] * 1000:.1f}")


def direct_times(lines) -> tuple[list[float], int]:
    ecl = in_process_rig(*pair(), DS, DV)
    return time_lines(ecl, lines), ecl.requests


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, nargs=2, default=(8, 112), metavar=("FIRST", "LAST"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=1,
                    help="passes over the lines on each file-link rig (default 1)")
    ap.add_argument("--waits", nargs="+", choices=list(WAITS), default=list(WAITS),
                    help="the file link's ways of waiting to time, interleaved "
                         "(default: both)")
    ap.add_argument("--only", choices=("file-link",),
                    help="time only the file link (no direct link, scans, OpenCV)")
    args = ap.parse_args(argv)
    lines = list(range(args.lines[0], args.lines[1] + 1))
    print(f"lines {lines[0]}..{lines[-1]} of the bundled pair ({len(lines)} lines); "
          f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    d_times, d_req = direct_times(lines)
    where = {"disk (system temp dir)": None}
    if Path("/dev/shm").is_dir():
        where["tmpfs (/dev/shm)"] = "/dev/shm"
    rigs = file_link_times(lines, where, args.waits, args.rounds)
    dm = statistics.median(d_times)
    print(f"edge-map requests per line: {d_req / len(lines):.1f}")
    print(f"one slice pair, direct link (reference): median {dm * 1000:.2f} ms")
    for place in where:
        print(f"one slice pair, file link, two processes, jhdata on {place}, "
              f"{args.rounds} x {len(lines)} lines interleaved:")
        for wait in args.waits:
            rig = rigs[place, wait]
            n = len(rig.times)
            req = rig.ecl.requests - rig.requests0
            usage = rig.nstar_usage
            print(f"  {wait:5s} {spread(rig.times)} = "
                  f"{statistics.median(rig.times) / dm:.1f}x direct")
            print(f"        ({WAITS[wait]}; {n} slice pairs)")
            wall = sum(rig.times)
            print(f"        per request ({1e6 * wall / req:.0f} us): ESTAR on a core "
                  f"{1e6 * rig.sched[0] / req:.0f} us, waiting for a core "
                  f"{1e6 * rig.sched[1] / req:.0f} us, {rig.switches / req:.2f} sleeps, "
                  f"{rig.preempted / req:.2f} preemptions; NSTAR on a core "
                  f"{1e6 * rig.nstar_sched[0] / req:.0f} us, waiting for a core "
                  f"{1e6 * rig.nstar_sched[1] / req:.0f} us")
        if len(args.waits) > 1:
            base = statistics.median(rigs[place, args.waits[-1]].times)
            for wait in args.waits[:-1]:
                m = statistics.median(rigs[place, wait].times)
                print(f"  median {wait} / {args.waits[-1]} = {m / base:.2f}")
    for rig in rigs.values():              # the same work on every rig
        assert rig.ecl.requests - rig.requests0 == d_req * args.rounds
    if args.only == "file-link":
        return 0
    scans = [sum(d_times)]              # the first pass in this process: cold
    for _ in range(args.repeat):
        ecl = in_process_rig(*pair(), DS, DV)
        t = time.perf_counter()
        for y in lines:
            ecl.lcln(y)
        scans.append(time.perf_counter() - t)
    cold, best = scans[0], min(scans[1:])
    print(f"whole-picture scan, direct link: warm {best * 1000:.1f} ms = {1 / best:.1f} "
          f"frames/s (best of {args.repeat}); first scan in the process {cold * 1000:.1f} ms")
    for (place, wait), rig in rigs.items():
        total = sum(rig.times) / args.rounds
        print(f"whole-picture scan, file link on {place} ({wait}), the sum of its "
              f"lines: {total * 1000:.0f} ms = {1 / total:.2f} frames/s = "
              f"{total / best:.1f}x the direct link")
    for name, t in opencv_times(*pair()).items():
        print(f"OpenCV {name} on the same 128x120 pair: {t * 1000:.2f} ms per frame "
              f"(rig direct scan / this = {best / t:.2f})")
    return 0


def opencv_times(left, right, repeat: int = 20) -> dict[str, float]:
    """Median time per frame of StereoBM and StereoSGBM on the 4-bit pair shown
    as 8-bit (level k as 17*k); 64 disparities, block 9 (BM) and 5 (SGBM)."""
    import cv2
    l8, r8 = (left * 17).astype("uint8"), (right * 17).astype("uint8")
    matchers = {"StereoBM (64 disparities, block 9)": cv2.StereoBM.create(64, 9),
                "StereoSGBM (64 disparities, block 5)": cv2.StereoSGBM.create(
                    0, 64, 5, P1=8 * 25, P2=32 * 25)}
    out = {}
    for name, m in matchers.items():
        m.compute(l8, r8)
        ts = []
        for _ in range(repeat):
            t = time.perf_counter()
            m.compute(l8, r8)
            ts.append(time.perf_counter() - t)
        out[name] = statistics.median(ts)
    return out


if __name__ == "__main__":
    sys.exit(main())
