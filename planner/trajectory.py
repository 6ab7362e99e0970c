"""Chapter IV's path optimisation and the motion-command string.

"Path optimization can then be used to round corners and skim near walls for a
reduced-energy trajectory.  In such path optimizing, the system must use
models of physically possible vehicle movements" — vehicle turning radius,
sharp-turn footprints, movement directions relative to its shape and
surface-following constraints.  The vehicle model here (:mod:`vehicle.profile`):

* **footprint / sharp turns** — the planner's passable map is grown by the
  circle the footprint sweeps when it pivots, so a pivot is safe anywhere on
  the path;
* **skim walls** — :func:`shorten` pulls the path taut: each waypoint is joined
  to the farthest later one in line of sight through passable cells, so the
  path runs along the grown walls;
* **round corners** — :func:`round_corners`, when the turning radius is above
  0, replaces each corner by an arc of that radius tangent to both legs (the
  arc checked in passable space); a corner whose legs are too short for the
  arc, or whose arc is blocked, is refused with :class:`~planner.search.NoPath`;
* **movement directions** — forward only (turn first, then drive);
* **floor following** — the vehicle stays on the floor plane; the floor map's
  height band is the volume it passes through.

:func:`to_commands` turns the path into FORWARD / TURN / ARC commands from the
vehicle's heading; :func:`next_segment` cuts the first ``step`` feet of it for
one cycle of the closed loop.
"""

from __future__ import annotations

import math

import numpy as np

from vehicle.commands import Arc, Forward, Turn
from .search import NoPath, Passable, line_of_sight, min_clearance

EPS_FT = 1e-6


def heading_to(a, b) -> float:
    """Heading (deg, +Z toward +X) of the direction a -> b."""
    return math.degrees(math.atan2(b[0] - a[0], b[1] - a[1]))


def wrap(deg: float) -> float:
    return (deg + 180.0) % 360.0 - 180.0


def shorten(p: Passable, pts) -> list[tuple[float, float]]:
    """Pull the polyline taut through passable cells (skim the walls)."""
    pts = [tuple(map(float, q)) for q in pts]
    if len(pts) <= 2:
        return pts
    out = [pts[0]]
    i = 0
    while i < len(pts) - 1:
        j = len(pts) - 1
        while j > i + 1 and not line_of_sight(p, pts[i], pts[j]):
            j -= 1
        out.append(pts[j])
        i = j
    return out


def round_corners(p: Passable, pts, radius: float, heading_deg: float | None = None):
    """Commands that follow ``pts`` with corners rounded by arcs of ``radius``.
    Returns the command list (the first leg starts with a pivot to its heading
    when ``heading_deg`` is given; a vehicle that cannot pivot should be
    started facing its first leg)."""
    pts = [tuple(map(float, q)) for q in pts]
    cmds = []
    heading = heading_deg
    lead = 0.0                      # length of the current leg already used by the last arc
    for k in range(len(pts) - 1):
        a, b = pts[k], pts[k + 1]
        leg = math.hypot(b[0] - a[0], b[1] - a[1])
        if leg < EPS_FT:
            continue
        h = heading_to(a, b)
        if heading is None:
            heading = h
        turn = wrap(h - heading)
        if k == 0 and abs(turn) > 1e-9:
            cmds.append(Turn(turn))
        heading = h
        if k + 2 < len(pts):
            c = pts[k + 2]
            turn2 = wrap(heading_to(b, c) - h)
            cut = radius * math.tan(math.radians(abs(turn2)) / 2)
            nxt = math.hypot(c[0] - b[0], c[1] - b[1])
            if cut > leg - lead + EPS_FT or cut > nxt + EPS_FT:
                raise NoPath(f"the corner at ({b[0]:.2f}, {b[1]:.2f}) ft turns {abs(turn2):.0f} "
                             f"deg: its legs are too short for the turning radius "
                             f"{radius:.2f} ft")
            straight = leg - lead - cut
            if straight > EPS_FT:
                cmds.append(Forward(straight))
            if abs(turn2) > 1e-9:
                arc = Arc(radius, turn2)
                _check_arc(p, b, h, cut, arc)
                cmds.append(arc)
            heading = wrap(h + turn2)
            lead = cut
        else:
            straight = leg - lead
            if straight > EPS_FT:
                cmds.append(Forward(straight))
    return cmds


def _check_arc(p: Passable, corner, h_in: float, cut: float, arc: Arc) -> None:
    from vehicle.sim import State, advance
    hr = math.radians(h_in)
    s = State(corner[0] - cut * math.sin(hr), corner[1] - cut * math.cos(hr), h_in)
    pts = []
    n = max(2, int(abs(arc.angle_deg) / 5) + 1)
    for _ in range(n):
        pts.append((s.x, s.z))
        s = advance(s, Arc(arc.radius_ft, arc.angle_deg / n))
    pts.append((s.x, s.z))
    cl, (x, z) = min_clearance(p, pts)
    if cl < p.radius - 1e-9:
        raise NoPath(f"the rounded corner near ({x:.2f}, {z:.2f}) ft leaves {cl:.2f} ft "
                     f"clearance; the vehicle needs {p.radius:.2f} ft")


def to_commands(pts, heading_deg: float, turning_radius: float = 0.0,
                p: Passable | None = None):
    """Motion commands that drive the polyline from the vehicle's heading:
    pivot turns and straight legs, or (turning radius above 0) rounded corners."""
    if turning_radius > 0:
        if p is None:
            raise ValueError("rounding corners needs the passable map to check the arcs")
        return round_corners(p, pts, turning_radius, heading_deg)
    cmds = []
    heading = heading_deg
    for a, b in zip(pts[:-1], pts[1:]):
        leg = math.hypot(b[0] - a[0], b[1] - a[1])
        if leg < EPS_FT:
            continue
        h = heading_to(a, b)
        t = wrap(h - heading)
        if abs(t) > 1e-9:
            cmds.append(Turn(t))
        cmds.append(Forward(leg))
        heading = h
    return cmds


def next_segment(cmds, step_ft: float):
    """The commands of one cycle: everything up to ``step_ft`` of travel (the
    last FORWARD cut there); pivots before the first leg always belong to it."""
    out = []
    left = step_ft
    for c in cmds:
        if isinstance(c, Turn):
            if left < EPS_FT:
                break
            out.append(c)
        elif isinstance(c, Forward):
            if left < EPS_FT:
                break
            d = min(c.distance_ft, left)
            out.append(Forward(d))
            left -= d
            if d < c.distance_ft:
                break
        elif isinstance(c, Arc):
            length = c.radius_ft * math.radians(abs(c.angle_deg))
            if left < EPS_FT:
                break
            if length <= left + EPS_FT:
                out.append(c)
                left -= length
            else:
                frac = left / length
                out.append(Arc(c.radius_ft, c.angle_deg * frac))
                break
    return out


def commands_length(cmds) -> float:
    total = 0.0
    for c in cmds:
        if isinstance(c, Forward):
            total += c.distance_ft
        elif isinstance(c, Arc):
            total += c.radius_ft * math.radians(abs(c.angle_deg))
    return total


def polyline(cmds, x: float, z: float, heading_deg: float):
    """Where the commands take the vehicle: (x, z) after each one."""
    from vehicle.sim import State, advance
    s = State(x, z, heading_deg)
    out = [(x, z)]
    for c in cmds:
        s = advance(s, c)
        out.append((s.x, s.z))
    return out


def as_array(pts) -> np.ndarray:
    return np.asarray(pts, float).reshape(-1, 2)
