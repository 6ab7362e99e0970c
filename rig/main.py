"""``rig`` — the rig in one command.

* ``rig demo``: the bundled laboratory pair through NSTAR and ESTAR as two
  processes over ``jhdata/`` (as in 1985), the position tables on screen, then
  pictures of what the rig saw.
* ``rig posit``: the located edges of a POSIT.DT (e.g. from a two-terminal
  run) as a table and a CSV.
* ``rig scan``: a whole-picture scan (lines 8..112 by default) with a progress
  bar: every located edge as a 3-D point with its error bounds and covariance,
  written as CSV and PLY; the accuracy table when the true range is known.
* ``rig walk``: the robot walks a room on the rig's eyes and keeps one model
  of it (rig/walk.py).
* ``rig drive``: the robot drives to a goal in a simulated room (rig/drive.py).

Every option is checked before any work starts; a bad one is one line on
standard error and exit status 1.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path


from diskfmt import version
from diskfmt.layouts import FormatError, decode_bi, decode_posit, read_file
from diskfmt.rdos import LinkTimeout, LockedError, describe_os_error
from estar.masl import Options as MaslOptions
from estar.program import in_process_rig
from . import batch, scan as scanmod
from .checks import (PICTURE_SUFFIXES, UsageError, blank_service_warning, check_lines,
                     check_output_dir, check_output_file, impossible_share, load_picture,
                     load_truth, pair_warnings, positive_number)
from .scene import bundled_path
from .session import (child_env, file_link_eclipse, rig_jhdata, start_nstar, stop_process,
                      tidy_link_files)

DEMO_LINES = (40, 60, 80)
EXIT_USAGE = 1                   # as estar and pre: 1 for any bad input
BUNDLED_UNIT = "ft"              # the laboratory pair's separation, 0.75, is in feet


def _load_pair(left: str | None, right: str | None):
    """The pair named, or the bundled laboratory pair; returns paths and pictures."""
    if (left is None) != (right is None):
        raise UsageError("give both --left and --right, or neither (the bundled pair)")
    if left is None:
        lp, rp = bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI")
        return lp, rp, decode_bi(read_file(lp), str(lp)), decode_bi(read_file(rp), str(rp))
    return Path(left), Path(right), load_picture(left, "--left"), load_picture(right, "--right")


def _truth_for(args, bundled: bool):
    if getattr(args, "truth", None):
        return load_truth(args.truth)
    if bundled:
        from .scene import bundled_range
        return bundled_range()
    return None


def _warn(message: str) -> None:
    print(f"rig: warning: {message}", file=sys.stderr)


def _replay(left, right, lines, ds, dv, options):
    """The same lines over the direct link, in this process: results for pictures."""
    ecl = in_process_rig(left, right, ds, dv, options=options)
    return ecl.link.nova, [ecl.lcln(y) for y in lines]


def cmd_demo(args) -> int:
    check_lines(list(args.lines), "--lines")
    lp, rp, left, right = _load_pair(None, None)
    out = check_output_dir(args.out, "--out")
    if args.jhdata is not None:
        check_output_dir(args.jhdata, "--jhdata")
    with rig_jhdata(args.jhdata) as jhdata:
        return _demo(args, jhdata, out, lp, rp, left, right)


def _demo(args, jhdata, out, lp, rp, left, right) -> int:
    from .pictures import line_picture, monitor_picture, save_png, topdown_map
    lines = [str(y) for y in args.lines]
    print(f"== NSTAR (NOVA) starts on {jhdata}/ with the bundled laboratory pair")
    # Both in sessions of their own: a Ctrl-C is rig's alone, and rig stops
    # them, so the console gets one "rig: interrupted", not one per program.
    nstar = start_nstar(jhdata, lp, rp, quiet=True, idle_timeout=120, own_session=True)
    estar = None
    try:
        print(f"== ESTAR (Eclipse): ds 0.75 ft, dv 180 px, debug 8 (position lists), "
              f"lines {' '.join(lines)}", flush=True)
        t0 = time.perf_counter()
        estar = subprocess.Popen(
            [sys.executable, "-m", "estar.main", "--jhdata", str(jhdata), "--separation",
             "0.75", "--virtual-distance", "180", "--debug", "8", "--line", *lines,
             "--terminate"], env=child_env(), stdin=subprocess.DEVNULL,
            start_new_session=True)
        estar.wait()
        took = time.perf_counter() - t0
        if estar.returncode != 0:
            print("rig: estar failed (see above)", file=sys.stderr)
            return 1
        stop_process(nstar, 60)
    finally:
        interrupted = False
        for proc in (estar, nstar):       # interrupted: at once
            if proc is not None and proc.poll() is None:
                proc.kill()
                proc.wait()
                interrupted = True
        if interrupted:                   # every protocol file left is the killed pair's
            tidy_link_files(jhdata)
    posit = (jhdata / "POSIT.DT").read_bytes()
    print(f"\n== {len(lines)} lines in {took:.2f} s over the file link; jhdata/ now holds: "
          + ", ".join(sorted(p.name for p in jhdata.iterdir() if p.is_file())))
    nova, results = _replay(left, right, args.lines, "0.75", "180", None)
    same = results[-1].posit == posit
    print(f"== POSIT.DT ({len(posit)} bytes, NP={decode_posit(posit).np_}) "
          f"{'matches' if same else 'DIFFERS FROM'} an in-process replay of the same lines")
    pictures = [save_png(out / "monitor.png", monitor_picture(nova.octek, args.lines))]
    for y, r in zip(args.lines, results):
        pictures.append(save_png(out / f"line-{y}.png", line_picture(left, right, r)))
    points = [p for r in results for p in scanmod.points_of_line(r)]
    truth = _truth_for(args, True)
    pictures.append(save_png(out / "topdown.png", _topdown(
        points, truth, topdown_map, "Top-down map of the edges located on lines "
        + ", ".join(lines), BUNDLED_UNIT, 0.75, 180)))
    print("== pictures: " + ", ".join(str(p) for p in pictures))
    return 0 if same else 1


def _topdown(points, truth, topdown_map, title, unit, ds, dv, max_range=None,
             error_bars=True):
    from .pictures import fitted_range
    tr = None
    if truth is not None:
        from .truth import true_range_at
        tr = [true_range_at(truth, p.line, p.loc1) for p in points]
    return topdown_map([(p.dp, p.dx, p.ep, p.ex) for p in points], truth=tr, title=title,
                       max_range=max_range or fitted_range([p.dp for p in points]),
                       unit=unit, error_bars=error_bars, separation=float(ds),
                       virtual_distance=float(dv))


def _scan_lines(args) -> list[int]:
    """``--line`` or ``--lines``, checked."""
    if args.line:
        return check_lines(list(args.line), "--line")
    first, last = args.lines
    if first > last:
        raise UsageError(f"--lines {first} {last}: no lines (FIRST must not exceed LAST)")
    check_lines([first, last], "--lines")
    return list(range(first, last + 1))


def _check_scan(args):
    """Everything ``rig scan`` is given, checked before any work: returns the
    lines, the pair and the truth."""
    args.separation = positive_number(args.separation, "--separation",
                                      "the camera separation, in any unit")
    args.virtual_distance = positive_number(args.virtual_distance, "--virtual-distance",
                                            "pixels at the 128-px picture width")
    if args.max_range is not None:
        positive_number(args.max_range, "--max-range", "the top of the picture's range axis")
    lines = _scan_lines(args)
    for option, path, suffixes in (("--csv", args.csv, None), ("--ply", args.ply, None),
                                   ("--picture", args.picture, PICTURE_SUFFIXES)):
        if path:
            check_output_file(path, option, suffixes)
    if args.line_pictures:
        check_output_dir(args.line_pictures, "--line-pictures")
    if args.link == "file" and args.jhdata is not None:
        check_output_dir(args.jhdata, "--jhdata")
    if not args.timeout >= 0:                  # also refuses nan
        raise UsageError(f"--timeout {args.timeout:g}: give seconds >= 0 (0 waits forever)")
    lp, rp, left, right = _load_pair(args.left, args.right)
    truth = _truth_for(args, args.left is None)
    return lines, lp, rp, left, right, truth


def _matcher_for(args, lp: Path, rp: Path):
    """--match / --constraints: None for 1985; the subpixel
    constraint reads the .VD pictures beside the .BI ones."""
    from matching.mode import constraints_from_args, make_matcher
    from diskfmt.layouts import decode_vd
    try:
        constraints = constraints_from_args(args)
    except ValueError as exc:
        raise SystemExit(f"rig: {exc}")
    vd = None
    if args.match == "improved" and constraints.subpixel:
        paths = [p.with_suffix(".VD") for p in (lp, rp)]
        missing = [str(p) for p in paths if not p.is_file()]
        if missing:
            raise SystemExit(f"rig: the subpixel constraint needs {', '.join(missing)} "
                             "(the .VD picture beside each .BI)")
        vd = tuple(decode_vd(read_file(p), str(p)) for p in paths)
    return make_matcher(args.match, constraints, vd=vd)


def cmd_scan(args) -> int:
    if batch.wants_batch(args):
        return batch.cmd_batch(args, _scan_lines(args))
    lines, lp, rp, left, right, truth = _check_scan(args)
    bundled = args.left is None
    unit = args.unit or (BUNDLED_UNIT if bundled else "units")
    for w in pair_warnings(left, right):
        _warn(w)
    options = MaslOptions(marf_sign_fix=args.marf_sign_fix)
    matcher = _matcher_for(args, lp, rp)
    t0 = time.perf_counter()
    if args.link == "file":
        with rig_jhdata(args.jhdata) as jhdata, \
                file_link_eclipse(jhdata, lp, rp, args.separation, args.virtual_distance,
                                  options, timeout=args.timeout, matcher=matcher) as ecl:
            result = scanmod.run_lines(ecl, lines, progress=not args.quiet)
    elif args.engine == "eyes" and matcher is None:   # the compiled 1985 frame scan, bit for bit
        from eyes import scan_pair as eyes_scan_pair
        result = eyes_scan_pair(left, right, lines, args.separation, args.virtual_distance,
                                options)
    else:
        result = scanmod.scan_pair(left, right, lines, args.separation, args.virtual_distance,
                                   options, progress=not args.quiet, matcher=matcher)
    took = time.perf_counter() - t0
    pts, confidences = result.points, None
    if matcher is not None:
        from fractions import Fraction
        from matching.mode import located_points
        pairs = [pc for r in result.results for pc in located_points(
            r, float(Fraction(args.separation)), float(Fraction(args.virtual_distance)))]
        pts, confidences = [p for p, _ in pairs], [c for _, c in pairs]
    print(f"{len(pts)} located edges on {len(result.lines)} lines "
          f"({len(pts) / max(1, len(result.lines)):.1f} per line), {result.requests} edge-map "
          f"requests, {took:.2f} s over the {args.link} link")
    blank = blank_service_warning(result.results)
    if blank:
        _warn(blank)
    print(scanmod.summary(result, unit, impossible_share(left, right, lines)))
    if args.csv:
        print(f"CSV: {scanmod.write_atomic(args.csv, scanmod.csv_text(pts, confidences))}")
    if args.ply:
        print(f"PLY: {scanmod.write_atomic(args.ply, scanmod.ply_text(pts))}")
    if truth is not None:
        from .truth import accuracy_table, format_table
        print(f"\nAccuracy against the true range (Table III's question, in {unit}):")
        print(format_table(accuracy_table([(p.line, p.loc1, p.loc2, p.dp, p.ep) for p in pts],
                                          truth=truth)))
    if args.picture:
        from .pictures import save_picture, topdown_map
        save_picture(args.picture, _topdown(
            pts, truth, topdown_map, _lines_title(lines), unit,
            args.separation, args.virtual_distance,
            float(args.max_range) if args.max_range else None, not args.no_error_bars))
        print(f"picture: {args.picture}")
    if args.line_pictures:
        written = _line_pictures(Path(args.line_pictures), left, right, result, args.quiet)
        print(f"line pictures: {len(written)} in {args.line_pictures}/ "
              f"(line-{lines[0]}.png ...)")
    if not (args.csv or args.ply or args.picture or args.line_pictures):
        print("write them with --csv FILE, --ply FILE (MeshLab, Open3D), --picture MAP.png "
              "(top-down map) or --line-pictures DIR (one picture per line)")
    return 0


def _lines_title(lines) -> str:
    if len(lines) == 1:
        return f"Top-down map of the edges located on line IY = {lines[0]}"
    if lines == list(range(lines[0], lines[-1] + 1)):
        return f"Top-down map of the edges located on lines {lines[0]}..{lines[-1]}"
    return f"Top-down map of the edges located on {len(lines)} lines"


def _line_pictures(outdir: Path, left, right, result, quiet: bool) -> list[Path]:
    from .pictures import line_picture, save_png
    pairs = list(zip(result.lines, result.results))
    if not quiet:
        from tqdm import tqdm
        pairs = tqdm(pairs, desc="line pictures", unit="picture")
    return [save_png(outdir / f"line-{y}.png", line_picture(left, right, r)) for y, r in pairs]


def cmd_posit(args) -> int:
    from . import posit
    ds = positive_number(args.separation, "--separation", "the camera separation, in any unit")
    dv = positive_number(args.virtual_distance, "--virtual-distance",
                         "pixels at the 128-px picture width")
    if args.csv:
        check_output_file(args.csv, "--csv")
    np_, rows = posit.read_posit(args.file, ds, dv)
    print(posit.table_text(np_, rows, args.unit))
    if rows and not all(r.point for r in rows):
        _warn(f"{sum(r.point is None for r in rows)} of {len(rows)} edges do not fit "
              f"--separation {ds} --virtual-distance {dv} exactly (were those ESTAR's?): "
              f"their line, LOC1 and LOC2 are left out")
    if args.csv:
        print(f"CSV: {scanmod.write_atomic(args.csv, posit.csv_text(rows))}")
    return 0


DEMO_EXAMPLES = """examples:
  rig demo                       the bundled pair, lines 40 60 80, pictures in ./out
  rig demo --lines 60 --out pics one line
"""

SCAN_EXAMPLES = """examples:
  rig scan                                   the bundled pair, accuracy table
  rig scan --csv pts.csv --picture map.png   points and a top-down map
  rig scan --left DESK-L.BI --right DESK-R.BI --separation 0.12 --unit m \\
           --virtual-distance 166 --line-pictures lines/
                                             your own pair (make it with pre pair)

units: the separation may be in any unit; every range and offset comes out in
that unit (--unit names it on the pictures).  The virtual distance is the
camera's focal length in pixels of the 128-px-wide picture: f_px * 128 / W for
a picture W pixels wide (f_px from a calibration), or 64 / tan(FOV/2) for a
horizontal field of view FOV.
"""


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rig", description=__doc__.split("\n\n")[0].strip(),
                                epilog="rig COMMAND --help shows each command's options "
                                       "and examples.")
    p.add_argument("--version", action="version", version=f"%(prog)s {version()}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    raw = argparse.RawDescriptionHelpFormatter
    d = sub.add_parser("demo", help="run NSTAR and ESTAR on the bundled pair, show and "
                                    "picture what they saw",
                       description="Start nstar on the bundled laboratory pair, run estar "
                                   "for a few lines (position tables on screen), then write "
                                   "pictures: the OCTEK monitor, each line, a top-down map.",
                       epilog=DEMO_EXAMPLES, formatter_class=raw)
    d.add_argument("--jhdata", default=None, metavar="DIR",
                   help="shared directory for the NSTAR demo starts (default: a private "
                        "temporary one; refused if an nstar already runs there)")
    d.add_argument("--out", default="out", metavar="DIR",
                   help="where the pictures go (default: ./out)")
    d.add_argument("--lines", type=int, nargs="+", default=list(DEMO_LINES), metavar="Y",
                   help="epipolar lines 0..119 (default: 40 60 80)")
    d.set_defaults(func=cmd_demo)
    s = sub.add_parser("scan", help="whole-picture scan to CSV/PLY, with the accuracy table",
                       description="Scan epipolar lines (default 8..112) of a pair (default "
                                   "the bundled laboratory pair); every located edge as a 3-D "
                                   "point in left-camera axes: x right, y down, z forward "
                                   "(range), in the unit of the camera separation.  The pair "
                                   "must be rectified: a point must lie on the same row in "
                                   "both pictures.",
                       epilog=SCAN_EXAMPLES, formatter_class=raw)
    s.add_argument("--left", metavar="FILE.BI",
                   help="left picture, 128x120 .BI (default: the bundled LAB-L.BI)")
    s.add_argument("--right", metavar="FILE.BI",
                   help="right picture, 128x120 .BI (default: the bundled LAB-R.BI)")
    s.add_argument("--lines", type=int, nargs=2, default=(8, 112), metavar=("FIRST", "LAST"),
                   help="a range of lines (default: 8 112, Appendix C's range)")
    s.add_argument("--line", type=int, nargs="+", metavar="Y",
                   help="any set of lines 0..119 instead, processed in the order given")
    s.add_argument("--link", choices=("direct", "file"), default="direct",
                   help="direct: NSTAR's handlers in this process (default); file: an nstar "
                        "process over --jhdata, as in 1985")
    s.add_argument("--jhdata", default=None, metavar="DIR",
                   help="with --link file: the shared directory for the NSTAR rig starts "
                        "(default: a private temporary one; refused if an nstar already "
                        "runs there)")
    s.add_argument("--timeout", type=float, default=30.0, metavar="SECONDS",
                   help="with --link file: how long to wait for NSTAR to take a command or "
                        "answer it before giving up with one line (default 30; 0 = forever)")
    s.add_argument("--separation", default="0.75", metavar="DS",
                   help="camera separation, any unit > 0; ranges come out in the same unit "
                        "(default: 0.75, feet, the bundled pair's)")
    s.add_argument("--virtual-distance", default="180", metavar="DV",
                   help="virtual image distance: the focal length in pixels at the 128-px "
                        "width, > 0 (default: 180, the bundled pair's)")
    s.add_argument("--unit", metavar="NAME",
                   help="name of the separation's unit, for the pictures and tables "
                        "(default: ft for the bundled pair, else 'units')")
    s.add_argument("--csv", metavar="FILE", help="write the points as CSV")
    s.add_argument("--ply", metavar="FILE",
                   help="write the points as ASCII PLY (MeshLab, Open3D)")
    s.add_argument("--picture", metavar="FILE.png",
                   help="write a top-down map of all points (.png, or .jpg for JPEG)")
    s.add_argument("--max-range", metavar="R",
                   help="top of the map's range axis, in the separation's unit (default: "
                        "fitted to the points; those beyond are arrows)")
    s.add_argument("--no-error-bars", action="store_true",
                   help="draw the map's points without their error bars (default: bars, "
                        "each cut at a fifth of the range axis)")
    s.add_argument("--line-pictures", metavar="DIR",
                   help="write one picture per line, DIR/line-Y.png (pictures, slices, "
                        "features, matched edges)")
    s.add_argument("--truth", metavar="FILE.npy",
                   help="true range per left-picture pixel (.npy, 120x128, the separation's "
                        "unit) for the accuracy table (default: the bundled pair's own)")
    s.add_argument("--marf-sign-fix", action="store_true",
                   help="FIX (not 1985): MARF's refined location with the geometric sign")
    s.add_argument("--engine", choices=("eyes", "reference"), default="eyes",
                   help="direct link: eyes = the compiled frame scan (default; identical "
                        "results), reference = ESTAR's Eclipse calling NSTAR's handlers")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    from matching.mode import add_arguments as add_match_arguments   # the improved matcher (matching/)
    add_match_arguments(s)
    batch.add_arguments(s)
    s.set_defaults(func=cmd_scan)
    q = sub.add_parser("posit", help="the located edges of a POSIT.DT as a table and CSV",
                       description="Read the POSIT.DT an ESTAR run left in its JHDATA (the "
                                   "last line's located edges) and print them; with the run's "
                                   "separation and virtual distance the line, LOC1 and LOC2 "
                                   "are recovered and checked bit for bit against LCSL.",
                       epilog="example:\n  rig posit jhdata/POSIT.DT --csv last-line.csv",
                       formatter_class=raw)
    q.add_argument("file", metavar="POSIT.DT", help="the file (e.g. jhdata/POSIT.DT)")
    q.add_argument("--separation", default="0.75", metavar="DS",
                   help="the run's camera separation (default: 0.75)")
    q.add_argument("--virtual-distance", default="180", metavar="DV",
                   help="the run's virtual image distance, pixels (default: 180)")
    q.add_argument("--unit", default="the unit of the separation", metavar="NAME",
                   help="name of the separation's unit for the table")
    q.add_argument("--csv", metavar="FILE", help="write the edges as CSV (rig scan's columns)")
    q.set_defaults(func=cmd_posit)
    from . import walk as walkmod          # rig walk: the robot's model of its world
    walkmod.add_parser(sub)
    from .drive import add_parser as add_drive_parser
    add_drive_parser(sub)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except UsageError as exc:
        print(f"rig: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (FormatError, LinkTimeout, LockedError) as exc:
        print(f"rig: {exc}", file=sys.stderr)
        return 1
    except BrokenPipeError:                # e.g. rig posit ... | head
        import os
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:
        print(f"rig: {describe_os_error(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:               # children stopped, directory tidied on the way
        print("rig: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
