"""``nstar`` — the NOVA program: the startup dialogue of NSTAR.FR, then the
label-100 loop waiting for NCONT.DT from ESTAR on the shared JHDATA directory.

Every value the 1985 dialogue asks for can be given as a flag; what is not given
is asked for exactly as in 1985.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from diskfmt.layouts import FormatError, decode_bi, read_file, encode_bi
from diskfmt.listing import Console, Listing
from diskfmt.rdos import JHData, LinkTimeout, LockedError, default_jhdata
from .program import Nova, Options

BANNER = [
    "",
    " NOVA half of stereo vision system",
    "",
    " The debug print options are: ",
    " 1---RADSP direction line values.",
    " 2-Feature lists.",
    " 4--Center blob characteristics.",
    " 8--BLOB bit map.",
    " 16-Edge bit map.",
    "",
    "Add up the desired flag values and enter the number.",
]

STALE_AT_START = ("NDAT.DT", "TRM.DT", "TERM.DT")
LOCK_NAME = "NSTAR.LCK"
BUSY_NAME = "NSTAR.BSY"    # locked from taking a command to publishing its reply (QUIRKS M14)


class Abort(Exception):
    """End the program with a message and a non-zero exit."""


def _ask_int(console: Console, prompt: str) -> int:
    while True:
        answer = console.prompt(prompt)
        if answer is None:
            raise EOFError
        try:
            return int(answer)
        except ValueError:
            console.type(f" '{answer}' is not a whole number; answer again.")


def load_picture(path: str):
    """A .BI picture (120x128), or FormatError naming the file."""
    return decode_bi(read_file(path), str(path))


def new_images_dialogue(nova: Nova, console: Console, left: str | None = None,
                        right: str | None = None) -> None:
    """Label 800 — "Save the current image?", "Input new images?", then the LEFT
    and RIGHT file names (flags answer them for scripts)."""
    scripted = left is not None and right is not None
    if scripted:
        pics = [load_picture(left), load_picture(right)]  # FormatError ends a script
        nova.load_pair(*pics)
        console.type(" Image loaded.")
        console.type(" Image loaded.")
        return
    try:
        if _ask_int(console, "Save the current image? (0=NO) ") != 0:
            for side, image in (("LEFT", 1), ("RIGHT", 2)):
                console.type("Saving the current image to disk.")
                console.type(f"Input the {side} image filename.")
                name = console.prompt("")
                if name is None:
                    raise EOFError
                _save_new(Path(name), encode_bi(nova.picture(image)), console)
            console.type(" Saved.")
        if _ask_int(console, "Input new images? (0=NO) ") == 0:
            return
        pics = []
        for side in ("LEFT", "RIGHT"):
            while True:
                console.type(f" Loading the {side} image from disk. ")
                console.type(f" Input the {side} image file name.")
                name = console.prompt("")
                if name is None:
                    raise EOFError
                try:
                    pics.append(load_picture(name))
                    break
                except FormatError as exc:   # 1985: "Open error on input file" and ask again
                    console.type(f" Open error on input file: {exc}")
            console.type(" Image loaded.")
        nova.load_pair(*pics)
    except EOFError:
        console.type(" (no more input: keeping the current images)")


def _save_new(path: Path, data: bytes, console: Console) -> None:
    if path.exists():
        console.type(f" {path} exists; not overwritten.")
        return
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    tmp.replace(path)


def run(nova: Nova, jh: JHData, console: Console, idle_timeout: float | None) -> int:
    """The label-100 loop: wait for NCONT.DT, take it, do it, publish the reply."""
    while True:
        nova.octek.hctab(128, 255)
        console.type(" Ready for the ECLIPSE command file.")
        jh.wait_for("NCONT.DT", timeout=idle_timeout or 0)
        with jh.busy():                    # a starting ESTAR waits for this (QUIRKS M14)
            try:
                data = jh.read("NCONT.DT")
            except FileNotFoundError:      # set aside by a starting ESTAR: wait again
                continue
            console.type(" Command file found.")
            try:
                replies = nova.execute(data)
            except FormatError:
                raise Abort(f"{jh.path('NCONT.DT')}: {len(data)} bytes, expected 12 — not "
                            f"a command file; left in place for inspection") from None
            jh.delete("NCONT.DT")
            if data[:2] == b"\x00\x03":
                new_images_dialogue(nova, console)
            for reply in replies:
                try:
                    jh.publish(reply.temp, reply.name, reply.data)
                except LinkTimeout as exc:     # nobody takes it: keep serving (QUIRKS M15)
                    where = jh.set_aside(reply.temp, "unsent", as_name=reply.name)
                    print(f"nstar: {exc} This {reply.name} reply was not published; kept as "
                          f"{where}. Waiting for the next command.", file=sys.stderr,
                          flush=True)
        if nova.terminated:
            return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="nstar",
        description="NSTAR, the NOVA half of the 1985 stereo vision system: holds the "
                    "stereo pair in the simulated OCTEK frame store and answers ESTAR's "
                    "commands (slices, edge bit maps, Star filter + block map) through "
                    "files in the JHDATA directory. Values not given as flags are asked "
                    "for as in 1985.")
    p.add_argument("--jhdata", type=Path, default=None,
                   help="shared directory (default: $JHDATA, else ./jhdata)")
    p.add_argument("--debug", type=int, default=None, metavar="N",
                   help="debug flags: 1 RADSP lines, 2 feature lists, 4 centre blob, "
                        "8 blob bit map, 16 edge bit map (-1 all)")
    p.add_argument("--left", help="left picture (.BI, 128x120)")
    p.add_argument("--right", help="right picture (.BI, 128x120)")
    p.add_argument("--listing", type=Path, help="debug listing file (FORTRAN unit 12; "
                                                "default standard output)")
    p.add_argument("--timeout", type=float, default=30.0, metavar="SECONDS",
                   help="how long a reply may wait for ESTAR to take the previous one "
                        "(default 30)")
    p.add_argument("--idle-timeout", type=float, default=None, metavar="SECONDS",
                   help="stop after this long without a command (default: wait forever, "
                        "as in 1985)")
    p.add_argument("--quiet", action="store_true", help="no console messages")
    p.add_argument("--verbose", action="store_true",
                   help="also the per-bit messages of the block map (17 lines per column)")
    p.add_argument("--no-wrap-percent", action="store_true",
                   help="FIX (not 1985): compute the block-map percentage without "
                        "16-bit overflow")
    p.add_argument("--bitmap-extensions", action="store_true",
                   help="BEYOND 1985: answer command codes 11-13 (Appendix B's radial bit map, "
                        "RBMAP.DT; bit-map operations B-2..B-8, OPMAP.DT); see docs/formats.md")
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if (args.left is None) != (args.right is None):
        print("nstar: give both --left and --right, or neither", file=sys.stderr)
        return 2
    console = Console(quiet=args.quiet, verbose=args.verbose)
    listing_stream = None
    jh = None
    try:
        if args.listing:
            listing_stream = open(args.listing, "a", encoding="ascii")
        listing = Listing(listing_stream)
        for line in BANNER:
            console.type(line)
        debug = args.debug
        if debug is None:
            try:
                debug = _ask_int(console, " Input the debug flags. (=0 for no flags.) ")
            except EOFError:
                debug = 0
        nova = Nova(debug=debug & 0xFFFF, listing=listing, console=console,
                    options=Options(no_wrap_percent=args.no_wrap_percent,
                                    bitmap_extensions=args.bitmap_extensions))
        jhdir = args.jhdata or default_jhdata()
        jh = JHData(jhdir, me="NSTAR", peer="ESTAR", timeout=args.timeout)
        jh.lock(LOCK_NAME)                 # two NSTARs would take each other's commands
        jh.open_busy(BUSY_NAME)
        for name in STALE_AT_START:
            where = jh.set_aside(name, "stale")
            if where:
                console.type(f" Found {name} from an earlier run; moved it to {where}")
        new_images_dialogue(nova, console, args.left, args.right)
        return run(nova, jh, console, args.idle_timeout)
    except (FormatError, FileNotFoundError, LinkTimeout, LockedError, Abort) as exc:
        print(f"nstar: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("nstar: interrupted", file=sys.stderr)
        return 130
    finally:
        if listing_stream:
            listing_stream.close()
        if jh is not None:
            jh.close()


if __name__ == "__main__":
    sys.exit(main())
