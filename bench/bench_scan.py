"""Time of the improved matcher's scan of one look (the drive loop's ``scan_look``).

    python bench/bench_scan.py [--rooms 3] [--looks 4] [--rounds 7] [--reference REV]

Renders ``--looks`` looks along a generated walk in each of ``--rooms`` generated
rooms (seeds 1..N, the drive's 2x2 rays per pixel) and times
``planner.loop.scan_look(left, right, lines, "improved")`` over all of them, on the
drive's lines (8, 10 .. 112).  The same looks are scanned by this tree and by the
tree of git revision ``--reference`` (default: the commit before the scan was made
faster), each in a process of its own, taking turns round by round so that a busy
machine slows both alike.  Prints the median milliseconds per look of each, the ratio,
and whether the two trees' scans are the same (every point and every verdict, the
floats bit for bit).  ``--reference none``: time this tree alone.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import pickle
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# A commit with the plain matcher from before the scan was made faster (its matching/ is
# that of 14c9150, the commit just before the speed-up landed; the fixture of
# tests/test_matching_speed.py was written from it too).
BEFORE_SPEED_UP = "add8861"


def render_looks(rooms: int, looks: int, supersample: int = 2):
    """(left .BI, right .BI) of ``looks`` poses along a generated walk in each of
    the generated rooms 1..``rooms``."""
    sys.path.insert(0, str(ROOT))
    from world.render import render_look
    from world.room import generate_room
    from world.walk import generate_walk
    out = []
    for seed in range(1, rooms + 1):
        room = generate_room(seed)
        for k, pose in enumerate(generate_walk(room, seed, looks)):
            look = render_look(room, pose, seed=1000 * seed + k, supersample=supersample)
            out.append((look.left_bi, look.right_bi))
    return out


def scan_digest(scan) -> str:
    """A digest of a scan's points and verdicts, every field (floats by repr,
    which names a float exactly).  Not its count of NBLOB round trips: through
    ESTAR (before 2026-12-07) it counted the matcher's own fetches too, which
    the eyes' line source (eyes.improved) does not make."""
    from dataclasses import astuple
    h = hashlib.sha256()
    for p in scan.points:
        h.update(repr(astuple(p)).encode())
    for r in scan.results:
        h.update(repr([astuple(v) for v in r.verdicts or ()]).encode())
    return h.hexdigest()


def worker(tree: str, looks_file: str) -> None:
    """Scan the looks once per line read from stdin; answer with one JSON line
    (ms per look, digest of the scans).  ``tree`` is the code to time."""
    from dataclasses import fields
    sys.path.insert(0, tree)
    os.chdir(tree)
    import planner.loop as loop
    looks = pickle.loads(Path(looks_file).read_bytes())
    lines = next(f.default for f in fields(loop.DriveConfig) if f.name == "lines")
    for _ in sys.stdin:
        h = hashlib.sha256()
        t = time.perf_counter()
        scans = [loop.scan_look(left, right, lines, "improved") for left, right in looks]
        ms = 1000 * (time.perf_counter() - t) / len(looks)
        for s in scans:
            h.update(scan_digest(s).encode())
        print(json.dumps({"ms": ms, "digest": h.hexdigest()}), flush=True)


class Worker:
    """One worker process on one tree."""

    def __init__(self, name: str, tree: Path, looks_file: str):
        self.name = name
        env = dict(os.environ, PYTHONPATH=str(tree))
        self.proc = subprocess.Popen([sys.executable, __file__, "--worker", str(tree), looks_file],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                                     cwd=tree, env=env)
        self.ms: list[float] = []
        self.digest = None

    def run(self, keep: bool = True) -> None:
        self.proc.stdin.write("run\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise SystemExit(f"the {self.name} worker stopped (see its error above)")
        answer = json.loads(line)
        self.digest = answer["digest"]
        if keep:
            self.ms.append(answer["ms"])

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait()


def reference_tree(rev: str, into: Path) -> None:
    """The files of git revision ``rev`` of this repository, unpacked into ``into``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Looks: generated rooms 1..ROOMS, LOOKS poses of a "
                                        "generated walk in each; lines 8, 10 .. 112.")
    ap.add_argument("--rooms", type=int, default=3, help="generated rooms (default 3)")
    ap.add_argument("--looks", type=int, default=4, help="looks per room (default 4)")
    ap.add_argument("--rounds", type=int, default=7,
                    help="timed scans of all the looks per tree, taking turns (default 7)")
    ap.add_argument("--reference", default=BEFORE_SPEED_UP, metavar="REV",
                    help="git revision to compare with (default %(default)s, the plain "
                         "matcher before the speed-up); 'none': this tree alone")
    ap.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker:
        worker(*a.worker)
        return 0
    looks = render_looks(a.rooms, a.looks)
    print(f"{len(looks)} looks ({a.rooms} rooms x {a.looks}), improved matcher, "
          f"{a.rounds} rounds")
    with tempfile.TemporaryDirectory() as tmp:
        looks_file = Path(tmp) / "looks.pkl"
        looks_file.write_bytes(pickle.dumps(looks))
        workers = [Worker("this tree", ROOT, str(looks_file))]
        if a.reference != "none":
            ref = Path(tmp) / "reference"
            ref.mkdir()
            reference_tree(a.reference, ref)
            workers.append(Worker(f"reference {a.reference}", ref, str(looks_file)))
        try:
            for w in workers:                     # warm up: imports, compiled kernels
                w.run(keep=False)
            for r in range(a.rounds):
                for w in (workers if r % 2 == 0 else workers[::-1]):
                    w.run()
        finally:
            for w in workers:
                w.close()
    print(f"{'tree':>24} {'median ms/look':>15} {'min':>7} {'max':>7}")
    for w in workers:
        print(f"{w.name:>24} {statistics.median(w.ms):15.1f} {min(w.ms):7.1f} {max(w.ms):7.1f}")
    if len(workers) == 2:
        new, ref = (statistics.median(w.ms) for w in workers)
        same = workers[0].digest == workers[1].digest
        print(f"ratio (reference / this tree): {ref / new:.2f}x faster; "
              f"scans {'identical' if same else 'DIFFERENT'}")
        return 0 if same else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
