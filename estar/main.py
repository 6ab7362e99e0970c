"""``estar`` — the Eclipse program: ESTAR.FR's dialogue (camera separation,
virtual image distance, debug flags, then line after line), each line through
LCLN, talking to ``nstar`` only through files in JHDATA.

Every value the 1985 dialogue asks for can be given as a flag; what is not
given is asked for exactly as in 1985.  With ``--line`` the lines are done in
order and the program ends; a line outside 0..119 stops, as in 1985.
"""

from __future__ import annotations

import argparse
import sys
from fractions import Fraction
from pathlib import Path

from diskfmt import version
from diskfmt.dgreal import DGRealError, Real
from diskfmt.listing import Console, Listing
from diskfmt.rdos import (LinkTimeout, LockedError, default_jhdata, describe_os_error,
                          ESTAR_LOCK)
from .link import FileLink
from .masl import Options
from .program import file_link_estar

BANNER = ["", "ROBOT VISION SYSTEM", "", " By James R. Holten III", ""]
DEBUG_MENU = ["", "The debugger options are:",
              " 1---Print feature lists.",
              " 2--Print blob characterizations.",
              " 4---Print match lists.",
              " 8---Print position lists.",
              " 16--Print bit maps.",
              " 32--Print compared bit maps.",
              "",
              " Add together the options desired.",
              ""]
BLANK_WARNING = ("estar: warning: NSTAR's slices have no edges at all: its pictures look blank "
                 "(was nstar given --left and --right, or new images at its prompt?)")
LOCK_NAME = ESTAR_LOCK


def parse_real(text: str, what: str) -> Real:
    try:
        value = Fraction(text.strip())
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"{what} '{text}' is not a number") from None
    if value <= 0:
        raise ValueError(f"{what} must be positive, got {text}")
    real = Real.from_fraction(value)
    try:
        real.to_bytes()
    except (DGRealError, OverflowError):       # the REAL would not fit its 4 bytes
        raise ValueError(f"{what} {text} is outside the Data General REAL range "
                         f"(about 5.4e-79 to 7.2e75)") from None
    return real


def _ask(console: Console, prompt: str, convert):
    """ACCEPT with a second chance on a bad answer; EOF ends the program."""
    return console.accept(prompt, convert)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="estar",
        description="ESTAR, the Eclipse half of the 1985 stereo vision system: for each "
                    "epipolar line asks NSTAR for the two slices and edge bit maps, matches "
                    "the edges, locates them in 3-D with error bounds and writes POSIT.DT. "
                    "Values not given as flags are asked for as in 1985.")
    p.add_argument("--version", action="version", version=f"%(prog)s {version()}")
    p.add_argument("--jhdata", type=Path, default=None,
                   help="shared directory (default: $JHDATA, else ./jhdata)")
    p.add_argument("--separation", metavar="DS", help="camera separation (any unit; "
                                                      "results come in the same unit)")
    p.add_argument("--virtual-distance", metavar="DV",
                   help="virtual image distance in pixels (about 180 for 128-px pictures)")
    p.add_argument("--debug", type=int, default=None, metavar="N",
                   help="1 feature lists, 2 blob maps, 4 match lists, 8 positions, "
                        "16 bit maps, 32 compared bit maps (-1 all; 13 is the usual)")
    p.add_argument("--line", type=int, nargs="+", metavar="Y",
                   help="process these lines (0..119) in order, then exit")
    p.add_argument("--listing", type=Path, help="debug listing file (FORTRAN unit 12; "
                                                "default standard output)")
    p.add_argument("--terminate", action="store_true",
                   help="send code -1 to NSTAR before exiting (NSTAR writes TERM.DT, stops)")
    p.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                   help="how long to wait for NSTAR's answer (default 30 when scripted; "
                        "at a terminal without --line, as long as it takes)")
    p.add_argument("--quiet", action="store_true", help="no console messages")
    p.add_argument("--verbose", action="store_true",
                   help="also the per-comparison messages of MASL")
    p.add_argument("--marf-sign-fix", action="store_true",
                   help="FIX (not 1985): store MARF's refined right-image location with "
                        "the sign the geometry implies")
    from matching.mode import add_arguments as add_match_arguments   # the improved matcher (matching/)
    add_match_arguments(p, subpixel=False)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    console = Console(quiet=args.quiet, verbose=args.verbose)
    # At a terminal a person may start estar before nstar: wait as long as it
    # takes; scripted, a missing NSTAR is an error after the timeout.
    interactive = args.line is None and _is_terminal(sys.stdin)
    timeout = args.timeout if args.timeout is not None else (None if interactive else 30.0)
    listing_stream = None
    link = None
    try:
        # Flags, files and the directory first: nothing asked, nothing moved on
        # a command line that cannot work.
        from matching.mode import constraints_from_args, make_matcher
        matcher = make_matcher(args.match, constraints_from_args(args, subpixel=False))
        dsep = dvirt = None
        if args.separation is not None:
            dsep = parse_real(args.separation, "--separation")
        if args.virtual_distance is not None:
            dvirt = parse_real(args.virtual_distance, "--virtual-distance")
        if args.listing:
            listing_stream = open(args.listing, "a", encoding="ascii")
        link = FileLink.open(args.jhdata or default_jhdata(), timeout=timeout)
        for line in BANNER:
            console.type(line)
        if dsep is None:
            dsep = _ask(console, " Camera seperation = ",
                        lambda t: parse_real(t, "camera separation"))
        if dvirt is None:
            dvirt = _ask(console, " Virtual image distance = ",
                         lambda t: parse_real(t, "virtual image distance"))
        for line in DEBUG_MENU:
            console.type(line)
        debug = args.debug
        if debug is None:
            debug = _ask(console, " Desired debug flags (0 for none) = ", int)
        link.start(console.type)
        if not link.nstar_running():
            console.type(f" waiting for NSTAR on {link.jh.dir}…")
            if interactive:
                link.wait_for_nstar(timeout)
                console.type(" NSTAR is running.")
        eclipse = file_link_estar(link, dsep, dvirt, debug=debug & 0xFFFF,
                                  listing=Listing(listing_stream), console=console,
                                  options=Options(marf_sign_fix=args.marf_sign_fix),
                                  matcher=matcher)
        lines = list(args.line) if args.line is not None else None
        featureless = 0                   # lines so far, while no slice had any feature
        while True:
            console.type("")
            if lines is not None:
                if not lines:
                    break
                iyloc = lines.pop(0)
            else:
                iyloc = _ask(console, " Which horizontal line? (0 to 119) IY=", int)
            if iyloc < 0 or 119 < iyloc:
                break
            result = eclipse.lcln(iyloc)
            if featureless >= 0:
                featureless = -1 if (result.features1 or result.features2) else featureless + 1
                if featureless == 2:
                    print(BLANK_WARNING, file=sys.stderr)
        if featureless == 1:
            print(BLANK_WARNING, file=sys.stderr)
        if args.terminate:
            eclipse.terminate()
            link.wait_taken()
        elif interactive:
            _say_nstar_still_runs(console, link)
        return 0
    except EOFError:
        if interactive and link is not None:
            _say_nstar_still_runs(console, link)
        return 0
    except ValueError as exc:                 # a bad flag value (FormatError is one too)
        print(f"estar: {exc}", file=sys.stderr)
        return 1
    except (LinkTimeout, LockedError) as exc:
        print(f"estar: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:                    # the file system: one line, no traceback
        print(f"estar: {describe_os_error(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        if link is not None and link.withdraw():
            print("estar: interrupted; its command to NSTAR was withdrawn", file=sys.stderr)
        else:
            print("estar: interrupted", file=sys.stderr)
        return 130
    finally:
        if listing_stream:
            listing_stream.close()
        if link is not None:
            link.close()


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def _say_nstar_still_runs(console: Console, link: FileLink) -> None:
    """A person ending ESTAR should know the NSTAR it leaves behind."""
    if link.nstar_running():
        d = link.jh.dir
        console.type(f" NSTAR is still running on {d}, waiting for commands. Stop it with "
                     f"Ctrl-C in its window, or with: estar --jhdata {d} --separation 1 "
                     f"--virtual-distance 1 --debug 0 --line -1 --terminate")


if __name__ == "__main__":
    sys.exit(main())
