"""Dead reckoning: what the vehicle's wheels report, integrated (the prior for every pose).

The vehicle moves as the Stanford Cart did: each step turns in place, then drives straight.  A
step from pose i to pose i+1 is therefore one turn (the heading change, wrapped to [-180, 180))
and one drive (the floor distance), made in that order.  The odometer reports both with
independent Gaussian errors:

* distance: ``d' = d * (1 + e_d)``, ``e_d ~ N(0, distance_fraction)`` (default 2 % of the
  distance, so a 0.75 ft step is off by 0.015 ft rms and a turn in place by nothing);
* turn: ``a' = a + e_a``, ``e_a ~ N(0, turn_deg)`` degrees (default 1 degree) for EVERY step,
  including a step whose commanded turn is 0: each step is one turn command, and a real
  vehicle's heading also wanders when it drives straight.

Dead reckoning starts at the true first pose (the robot knows where it starts) and integrates
the reported motions: heading += a', then position += d' along the new heading (plus the step's
drive direction relative to the heading, 0 for a vehicle that drives forward; a walk whose poses
do not move that way -- sideways steps -- keeps its true drive direction relative to the heading).
Odometry cannot sense pitch, roll or height, so dead-reckoned poses keep the start's.  The errors
come from one ``numpy.random.default_rng(seed)`` stream, distance then turn for each step in
order, so the same seed gives the same poses.
"""

from __future__ import annotations

import math

import numpy as np

from world.pose import Pose, wrap_deg

DEFAULT_ODOMETRY_SEED = 1985


class OdometryNoise:
    """The noise model above; ``measure`` draws one step's report."""

    def __init__(self, distance_fraction: float = 0.02, turn_deg: float = 1.0,
                 seed: int = DEFAULT_ODOMETRY_SEED):
        if not (distance_fraction >= 0 and turn_deg >= 0):
            raise ValueError(f"odometry noise must be non-negative, got distance_fraction="
                             f"{distance_fraction!r}, turn_deg={turn_deg!r}")
        self.distance_fraction = float(distance_fraction)
        self.turn_deg = float(turn_deg)
        self.seed = seed
        self._rng = np.random.default_rng(seed)

    def measure(self, distance_ft: float, turn_deg: float) -> tuple[float, float]:
        """(reported distance ft, reported turn deg) for one true step."""
        e_d = self._rng.normal(0.0, 1.0) * self.distance_fraction
        e_a = self._rng.normal(0.0, 1.0) * self.turn_deg
        return float(distance_ft) * (1.0 + e_d), float(turn_deg) + e_a

    def __repr__(self):
        return (f"OdometryNoise(distance_fraction={self.distance_fraction}, "
                f"turn_deg={self.turn_deg}, seed={self.seed})")


def step_motion(a: Pose, b: Pose) -> tuple[float, float, float]:
    """(turn deg, distance ft, drive direction relative to b's heading, deg) of the step a -> b."""
    turn = wrap_deg(b.heading_deg - a.heading_deg)
    dist = math.hypot(b.x - a.x, b.z - a.z)
    drive = 0.0 if dist < 1e-12 else \
        wrap_deg(math.degrees(math.atan2(b.x - a.x, b.z - a.z)) - b.heading_deg)
    if abs(drive) < 1e-6:
        drive = 0.0
    return turn, dist, drive


def odometry(true_poses, noise: OdometryNoise | None = None) -> list[tuple[float, float]]:
    """The reported (distance ft, turn deg) of every step of a walk (len(poses) - 1 of them)."""
    noise = OdometryNoise() if noise is None else noise
    out = []
    for a, b in zip(true_poses, true_poses[1:]):
        turn, dist, _ = step_motion(a, b)
        out.append(noise.measure(dist, turn))
    return out


def dead_reckon(true_poses, noise: OdometryNoise | None = None) -> list[Pose]:
    """The poses the vehicle believes it reached, one per true pose (the first is exact)."""
    poses = list(true_poses)
    if not poses:
        return []
    noise = OdometryNoise() if noise is None else noise
    p0 = poses[0]
    x, z, h = p0.x, p0.z, p0.heading_deg
    out = [p0]
    for a, b in zip(poses, poses[1:]):
        turn, dist, drive = step_motion(a, b)
        d_rep, t_rep = noise.measure(dist, turn)
        h = h + t_rep
        ang = math.radians(h + drive)
        x, z = x + d_rep * math.sin(ang), z + d_rep * math.cos(ang)
        out.append(Pose(x, z, wrap_deg(h), p0.pitch_deg, p0.roll_deg, p0.y))
    return out
