"""Pictures of what the rig saw, as BGR uint8 arrays (and PNG files).

Pure functions: nothing here touches NSTAR, ESTAR or the frame store; pass in
the pictures and the :class:`estar.program.LineResult` of a line.

* :func:`line_picture` — one epipolar line: both pictures enlarged, the line
  marked, each slice as a grey strip with its grey profile and EXQVFL features,
  and the matched edges joined left to right, labelled with their disparity.
* :func:`topdown_map` — the located edges seen from above: horizontal offset
  dx across, range dp up, with the error bounds ex and ep as bars.
* :func:`monitor_picture` — the OCTEK monitor with LEFT/RIGHT and the rows
  worked on labelled.
* :func:`save_png` — write a PNG atomically (temporary name, then rename);
  :func:`save_picture` the same, JPEG for a .jpg name.

Index conventions (as ESTAR's): a feature or match location is a 1-based index
i into the 128-pixel row, naming image column i-1.  Grey level k is drawn as
17k.

Layout of :func:`line_picture` for ``scale`` s (all numbers in output pixels)
---------------------------------------------------------------------------
* width ``LP_LEFT + 2*128*s + 10*s + LP_RIGHT`` = ``64 + 266*s``, height
  ``518 + 172*s`` (1128 x 1206 at the default s = 4);
* left picture's top-left corner at ``(x, y) = (LP_LEFT, LP_TOP)``, right
  picture's at ``(LP_LEFT + 128*s + 10*s, LP_TOP)``; picture pixel (col c,
  row r) covers ``x0 + c*s .. x0 + c*s + s-1``, ``y0 + r*s .. y0 + r*s + s-1``;
* below the pictures a panel with both slices at 2s pixels per column,
  starting at ``x = LP_LEFT + 5*s``: column c spans ``x + 2s*c .. x + 2s*c + 2s-1``.
  From top to bottom: left profile, left strip, the match band, right strip,
  right profile, legend.  A matched edge is a straight line from
  ``(centre of column LOC1-1, first row of the band)`` to
  ``(centre of column LOC2-1, last row of the band)``; the centre of column c
  is ``x + 2s*c + s``.  :func:`line_layout` returns these positions.
* each located edge is also ticked in the pictures, in its line's colour, on
  the ``s`` rows just above row IY's bracket: at column LOC1-1 in the left
  picture, LOC2-1 in the right.

Layout of :func:`topdown_map` (``max_range`` R, in the unit of the separation)
-----------------------------------------------------------------------------
The plot area is ``MAP_W`` x ``MAP_H`` = 640 x 800 pixels with its top-left
corner at ``(MAP_LEFT, MAP_TOP)`` = (70, 60); the image is
``(MAP_TOP + MAP_H + MAP_BOTTOM, MAP_LEFT + MAP_W + MAP_RIGHT)`` =
(1010, 740) pixels (rows, columns).  Range dp = 0 (the cameras) is the bottom
edge, dp = R the top; dx runs from -0.4R (left edge) to +0.4R (right edge).
So the point (dx, dp) is drawn at ``x = 70 + 320 + dx*800/R``,
``y = 60 + 800 - dp*800/R`` (rounded to the nearest pixel).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from diskfmt.rdos import write_atomic

__all__ = ["line_picture", "topdown_map", "fitted_range", "monitor_picture", "save_png",
           "save_picture", "used_matches", "line_layout",
           "LineLayout", "MATCH_PALETTE", "ROW_COLOUR", "POINT_COLOUR",
           "TRUTH_IN_COLOUR", "TRUTH_OUT_COLOUR"]

# --- colours (BGR) -----------------------------------------------------------
WHITE = (255, 255, 255)
BLACK = (0, 0, 0)
GRID = (200, 200, 200)
DARK = (60, 60, 60)
ROW_COLOUR = (0, 215, 255)                       # gold: the line IY in the pictures
MATCH_PALETTE = ((40, 40, 220), (200, 110, 0), (30, 150, 30),
                 (180, 0, 180), (0, 120, 230), (140, 90, 20))
FEATURE_FILLS = ((80, 170, 255), (255, 190, 90))  # alternating EXQVFL feature fills
PROFILE_COLOUR = (90, 40, 0)
POINT_COLOUR = (170, 60, 0)                      # located edge: dark blue
BAR_COLOUR = (230, 150, 80)                      # its error bars: lighter blue
TRUTH_IN_COLOUR = (0, 150, 0)                    # true range within dp +- ep
TRUTH_OUT_COLOUR = (0, 0, 220)                   # true range outside dp +- ep
BAND_SHADE = (242, 242, 242)

FONT = cv2.FONT_HERSHEY_SIMPLEX

# --- line_picture geometry -----------------------------------------------------
LP_LEFT = 48
LP_RIGHT = 16
LP_TOP = 64          # title (y 0..37) and picture captions above
NUM_H = 26           # two staggered rows of feature numbers
LEVEL_PX = 8         # profile: pixels per grey level
PROFILE_H = 15 * LEVEL_PX + 8
STRIP_H_PER_S = 6
MATCH_H_PER_S = 40
LEGEND_H = 78

# --- topdown_map geometry ---------------------------------------------------------
MAP_LEFT, MAP_TOP = 70, 60
MAP_W, MAP_H = 640, 800
MAP_RIGHT, MAP_BOTTOM = 30, 150


def _text(img, s, org, scale=0.45, colour=BLACK, thick=1, bg=None, pad=2):
    """putText with an optional filled background box; org is the bottom-left."""
    (w, h), base = cv2.getTextSize(s, FONT, scale, thick)
    x, y = int(org[0]), int(org[1])
    if bg is not None:
        cv2.rectangle(img, (x - pad, y - h - pad), (x + w + pad, y + base), bg, -1)
    cv2.putText(img, s, (x, y), FONT, scale, colour, thick, cv2.LINE_AA)
    return w, h


def _grey(pic, scale) -> np.ndarray:
    g = (np.clip(np.asarray(pic, dtype=np.int32), 0, 15) * 17).astype(np.uint8)
    g = cv2.resize(g, (g.shape[1] * scale, g.shape[0] * scale),
                   interpolation=cv2.INTER_NEAREST)
    return cv2.cvtColor(g, cv2.COLOR_GRAY2BGR)


# =============================================================================
# line_picture
# =============================================================================

@dataclass(frozen=True)
class LineLayout:
    """Where :func:`line_picture` puts things (output pixels)."""
    scale: int
    width: int
    height: int
    left_x: int          # left picture's top-left x
    right_x: int         # right picture's top-left x
    pic_y: int           # both pictures' top y
    panel_x: int         # slice panel's column 0 left edge
    pitch: int           # slice panel pixels per column (2*scale)
    left_nums_y: int
    left_profile_y: int
    left_strip_y: int
    band_y0: int         # first row of the match band
    band_y1: int         # last row of the match band
    right_strip_y: int
    right_profile_y: int
    right_nums_y: int
    legend_y: int

    def panel_centre(self, loc: int) -> int:
        """x of the centre of 1-based location ``loc`` in the slice panel."""
        return self.panel_x + self.pitch * (int(loc) - 1) + self.pitch // 2

    def picture_centre(self, loc: int, right: bool = False) -> int:
        """x of the centre of 1-based location ``loc`` in an enlarged picture."""
        x0 = self.right_x if right else self.left_x
        return x0 + self.scale * (int(loc) - 1) + self.scale // 2

    def row_y(self, iy: int) -> int:
        """y of the first output row of picture row ``iy``."""
        return self.pic_y + self.scale * int(iy)


def line_layout(scale: int = 4) -> LineLayout:
    """The geometry of :func:`line_picture` at ``scale`` (see module docstring)."""
    s = int(scale)
    if s < 1:
        raise ValueError("scale must be >= 1")
    gap = 10 * s
    pw, ph = 128 * s, 120 * s
    width = LP_LEFT + 2 * pw + gap + LP_RIGHT
    y = LP_TOP + ph + 10
    y += 22                                   # section caption
    left_nums = y
    left_profile = left_nums + NUM_H
    left_strip = left_profile + PROFILE_H + 4
    band0 = left_strip + STRIP_H_PER_S * s
    band1 = band0 + MATCH_H_PER_S * s - 1
    right_strip = band1 + 1
    right_profile = right_strip + STRIP_H_PER_S * s + 4
    right_nums = right_profile + PROFILE_H
    legend = right_nums + NUM_H + 22 + 6      # numbers, section caption
    height = legend + LEGEND_H
    return LineLayout(s, width, height, LP_LEFT, LP_LEFT + pw + gap, LP_TOP,
                      LP_LEFT + gap // 2, 2 * s, left_nums, left_profile, left_strip,
                      band0, band1, right_strip, right_profile, right_nums, legend)


def used_matches(result) -> list[tuple[int, int, int]]:
    """(edge, LOC1, LOC2) for every located edge of a line: the match entry LCSL
    recorded as the one its position came from (``result.used``).  Sorted by
    LOC1, then edge."""
    out = [(int(edge), int(result.used[edge][2]), int(result.used[edge][3]))
           for edge, pos in result.positions.items() if pos is not None]
    return sorted(out, key=lambda t: (t[1], t[0]))


def _profile(img, lay: LineLayout, y0: int, row: np.ndarray, features, nums_y: int) -> None:
    """Grey profile of one slice with its EXQVFL features as coloured intervals."""
    x0, p = lay.panel_x, lay.pitch
    x1 = x0 + 128 * p - 1
    y1 = y0 + PROFILE_H - 1

    def gy(g):
        return y0 + 4 + (15 - int(g)) * LEVEL_PX

    cv2.rectangle(img, (x0, y0), (x1, y1), GRID, 1)
    over = img.copy()
    for k, (start, stop, _gl, _gr) in enumerate(features, 1):
        a = x0 + p * (int(start) - 1)
        b = x0 + p * int(stop) - 1
        cv2.rectangle(over, (a, y0 + 1), (b, y1 - 1), FEATURE_FILLS[k % 2], -1)
    cv2.addWeighted(over, 0.45, img, 0.55, 0, dst=img)
    for g in (0, 5, 10, 15):
        cv2.line(img, (x0 + 1, gy(g)), (x1 - 1, gy(g)), GRID, 1)
        _text(img, str(g), (x0 - 8 - 9 * len(str(g)), gy(g) + 5), 0.4, DARK)
    pts = []
    for c, g in enumerate(row):
        pts += [(x0 + p * c, gy(g)), (x0 + p * c + p - 1, gy(g))]
    cv2.polylines(img, [np.array(pts, np.int32)], False, PROFILE_COLOUR, 2, cv2.LINE_AA)
    for k, (start, stop, _gl, _gr) in enumerate(features, 1):
        cx = x0 + (p * (int(start) - 1) + p * int(stop)) // 2
        s = str(k)
        (w, _h), _ = cv2.getTextSize(s, FONT, 0.36, 1)
        ty = nums_y + (11 if k % 2 else 23)
        col = tuple(int(v * 0.6) for v in FEATURE_FILLS[k % 2])
        _text(img, s, (cx - w // 2, ty), 0.36, col)


def _strip(img, lay: LineLayout, y0: int, row: np.ndarray) -> None:
    h = STRIP_H_PER_S * lay.scale
    g = (np.clip(np.asarray(row, np.int32), 0, 15) * 17).astype(np.uint8)[None, :]
    g = cv2.resize(g, (128 * lay.pitch, h), interpolation=cv2.INTER_NEAREST)
    img[y0:y0 + h, lay.panel_x:lay.panel_x + 128 * lay.pitch] = g[:, :, None]


def line_picture(left, right, result, scale: int = 4) -> np.ndarray:
    """Picture of one ESTAR line: ``left``/``right`` are the 120x128 pictures
    (grey 0..15), ``result`` the line's :class:`~estar.program.LineResult`
    (iyloc, features1, features2, matches, positions).  Returns a BGR uint8
    array of ``line_layout(scale).height`` x ``.width`` (see module docstring)."""
    from diskfmt.layouts import BI_COLS, BI_ROWS
    left, right = np.asarray(left), np.asarray(right)
    if left.shape != (BI_ROWS, BI_COLS) or right.shape != (BI_ROWS, BI_COLS):
        raise ValueError(f"pictures must be {BI_ROWS}x{BI_COLS}, got {left.shape} and "
                         f"{right.shape}")
    lay = line_layout(scale)
    s = lay.scale
    iy = int(result.iyloc)
    if not 0 <= iy < 120:
        raise ValueError(f"line IY={iy} outside 0..119")
    img = np.full((lay.height, lay.width, 3), 255, np.uint8)
    used = used_matches(result)
    n_loc = len(used)
    n_edges = 2 * len(result.features1)

    _text(img, f"ESTAR line IY = {iy}: what the rig saw", (LP_LEFT, 26), 0.75, BLACK, 2)
    summary = (f"{len(result.features1)} left / {len(result.features2)} right features, "
               f"{n_loc} of {n_edges} left edges located")
    (sw, _), _ = cv2.getTextSize(summary, FONT, 0.5, 1)
    _text(img, summary, (lay.width - LP_RIGHT - sw, 26), 0.5, DARK)

    # --- pictures with the row bracketed and the located edges ticked --------
    for x0, pic, name in ((lay.left_x, left, "LEFT picture"),
                          (lay.right_x, right, "RIGHT picture")):
        img[lay.pic_y:lay.pic_y + 120 * s, x0:x0 + 128 * s] = _grey(pic, s)
        _text(img, f"{name} (128x120, {s}x)", (x0, lay.pic_y - 8), 0.5, BLACK)
        ya, yb = lay.row_y(iy) - 1, lay.row_y(iy) + s
        for yy in (ya, yb):
            if lay.pic_y <= yy < lay.pic_y + 120 * s:
                cv2.line(img, (x0, yy), (x0 + 128 * s - 1, yy), ROW_COLOUR, 1)
        mid = lay.row_y(iy) + s // 2
        for tip, d in ((x0 - 2, -1), (x0 + 128 * s + 1, 1)):
            tri = np.array([[tip, mid], [tip + d * 9, mid - 6], [tip + d * 9, mid + 6]], np.int32)
            cv2.fillPoly(img, [tri], ROW_COLOUR)
    _text(img, f"IY={iy}", (4, lay.row_y(iy) - 10), 0.4, DARK)

    # --- slices ----------------------------------------------------------------
    rows = (left[iy], right[iy])
    _text(img, f"Left slice, row {iy}: grey profile (0..15) with EXQVFL features 1.."
               f"{len(result.features1)}", (lay.panel_x, lay.left_nums_y - 6), 0.5, BLACK)
    _profile(img, lay, lay.left_profile_y, rows[0], result.features1, lay.left_nums_y)
    _strip(img, lay, lay.left_strip_y, rows[0])
    _strip(img, lay, lay.right_strip_y, rows[1])
    _profile(img, lay, lay.right_profile_y, rows[1], result.features2,
             lay.right_nums_y)
    _text(img, f"Right slice, row {iy}: grey profile with EXQVFL features 1.."
               f"{len(result.features2)}",
          (lay.panel_x, lay.right_nums_y + NUM_H + 18), 0.5, BLACK)
    for y0, lab in ((lay.left_strip_y, "L"), (lay.right_strip_y, "R")):
        _text(img, lab, (lay.panel_x - 22, y0 + STRIP_H_PER_S * s // 2 + 6), 0.55, BLACK, 2)

    # --- matched edges ---------------------------------------------------------
    placed: list[tuple[int, int, int, int]] = []
    band_mid = (lay.band_y0 + lay.band_y1) // 2
    _text(img, "matched", (4, band_mid - 4), 0.4, DARK)
    _text(img, "edges", (4, band_mid + 12), 0.4, DARK)
    lines = []
    for i, (edge, loc1, loc2) in enumerate(used):
        colour = MATCH_PALETTE[i % len(MATCH_PALETTE)]
        a = (lay.panel_centre(loc1), lay.band_y0)
        b = (lay.panel_centre(loc2), lay.band_y1)
        lines.append((a, b, colour, loc1 - loc2))
        cv2.line(img, a, b, colour, 1, cv2.LINE_8)
        for x0, loc, right_pic in ((lay.left_x, loc1, False), (lay.right_x, loc2, True)):
            cx = lay.picture_centre(loc, right_pic)
            yb = lay.row_y(iy) - 2
            cv2.line(img, (cx, yb - s + 1), (cx, yb), colour, max(1, s // 2), cv2.LINE_8)
    for a, b, colour, disp in lines:
        label = str(disp)
        (w, h), _ = cv2.getTextSize(label, FONT, 0.4, 1)
        best = None
        for t in (0.5, 0.35, 0.65, 0.2, 0.8, 0.27, 0.42, 0.58, 0.73, 0.12, 0.88):
            x = a[0] + t * (b[0] - a[0])
            y = a[1] + t * (b[1] - a[1])
            r = (int(x) - w // 2 - 2, int(y) - h // 2 - 2, int(x) + w // 2 + 2, int(y) + h // 2 + 2)
            if all(r[2] < q[0] or r[0] > q[2] or r[3] < q[1] or r[1] > q[3] for q in placed):
                best = r
                break
        if best is None:
            continue                                  # no room: the line still shows
        placed.append(best)
        cv2.rectangle(img, (best[0], best[1]), (best[2], best[3]), WHITE, -1)
        cv2.rectangle(img, (best[0], best[1]), (best[2], best[3]), colour, 1)
        _text(img, label, (best[0] + 2, best[3] - 3), 0.4, colour)

    # --- legend ------------------------------------------------------------------
    y = lay.legend_y
    cv2.line(img, (LP_LEFT, y), (lay.width - LP_RIGHT, y), GRID, 1)
    x = LP_LEFT
    y += 24
    cv2.line(img, (x, y - 5), (x + 26, y - 5), ROW_COLOUR, 3)
    _text(img, "row IY (bracketed in both pictures)", (x + 34, y), 0.45)
    x2 = lay.width // 2
    cv2.rectangle(img, (x2, y - 12), (x2 + 12, y + 1), FEATURE_FILLS[1], -1)
    cv2.rectangle(img, (x2 + 14, y - 12), (x2 + 26, y + 1), FEATURE_FILLS[0], -1)
    _text(img, "EXQVFL feature k: a grey step, start..stop (numbered)", (x2 + 34, y), 0.45)
    y += 28
    for j in range(3):
        cv2.line(img, (x + 9 * j, y - 12), (x + 9 * j + 8, y + 2), MATCH_PALETTE[j], 2)
    _text(img, "matched edge (the entry LCSL used): left LOC1 joined to right LOC2, "
               "ticked above the row in both pictures; label = disparity LOC1-LOC2 "
               "in 128-px columns (larger = nearer)", (x + 34, y), 0.42)
    return img


# =============================================================================
# topdown_map
# =============================================================================

def _as_point(p) -> tuple[float, float, float, float]:
    """(dp, dx, ep, ex) from a 4-sequence, a 6-sequence POS column
    (dp, dx, dy, ep, ex, ey) or a mapping/object with dp, dx, ep, ex."""
    if isinstance(p, dict):
        low = {str(k).lower(): v for k, v in p.items()}
        return tuple(float(low[k]) for k in ("dp", "dx", "ep", "ex"))
    if isinstance(p, (tuple, list, np.ndarray)):
        if len(p) == 4:
            return tuple(float(v) for v in p)
        if len(p) == 6:
            return float(p[0]), float(p[1]), float(p[3]), float(p[4])
        raise ValueError(f"a point is (dp, dx, ep, ex) or (dp, dx, dy, ep, ex, ey), "
                         f"got {len(p)} values")
    return tuple(float(getattr(p, k)) for k in ("dp", "dx", "ep", "ex"))


def _nice_step(span: float, target: int) -> float:
    raw = span / target
    mag = 10 ** np.floor(np.log10(raw))
    for m in (1, 2, 5, 10):
        if m * mag >= raw:
            return float(m * mag)
    return float(10 * mag)


def fitted_range(dps, floor: float = 1.0) -> float:
    """A range axis fitted to the data: the next "nice" value (1, 1.5, 2, 2.5,
    3, 4, 5, 6, 8 times a power of ten) above 1.1 times the 95th percentile
    of the ranges ``dps``; points beyond it are drawn as arrows."""
    d = np.asarray([float(v) for v in dps if np.isfinite(v) and v > 0], dtype=np.float64)
    top = 1.1 * float(np.percentile(d, 95)) if d.size else floor
    top = max(top, 1e-9)
    mag = 10 ** np.floor(np.log10(top))
    for m in (1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10):
        if m * mag >= top - 1e-12:
            return float(m * mag)
    return float(10 * mag)


def topdown_map(points, truth=None, max_range: float = 25, title: str | None = None,
                unit: str = "ft", error_bars: bool = True, bar_cap: float = 0.2,
                separation: float = 0.75, virtual_distance: float = 180) -> np.ndarray:
    """The robot's view of the room from above.  ``points``: located edges as
    (dp, dx, ep, ex) tuples, 6-tuples as in LineResult.positions, or dicts with
    those keys; ``truth``: None or one true range (or None) per point.
    Each point is drawn at (dx, dp) with a bar +-ex across and +-ep along the
    range (``error_bars``); a bar half longer than ``bar_cap * max_range`` is
    cut there and drawn without its end tick.  A true range is marked at
    (dx, true range), green when inside dp +- ep, red when not.  Points beyond
    ``max_range`` are shown as arrows on the top edge.  ``unit`` names the unit
    of the camera separation (all distances are in it); the cameras are drawn
    at dx = 0 (left, the origin of LCSL's axes) and dx = ``separation``, the
    field of view from ``virtual_distance`` (pixels).  The legend lists only
    what is drawn.  Returns a BGR uint8 array of 1010 x 740 (module docstring)."""
    R = float(max_range)
    if not R > 0:
        raise ValueError("max_range must be > 0")
    pts = [_as_point(p) for p in points]
    if truth is not None and len(truth) != len(pts):
        raise ValueError(f"truth has {len(truth)} entries for {len(pts)} points")
    k = MAP_H / R
    hw = 0.4 * R
    cap = float(bar_cap) * R
    H = MAP_TOP + MAP_H + MAP_BOTTOM
    W = MAP_LEFT + MAP_W + MAP_RIGHT
    img = np.full((H, W, 3), 255, np.uint8)
    plot = np.full((MAP_H, MAP_W, 3), 255, np.uint8)   # drawn separately: clips for free

    def px(dx, dp):        # plot-local pixel
        return int(round(MAP_W / 2 + dx * k)), int(round(MAP_H - dp * k))

    step = _nice_step(R, 5)
    # range bands (alternately shaded) and grid
    b = 0.0
    while b < R:
        if int(round(b / step)) % 2 == 1:
            cv2.rectangle(plot, (0, px(0, min(b + step, R))[1]), (MAP_W - 1, px(0, b)[1]),
                          BAND_SHADE, -1)
        b += step
    xstep = _nice_step(2 * hw, 8)
    xv = -np.floor(hw / xstep) * xstep
    while xv <= hw + 1e-9:
        cv2.line(plot, (px(xv, 0)[0], 0), (px(xv, 0)[0], MAP_H - 1),
                 (150, 150, 150) if abs(xv) < 1e-9 else GRID, 1)
        xv += xstep
    r = step
    while r <= R + 1e-9:
        cv2.line(plot, (0, px(0, r)[1]), (MAP_W - 1, px(0, r)[1]), GRID, 1)
        r += step
    # field of view: ESTAR's dx = (LOC1-60)*dp/DV for LOC1 = 1..128
    for slope in ((1 - 60) / virtual_distance, (128 - 60) / virtual_distance):
        far = R * 1.05
        a, bpt = px(0, 0), px(slope * far, far)
        n = 40
        for j in range(0, n, 2):
            p0 = (int(a[0] + (bpt[0] - a[0]) * j / n), int(a[1] + (bpt[1] - a[1]) * j / n))
            p1 = (int(a[0] + (bpt[0] - a[0]) * (j + 1) / n),
                  int(a[1] + (bpt[1] - a[1]) * (j + 1) / n))
            cv2.line(plot, p0, p1, (170, 170, 170), 1, cv2.LINE_AA)
    # lines tying far-off true ranges to their points, error bars, points, truth marks
    beyond = 0
    n_truth = n_in = 0
    marks = []
    if truth is not None:
        for (dp, dx, ep, ex), tz in zip(pts, truth):
            if tz is None or not np.isfinite(tz):
                continue
            n_truth += 1
            inside = abs(dp - float(tz)) <= ep
            n_in += inside
            if tz > R:
                continue
            colour = TRUTH_IN_COLOUR if inside else TRUTH_OUT_COLOUR
            if not inside:          # tie a far-off true range to its point
                cv2.line(plot, px(dx, min(dp, R)), px(dx, float(tz)), (150, 150, 235), 1,
                         cv2.LINE_AA)
            marks.append((px(dx, float(tz)), colour))
    capped = 0
    shown = [p for p in pts if p[0] <= R]
    for dp, dx, ep, ex in (shown if error_bars else ()):
        x, y = px(dx, dp)
        cut_p, cut_x = ep > cap, ex > cap
        capped += cut_p or cut_x
        ep_, ex_ = min(ep, cap), min(ex, cap)
        y0, y1 = px(dx, dp + ep_)[1], px(dx, max(dp - ep_, 0))[1]
        x0, x1 = px(dx - ex_, dp)[0], px(dx + ex_, dp)[0]
        cv2.line(plot, (x, y0), (x, y1), BAR_COLOUR, 1, cv2.LINE_8)
        cv2.line(plot, (x0, y), (x1, y), BAR_COLOUR, 1, cv2.LINE_8)
        if not cut_p:
            cv2.line(plot, (x - 3, y0), (x + 3, y0), BAR_COLOUR, 1, cv2.LINE_8)
            cv2.line(plot, (x - 3, y1), (x + 3, y1), BAR_COLOUR, 1, cv2.LINE_8)
        if not cut_x:
            cv2.line(plot, (x0, y - 3), (x0, y + 3), BAR_COLOUR, 1, cv2.LINE_8)
            cv2.line(plot, (x1, y - 3), (x1, y + 3), BAR_COLOUR, 1, cv2.LINE_8)
    for dp, dx, ep, ex in pts:
        if dp > R:
            beyond += 1
            x = px(dx, R)[0]
            tri = np.array([[x, 0], [x - 5, 9], [x + 5, 9]], np.int32)
            cv2.fillPoly(plot, [tri], POINT_COLOUR)
            continue
        cv2.circle(plot, px(dx, dp), 4, POINT_COLOUR, -1, cv2.LINE_8)
    for at, colour in marks:
        cv2.drawMarker(plot, at, colour, cv2.MARKER_TILTED_CROSS, 9, 2, cv2.LINE_AA)
    # the cameras: the left one at LCSL's origin, the right one a separation away
    for cx in (0.0, float(separation)):
        x, y = px(cx, 0)
        cv2.rectangle(plot, (x - 5, y - 8), (x + 5, y - 1), BLACK, -1)
    img[MAP_TOP:MAP_TOP + MAP_H, MAP_LEFT:MAP_LEFT + MAP_W] = plot
    cv2.rectangle(img, (MAP_LEFT - 1, MAP_TOP - 1), (MAP_LEFT + MAP_W, MAP_TOP + MAP_H), DARK, 1)

    # axis labels
    r = step
    while r <= R + 1e-9:
        y = MAP_TOP + px(0, r)[1]
        s = f"{r:g} {unit}"
        (w, h), _ = cv2.getTextSize(s, FONT, 0.45, 1)
        _text(img, s, (MAP_LEFT - 8 - w, y + h // 2), 0.45, DARK)
        r += step
    _text(img, "0", (MAP_LEFT - 8 - 10, MAP_TOP + MAP_H + 5), 0.45, DARK)
    xv = -np.floor(hw / xstep) * xstep
    while xv <= hw + 1e-9:
        s = f"{xv:+g}" if abs(xv) > 1e-9 else "0"
        (w, _h), _ = cv2.getTextSize(s, FONT, 0.45, 1)
        _text(img, s, (MAP_LEFT + px(xv, 0)[0] - w // 2, MAP_TOP + MAP_H + 20), 0.45, DARK)
        xv += xstep
    xlabel = f"horizontal offset dx ({unit}, + = right)"
    (w, _h), _ = cv2.getTextSize(xlabel, FONT, 0.5, 1)
    _text(img, xlabel, (MAP_LEFT + MAP_W // 2 - w // 2, MAP_TOP + MAP_H + 42), 0.5, BLACK)
    cam_x = MAP_LEFT + max(px(0.0, 0)[0], px(float(separation), 0)[0]) + 12
    _text(img, "cameras", (cam_x, MAP_TOP + MAP_H - 4), 0.4, BLACK)
    rl = np.full((24, 200, 3), 255, np.uint8)
    _text(rl, f"range dp ({unit})", (4, 18), 0.5, BLACK)
    rl = cv2.rotate(rl, cv2.ROTATE_90_COUNTERCLOCKWISE)
    ry = MAP_TOP + MAP_H // 2 - 100
    img[ry:ry + 200, 2:26] = rl

    head = title or "Top-down map of located edges (the robot's view of the room)"
    _text(img, head, (MAP_LEFT, 26), 0.65, BLACK, 2)
    sub = f"{len(pts)} points"
    if beyond:
        sub += f", {beyond} beyond {R:g} {unit} (arrows on the top edge)"
    if truth is not None:
        sub += f"; true range inside dp +- ep for {n_in} of {n_truth}"
    _text(img, sub, (MAP_LEFT, 48), 0.45, DARK)

    # legend: only what is drawn
    y = MAP_TOP + MAP_H + 70
    x = MAP_LEFT
    row = 23
    if pts:
        cv2.circle(img, (x + 6, y - 5), 4, POINT_COLOUR, -1)
        what = "located edge at (dx, dp)"
        if error_bars and shown:
            cv2.line(img, (x + 6, y - 16), (x + 6, y + 6), BAR_COLOUR, 1)
            cv2.line(img, (x - 4, y - 5), (x + 16, y - 5), BAR_COLOUR, 1)
            what += "; bars: +-ex across, +-ep along the range"
        _text(img, what, (x + 26, y), 0.45)
        y += row
        notes = []
        if capped:
            notes.append(f"{capped} bars cut at {cap:g} {unit} (no end tick)")
        if beyond:
            notes.append(f"arrow: a point beyond {R:g} {unit}")
        if notes:
            if beyond:
                tri = np.array([[x + 6, y - 12], [x + 1, y - 3], [x + 11, y - 3]], np.int32)
                cv2.fillPoly(img, [tri], POINT_COLOUR)
            _text(img, "; ".join(notes), (x + 26, y), 0.45)
            y += row
    if n_truth:
        cv2.drawMarker(img, (x + 6, y - 5), TRUTH_IN_COLOUR, cv2.MARKER_TILTED_CROSS, 9, 2)
        cv2.drawMarker(img, (x + 20, y - 5), TRUTH_OUT_COLOUR, cv2.MARKER_TILTED_CROSS, 9, 2)
        _text(img, "true range at the same dx (green: within dp +- ep; red: outside, "
                   "joined to its point)", (x + 34, y), 0.45)
        y += row
    for j in range(0, 24, 6):
        cv2.line(img, (x + j, y - 5), (x + j + 3, y - 5), (150, 150, 150), 1)
    _text(img, "field of view (LOC1 = 1..128); shaded bands every "
               f"{step:g} {unit}", (x + 34, y), 0.45)
    return img


# =============================================================================
# monitor_picture
# =============================================================================

MON_HEAD = 34          # strip above the monitor for the LEFT / RIGHT labels
MON_SIDE = 58          # margin left of the monitor for the row labels


def monitor_picture(octek, lines=(), scale: int = 3) -> np.ndarray:
    """:func:`octek_sim.monitor.render_monitor` with what a reader needs to
    read it: LEFT and RIGHT over the two pictures (where NSTAR loads them in
    the frame store, x 26 and x 166) and each row ESTAR worked on marked and
    labelled ``IY=y`` beside the screen.  The monitor itself sits unchanged at
    (MON_SIDE, MON_HEAD)."""
    from nstar.program import LEFT_X, RIGHT_X
    from octek_sim.monitor import BEZEL, render_monitor
    mon = render_monitor(octek, scale)
    h, w = mon.shape[:2]
    img = np.full((h + MON_HEAD, w + MON_SIDE, 3), 255, np.uint8)
    img[MON_HEAD:, MON_SIDE:] = mon
    for x0, name in ((LEFT_X, "LEFT picture"), (RIGHT_X, "RIGHT picture")):
        a = MON_SIDE + BEZEL + x0 * scale
        b = a + 128 * scale - 1
        cv2.line(img, (a, MON_HEAD - 6), (b, MON_HEAD - 6), DARK, 2)
        label = f"{name} (x {x0}..{x0 + 127})"
        (tw, _), _ = cv2.getTextSize(label, FONT, 0.55, 1)
        _text(img, label, ((a + b) // 2 - tw // 2, MON_HEAD - 12), 0.55, BLACK, 1)
    for y in sorted(set(int(v) for v in lines)):
        if not 0 <= y < 120:
            continue
        yc = MON_HEAD + BEZEL + y * scale + scale // 2
        x1 = MON_SIDE - 2
        tri = np.array([[x1, yc], [x1 - 9, yc - 5], [x1 - 9, yc + 5]], np.int32)
        cv2.fillPoly(img, [tri], ROW_COLOUR)
        _text(img, f"IY={y}", (2, yc + 5), 0.42, DARK)
    return img


# =============================================================================
# save_png
# =============================================================================

PICTURE_FORMATS = {".png": (".png", []), ".jpg": (".jpg", [cv2.IMWRITE_JPEG_QUALITY, 95]),
                   ".jpeg": (".jpg", [cv2.IMWRITE_JPEG_QUALITY, 95])}


def save_picture(path, image) -> Path:
    """:func:`save_png`, or JPEG when the name ends in .jpg/.jpeg; any other
    suffix is refused (ValueError) before anything is written."""
    suffix = Path(path).suffix.lower()
    if suffix not in PICTURE_FORMATS:
        raise ValueError(f"{path}: can write .png or .jpg pictures, not "
                         f"{suffix or 'a name without a suffix'}")
    return save_png(path, image, fmt=suffix)


def save_png(path, image, fmt: str = ".png") -> Path:
    """Write ``image`` (BGR or grey uint8) to ``path`` as PNG (or the format
    ``fmt`` of :data:`PICTURE_FORMATS`): encoded in memory, then published by
    the project's one atomic write (diskfmt.rdos.write_atomic) — readers never
    see a partial file, and on any failure the temporary file is removed and an
    existing ``path`` is left as it was.  Returns the path."""
    path = Path(path)
    img = np.asarray(image)
    if img.dtype != np.uint8 or img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] not in (1, 3, 4)):
        raise ValueError(f"not an 8-bit image: dtype {img.dtype}, shape {img.shape}")
    ext, params = PICTURE_FORMATS[fmt]
    ok, buf = cv2.imencode(ext, img, params)
    if not ok:
        raise ValueError(f"{ext} encoding failed")
    write_atomic(path, buf.tobytes())            # the project's one atomic publish
    return path


# =============================================================================
# the pictures in docs/pictures.md
# =============================================================================

def make_doc_pictures(outdir, iy: int = 60, star=(85, 36, 30)) -> list[Path]:
    """Make docs/img/monitor.png, monitor-parked.png, line-<iy>.png and
    topdown.png from the bundled laboratory pair (``python -m rig.pictures
    [OUTDIR]``)."""
    from diskfmt.layouts import decode_bi, Command, encode_ncont, CODE_STAR
    from estar.program import in_process_rig
    from rig.scene import bundled_path, bundled_range
    from rig.truth import true_range_at

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    ecl = in_process_rig(left, right)
    nova = ecl.link.nova
    res = ecl.lcln(iy)
    written = [save_png(outdir / "monitor-parked.png", monitor_picture(nova.octek, [iy]))]
    written.append(save_png(outdir / f"line-{iy}.png", line_picture(left, right, res)))
    truth = bundled_range()
    points, tz = [], []
    for edge, pos in res.positions.items():
        if pos is None:
            continue
        points.append(pos)
        loc1 = res.used[edge][2]
        tz.append(true_range_at(truth, iy, loc1))
    written.append(save_png(outdir / "topdown.png", topdown_map(
        points, tz, title=f"Top-down map of the edges located on line IY = {iy}")))
    x, y, rad = star
    nova.execute(encode_ncont(Command(CODE_STAR, 1, x, y, rad, 0)))
    written.insert(0, save_png(outdir / "monitor.png", monitor_picture(nova.octek, [iy])))
    return written


if __name__ == "__main__":
    import sys
    for p in make_doc_pictures(sys.argv[1] if len(sys.argv) > 1 else "docs/img"):
        print(p)
