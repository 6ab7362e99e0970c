"""Render a look: both cameras of the rig at any pose, through PRE's condense, with truth.

The camera model is rig/scene.py's (ESTAR's LCSL): pinhole cameras with parallel optical axes
0.75 ft apart, focal length 360 px at 256x240 (180 px at 128x120), principal point at the
picture centre, 4x4 rays per 256-px pixel, rounding to 16 grey levels, 3 % of pixels moved one
level by a seeded generator (left picture first, then right), and PRE's 2x2 condense.  A ray
through camera-plane point (px, py) has camera direction (px, py, 1), so its hit parameter is
the range Z along the optical axis; in the room it starts at the camera centre with direction
``R @ (px, py, 1)``.  With the identity rotation every product and sum here is exact, which is
why Pose(0, 0, 0) gives the bundled pair's bytes.

Speed: each quad is intersected only with the rays inside the bounding box of its picture (its
corners, clipped to the half space in front of the camera, projected, padded by 2 rays); a ray
outside that box cannot hit it, so the result is exactly the full intersection's
(``trace_rays``, tested equal in tests/test_world_render.py).  With numba the windows are
intersected by a compiled loop doing the same float operations (``RIG_NO_JIT=1``: numpy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from diskfmt.jit import ENABLED as JIT_ENABLED
from diskfmt.jit import jit
from pre.condense import condense
from rig.scene import (CX, CY, DEFAULT_SEED, FOCAL_128, FOCAL_256, HEIGHT, NOISE_FRACTION,
                       SUPERSAMPLE, WIDTH, Quad, add_noise, quantise)
from world.pose import Pose
from world.room import Room

_NEAR = 1e-3           # clip quads at camera z >= this ...
_CLOSE = 1e-2          # ... when the camera is at least this far from them (then a clipped
                       # sliver projects at |x/z| > 9.9, far outside the picture)
_PAD = 2               # rays of padding around each quad's picture box


class LeftTheRoom(RuntimeError):
    """A ray hit nothing: the room is not closed, or the camera is outside it."""


def _grid(supersample: int):
    """Camera-plane coordinates (px per column, py per row) of the ray grid of a 256x240
    picture with ``supersample``^2 rays per pixel, as rig/scene.py lays them out."""
    s = supersample
    offs = (np.arange(s) + 0.5) / s
    u = (np.arange(WIDTH)[:, None] + offs[None, :]).reshape(-1)
    v = (np.arange(HEIGHT)[:, None] + offs[None, :]).reshape(-1)
    return (u - CX) / FOCAL_256, (v - CY) / FOCAL_256


def _grid_128():
    """Camera-plane coordinates of the rays through the centres of the 128x120 pixels."""
    u = 2.0 * np.arange(128) + 1.0          # 128-px centre j+0.5 -> 256-px 2j+1
    v = 2.0 * np.arange(120) + 1.0
    return (u - CX) / FOCAL_256, (v - CY) / FOCAL_256


def _directions(R, px, py):
    """Room directions R @ (px, py, 1) of a ray grid: a (3, rows, cols) array."""
    d = np.empty((3, py.size, px.size))
    for a in range(3):
        d[a] = R[a, 0] * px[None, :] + R[a, 1] * py[:, None] + R[a, 2]
    return d


def _quad_corners(q: Quad) -> np.ndarray:
    (a0, b0), (a1, b1) = q.lo, q.hi
    pts = []
    for a, b in ((a0, b0), (a1, b0), (a1, b1), (a0, b1)):
        pts.append({0: (q.c, a, b), 1: (a, q.c, b), 2: (a, b, q.c)}[q.axis])
    return np.array(pts, dtype=np.float64)


def _distance_to_quad(q: Quad, p) -> float:
    others = [a for a in range(3) if a != q.axis]
    d2 = (p[q.axis] - q.c) ** 2
    for a, lo, hi in zip(others, q.lo, q.hi):
        d2 += max(lo - p[a], 0.0, p[a] - hi) ** 2
    return float(np.sqrt(d2))


def _clip_front(poly: np.ndarray, near: float) -> np.ndarray:
    """Sutherland-Hodgman clip of a polygon (camera coordinates) to z >= near."""
    out = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        ina, inb = a[2] >= near, b[2] >= near
        if ina:
            out.append(a)
        if ina != inb:
            f = (near - a[2]) / (b[2] - a[2])
            out.append(a + f * (b - a))
    return np.array(out).reshape(-1, 3)


def _window(q: Quad, origin, R, px, py):
    """(row slice, column slice) of the ray grid that can hit quad ``q``, or None."""
    if _distance_to_quad(q, origin) < _CLOSE:
        return slice(0, py.size), slice(0, px.size)
    cam = (_quad_corners(q) - origin) @ R
    poly = _clip_front(cam, _NEAR)
    if len(poly) == 0:
        return None
    u = poly[:, 0] / poly[:, 2]
    v = poly[:, 1] / poly[:, 2]
    c0 = max(int(np.searchsorted(px, u.min())) - _PAD, 0)
    c1 = min(int(np.searchsorted(px, u.max())) + _PAD, px.size)
    r0 = max(int(np.searchsorted(py, v.min())) - _PAD, 0)
    r1 = min(int(np.searchsorted(py, v.max())) + _PAD, py.size)
    if c0 >= c1 or r0 >= r1:
        return None
    return slice(r0, r1), slice(c0, c1)


def _quad_params(quads) -> np.ndarray:
    """(K, 6): axis, c, lo0, hi0, lo1, hi1 of every quad."""
    return np.array([(q.axis, q.c, q.lo[0], q.hi[0], q.lo[1], q.hi[1]) for q in quads],
                    dtype=np.float64).reshape(-1, 6)


def _windows(quads, params, origin, R, px, py):
    """``_window`` for every quad, vectorised for the common case (the camera not close to the
    quad, all four corners in front of it); the others one by one."""
    k = len(quads)
    axis = params[:, 0].astype(np.int64)
    c, a0, a1, b0, b1 = params[:, 1], params[:, 2], params[:, 3], params[:, 4], params[:, 5]
    # corners (K, 4, 3) in the in-plane order (a0,b0) (a1,b0) (a1,b1) (a0,b1)
    aa = np.stack([a0, a1, a1, a0], axis=1)
    bb = np.stack([b0, b0, b1, b1], axis=1)
    cc = np.repeat(c[:, None], 4, axis=1)
    corners = np.empty((k, 4, 3))
    for ax, (i, j, m) in enumerate(((cc, aa, bb), (aa, cc, bb), (aa, bb, cc))):
        sel = axis == ax
        corners[sel, :, 0], corners[sel, :, 1], corners[sel, :, 2] = i[sel], j[sel], m[sel]
    # distance from the camera to each rectangle
    o = np.asarray(origin, dtype=np.float64)
    oa = np.choose(axis, [o[0], o[1], o[2]])
    o1 = np.where(axis == 0, o[1], o[0])
    o2 = np.where(axis == 2, o[1], o[2])
    dist = np.sqrt((oa - c) ** 2 + np.maximum.reduce([a0 - o1, np.zeros(k), o1 - a1]) ** 2
                   + np.maximum.reduce([b0 - o2, np.zeros(k), o2 - b1]) ** 2)
    cam = (corners - o) @ R
    z = cam[..., 2]
    simple = (z >= _NEAR).all(axis=1) & (dist >= _CLOSE)
    with np.errstate(divide="ignore", invalid="ignore"):
        u, v = cam[..., 0] / z, cam[..., 1] / z
    c0 = np.maximum(np.searchsorted(px, u.min(axis=1)) - _PAD, 0)
    c1 = np.minimum(np.searchsorted(px, u.max(axis=1)) + _PAD, px.size)
    r0 = np.maximum(np.searchsorted(py, v.min(axis=1)) - _PAD, 0)
    r1 = np.minimum(np.searchsorted(py, v.max(axis=1)) + _PAD, py.size)
    out = []
    for i, q in enumerate(quads):
        if not simple[i]:
            out.append(_window(q, o, R, px, py))
        elif c0[i] >= c1[i] or r0[i] >= r1[i]:
            out.append(None)
        else:
            out.append((slice(int(r0[i]), int(r1[i])), slice(int(c0[i]), int(c1[i]))))
    return out


def _intersect(q: Quad, origin, d, best, which, k):
    """Update (best, which) in place where rays ``d`` from ``origin`` hit ``q`` nearer."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (q.c - origin[q.axis]) / d[q.axis]
        hit = (t > 0) & (t < best)
        for a, lo, hi in zip([a for a in range(3) if a != q.axis], q.lo, q.hi):
            P = origin[a] + t * d[a]
            hit &= (P >= lo) & (P <= hi)
    np.copyto(best, t, where=hit)
    which[hit] = k


@jit
def _intersect_windows(params, wins, o, d, best, which):
    """Compiled ``_intersect`` for every quad inside its window; the same float operations in
    the same order, so the same result (tests/test_world_render.py compares).  params[k] =
    (axis, c, lo0, hi0, lo1, hi1); wins[k] = (r0, r1, c0, c1), empty when r0 == r1."""
    for k in range(params.shape[0]):
        axis = int(params[k, 0])
        a1 = 1 if axis == 0 else 0
        a2 = 1 if axis == 2 else 2
        c, lo0, hi0, lo1, hi1 = params[k, 1], params[k, 2], params[k, 3], params[k, 4], params[k, 5]
        num = c - o[axis]
        for i in range(wins[k, 0], wins[k, 1]):
            for j in range(wins[k, 2], wins[k, 3]):
                da = d[axis, i, j]
                if da == 0.0:              # numpy: +-inf or nan, never a hit
                    continue
                t = num / da
                if not (t > 0.0 and t < best[i, j]):
                    continue
                p = o[a1] + t * d[a1, i, j]
                if not (p >= lo0 and p <= hi0):
                    continue
                p = o[a2] + t * d[a2, i, j]
                if not (p >= lo1 and p <= hi1):
                    continue
                best[i, j] = t
                which[i, j] = k


def trace_rays(quads, origin, d):
    """Plain reference: the nearest hit of rays ``origin + t*d`` (d: three equal-shape arrays)
    against every quad.  Returns (t, index of the quad hit; -1 where nothing was hit).  Where
    two quads are hit at the same t the one listed first wins (decals before their wall)."""
    o = np.asarray(origin, dtype=np.float64)
    best = np.full(d[0].shape, np.inf)
    which = np.full(d[0].shape, -1, dtype=np.int32)
    for k, q in enumerate(quads):
        _intersect(q, o, d, best, which, k)
    return best, which


def trace_grid(quads, origin, R, px, py, windowed: bool = True):
    """``trace_rays`` on the ray grid (px per column, py per row) of a camera at ``origin`` with
    rotation ``R``, testing each quad only inside its picture window (``windowed=False``: the
    plain reference, every quad against every ray).  Returns (t, which, d)."""
    o = np.asarray(origin, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    d = _directions(R, px, py)
    if not windowed:
        return (*trace_rays(quads, o, d), d)
    best, which, _ = _trace_windows(quads, o, R, px, py, d)
    return best, which, d


def _trace_windows(quads, o, R, px, py, d):
    best = np.full(d[0].shape, np.inf)
    which = np.full(d[0].shape, -1, dtype=np.int32)
    params = _quad_params(quads)
    windows = _windows(quads, params, o, R, px, py)
    if JIT_ENABLED and isinstance(d, np.ndarray):
        wins = np.array([(0, 0, 0, 0) if w is None else (w[0].start, w[0].stop, w[1].start,
                                                         w[1].stop) for w in windows],
                        dtype=np.int64).reshape(-1, 4)
        _intersect_windows(params, wins, o, d, best, which)
        return best, which, windows
    for k, q in enumerate(quads):
        if windows[k] is not None:
            win = windows[k]
            _intersect(q, o, tuple(a[win] for a in d), best[win], which[win], k)
    return best, which, windows


def shade_hits(quads, origin, d, t, which, windows=None) -> np.ndarray:
    """Grey level at every ray's hit point.  ``windows``: per quad, the (rows, cols) slices
    that hold all its hits (None: the whole grid), from the windowed trace."""
    if (which < 0).any():
        n = int((which < 0).sum())
        raise LeftTheRoom(f"{n} rays hit nothing: the room is not closed or the camera at "
                          f"{tuple(float(v) for v in origin)} is outside it")
    # plain greys straight from a table; only textured quads need their hit points
    lut = np.array([getattr(q.shade, "grey", 0.0) for q in quads])
    grey = lut[which]
    o = np.asarray(origin, dtype=np.float64)
    everything = (slice(None), slice(None))
    for k, q in enumerate(quads):
        if hasattr(q.shade, "grey"):
            continue
        win = everything if windows is None else windows[k]
        if win is None:
            continue
        m = which[win] == k
        if m.any():
            tk = t[win][m]
            grey[win][m] = q.shade(o[0] + tk * d[0][win][m], o[1] + tk * d[1][win][m],
                                   o[2] + tk * d[2][win][m])
    return grey


def render_camera(quads, origin, R, supersample: int = SUPERSAMPLE,
                  windowed: bool = True, _d=None) -> np.ndarray:
    """The noise-free 240x256 picture (float mean grey 0..15) of a camera at ``origin`` whose
    axes are the columns of ``R``."""
    px, py = _grid(supersample)
    o, R = np.asarray(origin, dtype=np.float64), np.asarray(R, dtype=np.float64)
    if windowed:
        d = _directions(R, px, py) if _d is None else _d
        t, which, windows = _trace_windows(quads, o, R, px, py, d)
    else:
        t, which, d = trace_grid(quads, o, R, px, py, windowed=False)
        windows = None
    grey = shade_hits(quads, o, d, t, which, windows)
    s = supersample
    return grey.reshape(HEIGHT, s, WIDTH, s).mean(axis=(1, 3))


def range_128(quads, origin, R, windowed: bool = True):
    """(Z ft, quad index) through the centre of each 128x120 pixel of the camera at ``origin``."""
    px, py = _grid_128()
    t, which, _ = trace_grid(quads, origin, R, px, py, windowed)
    if (which < 0).any():
        raise LeftTheRoom(f"rays through {int((which < 0).sum())} pixel centres hit nothing")
    return t, which


def project(room_points, pose: Pose, side: str = "left"):
    """Continuous 128-px picture coordinates (col, row, z) of room points (..., 3): pixel j
    spans [j, j+1); principal point (64, 60); focal 180 px; z is the camera-axis range (ft).
    Points behind the camera (z <= 0) get NaN coordinates."""
    cam = pose.to_camera(room_points, side)
    z = cam[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        col = np.where(z > 0, 64.0 + FOCAL_128 * cam[..., 0] / z, np.nan)
        row = np.where(z > 0, 60.0 + FOCAL_128 * cam[..., 1] / z, np.nan)
    return col, row, z


def visible(room: Room, pose: Pose, room_points, side: str = "left", tol_ft: float = 0.02):
    """Boolean per room point: in the 128x120 picture of ``side`` and not hidden by anything
    nearer (the ray to it hits nothing more than ``tol_ft`` in front of it)."""
    pts = np.asarray(room_points, dtype=np.float64).reshape(-1, 3)
    col, row, z = project(pts, pose, side)
    inside = (z > 0) & (col >= 0) & (col < 128) & (row >= 0) & (row < 120)
    out = np.zeros(len(pts), dtype=bool)
    if inside.any():
        cam = pose.to_camera(pts[inside], side)
        dcam = cam / cam[:, 2:3]                      # (px, py, 1): t is the camera z
        droom = dcam @ pose.rotation().T
        t, _ = trace_rays(room.quads, pose.camera_centre(side), tuple(droom.T))
        out[inside] = t >= cam[:, 2] - tol_ft
    return out.reshape(np.shape(room_points)[:-1])


@dataclass(frozen=True, eq=False)
class Look:
    """One look of the rig: pictures and truth.

    ``left_vd``/``right_vd``: 240x256 uint8 grey 0..15 (the cameras' .VD pictures);
    ``left_bi``/``right_bi``: 120x128 PRE condense of them (.BI); ``range_left``/``range_right``:
    120x128 float32 Z (ft, along that camera's axis) through each 128-px pixel centre;
    ``surface_left``: 120x128 int32 index into ``room.quads`` of the surface seen there."""
    room: Room
    pose: Pose
    seed: int
    left_vd: np.ndarray
    right_vd: np.ndarray
    left_bi: np.ndarray
    right_bi: np.ndarray
    range_left: np.ndarray
    range_right: np.ndarray
    surface_left: np.ndarray

    def project(self, room_points, side: str = "left"):
        return project(room_points, self.pose, side)

    def visible(self, room_points, side: str = "left", tol_ft: float = 0.02):
        return visible(self.room, self.pose, room_points, side, tol_ft)

    @property
    def disparity_left(self) -> np.ndarray:
        """True LOC1 - LOC2 in 128-px columns per pixel of the left picture: 0.75*180/Z."""
        return (0.75 * FOCAL_128 / self.range_left.astype(np.float64)).astype(np.float32)

    def visible_vertices(self, side: str = "left"):
        """(indices into room.vertices, their (col, row, z)) of the corners this look shows."""
        ok = self.visible(self.room.vertices, side)
        idx = np.flatnonzero(ok)
        col, row, z = self.project(self.room.vertices[idx], side)
        return idx, np.stack([col, row, z], axis=-1)


def render_look(room: Room, pose: Pose, seed: int = DEFAULT_SEED,
                noise: float = NOISE_FRACTION, supersample: int = SUPERSAMPLE,
                windowed: bool = True) -> Look:
    """Render both cameras of the rig at ``pose`` in ``room``.  ``seed`` drives only the sensor
    noise (the bundled pair uses 1985); ``noise`` is the share of pixels moved one level;
    ``supersample`` rays per pixel side (4 as in 1985's bundled pair; fewer is faster);
    ``windowed=False`` traces every quad against every ray (the plain reference: same result)."""
    if not isinstance(pose, Pose):
        raise TypeError(f"pose must be a world.pose.Pose, got {type(pose).__name__}")
    R = pose.rotation()
    rng = np.random.default_rng(seed)
    vds = []
    d = _directions(R, *_grid(supersample))          # both cameras share the rotation
    for side in ("left", "right"):
        grey = render_camera(room.quads, pose.camera_centre(side), R, supersample, windowed, d)
        vds.append(add_noise(quantise(grey), rng, noise))
    zl, wl = range_128(room.quads, pose.camera_centre("left"), R, windowed)
    zr, _ = range_128(room.quads, pose.camera_centre("right"), R, windowed)
    arrays = [vds[0], vds[1], condense(vds[0]), condense(vds[1]), zl.astype(np.float32),
              zr.astype(np.float32), wl]
    for a in arrays:
        a.setflags(write=False)
    return Look(room, pose, int(seed), *arrays)
