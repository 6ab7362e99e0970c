"""Velocity from successive camera positions (Chapter III, "Sequential Images
and Flow Fields": "by combining the time of image acquisition with the
relative motion, the relative velocity can be estimated also").

``v = (c_k - c_{k-1}) / dt`` with covariance ``(C_k + C_{k-1}) / dt^2`` (the
two estimates taken as independent: each comes from its own look's rig
errors), and the turn rate the same way from the headings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Velocity:
    vx: float                 # ft/s, room x
    vz: float                 # ft/s, room z
    turn_deg_s: float         # deg/s
    cov: np.ndarray           # 3x3 over (vx, vz, turn rate in deg/s)

    @property
    def speed(self) -> float:
        return float(np.hypot(self.vx, self.vz))


def velocity(prev_xzh, prev_cov, xzh, cov, dt: float) -> Velocity:
    """Velocity between two (x, z, heading_deg) estimates ``dt`` seconds apart;
    ``prev_cov`` and ``cov`` are 3x3 over (x, z, heading in RADIANS) or None
    (unknown: a zero covariance is used, i.e. the look's pose was given)."""
    if dt <= 0:
        raise ValueError(f"the time between looks must be positive (got {dt} s)")
    a = np.asarray(prev_xzh, dtype=np.float64)
    b = np.asarray(xzh, dtype=np.float64)
    turn = (b[2] - a[2] + 180.0) % 360.0 - 180.0
    scale = np.diag([1.0, 1.0, np.degrees(1.0)])
    C = np.zeros((3, 3))
    for c in (prev_cov, cov):
        if c is not None:
            C = C + scale @ np.asarray(c, dtype=np.float64) @ scale
    return Velocity(float((b[0] - a[0]) / dt), float((b[1] - a[1]) / dt), float(turn / dt),
                    C / dt ** 2)
