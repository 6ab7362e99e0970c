"""A simulated vehicle executing motion commands in the true room.

State: the **true** pose (where the next look is rendered) and the
**dead-reckoned** pose (what the wheels report, integrated: the prior for the
camera estimate), both ``(x, z, heading_deg)`` in room coordinates.  Each
command moves the true pose exactly as commanded; the odometry reports the
motion through ``noise.measure(distance_ft, turn_deg)`` (the world's
``OdometryNoise``: a fraction of each distance and some degrees of each turn),
and the dead-reckoned pose integrates what it reports (one report per command).  ``noise=None`` is
noise off: both poses follow the commands exactly.

Every motion is swept in small steps (``sweep_ft``, ``sweep_deg``) and the true
footprint is checked against the true room at each; at the first hit the
vehicle stops there (its bumper), the collision is counted and the rest of the
string is dropped.

``PAN`` and ``TILT`` (a profile with a head, ``VehicleProfile.head``) set the
head's angles (:attr:`Vehicle.pan_deg`, :attr:`Vehicle.tilt_deg`, relative to
the body) without moving the body, so there is nothing to sweep or collide,
and WITHOUT odometry noise: the head's encoders are assumed exact, and the
dead reckoning of the body is untouched (no report, no track point).  An angle
outside the profile's limits, or a head command for a profile without a head,
is a ``ValueError`` naming the command, raised before anything of the string
is executed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from world.collide import footprint_hits_boxes
from .commands import Arc, Back, Forward, Pan, Stop, Tilt, Turn, format_commands, parse
from .profile import DEFAULT, VehicleProfile


def _wrap(deg: float) -> float:
    return (deg + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class State:
    x: float
    z: float
    heading_deg: float


def advance(s: State, cmd) -> State:
    """The pose after one command, exactly (no noise)."""
    h = math.radians(s.heading_deg)
    if isinstance(cmd, Forward):
        return State(s.x + cmd.distance_ft * math.sin(h), s.z + cmd.distance_ft * math.cos(h),
                     s.heading_deg)
    if isinstance(cmd, Back):
        return State(s.x - cmd.distance_ft * math.sin(h), s.z - cmd.distance_ft * math.cos(h),
                     s.heading_deg)
    if isinstance(cmd, Turn):
        return State(s.x, s.z, _wrap(s.heading_deg + cmd.angle_deg))
    if isinstance(cmd, Arc):
        # centre of the circle to the right (positive angle) or left of the vehicle
        sgn = 1.0 if cmd.angle_deg >= 0 else -1.0
        r = cmd.radius_ft
        cx = s.x + sgn * r * math.cos(h)
        cz = s.z - sgn * r * math.sin(h)
        h2 = h + math.radians(cmd.angle_deg)
        return State(cx - sgn * r * math.cos(h2), cz + sgn * r * math.sin(h2),
                     _wrap(s.heading_deg + cmd.angle_deg))
    if isinstance(cmd, (Stop, Pan, Tilt)):
        return s                          # the head turns on the body: the body stays
    raise TypeError(f"not a motion command: {cmd!r}")


def camera_pose(s: State, pan_deg: float, tilt_deg: float, profile: VehicleProfile = DEFAULT):
    """The rig's pose (a ``world.pose.Pose``) on a body at ``s`` whose head is
    panned ``pan_deg`` (right of the body) and tilted ``tilt_deg`` (on top of
    the profile's ``camera_pitch_deg``): the head turns about the vertical
    through the rig's midpoint, so a pan is the body turned by as much.  With
    the head straight ahead (0, 0) the pose is exactly the fixed rig's."""
    from world.pose import Pose
    heading = s.heading_deg if pan_deg == 0 else _wrap(s.heading_deg + pan_deg)
    return Pose(s.x, s.z, heading, profile.camera_pitch_deg + tilt_deg)


def _pieces(cmd, sweep_ft: float, sweep_deg: float):
    """``cmd`` cut into small commands of the same kind."""
    if isinstance(cmd, Forward):
        n = max(1, math.ceil(cmd.distance_ft / sweep_ft))
        return [Forward(cmd.distance_ft / n)] * n
    if isinstance(cmd, Back):
        n = max(1, math.ceil(cmd.distance_ft / sweep_ft))
        return [Back(cmd.distance_ft / n)] * n
    if isinstance(cmd, Turn):
        n = max(1, math.ceil(abs(cmd.angle_deg) / sweep_deg))
        return [Turn(cmd.angle_deg / n)] * n
    if isinstance(cmd, Arc):
        length = cmd.radius_ft * math.radians(abs(cmd.angle_deg))
        n = max(1, math.ceil(max(length / sweep_ft, abs(cmd.angle_deg) / sweep_deg)))
        return [Arc(cmd.radius_ft, cmd.angle_deg / n)] * n
    return []


@dataclass
class Vehicle:
    obstacles: object                    # (K, 4) true floor footprints
    bounds: tuple                        # true walls (x0, x1, z0, z1)
    true: State
    profile: VehicleProfile = DEFAULT
    noise: object = None                 # .measure(distance_ft, turn_deg) -> (d, t), or None
    dead: State | None = None
    sweep_ft: float = 0.05
    sweep_deg: float = 2.0
    collisions: int = 0
    travelled_ft: float = 0.0
    pan_deg: float = 0.0                 # the head's pan relative to the body (exact)
    tilt_deg: float = 0.0                # its tilt on top of the profile's camera_pitch_deg
    true_track: list = field(default_factory=list)
    dead_track: list = field(default_factory=list)

    def __post_init__(self):
        if self.dead is None:
            self.dead = self.true
        self.true_track.append(self.true)
        self.dead_track.append(self.dead)

    def hits(self, s: State) -> bool:
        return footprint_hits_boxes(self.obstacles, self.bounds, s.x, s.z, s.heading_deg,
                                    self.profile.footprint, touching_hits=False)

    def execute(self, commands) -> bool:
        """Run a command string or list; False when a collision stopped it."""
        cmds = parse(commands) if isinstance(commands, str) else list(commands)
        if not self.profile.reverse and any(isinstance(c, Back) for c in cmds):
            raise ValueError("BACK: this vehicle's profile does not allow reverse "
                             "(VehicleProfile.reverse is False)")
        for cmd in cmds:
            if isinstance(cmd, (Pan, Tilt)):
                self._check_head(cmd)
        for cmd in cmds:
            if isinstance(cmd, Stop):
                break
            if isinstance(cmd, Pan):
                self.pan_deg = float(cmd.angle_deg)
                continue
            if isinstance(cmd, Tilt):
                self.tilt_deg = float(cmd.angle_deg)
                continue
            if not self._one(cmd):
                return False
        return True

    def _check_head(self, cmd) -> None:
        what = format_commands([cmd])
        if not self.profile.head:
            raise ValueError(f"{what}: this vehicle's profile has no head "
                             f"(VehicleProfile.head is False)")
        name = "pan_limits_deg" if isinstance(cmd, Pan) else "tilt_limits_deg"
        lo, hi = getattr(self.profile, name)
        if not lo <= cmd.angle_deg <= hi:
            raise ValueError(f"{what}: outside the head's limits {lo:g}..{hi:g} deg "
                             f"(VehicleProfile.{name})")

    def _one(self, cmd) -> bool:
        """Sweep one command; the odometry reports it once (as the wheels would
        for one commanded motion), also when a collision cut it short."""
        start = self.true
        dist = 0.0
        ok = True
        for piece in _pieces(cmd, self.sweep_ft, self.sweep_deg):
            nxt = advance(self.true, piece)
            if self.hits(nxt):
                self.collisions += 1
                ok = False
                break
            dist += math.hypot(nxt.x - self.true.x, nxt.z - self.true.z)
            self.true = nxt
        turn = _wrap(self.true.heading_deg - start.heading_deg)
        if isinstance(cmd, Arc):
            done = abs(turn) / max(abs(cmd.angle_deg), 1e-12)
            dist = cmd.radius_ft * math.radians(abs(cmd.angle_deg)) * done
        self.travelled_ft += dist
        if dist > 0 or abs(turn) > 0:
            md, mt = self.noise.measure(dist, turn) if self.noise is not None else (dist, turn)
            # dead reckoning of one motion: move along the mean heading
            h = math.radians(self.dead.heading_deg + mt / 2)
            chord = md if abs(mt) < 1e-9 or not isinstance(cmd, Arc) else \
                2 * (md / math.radians(abs(mt))) * math.sin(math.radians(abs(mt)) / 2)
            if isinstance(cmd, Back):
                chord = -chord            # the wheels turn backward: the same heading
            self.dead = State(self.dead.x + chord * math.sin(h), self.dead.z + chord * math.cos(h),
                              _wrap(self.dead.heading_deg + mt))
        self.true_track.append(self.true)
        self.dead_track.append(self.dead)
        return ok


def odometry_covariance(cov, a: State, b: State, distance_fraction: float = 0.02,
                        turn_deg: float = 1.0):
    """The dead-reckoned pose's (x, z, heading in radians) covariance after one
    reported command from ``a`` to ``b`` (both dead-reckoned), propagated by
    the odometry's noise model (the world's ``OdometryNoise``: a standard
    deviation of ``distance_fraction`` of the distance and ``turn_deg`` per
    command), linearised about the move along the mean heading as
    :meth:`Vehicle._one` integrates it.  A step without motion reports
    nothing and adds nothing."""
    import numpy as np
    cov = np.asarray(cov, float)
    dx, dz = b.x - a.x, b.z - a.z
    d = math.hypot(dx, dz)
    t = math.radians(_wrap(b.heading_deg - a.heading_deg))
    if d < 1e-12 and abs(t) < 1e-12:
        return cov
    # the mean heading the move went along (sign: a backward move has d < 0)
    h = math.atan2(dx, dz) if d > 1e-12 else math.radians(a.heading_deg) + t / 2
    if d > 1e-12 and math.cos(h - math.radians(a.heading_deg) - t / 2) < 0:
        h, d = h + math.pi, -d
    F = np.array([[1.0, 0.0, d * math.cos(h)], [0.0, 1.0, -d * math.sin(h)], [0.0, 0.0, 1.0]])
    G = np.array([[math.sin(h), d * math.cos(h) / 2], [math.cos(h), -d * math.sin(h) / 2],
                  [0.0, 1.0]])
    Q = np.diag([(distance_fraction * d) ** 2, math.radians(turn_deg) ** 2])
    out = F @ cov @ F.T + G @ Q @ G.T
    return (out + out.T) / 2
