"""Benchmark: the rig on the bundled laboratory pair.

* one slice pair over the file link — ``nstar`` as a separate process, ESTAR in
  this process speaking only through files in a fresh jhdata directory — the
  time of one LCLN (both slices, every edge-map request, POSIT.DT): median, p90,
  quartiles, min and max over the lines, on the disk and on tmpfs, for each way
  of waiting (``--waits``: today's, the earlier one, and one request at a time
  with today's events), all interleaved line by line in one run; and where the
  time of a request goes: each program's time on a core, waiting for a core
  (a busy machine) and its sleeps, from /proc;
* the same lines over the direct (in-process) link, as the reference in the
  same run, and the ratio;
* whole-picture scans (lines 8..112) per second over the direct link — the first
  scan in the process (cold: compiled kernels loaded, LCSL terms computed) and
  the best of the following ones (warm) — and over the file link (the sum of
  its lines), with OpenCV's StereoBM and StereoSGBM on the same 128x120 4-bit
  pair timed in the same run for comparison.

Run:  python bench/bench_rig.py [--lines 8 112] [--repeat 3] [--rounds 3]
      python bench/bench_rig.py --only file-link --waits named any
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


WAITS = {"named": "the default: named events; the next request sent as the reply appears",
         "serial": "named events, one request at a time (this benchmark only)",
         "any": "RIG_LINK_WAIT=any, the earlier wait: any event wakes; one request at a time"}


def proc_sleeps(pid) -> int:
    """The voluntary context switches (sleeps) of process ``pid`` so far."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for row in f:
                if row.startswith("voluntary_ctxt_switches:"):
                    return int(row.split()[1])
    except OSError:
        pass
    return 0


def schedstat(pid="thread-self") -> tuple[float, float]:
    """(seconds on a core, seconds runnable but waiting for one) of process
    ``pid`` or of this thread, from /proc (zeros where there is none)."""
    try:
        with open(f"/proc/{pid}/schedstat") as f:
            on, queued = (int(x) for x in f.read().split()[:2])
        return on / 1e9, queued / 1e9
    except (OSError, ValueError):
        return 0.0, 0.0


class Tally:
    """What one way of waiting cost, pooled over its rigs: the time of each
    slice pair, and per request ESTAR's and NSTAR's time on a core, waiting
    for a core, and sleeps (from /proc: where the time of a round trip goes)."""

    def __init__(self):
        self.times: list[float] = []
        self.rounds: list[float] = []     # the median of each round (fresh processes)
        self.requests = 0
        self.estar = [0.0, 0.0, 0]        # on a core, waiting for a core, sleeps
        self.nstar = [0.0, 0.0, 0]

    def report(self) -> str:
        n = max(self.requests, 1)
        wall = 1e6 * sum(self.times) / n
        e, m = self.estar, self.nstar
        return (f"per request {wall:.0f} us: ESTAR on a core {1e6 * e[0] / n:.0f} us, waiting "
                f"for a core {1e6 * e[1] / n:.0f} us, {e[2] / n:.2f} sleeps; NSTAR on a core "
                f"{1e6 * m[0] / n:.0f} us, waiting for a core {1e6 * m[1] / n:.0f} us, "
                f"{m[2] / n:.2f} sleeps")


class FileRig:
    """One ESTAR (this process) and one ``nstar`` process on a fresh jhdata in
    ``parent``, both waiting the ``wait`` way (see diskfmt.rdos.link_wait)."""

    def __init__(self, parent, wait: str, tally: Tally):
        self.tally = tally
        self.tmp = tempfile.TemporaryDirectory(dir=parent)
        jh_dir = Path(self.tmp.name) / "jhdata"
        jh_dir.mkdir()
        wake = "named" if wait == "serial" else wait
        self.link = start_file_link(jh_dir, timeout=60, wake=wake)
        if wait == "serial":
            self.link.pipeline = False
        env = child_env()
        env.pop("JHDATA", None)
        env[LINK_WAIT_ENV] = wake
        self.nstar = start_nstar(jh_dir, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"),
                                 quiet=True, idle_timeout=300, env=env)
        self.ecl = file_link_estar(self.link, DS, DV)
        self.nstar0 = None

    def line(self, y: int) -> None:
        e0, s0 = schedstat(), resource.getrusage(RUSAGE).ru_nvcsw
        r0 = self.ecl.requests
        t = time.perf_counter()
        self.ecl.lcln(y)
        self.tally.times.append(time.perf_counter() - t)
        e1, s1 = schedstat(), resource.getrusage(RUSAGE).ru_nvcsw
        est = self.tally.estar
        est[0] += e1[0] - e0[0]
        est[1] += e1[1] - e0[1]
        est[2] += s1 - s0
        self.tally.requests += self.ecl.requests - r0

    def mark(self) -> None:
        """Start counting NSTAR's time (after the untimed first line)."""
        self.nstar0 = (*schedstat(self.nstar.pid), proc_sleeps(self.nstar.pid))

    def close(self) -> None:
        try:
            if self.nstar.poll() is None:
                end = (*schedstat(self.nstar.pid), proc_sleeps(self.nstar.pid))
                if self.nstar0 is not None:
                    for k in range(3):
                        self.tally.nstar[k] += end[k] - self.nstar0[k]
                self.ecl.terminate()
                self.nstar.wait(timeout=60)
        finally:
            self.link.close()
            if self.nstar.poll() is None:
                self.nstar.kill()
                self.nstar.wait()
            self.tmp.cleanup()


def file_link_times(lines, places: dict, waits, rounds: int = 1) -> dict:
    """A Tally per (place, wait).  Each round starts a fresh rig of every
    (place, wait) (fresh processes: where the scheduler puts them varies) and
    times the lines interleaved: line y on each rig in turn, the order
    rotating, so each sees the same load."""
    tallies = {(place, wait): Tally() for place in places for wait in waits}
    for _ in range(rounds):
        rigs = []
        try:
            for (place, wait), tally in tallies.items():
                rigs.append(FileRig(places[place], wait, tally))
            for rig in rigs:               # start-up and the first commands, untimed
                rig.ecl.lcln(lines[0])
                rig.mark()
            starts = {id(rig.tally): len(rig.tally.times) for rig in rigs}
            for y in lines:
                for rig in rigs:
                    rig.line(y)
                rigs.append(rigs.pop(0))
            for rig in rigs:
                rig.tally.rounds.append(statistics.median(rig.tally.times[starts[id(rig.tally)]:]))
        finally:
            for rig in rigs:
                rig.close()
    return tallies


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
    ap.add_argument("--rounds", type=int, default=3,
                    help="passes over the lines, each on fresh file-link processes "
                         "(default 3)")
    ap.add_argument("--waits", nargs="+", choices=list(WAITS), default=list(WAITS),
                    help="the file link's ways of waiting to time, interleaved "
                         "(default: all; the ratios are to the last)")
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
    tallies = file_link_times(lines, where, args.waits, args.rounds)
    dm = statistics.median(d_times)
    print(f"edge-map requests per line: {d_req / len(lines):.1f}")
    print(f"one slice pair, direct link (reference): median {dm * 1000:.2f} ms")
    for place in where:
        print(f"one slice pair (both slices, every edge-map request, POSIT.DT), file link, "
              f"two processes, jhdata on {place}; {args.rounds} round(s) of fresh processes x "
              f"{len(lines)} lines, interleaved:")
        for wait in args.waits:
            tally = tallies[place, wait]
            assert tally.requests == d_req * args.rounds     # the same work on every rig
            print(f"  {wait:6s} {spread(tally.times)} ({WAITS[wait]})")
            print(f"         {tally.report()}")
            print(f"         medians of the rounds: "
                  f"{', '.join(f'{1000 * m:.1f}' for m in tally.rounds)} ms")
        if len(args.waits) > 1:
            base = statistics.median(tallies[place, args.waits[-1]].times)
            print("  medians: " + ", ".join(
                f"{wait} / {args.waits[-1]} = "
                f"{statistics.median(tallies[place, wait].times) / base:.2f}"
                for wait in args.waits[:-1]))
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
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
    for (place, wait), tally in tallies.items():
        total = sum(tally.times) / args.rounds
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
