"""The closed loop of the goal-achievement system (Chapter I's goal, Chapter
IV's design): look -> scan -> model update -> camera estimate -> octree ->
floor map -> plan -> execute the next command segment -> repeat, "modifying
the path as needed during the traversal".

* **look**: the world renders both cameras at the vehicle's TRUE pose;
* **scan**: the rig's whole-picture scan of the pair (:func:`scan_look`): by the eyes
  (``eyes.scan_pair``, the compiled 1985 frame scan, bit for bit ``rig.scan.scan_pair``)
  with ``match="1985"`` (the default), or with ``match="improved"`` (``rig drive --match
  improved``, not 1985) by the improved matcher of package ``matching`` on the eyes'
  compiled line source (``eyes.improved.scan_pair``, line for line the in-process rig's
  ``rig.scan.scan_pair(..., matcher=make_matcher("improved"))``, as ``rig walk --match
  improved``): a verdict per edge, so an edge without a right match is left out
  instead of located at the best available;
* **model update / camera estimate**: ``pose="fused"`` (``rig drive --pose
  fused``) runs the walk's per-look step (:class:`model.mapping.Walker`) on the
  same scan: vertical edges and vertices into the symbolic model, matched to it
  from the odometry's prior, the driving method's fix fused with that prior by
  their covariances; that pose places the look.  ``pose="dead_reckoning"`` (the
  default before 2026-12-05) places it at the dead-reckoned pose, unchanged.
  ``pose="walls"`` (not 1985; the default since 2026-12-05, also with the head):
  the estimate moved by the odometry since the last look, fixed against the floor
  plan's walls by the look's own points (:func:`planner.localize.fix_against_walls`:
  each point gated against its nearest wall, an iterated EKF with the odometry's
  prior; the depth eyes' true ranges off the floor, or the rig's located points and,
  under ``wall_points="floor-ends"``, where the floor in view ends); after a
  fix the dead-reckoned covariance (hits, the plan's wall growth) is the fix's and
  grows with the odometry again.  Every way the octree is
  built from the located points of every look (:class:`planner.evidence.Perception`);
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
  ``occupied="model"`` (:mod:`planner.features`; the default since
  2026-12-05 13:45, ``"looks"`` the per-look cells above) draws the occupied
  and uncertain cells each cycle from floor features fused look by look,
  each grown by its fused covariance (Chapter IV's octree "regenerated from
  the symbolic model"); the free space is the same sight-line carving;
* **plan**: the floor map over the vehicle's height band, grown by the
  vehicle's radius, searched by the dissertation's search (or A*), pulled
  taut, turned into motion commands;
* **execute**: the first ``step`` feet of the commands, cut where the
  vehicle would come within its radius of an occupied or uncertain cell, or
  its swept width (and nose) would enter a cell not seen free; a pivot needs
  its circle seen free; after a turn of more than 15 deg it looks first.  Where that
  drives nowhere within a step of the goal's disc, ``approach="disc"`` (the default
  since 2026-12-02, not 1985) takes the straight move the same rules allow that ends
  nearest the goal inside its tolerance (:func:`planner.motion.disc_approach`).  ``trust_view``
  (off by default) also lets it into never-seen cells inside the field of view
  just looked at, while it still faces that way: a blank wall gives the
  edge-based eyes no points at all, so this drives into blank walls (measured:
  the bundled lab's back wall) and is kept only as a named experiment.

``head="pan-tilt"`` (``rig drive --head pan-tilt``, not 1985, off by
default; not with ``pose="fused"``, whose walk assumes the fixed rig): the rig
on a head (``VehicleProfile.head``, the commands ``PAN`` and ``TILT``).  Each
cycle is still one look, rendered at the TRUE pose with the heading plus the
pan and the pitch plus the tilt, and placed by the ESTIMATE with the same
(exact) angles; what it proves follows its tilt (``near_visible_ft`` for the
tilt), and a look the head turned (panned or tilted) assumes nothing of its
blank columns (measured: docs/planner.md, "A pan-tilt head").  Where the fixed rig pivots only to look, the head looks
instead (:func:`planner.motion.head_look`: the first never-seen cell beside
the way, tilted down to show it, the pivot circle, the way's evidence, the
path's way; then round: toward the goal, +-45, +-90 deg; the body's sweep
only after that), with no pivot check (the body does not move).  The body
drives with the head at 0/0; after the move the head is aimed at the first
never-seen cell on the band beyond it, for the next look
(:func:`planner.motion.head_commands`); the look-ahead's cut-and-pivot is not
used (the tilted head sees the cell from 0.9 ft or nearer).

``head="assist"`` (``rig drive --head assist``, not 1985, off by default; not with
``pose="fused"``): the fixed rig's cycle unchanged, and where it would stop or pivot
only to look, a second look in the same cycle with the head aimed by
:func:`planner.motion.head_look` (assuming nothing of its blank columns), the cycle
then decided again on the map with it; the body drives with the head at 0/0
(docs/planner.md, "The head that only adds looks").

The vehicle is set down in a clear spot (``start_clear_ft``, 2.5 ft, as the
generated rooms keep around the start): a look proves nothing nearer than
``near_visible_ft`` (2.3 ft with the default profile), so without this it
could not start.

The room's walls are given as a floor plan (``known_walls``, on by
default; the furniture is not): the edge-based eyes find no points on a
blank wall, and a false far match would otherwise let a sight line through
it (measured on the bundled lab: without the plan the vehicle drove into the
left wall).  The plan is in the room's frame and the looks are placed by the
estimate, so what a look only assumes (its blank columns' floor, the sides
two looks saw blank) stops short of the plan's walls by two standard
deviations of the estimate's position (:func:`planner.evidence.wall_growth`,
the odometry's covariance, at most 1.5 ft as a feature's growth): stopped by
the plan itself it ran past the wall by the drift (docs/planner.md, "The head
that only adds looks", room 7).  What a look proves (a sight line to a point
it located) is not cut.

The floor map each cycle plans on covers every hit so far, the estimate and the goal, 2 ft
round, and its border blocks the search.  Under ``map_extent="fallback"`` (not 1985; the
default since 2026-12-05 16:30, ``"seen"`` before) a cycle whose map has no path to the
goal plans on the map drawn out to the plan's walls instead, where that one has a path (the
way round the far side of a box no hit has reached yet); ``"walls"`` does so every cycle
(:func:`map_around`; measured: docs/planner.md, "The map out to the walls when the seen
map has no way").

When no path to the goal exists on the map (with unknown space blocked, or
the goal looking blocked from afar), the vehicle heads for the reachable cell
nearest the goal; when it cannot move at all it fetches the evidence its path
lacks (``look_around="evidence"``, the default since 2026-12-04: a look where the
path has not been seen free, from where it shows; ``"sweep"``, before: toward the
goal first, then sweeping); where it can neither pivot nor move on to where it could,
it undoes its own last motions (``backing="trail"``, the default since 2026-12-07 12:15:
back over ground its wheels swept, then a look from there); and it gives up with the
planner's reason after ``max_stuck`` looks without progress.

This module holds the loop's configuration (:class:`DriveConfig`, checked by
:func:`_check_config`), the cycle's steps by name (:class:`Drive`: :meth:`~Drive.look`,
:meth:`~Drive.estimate`, :meth:`~Drive.update_map`, :meth:`~Drive.plan`,
:meth:`~Drive.act`, one cycle :meth:`~Drive.cycle`) and the loop over them (:func:`run`);
the map it keeps is :mod:`planner.evidence`, what the vehicle may drive on it
:mod:`planner.motion`, the path and its commands :mod:`planner.planning`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from vehicle.commands import Back, Forward, Pan, Tilt, Turn, format_commands
from vehicle.profile import DEFAULT, VehicleProfile
from vehicle.sim import State, Vehicle, camera_pose, odometry_covariance
from .appearance import BOUNDING, STAND_INS as STAND_IN_SHARES, reads_floor
from .evidence import FLAT_FOOT_APART_DEG, FreeProvenance, Perception, floor_stats, mark_walls, \
    wall_growth
from .drift import Odometry, erode_by_drift
from .features import FloorFeatures
from .floormap import FLOOR_Y, FloorMap, empty_map, fill_one_cell_gaps
from .localize import HEADING_SIGMAS
from .motion import back_prefix, disc_approach, fetch_evidence, forward_to_turn, head_blank_ft, \
    steered_prefix, inner_ring_sweep, \
    shortcut_first_leg, head_commands, head_look, looked_ahead, path_heading, mark_track_free, safe_prefix, looked_free, \
    near_visible_ft, pivot_allowed, pivot_radius_ft, PivotSweep, SMALL_TURN_DEG, clear_unseen, goal_blocker, look_at, \
    push_trail, retrace, backs_over_map
from .octree import FREE, UNKNOWN, VolumeOfInterest, memory_bytes
from .perception import BLANK_LIMITS, BLANK_SIDES, MAX_RANGE_FT, PLACES, SIGHT_LINES, \
    BearingsApart, TwoLookSides
from .passage import narrow_cells
from .planning import GOAL_SLACK_FT, GOALS, PASSAGES, UNCERTAIN_PLANS, plan as plan_path, true_optimum
from .search import NoPath, clearance_map, path_length
from .trajectory import heading_to, wrap

POSES = ("fused", "dead_reckoning", "walls")
LOOK_AROUNDS = ("sweep", "evidence")
STRAIGHT_AFTER = 4                    # passage="stuck": looks without progress before a narrow way
MOVE_RINGS = ("seen", "known", "start")   # DriveConfig.move_ring: a move's band beyond the footprint
TURN_ROOMS = ("off", "forward")       # DriveConfig.turn_room: where a pivot is refused
BACKINGS = ("map", "trail")          # DriveConfig.backing: where a vehicle that reverses backs
RETRACE_FT = 1.5                     # backing="trail": the travel one retrace undoes
RETRACES = 4                         # backing="trail": the most retraces in one run
PROGRESSES = ("moved", "evidence")
TRACK_FREES = ("poses", "swept")
PIVOTS = ("disc", "margin", "swept", "small-swept", "swept-ring", "swept-ring-inner")  # what a pivot needs seen free (.pivot)
EYES = ("rig", "truth", "depth")      # whose ranges the loop sees (DriveConfig.eyes)
MATCHES = ("1985", "improved")        # the rig's stereo matcher (matching.mode.MODES)
DISPARITIES = ("pixel", "subpixel")   # DriveConfig.disparity: where a located edge lies
OCCUPIEDS = ("looks", "model")        # where the map's occupied cells come from
FEATURE_POSES = ("absolute", "drift", "none")    # the pose's share in a feature's covariance
FLOOR_EYES = ("off", "carve", "add", "bound", "bound-add", "veto")   # planner.appearance in the loop (Perception.update)
MAX_MIN_PIVOT_DEG = 5.0               # the largest DriveConfig.min_pivot_deg either check accepts
HIT = "stopped: the vehicle hit something (true footprint against the room)"   # run's reason
LEARN_FLOORS = ("off", "step-back")   # DriveConfig.learn_floor: a first look at the clear spot's floor
STAND_INS = tuple(STAND_IN_SHARES)    # DriveConfig.stand_in: the bottom rows' greys for the floor's
REFUTE_HITS = ("off", "under", "through")        # DriveConfig.refute_hits
HEADS = ("fixed", "pan-tilt", "assist")   # DriveConfig.head
APPROACHES = ("path", "disc")         # DriveConfig.approach: the last move near the goal
FINISHES = ("edge", "inner")          # DriveConfig.finish: where in the goal's disc the run ends
FINISH_INNER_FT = 0.4                 # finish="inner": the estimate this near the goal ends it
FINISH_NEARER_FT = 0.05               # finish="inner": a cycle begun in the disc that brings
                                      # the estimate less nearer than this ends it
HEAD_SWEEP_DEG = (45.0, -45.0, 90.0, -90.0)   # the head's pans when it looks round
MAP_EXTENTS = ("seen", "walls", "fallback")   # DriveConfig.map_extent: what the floor map covers
FINE_MAPS = ("off", "fallback")      # DriveConfig.fine_map: half cells where no map has a way
PLAN_WALLS = ("plan", "grown")      # DriveConfig.plan_walls: where the map draws the plan's walls
WALL_FIX_FIRSTS = ("widened", "base")  # DriveConfig.wall_fix_first
FAR_WITNESS_FT = 1.0                   # wall_fix_far: a far turn's second look from this far on
WALL_POINTS = ("edges", "floor-ends")   # DriveConfig.wall_points: what pose="walls" fixes on
FREE_GAPS = ("keep", "fill")         # DriveConfig.free_gaps: a one-cell unknown gap in free space
# DriveConfig.floor_end_check: a floor end the eyes place nearer, or that moves with the camera
FLOOR_END_CHECKS = ("off", "stereo", "motion")
PROOF_HITS = ("trace", "line")       # DriveConfig.proof_hits: where a hit stops the floor's proof
FREE_CELLS = ("any", "shadows")      # DriveConfig.free_cells: the shadows of a look's runs' ends
PROOF_HEADINGS = ("estimate", "window")   # DriveConfig.proof_heading: the floor ends' heading
FREE_DRIFTS = ("off", "erode", "moves")   # DriveConfig.free_drift: an older look's free space by the drift since
GOAL_EVIDENCES = ("off", "look", "look-expire")   # DriveConfig.goal_evidence
WALL_HITS = ("feature", "plan")          # DriveConfig.wall_hits (evidence.wall_explained)
ONE_GREY_RUNS = ("prove", "near-seen")   # DriveConfig.one_grey_runs
WALL_RUNS = ("none", "past", "foot", "texture", "flat-foot")   # DriveConfig.wall_runs: a floor run up a wall of its grey
TILE_EDGES = ("break", "blend")        # DriveConfig.tile_edges: a tile's averaged edge in a proof
STEERS = ("off", "small", "idle")     # DriveConfig.steer: a path's first leg cut short
GOAL_EXPIRE_LOOKS = 2                 # goal_evidence="look-expire": the looks a goal's blocker lasts


@dataclass
class DriveConfig:
    goal: tuple[float, float]
    unknown: str = "free"                 # planning through unknown space: "free" | "blocked"
    search: str = "dissertation"          # "dissertation" | "astar"
    profile: VehicleProfile = DEFAULT
    tolerance_ft: float = 0.75            # goal reached when the estimate is this near
    max_looks: int = 90                   # cycles, each one look of the fixed rig (under
                                          # head="assist" the head's added look on top); 90
                                          # since 2026-12-07 06:30, 60 before: 11 of the 96
                                          # runs that used up 60 on seeds 1-900 reach the
                                          # goal in 63-89 looks (docs/planner.md, "Ninety
                                          # looks")
    max_stuck: int = 24                   # looks in a row without progress before giving
                                          # up (not 1985; 24 since 2026-12-07 08:30: 5 of
                                          # the 212 runs that gave up after 16 on seeds
                                          # 1-900 reach the goal, docs/planner.md "Twenty-
                                          # four looks"; 16 since 2026-12-05 12:00; 8
                                          # before: the evidence's looks from one place, up
                                          # to 3 at each blocker, used it up)
    looks_per_viewpoint: int = 3          # looks the evidence takes at one blocker from one
                                          # place (turned to it, then looking again while it
                                          # stays in view and unresolved) before it drives
                                          # to another place to see it from (motion.look_at;
                                          # a cell hit once needs more than one look through
                                          # it to be cleared)
    lines: tuple = tuple(range(8, 113, 2))
    voi: VolumeOfInterest = VolumeOfInterest(32.0, 7)
    band: tuple[float, float] = (-0.5, FLOOR_Y - 0.25)   # room Y of the vehicle's passage
    supersample: int = 2                  # render rays per pixel side (1985's pair used 4)
    look_seed: int = 1985                 # sensor noise of look k uses look_seed + k
    max_range_ft: float = MAX_RANGE_FT
    confirm_looks: int = 2                # looks that must hit a cell before it is believed
    free_looks: int = 1                   # carvings that must cross a cell before it is free
    keep_ft: float = 3.0                  # keep the old path unless a new one is this much shorter
    rejoin: str = "leg"                   # where the kept path resumes: "leg" (the nearest leg's
                                          # end; planning._still_good; the default since 2026-12-01
                                          # 22:00) or "waypoint" (the nearest waypoint, before)
    blind_zone: str = "short"             # plan round never-seen cells nearer than a look shows:
                                          # "short" (only within keep_ft; planning.avoid_blind;
                                          # the default since 2026-12-01 22:00), "any" (loses the
                                          # lab under sight_lines="band") or "off" (before)
    trust_view: bool = False              # drive into never-seen cells of the view just looked at
    known_walls: bool = True              # the room's walls as a floor plan (furniture unknown)
    start_clear_ft: float = 2.5           # the vehicle is set down this far from anything
    match: str = "improved"               # the rig's stereo matcher: "1985" (the eyes, bit
                                          # for bit; the default before 2026-12-05 04:30) or
                                          # "improved" (not 1985; the default since: package
                                          # matching's verdict per edge on the in-process
                                          # rig, an edge without a right match left out;
                                          # its scan about 7 ms a look, its default rules
                                          # compiled over the whole frame (matching.frame);
                                          # scan_look)
    eyes: str = "rig"                     # "rig": the matcher's ranges; "truth": the
                                          # true range at the same edge pixels (an oracle
                                          # that separates the planner from the matcher);
                                          # "depth": the true range at EVERY pixel, a dense
                                          # range finder (a diagnostic oracle that
                                          # separates the planner from the eyes;
                                          # planner.depth_eyes)
    disparity: str = "pixel"              # "pixel": LCSL's locations, whole .BI pixels;
                                          # "subpixel" (not 1985; a named option, match
                                          # "improved" and eyes "rig" only): each matched
                                          # edge at its grey step's crossing in the .VD
                                          # pair, twice the .BI's resolution
                                          # (matching.subpixel.subpixel_points)
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
    blank_px: int | None = None           # the blank-column assumption only this many picture
                                          # columns beside a located one (floor_scan's
                                          # blank_px: half max_gap_px, as between two edges;
                                          # 16 from 2026-12-01 14:55, after room 45's
                                          # collision); None (the default since 2026-12-03,
                                          # under floor_eyes "bound-add", each assumed line
                                          # ended where its column's floor ends): the whole
                                          # blank run
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
    pivot: str = "swept-ring"             # what a pivot in place needs seen free: "disc"
                                          # (the default before 2026-12-05 09:30): its whole
                                          # circle (the footprint's half diagonal), whatever
                                          # the angle, without the margin forward moves keep
                                          # (room 774: cells of a box's face of the floor's
                                          # grey shown free, 0.13 ft deep, inside the circle;
                                          # a 70 deg pivot hit the box); "margin": that
                                          # circle grown by the planning margin against the
                                          # estimate's error (motion.pivot_radius_ft); "swept":
                                          # the cells the footprint, grown by the margin, sweeps
                                          # through the angle (_pivot_seen_free; the default
                                          # 2026-12-05 09:30-19:10); "small-swept":
                                          # a turn up to SMALL_TURN_DEG (5) by its sweep, a
                                          # larger one by the disc (motion._pivot_ok);
                                          # "swept-ring" (not 1985; the default since
                                          # 2026-12-05 19:10): the bare footprint's sweep
                                          # seen free, a cell of the margin's ring never
                                          # seen will do where nothing a look placed lies
                                          # within the planning radius of it (room 523;
                                          # rooms 774 and 857 without that radius);
                                          # "swept-ring-inner" (not 1985): "swept-ring",
                                          # but a turn made only to look (at evidence, or
                                          # round) needs the footprint grown by
                                          # PIVOT_INNER_FT seen free as well (room 32)
    move_ring: str = "start"              # a forward move's swept band beyond the bare
                                          # footprint (the margin's ring): "seen" (every
                                          # cell seen); "known" (not 1985): a never-seen
                                          # cell will do where nothing a look placed lies
                                          # within the planning radius of it
                                          # (FloorMap.move_ring, motion.clear_unseen), as
                                          # pivot="swept-ring" lets a pivot's ring; "start"
                                          # (not 1985; the default since 2026-12-06): that
                                          # only where the grown footprint stands at the
                                          # move's start, which every pivot there sweeps
                                          # too (room 105)
    passage: str = "moves"                # where the vehicle may pass (planner.passage):
                                          # "circle": paths and forward moves alike where
                                          # the pivot circle and the margin fit (before
                                          # 2026-12-06); "moves" (not 1985; the default
                                          # since 2026-12-06): the circle's paths, and a
                                          # forward move may also cross cells where only
                                          # its grown width fits, out to its grown nose
                                          # (room 516); "straight" (not 1985): and where the
                                          # circle finds no way to the goal, paths through
                                          # such cells on straight lines from and to cells
                                          # the circle fits in; "stuck" (not 1985): those
                                          # paths only after STRAIGHT_AFTER looks without
                                          # progress
    steer: str = "idle"                   # the path's first leg cut short by the checks
                                          # every move passes: "off" (before 2026-12-06):
                                          # the path's heading; "small" (not 1985): the
                                          # same leg up to STEER_MAX_DEG off it, nearest
                                          # first, where the checks let it run
                                          # STEER_GAIN_FT farther (motion.steered_prefix;
                                          # room 10; 2 collisions in 890 rooms); "idle"
                                          # (not 1985; the default since 2026-12-06): that
                                          # only in place of a look round, where the path,
                                          # the look-ahead, the approach, the evidence and
                                          # facing the path give the vehicle nothing to do
    min_pivot_deg: float = 1.0            # a turn of the path's commands smaller than this
                                          # needs no pivot circle seen free (not 1985; the
                                          # default since 2026-12-05 08:00; 0: every turn
                                          # checked, before): 1 deg moves the footprint's
                                          # corners 0.011 ft, inside the 0.15 ft planning
                                          # margin, and the path's own alignments (0.1 deg
                                          # in the bundled lab) stopped drives "cannot turn"
    clearance_at: str = "anywhere"        # "anywhere": the dissertation's, the cross section
                                          # passes anywhere in a passable cell; "centre":
                                          # a cell's centre has the radius and every
                                          # position is tested exactly; "anywhere-exact":
                                          # anywhere, by the exact gap between the cell
                                          # squares (search.clearance_map)
    growth: str = "covariance"            # "covariance": a hit grown by its whole covariance
                                          # (the dissertation's); "across": by its error
                                          # across the sight line only (across_sight_cov)
    pose: str = "walls"                   # the camera estimate: "fused" (the symbolic
                                          # model's, model.mapping.Walker),
                                          # "dead_reckoning" (the odometry alone; the
                                          # default before 2026-12-05) or "walls" (not
                                          # 1985; the default since: each look's points on
                                          # the floor plan's walls fused with the
                                          # odometry's prior, planner.localize)
    pose_method: str = "robust"           # the walk's driving method under "fused"
    turn_room: str = "forward"            # no pivot is allowed where the vehicle stands
                                          # (nor a BACK): "forward" (not 1985; the default
                                          # since 2026-12-05 15:00): the shortest straight
                                          # move on after which one is (motion.forward_to_turn);
                                          # "off": it stays and looks again
    backing: str = "trail"                # where the vehicle backs: "map" (the default
                                          # before 2026-12-07 12:15): where the profile
                                          # reverses, straight back over space seen free
                                          # (motion.back_prefix), wherever it cannot turn or
                                          # is too near what it must look at, and at the
                                          # first look's step back; "trail" (not 1985; the
                                          # default since; the vehicle then reverses,
                                          # whatever the profile): only where it cannot
                                          # turn at all (after turn_room's move) outside
                                          # the goal's disc, undoing its own last motions
                                          # (motion.retrace: ground its wheels have swept,
                                          # whatever the map shows), RETRACE_FT at a time,
                                          # at most RETRACES times a run; else it moves as
                                          # a vehicle that does not reverse
    look_around: str = "evidence"         # the vehicle cannot move: "sweep" (the default
                                          # before 2026-12-04): face the path, then turn
                                          # +35 / -70 deg in place; "evidence" (not 1985;
                                          # the default since 2026-12-04, with free_drift
                                          # "moves" and plan_walls "grown", which hold its
                                          # longer drives' heading drift off the boxes and
                                          # walls): look at where the path lacks it, from
                                          # where it shows (fetch_evidence)
    track_free: str = "poses"             # free where the vehicle stood: "poses": its
                                          # footprint at each pose; "swept" (a named
                                          # option): every pose between as well, shrunk
                                          # by the margin (mark_track_free)
    progress: str = "moved"               # what resets the count toward max_stuck:
                                          # "moved": any motion; "evidence" (measured, not
                                          # adopted): a shorter way left than ever, or new
                                          # free space seen
    occupied: str = "model"               # the map's occupied / uncertain cells: "model"
                                          # (the default since 2026-12-05 13:45): drawn
                                          # each cycle from the floor features, fused look
                                          # by look (planner.features; Perception.update);
                                          # "looks": every look's hits as log-odds, grown
                                          # by that look's covariance, never shrunk
    feature_pose: str = "absolute"        # under occupied="model", the pose error in each
                                          # observation's covariance: "absolute": the
                                          # dead-reckoned pose's whole covariance;
                                          # "drift": the features kept in the dead-reckoned
                                          # frame, an old feature's covariance grown by the
                                          # drift since it was last seen; "none"
    hit_at: str = "point"                 # where a look's range lands on the floor plane
                                          # (perception.floor_scan's place): "axis": laid
                                          # along the pitched optical axis (short by up to
                                          # its cosine; the default before 2026-12-05);
                                          # "point" (the default since): the located
                                          # point's own horizontal position
    approach: str = "disc"                # the last move near the goal: "disc" (not 1985;
                                          # the default since 2026-12-02 01:20): where the
                                          # path's safe prefix drives nowhere within a step of
                                          # the goal's disc, of the straight moves safe_prefix
                                          # allows the one ending nearest the goal, inside
                                          # tolerance_ft - 0.1 (motion.disc_approach); "path":
                                          # the path's prefix only (the default before)
    finish: str = "inner"                 # where in the goal's disc the run ends (not 1985):
                                          # "inner" (the default since 2026-12-07): on toward
                                          # the goal until the estimate is within
                                          # FINISH_INNER_FT, or a cycle begun in the disc
                                          # brings it no nearer (each such cycle also looks,
                                          # and so fixes the estimate); "edge" (before): as
                                          # soon as the estimate is within tolerance_ft
    goal_region: str = "disc"             # what the planner plans to (not 1985): "disc"
                                          # (the default since 2026-12-05 11:10): the
                                          # standable cell reachable from the estimate inside
                                          # the tolerance disc that is nearest the goal
                                          # (goal_target), the goal itself where the vehicle
                                          # may stand there; "point" (before): the goal
                                          # itself, refused when the map puts an obstacle
                                          # within the planning radius of it.  The loop's
                                          # success test is the disc either way
    floor_eyes: str = "bound-add"         # what the picture shows of the floor (planner.appearance)
                                          # (planner.appearance, not 1985): "off"; "carve":
                                          # once the floor's grey is learned, each column's
                                          # floor in view carved as a proof in place of the
                                          # blank-column assumption; "add": the floor's
                                          # proof and the assumption (under its own rules)
                                          # both; "veto": "carve" and leave out the located
                                          # points the floor in view contradicts; "bound"
                                          # (the default 2026-12-02 to 12-03): nothing carved,
                                          # each assumed line ends where its column's floor
                                          # in view ends; "bound-add" (the default since
                                          # 2026-12-03): "bound", and the learned floor's
                                          # proof carved no farther than that end
    expire_uncertain: int = 0             # 0 (off): an uncertain (once-hit) cell stays until
                                          # sight lines clear it; N (a named option, not
                                          # 1985): after N later looks had it in view and
                                          # located nothing there, it shows UNKNOWN (never
                                          # free) on the map (Perception.expire_in_view);
                                          # under occupied="model" the floor feature seen
                                          # once is retired (expire_features_in_view)
    uncertain: str = "core"               # no path avoids the uncertain cells: "core" (the
                                          # default since 2026-12-05 22:40, not 1985): plan
                                          # round only the uncertain features' one-sigma
                                          # cells and look again from nearer, never driven
                                          # near any (plan(); under occupied="looks", with
                                          # no features, every uncertain cell, as
                                          # "blocked"); "blocked": toward the reachable cell
                                          # nearest the goal; "look" (measured, not
                                          # adopted): plan through them all, the same way
    goal_evidence: str = "look-expire"    # (the default since 2026-12-06 16:45, with
                                          # wall_fix_far 30; "off" before)
                                          # no path reaches the goal: look round ("off"); "look"
                                          # (a named option, not 1985): first look at the
                                          # uncertain cell nearest the goal within the planning
                                          # radius, from where a look shows it (the path's
                                          # evidence's turn or viewpoint): a feature one look
                                          # placed at the goal, too near to show (room 113);
                                          # "look-expire": that, and such a feature whose
                                          # two-sigma ellipse reaches the goal's planning
                                          # radius expires after GOAL_EXPIRE_LOOKS looks
                                          # (expire_uncertain's rule, under occupied="model")
    wall_hits: str = "plan"               # (the default since 2026-12-06 20:30, with
                                          # one_grey_runs "near-seen"; "feature" before)
                                          # a floor hit whose two-sigma ellipse (the pose's
                                          # share in it) reaches the floor plan's walls:
                                          # "feature": a floor feature as any hit; "plan"
                                          # (not 1985; with known_walls): the plan's wall
                                          # explains it, no feature is started or fused
                                          # (evidence.wall_explained; room 119; seeds 1-900
                                          # alone: 638 goals against 627, but a collision
                                          # in room 881, which one_grey_runs mends)
    one_grey_runs: str = "near-seen"      # on a tiled floor (two learned greys), a column
                                          # whose floor run shows one of them only: "prove"
                                          # (before 2026-12-06 20:30) as any run; "near-seen"
                                          # (not 1985): only where the last map showed the
                                          # floor before its bottom row free (a face of that
                                          # grey there fills the bottom rows; room 881).
                                          # With wall_hits "plan", seeds 1-900: 632 goals
                                          # (597 by the truth) against 627 (596), no collision
    seen_cost: float = 0.0                # 0 (off): the path search as --search says; W > 0
                                          # (a named option, not the dissertation's; measured,
                                          # not adopted): A* where a cell within the pivot
                                          # circle (half diagonal) of a never-seen cell costs
                                          # 1 + W per ft, the path pulled taut outside them
                                          # (planning.seen_search): paths keep to what was in view
    look_ahead: bool = True               # (not 1985; the default since 2026-12-01) before
                                          # a move, the first never-seen cell on the path's swept band
                                          # (the next step + near_visible_ft): the move cut
                                          # while it can still show, a pivot to bring it in
                                          # view, a look (motion.look_ahead); each cell once
    sight_lines: str = "low"              # what a sight line to a hit frees: "low" (the
                                          # default since 2026-12-01, not 1985): only where
                                          # its ray runs below the lowest obstacle's top (a
                                          # box lower than the ray hides under it;
                                          # perception.floor_scan's low_y); "band" (the
                                          # default before): the whole height band up to it;
                                          # "low-all": "low", and a look that located nothing
                                          # frees only the far part of its blank view (as if
                                          # a surface at blank_ft showed to the band's bottom)
    learn_floor: str = "step-back"        # (not 1985; for floor_eyes) "step-back" (the default
                                          # since 2026-12-05 09:30): before the first look the
                                          # vehicle steps learn_back_ft back inside the clear
                                          # spot it was set down in (BACK where its profile
                                          # reverses, else TURN 180, FORWARD, TURN -180), so the
                                          # first look's bottom rows show floor the clear spot
                                          # vouches for and the floor's grey is learned from it
                                          # (Drive.step_back; without it the grey was never
                                          # learned in 154 rooms of 890, and none was reached);
                                          # "off" (before): learned once the map shows floor
                                          # free.  Only where a look reads the floor's grey
                                          # (steps_back: not under floor_eyes "off", nor
                                          # with the depth eyes under a bounding one)
    learn_back_ft: float = 1.25           # (1.0 ft leaves 249 training pixels, 1.25 ft 427)
    stand_in: str = "tenth"               # (not 1985; under floor_eyes in BOUNDING) what stands for
                                          # the floor's grey until it is learned: "tenth" (every
                                          # grey with a tenth of the picture's bottom 4 rows) or
                                          # "majority" (only a grey with more than half; none:
                                          # nothing assumed; room 256 under band; appearance.nearest_greys)
    refute_hits: str = "off"              # (not 1985; a named option) "under": a hit cell a
                                          # later sight line passes under (below the hit's
                                          # lowest located point, to a surface beyond it)
                                          # shows unknown, never free (Perception.refute_hits);
                                          # "through": a hit a later, nearer look sees through
                                          # (two points located farther at its pixel) refuted,
                                          # a cell all of whose hits are refuted unknown
                                          # (Perception._refute_through)
    stereo_margin: bool = False           # (not 1985; a named option) each free column
                                          # frees its line only from the depth the right
                                          # camera sees it at (perception.stereo_depth:
                                          # f B / (c - 1); room 177's box at the left edge)
    wall_fix_sigmas: float = HEADING_SIGMAS   # under pose="walls": how far from the prior's
                                          # heading (its standard deviations) a fix may
                                          # turn it (localize.HEADING_SIGMAS; 3 before
                                          # 2026-12-05, when a floor-grey skirting turned
                                          # room 684's heading 6 deg and it hit a box)
    wall_fix_widen: float = 1.0           # (not 1985; the default since 2026-12-05 09:30; 0:
                                          # as before) the fix's window grows by this many
                                          # sigmas for each look in a row without a fix: a
                                          # prior off by more than wall_fix_sigmas (an
                                          # odometry tail, room 175: 5.3 deg in two commands
                                          # against 1.4 sigma) is found again at the next look
                                          # instead of drifting on until a wrong fix
    wall_fix_most: float | None = 4.0     # (not 1985; the default since 2026-12-06 11:45)
                                          # the widened window at most this many sigmas
                                          # (never less than wall_fix_sigmas); None: no
                                          # bound, before.  A consensus is the heading most
                                          # points agree on anywhere in the window: 8 and 11
                                          # sigmas wide it took about 20 points 14-17 deg
                                          # off for a wall (rooms 321, 329, fine_map)
    wall_fix_far: int = 30                # (not 1985; the default since 2026-12-06 16:45,
                                          # with goal_evidence "look-expire"; 0: off) a fix more
                                          # than 3 sigmas from the prior's heading on fewer
                                          # points than this is taken only where a later
                                          # look from FAR_WITNESS_FT or more away shows one
                                          # turning it as far the same way (localize.far_turn;
                                          # room 2: 13 points turned it 10.6 deg, 3.5 sigma,
                                          # the wrong way)
    wall_fix_far_sigmas: float = 3.0      # wall_fix_far's "far": a turn more than this many
                                          # standard deviations of the prior's heading
                                          # (localize.FAR_SIGMAS); lower (not 1985; a named
                                          # option): room 583's fix on 6 points of a far
                                          # wall turned it 10.7 deg, 2.5 sigma, the wrong
                                          # way; 2, seeds 1-900: 629 goals against 632
    wall_fix_first: str = "widened"       # which window a widened fix searches: "widened"
                                          # (as since 09:30): the whole widened window at
                                          # once; "base" (not 1985; a named option): the
                                          # base window first, the widened one only where it
                                          # finds no fix (room 866: 75 points at a heading
                                          # 10 deg off outvoted 10 on the far wall);
                                          # seeds 1-900: 540 goals against 541, not adopted
    min_range_ft: float = 3.0             # located points nearer than this are left out of
                                          # the floor scan, the wall fix and the floor end
                                          # check (perception.filter_points): 2.5 ft (a
                                          # disparity of 54 px) before 2026-12-05; 3.0 (45 px)
                                          # since: from 2.5 to 3 ft 38 % of the 1985 matcher's
                                          # points lie 0.5 ft or more in front of the truth
                                          # (the lab's bookcase, a picket fence, by its goal)
    min_confidence: float = 0.0           # 0 (off): every point the matcher located; C > 0
                                          # (not 1985; a named option, match "improved"
                                          # only): the points whose verdict's confidence
                                          # (matching.Verdict) is under C are left out of
                                          # the look (matching.mode.vouched_points): on
                                          # rooms 49, 211, 405, 444 a third of the points
                                          # under 0.2 lie outside their own error bound,
                                          # against 8 % of those from 0.8; 0.2, seeds
                                          # 1-356: 258 goals against 260, not adopted
    head: str = "fixed"                   # (not 1985; a named option) "fixed": the rig as
                                          # mounted; "pan-tilt": on a head (PAN, TILT;
                                          # VehicleProfile.head) that looks where the loop
                                          # pivoted only to look: at the first never-seen
                                          # cell of the way (tilted down to see it), into the
                                          # pivot circle, round; the body drives with the
                                          # head at 0/0 (head_commands)
                                          # "assist": the fixed rig's cycle unchanged, and
                                          # where it would stop or pivot only to look, the
                                          # head's look (head_look) added first, the cycle
                                          # decided again with it (looks counts both;
                                          # measured 2026-12-05, not adopted: more goals
                                          # of seeds 1-900, the bundled lab far fewer)
    plan_walls: str = "grown"             # the floor plan's walls on the map: "plan" (where
                                          # the plan has them; the default before
                                          # 2026-12-04) or "grown" (not 1985; the default
                                          # since; rooms 7 and 272 under free_drift "moves"):
                                          # 2 sigma of the estimate's x, z nearer
                                          # (evidence.wall_growth), as the assumption stops
                                          # short of them: the map is placed by the estimate
                                          # (room 471: 0.8 ft of drift, driven into the wall)
    free_drift: str = "moves"             # an older look's free space on the map: "off" (as
                                          # proved; the default before 2026-12-04), "erode"
                                          # (not 1985; named): shrunk beside a hit by 2 sigma
                                          # of the odometry's drift since that look
                                          # (planner.drift; rooms 219, 298, 640, 471), or
                                          # "moves" (not 1985; the default since 2026-12-04):
                                          # "erode" for moves, a pivot's cells checked on the
                                          # map before it (FloorMap.drift_kept; under "erode"
                                          # a vehicle beside a box "cannot turn")
    wall_points: str = "floor-ends"       # under pose="walls", what the fix uses: "edges" (the
                                          # look's located points) or "floor-ends" (not 1985;
                                          # the default since 2026-12-05; the rig's eyes
                                          # only): those and where the floor in view ends,
                                          # each second column (localize.floor_end_points)
    free_gaps: str = "fill"               # an UNKNOWN cell between two FREE ones across a row
                                          # or a column: "fill" (not 1985; the default since
                                          # 2026-12-05 05:10, with the improved matcher):
                                          # free (floormap.one_cell_gaps: no box fits there
                                          # that misses both; the floor in view leaves such
                                          # stripes, room 57); "keep" (unknown; before)
    proof_hits: str = "line"              # where the floor in view carves (floor_eyes "carve",
                                          # "add", "veto", "bound-add"), the proof of a
                                          # picture row: never past a cell any look has hit
                                          # on its trace (d (1 - h / H) to d; "trace"), or on
                                          # its whole line from the camera ("line", not 1985;
                                          # the default since 2026-12-05): a box nearer
                                          # than the picture's bottom row
                                          # with a face of the floor's grey (room 293)
    free_cells: str = "any"               # what the floor in view and the blank-column
                                          # assumption may free: "any" cell their samples
                                          # reach, or "shadows" (not 1985): none on any
                                          # column's sight line within 2 ft past where its
                                          # floor run ends in that look
                                          # (appearance.run_shadows; room 230 under reverse:
                                          # the floor seen beside a box's corner freed the
                                          # cells along its hidden face, three quarters box)
    wall_runs: str = "flat-foot"          # under floor_eyes "bound"/"bound-add", a column whose
                                          # floor run goes on up past the plan's walls or to the
                                          # picture's top: it shows no floor's end ("none");
                                          # "texture" (not 1985; the default 2026-12-06 to -08):
                                          # its end is where the floor's tiles are last seen in
                                          # it (appearance.texture_end; a wall of a tile's
                                          # grey, room 341, a box face of it, room 773);
                                          # "foot" (a named option, not 1985): its end is the
                                          # walls' foot less their growth; "past": that only
                                          # for a run that ends past the walls; "flat-foot"
                                          # (not 1985; the default since 2026-12-08):
                                          # "texture", and on a flat floor "foot" cut at
                                          # every located point within a box's width, each
                                          # cell proven only when a look from a bearing 20
                                          # deg away proves it too
                                          # (Perception._carve_flat_foot)
    flat_foot_apart_deg: float = FLAT_FOOT_APART_DEG   # under wall_runs "flat-foot": the
                                          # bearings of a cell from the two looks that must
                                          # both prove it, at least this far apart (20;
                                          # Perception.foot_bearings; 30, a named option:
                                          # room 95 under looks_per_viewpoint 1 drove into a
                                          # box face of the floor's grey whose front row two
                                          # bearings 22 deg apart proved)
    tile_edges: str = "break"             # under floor_eyes "bound-add", the proof's run of the
                                          # learned greys: a pixel of another grey ends it
                                          # ("break"), or (a named option, not 1985; "blend")
                                          # a lone pixel between greys of the floor pixels
                                          # above and below it does not: a tiled floor's edge
                                          # (appearance.floor_run)
    floor_end_check: str = "motion"       # under floor_eyes "bound"/"bound-add": "off", or
                                          # "stereo" (not 1985; the default from 2026-12-05
                                          # to 2026-12-06): a located point in a
                                          # column's floor run, clearly nearer than the floor
                                          # its pixel would show, ends the column's floor there,
                                          # and three on one run top the whole edge
                                          # (appearance.raised_ends: a face or top of the
                                          # floor's grey, rooms 34, 278, 566); "motion" (not
                                          # 1985; the default since 2026-12-06 15:40):
                                          # "stereo", and a run's end that moved with the
                                          # camera since two earlier looks from elsewhere ends
                                          # on an edge above the floor, drawn occupied
                                          # (appearance.raised_by_motion; room 860's face of
                                          # a tile's grey)
    proof_heading: str = "window"         # under floor_eyes "bound"/"bound-add", the look's
                                          # floor ends laid down along: "estimate" (its
                                          # heading) or "window" (not 1985; the default
                                          # since 2026-12-05): each
                                          # column only as far as every column within
                                          # drift_sigmas of the heading's standard deviation
                                          # shows (appearance.within_heading; rooms 6, 34, 49)
    drift_sigmas: float = 2.0             # under "erode", "moves": the standard deviations of the
                                          # drift a free edge beside a hit gives up
    map_extent: str = "fallback"          # what the floor map (the search's space) covers:
                                          # "seen": every hit so far, the estimate and the
                                          # goal, 2 ft round (its border blocks the search);
                                          # "walls" (not 1985; a named option, needs
                                          # known_walls): the room's floor plan as well, so a
                                          # way through never-seen space by the walls is
                                          # planned (map_around; docs/planner.md, "The
                                          # detours with eyes that see everything");
                                          # "fallback" (not 1985; the default since
                                          # 2026-12-05 16:30, needs known_walls): "seen",
                                          # and where no path to the goal lies on it but
                                          # one lies on the map out to the walls, that map
                                          # for the cycle (Drive.map_to_plan_on); seeds
                                          # 1-900: 541 goals against 529, 0 collisions
    fine_map: str = "fallback"            # (not 1985; the default since 2026-12-06 15:40,
                                          # with floor_end_check "motion") "fallback": where
                                          # neither map of map_extent has a path to the goal,
                                          # the same maps on cells of half the side, the
                                          # features and the walls drawn again on them
                                          # (Perception.halved_map: only the blocked cells
                                          # shrink), for the cycle; "off": never
                                          # (Drive.map_to_plan_on)
    assist_pivot_ft: float | None = 4.64  # head="assist" only: a pivot's cells may not be
                                          # FREE only by an assumption made from farther
                                          # than this (2 x the 2.32 ft nearest proof;
                                          # evidence.assumed_columns; room 45); None: off


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
    render_s: float             # the rendering of the cycle's looks (with the head's, under assist)
    work_s: float               # scan + model + octree + plan of the cycle's looks (their
                                # rendering excluded; under assist the head's look and the
                                # decision taken again with it are counted too)
    path: list = field(default_factory=list)
    fmap: FloorMap | None = None
    scan_s: float = 0.0         # the rig's scan alone (part of work_s): the matcher's cost
    track_len: int = 0          # poses in the true (and estimate) track once the cycle's
                                # commands ran: the track has one pose per command, not per cycle
    head_looks: int = 0         # head="assist": the head's looks added to this cycle's
    work_cpu_s: float = 0.0     # work_s as this thread's CPU time: what the machine's other
                                # work does not stretch (time.thread_time)


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
                                               # (the floor features, under occupied="model")
    wall_fixes: int | None = None              # under pose="walls": the looks that gave a fix
    drift_eroded: int | None = None            # under free_drift "erode", "moves": the FREE cells the
                                               # last map gave up to the drift
    retraces: int | None = None                # under backing="trail": the retraces taken

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
    def work_ms_per_look(self) -> float:
        """``work_ms_per_cycle`` per look: the same without a head's added looks."""
        return 1e3 * float(sum(c.work_s for c in self.cycles)) / self.looks if self.looks else 0.0

    @property
    def work_cpu_ms_per_cycle(self) -> float:
        """``work_ms_per_cycle`` in this thread's CPU time."""
        return 1e3 * float(np.mean([c.work_cpu_s for c in self.cycles])) if self.cycles else 0.0

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
            "work_ms_per_look": round(self.work_ms_per_look, 2),
            "work_cpu_ms_per_cycle": round(self.work_cpu_ms_per_cycle, 2),
            "render_ms_per_cycle": round(self.render_ms_per_cycle, 2),
            "scan_ms_per_cycle": round(self.scan_ms_per_cycle, 2), "match": self.match,
            "seconds": round(self.seconds, 3), "octree_bytes": self.octree_bytes,
            "final_true_error_ft": round(self.final_true_error_ft, 3),
            "start": [self.start.x, self.start.z, self.start.heading_deg],
            "goal": list(self.goal), "unknown": self.unknown, "search": self.search,
            "pose": self.pose, **({"floor": self.floor} if self.floor else {}),
            **({"expired_uncertain": self.expired_uncertain}
               if self.expired_uncertain is not None else {}),
            **({"wall_fixes": self.wall_fixes} if self.wall_fixes is not None else {}),
            **({"drift_eroded": self.drift_eroded} if self.drift_eroded is not None else {}),
            **({"retraces": self.retraces} if self.retraces is not None else {}),
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
                        "work_cpu_ms": round(1e3 * c.work_cpu_s, 2),
                        "scan_ms": round(1e3 * c.scan_s, 2),
                        "render_ms": round(1e3 * c.render_s, 2)} for c in self.cycles],
        }


def scan_look(left, right, lines, match: str = "1985"):
    """The rig's scan (a ``rig.scan.ScanResult``) of one look's .BI pair over
    ``lines``.  ``"1985"``: the eyes (the compiled frame scan, the same result
    as the reference rig, bit for bit).  ``"improved"`` (not 1985): a fresh
    improved matcher (its default constraints: order, lr, neighbours, region,
    confirm) on the eyes' compiled slices and edge maps of every line
    (:mod:`eyes.improved`), the scan the in-process reference rig gives with
    it, as ``rig walk --match improved``, line for line (only its count of
    NBLOB round trips is MASL's alone); its line results carry the verdicts
    (``matching.mode.located_points`` gives each point's confidence)."""
    if match not in MATCHES:
        raise ValueError(f"unknown stereo matcher {match!r}; one of {', '.join(MATCHES)}")
    if match == "1985":
        from eyes import scan_pair
        return scan_pair(left, right, lines=lines)
    from eyes.improved import scan_pair
    return scan_pair(left, right, lines)


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


def _check_config(cfg: DriveConfig) -> None:
    """One clear ValueError for the first value of ``cfg`` the loop does not know."""
    if cfg.match not in MATCHES:
        raise ValueError(f"unknown stereo matcher {cfg.match!r}; one of {', '.join(MATCHES)}")
    if cfg.pose not in POSES:
        raise ValueError(f"unknown camera estimate {cfg.pose!r}; one of {', '.join(POSES)}")
    for name, allowed in (("eyes", EYES), ("pivot", PIVOTS), ("look_around", LOOK_AROUNDS),
                          ("turn_room", TURN_ROOMS), ("backing", BACKINGS),
                          ("move_ring", MOVE_RINGS),
                          ("passage", PASSAGES), ("steer", STEERS),
                          ("progress", PROGRESSES), ("uncertain", UNCERTAIN_PLANS),
                          ("track_free", TRACK_FREES), ("goal_region", GOALS),
                          ("floor_eyes", FLOOR_EYES), ("blank_carve", ("unknown", "always")),
                          ("blank_limit", BLANK_LIMITS), ("blank_sides", BLANK_SIDES),
                          ("sight_lines", SIGHT_LINES), ("stand_in", STAND_INS),
                          ("occupied", OCCUPIEDS),
                          ("hit_at", PLACES), ("feature_pose", FEATURE_POSES),
                          ("approach", APPROACHES), ("finish", FINISHES), ("head", HEADS),
                          ("refute_hits", REFUTE_HITS), ("map_extent", MAP_EXTENTS),
                          ("fine_map", FINE_MAPS),
                          ("plan_walls", PLAN_WALLS), ("learn_floor", LEARN_FLOORS),
                          ("free_drift", FREE_DRIFTS), ("free_gaps", FREE_GAPS),
                          ("wall_points", WALL_POINTS), ("wall_fix_first", WALL_FIX_FIRSTS),
                          ("proof_heading", PROOF_HEADINGS),
                          ("floor_end_check", FLOOR_END_CHECKS), ("proof_hits", PROOF_HITS),
                          ("free_cells", FREE_CELLS),
                          ("goal_evidence", GOAL_EVIDENCES), ("wall_runs", WALL_RUNS),
                          ("wall_hits", WALL_HITS), ("one_grey_runs", ONE_GREY_RUNS),
                          ("tile_edges", TILE_EDGES)):
        if getattr(cfg, name) not in allowed:
            raise ValueError(f"unknown {name} {getattr(cfg, name)!r}; one of {', '.join(allowed)}")
    for name in ("max_looks", "max_stuck", "looks_per_viewpoint"):
        count = getattr(cfg, name)
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise ValueError(f"{name} {count!r}: a count of looks, at least 1")
    if cfg.head != "fixed" and cfg.pose == "fused":
        raise ValueError(f"head {cfg.head!r} with pose 'fused': the walk's camera estimate "
                         "assumes the fixed rig's pitch; use head 'fixed' with it, or pose "
                         "'dead_reckoning' or 'walls'")
    if cfg.map_extent != "seen" and not cfg.known_walls:
        raise ValueError(f"map_extent {cfg.map_extent!r} needs known_walls: without the floor "
                         "plan the room's walls are not known; use map_extent 'seen'")
    if cfg.pose == "walls" and not cfg.known_walls:
        raise ValueError("pose 'walls' fixes the estimate against the room's walls: it needs "
                         "known_walls (the floor plan); use pose 'dead_reckoning'")
    if cfg.learn_floor != "off":
        reach = step_back_reach_ft(cfg)
        if not 0 < cfg.learn_back_ft or reach > cfg.start_clear_ft:
            raise ValueError(f"learn_back_ft {cfg.learn_back_ft!r}: the step back and the "
                             f"turn there ({reach:.2f} ft) must stay inside the clear spot "
                             f"(start_clear_ft {cfg.start_clear_ft:g} ft) and be more than 0")
    if isinstance(cfg.min_range_ft, bool) or not isinstance(cfg.min_range_ft, (int, float)) \
            or not 0 < cfg.min_range_ft < cfg.max_range_ft:
        raise ValueError(f"min_range_ft must be a distance in feet above 0 and under "
                         f"max_range_ft ({cfg.max_range_ft:g}), not {cfg.min_range_ft!r}")
    for name in ("wall_fix_sigmas", "drift_sigmas"):
        sigmas = getattr(cfg, name)
        if not (isinstance(sigmas, (int, float)) and 0 < sigmas < 10):
            raise ValueError(f"{name} must be a number of standard deviations above 0 and "
                             f"under 10, not {sigmas!r}")
    if isinstance(cfg.wall_fix_widen, bool) or not isinstance(cfg.wall_fix_widen, (int, float)) \
            or not 0 <= cfg.wall_fix_widen < 10:
        raise ValueError(f"wall_fix_widen must be a number of standard deviations from 0 (off) "
                         f"to under 10, not {cfg.wall_fix_widen!r}")
    if cfg.wall_fix_most is not None and (
            isinstance(cfg.wall_fix_most, bool) or not isinstance(cfg.wall_fix_most, (int, float))
            or not 0 < cfg.wall_fix_most < 10):
        raise ValueError(f"wall_fix_most must be None (no bound) or a number of standard "
                         f"deviations above 0 and under 10, not {cfg.wall_fix_most!r}")
    if isinstance(cfg.min_confidence, bool) or not isinstance(cfg.min_confidence, (int, float)) \
            or not 0 <= cfg.min_confidence < 1:
        raise ValueError(f"min_confidence must be a number from 0 (off) to under 1, "
                         f"not {cfg.min_confidence!r}")
    if cfg.min_confidence and cfg.match != "improved":
        raise ValueError(f"min_confidence needs the improved matcher's verdicts "
                         f"(match 'improved'), not match {cfg.match!r}")
    if isinstance(cfg.flat_foot_apart_deg, bool) or \
            not isinstance(cfg.flat_foot_apart_deg, (int, float)) or \
            not 0 < cfg.flat_foot_apart_deg < 180:
        raise ValueError(f"flat_foot_apart_deg must be an angle in degrees above 0 and "
                         f"under 180, not {cfg.flat_foot_apart_deg!r}")
    if cfg.disparity not in DISPARITIES:
        raise ValueError(f"disparity must be one of {', '.join(DISPARITIES)}, "
                         f"not {cfg.disparity!r}")
    if cfg.disparity == "subpixel" and (cfg.match != "improved" or cfg.eyes != "rig"):
        raise ValueError(f"disparity 'subpixel' needs the improved matcher's verdicts and "
                         f"the rig's own ranges (match 'improved', eyes 'rig'), not match "
                         f"{cfg.match!r} with eyes {cfg.eyes!r}")
    if isinstance(cfg.wall_fix_far_sigmas, bool) \
            or not isinstance(cfg.wall_fix_far_sigmas, (int, float)) \
            or not 0 < cfg.wall_fix_far_sigmas < 10:
        raise ValueError(f"wall_fix_far_sigmas must be a number of standard deviations above "
                         f"0 and under 10, not {cfg.wall_fix_far_sigmas!r}")
    if isinstance(cfg.wall_fix_far, bool) or not isinstance(cfg.wall_fix_far, int) \
            or cfg.wall_fix_far < 0:
        raise ValueError(f"wall_fix_far must be a number of points, 0 (off) or more, "
                         f"not {cfg.wall_fix_far!r}")
    if not (isinstance(cfg.min_pivot_deg, (int, float))
            and 0 <= cfg.min_pivot_deg <= MAX_MIN_PIVOT_DEG):
        raise ValueError(f"min_pivot_deg must be a turn of 0 (every turn a pivot) to "
                         f"{MAX_MIN_PIVOT_DEG:g} deg, not {cfg.min_pivot_deg!r}")
    if cfg.blank_px is not None and cfg.blank_px < 0:
        raise ValueError(f"blank_px must be 0 or more columns, not {cfg.blank_px!r}")
    if not isinstance(cfg.expire_uncertain, (int, np.integer)) or isinstance(
            cfg.expire_uncertain, bool) or cfg.expire_uncertain < 0:
        raise ValueError(f"expire_uncertain must be a whole number of looks >= 0 (0: off), "
                         f"not {cfg.expire_uncertain!r}")


def map_around(est: State, goal, bounds, extent: str = "seen") -> list:
    """The points the cycle's floor map must cover (:meth:`Perception.floor_map` adds
    every hit so far and 2 ft round, and its border blocks the search): the estimate
    and the goal; under ``extent="walls"`` also two opposite corners of the room's
    floor plan ``bounds`` (x0, x1, z0, z1), so the search may plan through never-seen
    space all the way to the walls.  With only what was seen, a way round the far side
    of an obstacle that no hit has reached yet lies off the map: the search finds none,
    and the loop drives toward the reachable cell nearest the goal instead (rooms 26
    and 99 on depth eyes: 3.8 and 5.4 ft into a dead end)."""
    around = [(float(est.x), float(est.z)), (float(goal[0]), float(goal[1]))]
    if extent == "walls":
        x0, x1, z0, z1 = bounds
        around += [(float(x0), float(z0)), (float(x1), float(z1))]
    elif extent != "seen":
        raise ValueError(f"unknown map_extent {extent!r}; one of seen, walls")
    return around


def _perception(cfg: DriveConfig, prof: VehicleProfile, factory) -> Perception:
    """The run's map (:class:`planner.evidence.Perception`, built by ``factory``)
    set up as ``cfg`` says."""
    model = factory(cfg.voi, cfg.band, cfg.max_range_ft, cfg.confirm_looks, cfg.free_looks,
                    near_visible_ft(prof, cfg.lowest_obstacle_ft), cfg.blank_ft)
    model.growth = cfg.growth
    model.blank_carve = cfg.blank_carve
    model.carve = cfg.carve
    model.blank_px = cfg.blank_px
    model.blank_limit = cfg.blank_limit
    model.sight_lines = cfg.sight_lines
    model.stand_in = cfg.stand_in
    model.refute_hits = cfg.refute_hits
    model.stereo_margin = cfg.stereo_margin
    model.min_range_ft = cfg.min_range_ft
    if cfg.blank_sides == "two-looks":       # (without blank_px no side is cut off: inert)
        model.two_look_sides = TwoLookSides(*cfg.sides_apart)
    model.occupied = cfg.occupied
    model.place = cfg.hit_at
    model.feature_pose = cfg.feature_pose
    model.floor_eyes = cfg.floor_eyes
    model.proof_heading, model.heading_sigmas = cfg.proof_heading, cfg.drift_sigmas
    model.floor_end_check, model.proof_hits = cfg.floor_end_check, cfg.proof_hits
    model.free_cells = cfg.free_cells
    model.wall_runs, model.tile_edges = cfg.wall_runs, cfg.tile_edges
    model.foot_bearings = BearingsApart(cfg.flat_foot_apart_deg)
    model.wall_hits, model.one_grey_runs = cfg.wall_hits, cfg.one_grey_runs
    model.expire_uncertain = int(cfg.expire_uncertain)
    if cfg.goal_evidence == "look-expire" and not cfg.expire_uncertain and cfg.occupied == "model":
        model.expire_uncertain = GOAL_EXPIRE_LOOKS
        model.expire_within = (tuple(map(float, cfg.goal)), prof.planning_radius_ft)
    model.draw_core = cfg.uncertain == "core"
    model.lowest_ft = cfg.lowest_obstacle_ft
    if cfg.head == "assist" and cfg.assist_pivot_ft is not None:   # a pivot's cells proven,
        model.pivot_proof = cfg.assist_pivot_ft                      # not assumed (room 45)
        model.provenance = model.provenance or FreeProvenance()
    if cfg.free_drift != "off":
        model.look_free, model.odometry = [], Odometry()
    return model


def _moves(seg) -> bool:
    """Whether the commands ``seg`` drive anywhere (a Forward among them)."""
    return any(isinstance(c, Forward) for c in seg)


def _take(got, seg, note: str, fetching: bool):
    """An alternative's (commands, how) in place of ``seg`` where it gave one, its
    note added; the commands then fetch a look.  Returns (seg, note, fetching)."""
    if got is None:
        return seg, note, fetching
    return got[0], note + got[1], True


@dataclass
class Decision:
    """What :meth:`Drive.plan` decided: the path planned (empty: none), the
    commands to execute, the note printed, the way left along the path (ft; None
    without a path), whether the commands fetch a look (a pivot or the head's aim
    that is itself the look: no sweep instead), and the clearance map it used."""
    path: list
    commands: list
    note: str
    left_ft: float | None
    fetching: bool
    safe: np.ndarray
    fmap: FloorMap            # the map it planned on (map_extent="fallback": maybe wider)


class Drive:
    """One drive's state from look to look: the vehicle, the camera estimate
    (the walk under ``pose="fused"``), the map (:class:`Perception`), the path
    kept, what was already looked at, and the counters toward giving up.  Its
    methods are the steps of the cycle in the module's docstring, in order:
    :meth:`look` (and the scan), :meth:`estimate`, :meth:`update_map` (model
    update, octree, floor map), :meth:`plan` (path, commands, the move or the
    look instead), :meth:`act`; :meth:`cycle` runs them once."""

    def __init__(self, room, start: State, cfg: DriveConfig, noise, keep_maps: bool,
                 perception_factory):
        self.room, self.start, self.cfg, self.keep_maps = room, start, cfg, keep_maps
        self.head = cfg.head == "pan-tilt"
        self.assist = cfg.head == "assist"
        prof = cfg.profile
        if self.head and not prof.head:
            prof = dataclasses.replace(prof, head=True)
        if cfg.backing == "trail" and not prof.reverse:
            prof = dataclasses.replace(prof, reverse=True)     # (BACK only to retrace)
        self.prof = prof
        self.veh = Vehicle(room.obstacles, room.bounds, start, prof, noise)
        self.walker = None
        self.walls = cfg.pose == "walls"      # the estimate fixed against the plan's walls
        self.wall_fixes = 0
        self.looks_unfixed = 0                # looks in a row without a wall fix (wall_fix_widen)
        self.far_before = None                # wall_fix_far: (turn deg, x, z) of the far turn
                                              # not yet taken, and where the look stood
        self.drift_eroded = 0                 # free_drift "erode", "moves": what the last map gave up
        if cfg.pose == "fused":
            from model.mapping import WalkConfig, Walker
            self.walker = Walker(room, WalkConfig(methods=(), driver=cfg.pose_method,
                                                  lines=tuple(cfg.lines), match=cfg.match,
                                                  camera_pitch_deg=prof.camera_pitch_deg))
        self.est_track = [self.veh.dead]
        self.look_est = self.look_dead = None   # the estimate, the dead-reckoned pose at the last look
        self.model = _perception(cfg, prof, perception_factory)
        self.fixed_near, self.fixed_blank = self.model.near_ft, self.model.blank_ft
        # the dead-reckoned pose's (x, z, heading rad) covariance, by the odometry's noise model
        self.dead_cov = np.zeros((3, 3))
        self.odo = (getattr(noise, "distance_fraction", 0.0), getattr(noise, "turn_deg", 0.0)) \
            if noise is not None else (0.0, 0.0)
        self.near_ft = near_visible_ft(prof, cfg.lowest_obstacle_ft)
        self.pivot_sweep = {                  # (None: the disc, motion._pivot_ok)
            "swept": PivotSweep(prof.footprint, prof.margin_ft),
            "small-swept": PivotSweep(prof.footprint, prof.margin_ft, SMALL_TURN_DEG),
            "swept-ring": PivotSweep(prof.footprint, prof.margin_ft, ring="known"),
            "swept-ring-inner": PivotSweep(prof.footprint, prof.margin_ft, ring="known"),
        }.get(cfg.pivot)                      # (the path's pivots as under "swept-ring")
        # a turn made only to look (look_round's): under "swept-ring-inner" the
        # ring's inner part seen free as well (motion._look_turn_ok)
        self.look_sweep = self.pivot_sweep if cfg.pivot != "swept-ring-inner" else \
            inner_ring_sweep(prof)
        self.pivot_r = pivot_radius_ft(prof, cfg.pivot == "margin")
        self.tried: dict = {}                 # blocker cell -> places it was looked at from
        self.ahead_cells: set = set()         # cells the look-ahead has turned to (each once)
        self.aimed: dict = {}                 # head: cell -> places the head looked at it from
        self.goal = (float(cfg.goal[0]), float(cfg.goal[1]))
        self.opt, self.opt_grid = true_optimum(room, (start.x, start.z), self.goal, prof,
                                               cfg.voi.resolution)
        self.cycles: list[Cycle] = []
        self.stuck = 0
        self.best_left, self.most_free = math.inf, 0   # the shortest way left so far, the most free cells
        self.last_reason = ""                 # the planner's NoPath of the last decision ("" if none)
        self._last_plan = None                # ((map, estimate, previous path), path or NoPath)
        self.sweep = 0                        # looks turned in place since the vehicle last moved
        # backing="map": BACK over space seen free; "trail": only the retrace (look_round)
        self.backs_on_map = backs_over_map(prof, cfg)
        self.trail: list = []                 # the motions executed, undone ones cancelled
        self.retraces = 0                     # backing="trail": retraces taken
        self.prev_path = None                 # the path kept (planning.plan's keep_ft)
        self.known = None                     # the last floor map, its track free

    def current(self) -> State:
        """The camera estimate now: the last look's moved by the odometry since
        (under ``pose="dead_reckoning"`` the dead-reckoned pose itself)."""
        if (self.walker is None and not self.walls) or self.look_est is None:
            return self.veh.dead
        from model.mapping import compose_step
        return State(*compose_step((self.look_est.x, self.look_est.z, self.look_est.heading_deg),
                                   self.look_dead, self.veh.dead)[0])

    def goal_left_ft(self) -> float:
        """The estimate's distance from the goal now."""
        est = self.current()
        return math.hypot(est.x - self.goal[0], est.z - self.goal[1])

    def at_goal(self) -> bool:
        """The loop's success test: the estimate within the goal's tolerance."""
        return self.goal_left_ft() <= self.cfg.tolerance_ft

    def finished(self, left: float, disc_left_ft: float | None) -> bool:
        """Whether the run ends at the goal before the next cycle, the estimate
        ``left`` ft from it (:meth:`goal_left_ft`).  Under ``finish="edge"`` as
        soon as it is within the tolerance (:meth:`at_goal`); under ``"inner"``
        once it is within :data:`FINISH_INNER_FT`, or within the tolerance when
        the last cycle began in the disc ``disc_left_ft`` from the goal and brought
        it less than :data:`FINISH_NEARER_FT` nearer.  Why: the estimate is a tenth
        of a foot or more off, and a run ended at the disc's edge by the estimate
        may lie outside it by the truth."""
        if self.cfg.finish == "edge":
            return left <= self.cfg.tolerance_ft
        if left <= FINISH_INNER_FT:
            return True
        return left <= self.cfg.tolerance_ft and disc_left_ft is not None \
            and disc_left_ft - left < FINISH_NEARER_FT

    # -- the cycle's steps ------------------------------------------------------------

    def look(self, look_no: int, extra_looks: int, pan: float, tilt: float):
        """Look and scan: both cameras rendered at the TRUE pose (the head at ``pan``,
        ``tilt``), the rig's scan of the pair, its located points (their ranges the
        true ones under ``eyes="truth"``).  Returns (look, scan, points, the time the
        rendering ended, this thread's CPU time then, the scan's seconds)."""
        from world.render import render_look
        cfg = self.cfg
        look = render_look(self.room, camera_pose(self.veh.true, pan, tilt, self.prof),
                           seed=cfg.look_seed + look_no + 100000 * extra_looks,
                           supersample=cfg.supersample)
        t1, c1 = time.perf_counter(), time.thread_time()
        scan = scan_look(look.left_bi, look.right_bi, cfg.lines, cfg.match)
        scan_s = time.perf_counter() - t1
        if cfg.disparity == "subpixel":
            from matching.subpixel import subpixel_points
            points = subpixel_points(scan.results, look.left_vd, look.right_vd)
        elif cfg.eyes == "truth":
            points = true_range_points(scan.points, look)
        else:
            points = scan.points
        if cfg.min_confidence:
            from matching.mode import vouched_points
            points = vouched_points(scan.results, points, cfg.min_confidence)
        return look, scan, points, t1, c1, scan_s

    def estimate(self, look, scan, points=(), pan: float = 0.0, tilt: float = 0.0) -> State:
        """The camera estimate at the look: the dead-reckoned pose, or under
        ``pose="fused"`` the walk's step (model update and fix fused with it), or
        under ``pose="walls"`` the estimate moved by the odometry since the last
        look, fixed against the floor plan's walls by this look's ``points`` (the
        depth eyes: the look's true ranges) with the head's exact ``pan``, ``tilt``
        (:func:`planner.localize.fix_against_walls`); the dead-reckoned covariance
        becomes the fix's, to grow with the odometry again."""
        if self.walls:
            est = self._wall_fix(look, points, pan, tilt)
        elif self.walker is None:
            est = self.veh.dead
        else:
            rec = self.walker.step(look, look.pose, self.veh.dead, self.look_dead, scan=scan)
            est = State(*rec.estimates["fused"])
        self.look_est, self.look_dead = est, self.veh.dead
        return est

    def _wall_fix(self, look, points, pan: float, tilt: float) -> State:
        """:meth:`estimate` under ``pose="walls"``."""
        from .localize import depth_wall_points, far_turn, fix_in_windows, rig_wall_points
        pitch = self.prof.camera_pitch_deg + tilt
        prior = self.current()
        if self.cfg.eyes == "depth":
            q, cq = depth_wall_points(look.range_left, pitch, FLOOR_Y)
        else:
            q, cq = rig_wall_points(points, self.cfg.min_range_ft)
            if self.cfg.wall_points == "floor-ends":
                q, cq = self._with_floor_ends(q, cq, look.left_bi, pitch)
        widened = self.cfg.wall_fix_sigmas + self.cfg.wall_fix_widen * self.looks_unfixed
        if self.cfg.wall_fix_most is not None:
            widened = min(widened, max(self.cfg.wall_fix_most, self.cfg.wall_fix_sigmas))
        windows = [widened]
        if self.cfg.wall_fix_first == "base" and windows[0] > self.cfg.wall_fix_sigmas:
            windows.insert(0, self.cfg.wall_fix_sigmas)
        fix = fix_in_windows(q, cq, (prior.x, prior.z, prior.heading_deg), self.dead_cov,
                             self.room.bounds, pitch, pan, windows)
        far = far_turn(fix, prior.heading_deg, self.dead_cov, self.cfg.wall_fix_far,
                       self.cfg.wall_fix_far_sigmas)
        if far is not None:
            # a far turn on few points: taken when a look from elsewhere shows it too
            # (from about the same place the same false consensus shows again: room 879)
            before = self.far_before
            moved = before is not None and \
                math.hypot(prior.x - before[1], prior.z - before[2]) >= FAR_WITNESS_FT
            same = before is not None and \
                abs(far - before[0]) <= 2.0 * math.degrees(math.sqrt(self.dead_cov[2][2]))
            if not (moved and same):
                if before is None or moved:
                    self.far_before = (far, prior.x, prior.z)      # a new turn to witness
                self.looks_unfixed += 1
                return prior
        self.far_before = None
        if not fix.fixed:
            self.looks_unfixed += 1
            return prior
        self.looks_unfixed = 0
        self.wall_fixes += 1
        self.dead_cov = fix.cov
        return State(fix.x, fix.z, fix.heading_deg)

    def _with_floor_ends(self, q, cq, picture, pitch: float):
        """``q``, ``cq`` and the floor in view's ends (:func:`planner.localize.floor_end_points`)
        in the floor's learned greys, or, before they are learned, the bottom rows' (the
        stand-in of ``cfg.stand_in``): the fix's gate drops a box's foot."""
        from .localize import floor_end_points
        fq, fc = floor_end_points(picture, self.model.bounding_greys(picture), pitch, FLOOR_Y)
        return np.vstack([q, fq]), np.concatenate([cq, fc])

    def update_map(self, look, points, est: State, pan: float, tilt: float,
                   headed: bool) -> FloorMap:
        """The look into the octree, placed by ``est`` (with the head's angles where
        ``headed``), and the floor map drawn from it with the track and the plan's
        walls.  Returns the floor map (kept as the next look's known map)."""
        from world.pose import Pose
        cfg, prof, model = self.cfg, self.prof, self.model
        if self.known is None:            # before the first look: the clear spot set down in
            self.known = empty_map((est.x, est.x, est.z, est.z), cfg.voi.resolution,
                                   cfg.start_clear_ft + 1.0)
            mark_track_free(self.known, self.est_track, prof.footprint, cfg.start_clear_ft)
        est_cam = est
        if headed:
            # the head's look placed by the estimate with the head's exact angles;
            # what it can prove depends on its tilt (nearer, farther floor), and a
            # look the head turned assumes nothing of its blank columns
            est_cam = State(est.x, est.z, wrap(est.heading_deg + pan))
            model.near_ft = near_visible_ft(prof, cfg.lowest_obstacle_ft, tilt)
            model.blank_ft = head_blank_ft(cfg.blank_ft, prof, pan, tilt,
                                           bounded=cfg.floor_eyes in BOUNDING)
        elif self.assist:                 # the fixed rig's own look, as without a head
            model.near_ft, model.blank_ft = self.fixed_near, self.fixed_blank
        if cfg.known_walls:
            # the plan is the room's truth, the look is placed by the estimate:
            # what the look only assumes stops short of the plan by the pose's 2 sigma
            gx, gz = wall_growth(self.dead_cov)
            bx0, bx1, bz0, bz1 = self.room.bounds
            model.assume_within = (bx0 + gx, bx1 - gx, bz0 + gz, bz1 - gz)
            model.plan_walls = self.room.bounds
            # the floor in view ends at the walls, the estimate's 2 sigma and a cell beyond
            c = cfg.voi.resolution
            model.floor_within = (bx0 - gx - c, bx1 + gx + c, bz0 - gz - c, bz1 + gz + c)
        model.update(points, est_cam, Pose, prof.camera_pitch_deg + tilt, self.known,
                     self.dead_cov, look.left_bi if cfg.floor_eyes != "off" else None,
                     look.range_left if cfg.eyes == "depth" else None)
        fm = self.drawn_map(est, "walls" if cfg.map_extent == "walls" else "seen")
        self.known = fm
        return fm

    def drawn_map(self, est: State, extent: str) -> FloorMap:
        """The model's floor map over :func:`map_around`'s ``extent``, with the vehicle's
        track free and the plan's walls."""
        cfg, prof = self.cfg, self.prof
        fm = self.model.floor_map(map_around(est, self.goal, self.room.bounds, extent))
        if cfg.free_drift != "off":
            self.drift_eroded = erode_by_drift(
                fm, cfg.voi.resolution, self.model.look_free, self.model.odometry,
                (est.x, est.z), self.odo[1], cfg.drift_sigmas, cfg.free_drift == "moves")
        mark_track_free(fm, self.est_track, prof.footprint, cfg.start_clear_ft,
                        prof.margin_ft if cfg.track_free == "swept" else None)
        if cfg.free_gaps == "fill":       # (after the erosion: what it gave up stays unknown)
            fm.cells = fill_one_cell_gaps(fm.cells)
        if cfg.known_walls:
            mark_walls(fm, self.plan_walls())
        if cfg.move_ring in ("known", "start"):
            fm.move_ring = clear_unseen(fm, prof.planning_radius_ft)
            fm.move_ring_start = cfg.move_ring == "start"
        return fm

    def plan_walls(self):
        """The floor plan's walls (x0, x1, z0, z1) as the map draws them
        (``plan_walls="grown"``: two standard deviations of the estimate's
        position nearer), or None without ``known_walls``."""
        if not self.cfg.known_walls:
            return None
        bx0, bx1, bz0, bz1 = self.room.bounds
        gx, gz = wall_growth(self.dead_cov) if self.cfg.plan_walls == "grown" else (0.0, 0.0)
        return (bx0 + gx, bx1 - gx, bz0 + gz, bz1 - gz)

    def map_to_plan_on(self, fm: FloorMap, est: State) -> FloorMap:
        """The map the cycle plans on: ``fm``; under ``map_extent="fallback"``, where no
        path to the goal lies on ``fm`` (the planner would head for the reachable cell
        nearest the goal) and one lies on the map drawn out to the room's walls, that
        map.  (Where the goal itself is refused on both, a goal too near an obstacle on
        the map, ``fm`` stays: with the wider map the nearest reachable cell moved and
        rooms 44 and 93 on depth eyes stopped short.)  Under ``fine_map="fallback"``,
        where neither has a path to the goal, the first of them that has one on half
        cells (:meth:`Perception.halved_map`)."""
        cfg = self.cfg
        if (cfg.map_extent != "fallback" and cfg.fine_map == "off") \
                or self._reaches_goal(fm, est):
            return fm
        maps = [fm]
        if cfg.map_extent == "fallback":
            wide = self.drawn_map(est, "walls")
            if self._reaches_goal(wide, est):
                return wide
            maps.append(wide)
        if cfg.fine_map == "fallback":
            # the blocked cells drawn again on half cells: a way the rounding to
            # whole cells closed (a feature blocks all of the cell it touches)
            for coarse in maps:
                fine = self.model.halved_map(coarse, self.plan_walls())
                if self._reaches_goal(fine, est):
                    return fine
        return fm

    def _reaches_goal(self, fm: FloorMap, est: State) -> bool:
        """Whether the planner finds a path to the goal itself on ``fm``."""
        try:
            note = self._plan_on(fm, est)[2]
        except NoPath:
            return False
        return not note.startswith("goal not reachable")

    def _plan_on(self, fm: FloorMap, est: State):
        """:func:`planner.planning.plan` on ``fm`` from ``est`` (raising its NoPath),
        kept for the same map, estimate and previous path: under
        ``map_extent="fallback"`` the cycle asks first whether the seen map has a
        way, then plans on it, and the search is most of a plan's time."""
        last = self._last_plan
        cfg = self.cfg
        if cfg.passage == "stuck":
            # straight through a narrow way only once the circle has left the vehicle
            # without progress for a while (looking on finds the wide way first)
            cfg = dataclasses.replace(cfg, passage="straight" if self.stuck >= STRAIGHT_AFTER
                                      else "moves")
        if last is None or last[0][0] is not fm or last[0][1] != est \
                or last[0][2] is not self.prev_path or last[0][3] != cfg.passage:
            try:
                got = plan_path(fm, est, self.goal, cfg, self.prev_path)
            except NoPath as exc:
                got = exc
            self._last_plan = last = ((fm, est, self.prev_path, cfg.passage), got)
        if isinstance(last[1], NoPath):
            raise last[1]
        return last[1]

    def plan(self, fm: FloorMap, est: State, pan: float) -> Decision:
        """Plan on the floor map: the path and its motion commands cut to what may be
        driven (:func:`planner.motion.safe_prefix`), else the look-ahead's pivot, the
        approach into the goal's disc, the head's look, the evidence's look, a turn to
        face the path; with no motion at all, :meth:`look_round`."""
        cfg, prof, head, goal = self.cfg, self.prof, self.head, self.goal
        fm = self.map_to_plan_on(fm, est)
        pivot_r, pivot_sweep = self.pivot_r, self.pivot_sweep
        safe = clearance_map(fm, prof.planning_radius_ft,
                             "blocked" if cfg.safety == "strict" else "free",
                             uncertain="blocked", at=cfg.clearance_at)
        if cfg.passage != "circle":
            safe.narrow = narrow_cells(safe, prof)
        seen = fm.cells != UNKNOWN
        seen_eyes = None
        if cfg.trust_view:
            seen_eyes = looked_free(fm, est, cfg.max_range_ft).cells != UNKNOWN
        fetching = False
        try:
            pts, cmds, note = self._plan_on(fm, est)
            if head:
                cmds = shortcut_first_leg(cmds, est)

            def prefix(c):
                return safe_prefix(c, est, safe, seen, prof.step_ft, seen_eyes,
                                   *prof.grown_half_ft, pivot_r, pivot_sweep,
                                   pan if head else None, min_pivot_deg=cfg.min_pivot_deg,
                                   margin_ft=prof.margin_ft)
            seg = path_seg = prefix(cmds)
            left = path_length(pts)

            def steer(seg, note):
                # the path's first leg, cut short (path_seg), on a heading a little off
                got = steered_prefix(cmds, path_seg, prefix, prof.step_ft)
                return (seg, note) if got is None else \
                    (got[0], note + f" (steered {got[1]:+d} deg)")
            if cfg.steer == "small":
                seg, note = steer(seg, note)
            if cfg.look_ahead and not head and _moves(seg):
                # its pivot is the look: no sweep instead
                seg, note, fetching = _take(
                    looked_ahead(seg, est, fm, pts, self.near_ft, safe, seen, seen_eyes, prof,
                                 pivot_sweep, self.ahead_cells, pivot_r, cfg.min_pivot_deg),
                    seg, note, fetching)
            if cfg.approach == "disc" and not _moves(seg) \
                    and math.hypot(est.x - goal[0], est.z - goal[1]) <= \
                    cfg.tolerance_ft + prof.step_ft:
                # the path's last foot refused: the safe move ending nearest the goal in its disc
                seg, note, fetching = _take(
                    disc_approach(est, goal, max(cfg.tolerance_ft - GOAL_SLACK_FT, 0.0),
                                  safe, seen, prof, pivot_r, pivot_sweep), seg, note, fetching)
            if head and not fetching and not _moves(seg):
                seg, note, fetching = _take(
                    head_look(fm, safe, est, pts, goal, seg, prof, cfg, pan, pivot_r, self.aimed),
                    seg, note, fetching)
            if not fetching and not _moves(seg) and cfg.look_around == "evidence":
                seg, note, fetching = _take(
                    fetch_evidence(fm, safe, seen, est, pts, self.near_ft, prof, cfg, self.tried),
                    seg, note, fetching)
            if not fetching and not _moves(seg) and note.startswith("goal not reachable"):
                seg, note, fetching = _take(self.look_at_goal(fm, safe, seen, est), seg,
                                            note, fetching)
            if not fetching and not _moves(seg):
                # nothing known free ahead: face the path and look again
                first = pts[1] if len(pts) > 1 else goal
                t = wrap(heading_to((est.x, est.z), first) - est.heading_deg)
                if head and path_heading(est, pts) is not None:
                    # (with the head: the first path point 0.3 ft away or more; the
                    # fixed rig's loop keeps its own)
                    t = wrap(path_heading(est, pts) - est.heading_deg)
                seg = [Turn(round(t, 2))] if abs(t) > 1.0 and \
                    pivot_allowed(fm, est, t, prof, pivot_sweep, pivot_r) else []
            if cfg.steer == "idle" and not fetching and not _moves(seg) and \
                    not any(isinstance(c, Turn) and abs(c.angle_deg) >= 1.0 for c in seg):
                # nothing else to do here but look round: the leg steered, if it may be
                seg, note = steer(seg, note)
            self.last_reason = ""
            self.prev_path = pts
        except NoPath as exc:
            pts, left, note, seg = [], None, str(exc), []
            self.last_reason = str(exc)
            seg, note, fetching = _take(self.look_at_goal(fm, safe, seen, est), seg, note,
                                        fetching)
        if not fetching and (not seg or all(isinstance(c, Turn) and abs(c.angle_deg) < 1.0
                                            for c in seg)):
            seg, note = self.look_round(fm, est, safe, seen, note, pts)
        if fm.cell < cfg.voi.resolution - 1e-9:
            note += " (planned on half cells)"
        return Decision(pts, seg, note, left, fetching, safe, fm)

    def look_at_goal(self, fm: FloorMap, safe, seen, est: State):
        """Under ``goal_evidence`` "look" or "look-expire", where no path
        reaches the goal: a look at the uncertain cell nearest the goal within
        the planning radius (:func:`planner.motion.goal_blocker`), fetched as
        the path's evidence is (:func:`planner.motion.look_at`); (commands,
        note) or None."""
        if self.cfg.goal_evidence == "off":
            return None
        u = goal_blocker(fm, self.goal, self.prof.planning_radius_ft)
        if u is None:
            return None
        return look_at(u, fm, safe, seen, est, self.near_ft, self.prof, self.cfg, self.tried)

    def look_round(self, fm: FloorMap, est: State, safe, seen, note: str, pts=()):
        """No motion: turn to look, toward the goal first, then sweep (+35, -70 deg);
        with the head, the head looks round first; else back to where it can turn
        (``reverse``), or forward to where it can (``turn_room="forward"``: then
        facing the path ``pts``, or turning as it would have here), or back
        along its own way (``backing="trail"``).
        Returns (commands, note)."""
        prof = self.prof
        self.sweep += 1
        sweep = self.sweep
        t = wrap(heading_to((est.x, est.z), self.goal) - est.heading_deg)
        if abs(t) < 10 or sweep > 1:
            t = 35.0 if sweep % 2 else -70.0
        back = back_prefix(est, 1.0, safe, seen, prof) if self.backs_on_map else []
        if self.head and sweep <= len(HEAD_SWEEP_DEG) + 1:
            # the head looks round first: toward the goal, then to either side
            p = t if sweep == 1 else HEAD_SWEEP_DEG[sweep - 2]
            lo, hi = prof.pan_limits_deg
            return [Pan(round(min(max(p, lo), hi), 2)), Tilt(0.0)], \
                note + " (looking round with the head)"
        if pivot_allowed(fm, est, t, prof, self.look_sweep, self.pivot_r):
            return [Turn(round(t, 2))], note + " (turning to look)"
        if back:
            return back, note + " (cannot turn here: backing to where it can)"
        if self.cfg.turn_room == "forward":
            aims = (lambda end: path_heading(end, pts),
                    lambda end: wrap(end.heading_deg + t))
            on = forward_to_turn(fm, est, aims, safe, seen, prof, self.pivot_sweep,
                                 self.pivot_r)
            if on:
                return on, note + " (cannot turn here: forward to where it can)"
        if self.cfg.backing == "trail" and self.retraces < RETRACES and \
                math.hypot(est.x - self.goal[0], est.z - self.goal[1]) > self.cfg.tolerance_ft:
            # what it lacks may lie too near to show (near_visible_ft): back off
            # along ground its wheels have swept, and look again (not from inside the
            # goal's disc, where standing still ends the run at the goal: room 661)
            back = retrace(self.trail, RETRACE_FT)
            if back:
                self.retraces += 1
                return back, note + " (cannot turn here: back along its own way)"
        return [], note + " (cannot turn: space within its radius not seen free)"

    def _decision_state(self):
        """What a decision changes besides the map and the head's aims (assist
        restores it when the head's look is added and the cycle decided again)."""
        return ({k: list(v) for k, v in self.tried.items()}, set(self.ahead_cells), self.sweep,
                self.prev_path, self.last_reason, self.retraces)

    def _restore_decision(self, saved) -> None:
        self.tried.clear()
        self.tried.update(saved[0])
        self.ahead_cells.clear()
        self.ahead_cells.update(saved[1])
        self.sweep, self.prev_path, self.last_reason, self.retraces = saved[2:]

    def act(self, seg, est: State) -> tuple[bool, float]:
        """Execute the commands ``seg``: the odometry's covariance and the estimate's
        track follow the dead-reckoned poses.  Returns (no collision, true ft moved)."""
        veh = self.veh
        before = (veh.true.x, veh.true.z)
        n_before = len(veh.dead_track)
        ok = veh.execute(seg)
        for c in seg:
            push_trail(self.trail, c)
        for a, b in zip(veh.dead_track[n_before - 1:], veh.dead_track[n_before:]):
            self.dead_cov = odometry_covariance(self.dead_cov, a, b, *self.odo)
            if self.model.odometry is not None and a != b:     # (a command that moved)
                self.model.odometry.report(math.hypot(b.x - a.x, b.z - a.z), self.odo[0])
        # (before the first look, Drive.step_back: the estimate is the dead reckoning)
        corrected = (self.walker is not None or self.walls) and self.look_est is not None
        if corrected:
            from model.mapping import compose_step
        for d in veh.dead_track[n_before:]:
            self.est_track.append(d if not corrected else State(*compose_step(
                (est.x, est.z, est.heading_deg), self.look_dead, d)[0]))
        moved = math.hypot(veh.true.x - before[0], veh.true.z - before[1])
        if moved > 0.05:
            self.sweep = 0
        return ok, moved

    def step_back(self) -> tuple[str, bool]:
        """``learn_floor="step-back"``, before the first look: back
        ``learn_back_ft`` inside the clear spot the vehicle was set down in
        (``start_clear_ft`` from anything: the step and a turn there stay in
        it, :func:`_check_config`).  From there the picture's bottom rows show
        floor whose whole trace lies in that spot, so the floor's grey is
        learned at the first look (:func:`planner.appearance.training_mask`:
        after Ulrich and Nourbakhsh's reference area in front of the robot).
        A vehicle that does not reverse (or reverses only along its own way,
        ``backing="trail"``) turns about, drives forward and turns back.
        Returns (the commands, no collision)."""
        d = self.cfg.learn_back_ft
        seg = [Back(d)] if self.backs_on_map else [Turn(180.0), Forward(d), Turn(-180.0)]
        ok, _ = self.act(seg, self.veh.dead)
        return format_commands(seg), ok

    def count_progress(self, moved: float, left, fm: FloorMap) -> None:
        """The count toward ``max_stuck``: reset by progress (``cfg.progress``)."""
        if self.cfg.progress == "moved":
            progressed = moved > 0.05
        else:
            # progress is a shorter way left than ever before, or new free
            # space seen (half a square foot): moving to and fro is not
            progressed = False
            if left is not None and left < self.best_left - 0.25:
                self.best_left, progressed = left, True
            # (counted in the look's own cells, a quarter foot: a halved map's
            # four cells are one)
            n_free = int((fm.cells == FREE).sum() * (fm.cell / self.cfg.voi.resolution) ** 2
                         + 1e-6)
            if n_free >= self.most_free + 8:
                self.most_free, progressed = n_free, True
        self.stuck = 0 if progressed else self.stuck + 1

    def cycle(self, look_no: int) -> tuple[Cycle, bool]:
        """One cycle: look, estimate, update the map, plan, act (under
        ``head="assist"``, where the plan would stop or pivot only to look, the
        head's look is added first and the cycle decided again).  Returns (the
        cycle's record, no collision)."""
        assist, veh = self.assist, self.veh
        extra_looks = 0                   # assist: the head's looks added this cycle
        if assist:
            saved = self._decision_state()
            pan = tilt = 0.0
        # summed over the cycle's looks (under assist the head's look decides it again)
        render_s = work_s = work_cpu_s = scan_s = 0.0
        while True:
            t0 = time.perf_counter()
            tp = veh.true
            if not assist:
                pan, tilt = veh.pan_deg, veh.tilt_deg
            look, scan, points, t1, c1, look_scan_s = self.look(look_no, extra_looks, pan,
                                                                 tilt)
            render_s += t1 - t0
            scan_s += look_scan_s
            est = self.estimate(look, scan, points, pan, tilt)
            fm = self.update_map(look, points, est, pan, tilt,
                                 self.head or bool(assist and extra_looks))
            d = self.plan(fm, est, pan)
            fm = d.fmap
            if assist and extra_looks == 0 and (not _moves(d.commands) or d.fetching):
                # the fixed loop is about to stop or pivot only to look: the head
                # looks first, the cycle is decided again with that look added
                got = head_look(fm, d.safe, est, d.path, self.goal, d.commands, self.prof,
                                self.cfg, 0.0, self.pivot_r, self.aimed) if d.path else None
                if got is not None:
                    aim = [c for c in got[0] if isinstance(c, (Pan, Tilt))]
                    pan = next((c.angle_deg for c in aim if isinstance(c, Pan)), 0.0)
                    tilt = next((c.angle_deg for c in aim if isinstance(c, Tilt)), 0.0)
                    self._restore_decision(saved)
                    extra_looks, assist_note = 1, got[1].replace(" (head at", " (assist: head at")
                    work_s += time.perf_counter() - t1
                    work_cpu_s += time.thread_time() - c1
                    continue
            break
        seg, note = d.commands, d.note
        if extra_looks:
            note += assist_note
        edge = self.model.raised_now()
        if edge is not None:
            note += (f" (the floor's ends moved with the camera: an edge above the floor from "
                     f"({edge[0][0]:.1f}, {edge[0][1]:.1f}) to ({edge[-1][0]:.1f}, "
                     f"{edge[-1][1]:.1f}))")
        if self.head:
            seg = head_commands(seg, est, fm, d.path, self.prof, self.cfg, veh.pan_deg,
                                veh.tilt_deg, self.aimed)
        work_s += time.perf_counter() - t1
        work_cpu_s += time.thread_time() - c1
        ok, moved = self.act(seg, est)
        self.count_progress(moved, d.left_ft, fm)
        cyc = Cycle(look_no, tp, est, len(self.model.points),
                    int(self.model.tree.getNumLeafNodes()), d.left_ft, format_commands(seg), note,
                    render_s, work_s, list(d.path), fm if self.keep_maps else None, scan_s,
                    len(veh.true_track), extra_looks, work_cpu_s)
        return cyc, ok

    def result(self, reached: bool, reason: str, seconds: float) -> DriveResult:
        cfg, veh, model, cycles = self.cfg, self.veh, self.model, self.cycles
        final_err = math.hypot(veh.true.x - self.goal[0], veh.true.z - self.goal[1])
        return DriveResult(reached, reason, len(cycles) + sum(c.head_looks for c in cycles),
                           veh.travelled_ft, self.opt, self.opt_grid,
                           veh.collisions, seconds, cycles, list(veh.true_track),
                           list(veh.dead_track), memory_bytes(model.tree), final_err, self.goal,
                           self.start,
                           cfg.unknown, cfg.search, self.est_track, cfg.pose, cfg.match,
                           model.features if cfg.occupied == "model" else None,
                           floor_stats(model) if cfg.floor_eyes != "off" else {},
                           model.expired_total if model.expire_uncertain else None,
                           self.wall_fixes if self.walls else None,
                           self.drift_eroded if cfg.free_drift != "off" else None,
                           self.retraces if cfg.backing == "trail" else None)


def steps_back(cfg: DriveConfig) -> bool:
    """Whether the drive steps back before its first look (``learn_floor="step-back"``):
    only where a look reads the floor's grey (:func:`planner.appearance.reads_floor`)."""
    return cfg.learn_floor == "step-back" and reads_floor(cfg.floor_eyes, cfg.eyes == "depth")


def step_back_reach_ft(cfg: DriveConfig) -> float:
    """How far from the start the step back reaches: ``learn_back_ft`` and the
    turn's circle there (the footprint's half diagonal)."""
    return cfg.learn_back_ft + cfg.profile.radius_ft


def run(room, start: State, cfg: DriveConfig, noise=None, on_cycle=None, keep_maps: bool = True,
        perception_factory=Perception) -> DriveResult:
    """Drive from ``start`` to ``cfg.goal`` in ``room`` (a world Room): cycle
    (:meth:`Drive.cycle`) until the estimate is within the goal's tolerance
    (:meth:`Drive.finished`: under ``finish="inner"`` on into the disc), the
    vehicle hits something, ``max_stuck`` looks pass without progress or
    ``max_looks`` are used up.

    ``perception_factory`` builds the run's :class:`Perception` from its
    positional arguments: a seam for diagnostics that must see inside the
    model without changing the drive (``bench/drive.py --losses`` passes one
    that keeps a FreeProvenance, which carving freed each cell)."""
    _check_config(cfg)
    drive = Drive(room, start, cfg, noise, keep_maps, perception_factory)
    t_start = time.perf_counter()
    reached, reason = False, ""
    # finish="inner": the estimate's distance from the goal when the last cycle began
    # inside the goal's disc (None: it began outside)
    disc_left_ft = None
    try:
        if steps_back(cfg) and not drive.step_back()[1]:
            return drive.result(False, HIT, time.perf_counter() - t_start)
        for look_no in range(1, cfg.max_looks + 1):
            left = drive.goal_left_ft()
            if drive.finished(left, disc_left_ft):
                reached, reason = True, "goal reached"
                break
            disc_left_ft = left if left <= cfg.tolerance_ft else None
            cyc, ok = drive.cycle(look_no)
            drive.cycles.append(cyc)
            if on_cycle:
                on_cycle(cyc)
            if not ok:
                reason = HIT
                break
            if drive.stuck >= cfg.max_stuck:
                if cfg.finish == "inner" and drive.at_goal():
                    reached, reason = True, "goal reached"
                    break
                reason = f"stopped after {cfg.max_stuck} looks without progress: " + \
                         (drive.last_reason or cyc.note)
                break
        else:
            if drive.at_goal():
                reached, reason = True, "goal reached"
            else:
                reason = f"stopped: {cfg.max_looks} looks used up"
    except KeyboardInterrupt:
        looks = len(drive.cycles) + sum(c.head_looks for c in drive.cycles)
        reason = f"stopped by Ctrl-C after {looks} looks"
    return drive.result(reached, reason, time.perf_counter() - t_start)
