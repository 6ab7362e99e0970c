"""Pictures of the simulated world (BGR uint8 arrays; ``rig.pictures.save_png`` writes them).

* :func:`room_map` -- the room from above: walls, obstacle footprints, the true vertical edges
  (dots), and walks drawn as paths with the cameras' field of view at chosen poses;
* :func:`look_strip` -- looks side by side: each look's left and right 128x120 .BI pictures
  enlarged 2x, captioned with the look number and pose.

Map axes: room X to the right, Z up the page (forward from the bundled pose), ``scale`` pixels
per foot, with a 1 ft grid.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from rig.pictures import BLACK, WHITE, _grey, _text

OBSTACLE = (150, 150, 150)
WALL = (40, 40, 40)
EDGE_DOT = (0, 110, 200)
PATH_COLOURS = ((200, 90, 0), (30, 30, 220), (30, 150, 30), (160, 0, 160))
FOV = (0, 190, 255)
HALF_FOV = math.atan(64.0 / 180.0)          # half the 128-px picture's width at 180 px


def room_map(room, walks=None, fov_looks=(), scale: int = 30, margin: int = 40,
             title: str | None = None) -> np.ndarray:
    """``walks``: {label: list of Pose}; ``fov_looks``: indices into the first walk whose
    field of view (left camera, 8 ft long) is drawn."""
    walks = walks or {}
    x0, x1, z0, z1 = room.bounds
    w = int(round((x1 - x0) * scale)) + 2 * margin
    h = int(round((z1 - z0) * scale)) + 2 * margin + (30 if title else 0)
    top = margin + (30 if title else 0)
    img = np.full((h, w, 3), 255, np.uint8)

    def px(x, z):
        return (int(round(margin + (x - x0) * scale)), int(round(top + (z1 - z) * scale)))

    for gx in range(int(math.ceil(x0)), int(math.floor(x1)) + 1):
        cv2.line(img, px(gx, z0), px(gx, z1), (235, 235, 235), 1)
    for gz in range(int(math.ceil(z0)), int(math.floor(z1)) + 1):
        cv2.line(img, px(x0, gz), px(x1, gz), (235, 235, 235), 1)
    for ox0, ox1, oz0, oz1 in room.obstacles:
        cv2.rectangle(img, px(ox0, oz1), px(ox1, oz0), OBSTACLE, -1)
        cv2.rectangle(img, px(ox0, oz1), px(ox1, oz0), BLACK, 1)
    cv2.rectangle(img, px(x0, z1), px(x1, z0), WALL, 3)
    for e in room.vertical_edges:
        cv2.circle(img, px(e[0, 0], e[0, 2]), 2, EDGE_DOT, -1)
    first = next(iter(walks.values()), None)
    for i in fov_looks:
        if first is None or not 0 <= i < len(first):
            continue
        p = first[i]
        c = p.camera_centre("left")
        pts = [px(c[0], c[2])]
        for a in (-HALF_FOV, HALF_FOV):
            hh = math.radians(p.heading_deg) + a
            pts.append(px(c[0] + 8 * math.sin(hh), c[2] + 8 * math.cos(hh)))
        overlay = img.copy()
        cv2.fillPoly(overlay, [np.array(pts)], FOV)
        img = cv2.addWeighted(overlay, 0.25, img, 0.75, 0)
        _text(img, str(i), (pts[0][0] + 4, pts[0][1] - 4), 0.4, BLACK)
    for k, (label, poses) in enumerate(walks.items()):
        colour = PATH_COLOURS[k % len(PATH_COLOURS)]
        pts = np.array([px(p.x, p.z) for p in poses])
        cv2.polylines(img, [pts], False, colour, 2, cv2.LINE_AA)
        for p in poses:
            a = math.radians(p.heading_deg)
            cv2.line(img, px(p.x, p.z), px(p.x + 0.3 * math.sin(a), p.z + 0.3 * math.cos(a)),
                     colour, 1, cv2.LINE_AA)
            cv2.circle(img, px(p.x, p.z), 2, colour, -1)
        _text(img, label, (margin + 6, top + 18 + 18 * k), 0.5, colour, bg=WHITE)
    if title:
        _text(img, title, (margin, 24), 0.6, BLACK)
    return img


def look_strip(looks, labels=None, scale: int = 2, per_row: int = 2) -> np.ndarray:
    """Each look as [left .BI | right .BI] enlarged ``scale``x, captioned, ``per_row`` a row."""
    tiles = []
    for i, look in enumerate(looks):
        pair = np.hstack([_grey(look.left_bi, scale), np.full((120 * scale, 4, 3), 255, np.uint8),
                          _grey(look.right_bi, scale)])
        cap = np.full((22, pair.shape[1], 3), 255, np.uint8)
        p = look.pose
        text = labels[i] if labels else (f"x {p.x:.2f} z {p.z:.2f} heading {p.heading_deg:.0f}"
                                         + (f" pitch {p.pitch_deg:.1f} roll {p.roll_deg:.1f}"
                                            if p.pitch_deg or p.roll_deg else ""))
        _text(cap, text, (2, 16), 0.45, BLACK)
        tiles.append(np.vstack([cap, pair]))
    rows = []
    for r in range(0, len(tiles), per_row):
        row = tiles[r:r + per_row]
        while len(row) < per_row:
            row.append(np.full_like(tiles[0], 255))
        gap = np.full((tiles[0].shape[0], 10, 3), 255, np.uint8)
        parts = []
        for t in row:
            parts += [t, gap]
        rows.append(np.hstack(parts[:-1]))
    return np.vstack(rows)


def bitmap_sheet(picture, icntr, maps: dict, radial_raw, orientation: int,
                 title: str = "") -> np.ndarray:
    """Appendix B on one region: the 128x120 picture (3x) with the region's ICNTR box; the
    rectangular map A and its B-2..B-8 maps (``maps``: name -> 16 column words, bit 0 the top
    row); the radial map (``radial_raw``: 16 sector words clockwise from +x, bit 0 innermost)
    as a disc, the sector stored first (``orientation``) outlined."""
    s = 3
    pic = _grey(picture, s)
    x0, x1, y0, y1 = icntr[:4]
    cv2.rectangle(pic, (x0 * s, y0 * s), ((x1 + 1) * s - 1, (y1 + 1) * s - 1), (0, 0, 230), 1)
    cell, gap = 7, 14
    tile = 16 * cell
    grid_w = 4 * tile + 3 * gap
    grid = np.full((2 * (tile + 22) + gap, grid_w, 3), 255, np.uint8)
    for n, name in enumerate(("A", "V", "L", "R", "H", "T", "B", "P")):
        ox, oy = (n % 4) * (tile + gap), (n // 4) * (tile + 22 + gap) + 20
        _text(grid, name, (ox, oy - 5), 0.5, BLACK)
        words = [int(w) & 0xFFFF for w in maps[name]]
        for j in range(16):
            for i in range(16):
                on = (words[j] >> i) & 1
                cv2.rectangle(grid, (ox + j * cell, oy + i * cell),
                              (ox + j * cell + cell - 2, oy + i * cell + cell - 2),
                              (40, 40, 40) if on else (225, 225, 225), -1)
    rad = 150
    disc = np.full((2 * rad + 30, 2 * rad + 20, 3), 255, np.uint8)
    cx, cy = rad + 10, rad + 24
    _text(disc, "radial map", (10, 16), 0.5, BLACK)
    for sec in range(16):
        for ring in range(16):
            on = (int(radial_raw[sec]) >> ring) & 1
            a0, a1 = sec * 22.5, (sec + 1) * 22.5
            r0, r1 = ring * rad / 16, (ring + 1) * rad / 16
            pts = [(cx + r * math.cos(math.radians(a)), cy + r * math.sin(math.radians(a)))
                   for r, a in ((r0, a0), (r1, a0))]
            pts += [(cx + r1 * math.cos(math.radians(a)), cy + r1 * math.sin(math.radians(a)))
                    for a in np.linspace(a0, a1, 5)]
            pts += [(cx + r0 * math.cos(math.radians(a)), cy + r0 * math.sin(math.radians(a)))
                    for a in np.linspace(a1, a0, 5)]
            poly = np.array(pts).round().astype(np.int32)
            cv2.fillPoly(disc, [poly], (40, 40, 40) if on else (225, 225, 225))
            cv2.polylines(disc, [poly], True, (255, 255, 255), 1)
    a0, a1 = orientation * 22.5, (orientation + 1) * 22.5
    edge = [(cx, cy)] + [(cx + rad * math.cos(math.radians(a)), cy + rad * math.sin(math.radians(a)))
                         for a in np.linspace(a0, a1, 9)]
    cv2.polylines(disc, [np.array(edge).round().astype(np.int32)], True, (0, 0, 230), 2)
    h = max(pic.shape[0], grid.shape[0], disc.shape[0]) + 30
    parts = []
    for p in (pic, grid, disc):
        col = np.full((h - 30, p.shape[1], 3), 255, np.uint8)
        col[:p.shape[0]] = p
        parts += [col, np.full((h - 30, 16, 3), 255, np.uint8)]
    body = np.hstack(parts[:-1])
    head = np.full((30, body.shape[1], 3), 255, np.uint8)
    _text(head, title, (4, 20), 0.55, BLACK)
    return np.vstack([head, body])
