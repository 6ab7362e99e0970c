"""What ``rig`` checks before it starts work: option values, input files,
output paths (each problem one line naming the option or file), and warnings
on a pair that would run but cannot give sensible ranges.

Pure functions; :class:`UsageError` carries the one-line message.
"""

from __future__ import annotations

import math
import os
from decimal import Decimal, InvalidOperation
from pathlib import Path

import numpy as np

from diskfmt.layouts import BI_COLS, BI_ROWS
from pre.files import PreError, load_bi

PICTURE_SUFFIXES = (".png", ".jpg", ".jpeg")
MAX_SHIFT = 40                   # the widest whole-row shift tried (128-px rows)


class UsageError(ValueError):
    """A bad option value or file, said in one line."""


def positive_number(text: str, option: str, meaning: str) -> str:
    """``text`` if it is a finite number above 0 (returned as given: ESTAR takes
    the decimal text, as its ACCEPT did), else :class:`UsageError`."""
    try:
        value = Decimal(str(text).strip())
    except InvalidOperation:
        raise UsageError(f"{option} {text}: not a number ({meaning})") from None
    if not value.is_finite() or value <= 0:
        raise UsageError(f"{option} {text}: must be a number above 0 ({meaning})")
    return str(text).strip()


def check_lines(lines: list[int], option: str) -> list[int]:
    """Lines to scan: at least one, each an epipolar line 0..119."""
    if not lines:
        raise UsageError(f"{option}: no lines (give FIRST <= LAST, or --line Y ...)")
    bad = [y for y in lines if not 0 <= y < BI_ROWS]
    if bad:
        raise UsageError(f"lines must lie within 0..{BI_ROWS - 1} (got {bad})")
    return lines


def load_truth(path) -> np.ndarray:
    """A true-range array: a .npy of 120 rows x 128 columns, finite or NaN."""
    try:
        truth = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        raise UsageError(f"--truth {path}: no such file") from None
    except IsADirectoryError:
        raise UsageError(f"--truth {path}: is a directory, not a .npy file") from None
    except PermissionError:
        raise UsageError(f"--truth {path}: cannot be read (permission denied)") from None
    except (ValueError, OSError, EOFError):
        raise UsageError(f"--truth {path}: not a NumPy .npy file (make one with numpy.save "
                         f"of a 120x128 array of true ranges)") from None
    if not isinstance(truth, np.ndarray) or truth.shape != (BI_ROWS, BI_COLS):
        shape = getattr(truth, "shape", "?")
        raise UsageError(f"--truth {path}: shape {shape}, expected ({BI_ROWS}, {BI_COLS}): one "
                         f"true range per left-picture pixel, rows top to bottom")
    if not np.issubdtype(truth.dtype, np.number):
        raise UsageError(f"--truth {path}: holds {truth.dtype}, not numbers")
    return truth.astype(np.float64)


def check_output_file(path, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """An output file name that can be written: not a directory, in a directory
    that exists and is writable, with one of ``suffixes`` when given."""
    p = Path(path)
    if p.is_dir():
        raise UsageError(f"{option} {path}: is a directory; give a file name")
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise UsageError(f"{option} {path}: can write {' or '.join(suffixes)} "
                         f"(the name says {p.suffix or 'nothing'})")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"{option} {path}: directory {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UsageError(f"{option} {path}: directory {parent} is not writable")
    if p.exists() and not os.access(p, os.W_OK):
        raise UsageError(f"{option} {path}: exists and is not writable")
    return p


def check_output_dir(path, option: str) -> Path:
    """A directory for outputs: made if missing; refused if a file or unwritable."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise UsageError(f"{option} {path}: is a file, not a directory")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"{option} {path}: cannot make the directory "
                         f"({exc.strerror})") from None
    if os.statvfs(p).f_flag & os.ST_RDONLY:
        raise UsageError(f"{option} {path}: directory is on a read-only file system")
    if not os.access(p, os.W_OK | os.X_OK):
        raise UsageError(f"{option} {path}: directory is not writable")
    return p


def load_picture(path, option: str) -> np.ndarray:
    """A .BI picture for ``--left``/``--right``; other files are named for what they are."""
    try:
        return load_bi(path)
    except PreError as exc:
        raise UsageError(f"{option} {exc}") from None


# --- nonsense that would run ----------------------------------------------------

def row_shift(left_row, right_row, max_shift: int = MAX_SHIFT) -> int:
    """The whole-row shift d (-max_shift..max_shift) that best lays the right
    row on the left one: right[x - d] ~ left[x] (least mean absolute grey
    difference over the overlap).  A point in front of the cameras has d > 0."""
    a = np.asarray(left_row, dtype=np.int32)
    b = np.asarray(right_row, dtype=np.int32)
    best, best_d = math.inf, 0
    for d in range(-max_shift, max_shift + 1):
        if d >= 0:
            cost = np.abs(a[d:] - b[:len(b) - d]).mean()
        else:
            cost = np.abs(a[:d] - b[-d:]).mean()
        if cost < best or (cost == best and abs(d) < abs(best_d)):
            best, best_d = cost, d
    return best_d


def impossible_share(left, right, lines) -> tuple[float, int]:
    """Of the ``lines`` with any grey change in both pictures, the share whose
    best whole-row shift is 0 or negative (the right picture's content at or
    right of the left's: no point in front of the cameras lies so), and how
    many lines were judged."""
    judged = impossible = 0
    for y in lines:
        lrow, rrow = np.asarray(left)[y], np.asarray(right)[y]
        if np.ptp(lrow) == 0 or np.ptp(rrow) == 0:
            continue
        judged += 1
        impossible += row_shift(lrow, rrow) <= 0
    return (impossible / judged if judged else 0.0), judged


def pair_warnings(left, right, lines=range(8, 113)) -> list[str]:
    """Warnings for a pair the rig would scan without complaint but cannot
    range: identical pictures, a blank picture, a pair that looks swapped."""
    left, right = np.asarray(left), np.asarray(right)
    out = []
    for name, pic in (("left", left), ("right", right)):
        if np.ptp(pic) == 0:
            out.append(f"the {name} picture is blank (every pixel grey {int(pic.flat[0])}): "
                       f"it has no edges to match")
    if out:
        return out
    if np.array_equal(left, right):
        return ["the left and right pictures are identical: every true disparity is 0, so "
                "every edge located pairs an edge with another one (give two pictures taken "
                "a camera separation apart)"]
    share, judged = impossible_share(left, right, lines)
    if judged >= 5 and share > 0.5:
        out.append(f"the pair looks swapped: on {share:.0%} of {judged} lines the right "
                   f"picture's content lies at or right of the left's, which no point in "
                   f"front of the cameras gives; swap --left and --right")
    return out


def blank_service_warning(results) -> str | None:
    """NSTAR served slices with no features on every line of a scan: its frame
    store is blank (or flat), not the pair the user meant."""
    if results and all(not r.features1 and not r.features2 for r in results):
        return (f"NSTAR's slices had no edges on any of the {len(results)} lines: its "
                f"pictures look blank (was nstar given --left and --right, or new images?)")
    return None
