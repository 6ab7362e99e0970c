"""The vehicle's true footprint against the true room.

The footprint is a rectangle ``(width, length)`` centred on the rig's
midpoint, its length along the heading (heading_deg turns +Z toward +X).
Obstacles are floor footprints ``(x0, x1, z0, z1)``; ``bounds`` are the walls
``(x0, x1, z0, z1)`` with the free floor inside.  Overlap is tested exactly
(separating axes of two rectangles); touching counts as no hit.
"""

from __future__ import annotations

import math

import numpy as np


def footprint_corners(x: float, z: float, heading_deg: float, footprint) -> np.ndarray:
    """The four corners (4, 2) in room (x, z)."""
    w, l = footprint
    h = math.radians(heading_deg)
    fwd = np.array([math.sin(h), math.cos(h)])
    right = np.array([math.cos(h), -math.sin(h)])
    c = np.array([x, z])
    return np.array([c + sx * w / 2 * right + sl * l / 2 * fwd
                     for sx, sl in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


def _overlaps(corners: np.ndarray, box, tol: float) -> bool:
    x0, x1, z0, z1 = box
    if corners[:, 0].max() <= x0 + tol or corners[:, 0].min() >= x1 - tol:
        return False
    if corners[:, 1].max() <= z0 + tol or corners[:, 1].min() >= z1 - tol:
        return False
    box_c = np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]])
    for k in (0, 1):
        e = corners[k + 1] - corners[k]
        axis = np.array([-e[1], e[0]])
        a = corners @ axis
        b = box_c @ axis
        if a.max() <= b.min() + tol or b.max() <= a.min() + tol:
            return False
    return True


def footprint_hits(obstacles, bounds, x: float, z: float, heading_deg: float, footprint,
                   tol: float = 1e-9) -> bool:
    """True when the footprint overlaps an obstacle or reaches past a wall."""
    corners = footprint_corners(x, z, heading_deg, footprint)
    bx0, bx1, bz0, bz1 = bounds
    if (corners[:, 0].min() < bx0 - tol or corners[:, 0].max() > bx1 + tol
            or corners[:, 1].min() < bz0 - tol or corners[:, 1].max() > bz1 + tol):
        return True
    return any(_overlaps(corners, ob, tol) for ob in np.asarray(obstacles, float).reshape(-1, 4))
