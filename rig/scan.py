"""Whole-picture scans: ESTAR's LCLN over a set of epipolar lines, every located
edge as a 3-D point with its error bounds and the covariance of equation A-20.

Axes are the left camera's (LCSL's): **X** to the right (dx), **Y** down (dy,
rows below line 60 are positive), **Z** forward along the optical axis (dp,
the range), all in the unit of the camera separation (feet for the bundled
pair).  Offsets are measured from pixel 60 in both directions, as the 1985
program does (QUIRKS E6).

Each point is an :class:`estar.lcsl.Point`, with the covariance of A-20.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from estar.lcsl import Point
from estar.masl import Options as MaslOptions
from diskfmt.rdos import write_atomic as _write_atomic
from estar.program import Eclipse, LineResult, in_process_rig

DEFAULT_LINES = range(8, 113)          # Appendix C: "in the range 8 to 112"

__all__ = ["Point", "points_of_line", "scan_pair", "run_lines", "ScanResult", "csv_text",
           "ply_text", "write_atomic", "read_ply_points", "summary", "DEFAULT_LINES"]


def points_of_line(result: LineResult) -> list[Point]:
    """The located edges of one LCLN, each with the match entry LCSL recorded
    as the one its position came from (``LineResult.used``)."""
    out = []
    for edge, pos in sorted(result.positions.items()):
        if pos is None:
            continue
        _indx, _qual, loc1, loc2 = result.used[edge]
        out.append(Point(result.iyloc, edge, loc1, loc2, *pos))
    return out


@dataclass
class ScanResult:
    lines: list[int]
    results: list[LineResult]
    points: list[Point]
    requests: int

    @property
    def last_posit(self) -> bytes:
        return self.results[-1].posit if self.results else b""


def scan_pair(left: np.ndarray, right: np.ndarray, lines=DEFAULT_LINES,
              ds: str = "0.75", dv: str = "180", options: MaslOptions | None = None,
              progress: bool = False, eclipse: Eclipse | None = None,
              matcher=None) -> ScanResult:
    """Scan the pair over the direct (in-process) link: NSTAR's command handler
    is called with the same NCONT.DT bytes the file link would carry."""
    if eclipse is None:
        eclipse = in_process_rig(left, right, ds, dv, options=options, matcher=matcher)
    return run_lines(eclipse, lines, progress)


def run_lines(eclipse: Eclipse, lines, progress: bool = False) -> ScanResult:
    lines = list(lines)
    iterator = lines
    if progress:
        from tqdm import tqdm
        iterator = tqdm(lines, desc="scanning lines", unit="line")
    results, points = [], []
    for y in iterator:
        r = eclipse.lcln(y)
        results.append(r)
        points.extend(points_of_line(r))
    return ScanResult(lines, results, points, eclipse.requests)


def summary(result: ScanResult, unit: str, impossible: tuple[float, int] | None = None) -> str:
    """A few lines on a scan: edges per line, the located ranges (min, median,
    max) and, when given, the share of lines whose pictures are shifted the
    impossible way (``rig.checks.impossible_share``)."""
    pts = result.points
    with_edges = sum(1 for r in result.results if r.features1)
    out = [f"lines: {len(result.lines)} scanned, {with_edges} with edges in the left slice; "
           f"{sum(2 * len(r.features1) for r in result.results)} left edges, "
           f"{len(pts)} located"]
    if pts:
        dp = np.array([p.dp for p in pts])
        disp = np.array([p.disparity for p in pts])
        out.append(f"range ({unit}): min {dp.min():.3g}, median {np.median(dp):.3g}, "
                   f"max {dp.max():.3g}; disparity {disp.min()}..{disp.max()} px")
    if impossible is not None:
        share, judged = impossible
        out.append(f"impossible disparities: {share:.0%} of {judged} lines (right picture "
                   f"shifted right of the left: large for a swapped or unrectified pair)")
    return "\n".join(out)


# --- output files -------------------------------------------------------------

CSV_COLUMNS = ["line", "edge", "loc1", "loc2", "disparity", "dp", "dx", "dy", "ep", "ex", "ey",
               "var_p", "var_x", "var_y"]


def csv_text(points: list[Point], confidences=None) -> str:
    """The points as CSV; with ``confidences`` (one per point: the improved
    matcher's) a last column ``confidence`` is added."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS + (["confidence"] if confidences is not None else []))
    for k, p in enumerate(points):
        c = p.covariance()
        w.writerow([p.line, p.edge, p.loc1, p.loc2, p.disparity,
                    *(repr(float(v)) for v in (p.dp, p.dx, p.dy, p.ep, p.ex, p.ey,
                                        c[0, 0], c[1, 1], c[2, 2]))]
                   + ([repr(float(confidences[k]))] if confidences is not None else []))
    return buf.getvalue()


def ply_text(points: list[Point]) -> str:
    """ASCII PLY (MeshLab, Open3D): x = dx (right), y = dy (down), z = dp
    (forward), plus the error bounds and the A-20 variances as extra vertex
    properties."""
    head = ["ply", "format ascii 1.0",
            "comment Holten 1985 stereo rig: located edges, left-camera axes "
            "x right, y down, z forward (range); unit of the camera separation",
            f"element vertex {len(points)}",
            "property float x", "property float y", "property float z",
            "property float ep", "property float ex", "property float ey",
            "property float var_p", "property float var_x", "property float var_y",
            "property int line", "property int edge", "end_header"]
    rows = []
    for p in points:
        c = p.covariance()
        rows.append(" ".join(f"{v:.6g}" for v in (p.dx, p.dy, p.dp, p.ep, p.ex, p.ey,
                                                  c[0, 0], c[1, 1], c[2, 2]))
                    + f" {p.line} {p.edge}")
    return "\n".join(head + rows) + "\n"


def write_atomic(path, text: str) -> Path:
    """Write ``text`` by the project's one atomic publish (diskfmt.rdos.write_atomic)."""
    return _write_atomic(Path(path), text.encode())


def read_ply_points(text: str) -> np.ndarray:
    """The vertex rows of an ASCII PLY written by :func:`ply_text` (for checks)."""
    body = text.split("end_header\n", 1)[1]
    return np.loadtxt(io.StringIO(body), ndmin=2) if body.strip() else np.zeros((0, 11))
