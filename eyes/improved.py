"""The improved matcher (package ``matching``, not 1985) on the eyes' compiled
line source: the drive's scan of a look (``planner.loop.scan_look(...,
"improved")``).

Through ESTAR (``rig.scan.scan_pair(..., matcher=make_matcher("improved"))``)
the matcher asks NSTAR, over the link, for the slices and edge maps of every
line within 22 of a scanned one, and ESTAR runs CFEAT, MASL and LCSL in
Python around it.  Here :func:`eyes.kernels.frame_lines_kernel` makes every
line's slices and maps in one compiled pass, the matcher judges the lines from
them (under its default rules compiled over the whole frame,
:func:`matching.frame.frame_verdicts`; under any other,
:meth:`matching.mode.ImprovedMatcher.frame_verdicts`), and LCSL runs
compiled (:func:`eyes.kernels.lcsl_line`) on the verdicts' tables, COMMON
/POSIT/ carried from line to line as ESTAR carries it.  The result is the
``ScanResult`` the ESTAR path gives, line for line (tests/test_eyes_improved.py),
except ``ScanResult.requests``: ESTAR's count of NBLOB round trips includes
the matcher's fetches, which depend on its cache; here it is MASL's alone.
"""

from __future__ import annotations

import numpy as np

from diskfmt.dgreal import DGRealError
from diskfmt.layouts import POSIT_BYTES
from estar.program import LineResult
from matching.verdict import LineData
from .frame import DEFAULT_LINES, Eyes, checked_scan, words_to_float
from .kernels import build_frame, frame_lines_kernel, lcsl_line

LINES = 120


def frame_arrays(frame: np.ndarray, windows: np.ndarray):
    """(nfeat (120, 2), ifeat (120, 2, 4, 50), maps (120, 2, 100, 17), MASL's NBLOB
    requests per line (120,)) of the frame store ``frame``
    (:func:`eyes.kernels.build_frame`): :func:`eyes.kernels.frame_lines_kernel`'s."""
    nfeat = np.empty((LINES, 2), dtype=np.int64)
    ifeat = np.empty((LINES, 2, 4, 50), dtype=np.int32)
    maps = np.empty((LINES, 2, 100, 17), dtype=np.int64)
    requests = np.empty(LINES, dtype=np.int64)
    frame_lines_kernel(frame, windows, nfeat, ifeat, maps, requests)
    return nfeat, ifeat, maps, requests


def line_data(y: int, nfeat, ifeat, maps) -> LineData:
    """Line y of :func:`frame_arrays` as :func:`matching.mode.fetch_line` gets it
    from NSTAR."""
    n, table = nfeat[y].tolist(), ifeat[y].tolist()
    return LineData(y, list(zip(*(row[:n[0]] for row in table[0]))),
                    list(zip(*(row[:n[1]] for row in table[1]))), maps[y, 0], maps[y, 1])


def frame_lines(frame: np.ndarray, windows: np.ndarray) -> tuple[list[LineData], np.ndarray]:
    """(every line's :class:`matching.verdict.LineData`, as
    :func:`matching.mode.fetch_line` gets it from NSTAR; MASL's NBLOB requests
    per line) of the frame store ``frame`` (:func:`eyes.kernels.build_frame`)."""
    nfeat, ifeat, maps, requests = frame_arrays(frame, windows)
    return [line_data(y, nfeat, ifeat, maps) for y in range(LINES)], requests


class ImprovedEyes(Eyes):
    """``ImprovedEyes(ds, dv).scan(left, right, lines, matcher)``: the scan
    ``rig.scan.scan_pair(left, right, lines, ds, dv, matcher=matcher)`` gives
    (see the module docstring).  ``matcher``: a fresh
    :class:`matching.mode.ImprovedMatcher` (None: the default constraints)."""

    def scan(self, left, right, lines=DEFAULT_LINES, matcher=None):
        from matching.frame import covers, frame_verdicts
        from matching.mode import VerdictTables, make_matcher
        from rig.scan import ScanResult, points_of_line
        left, right, lines = checked_scan(left, right, lines)
        if matcher is None:
            matcher = make_matcher("improved")
        if matcher.constraints.subpixel:
            raise ValueError("the subpixel constraint needs the .VD pictures (use rig scan)")
        self._frame = frame = build_frame(left, right, self._frame)
        nfeat, ifeat, maps, requests = frame_arrays(frame, self._windows)
        if covers(matcher.constraints, matcher.params):   # the default rules, compiled
            verdicts = frame_verdicts(nfeat, ifeat, maps, lines.tolist(), matcher.params)
            data = {y: line_data(y, nfeat, ifeat, maps) for y in lines.tolist()}
        else:
            data = [line_data(y, nfeat, ifeat, maps) for y in range(LINES)]
            verdicts = matcher.frame_verdicts(data, lines.tolist())
        pos = np.zeros(640, dtype=np.int64)
        nmatch = np.zeros(100, dtype=np.int64)
        imatch = np.zeros((100, 10, 4), dtype=np.int64)
        point_rows = np.empty((100, 6), dtype=np.int32)
        point_words = np.empty((100, 6), dtype=np.uint32)
        t = self.tables
        results, points = [], []
        for y, judged in zip(lines.tolist(), verdicts):
            d = data[y]
            nfeat1 = len(d.features1)
            edges = [e for k in range(1, nfeat1 + 1) for e in (k, k + 50)]
            # the verdicts' tables, as LCSL reads them through ESTAR, as COMMON /MATCH/
            tables = VerdictTables(judged)
            entries = {e: tables.entries(e) for e in edges}
            nmatch[:] = 0
            for e, rows in entries.items():
                nmatch[e - 1] = len(rows)
                if rows:
                    imatch[e - 1, 0] = rows[0]
            npt = lcsl_line(y, nfeat1, nmatch, imatch, self.consts, t["range_done"],
                            t["range_mq"], t["offset_done"], t["offset_words"], pos,
                            point_rows, point_words, 0)
            if npt < 0:
                raise DGRealError("POSIT.DT: a located position is outside the DG REAL range")
            positions = {e: None for e in edges}
            used = {}
            for row, values in zip(point_rows[:npt].tolist(),
                                   words_to_float(point_words[:npt]).tolist()):
                _line, edge, loc1, loc2, indx, qual = row
                positions[edge] = tuple(values)
                used[edge] = (indx, qual, loc1, loc2)
            posit = (nfeat1.to_bytes(2, "big", signed=True)
                     + pos.astype(">u4").tobytes())[:POSIT_BYTES]
            r = LineResult(y, d.features1, d.features2, entries, positions, posit,
                           int(requests[y]), used, d.maps1, d.maps2, judged)
            results.append(r)
            points.extend(points_of_line(r))
        return ScanResult([int(y) for y in lines], results, points,
                          int(requests[lines].sum()))


def scan_pair(left, right, lines=DEFAULT_LINES, ds: str = "0.75", dv: str = "180",
              matcher=None):
    """``rig.scan.scan_pair(left, right, lines, ds, dv, matcher=matcher)`` through
    the eyes, the improved matcher's (see the module docstring)."""
    return ImprovedEyes(ds, dv).scan(left, right, lines, matcher)
