"""``pre``: the 1985 preprocessor menu, and subcommands for scripts.

With no subcommand, ``pre`` runs the PRE.FR menu reading standard input.
The subcommands share the menu's code (:mod:`pre.framestore`,
:mod:`pre.condense`, :mod:`pre.cartoon`, :mod:`pre.digitize`):

    pre import PICTURE -o X.VD      a picture, video frame or webcam frame -> .VD
                                    (-o X.BI: the same, condensed to a .BI)
    pre shrink X.VD -o X.BI         menu command 2's 2x2 average -> .BI for NSTAR
    pre cartoon X.BI -o Y.BI        menu command 3: QV cartoon, bits/pixel report
    pre show X.VD|X.BI -o X.PNG     look at a picture file
    pre pair LEFT RIGHT -o NAME     NAME-L.VD NAME-R.VD NAME-L.BI NAME-R.BI in one go
    pre compare X.BI                production-system QV against EXQVFL, row by row

Every problem is one line on standard error naming the file or value, and a
non-zero exit status; an output is never half-written and an existing one is
never replaced without ``--force``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from diskfmt import version
from diskfmt.layouts import encode_bi, encode_vd

from .cartoon import DEFAULT_T, bits_report, cartoon
from .condense import condense
from .files import (PreError, check_output, load_picture_file, load_vd, publish,
                    publish_many)

EXIT_ERROR = 1


def _threshold(text: str) -> int:
    try:
        t = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if not 0 <= t <= 15:
        raise argparse.ArgumentTypeError(f"{t} is not a threshold 0..15")
    return t


def _positive(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"{n} is not 1 or more")
    return n


def _non_negative(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if n < 0:
        raise argparse.ArgumentTypeError(f"{n} is negative")
    return n


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


def _add_digitizer_options(p: argparse.ArgumentParser) -> None:
    from .digitize import DEFAULT_FIT, FITS
    p.add_argument("--fit", choices=FITS, default=DEFAULT_FIT,
                   help="how the picture is fitted to 256x240: crop the centre to the "
                        "256:240 shape (default; square pixels, no added borders), "
                        "stretch the whole picture, or pad it with black")
    p.add_argument("--frame", type=_non_negative, default=0,
                   help="frame number of a video file (default 0)")
    p.add_argument("--brightness", type=_float, default=0.0,
                   help="software brightness: d.c. bias added on the 0..255 scale "
                        "(Chapter VI recommendation; default 0 = off)")
    p.add_argument("--contrast", type=_float, default=1.0,
                   help="software contrast: gain about mid-range (default 1 = off)")
    p.add_argument("--auto-levels", action="store_true",
                   help="choose brightness and contrast from the picture "
                        "(1st..99th percentile onto 0..255); off by default")


def _levels(args):
    from .digitize import Levels
    return Levels(args.brightness, args.contrast, args.auto_levels)


def build_parser() -> argparse.ArgumentParser:
    raw = argparse.RawDescriptionHelpFormatter
    ap = argparse.ArgumentParser(
        prog="pre",
        description="PRE, the robot vision image preprocessor (Holten 1985). "
                    "Without a subcommand: the 1985 menu, reading standard input.",
        epilog="examples:\n  pre pair left.jpg right.jpg -o DESK   DESK-L.BI, DESK-R.BI "
               "(and .VD) for nstar and rig scan\n  pre                                   "
               "the 1985 menu", formatter_class=raw)
    ap.add_argument("--version", action="version", version=f"%(prog)s {version()}")
    ap.add_argument("--force", action="store_true",
                    help="menu commands 4 and 11 may replace an existing file")
    ap.add_argument("--threshold", type=_threshold, default=DEFAULT_T,
                    help=f"QV noise threshold T for menu command 3 (default {DEFAULT_T}, "
                         "NSTAR's slice threshold)")
    ap.add_argument("--camera", metavar="SOURCE",
                    help="optional stand-in for the Dage camera in menu command 1: a "
                         "picture, a video file or cam:N (a webcam); without it SYNC "
                         "never locks, as on a board with no camera")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("import", help="a picture, video frame or webcam frame -> .VD (or .BI)",
                       description="Digitize a picture OpenCV reads (PNG, JPEG, PGM, TIFF, "
                                   "BMP, ...), a frame of a video file, or a webcam frame "
                                   "(cam:N) to a 256x240 16-level .VD file, as the Dage camera "
                                   "and the OCTEK did (docs/pre.md, 'Digitizer model').  An "
                                   "output named .BI gets the picture condensed to 128x120.",
                       epilog="example: pre import desk.jpg -o DESK.VD", formatter_class=raw)
    p.add_argument("picture", help="picture or video file, or cam:N for webcam N")
    p.add_argument("-o", "--output", required=True, metavar="FILE.VD",
                   help="the .VD file to write (or a .BI: condensed to 128x120)")
    _add_digitizer_options(p)
    p.add_argument("--force", action="store_true", help="replace an existing output")

    p = sub.add_parser("shrink", help="condense a .VD to a 128x120 .BI (menu command 2)",
                       description="Condense a 256x240 .VD picture to the 128x120 .BI file "
                                   "NSTAR reads: each 2x2 block becomes (a+b+c+d+2)/4, as "
                                   "menu command 2 followed by command 4.")
    p.add_argument("vd", help="the .VD file")
    p.add_argument("-o", "--output", required=True, help="the .BI file to write")
    p.add_argument("--force", action="store_true", help="replace an existing output")

    p = sub.add_parser("cartoon", help="QV cartoon of a .BI (menu command 3)",
                       description="Cartoon a 128x120 .BI picture with the Queen Victoria "
                                   "production system: a horizontal then a vertical pass, "
                                   "smooth intervals at their grey level, edges as sharp "
                                   "steps.  Prints the bits per pixel of the feature strings.")
    p.add_argument("bi", help="the .BI file")
    p.add_argument("-o", "--output", required=True, help="the .BI file to write")
    p.add_argument("--threshold", type=_threshold, default=DEFAULT_T,
                   help=f"noise threshold T of Table I (default {DEFAULT_T})")
    p.add_argument("--extended-rules", action="store_true",
                   help="add the four X-rules (a flat pause inside an edge) to the 50 "
                        "productions; off by default (docs/pre.md)")
    p.add_argument("--passes", choices=("hv", "h", "v"), default="hv",
                   help="horizontal then vertical (default), or one pass only")
    p.add_argument("--force", action="store_true", help="replace an existing output")

    p = sub.add_parser("show", help="a .VD or .BI as a picture file (PNG, ...)",
                       description="Write a .VD or .BI picture (told apart by size) as an "
                                   "8-bit grey picture, level L shown as 17*L.")
    p.add_argument("file", help="the .VD or .BI file")
    p.add_argument("-o", "--output", required=True,
                   help="picture to write; the suffix picks the format (.png, .pgm, ...)")
    p.add_argument("--zoom", type=_positive, default=1, help="enlarge by a whole factor")
    p.add_argument("--force", action="store_true", help="replace an existing output")

    p = sub.add_parser("pair", help="a stereo pair -> NAME-L/NAME-R .VD and .BI",
                       description="Import a stereo pair and write NAME-L.VD, NAME-R.VD, "
                                   "NAME-L.BI and NAME-R.BI (the files NSTAR asks for, left "
                                   "then right).  LEFT and RIGHT may be pictures, video "
                                   "files, cam:N, or .VD files.  All four names are checked "
                                   "before anything is written.  The pair must be rectified "
                                   "(a point on the same row in both pictures): cameras side "
                                   "by side, axes parallel, or rectified with OpenCV first.",
                       epilog="example: pre pair left.jpg right.jpg -o DESK\n"
                              "         rig scan --left DESK-L.BI --right DESK-R.BI "
                              "--separation 0.12 --unit m",
                       formatter_class=raw)
    p.add_argument("left", help="left picture (video file, cam:N or .VD)")
    p.add_argument("right", help="right picture, from the camera to the left one's right")
    p.add_argument("-o", "--output", required=True, metavar="NAME",
                   help="name stem, e.g. data/DESK gives data/DESK-L.VD ...")
    _add_digitizer_options(p)
    p.add_argument("--force", action="store_true", help="replace existing outputs")

    p = sub.add_parser("compare", help="production-system QV against EXQVFL on rows",
                       description="Run the production-system QV and NSTAR's EXQVFL on "
                                   "every row of a .BI (or .VD) picture and report how often "
                                   "their edge intervals agree (docs/pre.md).")
    p.add_argument("file", help="a .BI or .VD file")
    p.add_argument("--threshold", type=_threshold, default=DEFAULT_T,
                   help=f"T and ITHR (default {DEFAULT_T}, NSTAR's slice threshold)")
    p.add_argument("--extended-rules", action="store_true",
                   help="production QV with the four X-rules as well")
    return ap


# --- subcommands ---------------------------------------------------------------

def cmd_import(args) -> int:
    from .digitize import import_picture
    kind = Path(args.output).suffix.upper()
    if kind not in (".VD", ".BI"):
        raise PreError(f"{args.output}: name it .VD (the 256x240 picture) or .BI (condensed "
                       f"to 128x120 for NSTAR)")
    check_output(args.output, args.force)
    pic = import_picture(args.picture, args.fit, _levels(args), args.frame)
    if kind == ".BI":
        publish(args.output, encode_bi(condense(pic)), args.force)
        print(f"{args.output}: 128x120, 16 grey levels, condensed from {args.picture} "
              f"(fit {args.fit})")
    else:
        publish(args.output, encode_vd(pic), args.force)
        print(f"{args.output}: 256x240, 16 grey levels, from {args.picture} (fit {args.fit})")
    return 0


def cmd_shrink(args) -> int:
    check_output(args.output, args.force)
    pic = load_vd(args.vd)
    publish(args.output, encode_bi(condense(pic)), args.force)
    print(f"{args.output}: 128x120 condensed from {args.vd}")
    return 0


def _load_bi_only(path) -> np.ndarray:
    pic = load_picture_file(path)
    if pic.shape != (120, 128):
        raise PreError(f"{path}: a 256x240 .VD picture; cartoon works on a .BI "
                       f"(run 'pre shrink' first)")
    return pic


def cmd_cartoon(args) -> int:
    check_output(args.output, args.force)
    pic = _load_bi_only(args.bi)
    from .qv_production import rule_set
    result = cartoon(pic, args.threshold, args.passes, rule_set(args.extended_rules))
    publish(args.output, encode_bi(result.picture), args.force)
    print(bits_report(result, str(args.bi)))
    return 0


def cmd_show(args) -> int:
    import cv2
    check_output(args.output, args.force)
    pic = load_picture_file(args.file)
    img = (pic.astype(np.uint8) * 17)
    if args.zoom > 1:
        img = np.kron(img, np.ones((args.zoom, args.zoom), dtype=np.uint8))
    suffix = Path(args.output).suffix.lower()
    if not suffix:
        raise PreError(f"{args.output}: no suffix to choose a picture format (.png, .pgm, ...)")
    try:
        ok, data = cv2.imencode(suffix, img)
    except cv2.error:
        ok = False
    if not ok:
        raise PreError(f"{args.output}: OpenCV cannot write {suffix} pictures")
    publish(args.output, data.tobytes(), args.force)
    print(f"{args.output}: {img.shape[1]}x{img.shape[0]} picture of {args.file}")
    return 0


def _pair_side(source: str, args) -> np.ndarray:
    from .digitize import import_picture
    if source.lower().endswith(".vd"):
        return load_vd(source)
    return import_picture(source, args.fit, _levels(args), args.frame)


def pair_names(stem: str) -> list[str]:
    """The four files of ``pre pair``: NAME-L.VD, NAME-R.VD, NAME-L.BI, NAME-R.BI
    (the convention of the bundled LAB-L.BI, LAB-R.BI)."""
    return [f"{stem}-{side}.{kind}" for kind in ("VD", "BI") for side in ("L", "R")]


def cmd_pair(args) -> int:
    names = pair_names(args.output)
    for n in names:
        check_output(n, args.force)
    left = _pair_side(args.left, args)
    right = _pair_side(args.right, args)
    publish_many([(names[0], encode_vd(left)), (names[1], encode_vd(right)),
                  (names[2], encode_bi(condense(left))), (names[3], encode_bi(condense(right)))],
                 args.force)
    print("written: " + ", ".join(names))
    return 0


def cmd_compare(args) -> int:
    from .compare import compare_picture, report
    pic = load_picture_file(args.file)
    if pic.shape == (240, 256):
        pic = condense(pic)
    from .qv_production import rule_set
    print(report(compare_picture(pic, args.threshold, rule_set(args.extended_rules)),
                 str(args.file)))
    return 0


COMMANDS = {"import": cmd_import, "shrink": cmd_shrink, "cartoon": cmd_cartoon,
            "show": cmd_show, "pair": cmd_pair, "compare": cmd_compare}


def _camera(source: str):
    from .digitize import import_picture
    return lambda: import_picture(source)


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        if args.command is None:
            from .menu import run_menu
            camera = _camera(args.camera) if args.camera else None
            return run_menu(force=args.force, threshold=args.threshold, camera=camera)
        return COMMANDS[args.command](args)
    except PreError as exc:
        print(f"pre: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except OSError as exc:
        print(f"pre: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        print("pre: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
