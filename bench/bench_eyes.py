"""Benchmark: the eyes (the rig as one compiled frame scan) against OpenCV.

* warm whole-picture scan (lines 8..112) of the eyes, OpenCV's StereoBM and
  StereoSGBM (docs/accuracy.md's settings: 16 disparities, BM block 9, SGBM
  block 5 with P1/P2 = 8/32 * 5^2, MODE_HH), one thread each
  (``cv2.setNumThreads(1)``), timed interleaved round after round on the same
  pictures, ratios of medians of the wall-clock time and of the thread's CPU
  time (which leaves out the time a busy machine's other work takes the core
  away); the bundled pair and (with scikit-image) the
  Middlebury motorcycle pair; the reference path (ESTAR's Eclipse + NSTAR's
  Nova in process) a few times for its ratio;
* where a warm scan's time goes (``--only stages``): the compiled line loop
  cut after each stage, the cuts timed interleaved; and the slices' EXQVFL
  alone, nstar's label-by-label kernel against the eyes' own, interleaved;
* cold first scan in a fresh process, with the compile cache (numba
  ``cache=True``, as installed) and without (an empty cache directory);
* a 200-frame stereo sequence (side-by-side video of the bundled pair moving
  one column a frame) through ``rig scan --video``: frames per second at
  ``--workers`` 1 and 2, and the resident memory of each process;
* one slice pair over the file link (nstar as a second process): median and
  p90 per line, jhdata on the disk.

Run:  python bench/bench_eyes.py [--rounds 200] [--frames 200] [--skip-file-link]
      [--only warm|stages|cold|sequence|file-link]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from diskfmt.layouts import decode_bi          # noqa: E402
from rig.scene import bundled_path             # noqa: E402


def bundled():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def pictures():
    out = {"bundled pair": bundled()}
    try:
        from bench.accuracy import motorcycle
        left, right, *_ = motorcycle()
        out["motorcycle (Middlebury, 128x120)"] = (left, right)
    except ImportError:
        print("(scikit-image not installed: no motorcycle pair)")
    return out


def warm(rounds: int) -> list[str]:
    import cv2
    from bench.accuracy import make_bm, make_sgbm
    from eyes import Eyes
    from rig.scan import scan_pair
    cv2.setNumThreads(1)
    lines = []
    for name, (left, right) in pictures().items():
        eyes = Eyes()
        l8, r8 = (left.astype(np.uint8) * 17), (right.astype(np.uint8) * 17)
        bm, sgbm = make_bm(), make_sgbm()
        runs = {"eyes": lambda: eyes.scan(left, right), "StereoBM": lambda: bm.compute(l8, r8),
                "StereoSGBM": lambda: sgbm.compute(l8, r8)}
        times = {k: [] for k in runs}
        cpu = {k: [] for k in runs}                   # this thread's CPU time: what the
        for fn in runs.values():                      # load's preemptions leave out
            fn()
        for _ in range(rounds):                       # interleaved
            for k, fn in runs.items():
                c = time.thread_time()
                t = time.perf_counter()
                fn()
                times[k].append(time.perf_counter() - t)
                cpu[k].append(time.thread_time() - c)
        ref = []
        for _ in range(3):
            t = time.perf_counter()
            scan_pair(left, right)
            ref.append(time.perf_counter() - t)
        med = {k: statistics.median(v) for k, v in times.items()}
        lines.append(f"{name}: {len(eyes.scan(left, right).point_rows)} located edges")
        for k, v in times.items():
            lines.append(f"  {k:10s} median {med[k] * 1e3:6.3f} ms  min {min(v) * 1e3:6.3f} ms  "
                         f"p90 {sorted(v)[int(0.9 * len(v))] * 1e3:6.3f} ms")
        lines.append(f"  eyes / StereoSGBM = {med['eyes'] / med['StereoSGBM']:.2f}, "
                     f"eyes / StereoBM = {med['eyes'] / med['StereoBM']:.2f} (medians, "
                     f"{rounds} interleaved rounds); eyes = {1 / med['eyes']:.0f} frames/s")
        cmed = {k: statistics.median(v) for k, v in cpu.items()}
        lines.append("  thread CPU time, medians: " + ", ".join(
            f"{k} {v * 1e3:.3f} ms" for k, v in cmed.items())
            + f"; eyes / StereoSGBM = {cmed['eyes'] / cmed['StereoSGBM']:.2f}, "
            f"eyes / StereoBM = {cmed['eyes'] / cmed['StereoBM']:.2f}")
        lines.append(f"  reference path (Eclipse + Nova in process) median "
                     f"{statistics.median(ref) * 1e3:.1f} ms = "
                     f"{statistics.median(ref) / med['eyes']:.0f}x the eyes")
    return lines


COLD = """
import time
t0 = time.perf_counter()
from eyes import Eyes
from diskfmt.layouts import decode_bi
from rig.scene import bundled_path
t1 = time.perf_counter()
l = decode_bi(bundled_path("LAB-L.BI").read_bytes())
r = decode_bi(bundled_path("LAB-R.BI").read_bytes())
e = Eyes()
t2 = time.perf_counter()
e.scan(l, r)
t3 = time.perf_counter()
e.scan(l, r)
t4 = time.perf_counter()
print(t1 - t0, t3 - t2, t4 - t3)
"""


def cold() -> list[str]:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    out = []
    with tempfile.TemporaryDirectory() as empty:
        for label, extra in (("compile cache warm", {}),
                             ("no compile cache (empty NUMBA_CACHE_DIR)",
                              {"NUMBA_CACHE_DIR": empty})):
            if not extra:                    # make sure the cache is there
                subprocess.run([sys.executable, "-c", COLD], env=env, capture_output=True)
            res = subprocess.run([sys.executable, "-c", COLD], env=dict(env, **extra),
                                 capture_output=True, text=True, check=True)
            imp, first, second = (float(v) for v in res.stdout.split())
            out.append(f"  {label}: import {imp:.2f} s, first scan {first:.2f} s, "
                       f"second {second * 1e3:.2f} ms")
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "rig.main", "scan", "--quiet"], env=env,
                   capture_output=True, check=True)
    out.append(f"  whole `rig scan --quiet` process (bundled pair, accuracy table): "
               f"{time.perf_counter() - t:.2f} s")
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "rig.main", "scan", "--quiet", "--engine",
                    "reference"], env=env, capture_output=True, check=True)
    out.append(f"  the same with --engine reference: {time.perf_counter() - t:.2f} s")
    return out


def sequence(frames: int) -> list[str]:
    import cv2
    from rig import batch
    from rig.scan import write_atomic   # noqa: F401  (import cost outside the timing)
    left, right = bundled()
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        video = Path(tmp) / "sbs.avi"
        vw = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"FFV1"), 30, (512, 240))
        for k in range(frames):
            pair = [np.kron(np.roll(p, k % 16, axis=1).astype(np.uint8) * 16 + 8,
                            np.ones((2, 2), dtype=np.uint8)) for p in (left, right)]
            vw.write(cv2.cvtColor(np.hstack(pair), cv2.COLOR_GRAY2BGR))
        vw.release()
        settings = batch.Settings(str(Path(tmp) / "out"), tuple(range(8, 113)))
        for workers in (1, 2):
            items = batch.digitized(batch.video_frames(str(video), None), (str(video),) * 2)
            res = batch.run(items, settings, workers=workers, chunk=16, total=frames,
                            progress=False)
            assert res.ok == frames, res.rows[:3]
            scan_ms = statistics.median(float(r["scan_ms"]) for r in res.rows)
            out.append(f"  --workers {workers}: {frames} frames in {res.seconds:.2f} s = "
                       f"{frames / res.seconds:.1f} frames/s with the start "
                       f"({res.first_seconds:.2f} s to the first chunk), "
                       f"{res.steady_fps:.1f} frames/s after it; median "
                       f"scan {scan_ms:.2f} ms a frame; RSS parent "
                       f"{res.parent_rss_kb / 1024:.0f} MB, per worker "
                       f"{max(res.worker_rss_kb) / 1024:.0f} MB)")
    return out


def file_link() -> list[str]:
    from bench.bench_rig import file_link_times
    times, _ = file_link_times(list(range(8, 113)))
    s = sorted(times)
    return [f"  one slice pair, file link, jhdata on the disk: median "
            f"{statistics.median(times) * 1e3:.1f} ms, p90 {s[int(0.9 * len(s))] * 1e3:.1f} ms, "
            f"min {s[0] * 1e3:.1f} ms, max {s[-1] * 1e3:.1f} ms over {len(s)} lines"]


def stages(rounds: int) -> list[str]:
    """Where a warm scan's time goes: the compiled line loop cut after each
    stage (slices; + MASL with its edge maps and MARF; + the match rows and
    LCSL), the cuts timed interleaved, differences of tenth percentiles (on a
    shared machine the median carries the other work's preemptions; the
    fastest tenth is the code's own time)."""
    from eyes.exqvfl import exqvfl_fast, new_work
    from eyes.kernels import (LEFT_X, RIGHT_X, build_frame, cfeat, lcsl_line, level_windows,
                              masl_line, match_list_rows, new_windows)
    from nstar.exqvfl import exqvfl_kernel
    from eyes import Eyes
    from diskfmt.jit import jit

    @jit
    def cut(frame, windows, lines, stop, consts, range_done, range_mq, offset_done, offset_words,
            match_rows, point_rows, point_words):
        ifeat1 = np.zeros((4, 50), dtype=np.int32)
        ifeat2 = np.zeros((4, 50), dtype=np.int32)
        pix = np.zeros(128, dtype=np.int64)
        work = np.zeros((3, 130), dtype=np.int64)
        level_windows(frame, windows)
        maps = np.zeros((2, 100, 4), dtype=np.uint64)
        bits = np.zeros((2, 100), dtype=np.int64)
        requests = np.zeros((200, 4), dtype=np.int64)
        partners = np.zeros((2, 18), dtype=np.int64)
        bounds = np.zeros((2, 50, 2), dtype=np.int64)
        kept = np.zeros((2, 50), dtype=np.int64)
        grey = np.zeros((2, 320), dtype=np.uint8)
        nmatch = np.zeros(100, dtype=np.int64)
        imatch = np.zeros((100, 10, 4), dtype=np.int64)
        pos = np.zeros(640, dtype=np.int64)
        nrow = 0
        npt = 0
        for k in range(lines.shape[0] if stop > 0 else 0):
            iyloc = lines[k]
            nfeat1, nfeat2 = cfeat(frame, iyloc, pix, ifeat1, ifeat2, work)
            if stop >= 2:
                masl_line(frame, windows, iyloc, nfeat1, ifeat1, nfeat2, ifeat2, False, nmatch,
                          imatch, maps, bits, requests, partners, bounds, kept, grey)
            if stop >= 3:
                nrow = match_list_rows(nfeat1, nmatch, imatch, match_rows, nrow)
                npt = lcsl_line(iyloc, nfeat1, nmatch, imatch, consts, range_done, range_mq,
                                offset_done, offset_words, pos, point_rows, point_words, npt)
        return npt

    @jit
    def all_slices_ref(rows, table, work):
        total = 0
        for i in range(rows.shape[0]):
            total += exqvfl_kernel(rows[i], 128, 2, table)[0]
        return total

    @jit
    def all_slices_fast(rows, table, work):
        total = 0
        for i in range(rows.shape[0]):
            total += exqvfl_fast(rows[i], 128, 2, table, work)[0]
        return total

    names = ("level windows", "EXQVFL slices", "MASL (edge maps, MARF, insertions)",
             "match rows + LCSL", "outputs + Eyes.scan's Python side")
    out = []
    for name, (left, right) in pictures().items():
        eyes = Eyes()
        eyes.scan(left, right)
        frame = build_frame(left, right)
        t = eyes.tables
        lines = np.arange(8, 113)
        work = (np.empty((105000, 5), np.int32), np.empty((10500, 6), np.int32),
                np.empty((10500, 6), np.uint32))
        windows = new_windows()
        runs = [lambda s=s: cut(frame, windows, lines, s, eyes.consts, t["range_done"], t["range_mq"],
                                t["offset_done"], t["offset_words"], *work) for s in range(4)]
        runs.append(lambda: eyes.scan(left, right))
        times = [[] for _ in runs]
        for fn in runs:
            fn()
        for _ in range(rounds):
            for i, fn in enumerate(runs):
                t0 = time.perf_counter()
                fn()
                times[i].append(time.perf_counter() - t0)
        med = [sorted(v)[len(v) // 10] * 1e3 for v in times]
        out.append(f"{name}: warm scan {med[-1]:.3f} ms (tenth percentile of {rounds} "
                   f"interleaved rounds)")
        for i, label in enumerate(names):
            out.append(f"  {label:36s} {med[i] - (med[i - 1] if i else 0):6.3f} ms")
        # the slice stage's kernel against the one it replaced, on the same slices
        rows = np.array([frame[y, x:x + 128].astype(np.int64) for y in range(8, 113)
                         for x in (LEFT_X, RIGHT_X)])
        table, work_ = np.zeros((4, 50), np.int32), new_work()
        kernels = {"nstar exqvfl_kernel": lambda: all_slices_ref(rows, table, work_),
                   "eyes exqvfl_fast": lambda: all_slices_fast(rows, table, work_)}
        ktimes = {k: [] for k in kernels}
        for fn in kernels.values():
            fn()
        for _ in range(rounds):
            for k, fn in kernels.items():
                t0 = time.perf_counter()
                fn()
                ktimes[k].append(time.perf_counter() - t0)
        kmed = {k: statistics.median(v) * 1e3 for k, v in ktimes.items()}
        out.append(f"  EXQVFL alone, {len(rows)} slices: " + ", ".join(
            f"{k} {v:.3f} ms" for k, v in kmed.items())
            + f"; eyes / nstar = {kmed['eyes exqvfl_fast'] / kmed['nstar exqvfl_kernel']:.2f}")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=200)
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--skip-file-link", action="store_true")
    ap.add_argument("--only", choices=("warm", "stages", "cold", "sequence", "file-link"),
                    help="run one part")
    args = ap.parse_args(argv)
    parts = {args.only} if args.only else {"warm", "cold", "sequence", "file-link"}
    if args.skip_file_link:
        parts.discard("file-link")
    print(f"machine: {os.cpu_count()} cores; load average "
          f"{' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    if "warm" in parts:
        print("warm whole-picture scan, lines 8..112, one thread:")
        for line in warm(args.rounds):
            print(line, flush=True)
    if "stages" in parts:
        print("where the warm scan's time goes (the compiled loop cut after each stage):")
        for line in stages(args.rounds):
            print(line, flush=True)
    if "cold" in parts:
        print("cold first scan in a fresh process:")
        for line in cold():
            print(line, flush=True)
    if "sequence" in parts:
        print(f"{args.frames}-frame side-by-side video through `rig scan --video` "
              f"(digitizer, scan, per-frame CSV):")
        for line in sequence(args.frames):
            print(line, flush=True)
    if "file-link" in parts:
        for line in file_link():
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
