"""``rig`` — the rig in one command.

* ``rig demo``: the bundled laboratory pair through NSTAR and ESTAR as two
  processes over ``jhdata/`` (as in 1985), the position tables on screen, then
  pictures of what the rig saw.
* ``rig scan``: a whole-picture scan (lines 8..112 by default) with a progress
  bar: every located edge as a 3-D point with its error bounds and covariance,
  written as CSV and PLY; the accuracy table when the true range is known.
* ``rig drive``: the robot drives to a goal in a simulated room (rig/drive.py).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from diskfmt.dgreal import Real
from diskfmt.layouts import FormatError, decode_bi, decode_posit, read_file
from estar.link import DirectLink
from estar.masl import Options as MaslOptions
from estar.program import Eclipse
from nstar.program import Nova
from . import scan as scanmod
from .scene import bundled_path
from .session import child_env, file_link_eclipse

DEMO_LINES = (40, 60, 80)


def _load_pair(left: str | None, right: str | None):
    """The pair named, or the bundled laboratory pair; returns paths and pictures."""
    if (left is None) != (right is None):
        raise SystemExit("rig: give both --left and --right, or neither (the bundled pair)")
    lp = Path(left) if left else bundled_path("LAB-L.BI")
    rp = Path(right) if right else bundled_path("LAB-R.BI")
    return lp, rp, decode_bi(read_file(lp), str(lp)), decode_bi(read_file(rp), str(rp))


def _truth_for(args, bundled: bool):
    if getattr(args, "truth", None):
        return np.load(args.truth)
    if bundled:
        from .scene import bundled_range
        return bundled_range()
    return None


def _replay(left, right, lines, ds, dv, options):
    """The same lines over the direct link, in this process: results for pictures."""
    nova = Nova()
    nova.load_pair(left, right)
    ecl = Eclipse(DirectLink(nova), Real.const(ds), Real.const(dv), options=options)
    return nova, [ecl.lcln(y) for y in lines]


def cmd_demo(args) -> int:
    from octek_sim.monitor import render_monitor
    from .pictures import line_picture, save_png, topdown_map
    lp, rp, left, right = _load_pair(None, None)
    jhdata = Path(args.jhdata)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    jhdata.mkdir(parents=True, exist_ok=True)
    lines = [str(y) for y in args.lines]
    print(f"== NSTAR (NOVA) starts on {jhdata}/ with the bundled laboratory pair")
    nstar = subprocess.Popen(
        [sys.executable, "-m", "nstar.main", "--jhdata", str(jhdata), "--debug", "0",
         "--quiet", "--left", str(lp), "--right", str(rp), "--idle-timeout", "120"],
        env=child_env(), stdin=subprocess.DEVNULL)
    try:
        print(f"== ESTAR (Eclipse): ds 0.75 ft, dv 180 px, debug 8 (position lists), "
              f"lines {' '.join(lines)}")
        t0 = time.perf_counter()
        estar = subprocess.run(
            [sys.executable, "-m", "estar.main", "--jhdata", str(jhdata), "--separation",
             "0.75", "--virtual-distance", "180", "--debug", "8", "--line", *lines,
             "--terminate"], env=child_env(), stdin=subprocess.DEVNULL)
        took = time.perf_counter() - t0
        if estar.returncode != 0:
            print("rig: estar failed (see above)", file=sys.stderr)
            return 1
        nstar.wait(timeout=60)
    finally:
        if nstar.poll() is None:
            nstar.kill()
    posit = (jhdata / "POSIT.DT").read_bytes()
    print(f"\n== {len(lines)} lines in {took:.2f} s over the file link; jhdata/ now holds: "
          + ", ".join(sorted(p.name for p in jhdata.iterdir() if p.is_file())))
    nova, results = _replay(left, right, args.lines, "0.75", "180", None)
    same = results[-1].posit == posit
    print(f"== POSIT.DT ({len(posit)} bytes, NP={decode_posit(posit).np_}) "
          f"{'matches' if same else 'DIFFERS FROM'} an in-process replay of the same lines")
    pictures = [save_png(out / "monitor.png", render_monitor(nova.octek))]
    for y, r in zip(args.lines, results):
        pictures.append(save_png(out / f"line-{y}.png", line_picture(left, right, r)))
    points = [p for r in results for p in scanmod.points_of_line(r)]
    truth = _truth_for(args, True)
    pictures.append(save_png(out / "topdown.png", _topdown(points, truth, topdown_map,
                                                          "lines " + ", ".join(lines))))
    print("== pictures: " + ", ".join(str(p) for p in pictures))
    return 0 if same else 1


def _topdown(points, truth, topdown_map, title):
    tr = None
    if truth is not None:
        from .truth import true_range_at
        tr = [true_range_at(truth, p.line, p.loc1) for p in points]
    return topdown_map([(p.dp, p.dx, p.ep, p.ex) for p in points], truth=tr, title=title)


def cmd_scan(args) -> int:
    lp, rp, left, right = _load_pair(args.left, args.right)
    bundled = args.left is None
    lines = list(args.line) if args.line else list(range(args.lines[0], args.lines[1] + 1))
    bad = [y for y in lines if not 0 <= y <= 119]
    if not lines or bad:
        raise SystemExit(f"rig: lines must lie within 0..119 (got {bad or 'none'})")
    options = MaslOptions(marf_sign_fix=args.marf_sign_fix)
    t0 = time.perf_counter()
    if args.link == "file":
        with file_link_eclipse(Path(args.jhdata), lp, rp, args.separation,
                               args.virtual_distance, options) as ecl:
            result = scanmod.run_lines(ecl, lines, progress=not args.quiet)
    else:
        result = scanmod.scan_pair(left, right, lines, args.separation, args.virtual_distance,
                                   options, progress=not args.quiet)
    took = time.perf_counter() - t0
    pts = result.points
    print(f"{len(pts)} located edges on {len(result.lines)} lines "
          f"({len(pts) / max(1, len(result.lines)):.1f} per line), {result.requests} edge-map "
          f"requests, {took:.2f} s over the {args.link} link")
    if args.csv:
        print(f"CSV: {scanmod.write_atomic(args.csv, scanmod.csv_text(pts))}")
    if args.ply:
        print(f"PLY: {scanmod.write_atomic(args.ply, scanmod.ply_text(pts))}")
    truth = _truth_for(args, bundled)
    if truth is not None:
        from .truth import accuracy_table, format_table
        print("\nAccuracy against the true range (Table III's question):")
        print(format_table(accuracy_table([(p.line, p.loc1, p.loc2, p.dp, p.ep) for p in pts],
                                          truth=truth)))
    if args.picture:
        from .pictures import save_png, topdown_map
        save_png(args.picture, _topdown(pts, truth, topdown_map,
                                        f"lines {lines[0]}..{lines[-1]} ({len(lines)})"))
        print(f"picture: {args.picture}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rig", description=__doc__.split("\n\n")[0].strip())
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="run NSTAR and ESTAR on the bundled pair, show and "
                                    "picture what they saw",
                       description="Start nstar on the bundled laboratory pair, run estar "
                                   "for a few lines (position tables on screen), then write "
                                   "pictures: the OCTEK monitor, each line, a top-down map.")
    d.add_argument("--jhdata", default="jhdata", help="shared directory (default ./jhdata)")
    d.add_argument("--out", default="out", help="where the pictures go (default ./out)")
    d.add_argument("--lines", type=int, nargs="+", default=list(DEMO_LINES), metavar="Y")
    d.set_defaults(func=cmd_demo)
    s = sub.add_parser("scan", help="whole-picture scan to CSV/PLY, with the accuracy table",
                       description="Scan epipolar lines (default 8..112) of a pair (default "
                                   "the bundled laboratory pair); every located edge as a 3-D "
                                   "point in left-camera axes: x right, y down, z forward "
                                   "(range), in the unit of the camera separation.")
    s.add_argument("--left", help="left picture (.BI)")
    s.add_argument("--right", help="right picture (.BI)")
    s.add_argument("--lines", type=int, nargs=2, default=(8, 112), metavar=("FIRST", "LAST"),
                   help="a range of lines (default 8 112, Appendix C's range)")
    s.add_argument("--line", type=int, nargs="+", metavar="Y",
                   help="any set of lines instead, processed in the order given")
    s.add_argument("--link", choices=("direct", "file"), default="direct",
                   help="direct: NSTAR's handlers in this process (default); file: an nstar "
                        "process over --jhdata, as in 1985")
    s.add_argument("--jhdata", default="jhdata")
    s.add_argument("--separation", default="0.75", metavar="DS")
    s.add_argument("--virtual-distance", default="180", metavar="DV")
    s.add_argument("--csv", help="write the points as CSV")
    s.add_argument("--ply", help="write the points as ASCII PLY (MeshLab, Open3D)")
    s.add_argument("--picture", help="write a top-down map PNG of all points")
    s.add_argument("--truth", help="true range per left pixel (.npy, 120x128); the bundled "
                                   "pair's is used automatically")
    s.add_argument("--marf-sign-fix", action="store_true",
                   help="FIX (not 1985): MARF's refined location with the geometric sign")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_scan)
    from .drive import add_parser as add_drive_parser
    add_drive_parser(sub)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except FormatError as exc:
        print(f"rig: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
