"""PRE.FR's interactive menu (Appendix F), driving a simulated OCTEK board.

Prompts and TYPE texts are the listing's, with the OCR's lost leading blanks
of the one-digit menu lines restored and the DASHER screen-control strings
(``<33>E``, ``<33>j``, ``<33>k<33>J``) not sent (QUIRKS.md P-lines).  Numbers
are read like ``ACCEPT``, file names like ``READ(11,1000)`` (one line).

Where the 1985 program would stop with a run-time error or write over a file,
this one says what is wrong in one line and goes back to the prompt: a
menu answer that is not a number, a missing or wrongly-sized file, an output
that already exists (unless the menu was started with ``force``).
"""

from __future__ import annotations

import sys
from typing import Callable, TextIO

import numpy as np

from diskfmt.listing import accept
from octek_sim.board import Octek

from . import framestore
from .cartoon import DEFAULT_T
from .files import PreError, check_output, publish
from diskfmt.layouts import BI_BYTES, VD_BYTES, FormatError, decode_bi, read_file

ICMAX = 11

MENU = (
    "Image Preprocessor Command List",
    "",
    "Choose a function:",
    " 1 Video input (Camera) control",
    " 2 Create condensed image for NSTAR",
    " 3 Cartoon the image using horizontal and verical QV",
    " 4 Output the 128x120 condensed image to disk file",
    " 5 Input a 128x120 condensed image from disk file",
    " 6 Dummied out",
    " 7 Dummied out",
    " 8 Dummied out",
    " 9 Dummied out",
    "10 Input image from disk file to OCTEK",
    "11 Output image from OCTEK to disk file",
    "-1 To exit the program",
)

PROMPT = "Enter function number (0 for help): "
VIDEO_PROMPT = "Video Input command (-1 to exit): "
NO_SYNC = "** Camera Input is missing (unable to find video sync)"


class EndOfInput(Exception):
    """Standard input ran out: the session ends as if -1 had been entered."""


class PreMenu:
    """The 1985 PRE program.  ``camera`` (optional) is a callable returning a
    240x256 4-bit picture: a stand-in for the Dage camera, so that SYNC locks
    and "Camera on" digitizes one frame into the frame store."""

    def __init__(self, board: Octek | None = None, stdin: TextIO | None = None,
                 stdout: TextIO | None = None, force: bool = False,
                 threshold: int = DEFAULT_T,
                 camera: Callable[[], np.ndarray] | None = None):
        self.ict = board if board is not None else Octek()
        self.stdin = stdin if stdin is not None else sys.stdin
        self.stdout = stdout if stdout is not None else sys.stdout
        self.force = force
        self.threshold = threshold
        self.camera = camera

    # --- FORTRAN I/O ----------------------------------------------------------
    def type(self, text: str = "") -> None:
        """TYPE "text": one line on the terminal."""
        self.stdout.write(text + "\n")
        self.stdout.flush()

    def _line(self) -> str:
        line = self.stdin.readline()
        if line == "":
            raise EndOfInput
        return line.rstrip("\r\n")

    def accept(self, prompt: str) -> int:
        """ACCEPT "prompt", I: an INTEGER from one line (:func:`diskfmt.listing.accept`);
        the end of input ends the session (EndOfInput)."""
        return accept(self._ask, self.type, prompt)

    def _ask(self, prompt: str) -> str:
        self.stdout.write(prompt)
        self.stdout.flush()
        return self._line()

    def read_name(self) -> str:
        """READ(11,1000) NFILE(1) with FORMAT(S40): the file name on one line."""
        return self._line().strip()

    # --- the program ------------------------------------------------------------
    def run(self) -> int:
        """The main program: banner, board set-up, menu loop.  Returns 0."""
        self.type()
        self.type("Robot Vision Image Preprocessor")
        ier = self.ict.sintro(63 * 1024)
        if ier != 1:
            self.type(f"INTRO ECODE: {ier}")
            self.type("UNABLE TO INITIALIZE")
            return 1
        # OPEN(3,"IACMON.XB"): the simulated board needs no microcode file.
        self.ict.lxb(3)
        self.ict.mprun(0, 1)
        self.ict.greyscale(1)
        self.ict.greyscale(2)
        try:
            self._menu()
            while True:                                      # label 7
                ic = self.accept(PROMPT)
                if ic < 0:
                    break
                if ic == 0 or ic > ICMAX:
                    self._menu()
                    continue
                handler = (self.cmd_video, self.cmd_condense, self.cmd_cartoon,
                           self.cmd_store_bi, self.cmd_load_bi, self._dummy, self._dummy,
                           self._dummy, self._dummy, self.cmd_load_vd, self.cmd_store_vd)[ic - 1]
                handler()
        except EndOfInput:
            self.type()
        self.ict.oremove()                                   # label 999
        return 0

    def _menu(self) -> None:                                 # label 5
        for line in MENU:
            self.type(line)

    def _dummy(self) -> None:                                # commands 6-9: GOTO 7
        pass

    # --- command 1 --------------------------------------------------------------
    def cmd_video(self) -> None:
        """Command 1, Video Input (Camera) Port Control (label 10)."""
        while True:
            self.type()                                      # label 10
            self.type("Video Input Control")
            self.type("Camera on (1), Camera off (2)")
            while True:                                      # label 11
                ic = self.accept(VIDEO_PROMPT)
                if ic == 2:
                    self.ict.voff()                          # label 14
                    self._internal_clock()
                    return
                if ic < 0:
                    return
                if ic != 1:
                    break                                    # GOTO 10
                self.ict.intlace(1)
                ilock = self.ict.sync(1)
                if self.camera is not None:
                    ilock = 1                                # the stand-in camera gives sync
                if ilock == 0:
                    self.type(NO_SYNC)                       # label 19
                    self._internal_clock()
                    return
                self.ict.von(0)
                try:
                    framestore.put_vd_picture(self.ict, self.camera())
                except PreError as exc:
                    self.type(f"** {exc}")

    def _internal_clock(self) -> None:                       # label 15
        self.ict.sync(0)
        self.ict.intlace(0)

    # --- command 2 --------------------------------------------------------------
    def cmd_condense(self) -> None:
        self.type()
        self.type("Condense the current image to 128x120")
        framestore.condense_frame(self.ict)

    # --- command 3 --------------------------------------------------------------
    def cmd_cartoon(self) -> None:
        """Command 3: the listing keeps only one TYPE line; the first line and
        the work are ours (QUIRKS.md)."""
        self.type()
        self.type("Cartoon the current 128x120 image")
        self.type(" using passes of horizontal and vertical QV processing.")
        framestore.cartoon_frame(self.ict, self.threshold)

    # --- command 4 --------------------------------------------------------------
    def cmd_store_bi(self) -> None:
        self.type("Saving the current 128x120 image to disk.")
        self.type(" Input the desired file name.")
        name = self.read_name()
        try:
            _need_name(name)
            check_output(name, self.force)
            publish(name, framestore.store_bi_frame(self.ict), self.force)
        except (PreError, OSError) as exc:
            self.type(f" Open error on file. IER= {_msg(exc)}")

    # --- command 5 --------------------------------------------------------------
    def cmd_load_bi(self) -> None:
        self.type("Loading a 128x120 image from disk.")
        self.type(" Input the desired file name.")
        name = self.read_name()
        try:
            _need_name(name)
            data = read_file(name)
        except (PreError, FormatError) as exc:
            self.type(f" Open error on file. IER= {_msg(exc)}")
            return
        try:
            if len(data) != BI_BYTES:
                raise FormatError(name, f"{len(data)} bytes, expected {BI_BYTES} for a .BI"
                                  + (" (that is a .VD file's size)" if len(data) == VD_BYTES else ""))
            decode_bi(data, name)                            # grey levels 0..15 only
        except FormatError as exc:
            self.type(f" Read error on file. {exc}; the screen is unchanged")
            return
        framestore.load_bi_frame(self.ict, data)

    # --- command 10 -------------------------------------------------------------
    def cmd_load_vd(self) -> None:
        self.type()
        self.type(" INPUT FROM DISK")
        self.type()
        self.type(" What file name?")
        name = self.read_name()
        try:
            _need_name(name)
            data = read_file(name)
        except (PreError, FormatError) as exc:
            self.type(f" File open error- {_msg(exc)}")
            return
        if len(data) != VD_BYTES:
            hint = " (that is a .BI file's size)" if len(data) == BI_BYTES else ""
            self.type(f"Read error-- {name}: {len(data)} bytes, expected {VD_BYTES} for a .VD"
                      f"{hint}; the screen is unchanged")
            return
        framestore.load_vd_frame(self.ict, data)
        self.type("FILE DISPLAYED")

    # --- command 11 -------------------------------------------------------------
    def cmd_store_vd(self) -> None:
        self.type()
        self.type(" OUTPUT TO DISK")
        self.type()
        self.type("What file name? ")
        name = self.read_name()
        try:
            _need_name(name)
            check_output(name, self.force)
            publish(name, framestore.store_vd_frame(self.ict), self.force)
        except (PreError, OSError) as exc:
            self.type(f"Open error on output file-- {_msg(exc)}")
            return
        self.type("THE FILE IS SAVED.")


def _need_name(name: str) -> None:
    if not name:
        raise PreError("no file name given")


def _msg(exc: Exception) -> str:
    if isinstance(exc, OSError) and not isinstance(exc, PreError):
        return f"{exc.filename}: {exc.strerror}"
    return str(exc)


def run_menu(stdin=None, stdout=None, force: bool = False, threshold: int = DEFAULT_T,
             camera=None, board: Octek | None = None) -> int:
    return PreMenu(board, stdin, stdout, force, threshold, camera).run()
