"""The eyes' Python face: one call scans a whole picture pair.

:class:`Eyes` holds one calibration (DSEP, DVIRT), the MASL options and
LCSL's memo tables; :meth:`Eyes.scan` runs :func:`eyes.kernels.scan_frame_kernel`
over the lines and returns a :class:`FrameScan` of plain arrays.  A
:class:`FrameScan` turns into the reference path's objects on request
(:meth:`FrameScan.line_results`, :meth:`FrameScan.scan_result`) — the same
``LineResult``/``ScanResult`` that ``Eclipse.lcln`` and :mod:`rig.scan` give,
which is how the tests compare the two paths value for value."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from diskfmt.dgreal import DGRealError, Real
from diskfmt.layouts import POSIT_BYTES
from estar.lcsl import EDISP, EDMAX, ELMAX, ONE
from estar.masl import Options as MaslOptions
from estar.program import LineResult
from .dgint import mq
from .kernels import build_frame, new_tables, new_windows, scan_frame_kernel

DEFAULT_LINES = range(8, 113)          # Appendix C: "in the range 8 to 112"
# The entry LCSL took, where LineResult records it ("used")
LINE_RESULT_FIELDS = {f.name for f in fields(LineResult)}
assert ELMAX == EDMAX                  # one offset table serves DX/EXMAX and DY/EYMAX


def words_to_float(words) -> np.ndarray:
    """DG REAL storage words -> float64 (exact: 24-bit fractions)."""
    w = np.asarray(words, dtype=np.int64)
    frac = (w & 0xFFFFFF).astype(np.float64)
    exp = (w >> 24) & 0x7F
    sign = np.where(w & 0x80000000, -1.0, 1.0)
    return sign * np.ldexp(frac, (4 * (exp - 64) - 24).astype(np.int32))


@dataclass
class FrameScan:
    """What one whole-picture scan produced, as arrays (see
    :func:`eyes.kernels.scan_frame_kernel` for the layout)."""
    lines: np.ndarray            # (n,) IY of each line, in scan order
    nfeat: np.ndarray            # (n, 2) NFEAT of slice 1 and slice 2
    ifeat: np.ndarray            # (n, 2, 4, 50) int16: IFEAT of both slices
    requests: np.ndarray         # (n,) NBLOB round trips
    match_start: np.ndarray      # (n+1,)
    match_rows: np.ndarray       # (M, 5) int32: edge, INDX, QUAL, LOC1, LOC2
    point_start: np.ndarray      # (n+1,)
    point_rows: np.ndarray       # (P, 6) int32: line, edge, LOC1, LOC2, INDX, QUAL of the entry taken
    point_words: np.ndarray      # (P, 6) uint32: POS(1..6) storage words
    posit_words: np.ndarray      # (n, 640) /POSIT/ after each line, or (1, 640) after the last

    @property
    def point_values(self) -> np.ndarray:
        """(P, 6) dp, dx, dy, ep, ex, ey as float64."""
        return words_to_float(self.point_words)

    def posit(self, k: int = -1) -> bytes:
        """The POSIT.DT image PNPL writes after line ``k`` (kept for every line
        only when scanned with ``keep_posit=True``; else the last)."""
        if self.posit_words.shape[0] != len(self.lines) and k not in (-1, len(self.lines) - 1):
            raise ValueError("scanned without keep_posit: only the last POSIT.DT is kept")
        words = self.posit_words[k if self.posit_words.shape[0] == len(self.lines) else -1]
        np_ = int(self.nfeat[k, 0])
        return (np_.to_bytes(2, "big", signed=True)
                + words.astype(">u4").tobytes())[:POSIT_BYTES]

    def features(self, k: int, image: int) -> list[tuple[int, int, int, int]]:
        """The feature list of slice ``image`` (1, 2) on line ``k``, as
        ``Slice.features()`` gives it."""
        n = int(self.nfeat[k, image - 1])
        t = self.ifeat[k, image - 1]
        return [tuple(int(t[j, i]) for j in range(4)) for i in range(n)]

    def line_results(self) -> list:
        """The reference path's ``LineResult`` of every line."""
        out = []
        values = self.point_values
        for k, iy in enumerate(self.lines.tolist()):
            nfeat1 = int(self.nfeat[k, 0])
            edges = [e for i in range(1, nfeat1 + 1) for e in (i, i + 50)]
            matches = {e: [] for e in edges}
            for row in self.match_rows[self.match_start[k]:self.match_start[k + 1]].tolist():
                matches[row[0]].append(tuple(row[1:]))
            positions = {e: None for e in edges}
            used = {}
            for p in range(self.point_start[k], self.point_start[k + 1]):
                line, edge, loc1, loc2, indx, qual = self.point_rows[p].tolist()
                positions[edge] = tuple(float(v) for v in values[p])
                used[edge] = (indx, qual, loc1, loc2)
            posit = self.posit(k) if self.posit_words.shape[0] == len(self.lines) else (
                self.posit() if k == len(self.lines) - 1 else b"")
            extra = {"used": used} if "used" in LINE_RESULT_FIELDS else {}
            out.append(LineResult(iy, self.features(k, 1), self.features(k, 2), matches,
                                  positions, posit, int(self.requests[k]), **extra))
        return out

    def scan_result(self):
        """A :class:`rig.scan.ScanResult`, as ``rig.scan.scan_pair`` returns."""
        from rig.scan import ScanResult, points_of_line
        results = self.line_results()
        points = [p for r in results for p in points_of_line(r)]
        return ScanResult([int(y) for y in self.lines], results, points,
                          int(self.requests.sum()))

    def csv_text(self) -> str:
        """The located edges as :func:`rig.scan.csv_text` writes them, from the
        arrays.  A POS value is one of few storage words (LCSL's terms), so
        each word's text is made once per process; the rows are formatted in
        one operation."""
        from rig.scan import CSV_COLUMNS
        n = len(self.point_rows)
        table = np.empty((n, 14), dtype=object)
        rows = self.point_rows
        table[:, 0:4] = rows[:, 0:4]
        table[:, 4] = rows[:, 2] - rows[:, 3]
        table[:, 5:11] = _word_texts(self.point_words)
        table[:, 11:14] = _word_texts(self.point_words[:, 3:6], squared_half=True)
        head = ",".join(CSV_COLUMNS) + "\n"
        return head + ("%d,%d,%d,%d,%d,%s,%s,%s,%s,%s,%s,%s,%s,%s\n" * n) % tuple(
            table.ravel().tolist())


_TEXT: dict[int, str] = {}
_TEXT_VAR: dict[int, str] = {}


def _word_texts(words: np.ndarray, squared_half: bool = False) -> np.ndarray:
    """``repr`` of the float of each storage word (or of the A-20 variance
    ``(v/2)**2``), as an object array of the same shape; memoised."""
    memo = _TEXT_VAR if squared_half else _TEXT
    unique, inverse = np.unique(words, return_inverse=True)
    missing = [w for w in unique.tolist() if w not in memo]
    if missing:
        values = words_to_float(np.array(missing, dtype=np.int64)).tolist()
        for w, v in zip(missing, values):
            memo[w] = repr((v / 2) ** 2) if squared_half else repr(v)
    texts = np.array([memo[w] for w in unique.tolist()] + [""], dtype=object)
    return texts[inverse.reshape(words.shape)] if len(unique) else np.empty(words.shape, object)


_DEFAULT_LINE_ARRAY = np.arange(DEFAULT_LINES.start, DEFAULT_LINES.stop, dtype=np.int64)
_DEFAULT_LINE_ARRAY.flags.writeable = False


def _line_array(lines) -> np.ndarray:
    """``lines`` as a 1-D int64 array (the default range without building it)."""
    if isinstance(lines, range):
        if lines == DEFAULT_LINES:
            return _DEFAULT_LINE_ARRAY
        return np.arange(lines.start, lines.stop, lines.step, dtype=np.int64)
    return np.asarray(list(lines), dtype=np.int64).reshape(-1)


def checked_scan(left, right, lines):
    """(left, right, lines) of a scan as arrays, or one ValueError naming what
    is wrong: a picture not 120x128, a line outside 0..119."""
    left, right = np.asarray(left), np.asarray(right)
    for name, pic in (("left", left), ("right", right)):
        if pic.shape != (120, 128):
            raise ValueError(f"{name} picture is {pic.shape}, expected (120, 128)")
    lines = _line_array(lines)
    if len(lines) and (lines.min() < 0 or lines.max() > 119):
        raise ValueError("lines must lie within 0..119")
    return left, right, lines


class Eyes:
    """The compiled frame scan for one calibration: ``Eyes(ds, dv).scan(left,
    right)`` gives what ``rig.scan.scan_pair(left, right, lines, ds, dv)``
    gives, as arrays.  Reuse one object for many frames: LCSL's terms are
    computed once per disparity and offset."""

    def __init__(self, ds: str | Real = "0.75", dv: str | Real = "180",
                 options: MaslOptions | None = None):
        self.dsep = ds if isinstance(ds, Real) else Real.const(ds)
        self.dvirt = dv if isinstance(dv, Real) else Real.const(dv)
        if self.dvirt.m == 0:
            raise ValueError("DVIRT (virtual distance) must not be zero")
        self.options = options or MaslOptions()
        dcons = self.dsep * self.dvirt
        dvi = ONE / self.dvirt
        self.consts = np.array([*mq(dcons), *mq(dvi), *mq(EDISP), *mq(ELMAX)], dtype=np.int64)
        self.tables = new_tables()
        self._rows = None
        self._frame = None
        self._windows = new_windows()

    def scan(self, left, right, lines=DEFAULT_LINES, keep_posit: bool = False) -> FrameScan:
        """Scan the 120x128 pair over ``lines`` (0..119, any order) as one fresh
        ESTAR and NSTAR would (COMMON blocks start empty)."""
        left, right, lines = checked_scan(left, right, lines)
        n = len(lines)
        self._frame = frame = build_frame(left, right, self._frame)
        nmatch = np.zeros(100, dtype=np.int64)
        imatch = np.zeros((100, 10, 4), dtype=np.int64)
        pos = np.zeros(640, dtype=np.int64)
        # written whole by the kernel, line by line: no clearing
        nfeat = np.empty((n, 2), dtype=np.int64)
        ifeat = np.empty((n, 2, 4, 50), dtype=np.int16)     # the Nova's 16-bit words
        requests = np.empty(n, dtype=np.int64)
        match_start = np.empty(n + 1, dtype=np.int64)
        point_start = np.empty(n + 1, dtype=np.int64)
        if self._rows is None or len(self._rows[1]) < n * 100:
            # work space for the rows, kept between scans (its pages stay mapped);
            # 32-bit, as every value fits: half the bytes to write and copy out
            self._rows = (np.empty((n * 1000, 5), dtype=np.int32),
                          np.empty((n * 100, 6), dtype=np.int32),
                          np.empty((n * 100, 6), dtype=np.uint32))
        match_rows, point_rows, point_words = self._rows
        posit_words = np.empty((n if keep_posit else 0, 640), dtype=np.int64)
        t = self.tables
        status = scan_frame_kernel(
            frame, self._windows, lines, bool(self.options.marf_sign_fix), self.consts,
            t["range_done"], t["range_mq"], t["offset_done"], t["offset_words"],
            nmatch, imatch, pos, nfeat, ifeat, requests, match_start, match_rows,
            point_start, point_rows, point_words, posit_words)
        if status != 0:
            raise DGRealError("POSIT.DT: a located position is outside the DG REAL range")
        m, p = match_start[n], point_start[n]
        return FrameScan(lines, nfeat, ifeat, requests, match_start, match_rows[:m].copy(),
                         point_start, point_rows[:p].copy(), point_words[:p].copy(),
                         posit_words if keep_posit else pos[None, :].copy())


def scan_pair(left, right, lines=DEFAULT_LINES, ds: str = "0.75", dv: str = "180",
              options: MaslOptions | None = None):
    """``rig.scan.scan_pair`` through the eyes: the same ``ScanResult``."""
    return Eyes(ds, dv, options).scan(left, right, lines, keep_posit=True).scan_result()
