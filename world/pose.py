"""The rig's pose in the room (equation A-21's camera position and orientation).

Room coordinates are the bundled lab's frame (``rig/scene.py``): X to the right, Y DOWN, Z
forward as seen from the bundled pose, in feet; the floor is the plane Y = +3.  A pose places the
rig centre (midway between the two cameras) and turns the rig's axes (x right, y down, z forward
along both optical axes):

* ``heading_deg`` turns the forward axis from +Z toward +X (a right turn is positive);
* ``pitch_deg`` positive lifts the nose (the forward axis tilts toward -Y, up);
* ``roll_deg`` positive tilts the rig's x axis toward +Y (the right camera goes down).

The rotation is heading about the room's vertical, then pitch about the rig's new x axis, then
roll about its newest z axis: ``R = R_heading @ R_pitch @ R_roll``.  Its COLUMNS are the rig's
x, y, z axes in room coordinates, so a room point p has camera coordinates
``R.T @ (p - camera_centre)`` (the direction cosines of A-21, row by row).  Pose(0, 0, 0) is the
identity exactly (cos 0 = 1, sin 0 = 0), which is why it reproduces the bundled pair bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

BASELINE_FT = 0.75          # the rig's camera separation ds (rig/scene.py)
SIDES = ("left", "right")


def _rot_heading(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_pitch(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_roll(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wrap_deg(deg: float) -> float:
    """An angle in degrees brought into [-180, 180)."""
    return (float(deg) + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class Pose:
    """The rig centre at room point (x, y, z) and its orientation (degrees)."""
    x: float
    z: float
    heading_deg: float
    pitch_deg: float = 0.0
    roll_deg: float = 0.0
    y: float = 0.0

    def __post_init__(self):
        for name in ("x", "z", "heading_deg", "pitch_deg", "roll_deg", "y"):
            v = getattr(self, name)
            if not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
                raise ValueError(f"Pose.{name} must be a finite number, got {v!r}")
            object.__setattr__(self, name, float(v))

    @property
    def position(self) -> np.ndarray:
        """The rig centre (x, y, z), room coordinates, ft."""
        return np.array([self.x, self.y, self.z])

    def rotation(self) -> np.ndarray:
        """3x3 float64; columns = the rig's x (right), y (down), z (forward) axes in room
        coordinates."""
        return _rot_heading(self.heading_deg) @ _rot_pitch(self.pitch_deg) @ _rot_roll(self.roll_deg)

    def camera_centre(self, side: str) -> np.ndarray:
        """Centre of the "left" (-0.375 ft along the rig's x axis) or "right" (+0.375) camera."""
        if side not in SIDES:
            raise ValueError(f"side must be 'left' or 'right', got {side!r}")
        offset = -BASELINE_FT / 2 if side == "left" else BASELINE_FT / 2
        return self.position + self.rotation() @ np.array([offset, 0.0, 0.0])

    def to_camera(self, points, side: str = "left") -> np.ndarray:
        """Room points (..., 3) in the camera coordinates of ``side``: R.T @ (p - centre)."""
        p = np.asarray(points, dtype=np.float64)
        return (p - self.camera_centre(side)) @ self.rotation()

    def to_room(self, points, side: str = "left") -> np.ndarray:
        """Camera coordinates of ``side`` (..., 3) back in room coordinates."""
        p = np.asarray(points, dtype=np.float64)
        return p @ self.rotation().T + self.camera_centre(side)

    def floor_distance(self, other: "Pose") -> float:
        """Distance on the floor (x, z) to another pose, ft."""
        return math.hypot(other.x - self.x, other.z - self.z)

    def as_dict(self) -> dict:
        return {"x": self.x, "z": self.z, "heading_deg": self.heading_deg,
                "pitch_deg": self.pitch_deg, "roll_deg": self.roll_deg, "y": self.y}
