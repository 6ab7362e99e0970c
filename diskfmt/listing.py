"""FORTRAN output as the 1985 programs produced it: FORMAT edit descriptors for
the debug listing (unit 12) and TYPE lines for the console.

Unit 12 records start with a carriage-control character, as on the line
printer Appendix D was printed on: ' ' plain line, '0' one blank line first,
'1' a new page (written here as a form feed).  Trailing blanks are dropped.
"""

from __future__ import annotations

import sys

from .dgreal import Real, fortran_f


def fi(value: int, w: int) -> str:
    """``Iw``: right-justified; a field too narrow is filled with asterisks."""
    text = str(int(value))
    return "*" * w if len(text) > w else text.rjust(w)


def ff(value, w: int, d: int) -> str:
    """``Fw.d`` of a DG REAL (or exact number)."""
    return fortran_f(value, w, d)


def type_text(*parts) -> str:
    """A TYPE statement: text as written, each INTEGER with one blank before it
    (the DG list-directed width is not documented; QUIRKS M13)."""
    out = []
    for p in parts:
        if isinstance(p, (int, Real)) and not isinstance(p, bool):
            out.append(" " + (str(p) if isinstance(p, int) else ff(p, 10, 4).strip()))
        else:
            out.append(str(p))
    return "".join(out)


class Listing:
    """FORTRAN unit 12: the debug listing, to a file or to standard output."""

    def __init__(self, stream=None):
        self.stream = stream if stream is not None else sys.stdout

    def record(self, text: str) -> None:
        """Write one record; its first character is carriage control."""
        cc, body = (text[:1], text[1:]) if text else (" ", "")
        prefix = {"1": "\f", "0": "\n"}.get(cc, "")
        self.stream.write(prefix + body.rstrip() + "\n")

    def records(self, texts) -> None:
        for t in texts:
            self.record(t)

    def flush(self) -> None:
        self.stream.flush()


def accept_integer(text: str) -> int:
    """An ACCEPTed INTEGER: a whole number that fits 16 bits, else ValueError
    with the problem in words."""
    t = text.strip()
    try:
        value = int(t)
    except ValueError:
        shown = repr(t) if t else "an empty line"
        raise ValueError(f"{shown} is not a number (a whole number is wanted)") from None
    if not -32768 <= value <= 32767:
        raise ValueError(f"{value} does not fit a 16-bit INTEGER (-32768..32767)")
    return value


def accept(ask, say, prompt: str, convert=accept_integer):
    """ACCEPT "prompt", V — the one ACCEPT of the three dialogues (PRE, NSTAR,
    ESTAR).  ``ask(prompt)`` shows the prompt and returns one line (None at the
    end of input: EOFError); ``convert`` turns it into the value or raises
    ValueError naming the problem, which ``say`` shows before asking again
    (DG FORTRAN would have stopped the program)."""
    while True:
        answer = ask(prompt)
        if answer is None:
            raise EOFError
        try:
            return convert(answer)
        except ValueError as exc:
            say(f"** {exc}; answer again.")


class Console:
    """The operator's terminal: TYPE lines and ACCEPT prompts."""

    def __init__(self, out=None, inp=None, quiet: bool = False, verbose: bool = False):
        self.out = out if out is not None else sys.stdout
        self.inp = inp if inp is not None else sys.stdin
        self.quiet = quiet
        self.verbose = verbose and not quiet   # the per-comparison chatter of MASL etc.

    def type(self, *parts) -> None:
        if not self.quiet:
            self.out.write(type_text(*parts) + "\n")
            self.out.flush()

    def accept(self, prompt: str, convert=accept_integer):
        """:func:`accept` on this terminal."""
        return accept(self.prompt, self.type, prompt, convert)

    def prompt(self, text: str) -> str | None:
        """Show the prompt, read one line; None at end of input."""
        self.out.write(text)
        self.out.flush()
        line = self.inp.readline()
        if not line:
            self.out.write("\n")
            return None
        return line.strip()
