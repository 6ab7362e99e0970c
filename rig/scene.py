"""The bundled laboratory stereo pair: a small, deterministic, synthetic lab scene.

The pictures of the 1985 laboratory are lost, so every command falls back to this
scene instead.  It is rendered with the geometry the rig assumes (ESTAR in the
listing LCSL):

* two pinhole cameras with parallel optical axes, 0.75 ft apart on a horizontal
  baseline: the LEFT camera at X = -0.375 ft, the RIGHT camera at X = +0.375 ft;
* focal length ("virtual image distance") 360 px on the 256x240 picture, i.e.
  180 px on the 128x120 picture the rig works on;
* principal point at the picture centre (column 128, row 120 of the 256x240
  picture in continuous coordinates whose pixel ``k`` spans ``[k, k+1)``);
* identical rows in both cameras, so epipolar lines are horizontal and a point
  at range Z appears ``0.75*180/Z`` 128-px columns further right in the left
  picture than in the right one (LOC1 - LOC2 > 0).

Camera-relative axes (the rig's dx, dy, dp): X to the right, Y DOWN (rows
increase downward, like ESTAR's ``dy = (IY-60)*dp/dv``), Z forward along the
optical axes; the origin is midway between the two cameras.  Ranges are Z, in
feet, measured along the optical axis (not along the ray).

Rendering: every pixel of the 256x240 picture is the average of 4x4 ray samples
(supersampling, so edges get intermediate grey levels as a real camera's would);
all surface grey levels are integers, so the average of 16 samples is an exact
binary fraction and the rounding to 16 grey levels has no float ambiguity.  A
fixed-seed generator then moves a small fraction of pixels one grey level up or
down ("sensor noise").  The 128x120 ``.BI`` pictures are PRE's 2x2 shrink
(:func:`pre.condense.condense`) of the ``.VD`` pictures.

Truth: ``LAB-RANGE.npy`` holds Z (ft, float32, 120x128) for each pixel of the
LEFT 128x120 picture, sampled by one ray through the CENTRE of the pixel (the
centre of the 2x2 block of 256-px pixels it condenses).  The true disparity in
128-px columns is ``0.75*180/Z`` (:func:`true_disparity`).

The rays are cast by :mod:`world.render` (which renders this lab, closed
behind the start, from any pose).  Everything is plain float64 numpy
arithmetic and a seeded ``numpy.random`` generator: no time, threads or platform dependence, so rendering twice gives
the same bytes (checked in tests/test_scene.py).

Regenerate the shipped files with ``python -m rig.scene --out rig/data``.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from diskfmt.layouts import encode_bi, encode_vd
from pre.condense import condense

# --- the rig's geometry --------------------------------------------------------

BASELINE_FT = 0.75            # ds: camera separation
FOCAL_128 = 180.0             # dv: virtual image distance at 128 px width
FOCAL_256 = 360.0             # the same at 256 px width
LEFT_X = -BASELINE_FT / 2     # left camera centre, ft
RIGHT_X = +BASELINE_FT / 2    # right camera centre, ft
WIDTH, HEIGHT = 256, 240      # camera (.VD) picture
CX, CY = WIDTH / 2, HEIGHT / 2  # principal point, continuous 256-px coordinates
SUPERSAMPLE = 4               # 4x4 ray samples per 256-px pixel
NOISE_FRACTION = 0.03         # share of pixels moved by one grey level
DEFAULT_SEED = 1985

FILES = ("LAB-L.VD", "LAB-R.VD", "LAB-L.BI", "LAB-R.BI", "LAB-RANGE.npy")

Shade = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


# --- scene description ---------------------------------------------------------

@dataclass(frozen=True)
class Quad:
    """An axis-aligned rectangle: the plane ``coord[axis] == c`` bounded by
    ``lo <= coord <= hi`` on the two other axes (in X, Y, Z order, skipping
    ``axis``).  ``shade(X, Y, Z)`` gives the integer grey level 0..15 at hit
    points.  Where two quads are hit at the same range the one listed first
    wins, so markings on a wall ("decals") are listed before the wall."""
    name: str
    axis: int
    c: float
    lo: tuple[float, float]
    hi: tuple[float, float]
    shade: Shade


class flat:
    """A plain grey ``g`` (a Shade; ``.grey`` lets a renderer fill it without hit points)."""

    def __init__(self, g: int):
        self.grey = float(g)

    def __call__(self, X, Y, Z):
        return np.full(np.shape(X), self.grey)

    def __repr__(self):
        return f"flat({self.grey:g})"


def checks(g1: int, g2: int, size: float, u: int, v: int, origin=(0.0, 0.0)) -> Shade:
    """A checkerboard of ``size`` ft squares on the in-plane axes ``u``, ``v``."""
    def shade(X, Y, Z):
        P = (X, Y, Z)
        k = (np.floor((P[u] - origin[0]) / size) + np.floor((P[v] - origin[1]) / size)) % 2
        return np.where(k == 0, float(g1), float(g2))
    return shade


def stripes(g1: int, g2: int, width: float, axis: int, origin: float = 0.0) -> Shade:
    """Stripes ``width`` ft wide across ``axis`` (axis 0 or 2: vertical stripes)."""
    def shade(X, Y, Z):
        P = (X, Y, Z)
        k = np.floor((P[axis] - origin) / width) % 2
        return np.where(k == 0, float(g1), float(g2))
    return shade


def _quad(name, axis, c, b1, b2, shade) -> Quad:
    return Quad(name, axis, float(c), (float(b1[0]), float(b2[0])),
                (float(b1[1]), float(b2[1])), shade)


def box(name: str, x: tuple[float, float], y: tuple[float, float],
        z: tuple[float, float], front: Shade, side: Shade, top: Shade) -> list[Quad]:
    """The visible faces of a box (front Z=z0, both sides, top Y=y0; Y is down)."""
    return [
        _quad(f"{name} front", 2, z[0], x, y, front),
        _quad(f"{name} left side", 0, x[0], y, z, side),
        _quad(f"{name} right side", 0, x[1], y, z, side),
        _quad(f"{name} top", 1, y[0], x, z, top),
    ]


FLOOR_Y = 3.0       # the cameras are 3 ft above the floor (Y is down)
CEILING_Y = -5.0    # 8 ft ceiling
BACK_Z = 19.0       # back wall
LEFT_WALL_X = -4.0  # the side wall receding on the left
RIGHT_WALL_X = 7.0  # out of view; closes the room


@dataclass(frozen=True)
class SceneObject:
    """One row of the scene table in docs/scene.md (also used by the tests)."""
    name: str
    x: tuple[float, float]
    y: tuple[float, float]
    z: tuple[float, float]
    grey: str
    note: str


BOOK_GREYS = (3, 11, 6, 13, 8, 4, 12, 9, 5, 14, 7, 10)


def _bookcase_front(X, Y, Z):
    """Bookcase: dark shelf boards every 1.3 ft, ring binders and file boxes
    0.24-0.4 ft wide (3-5 columns at 128 px width) in a fixed cycle of grey
    levels, each shelf starting the cycle elsewhere (many vertical edges)."""
    widths = np.array([0.25, 0.35, 0.3, 0.4, 0.26, 0.32, 0.38, 0.28, 0.34, 0.24, 0.4, 0.3])
    edges = np.concatenate([[0.0], np.cumsum(widths)])       # one cycle of books
    period = edges[-1]
    shelf = np.floor((Y - BOOKCASE_Y[0]) / 1.3)
    # each shelf starts the cycle at a different book, so shelves differ
    pos = (X - BOOKCASE_X[0] + 0.37 * shelf) % period
    k = np.searchsorted(edges, pos, side="right") - 1
    g = np.asarray(BOOK_GREYS, dtype=float)[np.clip(k, 0, len(widths) - 1)]
    board = ((Y - BOOKCASE_Y[0]) % 1.3) < 0.12
    g = np.where(board, 1.0, g)
    frame = (X < BOOKCASE_X[0] + 0.1) | (X > BOOKCASE_X[1] - 0.1)
    return np.where(frame, 1.0, g)


BIN_X, BIN_Y, BIN_Z = (-0.2, 0.8), (0.8, FLOOR_Y), (3.5, 4.2)
CRATE_X, CRATE_Y, CRATE_Z = (-1.0, 0.0), (0.2, FLOOR_Y), (5.0, 6.0)
TABLE_X, TABLE_Z, TABLE_TOP_Y = (-0.2, 2.0), (7.0, 9.0), FLOOR_Y - 2.5
SBOX_X, SBOX_Y, SBOX_Z = (0.5, 1.4), (TABLE_TOP_Y - 1.3, TABLE_TOP_Y), (7.6, 8.4)
CARTON_X, CARTON_Y, CARTON_Z = (-3.4, -2.0), (FLOOR_Y - 1.6, FLOOR_Y), (11.0, 12.2)
BOOKCASE_X, BOOKCASE_Y, BOOKCASE_Z = (3.0, 5.0), (-3.5, FLOOR_Y), (14.0, 15.0)
DOOR_FRAME_X, DOOR_FRAME_Y = (-3.25, -0.75), (-4.3, FLOOR_Y)
DOOR_PANEL_X, DOOR_PANEL_Y = (-2.95, -1.05), (-4.0, FLOOR_Y)
BOARD_X, BOARD_Y = (1.0, 5.0), (-3.0, -0.5)

SCENE_OBJECTS = (
    SceneObject("waste bin", BIN_X, BIN_Y, BIN_Z, "front 11, sides 8, top 4",
                "nearest thing; bottom rows only"),
    SceneObject("crate", CRATE_X, CRATE_Y, CRATE_Z, "checks 13/6 (0.35 ft), sides 4, top 11",
                "textured box on the floor"),
    SceneObject("table", TABLE_X, (TABLE_TOP_Y, FLOOR_Y), TABLE_Z,
                "top edge 3, top 5, legs 1", "top 2.5 ft above the floor, four 0.2 ft legs"),
    SceneObject("striped box", SBOX_X, SBOX_Y, SBOX_Z,
                "vertical stripes 14/8 (0.2 ft), sides 7, top 12", "stands on the table"),
    SceneObject("carton", CARTON_X, CARTON_Y, CARTON_Z, "front 12 with a tape band 4, sides 9, top 13",
                "plain box on the floor"),
    SceneObject("bookcase", BOOKCASE_X, BOOKCASE_Y, BOOKCASE_Z,
                "binders 3..14, boards and frame 1, sides 6, top 8", "many vertical edges"),
    SceneObject("door", DOOR_FRAME_X, DOOR_FRAME_Y, (BACK_Z, BACK_Z),
                "frame 14, panel 3, knob 15", "in the back wall"),
    SceneObject("blackboard", BOARD_X, BOARD_Y, (BACK_Z, BACK_Z), "2", "on the back wall"),
    SceneObject("back wall", (LEFT_WALL_X, RIGHT_WALL_X), (CEILING_Y, FLOOR_Y), (BACK_Z, BACK_Z),
                "10, skirting 4", "plain"),
    SceneObject("left wall", (LEFT_WALL_X, LEFT_WALL_X), (CEILING_Y, FLOOR_Y), (0.0, BACK_Z),
                "7", "receding; visible beyond about 11 ft"),
    SceneObject("floor", (LEFT_WALL_X, RIGHT_WALL_X), (FLOOR_Y, FLOOR_Y), (0.0, BACK_Z),
                "5", "plain; visible beyond about 9 ft"),
    SceneObject("ceiling", (LEFT_WALL_X, RIGHT_WALL_X), (CEILING_Y, CEILING_Y), (0.0, BACK_Z),
                "12", "plain; visible beyond about 15 ft"),
)


def scene_quads() -> list[Quad]:
    """The laboratory as quads, nearest things first (order only matters for
    ties, i.e. markings on a wall listed before the wall)."""
    q: list[Quad] = []
    q += box("waste bin", BIN_X, BIN_Y, BIN_Z, flat(11), flat(8), flat(4))
    q += box("crate", CRATE_X, CRATE_Y, CRATE_Z,
             checks(13, 6, 0.35, 0, 1, origin=(CRATE_X[0], CRATE_Y[0])), flat(4), flat(11))
    q += box("striped box", SBOX_X, SBOX_Y, SBOX_Z,
             stripes(14, 8, 0.2, 0, origin=SBOX_X[0]), flat(7), flat(12))
    ty = TABLE_TOP_Y
    q += box("table top", TABLE_X, (ty, ty + 0.15), TABLE_Z, flat(3), flat(3), flat(5))
    for lx in (TABLE_X[0] + 0.05, TABLE_X[1] - 0.25):
        for lz in (TABLE_Z[0] + 0.05, TABLE_Z[1] - 0.25):
            q += box("table leg", (lx, lx + 0.2), (ty + 0.15, FLOOR_Y), (lz, lz + 0.2),
                     flat(1), flat(1), flat(1))
    tape = CARTON_X[0] + 0.5
    q += box("carton", CARTON_X, CARTON_Y, CARTON_Z,
             lambda X, Y, Z: np.where(np.abs(X - tape) < 0.12, 4.0, 12.0),
             flat(9), flat(13))
    q += box("bookcase", BOOKCASE_X, BOOKCASE_Y, BOOKCASE_Z, _bookcase_front, flat(6), flat(8))
    # Door in the back wall: light frame, dark panel, light knob (decals first).
    q.append(_quad("door knob", 2, BACK_Z, (-1.4, -1.25), (-0.05, 0.1), flat(15)))
    q.append(_quad("door panel", 2, BACK_Z, DOOR_PANEL_X, DOOR_PANEL_Y, flat(3)))
    q.append(_quad("door frame", 2, BACK_Z, DOOR_FRAME_X, DOOR_FRAME_Y, flat(14)))
    q.append(_quad("blackboard", 2, BACK_Z, BOARD_X, BOARD_Y, flat(2)))
    q.append(_quad("skirting", 2, BACK_Z, (LEFT_WALL_X, RIGHT_WALL_X),
                   (FLOOR_Y - 0.3, FLOOR_Y), flat(4)))
    q.append(_quad("back wall", 2, BACK_Z, (LEFT_WALL_X, RIGHT_WALL_X),
                   (CEILING_Y, FLOOR_Y), flat(10)))
    q.append(_quad("left wall", 0, LEFT_WALL_X, (CEILING_Y, FLOOR_Y), (0.0, BACK_Z), flat(7)))
    q.append(_quad("right wall", 0, RIGHT_WALL_X, (CEILING_Y, FLOOR_Y), (0.0, BACK_Z), flat(9)))
    q.append(_quad("floor", 1, FLOOR_Y, (LEFT_WALL_X, RIGHT_WALL_X), (0.0, BACK_Z), flat(5)))
    q.append(_quad("ceiling", 1, CEILING_Y, (LEFT_WALL_X, RIGHT_WALL_X), (0.0, BACK_Z),
                   flat(12)))
    return q


# --- rendering -----------------------------------------------------------------

# The ray tracer is world.render's (one tracer for every pose); the bundled pose is a camera
# at (cam_x, 0, 0) with the identity rotation, for which its arithmetic is exactly the plain
# (px, py, 1) ray cast this module did alone before (the shipped files are unchanged, checked
# in tests/test_scene.py and tests/test_world_render.py).  Imported here, not at the top,
# because world.render builds on this module's Quad and constants.

def render_view(cam_x: float, quads: list[Quad] | None = None) -> np.ndarray:
    """The noise-free 240x256 picture (float, supersampled mean grey 0..15)
    seen by a camera at X = ``cam_x``."""
    from world.render import render_camera
    quads = scene_quads() if quads is None else quads
    return render_camera(quads, np.array([cam_x, 0.0, 0.0]), np.eye(3), SUPERSAMPLE)


def true_range_128(cam_x: float = LEFT_X, quads: list[Quad] | None = None) -> np.ndarray:
    """Z (ft) through the centre of each pixel of the 120x128 picture of the
    camera at ``cam_x`` (the centre of the 2x2 block PRE condenses)."""
    from world.render import range_128
    quads = scene_quads() if quads is None else quads
    z, _ = range_128(quads, np.array([cam_x, 0.0, 0.0]), np.eye(3))
    return z


def true_disparity(range_ft) -> np.ndarray:
    """True disparity LOC1 - LOC2 in 128-px columns for range Z: ds*dv/Z."""
    return BASELINE_FT * FOCAL_128 / np.asarray(range_ft, dtype=np.float64)


def quantise(mean_grey: np.ndarray) -> np.ndarray:
    """Round a mean grey to the nearest of the 16 levels (halves round up)."""
    return np.clip(np.floor(mean_grey + 0.5), 0, 15).astype(np.uint8)


def add_noise(pic: np.ndarray, rng: np.random.Generator,
              fraction: float = NOISE_FRACTION) -> np.ndarray:
    """Move ``fraction`` of the pixels one grey level up or down (kept in 0..15)."""
    hit = rng.random(pic.shape) < fraction
    step = np.where(rng.random(pic.shape) < 0.5, -1, 1)
    out = pic.astype(np.int16) + np.where(hit, step, 0)
    return np.clip(out, 0, 15).astype(np.uint8)


@dataclass(frozen=True)
class Pair:
    """A rendered pair.  ``left``/``right``: 240x256 uint8 grey 0..15 (.VD);
    ``left_bi``/``right_bi``: their 120x128 condensed pictures (.BI);
    ``range_left``: Z ft per pixel of ``left_bi``; ``disparity_left``: true
    LOC1-LOC2 in 128-px columns per pixel of ``left_bi``."""
    left: np.ndarray
    right: np.ndarray
    left_bi: np.ndarray
    right_bi: np.ndarray
    range_left: np.ndarray
    disparity_left: np.ndarray

    def __iter__(self):        # allows  left, right, z, *rest = render_pair()
        return iter((self.left, self.right, self.range_left, self.left_bi,
                     self.right_bi, self.disparity_left))


def render_pair(seed: int = DEFAULT_SEED, noise: float = NOISE_FRACTION) -> Pair:
    """Render the laboratory pair.  Unpacks as
    ``(left256, right256, range_left128, left128, right128, disparity_left128)``."""
    quads = scene_quads()
    rng = np.random.default_rng(seed)
    left = add_noise(quantise(render_view(LEFT_X, quads)), rng, noise)
    right = add_noise(quantise(render_view(RIGHT_X, quads)), rng, noise)
    z = true_range_128(LEFT_X, quads).astype(np.float32)
    return Pair(left, right, condense(left), condense(right), z,
                true_disparity(z).astype(np.float32))


def make_files(outdir, seed: int = DEFAULT_SEED, pair: Pair | None = None) -> dict[str, Path]:
    """Write LAB-L.VD, LAB-R.VD, LAB-L.BI, LAB-R.BI and LAB-RANGE.npy to
    ``outdir`` (created if needed); return name -> path.  ``pair``: an
    already rendered pair (otherwise ``render_pair(seed)``)."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    pair = render_pair(seed) if pair is None else pair
    blobs = {
        "LAB-L.VD": encode_vd(pair.left),
        "LAB-R.VD": encode_vd(pair.right),
        "LAB-L.BI": encode_bi(pair.left_bi),
        "LAB-R.BI": encode_bi(pair.right_bi),
        "LAB-RANGE.npy": range_npy_bytes(pair.range_left),
    }
    paths = {}
    for name, data in blobs.items():
        p = out / name
        p.write_bytes(data)
        paths[name] = p
    return paths


def range_npy_bytes(z: np.ndarray) -> bytes:
    """The .npy bytes of a range array (float32, 120x128), written via np.save."""
    import io
    buf = io.BytesIO()
    np.save(buf, np.asarray(z, dtype=np.float32), allow_pickle=False)
    return buf.getvalue()


def bundled_path(name: str) -> Path:
    """Path of a file shipped in rig/data (e.g. ``"LAB-L.BI"``): the embedded
    default every command falls back to."""
    if name not in FILES:
        raise ValueError(f"no bundled file {name!r}; have {', '.join(FILES)}")
    return Path(__file__).resolve().parent / "data" / name


def bundled_range() -> np.ndarray:
    """The shipped truth: Z ft per pixel of LAB-L.BI (120x128 float32)."""
    return np.load(bundled_path("LAB-RANGE.npy"), allow_pickle=False)


def preview_png(pair: Pair, path) -> None:
    """Left and right 256x240 pictures side by side, enlarged 2x (nearest
    neighbour), grey level k drawn as 17*k; a 4-px mid-grey gap between them."""
    import cv2
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    gap = np.full((HEIGHT, 2), 8, dtype=np.uint8)
    both = np.hstack([pair.left, gap, pair.right]).astype(np.uint16) * 17
    big = np.repeat(np.repeat(both, 2, axis=0), 2, axis=1).astype(np.uint8)
    if not cv2.imwrite(str(path), big):
        raise OSError(f"could not write {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m rig.scene",
                                 description="Regenerate the bundled laboratory stereo pair.")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "data"),
                    help="output directory (default: rig/data)")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED)
    ap.add_argument("--preview", help="also write a PNG preview to this path")
    args = ap.parse_args(argv)
    pair = render_pair(args.seed)
    for p in make_files(args.out, pair=pair).values():
        print(p)
    if args.preview:
        preview_png(pair, args.preview)
        print(args.preview)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
