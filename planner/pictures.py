"""Pictures of a drive: the top-down floor map (octree cells projected:
occupied / free / unknown / uncertain), the true room's obstacle outlines and walls, the
planned path, the true and estimated trajectories; and the run's animation.

Room X runs to the right, room Z up the picture (the vehicle starts looking
up).  Pure functions returning BGR uint8 arrays; files are written elsewhere.
"""

from __future__ import annotations

import cv2
import numpy as np



COL_FREE = (235, 235, 235)
COL_OCC = (40, 40, 40)
COL_UNKNOWN = (160, 160, 160)
COL_UNCERTAIN = (110, 110, 150)
COL_TRUTH = (0, 140, 255)        # orange: the true obstacles and walls
COL_PATH = (200, 0, 200)         # magenta: the planned path
COL_TRUE = (0, 160, 0)           # green: the true trajectory
COL_EST = (255, 80, 0)           # blue: the estimated (dead-reckoned) trajectory
COL_GOAL = (0, 0, 220)


def _text(img, s, org, scale=0.45, colour=(0, 0, 0)):
    cv2.putText(img, s, org, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), 3, cv2.LINE_AA)
    cv2.putText(img, s, org, cv2.FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv2.LINE_AA)


def drive_map(fm, bounds, obstacles=(), path=(), true_track=(), est_track=(), goal=None,
              title: str = "", px_per_ft: int = 16, heading=None) -> np.ndarray:
    """The map over ``bounds`` (x0, x1, z0, z1) of the room (plus 1 ft)."""
    x0, x1, z0, z1 = bounds
    x0, x1, z0, z1 = x0 - 1, x1 + 1, z0 - 1, z1 + 1
    W = int(round((x1 - x0) * px_per_ft))
    H = int(round((z1 - z0) * px_per_ft))
    top = 22
    img = np.full((H + top + 20, W, 3), COL_UNKNOWN, np.uint8)

    def px(x, z):
        return (int(round((x - x0) * px_per_ft)), int(round(top + (z1 - z) * px_per_ft)))

    if fm is not None:
        nz, nx = fm.shape
        colours = np.array([COL_FREE, COL_OCC, COL_UNKNOWN, COL_UNCERTAIN], np.uint8)  # state order
        cellimg = colours[fm.cells][::-1]                     # row 0 = nearest Z: bottom
        fx0, fx1, fz0, fz1 = fm.extent()
        a, b = px(fx0, fz1), px(fx1, fz0)
        w, h = b[0] - a[0], b[1] - a[1]
        if w > 0 and h > 0:
            scaled = cv2.resize(cellimg, (w, h), interpolation=cv2.INTER_NEAREST)
            ax0, ay0 = max(a[0], 0), max(a[1], top)
            ax1, ay1 = min(b[0], W), min(b[1], top + H)
            if ax1 > ax0 and ay1 > ay0:
                img[ay0:ay1, ax0:ax1] = scaled[ay0 - a[1]:ay1 - a[1], ax0 - a[0]:ax1 - a[0]]
    bx0, bx1, bz0, bz1 = bounds
    cv2.rectangle(img, px(bx0, bz1), px(bx1, bz0), COL_TRUTH, 2)
    for ox0, ox1, oz0, oz1 in np.asarray(obstacles, float).reshape(-1, 4):
        cv2.rectangle(img, px(ox0, oz1), px(ox1, oz0), COL_TRUTH, 1)
    if len(path) > 1:
        cv2.polylines(img, [np.array([px(x, z) for x, z in path], np.int32)], False, COL_PATH, 2,
                      cv2.LINE_AA)
    for track, colour in ((est_track, COL_EST), (true_track, COL_TRUE)):
        if len(track) > 1:
            cv2.polylines(img, [np.array([px(s.x, s.z) for s in track], np.int32)], False, colour,
                          2, cv2.LINE_AA)
        if len(track):
            cv2.circle(img, px(track[-1].x, track[-1].z), 4, colour, -1, cv2.LINE_AA)
    if goal is not None:
        g = px(*goal)
        cv2.drawMarker(img, g, COL_GOAL, cv2.MARKER_CROSS, 14, 2)
    if heading is not None and len(true_track):
        s = true_track[-1]
        h = np.radians(s.heading_deg)
        tip = px(s.x + 1.2 * np.sin(h), s.z + 1.2 * np.cos(h))
        cv2.arrowedLine(img, px(s.x, s.z), tip, COL_TRUE, 2, cv2.LINE_AA, tipLength=0.3)
    img[:top] = 255
    _text(img, title, (4, 16))
    items = (("occupied", COL_OCC), ("free", (200, 200, 200)), ("unknown", COL_UNKNOWN),
             ("uncertain", COL_UNCERTAIN), ("truth", COL_TRUTH), ("path", COL_PATH),
             ("true", COL_TRUE), ("estimate", COL_EST))
    rows, row, width = [], [], 4
    for label, colour in items:
        w = 13 + 7 * len(label) + 8
        if row and width + w > W:
            rows.append(row)
            row, width = [], 4
        row.append((label, colour, width))
        width += w
    rows.append(row)
    legend = np.full((16 * len(rows) + 4, W, 3), 255, np.uint8)
    for r, row in enumerate(rows):
        y = 13 + 16 * r
        for label, colour, x in row:
            cv2.rectangle(legend, (x, y - 9), (x + 10, y + 1), colour, -1)
            _text(legend, label, (x + 13, y), 0.38)
    img = np.vstack([img[:H + top], legend])
    return img
