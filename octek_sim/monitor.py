"""A picture of the OCTEK monitor: what the operator saw beside the NOVA.

:func:`render_monitor` draws the 320x240 frame store (``octek.frame[y, x]``,
grey level k shown as 17k) enlarged by nearest neighbour, with the board's
cursor overlaid as the display hardware put it, and a one-line caption below.

Geometry of the returned BGR image (height, width) =
``(240*scale + 2*BEZEL + CAPTION_H, 320*scale + 2*BEZEL)``: the screen sits in
a dark bezel ``BEZEL`` pixels wide, the caption strip below it; frame-store
pixel (x, y) covers image rows ``BEZEL + y*scale .. BEZEL + y*scale+scale-1``
and columns ``BEZEL + x*scale .. BEZEL + x*scale+scale-1``.

The cursor (``octek.display``; set by XHAIR, BOXCUR/BOCUR and HCTAB) is drawn
in :data:`CURSOR_COLOUR`, whole frame-store pixels at a time:

* ``"box"`` — the outline of a ``box_w`` x ``box_h`` box whose top-left pixel
  is (cursor_x, cursor_y): the frame-store pixels of its border rows and
  columns.  NSTAR puts the 18x18 box one pixel outside the 16x16 edge bit map
  it reads (label 500) and the block box exactly on the Star region (label 400).
* ``"crosshair"`` — a cross centred on (cursor_x, cursor_y): frame-store
  pixels ``cursor_x +- 2 .. +- CROSS_ARM`` on row cursor_y and the same rows on
  column cursor_x; the centre pixel and its 8 neighbours stay visible.
* ``"none"`` — nothing.

When the cursor is off-screen (cursor_y outside 0..239; NSTAR parks it at
y = 255 after every command, keeping the x where it last worked) a small
triangle pointing down is drawn on the bottom edge of the screen at cursor_x,
and the caption says "parked".
"""

from __future__ import annotations

import cv2
import numpy as np

from .board import Octek, WIDTH, HEIGHT

CURSOR_COLOUR = (0, 0, 255)        # BGR red: no grey level of the frame store is red
CAPTION_H = 30                     # caption strip below the bezel, image rows
BEZEL = 10                         # dark border round the screen, image pixels
BEZEL_COLOUR = (40, 40, 40)
CROSS_ARM = 7                      # cross-hair arm reach, frame-store pixels
PARK_MARK = 4                      # half-width / height of the parked marker, frame pixels

__all__ = ["render_monitor", "CURSOR_COLOUR", "CAPTION_H", "BEZEL", "CROSS_ARM", "PARK_MARK"]


def _grey_bgr(frame: np.ndarray, scale: int) -> np.ndarray:
    g = (np.clip(frame.astype(np.int32), 0, 15) * 17).astype(np.uint8)
    g = cv2.resize(g, (g.shape[1] * scale, g.shape[0] * scale),
                   interpolation=cv2.INTER_NEAREST)
    return cv2.cvtColor(g, cv2.COLOR_GRAY2BGR)


def _paint(img, x0, x1, y0, y1, scale, colour) -> None:
    """Paint frame-store pixels x0..x1, y0..y1 (inclusive, clipped to the screen)."""
    x0, x1 = max(x0, 0), min(x1, WIDTH - 1)
    y0, y1 = max(y0, 0), min(y1, HEIGHT - 1)
    if x0 > x1 or y0 > y1:
        return
    img[y0 * scale:(y1 + 1) * scale, x0 * scale:(x1 + 1) * scale] = colour


def _caption(d) -> str:
    parked = not 0 <= d.cursor_y < HEIGHT
    where = (f"parked off-screen (y={d.cursor_y}), last at x={d.cursor_x}" if parked
             else f"at x={d.cursor_x}, y={d.cursor_y}")
    if d.cursor_kind == "box":
        cur = f"box cursor {d.box_w}x{d.box_h} {where}"
    elif d.cursor_kind == "crosshair":
        cur = f"cross-hair cursor {where}"
    else:
        cur = "no cursor selected"
    return f"OCTEK frame store 320x240, grey k shown as 17k | {cur}"


def render_monitor(octek: Octek, scale: int = 3) -> np.ndarray:
    """The OCTEK monitor as it showed ``octek`` now: the frame store's pixels,
    the cursor state in ``octek.display`` (kind, position, box size) and a
    caption naming them.  Returns a BGR uint8 array of shape
    ``(240*scale + 2*BEZEL + CAPTION_H, 320*scale + 2*BEZEL, 3)``.  The board is not changed."""
    scale = int(scale)
    if scale < 1:
        raise ValueError("scale must be >= 1")
    d = octek.display
    screen = _grey_bgr(np.asarray(octek.frame), scale)
    cx, cy = int(d.cursor_x), int(d.cursor_y)
    on_screen = 0 <= cy < HEIGHT
    if d.cursor_kind != "none" and on_screen:
        if d.cursor_kind == "box":
            w, h = max(int(d.box_w), 1), max(int(d.box_h), 1)
            _paint(screen, cx, cx + w - 1, cy, cy, scale, CURSOR_COLOUR)
            _paint(screen, cx, cx + w - 1, cy + h - 1, cy + h - 1, scale, CURSOR_COLOUR)
            _paint(screen, cx, cx, cy, cy + h - 1, scale, CURSOR_COLOUR)
            _paint(screen, cx + w - 1, cx + w - 1, cy, cy + h - 1, scale, CURSOR_COLOUR)
        else:
            _paint(screen, cx - CROSS_ARM, cx - 2, cy, cy, scale, CURSOR_COLOUR)
            _paint(screen, cx + 2, cx + CROSS_ARM, cy, cy, scale, CURSOR_COLOUR)
            _paint(screen, cx, cx, cy - CROSS_ARM, cy - 2, scale, CURSOR_COLOUR)
            _paint(screen, cx, cx, cy + 2, cy + CROSS_ARM, scale, CURSOR_COLOUR)
    elif d.cursor_kind != "none" and 0 <= cx < WIDTH:
        # Parked: a triangle on the bottom edge (y = 255 is below the screen).
        bottom = HEIGHT * scale - 1
        mid = cx * scale + scale // 2
        tri = np.array([[mid - PARK_MARK * scale, bottom - PARK_MARK * scale],
                        [mid + PARK_MARK * scale, bottom - PARK_MARK * scale],
                        [mid, bottom]], dtype=np.int32)
        cv2.fillPoly(screen, [tri], CURSOR_COLOUR, lineType=cv2.LINE_8)
    h, w = screen.shape[:2]
    out = np.empty((h + 2 * BEZEL + CAPTION_H, w + 2 * BEZEL, 3), np.uint8)
    out[:] = BEZEL_COLOUR
    out[BEZEL:BEZEL + h, BEZEL:BEZEL + w] = screen
    text = _caption(d)
    font, fs = cv2.FONT_HERSHEY_SIMPLEX, 0.5
    while fs > 0.25 and cv2.getTextSize(text, font, fs, 1)[0][0] > out.shape[1] - 16:
        fs -= 0.05
    (_, th), _ = cv2.getTextSize(text, font, fs, 1)
    cv2.putText(out, text, (BEZEL, h + 2 * BEZEL + (CAPTION_H + th) // 2 - 4), font, fs,
                (255, 255, 255), 1, cv2.LINE_AA)
    return out
