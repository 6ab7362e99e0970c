"""A vehicle footprint against a room's obstacles and walls (for planners and the simulated
vehicle).

A footprint is a rectangle on the floor, carried by the rig: ``(width_ft, length_ft)`` centred
on the rig centre, or ``(width_ft, length_ft, ahead_ft)`` whose centre is ``ahead_ft`` in front
of the rig centre along the heading.  Obstacles are the room's axis-aligned floor footprints;
the footprint hits one if the two rectangles overlap (separating-axis test; touching counts as
a hit), and hits the walls if any corner leaves ``room.bounds``.
"""

from __future__ import annotations

import math

import numpy as np

from world.room import Room


def footprint_corners(x: float, z: float, heading_deg: float, footprint) -> np.ndarray:
    """The footprint's 4 corners (x, z) on the floor, (4, 2)."""
    if len(footprint) not in (2, 3):
        raise ValueError(f"footprint must be (width, length) or (width, length, ahead), "
                         f"got {footprint!r}")
    w, length = float(footprint[0]), float(footprint[1])
    ahead = float(footprint[2]) if len(footprint) == 3 else 0.0
    if not (w > 0 and length > 0):
        raise ValueError(f"footprint width and length must be positive, got {footprint!r}")
    h = math.radians(heading_deg)
    fwd = np.array([math.sin(h), math.cos(h)])      # (x, z) of the heading
    right = np.array([math.cos(h), -math.sin(h)])
    c = np.array([x, z]) + ahead * fwd
    return np.array([c + sr * w / 2 * right + sf * length / 2 * fwd
                     for sr, sf in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


TOUCH_TOL_FT = 1e-9     # "touching" within floating-point noise


def _separated(a: np.ndarray, b: np.ndarray, touching_hits: bool) -> bool:
    if touching_hits:
        return a.max() < b.min() or b.max() < a.min()
    return a.max() <= b.min() + TOUCH_TOL_FT or b.max() <= a.min() + TOUCH_TOL_FT


def _overlaps(corners: np.ndarray, box, touching_hits: bool) -> bool:
    x0, x1, z0, z1 = box
    rect = np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]])
    axes = [np.array([1.0, 0.0]), np.array([0.0, 1.0]),
            corners[1] - corners[0], corners[3] - corners[0]]
    return not any(_separated(corners @ ax, rect @ ax, touching_hits) for ax in axes)


def footprint_hits_boxes(obstacles, bounds, x: float, z: float, heading_deg: float, footprint,
                         touching_hits: bool = True) -> bool:
    """True if the footprint at this pose overlaps one of the floor ``obstacles``
    (x0, x1, z0, z1) or crosses the walls ``bounds`` (x0, x1, z0, z1).  With
    ``touching_hits=False`` a footprint that only touches a box or a wall is
    clear (the simulated vehicle's true collisions: skimming a wall is no crash)."""
    corners = footprint_corners(x, z, heading_deg, footprint)
    x0, x1, z0, z1 = bounds
    cx, cz = corners[:, 0], corners[:, 1]
    if touching_hits:
        outside = (cx <= x0).any() or (cx >= x1).any() or (cz <= z0).any() or (cz >= z1).any()
    else:
        t = TOUCH_TOL_FT
        outside = (cx.min() < x0 - t or cx.max() > x1 + t or cz.min() < z0 - t
                   or cz.max() > z1 + t)
    if outside:
        return True
    return any(_overlaps(corners, box, touching_hits)
               for box in np.asarray(obstacles, float).reshape(-1, 4))


def footprint_hits(room: Room, x: float, z: float, heading_deg: float, footprint) -> bool:
    """True if the footprint at this pose overlaps an obstacle or crosses a wall
    (touching counts as a hit)."""
    return footprint_hits_boxes(room.obstacles, room.bounds, x, z, heading_deg, footprint)
