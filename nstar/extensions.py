"""NSTAR's bit-map extensions beyond 1985: Appendix B's radial bit map and the rectangular map
operations B-2..B-8, as new command codes (``diskfmt.bitmap_files``; docs/formats.md).

The 1985 NSTAR ignores codes 11..13 and the faithful ESTAR never sends them: ``Nova`` carries
them out only with ``Options(bitmap_extensions=True)`` (``nstar --bitmap-extensions``).  Pixel
work stays in NSTAR, as Holten divided it; the operations on the maps are
:mod:`model.bitmaps`.

* code 11 -- the Star filter around (IXCTR, IYCTR) with radius IRAD exactly as code 1 (same
  console, cursor and /BLOB/ state), then the radial bit map of its region -> RBMAP.DT;
* code 12 -- label 500's 16x16 edge map at (IXCTR, IYCTR), side IDN, exactly as code 4, then
  B-2..B-8 of it -> OPMAP.DT;
* code 13 -- code 1's scaled block map, then B-2..B-8 of it -> OPMAP.DT.

The radial map is Appendix B's "Map Generation" (the listing never built it): centre = the
centre of the region's extents (the Star's ICNTR box); radius R = the greatest distance from the
centre to an in-range pixel's centre in that box, plus half a pixel, "so the region's greatest
extents just reach the edges of the circle"; 16 sectors of 22.5 degrees clockwise from the +x
axis (rows run down), 16 rings of R/16; each (sector, ring) cell sampled at 4 x 4 points evenly
spread in angle and radius, each point reading the pixel it falls in; a bit is set when more
than 80 % (ITHRB) of its 16 samples lie in the region's grey range IGMN..IGMX inside the box.
IEEE double arithmetic: this is not 1985 code.
"""

from __future__ import annotations

import math

import numpy as np

from diskfmt.bitmap_files import (CODE_BLOCK_OPERATIONS, CODE_EDGE_OPERATIONS, CODE_RADIAL_MAP,
                                  RadialMap, encode_opmap, encode_rbmap)
from diskfmt.dgreal import Real
from diskfmt.layouts import decode_block
from .bitmaps import ITHRB, command_geometry, edge_map

SAMPLES = 4                      # per cell side: 4 angles x 4 radii


def radial_map(frame: np.ndarray, box, grey_range) -> tuple[list[int], float, float, float]:
    """The radial bit map of the region in ``box`` = (x0, x1, y0, y1), inclusive frame
    columns and rows, whose pixels have grey levels in ``grey_range`` = (IGMN, IGMX).

    Returns (the 16 sector words clockwise from sector 0 -- NOT yet stored most-ones-first --,
    centre x, centre y (continuous: pixel k spans [k, k+1)), radius R)."""
    x0, x1, y0, y1 = (int(v) for v in box)
    igmn, igmx = grey_range
    sub = np.asarray(frame)[y0:y1 + 1, x0:x1 + 1].astype(np.int64)
    inside = (sub >= igmn) & (sub <= igmx)
    cx, cy = (x0 + x1 + 1) / 2.0, (y0 + y1 + 1) / 2.0
    if not inside.any():
        return [0] * 16, cx, cy, 0.0
    rr, cc = np.nonzero(inside)
    radius = float(np.hypot(x0 + cc + 0.5 - cx, y0 + rr + 0.5 - cy).max()) + 0.5
    f = (np.arange(SAMPLES) + 0.5) / SAMPLES
    sector = np.arange(16)[:, None, None, None]
    ring = np.arange(16)[None, :, None, None]
    theta = (sector + f[None, None, :, None]) * (2 * math.pi / 16)
    rho = (ring + f[None, None, None, :]) * (radius / 16)
    px = np.floor(cx + rho * np.cos(theta)).astype(np.int64)
    py = np.floor(cy + rho * np.sin(theta)).astype(np.int64)
    ok = (px >= x0) & (px <= x1) & (py >= y0) & (py <= y1)
    hit = np.zeros(px.shape, dtype=bool)
    hit[ok] = inside[py[ok] - y0, px[ok] - x0]
    count = hit.reshape(16, 16, -1).sum(axis=2)              # (sector, ring)
    bits = count * 100 // (SAMPLES * SAMPLES) > ITHRB
    words = [int(sum(1 << r for r in range(16) if bits[s, r])) for s in range(16)]
    return words, cx, cy, radius


def execute(nova, code: int, imf: int, ixctr: int, iyctr: int, irad: int, idn: int):
    """Carry out one extension command on ``nova`` (a ``nstar.program.Nova``); its replies."""
    from model.bitmaps import all_operations, radial_canonical   # only when asked for
    from .program import Reply
    ixoff, ixmin, ixmax, iymin, iymax, cx, cy, ixc, iyc = (
        int(v) for v in command_geometry(imf, ixctr, iyctr))
    bounds = (ixmin, ixmax, iymin, iymax)
    if code == CODE_EDGE_OPERATIONS:
        nova.console.type(" Bit map operations of the region edge (extension). IYC=", iyc,
                          " IXC=", ixc)
        ibmap, ixlft, iytop = edge_map(nova.octek, ixc, iyc, idn, bounds)
        nova.octek.boxcur(18, 18)
        nova.octek.hctab(ixlft, 255)
        return [Reply("OPMAP.DT", encode_opmap(code, all_operations(ibmap)))]
    block = decode_block(nova._star(imf, cx, cy, ixc, iyc, irad, idn, ixoff, 0, bounds).data)
    if code == CODE_BLOCK_OPERATIONS:
        nova.console.type(" Bit map operations of the block (extension).")
        return [Reply("OPMAP.DT", encode_opmap(code, all_operations(block.ibmap)))]
    assert code == CODE_RADIAL_MAP
    icntr = block.icntr
    box = (max(icntr[0] + ixoff, ixmin), min(icntr[1] + ixoff, ixmax),
           max(icntr[2], iymin), min(icntr[3], iymax))
    if box[0] > box[1] or box[2] > box[3]:
        sectors, mx, my, radius = [0] * 16, float(ixc), float(iyc), 0.0
    else:
        sectors, mx, my, radius = radial_map(nova.octek.frame, box, (icntr[4], icntr[5]))
    irmap, orientation = radial_canonical(sectors)
    nova.console.type(" Radial bit map (extension). Orientation=", orientation,
                      " Radius=", round(radius, 2))
    rm = RadialMap(orientation, Real.from_float(radius / 16), int(mx) - ixoff, int(my),
                   list(icntr), list(irmap))
    return [Reply("RBMAP.DT", encode_rbmap(rm))]
