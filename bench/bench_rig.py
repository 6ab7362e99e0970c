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
from rig.session import start_nstar                  # noqa: E402
from rig.scene import bundled_path                   # noqa: E402

DS, DV = Real.const("0.75"), Real.const("180")


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


def file_link_times(lines, parent=None) -> tuple[list[float], int]:
    with tempfile.TemporaryDirectory(dir=parent) as tmp:
        jh_dir = Path(tmp) / "jhdata"
        jh_dir.mkdir()
        link = start_file_link(jh_dir, timeout=60)
        nstar = start_nstar(jh_dir, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"),
                            quiet=True, idle_timeout=120)
        try:
            ecl = file_link_estar(link, DS, DV)
            times = time_lines(ecl, lines)
            ecl.terminate()
            nstar.wait(timeout=60)
            return times, ecl.requests
        finally:
            link.close()
            if nstar.poll() is None:
                nstar.kill()


def direct_times(lines) -> tuple[list[float], int]:
    ecl = in_process_rig(*pair(), DS, DV)
    return time_lines(ecl, lines), ecl.requests


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, nargs=2, default=(8, 112), metavar=("FIRST", "LAST"))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    lines = list(range(args.lines[0], args.lines[1] + 1))
    d_times, d_req = direct_times(lines)
    where = {"disk (ext4, system temp dir)": None}
    if Path("/dev/shm").is_dir():
        where["tmpfs (/dev/shm)"] = "/dev/shm"
    f_results = {name: file_link_times(lines, parent) for name, parent in where.items()}
    scans = [sum(d_times)]              # the first pass in this process: cold
    for _ in range(args.repeat):
        ecl = in_process_rig(*pair(), DS, DV)
        t = time.perf_counter()
        for y in lines:
            ecl.lcln(y)
        scans.append(time.perf_counter() - t)
    dm = statistics.median(d_times)
    print(f"lines {lines[0]}..{lines[-1]} of the bundled pair ({len(lines)} lines)")
    print(f"edge-map requests per line: {d_req / len(lines):.1f}")
    print(f"one slice pair, direct link (reference): median {dm * 1000:.2f} ms")
    for name, (f_times, f_req) in f_results.items():
        assert f_req == d_req
        fm = statistics.median(f_times)
        print(f"one slice pair, file link, two processes, jhdata on {name}: median "
              f"{fm * 1000:.2f} ms (p90 {sorted(f_times)[int(0.9 * len(f_times))] * 1000:.2f} ms)"
              f" = {fm / dm:.2f}x direct")
    cold, best = scans[0], min(scans[1:])
    print(f"whole-picture scan, direct link: warm {best * 1000:.1f} ms = {1 / best:.1f} "
          f"frames/s (best of {args.repeat}); first scan in the process {cold * 1000:.1f} ms")
    for name, (f_times, _) in f_results.items():
        total = sum(f_times)
        print(f"whole-picture scan, file link on {name}: {total * 1000:.0f} ms = "
              f"{1 / total:.2f} frames/s = {total / best:.1f}x the direct link")
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
