"""Free floor from what the picture shows: appearance-based obstacle detection
(Ulrich and Nourbakhsh, AAAI 2000; Horswill's Polly, 1993), a named option of
the closed loop (``DriveConfig.floor_eyes``), not the dissertation's method.

Edge-based eyes see nothing on a blank floor, but the floor is IN the picture:
the rig looks 25 deg down from 3 ft, so the bottom row of the 128x120 picture
meets the floor 3.2 ft ahead and the top row 25 ft ahead.  The floor's grey is
learned from the pixels whose rays end on floor the map already shows free
(:func:`training_mask`, accumulated look by look in a histogram,
:func:`floor_greys`).  A picture column whose greys, from the bottom row up to
row r, are all the floor's (:func:`floor_run`) shows the floor to that row's
distance d.  The ray to a floor point d away passes height H (1 - x / d) at
distance x, so an obstacle at least h tall anywhere on its floor trace from
d (1 - h / H) to d would have hidden that point; the column thus proves its
floor trace free from d_bottom (1 - h / H) — 2.33 ft for h = 0.8 ft, H = 3 ft,
the near limit of every look — to the run's far end (:func:`floor_proof`).

The hazard is a surface of the floor's grey: a box face of that grey shows as
floor, its run goes on up the face, and the proof runs into the box.  The
loop therefore carves such a proof only under the safety rules of its other
carving (docs/planner.md, "Carving by assumption"): never past a cell any look
has hit, and no farther than the floor scan's own bound of that column (its
hit, the near end of its neighbours' error bound, or the blank-column reach).

``bound`` (:func:`bound_by_floor`): the picture only bounds the blank-column
assumption, it proves nothing.  A blank column's assumed sight line ends
where that column's floor run ends: whatever stands on the floor there (a
box face, a wall's skirting) is not the floor's grey, and its foot is the
run's top.  Until the floor's grey is learned the picture's bottom rows
stand for it (:func:`nearest_greys`; ``stand_in="majority"``: only a grey
holding most of them); a face of the floor's grey runs on up the picture and
bounds nothing: the same hazard, never more carving.  But
with the floor plan's walls known (:func:`past_walls`), a run that goes on
past the wall's foot is not the floor's, and its column assumes nothing.

``bound-add``: ``bound``, and once the floor's grey is learned (never from
the stand-in) its proof carved too, under the rules above and no farther
than :func:`floor_end`: a column whose floor shows no end (a run up to the
top row, or past the walls) proves nothing.  Under the loop's low sight
lines a point high on a wall proves its line only near the wall; the floor
in view proves the floor before it.

A wall of a floor grey ends no run either, and the floor before it stays
unproven (room 341).  On a tiled floor the tiles tell the wall from a face:
both stand past the last tile seen, so ``wall_runs="texture"`` (the loop's
default, :func:`texture_end`) proves such a column's floor to there.

``veto`` (:func:`vetoed`): a located point whose floor point just behind it
shows inside the floor runs of its column and both neighbours is contradicted
by the picture (an obstacle standing there would hide that floor) and is left
out of the floor scan.  Measured (docs/planner.md): it also leaves out true
points on faces of the floor's grey, and it is not safe.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from diskfmt.jit import jit
from .floormap import FREE, FLOOR_Y, FloorMap

ROWS, COLS = 120, 128
FOCAL, CX, CY = 180.0, 64.0, 60.0          # the 128x120 picture (planner.perception)
GREYS = 16
MIN_SAMPLES = 200                          # floor pixels before the floor's grey is believed
MIN_SHARE = 0.1                            # a grey level is the floor's with this share of them
# what the bottom rows lend the floor before its grey is learned (DriveConfig.stand_in):
# "tenth": every grey with MIN_SHARE of them (the default); "majority": only a grey
# with more than half of them, none when no grey has (room 256: a box face's grey 4
# held 10-50 % of the bottom rows at look 1 and passed for floor; docs/planner.md)
STAND_INS = {"tenth": MIN_SHARE, "majority": 0.5 + 1e-9}
BOUNDING = ("bound", "bound-add")          # the floor_eyes values whose picture bounds the assumption


def reads_floor(floor_eyes: str, depth_eyes: bool) -> bool:
    """Whether a look reads the floor's grey from its picture under ``floor_eyes``
    (``DriveConfig.floor_eyes``): never under ``"off"``, nor with the depth eyes
    (``depth_eyes``) under a bounding value: they assume nothing, so there is
    nothing for the picture to bound."""
    return floor_eyes != "off" and not (depth_eyes and floor_eyes in BOUNDING)


@dataclass
class FloorRays:
    """Where each pixel's ray meets the floor plane."""
    x: np.ndarray              # (120, 128) room X of the floor point (NaN: the ray does not go down)
    z: np.ndarray              # (120, 128) room Z
    dist: np.ndarray           # (120, 128) horizontal distance from the camera, ft (inf: none)
    origin: np.ndarray         # (3,) the camera centre
    height: float              # the camera above the floor, ft
    R: np.ndarray              # (3, 3) the camera's axes in room coordinates


def floor_rays(R, origin, floor_y: float = FLOOR_Y) -> FloorRays:
    """The floor point of every pixel's ray through its centre (room Y down,
    the floor at ``floor_y``; ``R`` the camera's axes in room coordinates)."""
    R = np.asarray(R, float)
    origin = np.asarray(origin, float)
    u = (np.arange(COLS) + 0.5 - CX) / FOCAL
    v = (np.arange(ROWS) + 0.5 - CY) / FOCAL
    d = R[:, 0, None, None] * u[None, None, :] + R[:, 1, None, None] * v[None, :, None] \
        + R[:, 2, None, None]
    h = floor_y - origin[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d[1] > 1e-9, h / d[1], np.nan)
    x = origin[0] + t * d[0]
    z = origin[2] + t * d[2]
    dist = np.hypot(x - origin[0], z - origin[2])
    dist = np.where(np.isfinite(dist), dist, np.inf)
    return FloorRays(x, z, dist, origin, float(h), R)


def training_mask(rays: FloorRays, known: FloorMap, lowest_ft: float,
                  max_ft: float = 12.0, whole_trace: bool = False) -> np.ndarray:
    """The pixels whose ray ends on floor the map shows free AND whose whole
    stretch that an obstacle ``lowest_ft`` tall could stand on and hide it
    (from d (1 - h / H) to d) is free too: such a pixel shows the floor.
    A taller obstacle hides a longer stretch (one as tall as the camera, all
    of it): ``whole_trace`` asks the floor free along the ray's whole floor
    trace from the camera's foot, sampled every half cell, of every second
    pixel of every second row (a quarter of the work; the floor's greys are
    a histogram's shares)."""
    ok, steps = training_traces(rays, known.cell, lowest_ft, max_ft, whole_trace)
    idx = np.flatnonzero(ok)
    free = np.zeros(len(idx), bool)
    _trace_free(float(rays.origin[0]), float(rays.origin[2]), rays.x.ravel(), rays.z.ravel(),
                idx, np.asarray(steps, dtype=np.float64), known.cells, float(known.x0),
                float(known.z0), float(known.cell), FREE, free)
    out = np.zeros(ok.size, bool)
    out[idx[free]] = True
    return out.reshape(ok.shape)


def training_traces(rays: FloorRays, cell: float, lowest_ft: float, max_ft: float,
                    whole_trace: bool):
    """What :func:`training_mask` tests: (the pixels it may keep, (120, 128)
    bool; the steps s of each one's trace o + s (f - o), f its floor point)."""
    frac = 1.0 - lowest_ft / rays.height
    ok = np.isfinite(rays.dist) & (rays.dist <= max_ft)
    steps = (frac, (1 + frac) / 2, 1.0)
    if whole_trace:
        steps = np.linspace(0.0, 1.0, int(np.ceil(max_ft / (cell / 2))) + 1)
        sub = np.zeros_like(ok)
        sub[::2, ::2] = True
        ok &= sub
    return ok, steps


@jit
def _trace_free(ox, oz, fx, fz, idx, steps, cells, x0, z0, cell, free_value, out):
    """``out[n]``: whether every point ``o + s (f - o)`` (s in ``steps``) of
    pixel ``idx[n]``'s floor trace lies in a FREE cell of ``cells`` (a point
    off the map, or not finite, in none).  A pixel stops at its first cell not free: compiled,
    pixel by pixel, instead of a pass over every pixel still in per step
    (up to 97 steps a look)."""
    for n in range(len(idx)):
        p = idx[n]
        keep = True
        for s in steps:
            i = np.floor((oz + s * (fz[p] - oz) - z0) / cell)
            j = np.floor((ox + s * (fx[p] - ox) - x0) / cell)
            if not (np.isfinite(i) and np.isfinite(j)):
                keep = False
                break
            ii, jj = int(i), int(j)
            if (ii < 0 or jj < 0 or ii >= cells.shape[0] or jj >= cells.shape[1]
                    or cells[ii, jj] != free_value):
                keep = False
                break
        out[n] = keep


def floor_greys(hist, min_samples: int = MIN_SAMPLES, min_share: float = MIN_SHARE):
    """(16,) bool: the grey levels of the floor, from a histogram of the greys
    of pixels known to show floor; None until ``min_samples`` were seen."""
    hist = np.asarray(hist, float)
    total = hist.sum()
    if total < min_samples:
        return None
    return hist >= min_share * total


def nearest_greys(picture, rows: int = 4, min_share: float = MIN_SHARE) -> np.ndarray:
    """(16,) bool: the greys of the picture's bottom ``rows`` (the nearest
    floor in view, 3.2-3.5 ft ahead of the rig's camera): what ``bound``
    takes for the floor's grey until the map has shown enough floor free.
    A box standing there lends its own grey instead, and then bounds less:
    never more carving than without the floor eyes.  ``min_share``
    (:data:`STAND_INS`) sets how much of the bottom rows a grey must hold;
    where none holds it, no grey stands in and every column's run is empty
    (the assumption bounded to nothing)."""
    pic = np.asarray(picture)[-rows:]
    hist = np.bincount(np.clip(pic, 0, GREYS - 1).ravel().astype(int), minlength=GREYS)
    return floor_greys(hist, min_samples=0, min_share=min_share)


def floor_run(picture, greys, bridge: bool = False, blend: bool = False) -> np.ndarray:
    """(128,) int: per column the topmost row r such that rows r - 1..119
    all show a floor grey (120: fewer than two rows do).  The run's own top
    pixel is left out: the condensed picture averages 2x2 pixels, so the
    pixel where the floor meets what stands on it may round to the floor's
    grey while its centre shows the other surface.  ``bridge`` counts a
    lone pixel of another grey between two of the floor's (or on the bottom
    row under one) as floor: the sensor noise moves single pixels, and what
    stands on the floor shows as more than one row.  ``blend`` counts as
    floor a pixel whose grey lies strictly between those of the floor pixels
    right above and below it: a tile's edge, which the 2x2 condensing
    averages (greys g and g + 2 meet in a row of g + 1, under a tenth of the
    floor's pixels and so not learned); a face of that grey is more than a
    row and has no tile above it."""
    pic = np.asarray(picture)
    is_floor = np.asarray(greys, bool)[np.clip(pic, 0, GREYS - 1)]
    if blend:
        g = np.clip(pic, 0, GREYS - 1).astype(int)
        up = np.full(g.shape, -1)
        down = np.full(g.shape, -1)
        up[1:] = np.where(is_floor[:-1], g[:-1], -1)
        down[:-1] = np.where(is_floor[1:], g[1:], -1)
        lo, hi = np.minimum(up, down), np.maximum(up, down)
        is_floor = is_floor | ((lo >= 0) & (lo < g) & (g < hi))
    if bridge:
        above = np.vstack([np.zeros((1, pic.shape[1]), bool), is_floor[:-1]])
        below = np.vstack([is_floor[1:], np.ones((1, pic.shape[1]), bool)])
        is_floor = is_floor | (above & below)
    below = np.cumprod(is_floor[::-1], axis=0)[::-1]          # rows r..119 all floor
    return np.minimum(ROWS - below.sum(0) + 1, ROWS)


def run_reach(rays: FloorRays, top: np.ndarray) -> np.ndarray:
    """(128,) horizontal distance (ft) each column shows the floor to: its
    run's top row's floor point (0 where the run is empty)."""
    cols = np.arange(COLS)
    out = np.zeros(COLS)
    has = top < ROWS
    out[has] = rays.dist[top[has], cols[has]]
    return np.where(np.isfinite(out), out, 0.0)


SHADOW_FT = 2.0          # free_cells="shadows": how far past a run's end its shadow is kept


def run_shadows(rays: FloorRays, top: np.ndarray, res: float, lowest_ft: float,
                depth_ft: float = SHADOW_FT) -> np.ndarray:
    """(N, 3) samples, half a cell apart, of each column's sight line past
    where its floor run ends below the picture's top row (something not of
    the floor's grey stands there: its foot; the floor point of the pixel
    above the run, which :func:`floor_run` leaves out; where the column
    shows no floor at all, it stands nearer than the bottom row's floor,
    and the shadow starts where the neighbours' proofs do, at the near limit
    of a ``lowest_ft`` obstacle, :func:`floor_proof`), ``depth_ft`` past that
    end, at the camera's height as the proof's samples are.  Under
    ``DriveConfig.free_cells="shadows"`` no proof or assumed line of the look
    frees a cell they reach: what stands at a run's foot hides the floor
    behind it, and a neighbouring column's floor seen past its edge is a
    sliver of such a cell (room 230 under ``reverse``: the floor seen just
    beside a box's front, nearer than the bottom row's floor, freed the cells
    along its hidden side face, three quarters box)."""
    cols = np.flatnonzero(top > 1)
    rows = top[cols] - 1                     # (floor_run's top is at most ROWS)
    o = rays.origin
    dx, dz = rays.x[rows, cols] - o[0], rays.z[rows, cols] - o[2]
    d = np.hypot(dx, dz)
    start = np.where(top[cols] == ROWS, 1.0 - lowest_ft / rays.height, 1.0) * d
    ok = np.isfinite(d) & (d > 0)
    dx, dz, d, start = dx[ok], dz[ok], d[ok], start[ok]
    k = np.arange(int((d + depth_ft - start).max(initial=0.0) / (res / 2)) + 1)
    along = start[:, None] + k[None, :] * (res / 2)
    keep = along <= (d + depth_ft)[:, None]
    t = (along / d[:, None])[keep]
    dx = np.broadcast_to(dx[:, None], along.shape)[keep]
    dz = np.broadcast_to(dz[:, None], along.shape)[keep]
    return np.column_stack([o[0] + dx * t, np.full(t.size, o[1]), o[2] + dz * t])


def floor_proof(rays: FloorRays, top: np.ndarray, clip_ft: np.ndarray, lowest_ft: float,
                res: float, row_step: int = 4, lead_in: bool = False):
    """The proven floor of a look as sight-line samples: for every column's
    run (rows ``top[c]``..119) the rays of every ``row_step``-th row and the
    top one, each from d (1 - h / H) to d, cut at ``clip_ft[c]`` (horizontal
    ft from the camera).  Returns (samples (N, 3) at the camera's height, the
    ray of each sample, its distance from the camera) or None.

    ``lead_in``: each ray's samples also run back from d (1 - h / H) toward
    the camera at the same spacing, and a fourth item marks the samples
    that prove (the trace); the others only lead in, for
    :func:`keep_before_hit` to stop a trace that lies past a hit."""
    frac = 1.0 - lowest_ft / rays.height
    rr, cc = proof_rows(top, row_step)
    if not len(rr):
        return None
    d = rays.dist[rr, cc]
    far = np.minimum(d, clip_ft[cc]) - res          # stop a cell short, as a sight line
    near = frac * d
    n = np.where(far > near, np.floor((far - near) / (res / 2)).astype(int) + 1, 0)
    n[~np.isfinite(d)] = 0
    if n.sum() == 0:
        return None
    lead = np.where(n > 0, np.floor(near / (res / 2)).astype(int), 0) if lead_in \
        else np.zeros(len(n), int)
    ray, k = ray_steps(lead, n)
    dist = near[ray] + k * (res / 2)
    o = rays.origin
    ux = (rays.x[rr, cc] - o[0]) / d
    uz = (rays.z[rr, cc] - o[2]) / d
    pts = np.column_stack([o[0] + dist * ux[ray], np.full(len(dist), o[1]),
                           o[2] + dist * uz[ray]])
    return pts, ray, dist, k >= 0


def proof_rows(top, row_step: int):
    """(rows, columns) of :func:`floor_proof`'s rays: column by column (those
    with a run, ``top`` < 120), its rows top, top + row_step, ... and the
    bottom one, each once, in order."""
    below = np.arange(ROWS)[None, :] - np.asarray(top)[:, None]
    cc, rr = np.nonzero((below >= 0) & ((below % row_step == 0)
                                         | (np.arange(ROWS) == ROWS - 1)[None, :]))
    return rr, cc


def ray_steps(lead, n):
    """(the ray of each sample, its step): ray q's steps -lead[q] .. n[q] - 1,
    ray after ray."""
    count = lead + n
    ray = np.repeat(np.arange(len(n)), count)
    first = np.cumsum(count) - count
    return ray, np.arange(len(ray)) - first[ray] - lead[ray]


def _from_camera(points, rays: FloorRays):
    """The located points (rig.scan Points) as arrays: (0-based column, scan
    line, range error, (N, 3) offset from the camera in room axes, its
    horizontal length); the camera's axes are
    :func:`planner.perception.camera_points`'."""
    from .perception import camera_points
    cam, _, line, loc1, ep = camera_points(points)
    w = cam @ rays.R.T
    return np.rint(loc1).astype(int) - 1, line, ep, w, np.hypot(w[:, 0], w[:, 2])


def vetoed(points, rays: FloorRays, top: np.ndarray, margin_ft: float,
           floor_y: float = FLOOR_Y) -> np.ndarray:
    """Mask of located points (rig.scan Points) the picture contradicts.  An
    obstacle standing where a point says, d ft away, hides the floor just
    behind it (from d to d H / (H - h) at least); so when the floor point
    ``margin_ft`` plus the point's range error behind it, on its bearing,
    shows in the picture inside the floor runs of its column and of both
    neighbours (one of those is the obstacle's own side at a silhouette
    edge), nothing stands there: a false match (or a surface of the floor's
    grey, the hazard)."""
    n = len(points)
    if not n:
        return np.zeros(0, bool)
    _, _, ep, w, horiz = _from_camera(points, rays)
    behind = (horiz + ep + margin_ft) / np.maximum(horiz, 1e-9)
    q = np.stack([w[:, 0] * behind, np.full(n, floor_y - rays.origin[1]),
                  w[:, 2] * behind], 1)                   # the floor point behind, from the camera
    qc = q @ rays.R                                       # in the camera's axes
    out = np.zeros(n, bool)
    ahead = qc[:, 2] > 1e-6
    col = np.full(n, -1)
    row = np.full(n, -1)
    col[ahead] = np.floor(qc[ahead, 0] / qc[ahead, 2] * FOCAL + CX).astype(int)
    row[ahead] = np.floor(qc[ahead, 1] / qc[ahead, 2] * FOCAL + CY).astype(int)
    seen = ahead & (row >= 0) & (row < ROWS) & (col >= 1) & (col < COLS - 1)
    k = np.flatnonzero(seen)
    if len(k):
        r, cc = row[k], col[k]
        out[k] = (r >= top[cc - 1]) & (r >= top[cc]) & (r >= top[cc + 1])
    return out


def end_slack(rays: FloorRays, heading_sd: float = 0.0) -> np.ndarray:
    """(120, 128) how far (ft) a floor run's end at each pixel may be off: the
    floor footprint of the rows either side of it (inf at the last row
    that still meets the floor) and twice the heading's standard deviation
    ``heading_sd`` (rad) times its distance."""
    d = rays.dist
    rows = np.arange(ROWS)
    up, down = d[np.maximum(rows - 1, 0)], d[np.minimum(rows + 1, ROWS - 1)]
    with np.errstate(invalid="ignore"):
        return np.where(np.isfinite(up), up - down, np.inf) + 2.0 * heading_sd * d


def past_walls(rays: FloorRays, top: np.ndarray, within, heading_sd: float = 0.0) -> np.ndarray:
    """(128,) bool: the columns whose floor run ends outside ``within``
    ((x0, x1, z0, z1): the floor plan's walls grown by the estimate's x, z
    uncertainty), by more than the run's end is known to: a row's floor
    footprint either side of it (the far floor is a fraction of a foot per
    row) and twice the heading's standard deviation ``heading_sd`` (rad)
    times its distance.  The floor ends at a wall's foot, so such a run went
    on up a surface of the floor's grey (a box face, or a wall of that grey
    or a door): it shows no floor's end, and ``bound`` lets it assume
    nothing."""
    cols = np.arange(COLS)
    has = top < ROWS
    r = np.minimum(top, ROWS - 1)
    x = np.where(has, rays.x[r, cols], np.nan)
    z = np.where(has, rays.z[r, cols], np.nan)
    slack = end_slack(rays, heading_sd)[r, cols]
    x0, x1, z0, z1 = within
    with np.errstate(invalid="ignore"):
        inside = (x > x0 - slack) & (x < x1 + slack) & (z > z0 - slack) & (z < z1 + slack)
    return has & ~inside       # (NaN, no floor point: outside)


def no_end(rays: FloorRays, top: np.ndarray, within=None, heading_sd: float = 0.0):
    """The columns whose floor run shows no end, as two (128,) masks: the run goes
    on to the picture's top row, and (with the plan's walls ``within``) it ends
    below it but past the walls (:func:`past_walls`)."""
    to_top = top <= 1
    past = past_walls(rays, top, within, heading_sd) & ~to_top if within is not None \
        else np.zeros(COLS, bool)
    return to_top, past


def floor_end(rays: FloorRays, top: np.ndarray, within=None,
              heading_sd: float = 0.0, wall_runs: str = "none",
              texture: np.ndarray | None = None) -> np.ndarray:
    """(128,) how far each column's floor in view shows its end
    (:func:`run_reach`), 0 where it shows none: a run up to the picture's
    top row (the floor, or a face of its grey, goes on out of the picture)
    or, with the plan's walls ``within``, one that ends past them
    (:func:`past_walls`, ``heading_sd`` the estimate's).  ``wall_runs="foot"``
    (a named option, not 1985): such a run shows its end at the walls' foot
    instead (:func:`wall_foot_reach`), as a wall of the floor's grey would
    show it.  A box face of that grey it cannot tell from such a wall, and
    it proves the floor through the box (five rooms of seeds 1-900 collide,
    docs/planner.md).  ``"past"``: only a run that ends past the walls
    (below the picture's top row) does.  ``"texture"`` (not 1985; the
    loop's default): such a run shows its end where the floor's texture is
    last seen in it (``texture``, :func:`texture_end`; no farther than the
    walls' foot): a face of a tile's grey has none, a flat floor none
    either."""
    reach = run_reach(rays, top)
    to_top, past = no_end(rays, top, within, heading_sd)
    reach[to_top | past] = 0.0
    if wall_runs == "texture" and texture is not None:
        shown = (to_top | past) & (texture < ROWS)
        cols = np.flatnonzero(shown)
        reach[cols] = rays.dist[texture[cols], cols]
        if within is not None:
            reach[cols] = np.minimum(reach[cols], wall_foot_reach(rays, within, heading_sd)[cols])
    elif wall_runs in ("foot", "past") and within is not None:
        foot = past | to_top if wall_runs == "foot" else past
        reach[foot] = wall_foot_reach(rays, within, heading_sd)[foot]
    return reach


def is_tiled(greys, step: int = 2) -> bool:
    """Whether the learned floor greys ``greys`` ((16,) bool) are a tiled floor's: two
    at least ``step`` levels apart (g and g + 2).  A flat floor learns one."""
    learned = np.flatnonzero(greys)
    return len(learned) >= 2 and learned[-1] - learned[0] >= step


def texture_end(picture, greys, top: np.ndarray, rows: int = 3, step: int = 2) -> np.ndarray:
    """(128,) per column the nearest row of the farthest window of ``rows``
    rows inside its floor run (rows ``top[c]``..119) that holds two floor
    greys ``greys`` at least ``step`` levels apart: the floor's texture (a
    tiled floor's two greys, g and g + 2) is seen to there.  120 where the
    run shows none.  A flat floor shows none: its learned greys are one (the
    sensor noise moves under 1 % of its pixels a level, far below
    :data:`MIN_SHARE`), and so is a flat face of a floor grey.  Whatever
    stands on the floor with one of its greys ends the texture at its foot,
    so the floor is the floor to there."""
    if not is_tiled(greys, step):
        return np.full(COLS, ROWS)            # (a flat floor: no window can hold both)
    pic = np.clip(np.asarray(picture), 0, GREYS - 1).astype(float)
    is_floor = np.asarray(greys, bool)[pic.astype(int)]
    lo = np.where(is_floor, pic, np.inf)
    hi = np.where(is_floor, pic, -np.inf)
    win_lo = np.lib.stride_tricks.sliding_window_view(lo, rows, axis=0).min(-1)
    win_hi = np.lib.stride_tricks.sliding_window_view(hi, rows, axis=0).max(-1)
    starts = np.arange(ROWS - rows + 1)[:, None]
    seen = (win_hi - win_lo >= step) & (starts >= np.asarray(top)[None, :])
    first = np.where(seen.any(0), seen.argmax(0), ROWS)
    return np.where(first < ROWS, first + rows - 1, ROWS)


def wall_foot_reach(rays: FloorRays, within, heading_sd: float = 0.0) -> np.ndarray:
    """(128,) the farthest floor distance (ft) of each column whose floor
    point lies inside ``within`` (the plan's walls less the estimate's
    growth) by more than a run's end may be off (:func:`end_slack`).  0
    where none does."""
    d = rays.dist
    slack = end_slack(rays, heading_sd)
    with np.errstate(invalid="ignore"):
        x0, x1, z0, z1 = within
        inside = np.isfinite(d) & (rays.x > x0 + slack) & (rays.x < x1 - slack) & \
            (rays.z > z0 + slack) & (rays.z < z1 - slack)
    return np.where(inside, d, 0.0).max(0)


def raised_ends(points, rays: FloorRays, top: np.ndarray, reach: np.ndarray,
                rows: int = 3, min_points: int = 3, min_range_ft: float = 0.0) -> np.ndarray:
    """(128,) the floor ends ``reach`` (:func:`floor_end`) each cut where a
    located point (rig.scan Points) in its column's floor run (from ``rows``
    rows above its top down, in the column or a neighbour) stands clearly
    nearer than the floor its pixel would show (by more than the point's
    range error and a row's floor footprint): the pixel shows a surface off
    the floor that has the floor's grey, a box face the run went on up to a
    mark on it (room 34) or a box top of the floor's grey (room 278).  Such
    a column proves the floor only to the point, less its range error.  A
    point on the floor (a tile's edge, an obstacle's foot) locates where its
    pixel's floor lies, within those errors, and cuts nothing.  The matcher
    locates few of an edge's scan lines, so where the run's top goes on
    across columns (no jump of more than ``rows`` rows) and ``min_points``
    points on it are raised, it is taken for one edge at one height, as a box
    top's edge is, and all its ends are cut by the least share of their
    floor distance (room 566: a 0.99 ft box whose sides have the floor's
    grey).  Points nearer than ``min_range_ft`` (the loop passes the floor
    scan's, ``DriveConfig.min_range_ft``: nearer, many are false matches) are
    not used."""
    reach = np.array(reach, float)
    points = [p for p in points if p.dp >= min_range_ft]
    if not len(points):
        return reach
    c, line, ep, _, horiz = _from_camera(points, rays)
    r = np.clip(line, 1, ROWS - 2)
    share = np.full(COLS, np.inf)
    count = np.zeros(COLS, int)                   # raised points in their own column
    for k in range(-1, 2):
        cc = c + k
        ok = (cc >= 0) & (cc < COLS)
        cc, i = cc[ok], np.flatnonzero(ok)
        floor_d = rays.dist[r[i], cc]
        with np.errstate(invalid="ignore"):
            slack = np.abs(rays.dist[r[i] - 1, cc] - rays.dist[r[i] + 1, cc])
        slack = np.where(np.isfinite(slack), slack, np.inf)
        in_run = (top[cc] < ROWS) & (line[i] >= top[cc] - rows)
        raised = in_run & (horiz[i] + ep[i] + slack < floor_d)
        np.minimum.at(reach, cc[raised], np.maximum(horiz[i][raised] - ep[i][raised], 0.0))
        # how far below its floor each raised point stands, (H - h) / H of it
        np.minimum.at(share, cc[raised], (horiz[i][raised] - ep[i][raised]) / floor_d[raised])
        if k == 0:
            np.add.at(count, cc[raised], 1)
    # the run's top goes on from raised columns to their neighbours without a point (the
    # matcher locates few of an edge's scan lines): the same edge, as high, as a box top's
    # edge is (room 566).  An edge: the columns with an end, no jump of more than ``rows``
    # rows between neighbours; carried only where ``min_points`` points on it are raised,
    # so one false match does not cut a whole floor end
    cols = np.arange(COLS)
    end_d = np.where(top < ROWS, rays.dist[np.minimum(top, ROWS - 1), cols], 0.0)
    ends = (top < ROWS) & (reach > 0) & np.isfinite(end_d)
    jump = np.abs(np.diff(top.astype(int))) > rows
    cut = np.flatnonzero(~ends[:-1] | ~ends[1:] | jump) + 1     # edges split here
    for seg in np.split(cols, cut):
        seg = seg[ends[seg]]
        raised = np.isfinite(share[seg])
        if count[seg].sum() >= min_points:
            reach[seg] = np.minimum(reach[seg], share[seg][raised].min() * end_d[seg])
    return reach


def beside_points(points, rays: FloorRays, reach: np.ndarray, columns: np.ndarray,
                  width_ft: float, min_range_ft: float = 0.0) -> np.ndarray:
    """(128,) the floor ends ``reach``, in the columns ``columns`` ((128,) bool),
    each cut to the nearest located point (rig.scan Points, ranges from
    ``min_range_ft``) standing within ``width_ft`` sideways of the column (the
    camera's x at the point's range), less the point's range error.
    ``wall_runs="flat-foot"`` (not 1985): a run of a flat floor's grey up to
    the picture's top row may be a box face of that grey, whose edges the eyes
    locate only at its sides; no face is wider than ``width_ft``, so beside a
    point the run may stand on a face, and away from every point it does not."""
    reach = np.array(reach, float)
    points = [p for p in points if p.dp >= min_range_ft]
    if not len(points) or not np.any(columns):
        return reach
    c, _line, ep, _, horiz = _from_camera(points, rays)
    half = np.ceil(width_ft * FOCAL / np.array([p.dp for p in points], float)).astype(int)
    near = np.maximum(horiz - ep, 0.0)
    cut = np.full(COLS, np.inf)
    for k in range(len(points)):
        a, b = max(c[k] - half[k], 0), max(min(c[k] + half[k] + 1, COLS), 0)
        cut[a:b] = np.minimum(cut[a:b], near[k])
    return np.where(columns, np.minimum(reach, cut), reach)


@dataclass
class LookEnds:
    """One look's floor ends, kept for :func:`raised_by_motion`: the camera's
    floor position (x, z), the floor points (N, 2) where its columns' runs
    end at a grey change, and a test of which floor points (M, 2) its floor
    in view proved ((M,) bool)."""
    origin: np.ndarray
    ends: np.ndarray
    proved: object


def raised_by_motion(ends, origin, earlier, normals=None, tol_ft: float = 0.2,
                     min_move_ft: float = 0.9, min_shift_ft: float = 0.35, k_range=(1.2, 4.0),
                     agree: float = 0.1) -> np.ndarray:
    """(N,) for each floor end ``ends`` ((N, 2), where this look's runs end
    at a grey change, seen from the camera's floor position ``origin``) the
    factor k by which it lies beyond the edge that made it (NaN: on the
    floor, or not known).

    A run that ends at an edge h above the floor (a box top's edge over a
    face of the floor's grey) shows its end on the floor beyond the edge:
    seen from C it projects the edge's point P to E = C + k (P - C), k =
    H / (H - h).  Seen from C' the same point projects to E' = E + (k - 1)
    (C - C'): the end moves with the camera by (k - 1) times its move, where
    an end on the floor (k = 1) stays put.  Along an edge the move shows
    nothing, so with ``normals`` ((N, 2), the normal of the run ends' line
    at each E) only the move across the edge counts.

    An earlier look of ``earlier`` (:class:`LookEnds`), taken at least
    ``min_move_ft`` away (across the edge, given ``normals``), that proved
    the floor at E and showed no end within ``tol_ft`` of it, offers as
    candidates its ends within ``tol_ft`` of the line E + t (C - C'), t =
    k - 1 for k in ``k_range``, at least ``min_shift_ft`` from E; none if
    they string along that line over more than 3 ``tol_ft`` (an edge along
    the camera's move fits any k).  On a tiled floor the next tile's edge
    may lie on that line by chance, so E is raised only where two earlier
    looks, taken at least ``min_move_ft`` / 2 apart (not one place's looks
    turning), offer k within ``agree`` of each other (the pair that agrees
    best; k their mean).  The edge's point is then C + (E - C) / k."""
    ends = np.asarray(ends, float).reshape(-1, 2)
    c = np.asarray(origin, float)
    offers, places = [], []                 # per earlier look: (N, M) k offered (NaN none), where
    for look in earlier:
        move = c - np.asarray(look.origin, float)
        span = float(np.hypot(*move))
        theirs = np.asarray(look.ends, float).reshape(-1, 2)
        if span < min_move_ft or not len(theirs) or not len(ends):
            continue
        across = np.abs(np.asarray(normals, float) @ move) if normals is not None \
            else np.full(len(ends), span)
        rel = theirs[None, :, :] - ends[:, None, :]                 # (N, M) their ends from each E
        apart = np.hypot(rel[..., 0], rel[..., 1]).min(1) > tol_ft    # no end of theirs at E
        t = (rel @ move) / span ** 2                                  # along E + t (C - C')
        off = np.hypot(*np.moveaxis(rel - t[..., None] * move, -1, 0))
        fits = (off <= tol_ft) & (t >= k_range[0] - 1.0) & (t <= k_range[1] - 1.0) & \
            (t * span >= min_shift_ft)
        fits &= (apart & (across >= min_move_ft) & np.asarray(look.proved(ends), bool))[:, None]
        # ends of theirs strung along the line (an edge the camera moved along) fit any k
        along = np.where(fits, t * span, np.nan)
        with np.errstate(invalid="ignore"):
            strung = np.nanmax(along, 1, initial=-np.inf) - np.nanmin(along, 1, initial=np.inf) \
                > 3.0 * tol_ft
        fits &= ~strung[:, None]
        offers.append(np.where(fits, 1.0 + t, np.nan))
        places.append(np.asarray(look.origin, float))
    out = np.full(len(ends), np.nan)
    if len(offers) < 2:
        return out
    offered = np.array([np.isfinite(o).any(1) for o in offers])
    for i in np.flatnonzero(offered.sum(0) >= 2):
        best = np.inf
        for a in range(len(offers)):
            ka = offers[a][i][np.isfinite(offers[a][i])]
            for b in range(a + 1, len(offers)):
                kb = offers[b][i][np.isfinite(offers[b][i])]
                if not len(ka) or not len(kb) or \
                        np.hypot(*(places[a] - places[b])) < min_move_ft / 2.0:
                    continue
                gap = np.abs(ka[:, None] - kb[None, :]) / np.maximum(ka[:, None], kb[None, :])
                j = np.unravel_index(np.argmin(gap), gap.shape)
                if gap[j] <= agree and gap[j] < best:
                    best, out[i] = gap[j], (ka[j[0]] + kb[j[1]]) / 2.0
    return out


def raised_columns(ends, origin, earlier, min_columns: int = 3, gap: int = 2,
                   agree: float = 0.1) -> np.ndarray:
    """(128,) per column the factor k of :func:`raised_by_motion` for its
    floor end ``ends[c]`` ((128, 2), NaN where the column's run shows no end
    at a grey change), NaN where it is not raised.  A box top's edge spans
    columns, so a raised column counts only with another within ``gap``
    columns whose k agrees within ``agree`` (a lone one is a chance match),
    and the look's raised columns only when ``min_columns`` are left.  The
    normal of each end's line, along which the move counts, is taken from
    the first to the last end within ``gap`` columns (a column without
    another there is not judged)."""
    ends = np.asarray(ends, float).reshape(-1, 2)
    k = np.full(len(ends), np.nan)
    has = np.isfinite(ends[:, 0])
    # each end's line: from the first to the last end within ``gap`` columns of it
    n = len(ends)
    cols = np.arange(n)
    first, last = np.full(n, -1), np.full(n, -1)
    for off in range(gap, -gap - 1, -1):
        c = cols + off
        ok = (c >= 0) & (c < n)
        ok[ok] = has[c[ok]]
        first = np.where(ok, c, first)
        last = np.where(ok & (last < 0), c, last)
    along = ends[np.maximum(last, 0)] - ends[np.maximum(first, 0)]
    length = np.hypot(along[:, 0], along[:, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        normals = np.column_stack([-along[:, 1], along[:, 0]]) / length[:, None]
    has &= (first >= 0) & (last > first) & (length > 0)
    k[has] = raised_by_motion(ends[has], origin, earlier, normals[has], agree=agree)
    idx = np.flatnonzero(np.isfinite(k))
    keep = np.zeros(len(k), bool)
    for i in idx:
        near = idx[(np.abs(idx - i) <= gap) & (idx != i)]
        keep[i] = np.any(np.abs(k[near] - k[i]) <= agree * np.maximum(k[near], k[i]))
    if keep.sum() < min_columns:
        keep[:] = False
    return np.where(keep, k, np.nan)


def within_heading(reach: np.ndarray, heading_sd: float, sigmas: float = 2.0) -> np.ndarray:
    """(128,) each column's floor end ``reach`` (:func:`floor_end`) cut to
    the nearest end of every column within ``sigmas`` standard deviations
    ``heading_sd`` (rad) of the estimate's heading of it, a column off the
    picture counting 0 (nothing seen there).  The look is laid down along
    the estimated heading, so the ray a column claims may be a neighbour's
    by up to that angle: beside an obstacle, the floor that one column
    shows past its side another column shows blocked, and only what all of
    them show is proven.  Under the 1985 eyes' dead reckoning the heading
    drifts 5-9 deg in 20 looks (rooms 6, 34, 49), and the floor in view,
    laid down along it, proved cells 0.3-1 ft inside boxes."""
    reach = np.asarray(reach, float)
    delta = sigmas * max(float(heading_sd), 0.0)
    if delta <= 0.0:
        return reach.copy()
    angle = np.arctan((np.arange(COLS) + 0.5 - CX) / FOCAL)     # increasing with the column
    lo = np.searchsorted(angle, angle - delta, side="left")
    hi = np.searchsorted(angle, angle + delta, side="right")    # columns lo..hi-1 in the window
    off_picture = (angle - delta < angle[0]) | (angle + delta > angle[-1])
    out = np.array([reach[a:b].min() for a, b in zip(lo, hi)])
    out[off_picture] = 0.0
    return out


def bound_by_floor(ends, cols, origin, reach: np.ndarray):
    """The assumed free ends ``ends`` ((N, 3), picture columns ``cols``,
    1-based) pulled back along their lines from ``origin`` to at most
    ``reach`` of their column (:func:`floor_end`: the floor in view ends
    there, 0 where it shows no end).  Returns (the ends, mask of the ends kept: a column whose floor
    run is empty bounds its line to nothing)."""
    ends = np.asarray(ends, float).reshape(-1, 3)
    if not len(ends):
        return ends, np.zeros(0, bool)
    o = np.asarray(origin, float)
    c = np.clip(np.asarray(cols, int) - 1, 0, COLS - 1)
    d = np.hypot(ends[:, 0] - o[0], ends[:, 2] - o[2])
    r = np.asarray(reach, float)[c]
    scale = np.where(d > r, r / np.maximum(d, 1e-12), 1.0)
    out = o + (ends - o) * scale[:, None]
    out[:, 1] = ends[:, 1]
    return out, r > 0


def keep_before_hit(keys: np.ndarray, ray: np.ndarray, hit_keys) -> np.ndarray:
    """Mask of the samples (packed cell keys, grouped by ``ray`` in order of
    distance) that no sample at or before them on their ray puts in a cell of
    ``hit_keys``: a proof never passes a cell any look has hit."""
    hit = np.isin(keys, np.asarray(hit_keys, np.int64))
    if not len(keys):
        return np.zeros(0, bool)
    run = np.cumsum(hit)
    first = np.flatnonzero(np.r_[True, ray[1:] != ray[:-1]])
    counts = np.diff(np.r_[first, len(ray)])
    base = np.repeat(run[first] - hit[first], counts)
    return run - base == 0
