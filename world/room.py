"""Rooms to walk through: the bundled lab closed behind the start, and seeded generated rooms.

A room is a list of axis-aligned quads (``rig.scene.Quad``; the renderer's whole scene) plus its
truth, computed from those quads so it cannot drift from what is drawn:

* ``vertices`` -- every distinct quad corner: the corners of boxes, doors, posters and the room;
* ``vertical_edges`` -- every vertical boundary a scan line can cross: the vertical sides of every
  vertical quad and the vertical grey steps of their textures (checks, stripes, binders, tape),
  found by bisection on the shading function and merged where collinear;
* ``obstacles`` -- floor footprints (x0, x1, z0, z1) of everything standing in the room, after
  dropping footprints that lie inside another (the table's legs, the box on the table);
* ``bounds`` -- (x0, x1, z0, z1) of the walls.

Coordinates as in ``rig/scene.py``: X right, Y down, Z forward from the bundled pose; the floor
is Y = +3 (the cameras are 3 ft above it).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from rig import scene
from rig.scene import Quad, checks, flat, stripes
from world.pose import Pose

FLOOR_Y = scene.FLOOR_Y
FRONT_WALL_Z = -5.0        # the bundled lab's wall behind the start (not in the 1985 pose's view)
_FACE_SUFFIXES = (" front", " back", " left side", " right side", " top")


@dataclass(frozen=True, eq=False)
class Room:
    """A closed room and its truth (see the module docstring).  ``start``: where walks begin."""
    name: str
    quads: tuple[Quad, ...]
    vertices: np.ndarray                  # (N, 3) float64
    vertical_edges: np.ndarray            # (M, 2, 3): [top (smaller Y), bottom] end points
    obstacles: np.ndarray                 # (K, 4): x0, x1, z0, z1
    bounds: tuple[float, float, float, float]
    vertex_labels: tuple[str, ...] = ()
    edge_labels: tuple[str, ...] = ()
    start: Pose = field(default_factory=lambda: Pose(0.0, 0.0, 0.0))
    ceiling_y: float = scene.CEILING_Y
    floor_y: float = FLOOR_Y

    def clearance(self, x: float, z: float) -> float:
        """Distance on the floor from (x, z) to the nearest obstacle footprint or wall, ft
        (negative: inside an obstacle or outside the walls)."""
        x0, x1, z0, z1 = self.bounds
        d = min(x - x0, x1 - x, z - z0, z1 - z)
        if d < 0:
            return d
        for ox0, ox1, oz0, oz1 in self.obstacles:
            dx = max(ox0 - x, 0.0, x - ox1)
            dz = max(oz0 - z, 0.0, z - oz1)
            if dx == 0.0 and dz == 0.0:
                return -min(x - ox0, ox1 - x, z - oz0, oz1 - z)
            d = min(d, math.hypot(dx, dz))
        return d

    def is_free(self, x: float, z: float, clearance: float = 0.0) -> bool:
        """True if (x, z) is at least ``clearance`` ft from every obstacle and wall."""
        return self.clearance(x, z) >= clearance

    def check_pose(self, pose: Pose, clearance: float = 0.0) -> None:
        """Raise ValueError naming the pose if it stands outside the walls or in an obstacle."""
        if not self.is_free(pose.x, pose.z, clearance):
            raise ValueError(f"pose x={pose.x:g} z={pose.z:g} ft is outside the free floor of "
                             f"room {self.name!r} (walls x {self.bounds[0]:g}..{self.bounds[1]:g}, "
                             f"z {self.bounds[2]:g}..{self.bounds[3]:g}, clearance {clearance:g} ft)")


# --- building rooms ------------------------------------------------------------------------

def _q(name, axis, c, b1, b2, shade) -> Quad:
    """A quad on the plane ``coord[axis] == c`` spanning ranges ``b1``, ``b2`` of the two other
    axes in X, Y, Z order (rig.scene's convention)."""
    return Quad(name, axis, float(c), (float(b1[0]), float(b2[0])),
                (float(b1[1]), float(b2[1])), shade)


quad = _q          # the public name


def full_box(name, x, y, z, front, side, top, back=None) -> list[Quad]:
    """All faces of a box a floor-bound camera can see: front (Z=z0), both sides, back (Z=z1),
    top (Y=y0).  The bottom stands on something and is never seen."""
    back = front if back is None else back
    return [
        _q(f"{name} front", 2, z[0], x, y, front),
        _q(f"{name} left side", 0, x[0], y, z, side),
        _q(f"{name} right side", 0, x[1], y, z, side),
        _q(f"{name} back", 2, z[1], x, y, back),
        _q(f"{name} top", 1, y[0], x, z, top),
    ]


def object_name(quad_name: str) -> str:
    """'crate left side' -> 'crate'."""
    for s in _FACE_SUFFIXES:
        if quad_name.endswith(s):
            return quad_name[: -len(s)]
    return quad_name


def _is_flat(q: Quad) -> bool:
    uu, vv = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    g = _shade_in_plane(q, q.lo[0] + uu * (q.hi[0] - q.lo[0]), q.lo[1] + vv * (q.hi[1] - q.lo[1]))
    return bool(np.all(g == g.flat[0]))


def _shade_in_plane(q: Quad, a, b):
    """Shade at in-plane coordinates (a, b) = the quad's two other axes in X, Y, Z order."""
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    c = np.full(a.shape, q.c)
    P = {0: (c, a, b), 1: (a, c, b), 2: (a, b, c)}[q.axis]
    return q.shade(*P)


def _texture_edges(q: Quad, row_step=0.01, col_step=0.004):
    """Vertical grey steps inside a vertical quad: list of (u, y_top, y_bottom), u the
    horizontal in-plane coordinate (X for a Z-plane, Z for an X-plane)."""
    # in-plane order is (X, Y) for axis 2 and (Y, Z) for axis 0; h = horizontal, y = vertical
    if q.axis == 2:
        h_lo, h_hi, y_lo, y_hi = q.lo[0], q.hi[0], q.lo[1], q.hi[1]
        shade = lambda h, y: _shade_in_plane(q, h, y)            # noqa: E731
    else:
        h_lo, h_hi, y_lo, y_hi = q.lo[1], q.hi[1], q.lo[0], q.hi[0]
        shade = lambda h, y: _shade_in_plane(q, y, h)            # noqa: E731
    ny = max(2, int(math.ceil((y_hi - y_lo) / row_step)))
    ys = y_lo + (np.arange(ny) + 0.5) * (y_hi - y_lo) / ny
    nh = max(2, int(math.ceil((h_hi - h_lo) / col_step)))
    hs = h_lo + (np.arange(nh) + 0.5) * (h_hi - h_lo) / nh
    g = shade(hs[None, :] + 0 * ys[:, None], ys[:, None] + 0 * hs[None, :])
    change = g[:, 1:] != g[:, :-1]
    r_idx, c_idx = np.nonzero(change)
    if r_idx.size == 0:
        return []
    # bisect every step of every row at once, to the float limit
    a, b, yr = hs[c_idx].copy(), hs[c_idx + 1].copy(), ys[r_idx]
    ga = g[r_idx, c_idx]
    for _ in range(60):
        m = 0.5 * (a + b)
        same = shade(m, yr) == ga
        a = np.where(same, m, a)
        b = np.where(same, b, m)
    found: dict[float, list[int]] = {}
    for u, r in zip(np.round(b, 9), r_idx):
        found.setdefault(float(u), []).append(int(r))

    def steps_at(u, y):
        e = 1e-7
        return shade(u - e, y) != shade(u + e, y)

    out, pending = [], []          # pending: (u, y_without, y_with, slot in out, 1=top 2=bottom)
    for u, rows in found.items():
        rows = sorted(set(rows))
        runs, start = [], rows[0]
        for prev, cur in zip(rows, rows[1:]):
            if cur != prev + 1:
                runs.append((start, prev))
                start = cur
        runs.append((start, rows[-1]))
        for r0, r1 in runs:
            out.append([u, y_lo, y_hi])
            if r0 > 0:
                pending.append((u, ys[r0 - 1], ys[r0], len(out) - 1, 1))
            if r1 < ny - 1:
                pending.append((u, ys[r1 + 1], ys[r1], len(out) - 1, 2))
    if pending:
        u = np.array([p[0] for p in pending])
        y_without = np.array([p[1] for p in pending])
        y_with = np.array([p[2] for p in pending])
        for _ in range(60):
            m = 0.5 * (y_without + y_with)
            st = steps_at(u, m)
            y_with = np.where(st, m, y_with)
            y_without = np.where(st, y_without, m)
        for (_, _, _, slot, end), y in zip(pending, np.round(y_with, 9)):
            out[slot][end] = float(y)
    return [tuple(o) for o in out]


def _truth(quads):
    """(vertices, vertex labels, vertical edges, edge labels) of a list of quads."""
    verts: dict[tuple, str] = {}
    segs: dict[tuple, list] = {}

    def add_seg(x, z, y0, y1, label):
        segs.setdefault((round(x, 9), round(z, 9)), []).append([min(y0, y1), max(y0, y1), label])

    for q in quads:
        (a0, b0), (a1, b1) = q.lo, q.hi
        for a in (a0, a1):
            for b in (b0, b1):
                p = {0: (q.c, a, b), 1: (a, q.c, b), 2: (a, b, q.c)}[q.axis]
                verts.setdefault(tuple(round(v, 9) for v in p), object_name(q.name))
        if q.axis == 1:
            continue
        name = object_name(q.name)
        if q.axis == 2:            # plane Z = c; in-plane (X, Y)
            for x in (a0, a1):
                add_seg(x, q.c, b0, b1, name)
            if not _is_flat(q):
                for u, y0, y1 in _texture_edges(q):
                    add_seg(u, q.c, y0, y1, name + " texture")
        else:                      # plane X = c; in-plane (Y, Z)
            for z in (b0, b1):
                add_seg(q.c, z, a0, a1, name)
            if not _is_flat(q):
                for u, y0, y1 in _texture_edges(q):
                    add_seg(q.c, u, y0, y1, name + " texture")
    edges, labels = [], []
    for (x, z), items in sorted(segs.items()):
        items.sort(key=lambda s: (s[0], s[1]))
        merged = [list(items[0])]
        for y0, y1, lab in items[1:]:
            if y0 <= merged[-1][1] + 1e-9:
                merged[-1][1] = max(merged[-1][1], y1)
            else:
                merged.append([y0, y1, lab])
        for y0, y1, lab in merged:
            if y1 - y0 > 1e-6:
                edges.append([[x, y0, z], [x, y1, z]])
                labels.append(lab)
    v = np.array(sorted(verts), dtype=np.float64).reshape(-1, 3)
    vlab = tuple(verts[tuple(p)] for p in sorted(verts))
    e = np.array(edges, dtype=np.float64).reshape(-1, 2, 3)
    return v, vlab, e, tuple(labels)


def _footprints(boxes):
    """Floor footprints of boxes, dropping any that lies inside another."""
    fp = [(float(x[0]), float(x[1]), float(z[0]), float(z[1])) for x, z in boxes]
    keep = []
    for i, a in enumerate(fp):
        inside = any(j != i and b[0] <= a[0] and a[1] <= b[1] and b[2] <= a[2] and a[3] <= b[3]
                     and (b != a or j < i) for j, b in enumerate(fp))
        if not inside:
            keep.append(a)
    return np.array(keep, dtype=np.float64).reshape(-1, 4)


def make_room(name, quads, boxes, bounds, start=None, ceiling_y=scene.CEILING_Y) -> Room:
    """A Room from its quads and the (x, z) extents of its boxes; truth computed here."""
    quads = tuple(quads)
    v, vlab, e, elab = _truth(quads)
    for a in (v, e):
        a.setflags(write=False)
    obs = _footprints(boxes)
    obs.setflags(write=False)
    return Room(name=name, quads=quads, vertices=v, vertical_edges=e, obstacles=obs,
                bounds=tuple(float(b) for b in bounds), vertex_labels=vlab, edge_labels=elab,
                start=start or Pose(0.0, 0.0, 0.0), ceiling_y=float(ceiling_y))


# --- the bundled lab -----------------------------------------------------------------------

def _lab_boxes():
    """(x, y, z, side shade) of every box of rig/scene.py's lab, as scene_quads() builds them."""
    s = scene
    ty = s.TABLE_TOP_Y
    boxes = [("waste bin", s.BIN_X, s.BIN_Y, s.BIN_Z, flat(8)),
             ("crate", s.CRATE_X, s.CRATE_Y, s.CRATE_Z, flat(4)),
             ("striped box", s.SBOX_X, s.SBOX_Y, s.SBOX_Z, flat(7)),
             ("table top", s.TABLE_X, (ty, ty + 0.15), s.TABLE_Z, flat(3))]
    for lx in (s.TABLE_X[0] + 0.05, s.TABLE_X[1] - 0.25):
        for lz in (s.TABLE_Z[0] + 0.05, s.TABLE_Z[1] - 0.25):
            boxes.append(("table leg", (lx, lx + 0.2), (ty + 0.15, FLOOR_Y), (lz, lz + 0.2), flat(1)))
    boxes += [("carton", s.CARTON_X, s.CARTON_Y, s.CARTON_Z, flat(9)),
              ("bookcase", s.BOOKCASE_X, s.BOOKCASE_Y, s.BOOKCASE_Z, flat(6))]
    return boxes


@functools.lru_cache(maxsize=1)
def bundled_lab() -> Room:
    """rig/scene.py's laboratory, closed behind the start so the robot can walk and turn.

    Seen from Pose(0, 0, 0) it is exactly the bundled scene (so the bundled pair renders bit for
    bit); the additions are all out of that pose's view: the side walls, floor and ceiling run
    back to a front wall at Z = -5 ft (with a door and a poster), the side walls carry posters
    (left wall at Z 2..8, nearer than the 10.2 ft where the left wall enters the 1985 view; right
    wall at Z < 18.6), and every box gets its back face (never nearer than its front, so never
    drawn from the bundled pose).  tests/test_world_render.py checks the bytes.
    """
    s = scene
    y0, y1 = s.CEILING_Y, FLOOR_Y
    x0, x1, z0, z1 = s.LEFT_WALL_X, s.RIGHT_WALL_X, FRONT_WALL_Z, s.BACK_Z
    decals = [
        # left wall (X = -4): a light poster with a dark band, and a chequered chart
        _q("left poster band", 0, x0, (-2.0, -1.6), (2.0, 4.0), flat(2)),
        _q("left poster", 0, x0, (-2.8, -0.6), (2.0, 4.0), flat(13)),
        _q("left chart", 0, x0, (-2.5, 0.5), (5.5, 8.0),
           checks(11, 4, 0.5, 1, 2, origin=(-2.5, 5.5))),
        # left wall, near the front: a striped calendar
        _q("left calendar", 0, x0, (-2.2, 0.2), (-3.5, -0.5), stripes(12, 3, 0.3, 2, origin=-3.5)),
        # right wall (X = 7): a map, a striped poster, a notice board with two sheets, a picture
        _q("right map", 0, x1, (-2.0, 0.5), (-3.0, 1.5), checks(13, 5, 0.45, 1, 2, origin=(-2.0, -3.0))),
        _q("right poster", 0, x1, (-2.5, 0.0), (5.0, 8.0), stripes(14, 5, 0.4, 2, origin=5.0)),
        _q("right notice sheet", 0, x1, (-2.6, -1.5), (11.4, 12.3), flat(14)),
        _q("right notice sheet", 0, x1, (-1.2, 0.1), (12.8, 13.5), flat(12)),
        _q("right notice board", 0, x1, (-3.0, 0.5), (11.0, 14.0), flat(2)),
        _q("right picture", 0, x1, (-2.0, -0.5), (15.5, 17.5), flat(1)),
        # front wall (Z = -5): a door and a poster
        _q("front door knob", 2, z0, (1.25, 1.4), (-0.05, 0.1), flat(15)),
        _q("front door panel", 2, z0, (0.5, 2.4), (-4.0, y1), flat(4)),
        _q("front door frame", 2, z0, (0.2, 2.7), (-4.3, y1), flat(13)),
        _q("front poster", 2, z0, (-3.0, -1.0), (-3.0, -0.5), stripes(3, 12, 0.5, 0, origin=-3.0)),
    ]
    quads = []
    for q in s.scene_quads():
        if q.name in ("left wall", "right wall"):         # in-plane (Y, Z)
            q = replace(q, lo=(q.lo[0], z0))
        elif q.name in ("floor", "ceiling"):              # in-plane (X, Z)
            q = replace(q, lo=(q.lo[0], z0))
        quads.append(q)
    quads = decals + quads
    quads.append(_q("front wall", 2, z0, (x0, x1), (y0, y1), flat(8)))
    boxes = _lab_boxes()
    for name, bx, by, bz, side in boxes:
        quads.append(_q(f"{name} back", 2, bz[1], bx, by, side))
    return make_room("bundled lab", quads, [(b[1], b[3]) for b in boxes], (x0, x1, z0, z1))


# --- generated rooms -----------------------------------------------------------------------

def _texture(rng, base: int, horizontal_axis: int, lo_h: float, lo_y: float, avoid=None):
    """A random surface pattern with enough contrast to give edges (its second grey at least
    3 levels from ``avoid``, the grey of the wall behind a poster)."""
    kind = rng.choice(["flat", "stripes", "checks", "band"], p=[0.35, 0.25, 0.25, 0.15])
    other = int((base + rng.integers(4, 12)) % 16)
    if avoid is not None and abs(other - avoid) < 3:
        other = int((avoid + 8) % 16) if abs((avoid + 8) % 16 - base) >= 3 else int((base + 8) % 16)
    if kind == "flat":
        return flat(base)
    if kind == "stripes":
        return stripes(base, other, float(rng.choice([0.2, 0.25, 0.3, 0.4])), horizontal_axis,
                       origin=lo_h)
    if kind == "checks":
        return checks(base, other, float(rng.choice([0.3, 0.35, 0.5])), horizontal_axis, 1,
                      origin=(lo_h, lo_y))
    centre = lo_h + float(rng.uniform(0.3, 0.7))
    width = float(rng.uniform(0.08, 0.2))
    ax = horizontal_axis

    def band(X, Y, Z, centre=centre, width=width, g1=float(base), g2=float(other)):
        return np.where(np.abs((X, Y, Z)[ax] - centre) < width, g2, g1)
    return band


def _far_enough(a, b, gap):
    return a[0] - gap >= b[1] or b[0] - gap >= a[1] or a[2] - gap >= b[3] or b[2] - gap >= a[3]


@functools.lru_cache(maxsize=64)
def generate_room(seed: int) -> Room:
    """A new closed room from ``seed``: walls, floor and ceiling of random greys (floor sometimes
    tiled), 1-2 doors and up to 9 posters on the walls, 3-7 boxes on the floor (some textured, some
    carrying a smaller box).  The start is Pose(0, 0, 0), at least 2.5 ft from every box and
    wall; every box keeps a 1.8 ft gap to the walls and to other boxes so a robot can pass."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"room seed must be a non-negative integer, got {seed!r}")
    rng = np.random.default_rng([int(seed), 10])
    width, depth = float(rng.uniform(10, 16)), float(rng.uniform(16, 26))
    x0 = -float(rng.uniform(3.5, width - 3.5))
    x1 = x0 + width
    z0 = -float(rng.uniform(3.0, 6.0))
    z1 = z0 + depth
    y0, y1 = -float(rng.uniform(4.0, 6.0)), FLOOR_Y
    x0, x1, z0, z1, y0 = (round(v, 3) for v in (x0, x1, z0, z1, y0))
    wall_g = [int(g) for g in rng.integers(5, 12, size=4)]        # left, right, front, back
    floor_g, ceil_g = int(rng.integers(3, 8)), int(rng.integers(10, 14))
    quads: list[Quad] = []
    boxes = []

    # boxes on the floor
    placed = []
    for i in range(int(rng.integers(3, 8))):
        for _ in range(200):
            w, d = float(rng.uniform(0.8, 2.5)), float(rng.uniform(0.8, 2.5))
            bx0 = float(rng.uniform(x0 + 1.8, x1 - 1.8 - w))
            bz0 = float(rng.uniform(z0 + 1.8, z1 - 1.8 - d))
            fp = tuple(round(v, 3) for v in (bx0, bx0 + w, bz0, bz0 + d))
            if all(_far_enough(fp, p, 1.8) for p in placed) and \
                    math.hypot(max(fp[0], 0.0, -fp[1]), max(fp[2], 0.0, -fp[3])) >= 2.5:
                break
        else:
            continue
        placed.append(fp)
        h = float(rng.uniform(0.8, 5.0))
        bx, bz, by = fp[:2], fp[2:], (round(y1 - h, 3), y1)
        g = [int(v) for v in rng.choice(np.arange(1, 16), size=3, replace=False)]
        name = f"box {i + 1}"
        front = _texture(rng, g[0], 0, bx[0], by[0])
        back = _texture(rng, g[0], 0, bx[0], by[0])
        quads += full_box(name, bx, by, bz, front, _texture(rng, g[1], 2, bz[0], by[0]),
                          flat(g[2]), back=back)
        boxes.append((bx, bz))
        if rng.random() < 0.3 and h < 3.5:        # a smaller box on top
            sw, sd, sh = w * float(rng.uniform(0.3, 0.6)), d * float(rng.uniform(0.3, 0.6)), \
                float(rng.uniform(0.4, 1.2))
            sx = round(bx[0] + float(rng.uniform(0, w - sw)), 3)
            sz = round(bz[0] + float(rng.uniform(0, d - sd)), 3)
            sg = [int(v) for v in rng.choice(np.arange(1, 16), size=3, replace=False)]
            sbx, sbz, sby = (sx, round(sx + sw, 3)), (sz, round(sz + sd, 3)), \
                (round(by[0] - sh, 3), by[0])
            quads += full_box(f"{name} small box", sbx, sby, sbz,
                              _texture(rng, sg[0], 0, sbx[0], sby[0]), flat(sg[1]), flat(sg[2]))
            boxes.append((sbx, sbz))

    # doors and posters on the walls: (wall, horizontal interval) allocated without overlap
    walls = {"left": (0, x0, z0, z1, 2), "right": (0, x1, z0, z1, 2),
             "front": (2, z0, x0, x1, 0), "back": (2, z1, x0, x1, 0)}
    used: dict[str, list] = {k: [] for k in walls}

    def slot(wall, w):
        axis, c, h0, h1, hax = walls[wall]
        for _ in range(100):
            a = float(rng.uniform(h0 + 0.5, h1 - 0.5 - w))
            iv = (round(a, 3), round(a + w, 3))
            if all(iv[0] - 0.4 >= b[1] or b[0] - 0.4 >= iv[1] for b in used[wall]):
                used[wall].append(iv)
                return iv
        return None

    names = list(walls)
    decals: list[Quad] = []
    for i in range(int(rng.integers(1, 3))):
        wall = names[int(rng.integers(0, 4))]
        dw = float(rng.uniform(2.4, 3.2))
        iv = slot(wall, dw)
        if iv is None:
            continue
        axis, c, _, _, hax = walls[wall]
        top = round(y1 - float(rng.uniform(6.5, 7.2)), 3)
        top = max(top, round(y0 + 0.3, 3))
        fg, pg = int(rng.integers(11, 16)), int(rng.integers(1, 6))
        inset = 0.25
        panel = (round(iv[0] + inset, 3), round(iv[1] - inset, 3))
        k0 = panel[1] - 0.35 if rng.random() < 0.5 else panel[0] + 0.2
        knob = (round(k0, 3), round(k0 + 0.15, 3))
        ky = (round(y1 - 3.05, 3), round(y1 - 2.9, 3))
        for nm, hiv, yiv, shade in ((f"door {i + 1} knob", knob, ky, flat(15)),
                                    (f"door {i + 1} panel", panel, (round(top + inset, 3), y1), flat(pg)),
                                    (f"door {i + 1} frame", iv, (top, y1), flat(fg))):
            b1, b2 = ((yiv, hiv) if axis == 0 else (hiv, yiv))
            decals.append(_q(nm, axis, c, b1, b2, shade))
    for i in range(int(rng.integers(4, 10))):
        wall = names[int(rng.integers(0, 4))]
        pw = float(rng.uniform(1.0, 3.0))
        iv = slot(wall, pw)
        if iv is None:
            continue
        axis, c, _, _, hax = walls[wall]
        ph = float(rng.uniform(1.0, 2.5))
        ptop = float(rng.uniform(y0 + 0.8, min(y1 - 1.0 - ph, 0.5)))
        yiv = (round(ptop, 3), round(ptop + ph, 3))
        wg = wall_g[names.index(wall)]
        pg = int((wg + rng.integers(4, 12)) % 16)
        shade = _texture(rng, pg, hax, iv[0], yiv[0], avoid=wg)
        b1, b2 = ((yiv, iv) if axis == 0 else (iv, yiv))
        decals.append(_q(f"{wall} poster {i + 1}", axis, c, b1, b2, shade))
    quads += decals
    if rng.random() < 0.6:                           # skirting
        sg = int(rng.integers(1, 5))
        for wall, (axis, c, h0, h1, _) in walls.items():
            yiv, hiv = (round(y1 - 0.3, 3), y1), (h0, h1)
            b1, b2 = ((yiv, hiv) if axis == 0 else (hiv, yiv))
            quads.append(_q(f"{wall} skirting", axis, c, b1, b2, flat(sg)))
    for (wall, (axis, c, h0, h1, _)), g in zip(walls.items(), wall_g):
        b1, b2 = (((y0, y1), (h0, h1)) if axis == 0 else ((h0, h1), (y0, y1)))
        quads.append(_q(f"{wall} wall", axis, c, b1, b2, flat(g)))
    if rng.random() < 0.4:
        tile = float(rng.choice([1.0, 1.5, 2.0]))
        floor = checks(floor_g, floor_g + 2, tile, 0, 2, origin=(x0, z0))
    else:
        floor = flat(floor_g)
    quads.append(_q("floor", 1, y1, (x0, x1), (z0, z1), floor))
    quads.append(_q("ceiling", 1, y0, (x0, x1), (z0, z1), flat(ceil_g)))
    return make_room(f"room {seed}", quads, boxes, (x0, x1, z0, z1), ceiling_y=y0)
