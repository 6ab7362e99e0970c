"""The loop's map of its evidence (Chapter IV's volumetric model as the closed
loop keeps it): every look into the occupancy octree and the floor map
(:class:`Perception`), and what the map is told beside the looks — the room's
walls as a floor plan (:func:`mark_walls`).

Each look enters as a floor range scan (:func:`planner.perception.floor_scan`,
or :func:`planner.depth_eyes.depth_floor_scan` for the diagnostic depth eyes):
hits grown by their covariance, their sight lines free, the blank-column
assumption carved only where it is allowed (``blank_carve``, ``blank_px``,
``blank_sides``).  ``occupied="model"`` draws the occupied cells from floor
features fused look by look instead (:mod:`planner.features`).  The loop that
drives on this map is :mod:`planner.loop`.

A diagnostic beside it: a :class:`Perception` given a :class:`FreeProvenance`
records which carving freed each cell, and :func:`free_obstacle_cells` names,
for every true obstacle cell the final map shows free, the mechanism, how much
of the cell the obstacle covers, and :func:`standing_opened` what that costs
in safety (``bench/drive.py --losses``).
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import replace

import numpy as np

from vehicle.sim import State
from .appearance import ROWS, LookEnds, bound_by_floor, floor_end, floor_greys, floor_proof, \
    floor_rays, BOUNDING, STAND_INS, floor_run, is_tiled, keep_before_hit, nearest_greys, \
    run_shadows, \
    training_mask, vetoed, raised_columns, raised_ends, reads_floor, run_reach, texture_end, \
    within_heading, beside_points, no_end, wall_foot_reach
from .depth_eyes import depth_floor_scan
from .drift import LookFree, Odometry
from .features import FloorFeatures, mahalanobis2, pose_point_covariance, segment_cells
from .floormap import FLOOR_Y, FloorMap, project_octree, split_in_four
from .octree import MAX_GROWTH_FT, FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest, pack, unpack, \
    assumed_free_keys, cell_centres, cell_keys, features_cells, free_below, key_centres, \
    sight_samples, logodds_at, mark_free_rays, mark_keys_free, mark_occupied, \
    new_octree, spans_cells
from .perception import CX_128, CY_128, FOCAL_128, MIN_RANGE_FT, BearingsApart, camera_points, \
    filter_points, floor_scan


# The mechanisms that make a floor-map cell FREE (free_obstacle_cells names them)
SIGHT_TO_HIT = "sight line to a hit"            # a column's line to its located point
BETWEEN_EDGES = "columns between edges"         # free_ends the look proves (not assumed)
BLANK_ASSUMPTION = "blank-column assumption"    # FloorScan.assumed, mark_assumed_free
TWO_LOOK_SIDES = "two-look sides"               # TwoLookSides.confirm
FLOOR_IN_VIEW = "floor in view"                 # floor_eyes (planner.appearance)
FLAT_FOOT = "flat floor to the walls' foot"     # wall_runs="flat-foot" (_carve_flat_foot)
START_SPOT = "start spot"                       # the clear disc the vehicle was set down in
TRACK = "vehicle's track"                       # its footprint at every dead-reckoned pose
MECHANISMS = (SIGHT_TO_HIT, BETWEEN_EDGES, BLANK_ASSUMPTION, TWO_LOOK_SIDES, FLOOR_IN_VIEW,
              FLAT_FOOT, START_SPOT, TRACK)

FLAT_FOOT_BESIDE_FT = 3.6     # "flat-foot": no box face is wider (the rooms' boxes: at most
                              # 2.5 ft a side, 3.5 ft across seen corner on)
FLAT_FOOT_APART_DEG = 20.0    # "flat-foot": two looks' bearings of a cell at least this apart


def in_band(keys: np.ndarray, res: float, band) -> np.ndarray:
    """Which of the (N, 3) integer cell ``keys`` (cells of side ``res``) reach
    into the height ``band`` (room Y top, bottom)."""
    y = (keys[:, 1] + 0.5) * res
    return (y + res / 2 > band[0]) & (y - res / 2 < band[1])


class FreeProvenance:
    """Which carving marked each octree cell free, and in which looks: a
    diagnostic a :class:`Perception` keeps when its ``provenance`` is one
    (the map it builds is the same)."""

    def __init__(self):
        self.misses: dict[int, dict[str, int]] = {}   # packed key -> mechanism -> misses
        self.first_look: dict[int, int] = {}

    def add(self, keys, mechanism: str, look_no: int) -> None:
        for k in np.asarray(keys, np.int64).tolist():
            m = self.misses.setdefault(k, {})
            m[mechanism] = m.get(mechanism, 0) + 1
            self.first_look.setdefault(k, look_no)

    def columns(self, res: float, band) -> dict[tuple[int, int], dict[str, int]]:
        """The misses summed over each floor column (x key, z key) of the
        cells in the height ``band`` (room Y top, bottom)."""
        out: dict[tuple[int, int], dict[str, int]] = {}
        if not self.misses:
            return out
        keys = np.fromiter(self.misses.keys(), np.int64, len(self.misses))
        k = unpack(keys)
        inband = in_band(k, res, band)
        for key, (kx, _, kz) in zip(keys[inband].tolist(), k[inband].tolist()):
            col = out.setdefault((int(kx), int(kz)), {})
            for m, n in self.misses[key].items():
                col[m] = col.get(m, 0) + n
        return out


ASSUMED = (BLANK_ASSUMPTION, TWO_LOOK_SIDES)   # the carvings that only assume the floor
RAISED_LOOKS = 8                # floor_end_check="motion": the earlier looks an end is held to
RAISED_MIN_COLUMNS = 3          # ... and the columns of one look that must agree it moved
RAISED_JOIN_FT = 0.75           # ... two neighbouring edge points this near: one face between
RAISED_AGAIN_FT = 0.3           # ... an edge point kept once an earlier look found one this near
RAISED_HOLD = 4                 # ... and drawn for this many looks until then


def assumed_columns(fm: FloorMap, provenance: FreeProvenance, res: float, band,
                    blank_near=None, beyond_ft: float = 0.0) -> np.ndarray:
    """The FREE cells of ``fm`` whose octree column (cells of the height
    ``band``) only an assumption carved (:data:`ASSUMED`: blank columns, the
    two-look sides), no look's sight line nor the columns between edges, and
    no look nearer than ``beyond_ft`` had it blank (``provenance``,
    :meth:`FreeProvenance.columns`; ``blank_near``, :attr:`Perception.blank_near`,
    none given: every such column): (nz, nx) bool.  A blank box
    face far off is such a column (room 45, ``--head assist --eyes truth``: a
    box corner carved by one blank look 6.3 ft away, never located, let a
    pivot turn the vehicle's corner into it)."""
    out = np.zeros(fm.shape, bool)
    i0, j0 = int(round(fm.z0 / res)), int(round(fm.x0 / res))
    near: dict[tuple[int, int], float] = {}
    if blank_near:
        keys = np.fromiter(blank_near.keys(), np.int64, len(blank_near))
        k = unpack(keys)
        for (kx, _, kz), d in zip(k.tolist(), blank_near.values()):
            near[(kx, kz)] = min(near.get((kx, kz), math.inf), d)
    for (kx, kz), m in provenance.columns(res, band).items():
        if all(name in ASSUMED for name in m) and near.get((kx, kz), math.inf) > beyond_ft:
            i, j = kz - i0, kx - j0
            if 0 <= i < fm.shape[0] and 0 <= j < fm.shape[1]:
                out[i, j] = True
    return out & (fm.cells == FREE)


def cell_coverage(fm: FloorMap, obstacles, bounds, ij, sub: int = 16) -> np.ndarray:
    """The share of each cell ``ij`` ((N, 2) rows i, columns j of ``fm``)
    that the obstacle footprints (x0, x1, z0, z1) or the outside of the
    walls ``bounds`` cover, on a ``sub`` x ``sub`` grid of points in the cell."""
    ij = np.asarray(ij, int).reshape(-1, 2)
    t = (np.arange(sub) + 0.5) / sub
    out = np.zeros(len(ij))
    obs = np.asarray(obstacles, float).reshape(-1, 4)
    bx0, bx1, bz0, bz1 = bounds
    for n, (i, j) in enumerate(ij):
        x, z = np.meshgrid(fm.x0 + (j + t) * fm.cell, fm.z0 + (i + t) * fm.cell)
        cov = (x < bx0) | (x > bx1) | (z < bz0) | (z > bz1)
        for ox0, ox1, oz0, oz1 in obs:
            cov |= (x > ox0) & (x < ox1) & (z > oz0) & (z < oz1)
        out[n] = cov.mean()
    return out


def free_obstacle_cells(fm: FloorMap, obstacles, bounds, provenance: FreeProvenance, band,
                        track=(), footprint=(0.0, 0.0), start_clear_ft: float = 0.0,
                        hit_keys=None) -> list:
    """Every cell of the floor map ``fm`` that shows FREE where the true room
    (:func:`~planner.floormap.true_floor_map` of ``obstacles`` and the walls
    ``bounds``) has an obstacle, with the share of the cell the obstacle
    covers (:func:`cell_coverage`) and what made it free: the octree's misses
    in its column per mechanism (``provenance``), and whether the vehicle's
    dead-reckoned ``track`` (its ``footprint`` at each pose) or the start
    spot (``start_clear_ft`` about the first pose) lies on it
    (:func:`planner.motion.mark_track_free`, the loop's own marking).
    Each item: ``{"ij", "xz", "coverage", "depth_ft", "misses": {mechanism: n},
    "mechanisms": [names]}``, ``depth_ft`` how far inside an obstacle the
    cell's centre lies (0: outside it, a cell the obstacle covers in part).
    Given ``hit_keys`` (:attr:`Perception.hit_keys`: the cells any look hit),
    each item also says whether any look ever hit its column (``"hit"``)."""
    from .floormap import true_floor_map
    from .motion import mark_track_free
    ex = fm.extent()
    margin = max(bounds[0] - ex[0], ex[1] - bounds[1], bounds[2] - ex[2], ex[3] - bounds[3],
                 0.0) + fm.cell
    truth = true_floor_map(obstacles, bounds, fm.cell, margin)
    di = int(round((fm.z0 - truth.z0) / fm.cell))
    dj = int(round((fm.x0 - truth.x0) / fm.cell))
    nz, nx = fm.shape
    occ = truth.cells[di:di + nz, dj:dj + nx] == OCCUPIED
    ij = np.argwhere(occ & (fm.cells == FREE))
    marks = {}
    track = list(track)
    for name, poses, disc, fp in ((START_SPOT, track[:1], start_clear_ft, footprint),
                                  (TRACK, track, 0.0, footprint)):
        m = type(fm)(np.full(fm.shape, UNKNOWN, np.uint8), fm.x0, fm.z0, fm.cell)
        if poses:
            mark_track_free(m, poses, fp, disc)
        marks[name] = m.cells == FREE
    res = fm.cell
    cols = provenance.columns(res, band)
    i0, j0 = int(round(fm.z0 / res)), int(round(fm.x0 / res))
    cover = cell_coverage(fm, obstacles, bounds, ij)
    obs = np.asarray(obstacles, float).reshape(-1, 4)
    hit_cols = None
    if hit_keys is not None:
        hk = unpack(np.asarray(hit_keys, np.int64))
        hit_cols = set(zip(hk[:, 0].tolist(), hk[:, 2].tolist()))
    out = []
    for (i, j), c in zip(ij.tolist(), cover.tolist()):
        misses = dict(cols.get((j + j0, i + i0), {}))
        for name, mask in marks.items():
            if mask[i, j]:
                misses[name] = 1
        x, z = (float(v) for v in fm.centre(i, j))
        # how deep the cell's centre lies inside an obstacle (0: outside, a part cell)
        depth = max([min(x - a, b - x, z - d, e - z) for a, b, d, e in obs], default=0.0)
        item = {"ij": (i, j), "xz": (x, z), "coverage": c, "depth_ft": max(depth, 0.0),
                "misses": misses, "mechanisms": [m for m in MECHANISMS if m in misses]}
        if hit_cols is not None:
            item["hit"] = (j + j0, i + i0) in hit_cols
        out.append(item)
    return out


def standing_opened(fm: FloorMap, cells, obstacles, bounds, radius: float,
                    reach: float | None = None) -> dict:
    """What the cells of :func:`free_obstacle_cells` cost in safety: the
    cells where the vehicle's centre may stand on ``fm`` (the loop's
    clearance, :func:`planner.search.clearance_map` grown by ``radius``,
    unknown free, uncertain blocked) that would not be passable were those
    cells shown OCCUPIED (``opened``), and of those, the ones where a disc of
    ``radius`` about the cell's centre truly reaches into an obstacle or past
    a wall (``opened_unsafe``).  Zero ``opened_unsafe``: the growth by the
    vehicle's radius around the obstacle's other cells covers them."""
    from .search import clearance_map
    ok = clearance_map(fm, radius, "free", uncertain="blocked").ok
    if not len(cells):
        return {"opened": 0, "opened_unsafe": 0}
    shut = FloorMap(fm.cells.copy(), fm.x0, fm.z0, fm.cell)
    ij = np.array([c["ij"] for c in cells], int)
    shut.cells[ij[:, 0], ij[:, 1]] = OCCUPIED
    opened = np.argwhere(ok & ~clearance_map(shut, radius, "free", uncertain="blocked").ok)
    cx, cz = fm.centre(opened[:, 0], opened[:, 1])
    bx0, bx1, bz0, bz1 = bounds
    r = radius if reach is None else reach
    unsafe = (cx - r < bx0) | (cx + r > bx1) | (cz - r < bz0) | (cz + r > bz1)
    for ox0, ox1, oz0, oz1 in np.asarray(obstacles, float).reshape(-1, 4):
        dx = np.maximum(np.maximum(ox0 - cx, cx - ox1), 0.0)
        dz = np.maximum(np.maximum(oz0 - cz, cz - oz1), 0.0)
        unsafe |= np.hypot(dx, dz) < r
    return {"opened": int(len(opened)), "opened_unsafe": int(unsafe.sum())}


def free_inside_now(fm: FloorMap, obstacles, estimate, truth, depth_ft: float = 0.25) -> int:
    """How many FREE cells of ``fm`` lie ``depth_ft`` or more inside an
    obstacle (x0, x1, z0, z1) as the vehicle stands now: each cell's centre
    carried from the map's frame (the estimate's, ``estimate``: a State) into
    the room by where the vehicle truly is (``truth``).  The map is placed by
    the estimate, so against the room itself (:func:`free_obstacle_cells`) a
    look laid down by a drifted estimate shows free cells in the boxes that
    are floor beside them as the vehicle sees it: a look's own free space
    agrees with the pose it was taken from, and only the drift since then
    moves it against the vehicle now."""
    obs = np.asarray(obstacles, float).reshape(-1, 4)
    i, j = np.nonzero(fm.cells == FREE)
    if not len(i) or not len(obs):
        return 0
    x, z = fm.centre(i, j)
    he, ht = math.radians(estimate.heading_deg), math.radians(truth.heading_deg)
    dx, dz = x - estimate.x, z - estimate.z
    ahead = dx * math.sin(he) + dz * math.cos(he)        # in the vehicle's own axes
    right = dx * math.cos(he) - dz * math.sin(he)
    wx = truth.x + ahead * math.sin(ht) + right * math.cos(ht)
    wz = truth.z + ahead * math.cos(ht) - right * math.sin(ht)
    inside = np.minimum.reduce([wx[:, None] - obs[None, :, 0], obs[None, :, 1] - wx[:, None],
                                wz[:, None] - obs[None, :, 2], obs[None, :, 3] - wz[:, None]])
    return int((inside.max(1) >= depth_ft).sum())


def tally_free_obstacle_cells(cells) -> dict:
    """:func:`free_obstacle_cells` summed: cells per mechanism that had a
    hand in them (``any``), per mechanism that alone made them free
    (``only``), by the share of the cell the obstacle covers (``sliver``
    under a quarter, ``part`` up to three quarters, ``most`` short of the
    whole, ``whole``), overall and per mechanism, and by how deep inside the
    obstacle the cell's centre lies (``depth``); ``ever_hit`` counts those
    some look had hit (when the cells say)."""
    def share(c):
        return "whole" if c >= 0.999 else "most" if c >= 0.75 else "part" if c >= 0.25 \
            else "sliver"
    def inside(d):
        return "outside" if d <= 0 else "<0.25 ft" if d < 0.25 else "<0.5 ft" if d < 0.5 \
            else "<1 ft" if d < 1.0 else ">=1 ft"
    t = {"cells": len(cells), "any": {}, "only": {}, "coverage": {},
         "coverage_by_mechanism": {}, "depth": {}}
    for c in cells:
        s = share(c["coverage"])
        t["coverage"][s] = t["coverage"].get(s, 0) + 1
        d = inside(c.get("depth_ft", 0.0))
        t["depth"][d] = t["depth"].get(d, 0) + 1
        if "hit" in c:
            t["ever_hit"] = t.get("ever_hit", 0) + int(c["hit"])
        ms = c["mechanisms"] or ["none"]
        for m in ms:
            t["any"][m] = t["any"].get(m, 0) + 1
            d = t["coverage_by_mechanism"].setdefault(m, {})
            d[s] = d.get(s, 0) + 1
        if len(ms) == 1:
            t["only"][ms[0]] = t["only"].get(ms[0], 0) + 1
    return t


def across_sight_cov(points, covs, origin, res: float) -> np.ndarray:
    """The covariances with their spread along the (horizontal) sight line
    from ``origin`` cut to a quarter cell: a hit grown by its error ACROSS the
    sight line only, the range error not grown (a named option, off by
    default: the dissertation grows a feature by its whole covariance)."""
    pts = np.asarray(points, float).reshape(-1, 3)
    u = pts - np.asarray(origin, float)
    u[:, 1] = 0.0
    u /= np.maximum(np.linalg.norm(u, axis=1), 1e-12)[:, None]
    P = np.eye(3)[None] - u[:, :, None] * u[:, None, :]
    return P @ np.asarray(covs, float) @ P + (res / 4) ** 2 * (u[:, :, None] * u[:, None, :])


class Perception:
    """The model the loop plans on: located points (room coordinates) of every
    look and the octree built from them.  ``estimate`` is the camera estimate
    this adapter uses: the dead-reckoned pose, unchanged (``run`` replaces it
    with the walk's fused pose under ``pose="fused"``)."""

    def __init__(self, voi: VolumeOfInterest, band, max_range_ft: float, confirm_looks: int = 2,
                 free_looks: int = 2, near_ft: float = 2.8, blank_ft: float | None = None):
        self.tree = new_octree(voi, confirm_looks)
        self.growth = "covariance"        # or "across" (DriveConfig.growth)
        self.blank_carve = "always"       # or "unknown" (DriveConfig.blank_carve)
        self.carve = "range"              # or "error" (DriveConfig.carve)
        self.blank_px = None              # DriveConfig.blank_px
        self.blank_limit = "all"          # or "sides" (DriveConfig.blank_limit)
        self.sight_lines = "band"         # or "low", "low-all" (DriveConfig.sight_lines)
        self.stereo_margin = False        # DriveConfig.stereo_margin
        self.min_range_ft = MIN_RANGE_FT  # DriveConfig.min_range_ft: nearer points left out
        self.stand_in = "tenth"           # or "majority" (DriveConfig.stand_in)
        self.seen_over = 0                # under "low": cells on sight lines not proven
        self.refute_hits = "off"          # or "under", "through" (DriveConfig.refute_hits)
        # refute_hits="through": every hit so far (its located 3-D point, covariance, range
        # and look), which of them a later look saw through, and the hits each cell grew from
        self.seen_pts = np.zeros((0, 3))
        self.seen_cov = np.zeros((0, 3, 3))
        self.seen_range = np.zeros(0)
        self.seen_look = np.zeros(0, int)
        self.seen_through = np.zeros(0, bool)
        self.grown_from: dict[int, list[int]] = {}
        self.claims: dict[int, float] = {}    # packed key -> the lowest drop of a hit grown there
        self.refuted = 0                  # cells a later ray passed under (refute_hits)
        self._look_keys = np.zeros(0, np.int64)   # the current look's grown hit cells
        self.two_look_sides = None        # a TwoLookSides (DriveConfig.blank_sides="two-looks")
        self.occupied = "looks"           # or "model" (DriveConfig.occupied)
        self.place = "axis"               # or "point" (DriveConfig.hit_at)
        self.feature_pose = "absolute"    # or "drift", "none" (DriveConfig.feature_pose)
        self.floor_end_check = "off"      # or "stereo", "motion" (DriveConfig.floor_end_check)
        self.end_looks: list[LookEnds] = []   # under "motion": the last looks' floor ends
        self.raised_a = np.zeros((0, 2))  # under "motion": the edges found raised, as
        self.raised_b = np.zeros((0, 2))  # segments a-b on the floor (x, z), drawn occupied
        self.raised_seen: list = []       # ... and (look, edge points, segments a, b held) of
                                          # every look that found one
        self.proof_hits = "trace"         # or "line" (DriveConfig.proof_hits)
        self.free_cells = "any"           # or "shadows" (DriveConfig.free_cells)
        self._shadow_keys = np.zeros(0, np.int64)   # under "shadows": behind this look's runs
        self.proof_heading = "estimate"   # or "window" (DriveConfig.proof_heading)
        self.heading_sigmas = 2.0         # under "window": the heading's standard deviations
        self.floor_eyes = "off"           # or "carve", "add", "bound", "bound-add", "veto" (DriveConfig.floor_eyes)
        self.expire_uncertain = 0         # DriveConfig.expire_uncertain (0: off)
        self.wall_runs = "none"           # or "texture", "past", "foot", "flat-foot"
                                          # (DriveConfig.wall_runs)
        self.foot_bearings = BearingsApart(FLAT_FOOT_APART_DEG)   # under "flat-foot"
        self.tile_edges = "break"         # or "blend" (DriveConfig.tile_edges)
        self.expire_within = None         # ((x, z), r): only the features whose two-sigma
                                          # ellipse reaches that disc expire
                                          # (DriveConfig.goal_evidence="look-expire")
        self.unseen: dict[int, int] = {}  # packed key -> looks that had it in view, no hit
        self.expired: dict[int, float] = {}   # packed key -> its log-odds when it expired
        self.expired_total = 0            # expiries so far (a cell hit again may expire anew;
                                          # under occupied="model", the features retired)
        self.feature_unseen = np.zeros(0, int)   # per floor feature: looks that had it in
                                          # view and did not locate it (occupied="model")
        self.lowest_ft = 0.8              # DriveConfig.lowest_obstacle_ft
        self.floor_hist = np.zeros(16)    # greys of the pixels known to show floor, all looks
        self.vetoed = 0                   # located points the floor in view contradicted
        self.floor_cells = 0              # cells the floor in view proved free
        self.raised_columns = 0           # under floor_end_check="motion": the columns cut
        self.confirm_looks = confirm_looks
        self.features = FloorFeatures()
        self.draw_core = False            # DriveConfig.uncertain="core": floor_map marks the
                                          # uncertain features' one-sigma cells (FloorMap.uncertain_core)
        self.retired = 0
        self.hit_keys = np.zeros(0, np.int64)   # cells of the floor slab any look has hit
        self.free_looks = free_looks
        self.free_band = None
        self.near_ft = near_ft
        self.blank_ft = blank_ft
        self.voi = voi
        self.band = band
        self.max_range_ft = max_range_ft
        self.points = np.zeros((0, 3))
        self.lo = None
        self.hi = None
        self.pending = []
        self.provenance = None            # a FreeProvenance: which carving freed each cell
        self.look_free = None             # DriveConfig.free_drift="erode": a list of each
                                          # look's free floor columns (planner.drift.LookFree)
        self.odometry = None              # its planner.drift.Odometry totals (the loop's)
        self._freed: list = []            # the packed keys this look marked free
        self.one_grey_runs = "prove"      # DriveConfig.one_grey_runs
        self.wall_hits = "feature"        # DriveConfig.wall_hits: "plan" starts no feature
        self.plan_walls = None            # from a hit the plan's walls (x0, x1, z0, z1) explain
        self.assume_within = None         # (x0, x1, z0, z1): the assumed floor stops there
        self.floor_within = None          # (x0, x1, z0, z1): floor in view ends inside (bound)
                                          # (the loop: the plan's walls less wall_growth)
        self.look_no = 0                  # looks taken into the model
        self.pivot_proof = None           # head="assist": floor_map marks the cells FREE only
                                          # by an assumption from farther than this, ft
                                          # (FloorMap.assumed; assumed_columns)
        self.blank_near: dict[int, float] = {}   # under pivot_proof: packed key -> the nearest
                                          # look (ft) that had it on a blank column's line

    @contextmanager
    def _carving(self, tag):
        """Record in :attr:`provenance` (when tracing) every cell the batch
        updates inside this block mark free, under ``tag`` (a mechanism's
        name, or a function of the packed keys returning ``(keys, name)``
        pairs); the updates themselves are unchanged."""
        prov, tree = self.provenance, self.tree
        if prov is None and self.look_free is None:
            yield
            return

        def record(values, update, lazy_eval=False):
            out = type(tree).updateNodes(tree, values, update, lazy_eval)
            if not update and values is not None and len(values):
                keys = pack(tree.key_of(values))
                if self.look_free is not None:
                    self._freed.append(keys)
                if prov is not None:
                    for ks, name in (tag(keys) if callable(tag) else [(keys, tag)]):
                        prov.add(ks, name, self.look_no)
            return out
        tree.updateNodes = record
        try:
            yield
        finally:
            del tree.updateNodes

    def estimate(self, look, dead: State) -> State:
        return dead

    def stand_in_greys(self, picture) -> np.ndarray:
        """What stands for the floor's greys until they are learned: the picture's
        bottom rows' greys, each with the share ``stand_in`` asks
        (:func:`planner.appearance.nearest_greys`)."""
        return nearest_greys(picture, min_share=STAND_INS[self.stand_in])

    def bounding_greys(self, picture) -> np.ndarray:
        """The greys that end the floor in view: the learned ones
        (:func:`planner.appearance.floor_greys`), else :meth:`stand_in_greys`."""
        greys = floor_greys(self.floor_hist)
        return self.stand_in_greys(picture) if greys is None else greys

    def update(self, scan_points, est: State, pose_cls, pitch_deg: float = 0.0,
               known: FloorMap | None = None, pose_cov=None, picture=None, depth=None) -> int:
        """One look into the model as a floor range scan
        (:func:`~planner.perception.floor_scan`): each column's nearest
        supported point hit (grown by its covariance; surface spans between
        neighbours at one range), and its sight line carved free from
        ``near_ft`` on — nearer than that the lowest obstacle would be below
        the picture, so the look proves nothing there — as are the columns
        between two neighbours, up to the nearer of them.  One update per cell
        per look.

        Columns free only by the blank-column assumption (``blank_ft``) carve
        less under ``blank_carve="unknown"`` (a named option): only cells no look has seen, never
        past a cell any look has hit (:func:`~planner.octree.mark_assumed_free`),
        and, given the ``known`` floor map (the last one, the vehicle's track
        free), only along a line whose part nearer than ``near_ft`` (where the
        look proves nothing) is free on it: a blank view may be a blank face
        right in front.

        ``occupied="model"`` (a named option, :mod:`planner.features`): the
        octree gets the sight lines as above but only the hits' own cells
        (the evidence :meth:`retire` weighs); the hits go into the floor
        features instead, their covariance with the pose's share added
        (``pose_cov``: the estimate's (x, z, heading) covariance), and the map's
        occupied and uncertain cells are drawn from the features
        (:meth:`floor_map`).

        ``floor_eyes`` (a named option, :mod:`planner.appearance`) reads the
        look's left ``picture`` (the condensed 128x120 one the eyes scan):
        once the floor's grey is learned from pixels that show floor the
        ``known`` map has free, each column's floor in view is carved as a
        proof (never past a cell any look has hit, no farther than the floor
        scan's bound of that column) in place of the blank-column assumption
        (``"carve"``, ``"veto"``) or beside it (``"add"``: the assumption still
        carves under its own rules); ``"veto"`` also leaves out the located
        points the floor in view contradicts.  ``"bound"`` carves nothing: each
        assumed line ends where its column's floor in view ends
        (:func:`~planner.appearance.floor_end`, the bottom rows standing for the
        floor's grey until it is learned); ``"bound-add"`` does that and
        carves the learned grey's proof beside it, no farther than that end
        (nothing in a column whose floor shows no end).

        ``expire_uncertain`` (a named option, N looks; 0 off) counts the look
        against the uncertain cells it had in view without a hit
        (:meth:`expire_in_view`); after N the map shows them UNKNOWN.

        ``depth`` (the look's true range per pixel, ``Look.range_left``: the
        diagnostic depth eyes, :mod:`planner.depth_eyes`) replaces the floor
        scan of ``scan_points`` by :func:`~planner.depth_eyes.depth_floor_scan`;
        the rest of the update is the same."""
        self.look_no += 1
        self._look_keys = np.zeros(0, np.int64)   # this look's grown hit cells
        self._proved = np.zeros(0, np.int64)      # the cells this look's floor in view proved
        self._freed = []
        pose = pose_cls(est.x, est.z, est.heading_deg, pitch_deg)
        R = pose.rotation()
        left = pose.camera_centre("left")
        res = self.tree.getResolution()
        if self.refute_hits == "through" and depth is None and len(scan_points):
            self._refute_through(scan_points, R, left, res)
        rays = top = proof_top = learned = None
        bounded = self.floor_eyes in BOUNDING
        if picture is not None and reads_floor(self.floor_eyes, depth is not None):
            rays = floor_rays(R, left)
            pic = np.asarray(picture)
            if known is not None:
                m = training_mask(rays, known, self.lowest_ft, self.max_range_ft,
                                  whole_trace=bounded)
                self.floor_hist += np.bincount(pic[m].astype(int), minlength=16)[:16]
            learned = floor_greys(self.floor_hist)
            if learned is not None and self.floor_eyes == "bound-add":
                # only the learned grey proves; the stand-in only bounds
                proof_top = floor_run(pic, learned, blend=self.tile_edges == "blend")
            greys = self.bounding_greys(pic) if bounded else learned
            if greys is not None:
                top = floor_run(pic, greys, bridge=bounded)
                if self.floor_eyes == "veto" and len(scan_points):
                    bad = vetoed(scan_points, rays, top, res)
                    self.vetoed += int(bad.sum())
                    scan_points = [q for q, b in zip(scan_points, bad) if not b]
        self._shadow_keys = np.unique(cell_keys(run_shadows(rays, top, res, self.lowest_ft), res)) \
            if top is not None and self.free_cells == "shadows" else np.zeros(0, np.int64)
        if depth is not None:
            fs = depth_floor_scan(depth, R, left, self.band, self.max_range_ft, res)
        else:
            fs = floor_scan(scan_points, R, left, self.band, self.max_range_ft,
                            blank_ft=self.blank_ft, carve=self.carve, place=self.place,
                            blank_px=self.blank_px, blank_limit=self.blank_limit,
                            stereo_margin=self.stereo_margin, min_range=self.min_range_ft,
                            low_y=FLOOR_Y - self.lowest_ft if self.sight_lines != "band"
                            else None, blind_low=self.sight_lines == "low-all")
        if len(fs.hits) or len(fs.free_ends):
            cov = fs.hit_cov if self.growth == "covariance" else \
                across_sight_cov(fs.hits, fs.hit_cov, left, res)
            grown = np.vstack([cell_centres(fs.hits, res),
                               features_cells(fs.hits, cov, res),
                               spans_cells(fs.hits, fs.spans, res)])
            grown = cell_centres(grown[np.abs(grown[:, 1] - left[1]) < res], res)  # floor slab
            if self.expire_uncertain and self.occupied == "looks":
                self.expire_in_view(fs, R, left, cell_keys(grown, res))
            self.hit_keys = np.union1d(self.hit_keys, cell_keys(grown, res))
            self._look_keys = cell_keys(grown, res)
            assumed = fs.assumed if self.blank_carve == "unknown" and fs.assumed is not None \
                else np.zeros(len(fs.free_ends), bool)
            if top is not None and not bounded:
                # the floor in view replaces the blank-column assumption
                with self._carving(FLOOR_IN_VIEW):
                    self._carve_floor(fs, rays, top, left, res)
                assumed = fs.assumed if fs.assumed is not None else assumed
                proven = fs.free_ends[~assumed]
                # "add": the assumption carves as well, under its own rules
                ends = fs.free_ends[assumed] if self.floor_eyes == "add" else fs.free_ends[:0]
            else:
                proven = fs.free_ends[~assumed]
                ends = fs.free_ends[assumed]
            # under sight_lines="low" each line proves the band only from its start on
            low = fs.hit_start is not None
            fstart = fs.free_start if low else None
            with self._carving(self._split_seen(left, fs.hits, proven, res)):
                if low:
                    self._mark_low_rays(left, np.vstack([fs.hits, proven]), np.concatenate(
                        [fs.hit_start, fstart[~assumed]]), res, np.concatenate(
                        [fs.hit_short, np.zeros(len(proven))]))
                else:
                    mark_free_rays(self.tree, left, np.vstack([fs.hits, proven]),
                                   start_ft=self.near_ft)
            # by assumption only into unknown cells, never past a cell hit (this look too)
            # (ends, when any, are the assumed free ends: floor_eyes="add" or no floor eyes)
            ends_start = (fstart[assumed] if len(ends) else np.zeros(0)) if low else None
            heading_sd = math.sqrt(max(float(pose_cov[2, 2]), 0.0)) \
                if pose_cov is not None else None
            # "flat-foot": the texture's rule, and on a flat floor the walls' foot below
            runs = "texture" if self.wall_runs == "flat-foot" else self.wall_runs
            texture = texture_end(picture, learned, top) \
                if runs == "texture" and learned is not None and top is not None \
                else None
            reach = floor_end(rays, top, self.floor_within, heading_sd or 0.0, runs, texture) \
                if top is not None and bounded else None
            ends_now = None
            if reach is not None and self.floor_end_check == "motion" and depth is None:
                # an end that moves with the camera stands above the floor (room 860)
                reach, ends_now = self._raised_by_motion(rays, top, reach, left, res)
            if reach is not None and self.floor_end_check != "off" and depth is None:
                # a located point in a floor run, nearer than its floor: the run went up a face
                reach = raised_ends(scan_points, rays, top, reach,
                                    min_range_ft=self.min_range_ft)
            if reach is not None and self.proof_heading == "window" and heading_sd is not None:
                # the look lies along the estimated heading: only what every column
                # within its sigmas shows is proven (rooms 6, 34, 49)
                reach = within_heading(reach, heading_sd, self.heading_sigmas)
            if reach is not None and self.one_grey_runs == "near-seen" and known is not None \
                    and texture is not None and learned is not None and is_tiled(learned):
                # on a tiled floor a run that shows one of its greys only may be a face of
                # that grey filling the bottom rows: it proves nothing unless the last map
                # showed the floor before its bottom row free (room 881: a face 1.5 ft
                # ahead, checked in the floor's grey 3, proved as floor 3.2 ft out)
                bottom = np.column_stack([rays.x[ROWS - 1], np.full(len(reach), left[1]),
                                          rays.z[ROWS - 1]])
                near = float(np.nanmax(rays.dist[ROWS - 1]))
                reach = np.where((texture < ROWS) | _near_free(known, left, bottom, near),
                                 reach, 0.0)
            if proof_top is not None:
                # "bound-add": the floor in view proves its trace too, no farther
                # than where the bound ends it (nowhere in a column showing no end)
                with self._carving(FLOOR_IN_VIEW):
                    self._carve_floor(fs, rays, proof_top, left, res, reach=reach)
                if self.wall_runs == "flat-foot" and reach is not None and \
                        learned is not None and not is_tiled(learned) and \
                        self.floor_within is not None:
                    with self._carving(FLAT_FOOT):
                        self._carve_flat_foot(fs, rays, top, proof_top, reach, scan_points,
                                              heading_sd, left, res)
            if ends_now is not None:
                self._keep_ends(ends_now, left, res)
            if len(ends):
                ends, ends_start = self._limit_assumed(
                    ends, ends_start, fs.free_cols[assumed] if reach is not None else None,
                    left, reach, known, res)
            if self.pivot_proof is not None and len(ends):
                self._blank_seen(left, ends, ends_start, res)
            with self._carving(BLANK_ASSUMPTION):
                mark_keys_free(self.tree, self._assumed_keys(left, ends, ends_start))
            far_ends = fs.far_ends if self.two_look_sides is not None and \
                fs.far_ends is not None else fs.free_ends[:0]
            if len(far_ends):
                # the cut-off sides: carved where a look apart saw them blank too (TwoLookSides)
                far_ends, far_start = self._limit_assumed(far_ends, fs.far_start, fs.far_cols,
                                                          left, reach, known, res)
                keys = self._assumed_keys(left, far_ends, far_start)
                with self._carving(TWO_LOOK_SIDES):
                    mark_keys_free(self.tree, self.two_look_sides.confirm(
                        keys, (est.x, est.z, est.heading_deg)))
            if self.refute_hits == "under" and fs.hit_drop is not None and len(grown):
                self._claim(grown, fs.hits, fs.hit_drop)
            if self.refute_hits == "through" and fs.hit_xyz is not None and len(fs.hits):
                self._remember_hits(fs, cov, left, res)
            ids = np.zeros(0, int)            # the features this look fused into
            if self.occupied == "looks":
                if len(grown):
                    mark_occupied(self.tree, grown)
            elif len(fs.hits):
                mark_occupied(self.tree, cell_centres(fs.hits, res))
                obs = fs.hits[:, [0, 2]]
                obs_cov = fs.hit_cov[:, [0, 2]][:, :, [0, 2]]
                if pose_cov is not None and self.feature_pose == "absolute":
                    obs_cov = obs_cov + pose_point_covariance(obs, (est.x, est.z), pose_cov)
                keep = np.ones(len(obs), bool)
                if self.wall_hits == "plan" and self.plan_walls is not None:
                    keep = ~wall_explained(obs, obs_cov, self.plan_walls)
                kept = np.cumsum(keep) - 1
                spans = [(int(kept[a]), int(kept[b])) for a, b in fs.spans if keep[a] and keep[b]]
                ids = np.full(len(obs), -1, int)
                ids[keep] = self.features.add_look(
                    obs[keep], obs_cov[keep], spans, near=(est.x, est.z),
                    near_ft=self.max_range_ft + 3.0,
                    drift_cov=pose_cov if self.feature_pose == "drift"
                    and pose_cov is not None else None)
            if self.occupied == "model":
                if self.expire_uncertain:
                    self.expire_features_in_view(fs, R, left, ids)
                self.retire(left, self.max_range_ft + 3.0)
        elif self.expire_uncertain:                   # it located nothing
            if self.occupied == "looks":
                self.expire_in_view(fs, R, left, np.zeros(0, np.int64))
            else:
                self.expire_features_in_view(fs, R, left, np.zeros(0, int))
        self.points = np.vstack([self.points, fs.hits])
        self._extend(fs.hits[:, [0, 2]] if len(fs.hits) else np.zeros((0, 2)))
        if self.look_free is not None:
            self._keep_look_free(left, res)
        return len(fs.hits)

    def _keep_look_free(self, left, res: float) -> None:
        """This look's free cells of the floor slab, as floor columns, into
        :attr:`look_free` with the odometry's totals now (``free_drift``)."""
        keys = unpack(np.unique(np.concatenate(self._freed))) if self._freed else \
            np.zeros((0, 3), np.int64)
        slab = in_band(keys, res, self.band)
        cols = np.unique(keys[slab][:, [0, 2]], axis=0) if slab.any() else np.zeros((0, 2), int)
        self.look_free.append(LookFree((float(left[0]), float(left[2])), cols,
                                       replace(self.odometry) if self.odometry is not None
                                       else Odometry()))

    def _mark_low_rays(self, left, ends, starts, res: float, short=None) -> int:
        """:func:`~planner.octree.mark_free_rays` from ``near_ft`` on, each
        line only from its own ``starts`` (``FloorScan.hit_start`` /
        ``free_start``: where its ray runs below the lowest obstacle's top)
        on, and ending ``short`` (``FloorScan.hit_short``: the hit's error
        bound), at least a cell, before its end; the part nearer than its
        start is seen over, not proven free, and left as it was (counted in
        :attr:`seen_over`)."""
        along = sight_samples(left, ends, res, None, self.near_ft, self.near_ft)
        if along is None:
            return 0
        samples, dist, n = along
        seg = np.repeat(np.arange(len(n)), n)
        before_end = np.ones(len(dist), bool)     # short of the line's end (its error bound)
        if short is not None:
            ends = np.asarray(ends, float).reshape(-1, 3)
            length = np.hypot(ends[:, 0] - left[0], ends[:, 2] - left[2])
            before_end = dist <= (length - np.maximum(np.asarray(short, float), res))[seg]
        keep = (dist >= np.asarray(starts, float)[seg]) & before_end
        if self.refute_hits == "under" and self.claims:
            self._refute_under(samples, dist, seg, starts, before_end, left, res)
        over = np.unique(cell_keys(samples[~keep], res))
        self.seen_over += int(len(np.setdiff1d(over, cell_keys(samples[keep], res))))
        if not keep.any():
            return 0
        cells = cell_centres(samples[keep], res)
        self.tree.updateNodes(np.ascontiguousarray(cells), False)
        return len(cells)

    def _claim(self, grown, hits, drops) -> None:
        """``refute_hits``: each grown hit cell claims an obstacle standing on the
        floor at least up to the lowest located point of its nearest hit's
        column (``FloorScan.hit_drop``, ft below the camera); a cell keeps the
        lowest (the largest drop) any look claimed."""
        res = self.tree.getResolution()
        keys = cell_keys(grown, res)
        d2 = (grown[:, None, 0] - hits[None, :, 0]) ** 2 + (grown[:, None, 2] - hits[None, :, 2]) ** 2
        need = np.asarray(drops, float)[np.argmin(d2, 1)]
        for k, y in zip(keys, need):
            k = int(k)
            self.claims[k] = max(self.claims.get(k, -np.inf), float(y))

    def _refute_under(self, samples, dist, seg, starts, before_end, left, res: float) -> int:
        """``refute_hits="under"`` (a named option, not 1985): a hit cell whose
        claim (:meth:`_claim`) a later sight line passes UNDER is shown
        UNKNOWN (:meth:`_apply_expired`; never free), until a hit raises it
        again.  A sight line runs from the camera down to its located point;
        at ``r`` ft it is ``(low_y - camera) r / start`` below the camera
        (``start``: :func:`~planner.perception.low_start`, the conservative
        larger one for the columns between).  Where that drop, at the cell's
        near side (``r`` less a cell), reaches the claimed point's, the ray
        went below the point through the floor-standing obstacle the hit
        claims, and reached a surface beyond it (only the samples
        ``before_end``, short of the line's end as the proof's): a real surface point cannot
        be passed under.  A ray over the point (a low box's top seen over)
        refutes nothing.  Cells this look hit are not refuted by it."""
        need = FLOOR_Y - self.lowest_ft - left[1]
        st = np.asarray(starts, float)[seg]
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(np.isfinite(st) & (st > 0), need / st, 0.0)
        drop = slope * np.maximum(dist - res, 0.0)
        keys = cell_keys(samples, res)
        claim = np.array([self.claims.get(int(k), np.inf) for k in keys])
        under = before_end & (drop >= claim) & ~np.isin(keys, self._look_keys)
        n = 0
        for k in np.unique(keys[under]):
            if int(k) not in self.expired:
                self.expired[int(k)] = float("nan")
                n += 1
        self.refuted += n
        return n

    def _remember_hits(self, fs, cov, left, res: float) -> None:
        """``refute_hits="through"``: keep each hit of this look (its located
        3-D point, covariance, range) and the floor-slab cells it put on the
        map (its own cell, its growth by ``cov``, the surface spans it ends),
        so that a later look that sees through the point frees its cells of
        it (:meth:`_refute_through`)."""
        first = len(self.seen_range)
        n = len(fs.hits)
        self.seen_pts = np.vstack([self.seen_pts, fs.hit_xyz])
        self.seen_cov = np.concatenate([self.seen_cov, fs.hit_cov])
        self.seen_range = np.concatenate([self.seen_range, fs.hit_range])
        self.seen_look = np.concatenate([self.seen_look, np.full(n, self.look_no)])
        self.seen_through = np.concatenate([self.seen_through, np.zeros(n, bool)])
        spans_of = {}
        for a, b in fs.spans:
            spans_of.setdefault(a, []).append((a, b))
            spans_of.setdefault(b, []).append((a, b))
        for h in range(n):
            cells = np.vstack([cell_centres(fs.hits[h:h + 1], res),
                               features_cells(fs.hits[h:h + 1], cov[h:h + 1], res),
                               spans_cells(fs.hits, spans_of.get(h, []), res)])
            cells = cells[np.abs(cells[:, 1] - left[1]) < res]
            for k in np.unique(cell_keys(cells, res)):
                self.grown_from.setdefault(int(k), []).append(first + h)

    def _refute_through(self, scan_points, R, left, res: float) -> int:
        """``refute_hits="through"`` (a named option, not 1985): a hit that a
        later, nearer look sees through.  A located point claims a surface at
        its place in 3-D.  Projected into a later look (its estimated pose),
        the claim falls on a picture column and line; where that look stands
        nearer to it than the look that located it (so it sees it more
        sharply: ``min_range_ft`` or more away, at least a cell nearer than
        the claim's own range) and locates two points or more within 2 columns and 4 lines of
        that pixel, each farther than the claim by both their error bounds
        (the claim's two sigma along the new sight line plus the point's
        ``ep``: the two cannot be one surface), its ray passed through the place the claim says is
        solid: the claim is refuted, unless that look also locates a point
        there within those bounds (the claim's edge seen again: at an
        occluding boundary the surface behind shows beside it).  A cell every one of whose hits is
        refuted shows UNKNOWN, never free (:meth:`_apply_expired`, the
        expiry's display), until a hit raises it again; confirmed (occupied)
        cells stay.  Returns the hits refuted by this look."""
        alive = np.flatnonzero(~self.seen_through)
        if not len(alive):
            return 0
        R = np.asarray(R, float)
        rel = self.seen_pts[alive] - np.asarray(left, float)
        c = rel @ R                                   # into the camera's axes
        z = c[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            col = c[:, 0] / z * FOCAL_128 + CX_128 + 0.5
            row = c[:, 1] / z * FOCAL_128 + CY_128 - 0.5
        xyz_c, _, line, loc1, ep = camera_points(scan_points)
        ok = filter_points(xyz_c, ep, max_range=np.inf, min_range=self.min_range_ft)
        xyz_c, line, loc1, ep = xyz_c[ok], line[ok], loc1[ok], ep[ok]
        if not len(xyz_c):
            return 0
        cand = (z >= self.min_range_ft) & (z < self.seen_range[alive] - res) & (col >= 1) & \
            (col <= 128) & (row >= line.min() - 4) & (row <= line.max() + 4) & \
            (self.seen_look[alive] < self.look_no)
        if not cand.any():
            return 0
        idx, z, col, row, rel = alive[cand], z[cand], col[cand], row[cand], rel[cand]
        u = rel / np.linalg.norm(rel, axis=1)[:, None]
        two_sigma = 2 * np.sqrt(np.clip(np.einsum("ni,nij,nj->n", u, self.seen_cov[idx], u),
                                        0, None))
        near_px = (np.abs(loc1[None, :] - col[:, None]) <= 2) & \
            (np.abs(line[None, :] - row[:, None]) <= 4)
        bound = two_sigma[:, None] + ep[None, :]
        beyond = xyz_c[None, :, 2] - z[:, None] > bound
        # a point there as well (the claim's edge again, at an occluding boundary the
        # surface behind beside it): not seen through
        again = (np.abs(xyz_c[None, :, 2] - z[:, None]) <= bound) & \
            (np.abs(loc1[None, :] - col[:, None]) <= 1)
        through = idx[((near_px & beyond).sum(1) >= 2) & ((near_px & again).sum(1) < 2)]
        if not len(through):
            return 0
        self.seen_through[through] = True
        gone = set(through.tolist())
        n = 0
        for k, src in self.grown_from.items():
            if gone.intersection(src) and all(self.seen_through[i] for i in src) and \
                    k not in self.expired:
                self.expired[k] = float("nan")
                n += 1
        self.refuted += n
        return len(through)

    def _limit_assumed(self, ends, start, cols, left, reach, known, res):
        """What the assumption may carve of its sight lines ``left -> ends``
        (picture columns ``cols``; ``start``: where each begins to prove the
        band under sight_lines="low", else None): each line ended where its
        column's floor in view ends (``reach``, floor_eyes="bound"; none: not
        bounded), only the lines whose near part ``known`` shows free, each cut
        at the plan's walls (``assume_within``).  Returns (ends, start)."""
        def keep(ok):
            return ends[ok], None if start is None else start[ok]
        if reach is not None and len(ends):
            # the picture bounds the assumption: no line past its column's floor in view
            ends, ok = bound_by_floor(ends, cols, left, reach)
            ends, start = keep(ok)
        if known is not None and len(ends):
            ends, start = keep(_near_free(known, left, ends, self.near_ft))
        if self.assume_within is not None and len(ends):
            ends = within_walls(left, ends, self.assume_within, res)
        return ends, start

    def _blank_seen(self, left, ends, starts, res: float) -> None:
        """Under ``pivot_proof``: every cell on the look's assumed lines
        ``ends`` (seen before or not, as :meth:`_assumed_keys` without
        ``only_unknown``)
        remembers the nearest look that had it blank (:attr:`blank_near`):
        the assumption carves a cell once, from the first and farthest look."""
        keys = self._assumed_keys(left, ends, starts, only_unknown=False)
        if not len(keys):
            return
        c = key_centres(keys, res)
        for k, d in zip(keys.tolist(), np.hypot(c[:, 0] - left[0], c[:, 2] - left[2]).tolist()):
            self.blank_near[k] = min(self.blank_near.get(k, math.inf), d)

    def _assumed_keys(self, left, ends, starts, only_unknown: bool = True) -> np.ndarray:
        """:func:`~planner.octree.assumed_free_keys` of the assumed lines
        ``ends``, each from its own start (``FloorScan.free_start`` /
        ``far_start`` under sight_lines="low", at least ``near_ft``; None:
        all from ``near_ft``) on: the blank columns beside a hit are carved
        only where that hit's ray proves the band; lines grouped by start,
        the keys united (one update per cell per look), less this look's
        shadows (:meth:`_off_shadows`)."""
        starts = np.full(len(ends), self.near_ft) if starts is None else \
            np.asarray(starts, float)
        out = [np.zeros(0, np.int64)]
        for s in np.unique(starts[np.isfinite(starts)]):
            sel = starts == s
            out.append(assumed_free_keys(self.tree, left, ends[sel], self.hit_keys,
                                         start_ft=max(self.near_ft, float(s)),
                                         only_unknown=only_unknown))
        return self._off_shadows(np.unique(np.concatenate(out)).astype(np.int64))

    def _off_shadows(self, keys: np.ndarray) -> np.ndarray:
        """``keys`` less the cells in the shadows of this look's floor runs
        (``free_cells="shadows"``: :func:`~planner.appearance.run_shadows`;
        none under ``"any"``): an assumed line frees no cell hidden behind
        a run's foot."""
        return keys[~np.isin(keys, self._shadow_keys)] if len(self._shadow_keys) else keys

    def _split_seen(self, left, hits, proven, res: float):
        """The tag of :meth:`update`'s one seen-sight-line batch: the keys on
        the lines to the look's hits, and those on the lines of the columns
        between edges (a key on both counts under both)."""
        if self.provenance is None:
            return None

        def keys_of(ends):
            along = sight_samples(left, ends, res, None, self.near_ft, self.near_ft)
            return np.zeros(0, np.int64) if along is None else \
                np.unique(pack(self.tree.key_of(cell_centres(along[0], res))))

        to_hits, between = keys_of(hits), keys_of(proven)

        def split(keys):
            a, b = np.isin(keys, to_hits), np.isin(keys, between)
            return [(keys[a], SIGHT_TO_HIT), (keys[b], BETWEEN_EDGES),
                    (keys[~a & ~b], SIGHT_TO_HIT)]     # (none expected: the same sampling)
        return split

    def expire_in_view(self, fs, R, left, look_keys) -> int:
        """Count this look against every uncertain cell (hit by earlier looks,
        not confirmed) that it had IN VIEW without locating anything there,
        and expire a cell after ``expire_uncertain`` such looks: it then shows
        UNKNOWN on the map (:meth:`floor_map`), never free, until a hit raises
        its log-odds again.  Returns the cells expired by this look.

        In view: :meth:`_in_view_clear`.  A cell within one cell of anything
        this look hit (``look_keys``: its grown hit cells) is not counted and
        starts over: a real corner seen again from near by shows again.  Cells
        whose state is already OCCUPIED never expire."""
        res = self.tree.getResolution()
        cand = self._uncertain_keys(left, res)
        if not len(cand):
            return 0
        xyz = key_centres(cand, res)
        # the cell and its 8 neighbours against this look's hits
        k = unpack(cand)
        near_hit = np.zeros(len(cand), bool)
        look_keys = np.asarray(look_keys, np.int64)
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                near_hit |= np.isin(pack(k + np.array([di, 0, dj])), look_keys)
        counted = self._in_view_clear(xyz[:, [0, 2]], fs, R, left, res) & ~near_hit
        for key in cand[near_hit]:
            self.unseen.pop(int(key), None)
        expired = 0
        for key in cand[counted]:
            key = int(key)
            n = self.unseen.get(key, 0) + 1
            self.unseen[key] = n
            if n >= self.expire_uncertain and key not in self.expired:
                self.expired[key] = float("nan")      # its log-odds, read after this look
                expired += 1
        self.expired_total += expired
        return expired

    def _in_view_clear(self, xz, fs, R, left, res: float) -> np.ndarray:
        """Which floor points ``xz`` ((N, 2) room x, z) this look had IN VIEW
        with nothing located before them: in the picture's columns (the floor
        scan's own placement of a column's range, ``place="axis"``, inverted),
        from ``near_ft`` on (nearer, the lowest obstacle is below the picture)
        to ``max_range_ft``, and nearer by a cell than the column's bound in
        this look (its hit, or the end of its free sight line between two
        hits) in the point's column and the one each side; a column showing
        nothing at all has no bound."""
        xz = np.asarray(xz, float).reshape(-1, 2)
        # the column of each point: v = s * (u * a + b), a, b the levelled
        # right and forward axes of the camera (floor_scan's "axis" placement)
        a = R[[0, 2], 0]
        b = R[[0, 2], 2]
        v = xz - left[[0, 2]]
        M = np.array([[a[0], b[0]], [a[1], b[1]]])
        su, s = np.linalg.solve(M, v.T)
        d = np.hypot(v[:, 0], v[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            col = np.where(s > 0, su / s * FOCAL_128 + CX_128 + 0.5, -1.0)
        c = np.round(col).astype(int)
        inview = (s > 0) & (c >= 2) & (c <= 127) & (d >= self.near_ft) & \
            (d <= self.max_range_ft)
        bound = np.full(130, np.inf)                 # 1-based columns, with a pad each side
        for pts, cols, ok in ((fs.hits, fs.hit_cols, None),
                              (fs.free_ends, fs.free_cols, None if fs.assumed is None
                               else ~np.asarray(fs.assumed, bool))):
            if cols is None or not len(pts):
                continue
            dist = np.hypot(pts[:, 0] - left[0], pts[:, 2] - left[2])
            cc = np.asarray(cols, int)
            sel = np.ones(len(cc), bool) if ok is None else ok
            np.minimum.at(bound, cc[sel], dist[sel])
        cs = np.clip(c, 1, 128)
        nearest = np.minimum(np.minimum(bound[cs - 1], bound[cs]), bound[cs + 1])
        return inview & (d <= nearest - res)

    def expire_features_in_view(self, fs, R, left, ids) -> int:
        """``expire_uncertain`` under ``occupied="model"``: count this look
        against every alive floor feature fused from fewer than
        ``confirm_looks`` looks (drawn UNCERTAIN) that it had in view
        (:meth:`_in_view_clear`) without locating it, and retire the feature
        after ``expire_uncertain`` such looks.  Its cells then show what the
        octree holds (as after :meth:`retire`): the hit's own cell UNKNOWN
        (hit cells count only as seen), the grown ones free only where the
        looks carved them, as they were before the feature covered them.  A
        feature this look fused (``ids``, :meth:`FloorFeatures.add_look`), or with one
        of this look's hits within two standard deviations and a cell of it,
        starts its count over: a real corner seen again shows again.
        Confirmed features never expire.  Returns the features retired."""
        f = self.features
        if not len(f.mean):
            return 0
        res = self.tree.getResolution()
        if len(self.feature_unseen) < len(f.mean):
            self.feature_unseen = np.concatenate(
                [self.feature_unseen, np.zeros(len(f.mean) - len(self.feature_unseen), int)])
        seen = np.zeros(len(f.mean), bool)
        ids = np.asarray(ids, int)
        seen[ids[ids >= 0]] = True
        cand = np.flatnonzero(f.alive & (f.looks < self.confirm_looks) & ~seen)
        cand = cand[np.hypot(f.mean[cand, 0] - left[0], f.mean[cand, 1] - left[2])
                    <= self.max_range_ft + res]
        if self.expire_within is not None and len(cand):
            # only the features whose two-sigma growth reaches that disc (the goal's)
            (gx, gz), r = self.expire_within
            reach = 2.0 * np.sqrt(np.linalg.eigvalsh(f.cov[cand])[:, -1])
            cand = cand[np.hypot(f.mean[cand, 0] - gx, f.mean[cand, 1] - gz) - reach <= r]
        if len(cand) and len(fs.hits):
            near = mahalanobis2(f.mean[cand], f.cov[cand] + res ** 2 * np.eye(2),
                                fs.hits[:, [0, 2]], np.zeros((len(fs.hits), 2, 2)))
            close = (near <= 4.0).any(1)
            seen[cand[close]] = True
            cand = cand[~close]
        self.feature_unseen[seen] = 0
        if not len(cand):
            return 0
        counted = cand[self._in_view_clear(f.mean[cand], fs, R, left, res)]
        self.feature_unseen[counted] += 1
        gone = np.zeros(len(f.mean), bool)
        gone[counted[self.feature_unseen[counted] >= self.expire_uncertain]] = True
        n = f.retire(gone)
        self.expired_total += n
        return n

    def _uncertain_keys(self, left, res: float) -> np.ndarray:
        """Packed keys of the floor-slab cells any look hit that are UNCERTAIN
        now (before this look), within range of ``left``."""
        keys = self.hit_keys
        if not len(keys):
            return keys
        xyz = key_centres(keys, res)
        keys = keys[np.hypot(xyz[:, 0] - left[0], xyz[:, 2] - left[2])
                    <= self.max_range_ft + res]
        if not len(keys):
            return keys
        lo = logodds_at(self.tree, keys)
        unc = (lo >= 0) & (lo < self.tree.getOccupancyThresLog())    # NaN: neither
        return keys[unc]

    def _apply_expired(self, fm: FloorMap) -> None:
        """Show the expired cells UNKNOWN: those still uncertain whose log-odds
        have not risen since they expired (a later hit revives a cell, a
        later sight line through it may clear it as before)."""
        if not self.expired:
            return
        res = self.tree.getResolution()
        keys = np.fromiter(self.expired.keys(), np.int64, len(self.expired))
        then = np.fromiter(self.expired.values(), float, len(self.expired))
        lo = logodds_at(self.tree, keys)
        then = np.where(np.isnan(then), lo, then)       # expired this look: read now
        for key, t in zip(keys, then):
            self.expired[int(key)] = float(t)
        revived = ~(lo <= then + 1e-9)                  # raised by a hit (or gone)
        for key in keys[revived]:
            self.expired.pop(int(key), None)
            self.unseen.pop(int(key), None)
        occ_lo = self.tree.getOccupancyThresLog()
        show = ~revived & (lo >= 0) & (lo < occ_lo)
        if not show.any():
            return
        k = unpack(keys[show])
        i = k[:, 2] - int(round(fm.z0 / res))
        j = k[:, 0] - int(round(fm.x0 / res))
        ok = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        i, j = i[ok], j[ok]
        sel = fm.cells[i, j] == UNCERTAIN
        fm.cells[i[sel], j[sel]] = UNKNOWN

    def _carve_floor(self, fs, rays, top, left, res: float, reach=None) -> int:
        """Carve each column's floor in view (:func:`planner.appearance.floor_proof`),
        cut at the floor scan's own bound of that column (its hit, or the end
        of its free sight line: the near end of its neighbours' error bound,
        or the blank-column reach) and at ``reach`` when given (the column's
        floor end, :func:`planner.appearance.floor_end`; 0: nothing), never
        past a cell any look has hit."""
        return self._carve_keys(self._floor_keys(fs, rays, top, left, res, reach), res)

    def _floor_keys(self, fs, rays, top, left, res: float, reach=None) -> np.ndarray:
        """The packed keys of the cells :meth:`_carve_floor` carves, uncarved."""
        clip = np.zeros(128)
        for pts, cols in ((fs.hits, fs.hit_cols), (fs.free_ends, fs.free_cols)):
            if cols is None or not len(pts):
                continue
            d = np.hypot(pts[:, 0] - left[0], pts[:, 2] - left[2])
            c = np.asarray(cols, int) - 1
            ok = (c >= 0) & (c < 128)
            np.maximum.at(clip, c[ok], d[ok])
        if reach is not None:
            clip = np.minimum(clip, reach)
        proof = floor_proof(rays, top, clip, self.lowest_ft, res,
                            lead_in=self.proof_hits == "line")
        if proof is None:
            return np.zeros(0, np.int64)
        pts, ray, _, proving = proof
        keys = cell_keys(pts, res)
        keep = keep_before_hit(keys, ray, self.hit_keys) & proving
        keep &= ~np.isin(keys, self._shadow_keys)   # free_cells="shadows"
        return np.unique(keys[keep])

    def _carve_keys(self, keys, res: float) -> int:
        """The floor in view's cells ``keys`` carved free; returns how many."""
        if not len(keys):
            return 0
        self.tree.updateNodes(np.ascontiguousarray(key_centres(keys, res)), False)
        self.floor_cells += len(keys)
        self._proved = np.union1d(self._proved, keys)
        return len(keys)

    def _carve_flat_foot(self, fs, rays, top, proof_top, reach, scan_points, heading_sd,
                         left, res: float) -> int:
        """``wall_runs="flat-foot"`` (not 1985), on a flat floor: the columns whose run
        shows no end (up to the picture's top row, or past the plan's walls) prove the
        floor to the walls' foot (:func:`planner.appearance.wall_foot_reach`), as a wall
        of the floor's grey shows it, but cut at every located point within
        :data:`FLAT_FOOT_BESIDE_FT` sideways (:func:`planner.appearance.beside_points`:
        a box face of that grey stands beside its own edges), under the look's other
        checks (points raised off the floor, the heading's window), and a cell is
        carved only when a look from a bearing :data:`FLAT_FOOT_APART_DEG` away proves
        it too (:class:`planner.perception.BearingsApart`): seen head on, such a face
        shows no edge at all.  Returns the cells carved."""
        to_top, past = no_end(rays, top, self.floor_within, heading_sd or 0.0)
        foot = wall_foot_reach(rays, self.floor_within, heading_sd or 0.0)
        shown = (to_top | past) & (foot > 0)
        if not shown.any():
            return 0
        far = np.where(shown, foot, reach)
        if self.floor_end_check != "off":
            far = raised_ends(scan_points, rays, top, far, min_range_ft=self.min_range_ft)
        far = beside_points(scan_points, rays, far, shown, FLAT_FOOT_BESIDE_FT,
                            self.min_range_ft)
        if self.proof_heading == "window" and heading_sd is not None:
            far = within_heading(far, heading_sd, self.heading_sigmas)
        keys = self._floor_keys(fs, rays, proof_top, left, res, np.where(shown, far, 0.0))
        keys = np.setdiff1d(keys, self._proved)
        if not len(keys):
            return 0
        keys = self.foot_bearings.confirm(keys, key_centres(keys, res)[:, [0, 2]],
                                          (left[0], left[2]))
        return self._carve_keys(keys, res)

    def _raised_by_motion(self, rays, top, reach, left, res: float):
        """``floor_end_check="motion"``: the look's floor ends ``reach``
        (:func:`~planner.appearance.floor_end`) cut where their end moved with
        the camera since two earlier looks (:func:`~planner.appearance.raised_columns`):
        the run went on up a face of the floor's grey to an edge above the
        floor, and its column proves the floor only to below that edge.  At
        least :data:`RAISED_MIN_COLUMNS` such columns are needed.  Their edge
        points, and the stretches between neighbouring ones, are drawn
        occupied (:meth:`_draw_raised`): kept, and never passed by a later
        proof, where an earlier look found the edge too (within
        :data:`RAISED_AGAIN_FT`); held for :data:`RAISED_HOLD` looks where not.
        Returns (the floor ends, this look's end points by column, NaN where
        its run shows no end at a grey change)."""
        cols = np.arange(len(reach))
        # the run's own end, not a texture's or a wall's (run_reach is 0 where it has none)
        at_grey = (reach > 0) & np.isclose(reach, run_reach(rays, top))
        r = np.minimum(top, ROWS - 1)
        ends = np.full((len(reach), 2), np.nan)
        ends[at_grey] = np.column_stack([rays.x[r, cols], rays.z[r, cols]])[at_grey]
        c = np.asarray(left, float)[[0, 2]]
        k = raised_columns(ends, c, self.end_looks, RAISED_MIN_COLUMNS)
        raised = np.flatnonzero(np.isfinite(k))
        if not len(raised):
            return reach, ends
        edge = c + (ends[raised] - c) / k[raised, None]
        reach = np.array(reach, float)
        reach[raised] = np.minimum(reach[raised], np.hypot(*(edge - c).T))
        self.raised_columns += len(raised)
        # neighbouring raised columns (a gap of at most two) on one edge: the face between them
        joined = (np.diff(raised) <= 3) & (np.hypot(*np.diff(edge, axis=0).T) <= RAISED_JOIN_FT)
        # an edge point an earlier look found too is kept; the others are held only for
        # RAISED_HOLD looks: one look's estimate gone wrong moves all its ends at once
        # (room 157: 3.9 deg off at look 14, mended at look 15)
        before = [e for _, e, _, _ in self.raised_seen]
        again = np.zeros(len(edge), bool)
        if before:
            before = np.vstack(before)
            again = np.hypot(*(edge[:, None, :] - before[None, :, :]).transpose(2, 0, 1)) \
                .min(1) <= RAISED_AGAIN_FT
        pair = joined & again[:-1] & again[1:]
        a, b = np.vstack([edge[again], edge[:-1][pair]]), np.vstack([edge[again], edge[1:][pair]])
        held = joined & ~pair
        self.raised_seen.append((self.look_no, edge, np.vstack([edge[~again], edge[:-1][held]]),
                                 np.vstack([edge[~again], edge[1:][held]])))
        if len(a):
            self.raised_a = np.vstack([self.raised_a, a])
            self.raised_b = np.vstack([self.raised_b, b])
            cells = (segment_cells(a, b, res) + 0.5) * res
            self.hit_keys = np.union1d(self.hit_keys, cell_keys(np.column_stack(
                [cells[:, 0], np.full(len(cells), left[1]), cells[:, 1]]), res))
        return reach, ends

    def _keep_ends(self, ends, left, res: float) -> None:
        """Keep this look's floor ends ``ends`` (by column, NaN: none) and the
        cells its floor in view proved for :meth:`_raised_by_motion`."""
        proved = self._proved
        y = float(left[1])

        def proves(xz):
            xz = np.asarray(xz, float).reshape(-1, 2)
            pts = np.column_stack([xz[:, 0], np.full(len(xz), y), xz[:, 1]])
            return np.isin(cell_keys(pts, res), proved)

        ends = ends[np.isfinite(ends[:, 0])]
        self.end_looks = (self.end_looks + [LookEnds(np.asarray(left, float)[[0, 2]], ends,
                                                     proves)])[-RAISED_LOOKS:]

    def raised_now(self) -> np.ndarray | None:
        """The edge points (x, z) the last look found raised
        (:meth:`_raised_by_motion`), in column order, or None."""
        if self.raised_seen and self.raised_seen[-1][0] == self.look_no:
            return self.raised_seen[-1][1]
        return None

    def _draw_raised(self, fm: FloorMap) -> None:
        """The edges :meth:`_raised_by_motion` found raised, occupied on ``fm``:
        those found again, and the others of the last :data:`RAISED_HOLD` looks."""
        held = [(a, b) for n, _, a, b in self.raised_seen if n > self.look_no - RAISED_HOLD]
        a = np.vstack([self.raised_a] + [a for a, _ in held])
        b = np.vstack([self.raised_b] + [b for _, b in held])
        if len(a):
            fm.cells[cells_mask(fm, segment_cells(a, b, fm.cell))] = OCCUPIED

    def retire(self, origin, within_ft: float) -> int:
        """Retire the floor features within ``within_ft`` of ``origin`` whose
        cell later looks have seen through: its log-odds in the octree below
        the free threshold (more misses than hits)."""
        f = self.features
        sel = np.flatnonzero(f.alive)
        if not len(sel):
            return 0
        sel = sel[np.hypot(f.mean[sel, 0] - origin[0], f.mean[sel, 1] - origin[2]) <= within_ft]
        if not len(sel):
            return 0
        res = self.tree.getResolution()
        xyz = np.column_stack([f.mean[sel, 0], np.full(len(sel), origin[1]), f.mean[sel, 1]])
        keys = cell_keys(xyz, res)
        uniq, inv = np.unique(keys, return_inverse=True)
        lo = logodds_at(self.tree, uniq)[inv]
        through = np.zeros(len(f.alive), bool)
        through[sel] = lo < free_below(self.free_looks)       # NaN (unknown): not seen through
        n = f.retire(through)
        self.retired += n
        return n

    def _extend(self, xz):
        if len(xz) == 0:
            return
        lo, hi = xz.min(0), xz.max(0)
        self.lo = lo if self.lo is None else np.minimum(self.lo, lo)
        self.hi = hi if self.hi is None else np.maximum(self.hi, hi)

    def floor_map(self, around) -> FloorMap:
        pts = np.asarray(around, float).reshape(-1, 2)
        lo, hi = pts.min(0), pts.max(0)
        if self.lo is not None:
            lo, hi = np.minimum(lo, self.lo), np.maximum(hi, self.hi)
        margin = 2.0
        fm = project_octree(self.tree, (lo[0] - margin, hi[0] + margin, lo[1] - margin,
                                        hi[1] + margin), self.band, margin=0.0,
                            free_looks=self.free_looks, free_band=self.free_band)
        if self.occupied == "model":
            self._draw_features(fm)
        elif self.expire_uncertain or self.refute_hits != "off":
            self._apply_expired(fm)
        self._draw_raised(fm)
        if self.pivot_proof is not None and self.provenance is not None:
            fm.assumed = assumed_columns(fm, self.provenance, self.tree.getResolution(),
                                         self.band, self.blank_near, self.pivot_proof)
        return fm

    def _draw_features(self, fm: FloorMap, within: np.ndarray | None = None) -> None:
        """The occupied and uncertain cells regenerated from the floor
        features; the octree's hit cells count only as seen, not free.  With
        ``within`` (a mask of ``fm``), only there: the rest of the map as it is."""
        redraw = (fm.cells == OCCUPIED) | (fm.cells == UNCERTAIN)
        if within is not None:
            redraw &= within
        fm.cells[redraw] = UNKNOWN
        occ, unc = self.features.cells(fm.cell, self.confirm_looks)
        for cells, st in ((unc, UNCERTAIN), (occ, OCCUPIED)):        # occupied wins
            mask = cells_mask(fm, cells)
            fm.cells[mask if within is None else mask & within] = st
        if self.draw_core:
            one_sigma = cells_mask(fm, self.features.uncertain_cells(fm.cell, self.confirm_looks,
                                                                     1.0))
            if within is None:
                fm.uncertain_core = one_sigma
            else:
                kept = fm.uncertain_core if fm.uncertain_core is not None else \
                    np.zeros(fm.shape, bool)
                fm.uncertain_core = (kept & ~within) | (one_sigma & within)
            fm.uncertain_core &= fm.cells == UNCERTAIN

    def halved_map(self, fm: FloorMap, walls=None) -> FloorMap:
        """``fm`` (a map this model drew: :meth:`floor_map`, with the track,
        the walls and the rest laid on it) on cells of half the side, for the
        search (``DriveConfig.fine_map``; not 1985): every cell split in four
        as it is, except the cells the features or the plan's ``walls`` (x0,
        x1, z0, z1) blocked, where the features and the walls are drawn again
        on the half cells.  What the looks proved free or left unknown is not
        resolved any finer: only the blocked cells shrink toward the features
        and walls that blocked them (a feature 0.05 ft inside a 0.25 ft cell
        blocked all of it), never grow."""
        fine = fm.halved()
        blocked = (fm.cells == OCCUPIED) | (fm.cells == UNCERTAIN)
        if self.occupied != "model":
            # a look's hits block their cells as the octree holds them: only the walls
            blocked &= walls_mask(fm, walls) if walls is not None else False
        # (under "model" every blocked cell is a feature's or a wall's: _draw_features
        # turned the octree's own hit cells unknown, and nothing after it blocks a cell
        # but mark_walls)
        within = split_in_four(blocked)
        if self.occupied == "model":
            self._draw_features(fine, within)
        else:
            fine.cells[within] = UNKNOWN
        self._draw_raised(fine)
        if walls is not None:
            mark_walls(fine, walls)
        return fine


def _near_free(fm: FloorMap, origin, ends, near_ft: float) -> np.ndarray:
    """Mask of the sight lines ``origin -> end`` whose part nearer than
    ``near_ft`` lies on cells FREE on ``fm`` (outside it: unknown)."""
    origin = np.asarray(origin, float)
    d = np.asarray(ends, float)[:, [0, 2]] - origin[[0, 2]]
    unit = d / np.maximum(np.linalg.norm(d, axis=1), 1e-12)[:, None]
    t = np.arange(0.0, near_ft + 1e-9, fm.cell / 2)
    x = origin[0] + unit[:, None, 0] * t[None]
    z = origin[2] + unit[:, None, 1] * t[None]
    i = np.floor((z - fm.z0) / fm.cell).astype(int)
    j = np.floor((x - fm.x0) / fm.cell).astype(int)
    nz, nx = fm.cells.shape
    inside = (i >= 0) & (i < nz) & (j >= 0) & (j < nx)
    free = np.zeros(i.shape, bool)
    free[inside] = fm.cells[i[inside], j[inside]] == FREE
    return free.all(1)


def walls_mask(fm: FloorMap, bounds) -> np.ndarray:
    """(nz, nx) bool: the cells of ``fm`` reaching past the walls ``bounds``
    (x0, x1, z0, z1)."""
    nz, nx = fm.shape
    xs = fm.x0 + np.arange(nx + 1) * fm.cell
    zs = fm.z0 + np.arange(nz + 1) * fm.cell
    bx0, bx1, bz0, bz1 = bounds
    out_x = (xs[:-1] < bx0) | (xs[1:] > bx1)
    out_z = (zs[:-1] < bz0) | (zs[1:] > bz1)
    return out_z[:, None] | out_x[None, :]


def mark_walls(fm: FloorMap, bounds) -> None:
    """The floor plan: every cell reaching past the walls is occupied."""
    fm.cells[walls_mask(fm, bounds)] = OCCUPIED


def cells_mask(fm: FloorMap, cells) -> np.ndarray:
    """(nz, nx) bool: the integer cells ``cells`` ((M, 2): floor(x / cell),
    floor(z / cell)) that lie on ``fm``."""
    i0, j0 = int(round(fm.z0 / fm.cell)), int(round(fm.x0 / fm.cell))
    cells = np.asarray(cells, np.int64).reshape(-1, 2)
    i, j = cells[:, 1] - i0, cells[:, 0] - j0
    ok = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    out = np.zeros(fm.shape, bool)
    out[i[ok], j[ok]] = True
    return out


WALL_SIGMAS = 2.0       # the assumed floor kept off the plan's walls by 2 sigma (as features grow)


def wall_growth(pose_cov, sigmas: float = WALL_SIGMAS) -> tuple[float, float]:
    """How far inside the floor plan's walls the blank-column assumption stops
    on a map placed by a pose estimate with (x, z, heading) covariance
    ``pose_cov``: ``sigmas`` standard deviations of the estimate's x (the side
    walls) and z (the near and far walls), each at most
    :data:`planner.octree.MAX_GROWTH_FT` as a feature's growth is.  Why: the
    looks are placed by the estimate, the plan by the room's truth; with the
    estimate off by d a blank column's assumed floor (``blank_ft``), stopped
    only by the plan's wall, runs d past the wall the vehicle will meet (room 7
    under ``--head assist``: 1.05 ft of drift, a pivot into the side wall)."""
    cov = np.asarray(pose_cov, float)
    return tuple(float(min(sigmas * math.sqrt(max(cov[k, k], 0.0)), MAX_GROWTH_FT))
                 for k in (0, 1))


def wall_explained(obs, obs_cov, bounds, sigmas: float = WALL_SIGMAS) -> np.ndarray:
    """(N,) bool: the floor hits ``obs`` ((N, 2) x, z) whose ``sigmas`` ellipse
    (``obs_cov`` (N, 2, 2), the pose's share in it) reaches a wall of the floor plan
    ``bounds`` (x0, x1, z0, z1), or that lie past one: the plan's wall explains them.
    ``DriveConfig.wall_hits="plan"`` (not 1985) starts no floor feature from them:
    a wall's own points, located short of it by their range error, grow into the
    floor as features (room 119: at look 2 the right wall's, hit once just before it,
    narrow the way along it and the drive goes round the far side, to stop "narrower"
    after 51 looks; under "plan" it drives along the wall, 11 looks to the goal)."""
    o = np.asarray(obs, float).reshape(-1, 2)
    c = np.asarray(obs_cov, float).reshape(-1, 2, 2)
    x0, x1, z0, z1 = bounds
    reach_x = sigmas * np.sqrt(np.maximum(c[:, 0, 0], 0.0))
    reach_z = sigmas * np.sqrt(np.maximum(c[:, 1, 1], 0.0))
    return (o[:, 0] - reach_x <= x0) | (o[:, 0] + reach_x >= x1) | \
        (o[:, 1] - reach_z <= z0) | (o[:, 1] + reach_z >= z1)


def within_walls(origin, ends, bounds, res: float) -> np.ndarray:
    """The sight lines ``origin -> end`` (room x, y, z) cut where they leave
    the floor ``bounds`` (x0, x1, z0, z1), a cell past it (the carving stops a
    cell short of its end, so the last cell inside is still reached); a line
    from outside them keeps nothing (its end at the origin)."""
    o = np.asarray(origin, float)
    ends = np.asarray(ends, float).reshape(-1, 3)
    d = ends - o
    length = np.linalg.norm(d, axis=1)
    t = np.ones(len(ends))
    for k, (lo, hi) in ((0, bounds[:2]), (2, bounds[2:])):
        if not lo <= o[k] <= hi:
            return np.repeat(o[None], len(ends), 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            tk = np.where(d[:, k] > 0, (hi - o[k]) / d[:, k],
                          np.where(d[:, k] < 0, (lo - o[k]) / d[:, k], np.inf))
        t = np.minimum(t, tk)
    t = np.minimum(1.0, t + res / np.maximum(length, 1e-12))
    return o + t[:, None] * d


def floor_stats(model: "Perception") -> dict:
    """What the floor in view did in one drive (planner.appearance)."""
    g = floor_greys(model.floor_hist)
    return {"floor_greys": [] if g is None else np.flatnonzero(g).tolist(),
            "floor_samples": int(model.floor_hist.sum()), "floor_cells": int(model.floor_cells),
            "vetoed_points": int(model.vetoed), "raised_columns": int(model.raised_columns)}


def tracing_perception(made: list):
    """A :class:`Perception` factory for ``planner.loop.run(perception_factory=)``:
    each Perception it builds keeps a :class:`FreeProvenance` (which carving
    freed each cell; the drive is the same) and is appended to ``made``, so
    the caller can read it after the run (``bench/drive.py --losses``)."""
    def make(*args):
        model = Perception(*args)
        model.provenance = FreeProvenance()
        made.append(model)
        return model
    return make
