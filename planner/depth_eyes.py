"""Depth eyes: a diagnostic oracle for the closed loop (``DriveConfig.eyes="depth"``,
``rig drive --eyes depth``; never the default, not 1985).

The rig's eyes locate edges, and only edges: a blank face gives them nothing,
and most of each look's columns carry no range at all.  To tell how much of the
loop's failure is the planner's own, these eyes see EVERYTHING: a dense range
finder built from the world's true range through every pixel of the left camera
(``world.render.Look.range_left``, Z along the camera's axis through each
128x120 pixel centre).  Per picture column:

* the nearest true point inside the vehicle's height band (``band``: room Y,
  down; the floor and the lowest quarter foot above it are not in it) is a HIT,
  when it is within ``max_range`` — its sight line is free up to it;
* a column with no such point within range gives free space to the farthest
  floor it shows, at most ``max_range`` (the floor is seen without a break up
  to the foot of the first thing standing on it: anything nearer in that
  column would show in the band first).

The points are the camera's own (exact); they are carried into the room by the
pose the loop places the look with (the dead-reckoned or fused ESTIMATE, as
for every eyes), so the odometry's drift is still the loop's.

What differs from :func:`planner.perception.floor_scan` (the path the rig's
eyes take): every column has its own range, so no votes, no columns between
edges and no blank-column assumption (``assumed`` all False); a hit lands at
its point's own horizontal position (floor_scan's ``place="point"``; the
``"axis"`` placement exists for a 1-D range along a pitched axis); a hit's
covariance is :data:`SIGMA_FT` each way (the truth has no error, so a hit
occupies its own cell and no more; a zero covariance cannot be inverted for
growth); neighbouring columns whose hits
agree within 5 % of the range (at least a cell) and lie within 1 ft are
joined by a surface span, as floor_scan joins edges.  The result is a
:class:`~planner.perception.FloorScan`, inserted by
:meth:`planner.evidence.Perception.update` as any other look.
"""

from __future__ import annotations

import numpy as np

from .perception import CX_128, CY_128, FOCAL_128, MAX_RANGE_FT, FloorScan

SIGMA_FT = 0.01              # a hit's standard deviation: growth only into its own cell
SPAN_FT = 1.0                 # neighbouring hits farther apart than this are not one surface


def camera_points(range_left) -> np.ndarray:
    """(120, 128, 3) camera-frame points (x right, y down, z forward) of a
    range-per-pixel picture: pixel (row, col) at its centre against the
    principal point (64, 60), focal 180 px, scaled by its Z."""
    z = np.asarray(range_left, float)
    rows, cols = z.shape
    u = (np.arange(cols) + 0.5 - CX_128) / FOCAL_128
    v = (np.arange(rows) + 0.5 - CY_128) / FOCAL_128
    return np.stack([u[None, :] * z, v[:, None] * z, z], -1)


def depth_floor_scan(range_left, R, left_centre, band, max_range: float = MAX_RANGE_FT,
                     res: float = 0.25) -> FloorScan:
    """The look of a dense true range finder as a floor range scan (see the
    module docstring): one hit or one free end per picture column."""
    R = np.asarray(R, float)
    origin = np.asarray(left_centre, float)
    room = camera_points(range_left) @ R.T + origin            # (rows, cols, 3)
    y = room[..., 1]
    d = np.hypot(room[..., 0] - origin[0], room[..., 2] - origin[2])
    in_band = (y >= band[0]) & (y <= band[1])
    floor = y > band[1]
    d_band = np.where(in_band, d, np.inf)
    near_row = np.argmin(d_band, 0)
    cols = np.arange(d.shape[1])
    nearest = d_band[near_row, cols]
    d_floor = np.where(floor, d, -np.inf)
    far_row = np.argmax(d_floor, 0)
    farthest = d_floor[far_row, cols]

    hit = nearest <= max_range
    hits = room[near_row[hit], cols[hit]].copy()
    hits[:, 1] = origin[1]                                     # moved to the camera's height
    hit_cols = cols[hit] + 1

    # the rest: free to the band's nearest point beyond range, or the farthest floor shown
    rest = ~hit
    reach = np.where(np.isfinite(nearest), max_range, np.minimum(farthest, max_range))
    shows = rest & (reach > 0)
    row = np.where(np.isfinite(nearest), near_row, far_row)[shows]
    toward = room[row, cols[shows]] - origin
    toward[:, 1] = 0.0
    toward /= np.maximum(np.linalg.norm(toward, axis=1), 1e-12)[:, None]
    free_ends = origin + toward * reach[shows][:, None]
    free_ends[:, 1] = origin[1]

    spans = []
    dh = nearest[hit]
    for k in range(len(hits) - 1):
        if hit_cols[k + 1] - hit_cols[k] != 1:
            continue
        tol = max(0.05 * min(dh[k], dh[k + 1]), res)
        if abs(dh[k] - dh[k + 1]) <= tol and np.linalg.norm(hits[k + 1] - hits[k]) <= SPAN_FT:
            spans.append((k, k + 1))
    hit_cov = np.broadcast_to(np.eye(3) * SIGMA_FT ** 2, (len(hits), 3, 3)).copy()
    return FloorScan(origin, hits, hit_cov, free_ends, spans,
                     np.zeros(len(free_ends), bool), hit_cols, cols[shows] + 1)
