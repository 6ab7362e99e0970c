"""The closed loop's perception step, until the symbolic model takes it over:
one stereo scan of a look turned into room points for the volumetric model.

The rig's LCSL gives each located edge in the left camera's axes (x right,
y down, z forward).  Its dx, dy are measured from pixel 60 (QUIRKS E6, kept in
the rig); here the direction is taken from the match's own picture position
instead — column ``loc1`` (1-based) and line ``IY`` at their pixel centres
against the principal point (64, 60) of the 128x120 picture, focal 180 px —
and scaled by LCSL's range dp.  A pose (the prior / dead-reckoned estimate)
carries the points into room coordinates: ``p_room = R @ p_cam + c_left``.

:func:`filter_points` keeps what the dissertation trusts: ranges up to 15 ft
("for ranges of 15 feet or less" the estimates were "fairly accurate", Ch. V)
and error bounds within a fraction of the range, from 2.5 ft on.  :func:`surface_spans` joins
consecutive edges of one scan line at the same range within their error
bounds: the surface between two boundary lines (Chapter IV: occupied where
"the surfaces between their boundary lines are").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FOCAL_128 = 180.0
CX_128, CY_128 = 64.0, 60.0
MAX_RANGE_FT = 12.0
MIN_RANGE_FT = 2.5


@dataclass
class RoomPoints:
    xyz: np.ndarray          # (N, 3) room coordinates
    cov: np.ndarray          # (N, 3, 3) room-frame covariance (A-20 rotated)
    line: np.ndarray         # (N,) scan line
    loc1: np.ndarray         # (N,) left column (1-based)
    origin: np.ndarray       # (3,) left camera centre in the room


def camera_points(points) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(xyz_cam (N,3), cov_cam (N,3,3), line, loc1, ep) from rig.scan Points."""
    n = len(points)
    line = np.array([p.line for p in points], int).reshape(n)
    loc1 = np.array([p.loc1 for p in points], float).reshape(n)
    dp = np.array([p.dp for p in points], float).reshape(n)
    ep = np.array([p.ep for p in points], float).reshape(n)
    ex = np.array([p.ex for p in points], float).reshape(n)
    ey = np.array([p.ey for p in points], float).reshape(n)
    x = (loc1 - 0.5 - CX_128) * dp / FOCAL_128
    y = (line + 0.5 - CY_128) * dp / FOCAL_128
    xyz = np.stack([x, y, dp], -1)
    # the bounds are two standard deviations, (range, x, y) -> (x, y, z)
    cov = np.zeros((n, 3, 3))
    cov[:, 0, 0] = (ex / 2) ** 2
    cov[:, 1, 1] = (ey / 2) ** 2
    cov[:, 2, 2] = (ep / 2) ** 2
    return xyz, cov, line, loc1, ep


def filter_points(xyz_cam, ep, max_range: float = MAX_RANGE_FT, max_rel_error: float = 0.25,
                  min_range: float = MIN_RANGE_FT):
    """Mask of points worth modelling: within range, bounded error.  Nearer than
    ``min_range`` (a disparity above 54 px) the 1985 matcher's locations are
    mostly false matches (a repeated false match at 2.3 ft stands in front of
    the bundled lab's start); the vehicle never needs them, as it only drives into
    space seen free from farther away."""
    z = xyz_cam[:, 2]
    return (z >= min_range) & (z <= max_range) & (ep <= max_rel_error * z)


def to_room(xyz_cam, cov_cam, R, left_centre):
    """Camera points and covariances into room coordinates."""
    R = np.asarray(R, float)
    xyz = xyz_cam @ R.T + np.asarray(left_centre, float)
    cov = R @ cov_cam @ R.T
    return xyz, cov


def surface_spans(xyz_cam, ep, line, loc1, max_gap_ft: float = 3.0):
    """Pairs (a, b) of point indices: neighbours along one scan line (in left
    column order) whose ranges agree within their summed error bounds (and at
    least 5 % of the range) and that are at most ``max_gap_ft`` apart."""
    pairs = []
    for y in np.unique(line):
        idx = np.flatnonzero(line == y)
        idx = idx[np.argsort(loc1[idx], kind="stable")]
        for a, b in zip(idx[:-1], idx[1:]):
            za, zb = xyz_cam[a, 2], xyz_cam[b, 2]
            tol = max(ep[a] + ep[b], 0.05 * min(za, zb))
            if abs(za - zb) <= tol and np.linalg.norm(xyz_cam[a] - xyz_cam[b]) <= max_gap_ft:
                pairs.append((int(a), int(b)))
    return pairs


def look_to_room(points, R, left_centre, max_range: float = MAX_RANGE_FT):
    """rig.scan Points of one look -> (RoomPoints kept, surface span pairs)."""
    xyz_c, cov_c, line, loc1, ep = camera_points(points)
    keep = filter_points(xyz_c, ep, max_range)
    xyz_c, cov_c, line, loc1, ep = xyz_c[keep], cov_c[keep], line[keep], loc1[keep], ep[keep]
    spans = surface_spans(xyz_c, ep, line, loc1)
    xyz, cov = to_room(xyz_c, cov_c, R, left_centre)
    return RoomPoints(xyz, cov, line, loc1, np.asarray(left_centre, float)), spans
