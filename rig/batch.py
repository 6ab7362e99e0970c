"""``rig scan`` over many pictures: a list or glob of pairs, or a stereo video
(two files, or one side-by-side file), each frame through PRE's digitizer
model and the eyes' compiled frame scan.

Per frame a CSV of located edges (the columns of ``rig scan --csv``) and,
with ``--ply-frames``, a PLY; ``summary.csv`` has one row per frame (status,
points, edge-map requests, milliseconds, the error of a bad frame) and the
last line of output sums it up.  ``--workers N`` scans chunks of frames in a
pool of N processes; a bad frame is reported and skipped; Ctrl-C stops
cleanly, keeping every finished frame's files and the summary of those.

Pictures: ``.BI`` files are NSTAR's 120x128 pictures as they are; ``.VD``
files are condensed as PRE's command 2 does; anything else (PNG, JPEG, video
frames, ...) goes through ``pre.digitize.digitize`` (grey, fit to 256x240,
16 levels) and is condensed."""

from __future__ import annotations

import csv
import glob
import io
import signal
import sys
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

import numpy as np

SUMMARY_COLUMNS = ["frame", "left", "right", "status", "points", "requests", "scan_ms",
                   "error"]


class BatchError(Exception):
    """Bad batch input: one clear message."""


# --- pictures -------------------------------------------------------------------

def picture_128(img: np.ndarray, fit: str = "crop") -> np.ndarray:
    """Any picture (as OpenCV reads it) -> NSTAR's 120x128 4-bit picture."""
    from pre.condense import condense
    from pre.digitize import digitize
    return condense(digitize(img, fit))


def load_picture(path: str, fit: str = "crop") -> np.ndarray:
    from diskfmt.layouts import decode_bi, decode_vd, read_file
    suffix = Path(path).suffix.lower()
    if suffix == ".bi":
        return decode_bi(read_file(path), path)
    if suffix == ".vd":
        from pre.condense import condense
        return condense(decode_vd(read_file(path), path))
    from pre.digitize import read_source
    return picture_128(read_source(path), fit)


def pairs_from_globs(left_glob: str, right_glob: str) -> list[tuple[str, str]]:
    lefts, rights = sorted(glob.glob(left_glob)), sorted(glob.glob(right_glob))
    if not lefts:
        raise BatchError(f"{left_glob}: matches no file")
    if len(lefts) != len(rights):
        raise BatchError(f"{left_glob} matches {len(lefts)} files but {right_glob} "
                         f"matches {len(rights)}: cannot pair them")
    return list(zip(lefts, rights))


def pairs_from_list(path: str) -> list[tuple[str, str]]:
    """A text file: one pair a line, ``LEFT RIGHT`` (or ``LEFT,RIGHT``); blank
    lines and ``#`` comments skipped; relative names are relative to the file."""
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise BatchError(f"{path}: cannot be read ({exc.strerror})") from None
    out = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.replace(",", " ").split()
        if len(parts) != 2:
            raise BatchError(f"{path}, line {n}: expected two picture names, got {len(parts)}")
        out.append(tuple(str(q if Path(q).is_absolute() else p.parent / q) for q in parts))
    if not out:
        raise BatchError(f"{path}: lists no pair")
    return out


def video_frames(left: str, right: str | None, fit: str = "crop", limit: int | None = None):
    """(index, left128, right128) of each frame of a stereo video: two files,
    or one side-by-side file (left half, right half)."""
    import cv2
    caps = []
    for name in ([left] if right is None else [left, right]):
        if not Path(name).is_file():
            raise BatchError(f"{name}: no such video file")
        cap = cv2.VideoCapture(name)
        if not cap.isOpened():
            raise BatchError(f"{name}: not a video OpenCV can read")
        caps.append(cap)
    try:
        k = 0
        while limit is None or k < limit:
            frames = [cap.read() for cap in caps]
            if not all(ok for ok, _ in frames):
                return
            if right is None:
                img = frames[0][1]
                half = img.shape[1] // 2
                yield k, img[:, :half], img[:, half:2 * half]
            else:
                yield k, frames[0][1], frames[1][1]
            k += 1
    finally:
        for cap in caps:
            cap.release()


def digitized(frames, names, fit: str = "crop"):
    """Items of video frames digitized here, in the reading process: a worker
    then gets two 120x128 pictures (30 kB) instead of a raw frame.  A frame
    the digitizer refuses becomes an item carrying its error."""
    for k, left, right in frames:
        try:
            yield k, picture_128(left, fit), picture_128(right, fit), names, False
        except Exception as exc:          # reported in the summary, the others go on
            yield k, exc, exc, names, False


def video_length(left: str) -> int | None:
    import cv2
    cap = cv2.VideoCapture(left)
    n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
    cap.release()
    return n if n > 0 else None


# --- one frame, one chunk ----------------------------------------------------------

@dataclass(frozen=True)
class Settings:
    out: str
    lines: tuple[int, ...]
    ds: str = "0.75"
    dv: str = "180"
    marf_sign_fix: bool = False
    fit: str = "crop"
    ply: bool = False


_EYES = {}


def _eyes(s: Settings):
    key = (s.ds, s.dv, s.marf_sign_fix)
    if key not in _EYES:
        from estar.masl import Options
        from eyes import Eyes
        _EYES[key] = Eyes(s.ds, s.dv, Options(marf_sign_fix=s.marf_sign_fix))
    return _EYES[key]


def frame_name(k: int) -> str:
    return f"frame-{k:06d}"


def scan_one(k: int, left, right, names, raw: bool, s: Settings) -> dict:
    """Scan one frame — two paths of pictures, or (``raw``) two pictures still
    to be digitized — and write its files."""
    from rig.scan import ply_text, write_atomic
    row = {"frame": k, "left": names[0], "right": names[1], "status": "ok", "points": 0,
           "requests": 0, "scan_ms": "", "error": ""}
    try:
        if isinstance(left, Exception):         # the frame could not be digitized
            raise left
        if isinstance(left, str):
            left = load_picture(left, s.fit)
        if isinstance(right, str):
            right = load_picture(right, s.fit)
        if raw:
            left, right = picture_128(left, s.fit), picture_128(right, s.fit)
        t = time.perf_counter()
        result = _eyes(s).scan(left, right, s.lines)
        row["scan_ms"] = f"{(time.perf_counter() - t) * 1000:.3f}"
        row["points"] = len(result.point_rows)
        row["requests"] = int(result.requests.sum())
        write_atomic(Path(s.out) / f"{frame_name(k)}.csv", result.csv_text())
        if s.ply:
            write_atomic(Path(s.out) / f"{frame_name(k)}.ply",
                         ply_text(result.scan_result().points))
    except Exception as exc:          # a bad frame is reported, the others go on
        row["status"] = "error"
        row["error"] = f"{type(exc).__name__}: {exc}"
    return row


def scan_chunk(items, s: Settings) -> tuple[list[dict], int]:
    """Scan a chunk of items; returns the rows and this process's resident
    memory (kB)."""
    rows = [scan_one(*item, s) for item in items]
    return rows, rss_kb()


def rss_kb(pid: int | str = "self") -> int:
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def _start_worker() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)     # the parent handles Ctrl-C
    from eyes import Eyes                            # load the compiled kernels now
    flat = np.zeros((120, 128), dtype=np.uint8)
    Eyes().scan(flat, flat, [60])


# --- the run ------------------------------------------------------------------------

@dataclass
class BatchResult:
    rows: list[dict]
    seconds: float
    interrupted: bool
    first_seconds: float          # until the first chunk came back (pool start included)
    first_frames: int
    worker_rss_kb: list[int]
    parent_rss_kb: int

    @property
    def steady_fps(self) -> float:
        """Frames per second after the first chunk (the pool running)."""
        n = len(self.rows) - self.first_frames
        t = self.seconds - self.first_seconds
        return n / t if n > 0 and t > 0 else float("nan")

    @property
    def ok(self) -> int:
        return sum(r["status"] == "ok" for r in self.rows)

    @property
    def bad(self) -> int:
        return sum(r["status"] != "ok" for r in self.rows)


def chunks(items, size: int):
    chunk = []
    for item in items:
        chunk.append(item)
        if len(chunk) >= size:
            yield chunk
            chunk = []
    if chunk:
        yield chunk


def run(items, s: Settings, workers: int = 1, chunk: int = 16, total: int | None = None,
        progress: bool = True) -> BatchResult:
    """Scan every (index, left, right, names, raw) item; files in ``s.out``.
    ``raw``: the pictures are arrays still to be digitized (video frames)."""
    Path(s.out).mkdir(parents=True, exist_ok=True)
    rows: list[dict] = []
    rss: list[int] = []
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=total, desc="scanning frames", unit="frame", file=sys.stderr)
    t0 = time.perf_counter()
    interrupted = False
    first_chunk: list = []
    try:
        if workers <= 1:
            for item in items:
                rows.append(scan_one(*item, s))
                if len(rows) == min(chunk, total or chunk):
                    first_chunk[:] = [time.perf_counter(), len(rows)]
                if bar:
                    bar.update(1)
            rss.append(rss_kb())
        else:
            interrupted = _run_pool(items, s, workers, chunk, rows, rss, bar, first_chunk)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        if bar:
            bar.close()
    seconds = time.perf_counter() - t0
    first = first_chunk[0] - t0 if first_chunk else seconds
    nfirst = first_chunk[1] if first_chunk else len(rows)
    rows.sort(key=lambda r: r["frame"])
    result = BatchResult(rows, seconds, interrupted, first, nfirst, rss, rss_kb())
    write_summary(Path(s.out) / "summary.csv", rows)
    return result


def _run_pool(items, s, workers, chunk, rows, rss, bar, first_chunk) -> bool:
    """Chunks to a pool of ``workers`` processes, at most two chunks a worker
    queued (a video is read as it goes).  Returns True when interrupted: the
    chunks not started are cancelled, those running are finished and kept."""
    with ProcessPoolExecutor(max_workers=workers, initializer=_start_worker) as pool:
        pending = set()
        try:
            for part in chunks(items, chunk):
                pending.add(pool.submit(scan_chunk, part, s))
                while len(pending) >= 2 * workers:
                    pending = _collect(pending, rows, rss, bar, first_chunk)
            while pending:
                pending = _collect(pending, rows, rss, bar, first_chunk)
            return False
        except KeyboardInterrupt:
            for f in pending:
                f.cancel()
            for f in pending:
                if not f.cancelled():
                    try:
                        got, kb = f.result()
                    except Exception:
                        continue
                    rows.extend(got)
                    rss.append(kb)
            return True


def _collect(pending, rows, rss, bar, first_chunk):
    done, pending = wait(pending, return_when=FIRST_COMPLETED)
    for f in done:
        got, kb = f.result()
        rows.extend(got)
        if not first_chunk:
            first_chunk[:] = [time.perf_counter(), len(rows)]
        rss.append(kb)
        if bar:
            bar.update(len(got))
    return pending


def write_summary(path: Path, rows: list[dict]) -> None:
    from rig.scan import write_atomic
    buf = io.StringIO()
    w = csv.DictWriter(buf, SUMMARY_COLUMNS, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    write_atomic(path, buf.getvalue())


# --- the command -----------------------------------------------------------------

def add_arguments(s) -> None:
    """``rig scan``'s options for many pictures."""
    g = s.add_argument_group("many pictures (the eyes' compiled scan, one CSV per frame)")
    g.add_argument("--pairs", nargs=2, metavar=("LEFT_GLOB", "RIGHT_GLOB"),
                   help="scan every pair: the files matching each glob, sorted and paired "
                        "in order (quote the globs)")
    g.add_argument("--pair-list", metavar="FILE",
                   help="scan the pairs listed in FILE, one 'LEFT RIGHT' a line")
    g.add_argument("--video", nargs="+", metavar="VIDEO",
                   help="scan a stereo video: LEFT RIGHT (two files) or one side-by-side "
                        "file (left half, right half)")
    g.add_argument("--frames", type=int, metavar="N", help="at most N frames of the video")
    g.add_argument("--out", default="scan-out", metavar="DIR",
                   help="where the per-frame CSVs and summary.csv go (default ./scan-out)")
    g.add_argument("--ply-frames", action="store_true", help="also one PLY per frame")
    g.add_argument("--fit", choices=("crop", "stretch", "pad"), default="crop",
                   help="how the digitizer fits a picture to 256x240 (default crop)")
    g.add_argument("--workers", type=int, default=1, metavar="N",
                   help="scan in N processes (default 1)")
    g.add_argument("--chunk", type=int, default=16, metavar="K",
                   help="frames handed to a worker at a time (default 16)")


def wants_batch(args) -> bool:
    return bool(args.pairs or args.pair_list or args.video)


def cmd_batch(args, lines) -> int:
    if sum(bool(x) for x in (args.pairs, args.pair_list, args.video)) > 1:
        raise SystemExit("rig: give one of --pairs, --pair-list, --video")
    if (args.left or args.right or args.link == "file" or args.engine == "reference"
            or args.match != "1985"):
        raise SystemExit("rig: --pairs/--pair-list/--video scan with the eyes (the 1985 "
                         "matcher) over no link; drop --left/--right/--link file/"
                         "--engine reference/--match improved")
    if args.workers < 1 or args.chunk < 1:
        raise SystemExit("rig: --workers and --chunk must be at least 1")
    s = Settings(str(args.out), tuple(lines), args.separation, args.virtual_distance,
                 args.marf_sign_fix, args.fit, args.ply_frames)
    try:
        if args.video:
            if len(args.video) > 2:
                raise BatchError("--video takes one side-by-side file or two files")
            right = args.video[1] if len(args.video) == 2 else None
            total = video_length(args.video[0])
            if args.frames is not None:
                total = min(total or args.frames, args.frames)
            names = (args.video[0], right or args.video[0])
            items = digitized(video_frames(args.video[0], right, args.fit, args.frames),
                              names, args.fit)
        else:
            pairs = (pairs_from_globs(*args.pairs) if args.pairs
                     else pairs_from_list(args.pair_list))
            total = len(pairs)
            items = ((k, l, r, (l, r), False) for k, (l, r) in enumerate(pairs))
        result = run(items, s, args.workers, args.chunk, total, progress=not args.quiet)
    except BatchError as exc:
        print(f"rig: {exc}", file=sys.stderr)
        return 1
    for r in result.rows:
        if r["status"] != "ok":
            print(f"rig: frame {r['frame']} ({r['left']}, {r['right']}) skipped: {r['error']}",
                  file=sys.stderr)
    n = len(result.rows)
    points = sum(r["points"] for r in result.rows)
    print(f"{result.ok} frames scanned, {result.bad} bad, {points} located edges in "
          f"{result.seconds:.2f} s ({n / max(result.seconds, 1e-9):.1f} frames/s, "
          f"{args.workers} worker{'s' if args.workers > 1 else ''}); "
          f"summary: {Path(s.out) / 'summary.csv'}"
          + ("; interrupted (Ctrl-C): the frames above are kept" if result.interrupted else ""))
    if result.interrupted:
        return 130
    return 0 if result.bad == 0 else 2
