"""The motion-command language (Chapter IV: "the sequence of vehicle motions
necessary for traversing that trajectory is then stored as the motion command
string for the vehicle"), in the spirit of the HERO-1's and the Stanford
Cart's: one command per statement, statements separated by ``;`` or new
lines, verbs case-insensitive, numbers in feet and degrees::

    FORWARD 2.5        move straight ahead 2.5 ft (negative not allowed)
    BACK 1.0           move straight backward 1.0 ft, heading kept (a vehicle whose
                       profile allows reverse: ``VehicleProfile.reverse``)
    TURN -30           pivot in place; positive turns right (heading from +Z toward +X)
    ARC 1.5 45         drive a circular arc of radius 1.5 ft turning 45 deg right
    PAN 40             turn the head to 40 deg right of the body (absolute, not by 40 more;
                       PAN 0 is straight ahead); the body does not move
    TILT -30           tilt the head to 30 deg down from the rig's mounting pitch
                       (absolute; TILT 0 is the mount's own pitch)
    STOP               end of the string; nothing after it is allowed

PAN and TILT are for a vehicle whose profile has a head (``VehicleProfile.head``,
in the spirit of the HERO-1's head, which rotates on its body); the vehicle
checks their angles against the profile's limits when it executes them
(:meth:`vehicle.sim.Vehicle.execute`), the parser only that they lie within
-180..180 deg.  Short forms ``F``, ``B``, ``T``, ``A``, ``P``, ``TI``, ``S``
are accepted.  ``#`` starts a comment.
:func:`parse` raises :class:`CommandError` naming the statement, its number
and what is wrong; :func:`format_commands` writes the canonical string
(``parse(format_commands(c)) == c``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass


class CommandError(ValueError):
    """A malformed motion-command string."""


@dataclass(frozen=True)
class Forward:
    distance_ft: float


@dataclass(frozen=True)
class Back:
    distance_ft: float


@dataclass(frozen=True)
class Turn:
    angle_deg: float


@dataclass(frozen=True)
class Arc:
    radius_ft: float
    angle_deg: float


@dataclass(frozen=True)
class Pan:
    angle_deg: float          # the head's pan relative to the body, positive right


@dataclass(frozen=True)
class Tilt:
    angle_deg: float          # the head's tilt on top of the mounting pitch, negative down


@dataclass(frozen=True)
class Stop:
    pass


Command = Forward | Back | Turn | Arc | Pan | Tilt | Stop

_VERBS = {"FORWARD": "FORWARD", "F": "FORWARD", "BACK": "BACK", "B": "BACK", "TURN": "TURN", "T": "TURN",
          "ARC": "ARC", "A": "ARC", "PAN": "PAN", "P": "PAN", "TILT": "TILT", "TI": "TILT",
          "STOP": "STOP", "S": "STOP"}
_ARITY = {"FORWARD": 1, "BACK": 1, "TURN": 1, "ARC": 2, "PAN": 1, "TILT": 1, "STOP": 0}
_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)$")


def _number(tok: str, where: str) -> float:
    if not _NUMBER.match(tok):
        raise CommandError(f"{where}: {tok!r} is not a number")
    v = float(tok)
    if not math.isfinite(v):
        raise CommandError(f"{where}: {tok!r} is not finite")
    return v


def parse(text: str) -> list[Command]:
    """The commands of a command string (see the module docstring)."""
    if not isinstance(text, str):
        raise CommandError(f"a command string must be text, not {type(text).__name__}")
    out: list[Command] = []
    statements = []
    for line in text.splitlines() or [""]:
        line = line.split("#", 1)[0]
        statements.extend(s.strip() for s in line.split(";"))
    n = 0
    stopped = False
    for st in statements:
        if not st:
            continue
        n += 1
        where = f"command {n} {st!r}"
        if stopped:
            raise CommandError(f"{where}: nothing may follow STOP")
        toks = st.split()
        verb = _VERBS.get(toks[0].upper())
        if verb is None:
            raise CommandError(f"{where}: unknown command {toks[0]!r} "
                               f"(expected FORWARD, BACK, TURN, ARC, PAN, TILT or STOP)")
        args = toks[1:]
        if len(args) != _ARITY[verb]:
            raise CommandError(f"{where}: {verb} takes {_ARITY[verb]} number"
                               f"{'s' if _ARITY[verb] != 1 else ''}, got {len(args)}")
        vals = [_number(a, where) for a in args]
        if verb == "FORWARD":
            if vals[0] < 0:
                raise CommandError(f"{where}: FORWARD distance must not be negative "
                                   f"(the vehicle drives forward only)")
            out.append(Forward(vals[0]))
        elif verb == "BACK":
            if vals[0] < 0:
                raise CommandError(f"{where}: BACK distance must not be negative")
            out.append(Back(vals[0]))
        elif verb == "TURN":
            if abs(vals[0]) > 180:
                raise CommandError(f"{where}: TURN angle must be within -180..180 deg")
            out.append(Turn(vals[0]))
        elif verb == "ARC":
            if vals[0] <= 0:
                raise CommandError(f"{where}: ARC radius must be positive")
            if abs(vals[1]) > 360:
                raise CommandError(f"{where}: ARC angle must be within -360..360 deg")
            out.append(Arc(vals[0], vals[1]))
        elif verb in ("PAN", "TILT"):
            if abs(vals[0]) > 180:
                raise CommandError(f"{where}: {verb} angle must be within -180..180 deg")
            out.append(Pan(vals[0]) if verb == "PAN" else Tilt(vals[0]))
        else:
            out.append(Stop())
            stopped = True
    return out


def _num(v: float) -> str:
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def format_commands(cmds) -> str:
    """The canonical string: ``FORWARD 2.5; TURN -30; STOP``."""
    parts = []
    for c in cmds:
        if isinstance(c, Forward):
            parts.append(f"FORWARD {_num(c.distance_ft)}")
        elif isinstance(c, Back):
            parts.append(f"BACK {_num(c.distance_ft)}")
        elif isinstance(c, Turn):
            parts.append(f"TURN {_num(c.angle_deg)}")
        elif isinstance(c, Arc):
            parts.append(f"ARC {_num(c.radius_ft)} {_num(c.angle_deg)}")
        elif isinstance(c, Pan):
            parts.append(f"PAN {_num(c.angle_deg)}")
        elif isinstance(c, Tilt):
            parts.append(f"TILT {_num(c.angle_deg)}")
        elif isinstance(c, Stop):
            parts.append("STOP")
        else:
            raise TypeError(f"not a motion command: {c!r}")
    return "; ".join(parts)
