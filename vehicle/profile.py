"""The vehicle profile: what the planner and the simulated vehicle assume.

Default (:data:`DEFAULT`): a small base carrying the rig (the HERO-1 is about
1.5 ft across; this one is smaller so that the generated rooms' 1.8 ft gaps
stay passable) — a footprint 0.8 ft wide by 1.0 ft long centred under the
rig's midpoint, the cameras 3 ft
above the floor (room Y = 0, the floor at Y = +3, as in the bundled lab), pivot
turns (turning radius 0: the HERO-1 turns its single drive wheel across and
pivots), the rig pitched 25 deg down (like the Stanford Cart's camera: level,
a camera 3 ft up with the rig's 37 deg tall view sees no floor nearer than
9 ft), at most 1.5 ft of forward travel between looks (the Stanford Cart
moved about 2.5 ft per look), forward only.  ``reverse`` (off by default;
the HERO-1's drive wheel turns either way) allows ``BACK``: the closed loop
may then back straight along its heading over space seen free, to see what is
too near to show in a look or to get room to pivot (``DriveConfig.backing="map"``;
measured, not adopted: docs/planner.md).  The closed loop's default
(``backing="trail"``, since 2026-12-07) lets the vehicle back only to undo its own
last motions where it cannot turn, whatever this flag says.  ``margin_ft`` is added to the
vehicle's radius when planning, against the error of the position estimate.

The head (``head``, off by default: the rig is fixed, pan 0 and tilt 0 on top
of ``camera_pitch_deg``): with ``head=True`` the rig sits on a head that pans
about the vertical through the rig's midpoint (above the footprint's centre)
within ``pan_limits_deg`` (-90..+90 deg, positive to the right as a TURN) and
tilts about the rig's own x axis within ``tilt_limits_deg`` (-55..0 deg,
negative down; added to ``camera_pitch_deg``, so -25 down to -80 deg: at -80
the picture's lower edge looks 8 deg behind the vertical and the floor beside
the footprint shows).  The HERO-1's head turns on its body in the same way; the
limits are this project's choice (a cable-wound head, no slip ring: +-90 deg;
no tilt above the mount, which already sees the far wall).  The head's
encoders are assumed exact: the motion-command language's ``PAN`` and ``TILT``
(:mod:`vehicle.commands`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class VehicleProfile:
    width_ft: float = 0.8            # across (the rig's x axis)
    length_ft: float = 1.0           # along the forward axis
    camera_height_ft: float = 3.0    # above the floor
    camera_pitch_deg: float = -25.0  # the rig looks down (positive: nose up)
    turning_radius_ft: float = 0.0   # 0: pivot turns
    step_ft: float = 1.5             # most forward travel between looks
    margin_ft: float = 0.15          # added to the radius for planning
    reverse: bool = False            # BACK allowed (the HERO-1's drive wheel reverses)
    head: bool = False               # a pan-tilt head under the rig (PAN, TILT allowed)
    pan_limits_deg: tuple[float, float] = (-90.0, 90.0)    # the head's pan, relative to the body
    tilt_limits_deg: tuple[float, float] = (-55.0, 0.0)    # its tilt, on top of camera_pitch_deg

    def __post_init__(self):
        for name in ("width_ft", "length_ft", "camera_height_ft", "step_ft"):
            if not getattr(self, name) > 0:
                raise ValueError(f"vehicle {name} must be positive, got {getattr(self, name)!r}")
        if self.turning_radius_ft < 0 or self.margin_ft < 0:
            raise ValueError("turning radius and margin must not be negative")
        for name in ("pan_limits_deg", "tilt_limits_deg"):
            lo, hi = getattr(self, name)
            if not lo <= 0.0 <= hi:
                raise ValueError(f"vehicle {name} must hold 0 (the head straight ahead), "
                                 f"got {getattr(self, name)!r}")

    @property
    def footprint(self) -> tuple[float, float]:
        return (self.width_ft, self.length_ft)

    @property
    def radius_ft(self) -> float:
        """The circle the footprint sweeps turning in place (half its diagonal)."""
        return math.hypot(self.width_ft, self.length_ft) / 2

    @property
    def grown_half_ft(self) -> tuple[float, float]:
        """Half the footprint's width and half its length, each grown by the margin: the
        band a forward move sweeps either side and the nose ahead of it that must be
        seen free (planner.motion.safe_prefix)."""
        return (self.width_ft / 2 + self.margin_ft, self.length_ft / 2 + self.margin_ft)

    @property
    def planning_radius_ft(self) -> float:
        return self.radius_ft + self.margin_ft


DEFAULT = VehicleProfile()
PAN_TILT = VehicleProfile(head=True)
"""The default vehicle with the pan-tilt head (``rig drive --head pan-tilt``)."""
