"""Soak benchmark of the file link (docs/robustness.md): request/response round trips
between a real ``nstar`` process and an ESTAR, counting lost and duplicated
messages, with the throughput and the resident memory (VmRSS) of both
processes at start and end.

Two parts, both on the bundled laboratory pair, each in a fresh jhdata
directory:

* ``raw`` — this process acts as ESTAR (it takes ESTAR.LCK and waits for NSTAR
  to be idle, as estar does) and sends N raw NCONT.DT commands, a seeded random
  mix of edge maps (code 4, random image, X-centre, line and side), slices
  (code 2) and Star block maps (code 1).  Each reply is checked byte for byte
  against the same command run on an in-process NSTAR (``nstar.program.Nova``,
  fed the same sequence, so SLICE.DT history matches too).  Lost = a command
  whose reply never came; duplicated = a reply file present when none was
  owed; wrong = a reply whose bytes differ.
* ``estar`` — the real ``estar`` program scans lines 0..119 ``--scans`` times
  (about 5,500 round trips a scan) and terminates NSTAR.  This process counts
  every NCONT.DT and reply published, from inotify events on jhdata/, against
  the counts the in-process reference run makes; the final POSIT.DT must equal
  the reference bytes.

Run:  python bench/soak.py [--round-trips 10000] [--scans 2] [--part raw estar]
"""

from __future__ import annotations

import argparse
import os
import random
import select
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from diskfmt.layouts import (Command, encode_ncont, decode_bi, CODE_EDGE_MAP,  # noqa: E402
                             CODE_SLICE, CODE_STAR)
from diskfmt.rdos import LinkTimeout                               # noqa: E402
from estar.link import start_file_link                             # noqa: E402
from estar.program import in_process_rig                           # noqa: E402
from rig.session import start_nstar as _start_nstar                # noqa: E402
from nstar.program import Nova                                     # noqa: E402
from rig.scene import bundled_path                                 # noqa: E402

REPLY = {CODE_EDGE_MAP: "WBMAP.DT", CODE_SLICE: "SLICE.DT", CODE_STAR: "BLOCK.DT"}
REPLY_NAMES = ("WBMAP.DT", "SLICE.DT", "BLOCK.DT", "TERM.DT")


def rss_kb(pid: int) -> int | None:
    try:
        with open(f"/proc/{pid}/status") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except FileNotFoundError:
        return None
    return None


def mib(kb: int | None) -> str:
    return "gone" if kb is None else f"{kb / 1024:.1f} MiB"


def start_nstar(jh: Path, timeout: float) -> subprocess.Popen:
    return _start_nstar(jh, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"), "--timeout",
                        str(timeout), quiet=True, idle_timeout=120, stdout=subprocess.DEVNULL,
                        stderr=subprocess.PIPE)


def reference_nova() -> Nova:
    nova = Nova()
    nova.load_pair(decode_bi(bundled_path("LAB-L.BI").read_bytes()),
                   decode_bi(bundled_path("LAB-R.BI").read_bytes()))
    return nova


def wait_ready(jh: Path, proc: subprocess.Popen) -> None:
    """NSTAR creates NSTAR.BSY once its directory is open; the pictures are then
    loaded before it looks for NCONT.DT (a command sent earlier just waits)."""
    deadline = time.monotonic() + 60
    while not (jh / "NSTAR.BSY").exists():
        if proc.poll() is not None or time.monotonic() > deadline:
            raise SystemExit(f"nstar did not start: {proc.stderr.read()}")
        time.sleep(0.01)


def random_command(rng: random.Random, star_share: float, slice_share: float) -> Command:
    r = rng.random()
    image = rng.choice((1, 2))
    if r < star_share:
        return Command(CODE_STAR, image, rng.randrange(10, 118), rng.randrange(10, 110),
                       rng.randrange(5, 40), 0)
    if r < star_share + slice_share:
        return Command(CODE_SLICE, image, 0, rng.randrange(0, 120), 128, 0)
    return Command(CODE_EDGE_MAP, image, rng.randrange(0, 128), rng.randrange(0, 120), 0,
                   rng.choice((-1, 1)))


# --- part 1: raw commands, every reply checked ---------------------------------------

def soak_raw(n: int, seed: int, timeout: float, parent) -> dict:
    with tempfile.TemporaryDirectory(dir=parent) as tmp:
        jh_dir = Path(tmp) / "jhdata"
        jh_dir.mkdir()
        nstar = start_nstar(jh_dir, timeout)
        link = None
        try:
            wait_ready(jh_dir, nstar)
            link = start_file_link(jh_dir, timeout=timeout)   # ESTAR's start-up protocol
            jh = link.jh
            ref = reference_nova()
            rng = random.Random(seed)
            plan = []                                 # commands and the replies they owe
            for _ in range(n):
                cmd = random_command(rng, 0.01, 0.09)
                plan.append((cmd, ref.execute(encode_ncont(cmd))[0]))
            counts = {"sent": 0, "answered": 0, "lost": 0, "duplicated": 0, "wrong": 0}
            by_code = {c: 0 for c in REPLY}
            rss = {"start": (rss_kb(nstar.pid), rss_kb(os.getpid()))}
            lat = []
            t0 = time.perf_counter()
            for i, (cmd, want) in enumerate(plan):
                for name in REPLY_NAMES:              # nothing may be waiting unasked
                    if jh.exists(name):
                        counts["duplicated"] += 1
                        jh.take(name)
                t = time.perf_counter()
                jh.publish("ECONT.DT", "NCONT.DT", encode_ncont(cmd))
                counts["sent"] += 1
                by_code[cmd.code] += 1
                try:
                    jh.wait_for(want.name)
                except LinkTimeout:
                    counts["lost"] += 1
                    break                             # the two programs no longer agree
                got = jh.take(want.name)
                lat.append((cmd.code, time.perf_counter() - t))
                counts["answered"] += 1
                if got != want.data:
                    counts["wrong"] += 1
                if i == 99:
                    rss["after 100"] = (rss_kb(nstar.pid), rss_kb(os.getpid()))
            wall = time.perf_counter() - t0
            rss["end"] = (rss_kb(nstar.pid), rss_kb(os.getpid()))
            time.sleep(0.5)                            # a late duplicate would show now
            counts["duplicated"] += sum(jh.exists(name) for name in REPLY_NAMES)
            jh.publish("ECONT.DT", "NCONT.DT", encode_ncont(Command(-1)))
            jh.wait_for("TERM.DT")
            rc = nstar.wait(timeout=30)
            return {"counts": counts, "by_code": by_code, "wall": wall, "lat": lat,
                    "rss": rss, "nstar_rc": rc, "nstar_err": nstar.stderr.read()}
        finally:
            if link is not None:
                link.close()
            if nstar.poll() is None:
                nstar.kill()
                nstar.wait()


# --- part 2: the real estar program -------------------------------------------------

class Counter(threading.Thread):
    """Arrivals of the public names in jhdata/: both programs publish by a
    no-replace rename (IN_MOVED_TO), or by link(2) where the file system has no
    renameat2 (IN_CREATE) — exactly one event per message either way."""

    def __init__(self, directory: Path):
        from watchdog.observers.inotify_c import (inotify_init, inotify_add_watch,
                                                  InotifyConstants as C)
        super().__init__(daemon=True)
        self.fd = inotify_init()
        inotify_add_watch(self.fd, os.fsencode(directory),
                          C.IN_CREATE | C.IN_MOVED_TO | C.IN_Q_OVERFLOW)
        self.C = C
        self.created: dict[str, int] = {}
        self.first: float | None = None
        self.last: float | None = None
        self.overflow = False
        self.running = True

    def run(self):
        poller = select.poll()
        poller.register(self.fd, select.POLLIN)
        while self.running:
            if not poller.poll(50):
                continue
            buf = os.read(self.fd, 1 << 20)
            now = time.perf_counter()
            off = 0
            while off < len(buf):
                _, mask, _, length = struct.unpack_from("iIII", buf, off)
                name = buf[off + 16:off + 16 + length].rstrip(b"\0").decode()
                off += 16 + length
                if mask & self.C.IN_Q_OVERFLOW:
                    self.overflow = True
                if mask & (self.C.IN_CREATE | self.C.IN_MOVED_TO):
                    self.created[name] = self.created.get(name, 0) + 1
                    if name == "NCONT.DT" and self.first is None:
                        self.first = now
                    if name == "TERM.DT":
                        self.last = now

    def stop(self):
        self.running = False
        self.join(5)
        os.close(self.fd)


def soak_estar(scans: int, timeout: float, parent) -> dict:
    lines = list(range(120)) * scans
    ecl = in_process_rig(None, None, nova=reference_nova())
    for y in lines:
        posit = ecl.lcln(y).posit
    expected = {"NCONT.DT": 2 * len(lines) + ecl.requests + 1, "SLICE.DT": 2 * len(lines),
                "WBMAP.DT": ecl.requests, "TERM.DT": 1, "BLOCK.DT": 0}
    with tempfile.TemporaryDirectory(dir=parent) as tmp:
        jh_dir = Path(tmp) / "jhdata"
        jh_dir.mkdir()
        counter = Counter(jh_dir)
        counter.start()
        nstar = start_nstar(jh_dir, timeout)
        estar = None
        try:
            wait_ready(jh_dir, nstar)
            env = dict(os.environ, PYTHONPATH=str(REPO))
            env.pop("JHDATA", None)
            estar = subprocess.Popen(
                [sys.executable, "-m", "estar.main", "--jhdata", str(jh_dir), "--separation",
                 "0.75", "--virtual-distance", "180", "--debug", "0", "--quiet", "--timeout",
                 str(timeout), "--terminate", "--line", *map(str, lines)],
                env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE, text=True)
            while counter.first is None and estar.poll() is None:
                time.sleep(0.001)
            rss = {"start": (rss_kb(nstar.pid), rss_kb(estar.pid))}
            last = rss["start"]
            while estar.poll() is None:               # the last sample before it exits
                sample = (rss_kb(nstar.pid), rss_kb(estar.pid))
                if None not in sample:
                    last = sample
                    if "after scan 1" not in rss and counter.created.get("SLICE.DT", 0) >= 240:
                        rss["after scan 1"] = sample
                time.sleep(0.05)
            rss["end"] = last
            erc, nrc = estar.wait(), nstar.wait(timeout=30)
            time.sleep(0.3)
        finally:
            counter.stop()
            for p in (estar, nstar):
                if p is not None and p.poll() is None:
                    p.kill()
                    p.wait()
        got = {name: counter.created.get(name, 0) for name in expected}
        return {"expected": expected, "got": got, "lines": len(lines),
                "wall": (counter.last or time.perf_counter()) - (counter.first or 0),
                "rss": rss, "estar_rc": erc, "nstar_rc": nrc, "overflow": counter.overflow,
                "posit_ok": (jh_dir / "POSIT.DT").read_bytes() == posit,
                "estar_err": estar.stderr.read(), "nstar_err": nstar.stderr.read()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--round-trips", type=int, default=10000, help="raw part (default 10000)")
    ap.add_argument("--scans", type=int, default=2, help="estar part: whole-picture scans")
    ap.add_argument("--seed", type=int, default=1985)
    ap.add_argument("--timeout", type=float, default=10.0)
    ap.add_argument("--part", nargs="+", choices=("raw", "estar"), default=["raw", "estar"])
    ap.add_argument("--dir", default=None, help="parent of the jhdata directory "
                                                "(default: the system temp dir)")
    args = ap.parse_args(argv)
    ok = True
    where = args.dir or tempfile.gettempdir()
    fs = subprocess.run(["stat", "-f", "-c", "%T", where], capture_output=True, text=True)
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} CPUs, jhdata under {where} "
          f"({fs.stdout.strip() or 'file system unknown'})")
    if "raw" in args.part:
        r = soak_raw(args.round_trips, args.seed, args.timeout, args.dir)
        c = r["counts"]
        lat = sorted(t for _, t in r["lat"])
        print(f"\nraw: this process as ESTAR, {c['sent']} commands "
              f"(edge maps {r['by_code'][CODE_EDGE_MAP]}, slices {r['by_code'][CODE_SLICE]}, "
              f"Star block maps {r['by_code'][CODE_STAR]}; seed {args.seed})")
        print(f"  answered {c['answered']}, lost {c['lost']}, duplicated {c['duplicated']}, "
              f"wrong bytes {c['wrong']}")
        print(f"  {c['answered'] / r['wall']:.0f} round trips/s ({r['wall']:.2f} s); latency "
              f"median {statistics.median(lat) * 1e3:.3f} ms, p99 "
              f"{lat[int(0.99 * (len(lat) - 1))] * 1e3:.3f} ms, max {lat[-1] * 1e3:.1f} ms")
        for code, name in REPLY.items():
            ts = sorted(t for c, t in r["lat"] if c == code)
            if ts:
                print(f"    {name}: median {statistics.median(ts) * 1e3:.3f} ms, max "
                      f"{ts[-1] * 1e3:.1f} ms")
        for when, (n_kb, me_kb) in r["rss"].items():
            print(f"  VmRSS {when:>12}: nstar {mib(n_kb)}, driver {mib(me_kb)}")
        print(f"  nstar exit {r['nstar_rc']}{'; stderr: ' + r['nstar_err'] if r['nstar_err'] else ''}")
        ok &= (c["lost"] == c["duplicated"] == c["wrong"] == 0 and c["answered"] == args.round_trips
               and r["nstar_rc"] == 0)
    if "estar" in args.part:
        r = soak_estar(args.scans, args.timeout, args.dir)
        e, g = r["expected"], r["got"]
        trips = g["SLICE.DT"] + g["WBMAP.DT"]
        lost = sum(max(0, e[k] - g[k]) for k in e)
        dup = sum(max(0, g[k] - e[k]) for k in e)
        print(f"\nestar: the estar program, {r['lines']} lines ({args.scans} scans of 0..119), "
              f"--terminate")
        print("  published (expected): " + ", ".join(f"{k} {g[k]} ({e[k]})" for k in e))
        print(f"  lost {lost}, duplicated {dup}, POSIT.DT equal to the reference: "
              f"{r['posit_ok']}; inotify overflow: {r['overflow']}")
        print(f"  {trips / r['wall']:.0f} round trips/s ({trips} in {r['wall']:.2f} s, "
              f"{r['lines'] / r['wall']:.1f} lines/s)")
        for when, (n_kb, e_kb) in r["rss"].items():
            print(f"  VmRSS {when:>12}: nstar {mib(n_kb)}, estar {mib(e_kb)}")
        print(f"  exit: estar {r['estar_rc']}, nstar {r['nstar_rc']}"
              + (f"; stderr: {r['estar_err']}{r['nstar_err']}" if r['estar_err'] + r['nstar_err'] else ""))
        ok &= (lost == dup == 0 and r["posit_ok"] and not r["overflow"]
               and r["estar_rc"] == r["nstar_rc"] == 0)
    print("\nresult:", "PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
