"""``nstar`` — the NOVA program: the startup dialogue of NSTAR.FR, then the
label-100 loop waiting for NCONT.DT from ESTAR on the shared JHDATA directory.

Every value the 1985 dialogue asks for can be given as a flag; what is not given
is asked for exactly as in 1985.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from diskfmt import version
from diskfmt.layouts import (FormatError, decode_bi, read_file, encode_bi, BI_BYTES,
                             TERM_TEXT)
from diskfmt.listing import Console, Listing
from diskfmt.rdos import (JHData, LinkTimeout, LockedError, NotAProtocolFile, default_jhdata,
                          describe_os_error, write_atomic, ESTAR_LOCK, NSTAR_BUSY, NSTAR_LOCK)
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

STALE_AT_START = ("NDAT.DT", "TRM.DT")
LOCK_NAME = NSTAR_LOCK
BUSY_NAME = NSTAR_BUSY     # locked from taking a command to publishing its reply (QUIRKS M14)


class Abort(Exception):
    """End the program with a message and a non-zero exit."""


def _ask_int(console: Console, prompt: str) -> int:
    return console.accept(prompt)


def load_picture(path: str):
    """A .BI picture (120x128), or FormatError naming the file: checked to be a
    regular file of at most 1 MiB before anything is read, and a file of another
    size named for what it is, with the command that makes a .BI of it."""
    from pre.files import how_to_make_bi, what_file_is
    data = read_file(path, limit=1 << 20)
    if len(data) != BI_BYTES:
        raise FormatError(str(path), f"not a .BI picture: {what_file_is(data)}; "
                                     f"{how_to_make_bi(data)}")
    return decode_bi(data, str(path))


def new_images_dialogue(nova: Nova, console: Console) -> None:
    """Label 800 — "Save the current image?", "Input new images?", then the LEFT
    and RIGHT file names (``--left``/``--right`` answer them for scripts: main
    loads those before anything is asked)."""
    try:
        if _ask_int(console, "Save the current image? (0=NO) ") != 0:
            saved = True
            for side, image in (("LEFT", 1), ("RIGHT", 2)):
                console.type("Saving the current image to disk.")
                console.type(f"Input the {side} image filename.")
                name = console.prompt("")
                if name is None:
                    raise EOFError
                saved = _save_new(name, encode_bi(nova.picture(image)), console) and saved
            if saved:
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


def _save_new(name: str, data: bytes, console: Console) -> bool:
    """Write a new picture file; an existing one is never replaced (the rename
    itself refuses, so there is no check-then-replace race).  A name that cannot
    be written is said, and NSTAR goes on serving."""
    try:
        write_atomic(Path(name), data, replace=False)
        return True
    except FileExistsError:
        console.type(f" {name} exists; not overwritten.")
    except (OSError, ValueError) as exc:        # ValueError: a NUL byte in the name
        why = f"{name!r}: {exc.strerror if isinstance(exc, OSError) else exc}"
        console.type(f" Cannot save the image: {why}; not saved.")
    return False


STARTER_POLL_S = 1.0      # how often a wait for a command looks whether its starter still runs


def wait_for_command(jh: JHData, idle_timeout: float | None, starter_pid: int | None) -> None:
    """NWAIT for NCONT.DT (label 100).  With ``starter_pid`` (beyond 1985) the
    wait also ends, with :class:`Abort`, once this process is no longer that
    one's child: a starter killed outright (SIGKILL) cannot send the terminate
    command, and its NSTAR would otherwise wait out the idle timeout."""
    if starter_pid is None:
        jh.wait_for("NCONT.DT", timeout=idle_timeout or 0)
        return
    deadline = time.monotonic() + idle_timeout if idle_timeout else None
    while True:
        step = STARTER_POLL_S
        if deadline is not None:
            step = min(step, deadline - time.monotonic())
            if step <= 0:
                raise LinkTimeout(jh.not_written("NCONT.DT", idle_timeout))
        try:
            jh.wait_for("NCONT.DT", timeout=step)
            return
        except LinkTimeout:
            if os.getppid() != starter_pid:
                raise Abort(f"the program that started this one (pid {starter_pid}) has "
                            f"ended; stopping") from None


def run(nova: Nova, jh: JHData, console: Console, idle_timeout: float | None,
        starter_pid: int | None = None) -> int:
    """The label-100 loop: wait for NCONT.DT, take it, do it, publish the reply."""
    while True:
        nova.octek.hctab(128, 255)
        console.type(" Ready for the ECLIPSE command file.")
        wait_for_command(jh, idle_timeout, starter_pid)
        with jh.busy():                    # a starting ESTAR waits for this (QUIRKS M14)
            try:
                data = jh.read("NCONT.DT")
            except FileNotFoundError:      # set aside by a starting ESTAR: wait again
                continue
            except NotAProtocolFile as exc:
                if exc.problem.startswith("not a regular file"):   # a FIFO, link, directory
                    where = jh.set_aside("NCONT.DT", "not a file")
                    print(f"nstar: {exc} — not a command file; moved it to {where}. Waiting "
                          f"for the next command.", file=sys.stderr, flush=True)
                    continue
                raise Abort(f"{exc} — not a command file; left in place for "
                            f"inspection") from None
            console.type(" Command file found.")
            try:
                replies = nova.execute(data)
            except FormatError:
                raise Abort(f"{jh.path('NCONT.DT')}: {len(data)} bytes, expected 12 — not "
                            f"a command file; left in place for inspection") from None
            try:
                jh.delete("NCONT.DT")
            except OSError as exc:         # it would be obeyed again and again
                _publish(jh, replies, then="")     # the reply is not lost
                raise Abort(f"cannot delete {jh.path('NCONT.DT')} after carrying it out "
                            f"({exc.strerror}); stopping, as the same command would be "
                            f"carried out again") from None
            if data[:2] == b"\x00\x03":
                new_images_dialogue(nova, console)
            _publish(jh, replies)
        if nova.terminated:
            return 0


def _publish(jh: JHData, replies, then: str = " Waiting for the next command.") -> None:
    """Publish each reply; one that cannot be is said, and NSTAR keeps serving."""
    for reply in replies:
        try:
            jh.publish(reply.temp, reply.name, reply.data)
        except LinkTimeout as exc:     # nobody takes it: keep serving (QUIRKS M15)
            where = jh.set_aside(reply.temp, "unsent", as_name=reply.name)
            print(f"nstar: {exc} This {reply.name} reply was not published; kept as "
                  f"{where}.{then}", file=sys.stderr, flush=True)
        except OSError as exc:         # disk full, permissions, a directory in the way
            try:
                jh.delete(reply.temp)
            except OSError:
                pass
            print(f"nstar: cannot publish {reply.name}: {describe_os_error(exc)}. This "
                  f"reply is lost.{then}", file=sys.stderr, flush=True)


def sweep_at_start(jh: JHData, console: Console) -> None:
    """What an earlier run left: NSTAR's temporaries, a TERM.DT that is not a
    clean end's, and a command nobody waits for (no ESTAR holds ESTAR.LCK: a
    dead ESTAR's, e.g. a terminate) are set aside and said; a clean TERM.DT is
    just the last run's end, removed without a word."""
    for name in STALE_AT_START:
        where = jh.set_aside(name, "stale")
        if where:
            console.type(f" Found {name} from an earlier run; moved it to {where}")
    if jh.exists("TERM.DT"):
        try:
            clean = jh.read("TERM.DT") == TERM_TEXT.encode("ascii")
        except (OSError, NotAProtocolFile):
            clean = False
        if clean:
            jh.delete("TERM.DT")
        else:
            where = jh.set_aside("TERM.DT", "stale")
            if where:
                console.type(f" Found TERM.DT from an earlier run; moved it to {where}")
    if jh.exists("NCONT.DT") and not jh.held(ESTAR_LOCK):
        where = jh.set_aside("NCONT.DT", "stale")
        if where:
            console.type(f" Found NCONT.DT from an earlier run and no ESTAR waiting for it "
                         f"(none holds {ESTAR_LOCK}); moved it to {where}")


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="nstar",
        description="NSTAR, the NOVA half of the 1985 stereo vision system: holds the "
                    "stereo pair in the simulated OCTEK frame store and answers ESTAR's "
                    "commands (slices, edge bit maps, Star filter + block map) through "
                    "files in the JHDATA directory. Values not given as flags are asked "
                    "for as in 1985.")
    p.add_argument("--version", action="version", version=f"%(prog)s {version()}")
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
    p.add_argument("--starter-pid", type=int, default=None, metavar="PID",
                   help="BEYOND 1985: stop when the process PID that started this one has "
                        "ended (rig and the benches pass their own; a 1985 NSTAR waits on)")
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
        # Flags, files and the directory first: nothing asked, nothing moved on
        # a command line that cannot work.
        pics = None
        if args.left is not None:
            pics = [load_picture(args.left), load_picture(args.right)]
        if args.listing:
            listing_stream = open(args.listing, "a", encoding="ascii")
        listing = Listing(listing_stream)
        jhdir = args.jhdata or default_jhdata()
        jh = JHData(jhdir, me="NSTAR", peer="ESTAR", timeout=args.timeout)
        jh.lock(LOCK_NAME)                 # two NSTARs would take each other's commands
        jh.open_busy(BUSY_NAME)
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
        sweep_at_start(jh, console)
        if pics is not None:
            nova.load_pair(*pics)
            console.type(" Image loaded.")
            console.type(" Image loaded.")
        else:
            new_images_dialogue(nova, console)
        return run(nova, jh, console, args.idle_timeout, args.starter_pid)
    except (FormatError, LinkTimeout, LockedError, Abort) as exc:
        print(f"nstar: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:                 # the file system: one line, no traceback
        print(f"nstar: {describe_os_error(exc)}", file=sys.stderr)
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
