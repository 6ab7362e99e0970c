"""The closed loop of the goal-achievement system (Chapter I's goal, Chapter
IV's design): look -> scan -> model update -> camera estimate -> octree ->
floor map -> plan -> execute the next command segment -> repeat, "modifying
the path as needed during the traversal".

* **look**: the world renders both cameras at the vehicle's TRUE pose;
* **scan**: the rig's whole-picture scan of the pair (:func:`scan_look`): by the eyes
  (``eyes.scan_pair``, the compiled 1985 frame scan, bit for bit ``rig.scan.scan_pair``)
  with ``match="1985"`` (the default), or with ``match="improved"`` (``rig drive --match
  improved``, not 1985) by the in-process rig with the improved matcher of package
  ``matching`` (``rig.scan.scan_pair(..., matcher=make_matcher("improved"))``, as ``rig walk
  --match improved``): a verdict per edge, so an edge without a right match is left out
  instead of located at the best available;
* **model update / camera estimate**: ``pose="fused"`` (``rig drive --pose
  fused``) runs the walk's per-look step (:class:`model.mapping.Walker`) on the
  same scan: vertical edges and vertices into the symbolic model, matched to it
  from the odometry's prior, the driving method's fix fused with that prior by
  their covariances; that pose places the look.  ``pose="dead_reckoning"``
  places it at the dead-reckoned pose, unchanged.  Either way the octree is
  built from the located points of every look (:class:`Perception`);
* **octree**: each look enters as a floor range scan
  (:func:`planner.perception.floor_scan`): per picture column the nearest
  range two located points agree on, hit (grown by its covariance, surfaces
  between neighbours at one range) and its sight line carved free from
  ``near_visible_ft`` on (nearer, the lowest obstacle is below the picture);
  the columns between two such columns free up to the nearer; columns outside
  all of them free up to ``blank_ft``.  One update per cell per look, so
  inserting a look equals regenerating the tree from all looks while no
  earlier feature moves (true of the dead-reckoned adapter).  A cell is
  believed occupied once ``confirm_looks`` looks hit it (uncertain before).
  ``occupied="model"`` (a named option, :mod:`planner.features`) instead
  draws the occupied and uncertain cells each cycle from floor features
  fused look by look, each grown by its fused covariance (Chapter IV's
  octree "regenerated from the symbolic model"); the free space is the same
  sight-line carving;
* **plan**: the floor map over the vehicle's height band, grown by the
  vehicle's radius, searched by the dissertation's search (or A*), pulled
  taut, turned into motion commands;
* **execute**: the first ``step`` feet of the commands, cut where the
  vehicle would come within its radius of an occupied or uncertain cell, or
  its swept width (and nose) would enter a cell not seen free; a pivot needs
  its circle seen free; after a turn of more than 15 deg it looks first.  ``trust_view``
  (off by default) also lets it into never-seen cells inside the field of view
  just looked at, while it still faces that way: a blank wall gives the
  edge-based eyes no points at all, so this drives into blank walls (measured:
  the bundled lab's back wall) and is kept only as a named experiment.

The vehicle is set down in a clear spot (``start_clear_ft``, 2.5 ft, as the
generated rooms keep around the start): a look proves nothing nearer than
``near_visible_ft`` (2.3 ft with the default profile), so without this it
could not start.

The room's walls are given as a floor plan (``known_walls``, on by
default; the furniture is not): the edge-based eyes find no points on a
blank wall, and a false far match would otherwise let a sight line through
it (measured on the bundled lab: without the plan the vehicle drove into the
left wall).

When no path to the goal exists on the map (with unknown space blocked, or
the goal looking blocked from afar), the vehicle heads for the reachable cell
nearest the goal; when it cannot move at all it turns to look
(toward the goal first, then sweeping), and gives up with the planner's reason
after ``max_stuck`` looks without progress.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import cv2
import numpy as np

from vehicle.commands import Back, Forward, Turn, format_commands
from vehicle.profile import DEFAULT, VehicleProfile
from vehicle.sim import State, Vehicle, odometry_covariance
from .floormap import FLOOR_Y, FloorMap, empty_map, project_octree, true_floor_map
from .octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest, cell_centres, \
    cell_keys, features_cells, mark_assumed_free, mark_free_rays, mark_occupied, memory_bytes, \
    new_octree, spans_cells
from .features import FloorFeatures, pose_point_covariance
from .octree import _pack, _unpack, free_below, key_centres, logodds_at
from .depth_eyes import depth_floor_scan
from .perception import CX_128, FOCAL_128, MAX_RANGE_FT, PLACES, BLANK_LIMITS, floor_scan
from .perception import BLANK_SIDES, TwoLookSides
from .octree import assumed_free_keys, mark_keys_free
from .appearance import floor_greys, floor_proof, floor_rays, floor_run, keep_before_hit, \
    training_mask, vetoed
from .search import NoPath, Passable, astar, clearance_at, clearance_map, hierarchical_search, \
    line_of_sight, path_length, segment_samples
from .trajectory import heading_to, next_segment, shorten, to_commands, wrap

SEARCHES = {"dissertation": hierarchical_search, "astar": astar}
POSES = ("fused", "dead_reckoning")
UNCERTAIN_PLANS = ("blocked", "look")
LOOK_AROUNDS = ("sweep", "evidence")
PROGRESSES = ("moved", "evidence")
TRACK_FREES = ("poses", "swept")
PIVOTS = ("disc", "swept")            # what a pivot needs seen free (DriveConfig.pivot)
EYES = ("rig", "truth", "depth")      # whose ranges the loop sees (DriveConfig.eyes)
MATCHES = ("1985", "improved")        # the rig's stereo matcher (matching.mode.MODES)
OCCUPIEDS = ("looks", "model")        # where the map's occupied cells come from
FEATURE_POSES = ("absolute", "drift", "none")    # the pose's share in a feature's covariance
GOALS = ("point", "disc")             # what the planner plans to: the goal point, or the
                                      # standable cells of the tolerance disc (goal_target)
FLOOR_EYES = ("off", "carve", "add", "veto")   # planner.appearance in the loop (Perception.update)
GOAL_SLACK_FT = 0.1                   # a target cell's centre this far inside the disc
PENDING_LOOKS = 6            # how long a located point waits for confirmation


@dataclass
class DriveConfig:
    goal: tuple[float, float]
    unknown: str = "free"                 # planning through unknown space: "free" | "blocked"
    search: str = "dissertation"          # "dissertation" | "astar"
    profile: VehicleProfile = DEFAULT
    tolerance_ft: float = 0.75            # goal reached when the estimate is this near
    max_looks: int = 60
    max_stuck: int = 8                    # looks without progress before giving up
    lines: tuple = tuple(range(8, 113, 2))
    voi: VolumeOfInterest = VolumeOfInterest(32.0, 7)
    band: tuple[float, float] = (-0.5, FLOOR_Y - 0.25)   # room Y of the vehicle's passage
    supersample: int = 2                  # render rays per pixel side (1985's pair used 4)
    look_seed: int = 1985                 # sensor noise of look k uses look_seed + k
    max_range_ft: float = MAX_RANGE_FT
    confirm_looks: int = 2                # looks that must hit a cell before it is believed
    free_looks: int = 1                   # carvings that must cross a cell before it is free
    keep_ft: float = 3.0                  # keep the old path unless a new one is this much shorter
    trust_view: bool = False              # drive into never-seen cells of the view just looked at
    known_walls: bool = True              # the room's walls as a floor plan (furniture unknown)
    start_clear_ft: float = 2.5           # the vehicle is set down this far from anything
    match: str = "1985"                   # the rig's stereo matcher: "1985" (the eyes, bit
                                          # for bit) or "improved" (package matching, on the
                                          # in-process rig: several times slower; scan_look)
    eyes: str = "rig"                     # "rig": the matcher's ranges; "truth": the
                                          # true range at the same edge pixels (an oracle
                                          # that separates the planner from the matcher);
                                          # "depth": the true range at EVERY pixel, a dense
                                          # range finder (a diagnostic oracle that
                                          # separates the planner from the eyes;
                                          # planner.depth_eyes)
    lowest_obstacle_ft: float = 0.8       # nothing lower stands on the floor (the rooms' boxes)
    blank_ft: float | None = 8.0          # columns showing nothing: free this far (assumption)
    blank_carve: str = "unknown"          # how the blank-column assumption carves: "unknown":
                                          # only cells no look has seen, never past a cell any
                                          # look hit, only past a near zone seen free
                                          # (Perception.update); "always": as a proven sight
                                          # line (so it carved through blank box faces: a
                                          # collision in room 40)
    carve: str = "error"                  # perception.floor_scan's carve: "error": to the
                                          # near end of an edge's bound; "range": to its range
                                          # (0.2-0.45 ft into a face in room 40)
    blank_px: int | None = 16             # the blank-column assumption only this many picture
                                          # columns beside a located one (floor_scan's
                                          # blank_px: half max_gap_px, as between two edges);
                                          # None: the whole blank run (a box whose edges no
                                          # look located was carved: collision in room 45)
    blank_limit: str = "all"              # where blank_px applies (floor_scan's blank_limit):
                                          # "all": beside the outermost edges and inside wide
                                          # gaps; "sides": only beside the outermost edges
    blank_sides: str = "two-looks"        # the side columns blank_px cuts off: "two-looks"
                                          # (since 2026-12-01 16:35): a cell carved where two
                                          # looks sides_apart apart both saw it blank
                                          # (TwoLookSides); "cut": never carved
    sides_apart: tuple[float, float] = (1.0, 20.0)   # (ft, deg): how far apart two looks are
    safety: str = "swept"                 # "strict": the whole pivot disc seen free;
                                          # "swept": the swept width seen free, no known
                                          # obstacle within the radius
    pivot: str = "disc"                   # what a pivot in place needs seen free: "disc":
                                          # its whole circle (the footprint's half
                                          # diagonal), whatever the angle; "swept": the
                                          # cells the footprint, grown by the margin, sweeps
                                          # through the angle (_pivot_seen_free)
    clearance_at: str = "anywhere"        # "anywhere": the dissertation's, the cross section
                                          # passes anywhere in a passable cell; "centre":
                                          # a cell's centre has the radius and every
                                          # position is tested exactly (search.clearance_map)
    growth: str = "covariance"            # "covariance": a hit grown by its whole covariance
                                          # (the dissertation's); "across": by its error
                                          # across the sight line only (across_sight_cov)
    pose: str = "dead_reckoning"          # the camera estimate: "fused" (the symbolic
                                          # model's, model.mapping.Walker) or
                                          # "dead_reckoning" (the odometry alone)
    pose_method: str = "robust"           # the walk's driving method under "fused"
    look_around: str = "sweep"            # the vehicle cannot move: "sweep": face the
                                          # path, then turn +35 / -70 deg in place;
                                          # "evidence" (measured, not adopted): look at
                                          # where the path lacks it, from where it shows
                                          # (_fetch_evidence)
    track_free: str = "poses"             # free where the vehicle stood: "poses": its
                                          # footprint at each pose; "swept" (a named
                                          # option): every pose between as well, shrunk
                                          # by the margin (_mark_track_free)
    progress: str = "moved"               # what resets the count toward max_stuck:
                                          # "moved": any motion; "evidence" (measured, not
                                          # adopted): a shorter way left than ever, or new
                                          # free space seen
    occupied: str = "looks"               # the map's occupied / uncertain cells: "looks":
                                          # every look's hits as log-odds, grown by that
                                          # look's covariance, never shrunk; "model": drawn
                                          # each cycle from the floor features, fused look
                                          # by look (planner.features; Perception.update)
    feature_pose: str = "absolute"        # under occupied="model", the pose error in each
                                          # observation's covariance: "absolute": the
                                          # dead-reckoned pose's whole covariance;
                                          # "drift": the features kept in the dead-reckoned
                                          # frame, an old feature's covariance grown by the
                                          # drift since it was last seen; "none"
    hit_at: str = "axis"                  # where a look's range lands on the floor plane
                                          # (perception.floor_scan's place): "axis": laid
                                          # along the pitched optical axis (short by up to
                                          # its cosine); "point": the located point's own
                                          # horizontal position
    goal_region: str = "point"            # what the planner plans to: "point": the goal
                                          # itself (refused when the map puts an obstacle
                                          # within the planning radius of it); "disc": the
                                          # standable cell reachable from the estimate inside
                                          # the tolerance disc that is nearest the goal
                                          # (goal_target); the loop's success test is the
                                          # disc either way
    floor_eyes: str = "off"               # free floor from what the picture shows
                                          # (planner.appearance, not 1985): "off"; "carve":
                                          # once the floor's grey is learned, each column's
                                          # floor in view carved as a proof in place of the
                                          # blank-column assumption; "add": the floor's
                                          # proof and the assumption (under its own rules)
                                          # both; "veto": "carve" and leave out the located
                                          # points the floor in view contradicts
    expire_uncertain: int = 0             # 0 (off): an uncertain (once-hit) cell stays until
                                          # sight lines clear it; N (a named option, not
                                          # 1985): after N later looks had it in view and
                                          # located nothing there, it shows UNKNOWN (never
                                          # free) on the map (Perception.expire_in_view)
    uncertain: str = "blocked"            # no path avoids the uncertain cells: "blocked":
                                          # toward the reachable cell nearest the goal;
                                          # "look" (measured, not adopted): plan through
                                          # them and look again, never driven near (plan())


@dataclass
class Cycle:
    look: int
    true: State
    estimate: State
    points: int                 # located points in the model
    leaves: int                 # known octree leaves
    path_left_ft: float | None
    command: str
    note: str
    render_s: float
    work_s: float               # scan + model + octree + plan (the look's rendering excluded)
    path: list = field(default_factory=list)
    fmap: FloorMap | None = None
    scan_s: float = 0.0         # the rig's scan alone (part of work_s): the matcher's cost


@dataclass
class DriveResult:
    reached: bool
    reason: str
    looks: int
    travelled_ft: float
    optimal_ft: float | None
    optimal_grid_ft: float | None
    collisions: int
    seconds: float
    cycles: list
    true_track: list
    dead_track: list
    octree_bytes: int
    final_true_error_ft: float
    goal: tuple[float, float]
    start: State
    unknown: str
    search: str
    estimate_track: list = field(default_factory=list)   # the camera estimate, as dead_track
    pose: str = "dead_reckoning"
    match: str = "1985"
    features: FloorFeatures | None = None     # the floor features under occupied="model"
    floor: dict = field(default_factory=dict)  # under floor_eyes: what the floor in view did
    expired_uncertain: int | None = None       # under expire_uncertain: the cells expired

    def track_errors(self, track=None) -> np.ndarray:
        """Distance (ft) of each point of a track (default: the estimate's) from
        the true track at the same step."""
        track = self.estimate_track if track is None else track
        return np.array([math.hypot(a.x - t.x, a.z - t.z) for a, t in zip(track, self.true_track)])

    @property
    def seconds_per_cycle(self) -> float:
        return self.seconds / max(1, len(self.cycles))

    @property
    def work_ms_per_cycle(self) -> float:
        return 1e3 * float(np.mean([c.work_s for c in self.cycles])) if self.cycles else 0.0

    @property
    def scan_ms_per_cycle(self) -> float:
        return 1e3 * float(np.mean([c.scan_s for c in self.cycles])) if self.cycles else 0.0

    @property
    def render_ms_per_cycle(self) -> float:
        return 1e3 * float(np.mean([c.render_s for c in self.cycles])) if self.cycles else 0.0

    def as_json(self) -> dict:
        return {
            "reached": self.reached, "reason": self.reason, "collisions": self.collisions,
            "looks": self.looks, "travelled_ft": round(self.travelled_ft, 3),
            "optimal_ft": None if self.optimal_ft is None else round(self.optimal_ft, 3),
            "optimal_grid_ft": None if self.optimal_grid_ft is None
            else round(self.optimal_grid_ft, 3),
            "seconds_per_cycle": round(self.seconds_per_cycle, 4),
            "work_ms_per_cycle": round(self.work_ms_per_cycle, 2),
            "render_ms_per_cycle": round(self.render_ms_per_cycle, 2),
            "scan_ms_per_cycle": round(self.scan_ms_per_cycle, 2), "match": self.match,
            "seconds": round(self.seconds, 3), "octree_bytes": self.octree_bytes,
            "final_true_error_ft": round(self.final_true_error_ft, 3),
            "start": [self.start.x, self.start.z, self.start.heading_deg],
            "goal": list(self.goal), "unknown": self.unknown, "search": self.search,
            "pose": self.pose, **({"floor": self.floor} if self.floor else {}),
            **({"expired_uncertain": self.expired_uncertain}
               if self.expired_uncertain is not None else {}),
            "estimate_error_ft_final": round(float(self.track_errors()[-1]), 3),
            "dead_reckoning_error_ft_final":
                round(float(self.track_errors(self.dead_track)[-1]), 3),
            "true_track": [[round(s.x, 3), round(s.z, 3), round(s.heading_deg, 2)]
                           for s in self.true_track],
            "estimated_track": [[round(s.x, 3), round(s.z, 3), round(s.heading_deg, 2)]
                                for s in self.estimate_track],
            "dead_reckoned_track": [[round(s.x, 3), round(s.z, 3), round(s.heading_deg, 2)]
                                    for s in self.dead_track],
            "cycles": [{"look": c.look, "command": c.command, "note": c.note,
                        "path_left_ft": None if c.path_left_ft is None
                        else round(c.path_left_ft, 3),
                        "work_ms": round(1e3 * c.work_s, 2),
                        "scan_ms": round(1e3 * c.scan_s, 2),
                        "render_ms": round(1e3 * c.render_s, 2)} for c in self.cycles],
        }


def scan_look(left, right, lines, match: str = "1985"):
    """The rig's scan (a ``rig.scan.ScanResult``) of one look's .BI pair over
    ``lines``.  ``"1985"``: the eyes (the compiled frame scan, the same result
    as the reference rig, bit for bit).  ``"improved"`` (not 1985): the
    in-process reference rig with a fresh improved matcher (its default
    constraints: order, lr, neighbours, region, readmit), as ``rig walk
    --match improved``; its line results carry the verdicts
    (``matching.mode.located_points`` gives each point's confidence).  The
    neighbours constraint asks NSTAR for lines IY-1 and IY+1 as well, so a
    scan of every second line fetches the lines between too."""
    if match not in MATCHES:
        raise ValueError(f"unknown stereo matcher {match!r}; one of {', '.join(MATCHES)}")
    if match == "1985":
        from eyes import scan_pair
        return scan_pair(left, right, lines=lines)
    from matching.mode import make_matcher
    from rig.scan import scan_pair
    return scan_pair(left, right, lines, matcher=make_matcher("improved"))


def true_optimum(room, start, goal, profile: VehicleProfile, cell: float):
    """(taut length, A* grid length) of the best path for the vehicle in the
    TRUE room at the planner's resolution, or (None, None) without one."""
    fm = true_floor_map(room.obstacles, room.bounds, cell)
    p = clearance_map(fm, profile.planning_radius_ft, "blocked")
    try:
        raw = astar(p, start, goal)
    except NoPath:
        return None, None
    return path_length(shorten(p, raw)), path_length(raw)


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
        self.two_look_sides = None        # a TwoLookSides (DriveConfig.blank_sides="two-looks")
        self.occupied = "looks"           # or "model" (DriveConfig.occupied)
        self.place = "axis"               # or "point" (DriveConfig.hit_at)
        self.feature_pose = "absolute"    # or "drift", "none" (DriveConfig.feature_pose)
        self.floor_eyes = "off"           # or "carve", "add", "veto" (DriveConfig.floor_eyes)
        self.expire_uncertain = 0         # DriveConfig.expire_uncertain (0: off)
        self.unseen: dict[int, int] = {}  # packed key -> looks that had it in view, no hit
        self.expired: dict[int, float] = {}   # packed key -> its log-odds when it expired
        self.expired_total = 0            # expiries so far (a cell hit again may expire anew)
        self.lowest_ft = 0.8              # DriveConfig.lowest_obstacle_ft
        self.floor_hist = np.zeros(16)    # greys of the pixels known to show floor, all looks
        self.vetoed = 0                   # located points the floor in view contradicted
        self.floor_cells = 0              # cells the floor in view proved free
        self.confirm_looks = confirm_looks
        self.features = FloorFeatures()
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

    def estimate(self, look, dead: State) -> State:
        return dead

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
        points the floor in view contradicts.

        ``expire_uncertain`` (a named option, N looks; 0 off) counts the look
        against the uncertain cells it had in view without a hit
        (:meth:`expire_in_view`); after N the map shows them UNKNOWN.

        ``depth`` (the look's true range per pixel, ``Look.range_left``: the
        diagnostic depth eyes, :mod:`planner.depth_eyes`) replaces the floor
        scan of ``scan_points`` by :func:`~planner.depth_eyes.depth_floor_scan`;
        the rest of the update is the same."""
        pose = pose_cls(est.x, est.z, est.heading_deg, pitch_deg)
        R = pose.rotation()
        left = pose.camera_centre("left")
        res = self.tree.getResolution()
        rays = top = None
        if self.floor_eyes != "off" and picture is not None:
            rays = floor_rays(R, left)
            pic = np.asarray(picture)
            if known is not None:
                m = training_mask(rays, known, self.lowest_ft, self.max_range_ft)
                self.floor_hist += np.bincount(pic[m].astype(int), minlength=16)[:16]
            greys = floor_greys(self.floor_hist)
            if greys is not None:
                top = floor_run(pic, greys)
                if self.floor_eyes == "veto" and len(scan_points):
                    bad = vetoed(scan_points, rays, top, res)
                    self.vetoed += int(bad.sum())
                    scan_points = [q for q, b in zip(scan_points, bad) if not b]
        if depth is not None:
            fs = depth_floor_scan(depth, R, left, self.band, self.max_range_ft, res)
        else:
            fs = floor_scan(scan_points, R, left, self.band, self.max_range_ft,
                            blank_ft=self.blank_ft, carve=self.carve, place=self.place,
                            blank_px=self.blank_px, blank_limit=self.blank_limit)
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
            assumed = fs.assumed if self.blank_carve == "unknown" and fs.assumed is not None \
                else np.zeros(len(fs.free_ends), bool)
            if top is not None:
                # the floor in view replaces the blank-column assumption
                self._carve_floor(fs, rays, top, left, res)
                assumed = fs.assumed if fs.assumed is not None else assumed
                proven = fs.free_ends[~assumed]
                # "add": the assumption carves as well, under its own rules
                ends = fs.free_ends[assumed] if self.floor_eyes == "add" else fs.free_ends[:0]
            else:
                proven = fs.free_ends[~assumed]
                ends = fs.free_ends[assumed]
            mark_free_rays(self.tree, left, np.vstack([fs.hits, proven]), start_ft=self.near_ft)
            # by assumption only into unknown cells, never past a cell hit (this look too)
            if known is not None and len(ends):
                ends = ends[_near_free(known, left, ends, self.near_ft)]
            mark_assumed_free(self.tree, left, ends, self.hit_keys, start_ft=self.near_ft)
            far_ends = fs.far_ends if self.two_look_sides is not None and \
                fs.far_ends is not None else fs.free_ends[:0]
            if len(far_ends):
                # the cut-off sides: carved where a look apart saw them blank too (TwoLookSides)
                if known is not None:
                    far_ends = far_ends[_near_free(known, left, far_ends, self.near_ft)]
                keys = assumed_free_keys(self.tree, left, far_ends, self.hit_keys,
                                         start_ft=self.near_ft)
                mark_keys_free(self.tree, self.two_look_sides.confirm(
                    keys, (est.x, est.z, est.heading_deg)))
            if self.occupied == "looks":
                if len(grown):
                    mark_occupied(self.tree, grown)
            elif len(fs.hits):
                mark_occupied(self.tree, cell_centres(fs.hits, res))
                obs = fs.hits[:, [0, 2]]
                obs_cov = fs.hit_cov[:, [0, 2]][:, :, [0, 2]]
                if pose_cov is not None and self.feature_pose == "absolute":
                    obs_cov = obs_cov + pose_point_covariance(obs, (est.x, est.z), pose_cov)
                self.features.add_look(obs, obs_cov, fs.spans, near=(est.x, est.z),
                                       near_ft=self.max_range_ft + 3.0,
                                       drift_cov=pose_cov if self.feature_pose == "drift"
                                       and pose_cov is not None else None)
            if self.occupied == "model":
                self.retire(left, self.max_range_ft + 3.0)
        elif self.expire_uncertain and self.occupied == "looks":
            self.expire_in_view(fs, R, left, np.zeros(0, np.int64))   # it located nothing
        self.points = np.vstack([self.points, fs.hits])
        self._extend(fs.hits[:, [0, 2]] if len(fs.hits) else np.zeros((0, 2)))
        return len(fs.hits)

    def expire_in_view(self, fs, R, left, look_keys) -> int:
        """Count this look against every uncertain cell (hit by earlier looks,
        not confirmed) that it had IN VIEW without locating anything there,
        and expire a cell after ``expire_uncertain`` such looks: it then shows
        UNKNOWN on the map (:meth:`floor_map`), never free, until a hit raises
        its log-odds again.  Returns the cells expired by this look.

        In view: in the picture's columns (the floor scan's own placement of
        a column's range, ``place="axis"``, inverted), from ``near_ft`` on
        (nearer, the lowest obstacle is below the picture) to ``max_range_ft``,
        and nearer by a cell than the column's bound in this look — its hit, or
        the end of its free sight line between two hits — in the cell's
        column and the one each side (a column showing nothing at all has no
        bound).  A cell within one cell of anything this look hit
        (``look_keys``: its grown hit cells) is not counted and starts over:
        a real corner seen again from near by shows again.  Cells whose state
        is already OCCUPIED never expire."""
        res = self.tree.getResolution()
        cand = self._uncertain_keys(left, res)
        if not len(cand):
            return 0
        xyz = key_centres(cand, res)
        # the cell and its 8 neighbours against this look's hits
        k = _unpack(cand)
        near_hit = np.zeros(len(cand), bool)
        look_keys = np.asarray(look_keys, np.int64)
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                near_hit |= np.isin(_pack(k + np.array([di, 0, dj])), look_keys)
        # the column of each cell: v = s * (u * a + b), a, b the levelled
        # right and forward axes of the camera (floor_scan's "axis" placement)
        a = R[[0, 2], 0]
        b = R[[0, 2], 2]
        v = xyz[:, [0, 2]] - left[[0, 2]]
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
        counted = inview & (d <= nearest - res) & ~near_hit
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
        k = _unpack(keys[show])
        i = k[:, 2] - int(round(fm.z0 / res))
        j = k[:, 0] - int(round(fm.x0 / res))
        ok = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        i, j = i[ok], j[ok]
        sel = fm.cells[i, j] == UNCERTAIN
        fm.cells[i[sel], j[sel]] = UNKNOWN

    def _carve_floor(self, fs, rays, top, left, res: float) -> int:
        """Carve each column's floor in view (:func:`planner.appearance.floor_proof`),
        cut at the floor scan's own bound of that column (its hit, or the end
        of its free sight line: the near end of its neighbours' error bound,
        or the blank-column reach), never past a cell any look has hit."""
        clip = np.zeros(128)
        for pts, cols in ((fs.hits, fs.hit_cols), (fs.free_ends, fs.free_cols)):
            if cols is None or not len(pts):
                continue
            d = np.hypot(pts[:, 0] - left[0], pts[:, 2] - left[2])
            c = np.asarray(cols, int) - 1
            ok = (c >= 0) & (c < 128)
            np.maximum.at(clip, c[ok], d[ok])
        proof = floor_proof(rays, top, clip, self.lowest_ft, res)
        if proof is None:
            return 0
        pts, ray, _ = proof
        keys = cell_keys(pts, res)
        keys = np.unique(keys[keep_before_hit(keys, ray, self.hit_keys)])
        if not len(keys):
            return 0
        self.tree.updateNodes(np.ascontiguousarray(key_centres(keys, res)), False)
        self.floor_cells += len(keys)
        return len(keys)

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
        elif self.expire_uncertain:
            self._apply_expired(fm)
        return fm

    def _draw_features(self, fm: FloorMap) -> None:
        """The occupied and uncertain cells regenerated from the floor
        features; the octree's hit cells count only as seen, not free."""
        fm.cells[(fm.cells == OCCUPIED) | (fm.cells == UNCERTAIN)] = UNKNOWN
        occ, unc = self.features.cells(fm.cell, self.confirm_looks)
        i0, j0 = int(round(fm.z0 / fm.cell)), int(round(fm.x0 / fm.cell))
        for cells, st in ((unc, UNCERTAIN), (occ, OCCUPIED)):        # occupied wins
            i, j = cells[:, 1] - i0, cells[:, 0] - j0
            ok = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
            fm.cells[i[ok], j[ok]] = st


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


def swept_poses(track, step_ft: float = 0.25, step_deg: float = 10.0) -> list:
    """The poses between consecutive poses of a track: a straight move sampled
    every ``step_ft``, a pivot every ``step_deg`` (the footprint's sweep)."""
    if not track:
        return []
    out = [track[0]]
    for a, b in zip(track[:-1], track[1:]):
        turn = wrap(b.heading_deg - a.heading_deg)
        dist = math.hypot(b.x - a.x, b.z - a.z)
        n = max(1, int(math.ceil(max(abs(turn) / step_deg, dist / step_ft))))
        for k in range(1, n + 1):
            t = k / n
            out.append(State(a.x + t * (b.x - a.x), a.z + t * (b.z - a.z),
                             wrap(a.heading_deg + t * turn)))
    return out


def _mark_track_free(fm: FloorMap, track, footprint, disc_ft: float = 0.0,
                     swept_margin: float | None = None) -> None:
    """Where the vehicle has stood is free: its footprint rectangle at every
    dead-reckoned pose (and, with ``disc_ft``, a disc of that radius about the
    first pose: the clear spot it was set down in).  With ``swept_margin`` (a
    named option, ``DriveConfig.track_free="swept"``) also every pose between
    them (the footprint swept by each move and pivot), the footprint shrunk by
    that margin on every side against the estimate's error."""
    from world.collide import footprint_corners
    mask = np.zeros(fm.shape, np.uint8)
    if swept_margin is not None:
        track = swept_poses(track)
        footprint = (max(footprint[0] - 2 * swept_margin, 0.0),
                     max(footprint[1] - 2 * swept_margin, 0.0))
    for s in track:
        c = footprint_corners(s.x, s.z, s.heading_deg, footprint)
        poly = np.stack([(c[:, 0] - fm.x0) / fm.cell, (c[:, 1] - fm.z0) / fm.cell], 1)
        cv2.fillPoly(mask, [np.round(poly - 0.5).astype(np.int32)], 1)
    if disc_ft > 0 and len(track):
        i, j = fm.index(track[0].x, track[0].z)
        cv2.circle(mask, (j, i), int(math.floor(disc_ft / fm.cell)), 1, -1)
    fm.cells[mask > 0] = FREE


def _disc_seen_free(fm: FloorMap, x: float, z: float, radius: float) -> bool:
    """Every cell within ``radius`` of (x, z) is FREE: a pivot there is safe."""
    n = int(math.ceil(radius / fm.cell)) + 1
    i0, j0 = fm.index(x, z)
    ii, jj = np.mgrid[i0 - n:i0 + n + 1, j0 - n:j0 + n + 1]
    cx, cz = fm.centre(ii, jj)
    # cells whose square comes within the radius
    dx = np.maximum(np.abs(cx - x) - fm.cell / 2, 0)
    dz = np.maximum(np.abs(cz - z) - fm.cell / 2, 0)
    near = np.hypot(dx, dz) <= radius
    inside = (ii >= 0) & (jj >= 0) & (ii < fm.shape[0]) & (jj < fm.shape[1])
    if (near & ~inside).any():
        return False
    return bool((fm.cells[ii[near], jj[near]] == FREE).all())


def _pivot_seen_free(fm: FloorMap, x: float, z: float, heading_deg: float, angle_deg: float,
                     footprint, margin_ft: float, step_deg: float = 2.0) -> bool:
    """Every cell the footprint (``(width, length)``, grown by ``margin_ft`` on
    each side) covers while it pivots about (x, z) from ``heading_deg``
    through ``angle_deg`` is FREE: sampled a quarter cell apart over the
    rectangle (its edges included) at headings at most ``step_deg`` apart.  A
    turn of a degree sweeps hardly more than the footprint itself, where the
    whole disc of :func:`_disc_seen_free` asks for every cell within the half
    diagonal whatever the angle."""
    hw = footprint[0] / 2 + margin_ft
    hl = footprint[1] / 2 + margin_ft
    q = fm.cell / 4
    a = np.linspace(-hw, hw, int(math.ceil(2 * hw / q)) + 1)
    b = np.linspace(-hl, hl, int(math.ceil(2 * hl / q)) + 1)
    across, along = (g.ravel() for g in np.meshgrid(a, b))
    n = max(1, int(math.ceil(abs(angle_deg) / step_deg)))
    hs = np.radians(heading_deg + np.linspace(0.0, angle_deg, n + 1))
    px = x + across[None] * np.cos(hs)[:, None] + along[None] * np.sin(hs)[:, None]
    pz = z - across[None] * np.sin(hs)[:, None] + along[None] * np.cos(hs)[:, None]
    i = np.floor((pz.ravel() - fm.z0) / fm.cell).astype(int)
    j = np.floor((px.ravel() - fm.x0) / fm.cell).astype(int)
    if ((i < 0) | (j < 0) | (i >= fm.shape[0]) | (j >= fm.shape[1])).any():
        return False
    return bool((fm.cells[i, j] == FREE).all())


HALF_FOV_DEG = 19.5          # atan(64 / 180): half the 128-px picture's width
EYES_TURN_DEG = 15.0         # a smaller turn keeps the way ahead inside the view just seen


def looked_free(fm: FloorMap, est: State, max_range: float) -> FloorMap:
    """A copy of ``fm`` whose never-seen cells inside the field of view just
    looked at (within ``max_range``) count as free: the look located nothing
    nearer there.  Occupied and uncertain cells stay as they are."""
    out = FloorMap(fm.cells.copy(), fm.x0, fm.z0, fm.cell)
    nz, nx = fm.shape
    xs, zs = fm.centre(np.arange(nz)[:, None], np.arange(nx)[None, :])
    dx, dz = xs - est.x, zs - est.z
    bearing = np.degrees(np.arctan2(dx, dz))
    off = np.abs((bearing - est.heading_deg + 180.0) % 360.0 - 180.0)
    wedge = (off <= HALF_FOV_DEG) & (np.hypot(dx, dz) <= max_range)
    out.cells[wedge & (fm.cells == UNKNOWN)] = FREE
    return out


HALF_VFOV_DEG = math.degrees(math.atan(60 / 180))     # half the 120-line picture's height


def near_visible_ft(profile: VehicleProfile, lowest_obstacle_ft: float) -> float:
    """The distance from which an obstacle ``lowest_obstacle_ft`` tall shows in
    the picture (the lower edge of the view, pitched by the profile, reaches
    its top): nearer than that a look proves no floor free."""
    down = -profile.camera_pitch_deg + HALF_VFOV_DEG
    if down <= 0:
        return math.inf
    return (profile.camera_height_ft - lowest_obstacle_ft) / math.tan(math.radians(down))


def true_range_points(points, look):
    """The rig's located edges with their range replaced by the TRUE range at
    the same pixel (the nearer surface over the edge's +-1 columns): the
    matcher's false matches removed, everything else the same."""
    import dataclasses
    out = []
    for p in points:
        c = p.loc1 - 1
        z = float(look.range_left[p.line, max(c - 1, 0):min(c + 2, 128)].min())
        out.append(dataclasses.replace(p, dp=z))
    return out


def _mark_walls(fm: FloorMap, bounds) -> None:
    """The floor plan: every cell reaching past the walls is occupied."""
    nz, nx = fm.shape
    xs = fm.x0 + np.arange(nx + 1) * fm.cell
    zs = fm.z0 + np.arange(nz + 1) * fm.cell
    bx0, bx1, bz0, bz1 = bounds
    out_x = (xs[:-1] < bx0) | (xs[1:] > bx1)
    out_z = (zs[:-1] < bz0) | (zs[1:] > bz1)
    fm.cells[out_z[:, None] | out_x[None, :]] = OCCUPIED


def _band_seen(known: np.ndarray, fm: FloorMap, samples: np.ndarray, heading_rad: float,
               half_width: float) -> np.ndarray:
    """For each sample of a straight move: every cell across the vehicle's
    swept width (``half_width`` each side of the centre line) has been seen."""
    right = np.array([math.cos(heading_rad), -math.sin(heading_rad)])
    offs = np.arange(-half_width, half_width + 1e-9, fm.cell / 2)
    pts = samples[:, None, :] + offs[None, :, None] * right[None, None, :]
    i = np.floor((pts[..., 1] - fm.z0) / fm.cell).astype(int)
    j = np.floor((pts[..., 0] - fm.x0) / fm.cell).astype(int)
    inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    ok = np.zeros(i.shape, bool)
    ok[inside] = known[i[inside], j[inside]]
    return ok.all(1)


def _safe_prefix(cmds, est: State, safe: Passable, seen: np.ndarray, step: float,
                 seen_eyes: np.ndarray | None = None, half_width: float = 0.5,
                 nose_ft: float = 0.5, pivot_ft: float = 0.0, pivot_sweep=None):
    """The first ``step`` ft of ``cmds``, each FORWARD cut where the vehicle
    would come nearer than its radius to an occupied or uncertain cell
    (``safe``), or where its swept width (``half_width`` each side) would
    enter a cell never seen (``seen``;
    ``seen_eyes`` adds the field of view just looked at, used while the vehicle
    still faces the way it looked).  A turn is a pivot: it needs every cell
    within ``pivot_ft`` (the footprint's half diagonal) seen free, or, given
    ``pivot_sweep`` (a named option: the footprint and the margin,
    ``DriveConfig.pivot="swept"``), every cell that footprint grown by the margin
    sweeps through the turn (:func:`_pivot_seen_free`)."""
    out = []
    x, z, h = est.x, est.z, est.heading_deg
    turned = 0.0
    fm = safe.fmap
    for c in next_segment(cmds, step):
        if isinstance(c, Turn):
            if pivot_sweep is not None:
                if not _pivot_seen_free(fm, x, z, h, c.angle_deg, *pivot_sweep):
                    break                 # its sweep reaches space not seen free
            elif pivot_ft > 0 and not _disc_seen_free(fm, x, z, pivot_ft):
                break                     # its pivot circle reaches space not seen free
            out.append(c)
            h = wrap(h + c.angle_deg)
            turned += abs(c.angle_deg)
            continue
        if not isinstance(c, Forward):
            break
        if turned > EYES_TURN_DEG and out:
            break                         # look the new way before driving into it
        known = seen_eyes if (seen_eyes is not None and turned <= EYES_TURN_DEG) else seen
        hr = math.radians(h)
        end = (x + c.distance_ft * math.sin(hr), z + c.distance_ft * math.cos(hr))
        s = segment_samples((x, z), end, fm.cell / 4)
        i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
        j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
        inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        # each position needs the band seen on to the vehicle's nose ahead of it
        step_s = fm.cell / 4
        m = int(math.ceil(nose_ft / step_s))
        ext = np.vstack([s, end + (np.arange(1, m + 1) * step_s)[:, None] *
                         np.array([math.sin(hr), math.cos(hr)])[None, :]])
        bs = _band_seen(known, fm, ext, hr, half_width)
        run_ok = np.convolve(~bs, np.ones(m + 1), mode="full")[m:m + len(s)] == 0
        seen_band = run_ok
        ok = np.zeros(len(s), bool)
        near = np.zeros(len(s), bool)
        if safe.at == "centre":
            # each position by its own exact distance to the blocked cells
            cl = clearance_at(safe, s)
            ok = (cl >= safe.radius - 1e-9) & seen_band & inside
            near = (cl >= cl[0] - 1e-9) & seen_band & inside
        else:
            ok[inside] = safe.ok[i[inside], j[inside]] & seen_band[inside]
            # the vehicle may leave a cell it stands in even if a (perhaps false)
            # obstacle came near it, as long as it gets no nearer
            cl0 = safe.clearance[i[0], j[0]] if inside[0] else 0.0
            near[inside] = (safe.clearance[i[inside], j[inside]] >= cl0 - 1e-9) & \
                seen_band[inside]
        good = ok | (near & (np.arange(len(s)) * fm.cell / 4 <= 1.0))
        bad = np.flatnonzero(~good)
        if len(bad) == 0:
            out.append(c)
            x, z = end
            continue
        k = bad[0] - 1
        d = max(0.0, k * c.distance_ft / (len(s) - 1)) if k > 0 else 0.0
        if d > 0.05:
            out.append(Forward(round(d, 3)))
        break
    return out


def _blocker(fm: FloorMap, safe: Passable, pts, near_ft: float):
    """Where the path's execution would stop for want of evidence: the first
    sample of the path (a quarter cell apart) outside the space seen free, or
    within the vehicle's radius of an uncertain cell, and the cell to look at
    there (the nearest cell not seen free: unknown or uncertain).  None when
    the path has no such place."""
    look_at = (fm.cells == UNKNOWN) | (fm.cells == UNCERTAIN)
    if not look_at.any():
        return None
    n = int(math.ceil((safe.radius + fm.cell) / fm.cell))
    for a, b in zip(pts[:-1], pts[1:]):
        s = segment_samples(a, b, fm.cell / 4)
        i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
        j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
        inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        bad = ~inside
        bad[inside] = (fm.cells[i[inside], j[inside]] != FREE) | ~safe.ok[i[inside], j[inside]]
        for k in np.flatnonzero(bad):
            if not inside[k]:
                return None
            i0, j0 = i[k], j[k]
            ii, jj = np.mgrid[max(i0 - n, 0):min(i0 + n + 1, fm.shape[0]),
                              max(j0 - n, 0):min(j0 + n + 1, fm.shape[1])]
            m = look_at[ii, jj]
            if not m.any():
                continue                  # near a confirmed obstacle: nothing to look at
            cx, cz = fm.centre(ii[m], jj[m])
            d = np.hypot(cx - s[k, 0], cz - s[k, 1])
            q = int(np.argmin(d))
            return float(cx[q]), float(cz[q])
    return None


def _viewpoint(fm: FloorMap, safe_seen: Passable, est: State, target, near_ft: float,
               tried, far_ft: float = 2.0):
    """A path (polyline) through space seen free to a place from which
    ``target`` can be looked at: between ``near_ft`` + 0.3 ft and ``near_ft`` +
    ``far_ft`` from it (nearer, a look proves nothing there), not within 0.5 ft
    of a place in ``tried``, the nearest such place first.  None without one."""
    p = _escape_start(safe_seen, (est.x, est.z))
    si, sj = fm.index(est.x, est.z)
    if not fm.inside(si, sj) or not p.ok[si, sj]:
        return None
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    ii, jj = np.nonzero(comp == comp[si, sj])
    cx, cz = fm.centre(ii, jj)
    dt = np.hypot(cx - target[0], cz - target[1])
    keep = (dt >= near_ft + 0.3) & (dt <= near_ft + far_ft)
    for q in tried + [(est.x, est.z)]:
        keep &= np.hypot(cx - q[0], cz - q[1]) > 0.5
    if not keep.any():
        return None
    cx, cz = cx[keep], cz[keep]
    order = np.argsort(np.hypot(cx - est.x, cz - est.z))
    for k in order[:4]:
        v = (float(cx[k]), float(cz[k]))
        try:
            return shorten(p, astar(p, (est.x, est.z), v))
        except NoPath:
            continue
    return None


def _back_prefix(est: State, dist: float, safe: Passable, seen, prof: VehicleProfile) -> list:
    """``[BACK d]``: as far as ``dist`` (at most the profile's step) straight
    back along the heading, cut by the same rules as a forward move
    (:func:`_safe_prefix` on the heading turned round: the swept width and
    the tail seen free, nothing known within the radius); ``[]`` when less
    than 0.05 ft is allowed."""
    dist = min(dist, prof.step_ft)
    if dist <= 0.05:
        return []
    behind = State(est.x, est.z, wrap(est.heading_deg + 180.0))
    seg = _safe_prefix([Forward(dist)], behind, safe, seen, dist, None,
                       prof.width_ft / 2 + prof.margin_ft, prof.length_ft / 2 + prof.margin_ft,
                       0.0)
    d = sum(c.distance_ft for c in seg if isinstance(c, Forward))
    return [Back(round(d, 3))] if d > 0.05 else []


LOOKS_PER_VIEWPOINT = 3      # looks at one blocker from one place before trying another


def _fetch_evidence(fm: FloorMap, safe: Passable, seen, est: State, pts, near_ft: float,
                    prof: VehicleProfile, cfg, tried: dict):
    """(commands, note) that go and get the evidence the path lacks, or None.
    The place where the path's execution stops (:func:`_blocker`: a cell not
    seen free, or an uncertain cell within the vehicle's radius of it) is
    looked at: turned to, when it lies far enough (``near_ft``) to show in a
    look and outside the view just taken; otherwise (too near to show, or
    looked at from here already) the vehicle drives, through space seen free,
    to a place from which it can be seen (:func:`_viewpoint`), then turns to
    it.  ``tried`` maps each blocker's cell to the places it was looked at from."""
    u = _blocker(fm, safe, pts, near_ft)
    if u is None:
        return None
    tried = tried.setdefault(fm.index(*u), [])
    here = (est.x, est.z)
    d = math.hypot(u[0] - here[0], u[1] - here[1])
    off = wrap(heading_to(here, u) - est.heading_deg)
    looked = sum(math.hypot(q[0] - here[0], q[1] - here[1]) <= 0.5 for q in tried)
    if d < near_ft + 0.2 and prof.reverse and abs(off) <= HALF_FOV_DEG - 4.0:
        # too near to show, and ahead: back straight off until it shows
        seg = _back_prefix(est, near_ft + 0.5 - d, safe, seen, prof)
        if seg:
            return seg, f" (backing off to look at ({u[0]:.1f}, {u[1]:.1f}))"
    if d >= near_ft + 0.2 and looked < LOOKS_PER_VIEWPOINT:
        if abs(off) <= HALF_FOV_DEG - 4.0:
            # the look just taken saw it and left it unresolved: a cell hit once
            # needs more than one look through it to be cleared; look again
            tried.append(here)
            return [], f" (looking again at ({u[0]:.1f}, {u[1]:.1f}))"
        if _disc_seen_free(fm, est.x, est.z, prof.radius_ft):
            return [Turn(round(off, 2))], f" (turning to look at ({u[0]:.1f}, {u[1]:.1f}))"
    seen_only = clearance_map(fm, prof.planning_radius_ft, "blocked", uncertain="blocked",
                              at=cfg.clearance_at)
    vp = _viewpoint(fm, seen_only, est, u, near_ft, tried)
    if vp is None or len(vp) < 2:
        return None
    cmds = to_commands(vp, est.heading_deg, prof.turning_radius_ft, seen_only)
    seg = _safe_prefix(cmds, est, safe, seen, prof.step_ft, None,
                       prof.width_ft / 2 + prof.margin_ft, prof.length_ft / 2 + prof.margin_ft,
                       prof.radius_ft)
    if not any(isinstance(c, Forward) or abs(c.angle_deg) >= 1.0 for c in seg):
        return None
    return seg, (f" (to look at ({u[0]:.1f}, {u[1]:.1f}) from "
                 f"({vp[-1][0]:.1f}, {vp[-1][1]:.1f}))")


def _nearest_reachable(p: Passable, start, goal):
    """The passable cell reachable from the start that is nearest the goal."""
    fm = p.fmap
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    si, sj = fm.index(*start)
    if not fm.inside(si, sj) or comp[si, sj] == 0:
        return None
    ii, jj = np.nonzero(comp == comp[si, sj])
    xs, zs = fm.centre(ii, jj)
    d = np.hypot(xs - goal[0], zs - goal[1])
    k = int(np.argmin(d))
    return float(xs[k]), float(zs[k])


def _still_good(p: Passable, prev, start) -> list | None:
    """The previous path from the vehicle's new position, if still passable."""
    if not prev or len(prev) < 2:
        return None
    # drop the waypoints already passed: continue from the nearest leg's end
    rest = [tuple(start)] + [tuple(q) for q in prev[1:]]
    d = [math.hypot(q[0] - start[0], q[1] - start[1]) for q in rest[1:]]
    k = int(np.argmin(d))
    if k > 0 and line_of_sight(p, start, rest[k + 1]):
        rest = [tuple(start)] + rest[k + 1:]
    if all(line_of_sight(p, a, b) for a, b in zip(rest[:-1], rest[1:])):
        return rest
    return None


ESCAPE_FT = 1.0              # as far as _safe_prefix lets the vehicle leave a too-near spot


def _escape_start(p: Passable, start) -> Passable:
    """When the estimate stands nearer an obstacle than the planning radius
    (a feature seen late, or a fix that moved the estimate), the cells within
    ``ESCAPE_FT`` of it that are no nearer to any obstacle count passable, so
    the search can lead the vehicle away; :func:`_safe_prefix` allows exactly
    those moves.  Otherwise the planner refuses the start and the vehicle
    stays put until it gives up."""
    fm = p.fmap
    i0, j0 = fm.index(*start)
    if not fm.inside(i0, j0) or p.ok[i0, j0] or p.blocked[i0, j0]:
        return p
    cl0 = p.clearance[i0, j0]
    ii, jj = np.indices(fm.shape)
    cx, cz = fm.centre(ii, jj)
    near = np.hypot(cx - start[0], cz - start[1]) <= ESCAPE_FT
    ok = p.ok | (near & ~p.blocked & (p.clearance >= cl0 - 1e-9))
    return Passable(ok, p.clearance, p.blocked, fm, p.radius, p.unknown, p.at)


def plan(fm: FloorMap, est: State, goal, cfg: DriveConfig, prev=None):
    """(polyline, commands, note) from the estimate toward the goal, or raise
    NoPath.  The previous path is kept while it stays passable and is no more
    than ``keep_ft`` longer than a new one (no dithering between two ways round).

    Uncertain cells (hit by one look, not yet confirmed by a second) block the
    path; when none avoids them (``cfg.uncertain="blocked"``, the default) the
    vehicle heads for the reachable cell nearest the goal.  With ``"look"`` (a
    named option, measured and not adopted: docs/planner.md) the path may pass
    through them: the vehicle drives toward them (never nearer than its
    radius: the execution still treats them as obstacles) and looks again, so
    a second look confirms or clears them."""
    if cfg.uncertain not in UNCERTAIN_PLANS:
        raise ValueError(f"unknown uncertain-cell plan {cfg.uncertain!r}; one of "
                         f"{', '.join(UNCERTAIN_PLANS)}")
    if cfg.uncertain == "blocked" or not (fm.cells == UNCERTAIN).any():
        return _plan(fm, est, goal, cfg, prev, "blocked")
    try:
        return _plan(fm, est, goal, cfg, prev, "blocked", nearest=False)
    except NoPath as exc:
        try:
            pts, cmds, _ = _plan(fm, est, goal, cfg, prev, "free", nearest=False)
            return pts, cmds, f"{exc}; through uncertain cells, to look at them"
        except NoPath:
            return _plan(fm, est, goal, cfg, prev, "blocked")


def goal_target(p: Passable, start, goal, radius: float):
    """The point the planner plans to under ``goal_region="disc"``: the goal
    itself when the vehicle may stand there and reach it from ``start``;
    otherwise, of the cells within ``radius`` of the goal (centre distance)
    that are passable and connected to the start's cell (4-connected: a
    region both searches can grow through), the one nearest the goal; the
    goal itself when there is none (the point planning then says why not).
    A cell passable on ``p`` has the vehicle's planning radius to every
    blocked cell, so the target is never in or against an obstacle."""
    fm = p.fmap
    gi, gj = fm.index(*goal)
    si, sj = fm.index(*start)
    if not fm.inside(si, sj) or not p.ok[si, sj]:
        return tuple(map(float, goal))
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=4)
    here = comp[si, sj]
    if fm.inside(gi, gj) and p.ok[gi, gj] and comp[gi, gj] == here:
        return tuple(map(float, goal))
    n = int(math.ceil(radius / fm.cell)) + 1
    ii, jj = np.mgrid[max(gi - n, 0):min(gi + n + 1, fm.shape[0]),
                      max(gj - n, 0):min(gj + n + 1, fm.shape[1])]
    cx, cz = fm.centre(ii, jj)
    d = np.hypot(cx - goal[0], cz - goal[1])
    cand = (d <= radius) & p.ok[ii, jj] & (comp[ii, jj] == here)
    if not cand.any():
        return tuple(map(float, goal))
    k = np.flatnonzero(cand.ravel())[np.argmin(d[cand])]
    return float(cx.ravel()[k]), float(cz.ravel()[k])


def _plan(fm: FloorMap, est: State, goal, cfg: DriveConfig, prev, uncertain: str,
          nearest: bool = True):
    search = SEARCHES[cfg.search]
    r = cfg.profile.planning_radius_ft
    p = _escape_start(clearance_map(fm, r, cfg.unknown, uncertain=uncertain,
                                    at=cfg.clearance_at), (est.x, est.z))
    start = (est.x, est.z)
    aim = tuple(map(float, goal))
    if cfg.goal_region == "disc":
        aim = goal_target(p, start, goal, max(cfg.tolerance_ft - GOAL_SLACK_FT, 0.0))

    def to_goal(q) -> bool:
        # a previous path is kept only when it ends at the goal point itself,
        # as without the disc (keeping paths to a disc cell took the bundled
        # lab's drive round the far side of the table, and lost it)
        return tuple(map(float, q)) == tuple(map(float, goal))
    try:
        pts = shorten(p, search(p, start, aim))
        note = "path to the goal" if aim == tuple(map(float, goal)) else \
            f"path to the goal's disc at ({aim[0]:.2f}, {aim[1]:.2f})"
        old = _still_good(p, prev, start) if prev and to_goal(prev[-1]) else None
        if old is not None and path_length(old) <= path_length(pts) + cfg.keep_ft:
            pts, note = old, "path to the goal (kept)"
        elif prev:
            note = "path to the goal (replanned)"
    except NoPath as exc:
        if not nearest:
            raise
        # the goal itself may look blocked from afar (a far feature's grown
        # covariance): head for the reachable cell nearest it and look again
        target = _nearest_reachable(p, start, goal)
        if target is None or math.hypot(target[0] - start[0], target[1] - start[1]) < 0.3:
            raise exc
        pts = shorten(p, search(p, start, target))
        note = f"goal not reachable ({exc}); toward ({target[0]:.1f}, {target[1]:.1f})"
    cmds = to_commands(pts, est.heading_deg, cfg.profile.turning_radius_ft, p)
    return pts, cmds, note


def run(room, start: State, cfg: DriveConfig, noise=None, on_cycle=None, keep_maps: bool = True
        ) -> DriveResult:
    """Drive from ``start`` to ``cfg.goal`` in ``room`` (a world Room)."""
    from world.pose import Pose
    from world.render import render_look

    prof = cfg.profile
    if cfg.match not in MATCHES:
        raise ValueError(f"unknown stereo matcher {cfg.match!r}; one of {', '.join(MATCHES)}")
    if cfg.pose not in POSES:
        raise ValueError(f"unknown camera estimate {cfg.pose!r}; one of {', '.join(POSES)}")
    for name, allowed in (("eyes", EYES), ("pivot", PIVOTS), ("look_around", LOOK_AROUNDS), ("progress", PROGRESSES),
                          ("uncertain", UNCERTAIN_PLANS), ("track_free", TRACK_FREES),
                          ("goal_region", GOALS), ("floor_eyes", FLOOR_EYES),
                          ("blank_carve", ("unknown", "always")), ("blank_limit", BLANK_LIMITS),
                          ("blank_sides", BLANK_SIDES),
                          ("occupied", OCCUPIEDS), ("hit_at", PLACES),
                          ("feature_pose", FEATURE_POSES)):
        if getattr(cfg, name) not in allowed:
            raise ValueError(f"unknown {name} {getattr(cfg, name)!r}; one of {', '.join(allowed)}")
    veh = Vehicle(room.obstacles, room.bounds, start, prof, noise)
    walker = None
    if cfg.pose == "fused":
        from model.mapping import WalkConfig, Walker, compose_step
        walker = Walker(room, WalkConfig(methods=(), driver=cfg.pose_method,
                                         lines=tuple(cfg.lines), match=cfg.match,
                                         camera_pitch_deg=prof.camera_pitch_deg))
    est_track = [veh.dead]
    look_est = look_dead = None           # the estimate and the dead-reckoned pose at the last look

    def current() -> State:
        """The camera estimate now: the last look's moved by the odometry since."""
        if walker is None or look_est is None:
            return veh.dead
        return State(*compose_step((look_est.x, look_est.z, look_est.heading_deg), look_dead,
                                   veh.dead)[0])
    model = Perception(cfg.voi, cfg.band, cfg.max_range_ft, cfg.confirm_looks, cfg.free_looks,
                       near_visible_ft(prof, cfg.lowest_obstacle_ft), cfg.blank_ft)
    model.growth = cfg.growth
    model.blank_carve = cfg.blank_carve
    model.carve = cfg.carve
    if cfg.blank_px is not None and cfg.blank_px < 0:
        raise ValueError(f"blank_px must be 0 or more columns, not {cfg.blank_px!r}")
    model.blank_px = cfg.blank_px
    model.blank_limit = cfg.blank_limit
    if cfg.blank_sides == "two-looks":       # (without blank_px no side is cut off: inert)
        model.two_look_sides = TwoLookSides(*cfg.sides_apart)
    model.occupied = cfg.occupied
    model.place = cfg.hit_at
    model.feature_pose = cfg.feature_pose
    model.floor_eyes = cfg.floor_eyes
    if not isinstance(cfg.expire_uncertain, (int, np.integer)) or isinstance(
            cfg.expire_uncertain, bool) or cfg.expire_uncertain < 0:
        raise ValueError(f"expire_uncertain must be a whole number of looks >= 0 (0: off), "
                         f"not {cfg.expire_uncertain!r}")
    model.expire_uncertain = int(cfg.expire_uncertain)
    model.lowest_ft = cfg.lowest_obstacle_ft
    # the dead-reckoned pose's (x, z, heading rad) covariance, by the odometry's noise model
    dead_cov = np.zeros((3, 3))
    odo = (getattr(noise, "distance_fraction", 0.0), getattr(noise, "turn_deg", 0.0)) \
        if noise is not None else (0.0, 0.0)
    near_ft = near_visible_ft(prof, cfg.lowest_obstacle_ft)
    pivot_sweep = (prof.footprint, prof.margin_ft) if cfg.pivot == "swept" else None
    tried: dict = {}                      # blocker cell -> places it was looked at from
    goal = (float(cfg.goal[0]), float(cfg.goal[1]))
    opt, opt_grid = true_optimum(room, (start.x, start.z), goal, prof, cfg.voi.resolution)
    cycles: list[Cycle] = []
    t_start = time.perf_counter()
    reached, reason = False, ""
    stuck = 0
    best_left, most_free = math.inf, 0    # the shortest way left so far, the most free cells
    last_reason = ""
    sweep = 0
    prev_path = None
    known = None                          # the last floor map, its track free
    try:
        for look_no in range(1, cfg.max_looks + 1):
            est = current()
            if math.hypot(est.x - goal[0], est.z - goal[1]) <= cfg.tolerance_ft:
                reached, reason = True, "goal reached"
                break
            t0 = time.perf_counter()
            tp = veh.true
            look = render_look(room, Pose(tp.x, tp.z, tp.heading_deg, prof.camera_pitch_deg),
                               seed=cfg.look_seed + look_no,
                               supersample=cfg.supersample)
            t1 = time.perf_counter()
            scan = scan_look(look.left_bi, look.right_bi, cfg.lines, cfg.match)
            scan_s = time.perf_counter() - t1
            points = scan.points if cfg.eyes != "truth" else true_range_points(scan.points, look)
            if walker is None:
                est = veh.dead
            else:
                rec = walker.step(look, look.pose, veh.dead, look_dead, scan=scan)
                est = State(*rec.estimates["fused"])
            look_est, look_dead = est, veh.dead
            if known is None:             # before the first look: the clear spot set down in
                known = empty_map((est.x, est.x, est.z, est.z), cfg.voi.resolution,
                                  cfg.start_clear_ft + 1.0)
                _mark_track_free(known, est_track, prof.footprint, cfg.start_clear_ft)
            model.update(points, est, Pose, prof.camera_pitch_deg, known, dead_cov,
                         look.left_bi if cfg.floor_eyes != "off" else None,
                         look.range_left if cfg.eyes == "depth" else None)
            fm = model.floor_map([(est.x, est.z), goal])
            _mark_track_free(fm, est_track, prof.footprint, cfg.start_clear_ft,
                             prof.margin_ft if cfg.track_free == "swept" else None)
            if cfg.known_walls:
                _mark_walls(fm, room.bounds)
            known = fm
            safe = clearance_map(fm, prof.planning_radius_ft,
                                 "blocked" if cfg.safety == "strict" else "free",
                                 uncertain="blocked", at=cfg.clearance_at)
            seen = fm.cells != UNKNOWN
            seen_eyes = None
            if cfg.trust_view:
                seen_eyes = looked_free(fm, est, cfg.max_range_ft).cells != UNKNOWN
            fetching = False
            try:
                pts, cmds, note = plan(fm, est, goal, cfg, prev_path)
                seg = _safe_prefix(cmds, est, safe, seen, prof.step_ft, seen_eyes,
                                   prof.width_ft / 2 + prof.margin_ft,
                                   prof.length_ft / 2 + prof.margin_ft,
                                   prof.radius_ft, pivot_sweep)
                left = path_length(pts)
                if not any(isinstance(c, Forward) for c in seg) and \
                        cfg.look_around == "evidence":
                    got = _fetch_evidence(fm, safe, seen, est, pts, near_ft, prof, cfg, tried)
                    if got is not None:
                        seg, how = got
                        note += how
                        fetching = True
                if not fetching and not any(isinstance(c, Forward) for c in seg):
                    # nothing known free ahead: face the path and look again
                    first = pts[1] if len(pts) > 1 else goal
                    t = wrap(heading_to((est.x, est.z), first) - est.heading_deg)
                    seg = [Turn(round(t, 2))] if abs(t) > 1.0 else []
                last_reason = ""
                prev_path = pts
            except NoPath as exc:
                pts, left, note, seg = [], None, str(exc), []
                last_reason = str(exc)
            if not fetching and (not seg or all(isinstance(c, Turn) and abs(c.angle_deg) < 1.0
                                                for c in seg)):
                # no motion: turn to look, toward the goal first, then sweep
                sweep += 1
                t = wrap(heading_to((est.x, est.z), goal) - est.heading_deg)
                if abs(t) < 10 or sweep > 1:
                    t = 35.0 if sweep % 2 else -70.0
                back = _back_prefix(est, 1.0, safe, seen, prof) if prof.reverse else []
                if (_disc_seen_free(fm, est.x, est.z, prof.radius_ft) if pivot_sweep is None
                        else _pivot_seen_free(fm, est.x, est.z, est.heading_deg, t,
                                              *pivot_sweep)):
                    seg = [Turn(round(t, 2))]
                    note += " (turning to look)"
                elif back:
                    seg = back
                    note += " (cannot turn here: backing to where it can)"
                else:
                    seg = []
                    note += " (cannot turn: space within its radius not seen free)"
            t2 = time.perf_counter()
            before = (veh.true.x, veh.true.z)
            n_before = len(veh.dead_track)
            ok = veh.execute(seg)
            for a, b in zip(veh.dead_track[n_before - 1:], veh.dead_track[n_before:]):
                dead_cov = odometry_covariance(dead_cov, a, b, *odo)
            for d in veh.dead_track[n_before:]:
                est_track.append(d if walker is None else State(*compose_step(
                    (est.x, est.z, est.heading_deg), look_dead, d)[0]))
            moved = math.hypot(veh.true.x - before[0], veh.true.z - before[1])
            if moved > 0.05:
                sweep = 0
            if cfg.progress == "moved":
                progressed = moved > 0.05
            else:
                # progress is a shorter way left than ever before, or new free
                # space seen (half a square foot): moving to and fro is not
                progressed = False
                if left is not None and left < best_left - 0.25:
                    best_left, progressed = left, True
                n_free = int((fm.cells == FREE).sum())
                if n_free >= most_free + 8:
                    most_free, progressed = n_free, True
            stuck = 0 if progressed else stuck + 1
            cyc = Cycle(look_no, tp, est, len(model.points), int(model.tree.getNumLeafNodes()),
                        left, format_commands(seg), note, t1 - t0, t2 - t1,
                        list(pts), fm if keep_maps else None, scan_s)
            cycles.append(cyc)
            if on_cycle:
                on_cycle(cyc)
            if not ok:
                reason = "stopped: the vehicle hit something (true footprint against the room)"
                break
            if stuck >= cfg.max_stuck:
                reason = f"stopped after {cfg.max_stuck} looks without progress: " + \
                         (last_reason or note)
                break
        else:
            est = current()
            if math.hypot(est.x - goal[0], est.z - goal[1]) <= cfg.tolerance_ft:
                reached, reason = True, "goal reached"
            else:
                reason = f"stopped: {cfg.max_looks} looks used up"
    except KeyboardInterrupt:
        reason = f"stopped by Ctrl-C after {len(cycles)} looks"
    seconds = time.perf_counter() - t_start
    final_err = math.hypot(veh.true.x - goal[0], veh.true.z - goal[1])
    return DriveResult(reached, reason, len(cycles), veh.travelled_ft, opt, opt_grid,
                       veh.collisions, seconds, cycles, list(veh.true_track),
                       list(veh.dead_track), memory_bytes(model.tree), final_err, goal, start,
                       cfg.unknown, cfg.search, est_track, cfg.pose, cfg.match,
                       model.features if cfg.occupied == "model" else None,
                       _floor_stats(model) if cfg.floor_eyes != "off" else {},
                       model.expired_total if cfg.expire_uncertain else None)


def _floor_stats(model: "Perception") -> dict:
    """What the floor in view did in one drive (planner.appearance)."""
    from .appearance import floor_greys
    g = floor_greys(model.floor_hist)
    return {"floor_greys": [] if g is None else np.flatnonzero(g).tolist(),
            "floor_samples": int(model.floor_hist.sum()), "floor_cells": int(model.floor_cells),
            "vetoed_points": int(model.vetoed)}


def random_goal(room, start: State, profile: VehicleProfile, rng, min_ft: float = 6.0,
                cell: float = 0.25, tries: int = 200):
    """A goal the vehicle can reach from ``start`` in the TRUE room (a path
    exists at the planner's resolution) at least ``min_ft`` away, or None."""
    x0, x1, z0, z1 = room.bounds
    r = profile.planning_radius_ft
    fm = true_floor_map(room.obstacles, room.bounds, cell)
    p = clearance_map(fm, r, "blocked")
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    si, sj = fm.index(start.x, start.z)
    if not fm.inside(si, sj) or comp[si, sj] == 0:
        return None
    for _ in range(tries):
        gx, gz = float(rng.uniform(x0 + r, x1 - r)), float(rng.uniform(z0 + r, z1 - r))
        if math.hypot(gx - start.x, gz - start.z) < min_ft:
            continue
        gi, gj = fm.index(gx, gz)
        if comp[gi, gj] == comp[si, sj] and room.clearance(gx, gz) >= r:
            return round(gx, 2), round(gz, 2)
    return None
