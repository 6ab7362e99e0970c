"""``rig posit``: read the POSIT.DT an ESTAR run left (two terminals, or
``rig scan --link file``) and give its located edges as a table and a CSV.

POSIT.DT holds NP and COMMON /POSIT/ (QUIRKS E8): for each of the NP features
of the last line, POS(1..6) of its left edge k and right edge k+50 — range dp,
offsets dx, dy, error bounds ep, ex, ey; dp = -1 marks "no data point".  It
does not record the line, the match or the calibration, but LCSL's formulas
give them back from the separation DS and virtual distance DV:
``LOC1 = 60 + dx*DV/dp``, ``disparity = DS*DV/dp``, ``IY = 60 + dy*DV/dp``.
Each reconstruction is checked by running LCSL's arithmetic again: the six
REALs must come out bit for bit, or the row is given without LOC1, LOC2 and
the line (and a warning says DS/DV do not fit).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass

from diskfmt.dgreal import Real
from diskfmt.layouts import POSIT_BYTES, FormatError, decode_posit, read_file
from estar.lcsl import Point, locate
from estar.printouts import RIGHT_EDGE


@dataclass(frozen=True)
class PositRow:
    edge: int
    values: tuple[float, ...]               # dp, dx, dy, ep, ex, ey
    point: Point | None                     # with line, LOC1, LOC2 when they fit DS/DV


def read_posit(path, ds: str = "0.75", dv: str = "180") -> tuple[int, list[PositRow]]:
    """NP and the located edges of a POSIT.DT, by edge (FormatError if it is not one)."""
    data = read_file(path)
    if len(data) != POSIT_BYTES:
        from pre.files import what_file_is
        raise FormatError(str(path), f"not a POSIT.DT: {what_file_is(data)}; ESTAR writes one "
                                     f"({POSIT_BYTES:,} bytes) in its JHDATA after every line")
    positions = decode_posit(data, str(path))
    dsep, dvirt = Real.const(ds), Real.const(dv)
    rows = []
    for indx in range(1, positions.np_ + 1):
        for edge in (indx, indx + RIGHT_EDGE):
            reals = positions.entry(edge)
            if not reals[0] > Real.const("0"):
                continue                        # "No data point."
            values = tuple(float(r) for r in reals)
            rows.append(PositRow(edge, values, _reconstruct(edge, reals, dsep, dvirt)))
    return positions.np_, sorted(rows, key=lambda r: r.edge)


def _reconstruct(edge, reals, dsep, dvirt) -> Point | None:
    dp, dx, dy = (float(r) for r in reals[:3])
    v = float(dvirt)
    disp = round(float(dsep) * v / dp)
    loc1 = 60 + round(dx * v / dp)
    iy = 60 + round(dy * v / dp)
    if not 0 <= iy <= 119 or not 1 <= loc1 <= 128:
        return None
    again = locate(loc1, loc1 - disp, iy, dsep, dvirt)
    if again is None or list(again) != list(reals):
        return None
    return Point(iy, edge, loc1, loc1 - disp, *(float(r) for r in reals))


def table_text(np_: int, rows: list[PositRow], unit: str) -> str:
    lines = [f"NP = {np_} features on the last line; {len(rows)} located edges "
             f"(ranges in {unit})",
             " edge  line  LOC1  LOC2        dp        dx        dy        ep        ex"
             "        ey"]
    for r in rows:
        p = r.point
        where = (f"{p.line:5d} {p.loc1:5d} {p.loc2:5d}" if p else "    -     -     -")
        lines.append(f"{r.edge:5d} {where} " + " ".join(f"{v:9.3f}" for v in r.values))
    return "\n".join(lines)


CSV_COLUMNS = ["line", "edge", "loc1", "loc2", "disparity", "dp", "dx", "dy", "ep", "ex", "ey",
               "var_p", "var_x", "var_y"]


def csv_text(rows: list[PositRow]) -> str:
    """The columns of ``rig scan --csv``; line, LOC1, LOC2, disparity empty where
    they do not fit DS/DV."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for r in rows:
        p = r.point
        dp, dx, dy, ep, ex, ey = r.values
        head = [p.line, r.edge, p.loc1, p.loc2, p.disparity] if p else ["", r.edge, "", "", ""]
        w.writerow(head + [repr(float(v)) for v in (dp, dx, dy, ep, ex, ey,
                                                    (ep / 2) ** 2, (ex / 2) ** 2,
                                                    (ey / 2) ** 2)])
    return buf.getvalue()
