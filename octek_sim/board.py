"""The OCTEK 2000 image analyser card: a 320x240 frame store of 4-bit pixels and
the IACF4.LB library calls the 1985 listings make.

Buffers follow the library's convention, which the listings rely on: a buffer
read by RVBLK carries a header word first and the pixels from word 2 on (PRE and
NSTAR pass ``IDAT(2)`` to RDBLK/WRBLK and ``IDAT`` to WVBLK).  Here a buffer is a
numpy int array whose element 0 is that header; FORTRAN ``IDAT(k)`` is
``buf[k-1]``.  The header holds the pixel count (QUIRKS M7).

Display-only calls (cursor, grey-scale tables, camera sync) keep their state so
that a picture of the monitor can show it later.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

WIDTH = 320
HEIGHT = 240


class OctekError(RuntimeError):
    """A call the real board would have refused."""


@dataclass
class DisplayState:
    """What the monitor showed beyond the pixels."""
    cursor_kind: str = "none"            # "crosshair" (XHAIR) or "box" (BOXCUR/BOCUR)
    cursor_x: int = 128                  # HCTAB position; 255 moves it off-screen
    cursor_y: int = 255
    box_w: int = 0
    box_h: int = 0
    greyscale_tables: list[int] = field(default_factory=list)
    interlaced: bool = False
    external_sync: bool = False
    camera_on: bool = False
    microcode_running: bool = False


class Octek:
    """One simulated board (the device control table ICT is this object)."""

    def __init__(self):
        self.frame = np.zeros((HEIGHT, WIDTH), dtype=np.uint8)
        self.display = DisplayState()
        self.open = False

    # --- board control ------------------------------------------------------
    def sintro(self, memory_words: int = 63 * 1024) -> int:
        """SINTRO — introduce the board to the system; returns IER (1 = ok)."""
        self.open = True
        return 1

    def oremove(self) -> None:
        """OREMOVE — release the board."""
        self.open = False

    def lxb(self, unit=None) -> None:
        """LXB — load the IACMON.XB microcode (no microcode is needed here)."""

    def mprun(self, *args) -> None:
        """MPRUN — start the board's processor."""
        self.display.microcode_running = True

    def greyscale(self, table: int) -> None:
        """GREYSCALE — load a linear grey-scale look-up table."""
        self.display.greyscale_tables.append(table)

    def intlace(self, on: int) -> None:
        """INTLACE — interlaced (1) or non-interlaced (0) display."""
        self.display.interlaced = bool(on)

    def sync(self, external: int) -> int:
        """SYNC — choose the clock; returns ILOCK.  No camera is attached to the
        simulated board, so external sync never locks (PRE then reports the
        camera missing, as the 1985 code does)."""
        self.display.external_sync = bool(external)
        return 0 if external else 1

    def von(self, *args) -> None:
        """VON — camera input on."""
        self.display.camera_on = True

    def voff(self) -> None:
        """VOFF — camera input off."""
        self.display.camera_on = False

    # --- cursors ------------------------------------------------------------
    def xhair(self) -> None:
        """XHAIR — select the cross-hair cursor."""
        self.display.cursor_kind = "crosshair"

    def boxcur(self, w: int, h: int) -> None:
        """BOXCUR (spelled BOCUR once in NSTAR.FR) — select a w x h box cursor."""
        self.display.cursor_kind = "box"
        self.display.box_w, self.display.box_h = int(w), int(h)

    bocur = boxcur

    def hctab(self, x: int, y: int) -> None:
        """HCTAB — move the cursor; NSTAR parks it at y = 255 (off-screen)."""
        self.display.cursor_x, self.display.cursor_y = int(x), int(y)

    # --- pixels -------------------------------------------------------------
    def rvblk(self, x: int, width: int, y: int, height: int) -> np.ndarray:
        """RVBLK — read a width x height block, row by row, into a buffer whose
        word 1 is a header (the pixel count) and words 2.. the pixels.

        Pixels outside the frame store read as 0; the listings never use them
        (NSTAR's edge-map loop skips rows outside the picture by index)."""
        n = width * height
        buf = np.zeros(n + 1, dtype=np.int32)
        buf[0] = n
        block = np.zeros((height, width), dtype=np.int32)
        y0, y1 = max(y, 0), min(y + height, HEIGHT)
        x0, x1 = max(x, 0), min(x + width, WIDTH)
        if y0 < y1 and x0 < x1:
            block[y0 - y:y1 - y, x0 - x:x1 - x] = self.frame[y0:y1, x0:x1]
        buf[1:] = block.reshape(-1)
        return buf

    def wvblk(self, buf, x: int, width: int, y: int, height: int) -> None:
        """WVBLK — write a block from buffer words 2.. (word 1 is the header).
        Only the low 4 bits of each word reach the 4-bit frame store."""
        data = np.asarray(buf)[1:1 + width * height].astype(np.int64) & 15
        block = data.reshape(height, width)
        y0, y1 = max(y, 0), min(y + height, HEIGHT)
        x0, x1 = max(x, 0), min(x + width, WIDTH)
        if y0 < y1 and x0 < x1:
            self.frame[y0:y1, x0:x1] = block[y0 - y:y1 - y, x0 - x:x1 - x]

    def pxfill(self, value: int, x: int, width: int, y: int, height: int) -> None:
        """PXFILL — fill a rectangle with one grey level."""
        self.frame[max(y, 0):max(y + height, 0), max(x, 0):max(x + width, 0)] = int(value) & 15

    def irdpix(self, x: int, y: int) -> int:
        """IRDPIX — read one pixel."""
        if 0 <= x < WIDTH and 0 <= y < HEIGHT:
            return int(self.frame[y, x])
        return 0

    def gvect(self, x1: int, y1: int, x2: int, y2: int, value: int) -> None:
        """GVECT — draw a straight line (PRE draws its black box with four)."""
        n = max(abs(x2 - x1), abs(y2 - y1))
        for i in range(n + 1):
            x = x1 + round(i * (x2 - x1) / n) if n else x1
            y = y1 + round(i * (y2 - y1) / n) if n else y1
            if 0 <= x < WIDTH and 0 <= y < HEIGHT:
                self.frame[y, x] = int(value) & 15
