"""Walks: sequences of rig poses through a room, one look per pose.

Every walk moves like the Stanford Cart: each step turns in place by at most 15 degrees, then
drives straight ahead about 0.75 ft (a step that must turn further first turns in place, with
no drive).  The bundled walk goes twice round a loop through the bundled lab, from Pose(0, 0, 0)
(the bundled pair) up the left side past the crate, across in front of the carton and the
bookcase, back down the right side past the table and the bin, round behind the start, shipped
as ``world/data/lab-walk.csv`` (written by ``python -m world walk --bundled``).  Twice, because
a feature must be seen many times for its error to fall with the looks: once round, with turns
of 15 degrees a step and a 39 degree field of view, no feature stays in view for more than 8
looks; the second lap sees the first lap's features again.  ``generate_walk`` wanders a room between
random goals along shortest paths on a 0.25 ft grid of the free floor.

Walk files are CSV with the header ``x,z,heading_deg,pitch_deg,roll_deg`` (ft and degrees, room
coordinates; an optional sixth column ``y``).  Values are written with 4 decimals, so reading a
written walk gives the poses that were written.
"""

from __future__ import annotations

import csv
import io
import math
from collections import deque
from pathlib import Path

import numpy as np

from diskfmt.rdos import write_atomic
from world.pose import Pose, wrap_deg
from world.room import Room, bundled_lab

STEP_FT = 0.75
MAX_TURN_DEG = 15.0
CLEARANCE_FT = 1.2         # rig centre to any obstacle or wall (a robot about 2 ft across)
HEADER = ("x", "z", "heading_deg", "pitch_deg", "roll_deg")
BUNDLED_WALK = Path(__file__).resolve().parent / "data" / "lab-walk.csv"

# The bundled loop (x, z), ft: from the start left of the bin and crate, up the left side, across
# in front of the carton and the bookcase (facing the right wall's posters), down the right side
# (facing the front wall's door and poster), round behind the start and turned to face forward.
LAB_LAPS = 2
LAB_WAYPOINTS = ((0.0, 0.0), (-1.6, 1.4), (-2.6, 3.0), (-2.6, 8.0), (-1.1, 10.0), (0.0, 11.4),
                 (2.2, 11.6), (3.5, 10.0), (3.4, 4.6), (1.6, 1.8), (0.6, -0.6), (-0.4, -1.2))


def _round(p: Pose) -> Pose:
    return Pose(round(p.x, 4), round(p.z, 4), round(wrap_deg(p.heading_deg), 4),
                round(p.pitch_deg, 4), round(p.roll_deg, 4), round(p.y, 4))


def _step_towards(x, z, h, tx, tz, step=STEP_FT, max_turn=MAX_TURN_DEG, full=False):
    """One Cart step toward (tx, tz): turn (<= max_turn), then drive if facing within 2 turns
    (a full step if ``full``, else no further than the target)."""
    want = math.degrees(math.atan2(tx - x, tz - z))
    err = wrap_deg(want - h)
    turn = max(-max_turn, min(max_turn, err))
    h = h + turn
    if abs(err) > 2 * max_turn:
        return x, z, h, 0.0
    d = step if full else min(step, math.hypot(tx - x, tz - z))
    r = math.radians(h)
    return x + d * math.sin(r), z + d * math.cos(r), h, d


def follow(waypoints, start_heading: float = 0.0, step: float = STEP_FT,
           max_turn: float = MAX_TURN_DEG, final_heading: float | None = None,
           room: Room | None = None, clearance: float = CLEARANCE_FT) -> list[Pose]:
    """Poses of a Cart that starts at waypoints[0] with ``start_heading`` and drives through
    the others in turn (passing each within one step, stopping on the last), ending turned in place to
    ``final_heading`` if given.  With ``room``, every pose is checked to keep ``clearance``."""
    x, z = waypoints[0]
    h = start_heading
    poses = [Pose(x, z, h)]
    last = len(waypoints) - 1
    for i, (tx, tz) in enumerate(waypoints[1:], start=1):
        # pass an intermediate waypoint within one step (keeps full steps); stop on the last
        reach = step / 2 if i == last else step
        for _ in range(10000):
            if math.hypot(tx - x, tz - z) <= reach:
                break
            x, z, h, _d = _step_towards(x, z, h, tx, tz, step, max_turn, full=i < last)
            poses.append(_round(Pose(x, z, h)))
            x, z, h = poses[-1].x, poses[-1].z, poses[-1].heading_deg
        else:
            raise RuntimeError(f"walk did not reach waypoint {(tx, tz)}")
    if final_heading is not None:
        while abs(wrap_deg(final_heading - h)) > 1e-9:
            h = h + max(-max_turn, min(max_turn, wrap_deg(final_heading - h)))
            poses.append(_round(Pose(x, z, h)))
            h = poses[-1].heading_deg
    if room is not None:
        for i, p in enumerate(poses):
            if not room.is_free(p.x, p.z, clearance):
                raise RuntimeError(f"walk pose {i} ({p.x:.2f}, {p.z:.2f}) is within "
                                   f"{clearance} ft of an obstacle or wall")
    return poses


def make_bundled_walk() -> list[Pose]:
    """The bundled walk, computed (``bundled_walk`` reads the shipped copy): ``LAB_LAPS``
    times round ``LAB_WAYPOINTS``, then turned to face forward."""
    laps = LAB_WAYPOINTS + LAB_WAYPOINTS[1:] * (LAB_LAPS - 1)
    return follow(laps, 0.0, final_heading=0.0, room=bundled_lab())


def bundled_walk() -> list[Pose]:
    """The shipped walk through the bundled lab (world/data/lab-walk.csv)."""
    return read_walk(BUNDLED_WALK)


# --- generated walks -----------------------------------------------------------------------

def _free_grid(room: Room, cell: float, clearance: float):
    x0, x1, z0, z1 = room.bounds
    xs = np.arange(x0 + cell / 2, x1, cell)
    zs = np.arange(z0 + cell / 2, z1, cell)
    free = np.array([[room.is_free(float(x), float(z), clearance) for x in xs] for z in zs])
    return xs, zs, free


def _shortest(free, a, b):
    """8-connected breadth-first path of grid cells from a to b (None if unreachable)."""
    prev = {a: None}
    q = deque([a])
    nz, nx = free.shape
    while q:
        c = q.popleft()
        if c == b:
            break
        for dz in (-1, 0, 1):
            for dx in (-1, 0, 1):
                n = (c[0] + dz, c[1] + dx)
                if (dz or dx) and 0 <= n[0] < nz and 0 <= n[1] < nx and free[n] and n not in prev \
                        and free[c[0] + dz, c[1]] and free[c[0], c[1] + dx]:
                    prev[n] = c
                    q.append(n)
    if b not in prev:
        return None
    path = [b]
    while prev[path[-1]] is not None:
        path.append(prev[path[-1]])
    return path[::-1]


def generate_walk(room: Room, seed: int, looks: int, step: float = STEP_FT,
                  max_turn: float = MAX_TURN_DEG, clearance: float = CLEARANCE_FT,
                  wobble_deg: float = 0.0) -> list[Pose]:
    """``looks`` poses of a Cart wandering ``room`` from ``room.start``: it picks a random free
    goal, follows the shortest grid path there (looking 1.5 ft ahead along it), and picks the
    next.  ``wobble_deg`` > 0 adds seeded pitch and roll, uniform in +-wobble_deg, to every pose
    after the first (an uneven floor: exercises all six degrees of freedom)."""
    if looks < 1:
        raise ValueError(f"a walk needs at least 1 look, got {looks}")
    rng = np.random.default_rng([int(seed), 20])
    cell = 0.25
    xs, zs, free = _free_grid(room, cell, clearance)
    cells = np.argwhere(free)
    if not len(cells):
        raise ValueError(f"room {room.name!r} has no free floor with {clearance} ft clearance")

    def cell_of(x, z):
        c = (int(np.clip((z - zs[0]) / cell + 0.5, 0, len(zs) - 1)),
             int(np.clip((x - xs[0]) / cell + 0.5, 0, len(xs) - 1)))
        if free[c]:
            return c
        d = ((cells - np.array(c)) ** 2).sum(axis=1)
        return tuple(cells[int(np.argmin(d))])

    s = room.start
    if not room.is_free(s.x, s.z, clearance):
        raise ValueError(f"room {room.name!r}: the start ({s.x:g}, {s.z:g}) is nearer than "
                         f"{clearance} ft to an obstacle or wall")
    x, z, h = s.x, s.z, s.heading_deg
    poses = [Pose(x, z, h, s.pitch_deg, s.roll_deg, s.y)]
    path: list = []
    failed = 0
    while len(poses) < looks:
        if not path:
            goal = tuple(cells[int(rng.integers(len(cells)))])
            p = _shortest(free, cell_of(x, z), goal)
            if not p or len(p) < 8:
                failed += 1
                if failed > 500:
                    raise ValueError(f"room {room.name!r}: no goal 2 ft away is reachable from "
                                     f"({x:.2f}, {z:.2f}) with {clearance} ft clearance")
                continue
            path = [(float(xs[c[1]]), float(zs[c[0]])) for c in p]
        # the target: the first path point at least 1.5 ft ahead; drop points already passed
        while len(path) > 1 and math.hypot(path[0][0] - x, path[0][1] - z) < 1.5:
            path.pop(0)
        tx, tz = path[0]
        nx_, nz_, nh, d = _step_towards(x, z, h, tx, tz, step, max_turn)
        if d > 0 and not room.is_free(nx_, nz_, clearance * 0.9):
            nx_, nz_ = x, z                    # would touch: turn only
        if len(path) == 1 and math.hypot(tx - nx_, tz - nz_) <= step / 2:
            path = []
        pitch = roll = 0.0
        if wobble_deg > 0:
            pitch, roll = (float(v) for v in rng.uniform(-wobble_deg, wobble_deg, size=2))
        poses.append(_round(Pose(nx_, nz_, nh, pitch, roll, s.y)))
        x, z, h = poses[-1].x, poses[-1].z, poses[-1].heading_deg
    return poses


# --- walk files ----------------------------------------------------------------------------

def walk_csv(poses) -> str:
    """The CSV text of a walk (header, then one row per pose, 4 decimals)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    with_y = any(p.y != 0.0 for p in poses)
    w.writerow(HEADER + (("y",) if with_y else ()))
    for p in poses:
        row = [p.x, p.z, p.heading_deg, p.pitch_deg, p.roll_deg] + ([p.y] if with_y else [])
        w.writerow([f"{v:.4f}" for v in row])
    return buf.getvalue()


def write_walk(path, poses) -> Path:
    """Write a walk CSV by the project's one atomic publish (diskfmt.rdos.write_atomic)."""
    return write_atomic(Path(path), walk_csv(poses).encode())


def parse_walk(text: str, name: str = "walk") -> list[Pose]:
    """Poses from walk CSV text; a bad header or row raises ValueError naming it."""
    rows = list(csv.reader(io.StringIO(text)))
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if not rows:
        raise ValueError(f"{name}: empty walk file (expected header {','.join(HEADER)})")
    head = tuple(c.strip() for c in rows[0])
    if head[:5] != HEADER or head[5:] not in ((), ("y",)):
        raise ValueError(f"{name}: header must be {','.join(HEADER)}[,y], got {','.join(head)}")
    poses = []
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(head):
            raise ValueError(f"{name}: line {i}: expected {len(head)} values, got {len(r)}")
        try:
            vals = [float(c) for c in r]
        except ValueError:
            raise ValueError(f"{name}: line {i}: not a number in {','.join(r)}") from None
        if not all(math.isfinite(v) for v in vals):
            raise ValueError(f"{name}: line {i}: values must be finite, got {','.join(r)}")
        x, z, hd, pt, rl = vals[:5]
        poses.append(Pose(x, z, hd, pt, rl, vals[5] if len(vals) > 5 else 0.0))
    if not poses:
        raise ValueError(f"{name}: no poses after the header")
    return poses


def read_walk(path) -> list[Pose]:
    """Poses from a walk CSV file."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise ValueError(f"{path}: cannot read walk file ({e.strerror})") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text CSV walk file") from None
    return parse_walk(text, str(path))
