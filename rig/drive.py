"""``rig drive`` — the 1985 design drives a robot through a simulated room.

The closed loop of :mod:`planner.loop` (look -> scan -> model update ->
camera estimate -> octree -> plan -> execute the next command segment ->
repeat) with a per-cycle line, the ending sentence ("goal reached in N looks,
D ft travelled, T s" or the reason it stopped), pictures (the last map and an
animated GIF of the run, written with Pillow) and ``--json FILE``.  Ctrl-C
stops cleanly after the cycle under way and still writes what it has.

The perception step: the look rendered at the TRUE pose, scanned by the rig
(``--match``: the 1985 matcher, or the improved one of package ``matching``),
placed in the room with the camera estimate of ``--pose``: the symbolic model's
fused pose (the walk's per-look step, :class:`model.mapping.Walker`) or the
dead-reckoned pose.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import replace
from pathlib import Path

from diskfmt.rdos import write_atomic

DEFAULT_LAB_GOAL = (4.5, 11.0)


def _numbers(text: str, what: str, counts) -> list[float]:
    """``X,Z`` style option values; one clear error otherwise."""
    import math
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        vals = []
    if len(vals) not in counts or not all(math.isfinite(v) for v in vals):
        need = " or ".join(str(c) for c in counts)
        raise SystemExit(f"rig drive: {what} {text!r} must be {need} numbers separated by commas")
    return vals


def write_gif(path: Path, frames, ms_per_frame: int = 500) -> None:
    """An animated GIF (Pillow), written to a temporary name and renamed."""
    import io

    import numpy as np
    from PIL import Image
    imgs = [Image.fromarray(np.ascontiguousarray(f[:, :, ::-1])) for f in frames]
    buf = io.BytesIO()
    imgs[0].save(buf, format="GIF", save_all=True, append_images=imgs[1:],
                 duration=ms_per_frame, loop=0)
    write_atomic(path, buf.getvalue())


def frames_of(result, room):
    from planner.pictures import drive_map
    frames = []
    for c in result.cycles:
        title = f"look {c.look}: {c.command or '-'}"
        frames.append(drive_map(c.fmap, room.bounds, room.obstacles, c.path,
                                result.true_track[:c.track_len], result.estimate_track[:c.track_len],
                                result.goal, title[:60], heading=True))
    return frames


def cmd_drive(args) -> int:
    from planner.loop import run, step_back_reach_ft, steps_back
    from rig.pictures import save_png
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    from world.room import bundled_lab, generate_room

    if args.room is None:
        room = bundled_lab()
    else:
        try:
            room = generate_room(args.room)
        except ValueError as exc:
            raise SystemExit(f"rig drive: --room: {exc}")
    s = room.start
    start = State(s.x, s.z, s.heading_deg)
    if args.start:
        v = _numbers(args.start, "--start", (2, 3))
        start = State(v[0], v[1], v[2] if len(v) == 3 else 0.0)
    if args.goal:
        goal = tuple(_numbers(args.goal, "--goal", (2,)))
    elif args.room is None:
        goal = DEFAULT_LAB_GOAL
    else:
        import numpy as np
        from planner.planning import random_goal
        goal = random_goal(room, start, DEFAULT, np.random.default_rng(args.room))
        if goal is None:
            raise SystemExit(f"rig drive: room {args.room} has no reachable goal from the start; "
                             f"give --goal X,Z")
    r = DEFAULT.planning_radius_ft
    for what, (x, z) in (("start", (start.x, start.z)), ("goal", goal)):
        c = room.clearance(x, z)
        if c < r:
            where = "inside an obstacle or outside the walls" if c < 0 else \
                f"{c:.2f} ft from an obstacle or wall"
            raise SystemExit(f"rig drive: the {what} ({x:g}, {z:g}) ft is {where} in "
                             f"{room.name!r}; the vehicle needs {r:.2f} ft")
    def fail(message):
        raise SystemExit(f"rig drive: {message}")
    cfg = loop_config(args, goal, fail)
    back, clear = step_back_reach_ft(cfg), room.clearance(start.x, start.z)
    if steps_back(cfg) and clear < back:
        fail(f"the start ({start.x:g}, {start.z:g}) ft is {clear:.2f} ft from an obstacle or "
             f"wall; the step back that learns the floor's grey needs {back:.2f} ft all round "
             f"(--learn-floor off: no step back)")
    noise = None if args.no_noise else OdometryNoise(seed=args.seed)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"rig drive: {room.name}, start ({start.x:g}, {start.z:g}) heading "
          f"{start.heading_deg:g} deg, goal ({goal[0]:g}, {goal[1]:g}), unknown space "
          f"{args.unknown}, search {args.search}, eyes {args.eyes}, stereo matcher {args.match}, "
          f"head {args.head}, pose {args.pose}, odometry noise {'off' if noise is None else 'on'}")
    if steps_back(cfg):
        print(f"before the first look: {cfg.learn_back_ft:g} ft back inside the clear spot, "
              "to learn the floor's grey (--learn-floor off: not)")

    def line(c):
        left = "-" if c.path_left_ft is None else f"{c.path_left_ft:5.1f} ft"
        print(f"look {c.look:2d}: est ({c.estimate.x:6.2f}, {c.estimate.z:6.2f}, "
              f"{c.estimate.heading_deg:6.1f}) true ({c.true.x:6.2f}, {c.true.z:6.2f}, "
              f"{c.true.heading_deg:6.1f})  model {c.points:5d} pts {c.leaves:6d} cells  "
              f"path left {left}  cmd {c.command or '-'}"
              + ("" if args.quiet_notes else f"  [{c.note}]"), flush=True)

    res = run(room, start, cfg, noise=noise, on_cycle=line)
    if res.reached:
        print(f"goal reached in {res.looks} looks, {res.travelled_ft:.1f} ft travelled, "
              f"{res.seconds:.1f} s")
    else:
        print(f"goal not reached: {res.reason} ({res.looks} looks, {res.travelled_ft:.1f} ft "
              f"travelled, {res.seconds:.1f} s)")
    opt = "-" if res.optimal_ft is None else f"{res.optimal_ft:.1f} ft"
    first = first_look_note(res.cycles)
    per_look = (f"; {res.work_ms_per_look:.0f} ms per look, the head's looks counted"
                if res.looks > len(res.cycles) else "")
    print(f"true optimum {opt}; collisions {res.collisions}; {res.work_ms_per_cycle:.0f} ms per "
          f"cycle without the look's rendering (the scan {res.scan_ms_per_cycle:.0f} ms of it"
          f"{first}{per_look}), {1e3 * res.seconds_per_cycle:.0f} ms with it; "
          f"octree {res.octree_bytes / 1024:.0f} KiB; true distance to goal "
          f"{res.final_true_error_ft:.2f} ft; estimate off the truth by "
          f"{res.track_errors()[-1]:.2f} ft at the end (dead reckoning "
          f"{res.track_errors(res.dead_track)[-1]:.2f} ft)")
    if res.cycles:
        frames = frames_of(res, room)
        save_png(out / "drive-map.png", frames[-1])
        write_gif(out / "drive.gif", frames)
        print(f"pictures: {out / 'drive-map.png'}, {out / 'drive.gif'}")
    if args.json:
        write_atomic(Path(args.json), (json.dumps(res.as_json(), indent=1) + "\n").encode())
        print(f"json: {args.json}")
    if res.reason.startswith("stopped by Ctrl-C"):
        return 130
    return 0 if res.reached else 3


# The closed loop's options as `--help` shows them, in the order of a cycle; every
# rule was measured (docs/planner.md), and each help says which value is the default.
LOOP_OPTION_GROUPS = (
    ("the eyes", "what the loop sees with",
     ("--eyes", "--match", "--disparity", "--head", "--assist-pivot-ft", "--min-range", "--min-confidence",
      "--stereo-margin")),
    ("the camera estimate", "where the loop believes the vehicle stands",
     ("--pose", "--pose-method", "--wall-points", "--wall-fix-sigmas", "--wall-fix-widen", "--wall-fix-most", "--wall-fix-far", "--wall-fix-far-sigmas", "--wall-fix-first",
      "--feature-pose", "--drift-sigmas")),
    ("the map: what is occupied", "where a look's located points and the floor plan block",
     ("--hit-at", "--growth", "--occupied", "--expire-uncertain", "--refute-hits",
      "--plan-walls", "--cell-ft")),
    ("the map: what is free", "what a look proves free, and what is assumed free",
     ("--floor-eyes", "--sight-lines", "--blank-ft", "--blank-carve", "--carve", "--blank-px",
      "--blank-limit", "--blank-sides", "--sides-apart", "--stand-in", "--learn-floor",
      "--proof-hits", "--free-cells", "--wall-hits", "--one-grey-runs", "--wall-runs", "--flat-foot-apart", "--tile-edges", "--floor-end-check", "--proof-heading", "--free-drift", "--free-gaps",
      "--track-free")),
    ("the path", "the search over the floor map",
     ("--unknown", "--search", "--margin", "--clearance-at", "--passage", "--goal-region", "--uncertain",
      "--goal-evidence",
      "--seen-cost", "--rejoin", "--blind-zone", "--map-extent", "--fine-map")),
    ("the motion", "what the vehicle may do with the path",
     ("--pivot", "--move-ring", "--steer", "--min-pivot-deg", "--approach", "--finish", "--look-ahead", "--look-around", "--progress",
      "--reverse", "--backing", "--turn-room", "--max-looks", "--max-stuck", "--looks-per-viewpoint")),
)


def add_loop_options(p) -> None:
    """The closed loop's options (:class:`planner.loop.DriveConfig`), shared by
    ``rig drive`` and ``bench/drive.py``; each default is DriveConfig's own."""
    from planner.loop import APPROACHES, FINISHES, FINISH_INNER_FT, DriveConfig as C, EYES, HEADS, PIVOTS, FEATURE_POSES, FLOOR_EYES, LOOK_AROUNDS, \
        TURN_ROOMS, BACKINGS, RETRACE_FT, RETRACES, MOVE_RINGS, STRAIGHT_AFTER, STEERS, \
    MAP_EXTENTS, FINE_MAPS, MATCHES, DISPARITIES, OCCUPIEDS, PLAN_WALLS, POSES, PROGRESSES, STAND_INS, TRACK_FREES, LEARN_FLOORS, FREE_DRIFTS, FREE_GAPS, PROOF_HEADINGS, FLOOR_END_CHECKS, PROOF_HITS, FREE_CELLS, GOAL_EVIDENCES, GOAL_EXPIRE_LOOKS, WALL_RUNS, TILE_EDGES, WALL_HITS, ONE_GREY_RUNS, \
        WALL_POINTS, WALL_FIX_FIRSTS
    from planner.motion import PIVOT_INNER_FT, STEER_MAX_DEG
    from planner.planning import BLIND_ZONES, GOALS, PASSAGES, REJOINS, UNCERTAIN_PLANS
    from planner.perception import BLANK_LIMITS, BLANK_SIDES, PLACES, SIGHT_LINES
    from model.pose import ESTIMATORS
    group_of = {}
    for title, what, flags in LOOP_OPTION_GROUPS:
        g = p.add_argument_group(title, what)
        group_of.update(dict.fromkeys(flags, g))

    def opt(flag, **kw):
        group_of[flag].add_argument(flag, **kw)

    opt("--unknown", choices=("free", "blocked"), default=C.unknown,
        help="plan through never-seen space as free (default) or blocked; the vehicle "
             "never drives into it either way")
    opt("--search", choices=("dissertation", "astar"), default=C.search,
        help="the dissertation's hierarchical search (default) or A*")
    opt("--eyes", choices=EYES, default=C.eyes,
        help="rig: the matcher's ranges (default); truth: the true range at the "
             "same edge pixels (an oracle: the planner without the matcher's errors); "
             "depth: the true range at every pixel, a dense range finder (a "
             "diagnostic oracle: the planner without the eyes' limits)")
    opt("--match", choices=MATCHES, default=C.match,
        help="the rig's stereo matcher: improved (not 1985; default since 2026-12-05: a "
             "verdict per edge, 'no match' instead of the best available; on the "
             "in-process rig, a scan of about 7 ms, compiled over the whole frame) or 1985 (the "
             "eyes: ESTAR's own match lists, bit for bit; the default before)")
    opt("--disparity", choices=DISPARITIES, default=C.disparity,
        help="where a located edge lies: pixel (default: LCSL's whole .BI pixels) or "
             "subpixel (not 1985; with --match improved and --eyes rig: each matched "
             "edge where its grey step crosses the level halfway between its greys in "
             "the .VD pictures, twice the .BI's resolution)")
    opt("--pose", choices=POSES, default=C.pose,
        help="the camera estimate that places each look: fused: the symbolic model's "
             "(the walk's step: the robust fix on matched vertices fused with the "
             "odometry's prior); dead_reckoning: the odometry alone (the default "
             "before 2026-12-05); walls (not 1985; default): each look's points on "
             "the floor plan's walls fused with the odometry's prior "
             "(planner.localize), also with --head")
    opt("--pose-method", default=C.pose_method, choices=ESTIMATORS,
        help="the fix fused under --pose fused (rig walk's --method; default robust)")
    opt("--margin", type=float, default=None, metavar="FT",
        help="the vehicle profile's planning margin (default: the profile's)")
    opt("--pivot", choices=PIVOTS, default=C.pivot,
        help="what a pivot in place needs seen free: disc: the whole circle of the "
             "footprint's half diagonal, whatever the angle (the default before "
             "2026-12-05); margin: that circle grown by the planning margin against the "
             "estimate's error; swept: the cells the footprint, grown by the margin, "
             "sweeps through the angle; small-swept: a turn up to 5 deg by its sweep, a "
             "larger one by the disc; swept-ring (default): the bare footprint's sweep "
             "seen free, a cell of the margin's ring never seen where nothing seen lies "
             "within the planning radius of it; swept-ring-inner (not 1985): that, but a "
             f"turn made only to look needs the footprint grown by {PIVOT_INNER_FT} ft seen "
             "free as well")
    opt("--move-ring", choices=MOVE_RINGS, default=C.move_ring,
        help="a forward move's swept band beyond the bare footprint (the margin's ring): "
             "seen: every cell seen; known (not 1985): a never-seen cell will do where "
             "nothing seen lies within the planning radius of it, as --pivot swept-ring "
             "lets a pivot's; start (not 1985; default): that only where the grown "
             "footprint stands at the move's start, which every pivot there sweeps too")
    opt("--steer", choices=STEERS, default=C.steer,
        help="a path's first leg cut short by the checks every move passes (a band "
             "that grazes a never-seen cell beside the vehicle): off: the path's heading; "
             f"small (not 1985): the same leg on a heading up to {STEER_MAX_DEG} deg off "
             "it, nearest first, where the checks let it run farther; idle (not 1985; "
             "default): that only where the vehicle would otherwise look round in place, "
             "nothing else to do")
    opt("--passage", choices=PASSAGES, default=C.passage,
        help="where the vehicle may pass: circle: paths and forward moves where the "
             "pivot circle and the margin fit; moves (not 1985; default): the circle's "
             "paths, a forward move also where only its grown width fits; straight (not "
             "1985): and where the circle finds no way to the goal, paths straight "
             "through such narrow ways, pivoting only where the circle fits; stuck (not "
             f"1985): those paths only after {STRAIGHT_AFTER} looks without progress")
    opt("--clearance-at", choices=("anywhere", "centre", "anywhere-exact"),
        default=C.clearance_at,
        help="where in a passable cell the vehicle's centre may be: anywhere (the "
             "dissertation's cross-section test, default; a cell's clearance by a "
             "lower bound, centre distance less a cell diagonal), its centre, every "
             "position then tested by its exact distance to the blocked cells, or "
             "anywhere-exact: anywhere, by the exact distance between the squares")
    opt("--growth", choices=("covariance", "across"), default=C.growth,
        help="a located hit grown by its whole covariance (the dissertation's, "
             "default) or by its error across the sight line only")
    opt("--feature-pose", choices=FEATURE_POSES,
        default=C.feature_pose,
        help="with --occupied model: the pose error in each observation's "
             "covariance: the dead-reckoned pose's whole covariance (default), the "
             "drift since a feature was last seen, or none")
    opt("--hit-at", choices=PLACES, default=C.hit_at,
        help="where a look's range lands on the floor plane: 'axis': along the "
             "pitched optical axis (short by up to the pitch's cosine; the default "
             "before 2026-12-05) or 'point' (default): at the located point's own "
             "horizontal position")
    opt("--occupied", choices=OCCUPIEDS, default=C.occupied,
        help="the map's occupied cells: model (default since 2026-12-05 13:45): "
             "regenerated each cycle from the floor features fused look by look "
             "(Chapter IV's octree regenerated from the symbolic model); looks: "
             "every look's hits grown by that look's covariance, never shrunk")
    opt("--approach", choices=APPROACHES, default=C.approach,
        help="the last move near the goal: disc (default since 2026-12-02; not "
             "1985): where the path's safe prefix drives nowhere, the straight move "
             "the same safety rules allow that ends nearest the goal inside its "
             "tolerance less 0.1 ft; path: the path's safe prefix only (before)")
    opt("--finish", choices=FINISHES, default=C.finish,
        help="where in the goal's disc the run ends: inner (default since 2026-12-07; "
             f"not 1985): on toward the goal until the estimate is within {FINISH_INNER_FT} "
             "ft of it, or a cycle begun in the disc brings it no nearer (each such cycle "
             "looks again, and so fixes the estimate: a run ended at the disc's edge by "
             "the estimate may lie outside it by the truth); edge (before): as soon as "
             "the estimate is within the tolerance")
    opt("--goal-region", choices=GOALS, default=C.goal_region,
        help="what the planner plans to: disc (default since 2026-12-05; not 1985): "
             "the standable cell nearest the goal inside its tolerance less 0.1 ft, the "
             "goal itself where the vehicle may stand there; point (before): the goal "
             "itself, refused when the map puts an obstacle within the vehicle's radius "
             "of it")
    opt("--floor-eyes", choices=FLOOR_EYES, default=C.floor_eyes,
        help="what the picture shows of the floor (not 1985; planner.appearance): "
             "bound-add (default since 2026-12-03): bound, and once the floor's grey "
             "is learned its proof carved, no farther than where bound ends its "
             "column; bound (the default 2026-12-02): nothing carved, each line the "
             "blank-column assumption carves ends where its column's floor in view "
             "ends (none where the floor's grey runs to the picture's top or past the "
             "plan's walls); off: the assumption unbounded, as before; carve: once "
             "the floor's grey is learned, each column's floor in view carved free in "
             "place of the assumption; add: carved beside it; veto: carve, and leave "
             "out located points the floor in view contradicts")
    opt("--expire-uncertain", type=int, default=C.expire_uncertain, metavar="N",
        help="an uncertain (once-hit, unconfirmed) cell goes back to UNKNOWN (never "
             "free) after N later looks had it in view and located nothing there; "
             "under --occupied model the floor feature one look placed is retired so "
             "(not 1985; default 0: off, it stays until sight lines clear it)")
    opt("--cell-ft", type=float, default=None, metavar="FT",
        help="the octree's finest cell: the fewest levels over the 32 ft volume of "
             "interest whose cell is no larger (default: depth 7, 0.25 ft; 0.125 is "
             "depth 8)")
    opt("--look-around", choices=LOOK_AROUNDS, default=C.look_around,
        help="when the vehicle cannot move: 'evidence' (default since 2026-12-04): look "
             "at where the path lacks evidence, from a place a look shows it; 'sweep': "
             "face the path and sweep")
    opt("--progress", choices=PROGRESSES, default=C.progress,
        help="what resets the count of looks without progress: any motion (default), "
             "or a shorter way left than ever or new free space seen")
    opt("--uncertain", choices=UNCERTAIN_PLANS, default=C.uncertain,
        help="no path avoids the uncertain cells (hit by one look): plan past the "
             "uncertain features' cells beyond one standard deviation and look again from "
             "nearer (core, the default since 2026-12-05 22:40; under --occupied looks, "
             "which draws no features, as blocked); head for the reachable cell nearest "
             "the goal (blocked, the default before); or plan through them all and look "
             "(look).  The moves keep clear of every uncertain cell")
    opt("--goal-evidence", choices=GOAL_EVIDENCES, default=C.goal_evidence,
        help="no path reaches the goal: look round (off), or first look at "
             "the uncertain cell nearest the goal from where a look shows it (look, not "
             "1985); look-expire (the default): that, and a feature one look placed whose two-sigma "
             "ellipse reaches the goal's planning radius is retired after "
             f"{GOAL_EXPIRE_LOOKS} looks that had it in view and did not locate it "
             "(--occupied model)")
    opt("--wall-hits", choices=WALL_HITS, default=C.wall_hits,
        help="a floor hit whose two-sigma ellipse reaches the floor plan's walls: a floor "
             "feature as any hit (feature, the default before 2026-12-06 20:30), or "
             "explained by the plan's wall and no feature started (plan, the default; not "
             "1985: a wall's own points located short of it grow into the floor, room 119; "
             "with --one-grey-runs near-seen, seeds 1-900: 632 goals against 627)")
    opt("--one-grey-runs", choices=ONE_GREY_RUNS, default=C.one_grey_runs,
        help="on a tiled floor, a column whose floor run shows one of its greys only: "
             "proves as any run (prove, the default before 2026-12-06 20:30), or only "
             "where the last map showed the floor before its bottom row free (near-seen, "
             "the default; not 1985: a face of that grey there fills the bottom rows, "
             "room 881)")
    opt("--reverse", choices=("off", "on"), default="off",
        help="the vehicle's profile reverses (default off); with --backing map it may "
             "then BACK straight over space seen free")
    opt("--backing", choices=BACKINGS, default=C.backing,
        help="where the vehicle backs: 'trail' (default since 2026-12-07 12:15; not 1985; "
             "the vehicle then reverses, with or without --reverse on): only where it cannot "
             f"turn at all, outside the goal's disc, undoing its own last {RETRACE_FT:g} ft "
             f"of motion (ground its wheels swept, whatever the map shows), at most "
             f"{RETRACES} times a run; 'map' (the default before): only with --reverse on, "
             "straight back over space seen free")
    opt("--turn-room", choices=TURN_ROOMS, default=C.turn_room,
        help="where no pivot is allowed (its swept cells not seen free) and the vehicle "
             "cannot back: 'forward' (default since 2026-12-05 15:00; not 1985): the "
             "shortest straight move on, over space seen free, after which a pivot is "
             "allowed, then that pivot; 'off': it stays and looks again")
    opt("--track-free", choices=TRACK_FREES, default=C.track_free,
        help="free where the vehicle stood: its footprint at each pose (default), or "
             "the footprint swept by every move and pivot, shrunk by the margin")
    opt("--blank-ft", type=float, default=C.blank_ft, metavar="FT",
        help="picture columns outside everything the look located count free this "
             "far (default 8; 0: off, then blank walls stop the vehicle)")
    opt("--blank-carve", choices=("unknown", "always"), default=C.blank_carve,
        help="how that assumption carves: 'unknown' (default): only cells no look has "
             "seen, never past a cell any look hit, only past a near zone seen free; "
             "'always': as a seen sight line (collides in room 40)")
    opt("--carve", choices=("error", "range"), default=C.carve,
        help="columns between two edges free up to the near end of the edges' error "
             "bound (default) or up to their range")
    opt("--blank-px", type=int, default=C.blank_px if C.blank_px is not None else -1,
        metavar="N",
        help="that assumption carves only picture columns at most N columns beside a "
             "located one (-1, the default since 2026-12-03: the whole blank run, "
             "its lines ended by the floor in view; 16 before, since room 45's "
             "collision under the rules of 2026-12-01)")
    opt("--blank-limit", choices=BLANK_LIMITS, default=C.blank_limit,
        help="where --blank-px applies: 'all' (default): beside the outermost located "
             "columns and inside wide gaps between two; 'sides': only beside the "
             "outermost ones, wide gaps carved whole")
    opt("--blank-sides", choices=BLANK_SIDES, default=C.blank_sides,
        help="the side columns --blank-px cuts off (beside the outermost located "
             "one, out to the picture's edge): 'two-looks' (default): a cell carved "
             "once two looks --sides-apart apart both had it in such a blank "
             "column; 'cut': never carved (with --blank-px -1, the default, no "
             "column is cut off and this does nothing)")
    opt("--sides-apart", type=float, nargs=2, default=C.sides_apart,
        metavar=("FT", "DEG"),
        help="for --blank-sides two-looks: the two looks at least FT apart or "
             f"turned DEG from each other (default {C.sides_apart[0]:g} ft, "
             f"{C.sides_apart[1]:g} deg)")
    opt("--refute-hits", choices=("off", "under", "through"), default=C.refute_hits,
        help="'under' (not 1985): a hit cell a later sight line passes under (below "
             "the hit's lowest located point, to a surface beyond) shows unknown, "
             "never free; 'through' (not 1985): a hit a later, nearer look sees "
             "through (two located points farther at its pixel) is refuted, a cell "
             "all of whose hits are refuted shows unknown; 'off' (default)")
    opt("--stereo-margin", action="store_true", default=C.stereo_margin,
        help="(not 1985) a picture column frees the floor only from the depth at "
             "which the right camera sees it too (f B / (column - 1): column 20 "
             "from 7.1 ft): in the left picture's leftmost columns a near box is "
             "out of the right camera's view, shows no edge, and would count blank")
    opt("--min-range", type=float, default=C.min_range_ft, metavar="FT",
        help="located points nearer than FT are left out of the map and the wall "
             f"fix (default {C.min_range_ft:g}; 2.5 before 2026-12-05): from 2.5 to "
             "3 ft a third of the 1985 matcher's points are false matches")
    opt("--min-confidence", type=float, default=C.min_confidence, metavar="C",
        help="(not 1985; with --match improved) located points whose match the improved "
             "matcher vouches for with a confidence under C (0..1) are left out of the "
             "look (default 0: none)")
    opt("--sight-lines", choices=SIGHT_LINES, default=C.sight_lines,
        help="what a sight line to a located point frees: 'low' (default; not "
             "1985): only where its ray runs below the lowest obstacle's top (a box "
             "lower than the ray may hide under it: the 1985 eyes do not locate box "
             "tops); 'band' (the default before 2026-12-01): the whole height band "
             "up to it; 'low-all': 'low', "
             "and a look that located nothing frees only the far part of its "
             "blank view (from 0.8 of --blank-ft)")
    opt("--stand-in", choices=STAND_INS, default=C.stand_in,
        help="under --floor-eyes bound or bound-add, what stands for the floor's "
             "grey until the map has shown enough floor free: the greys of the "
             "picture's bottom 4 rows, 'tenth' (default): each grey with a tenth "
             "of them; 'majority' "
             "(not 1985): only a grey with more than half (none: the look assumes "
             "nothing), so a box face near the vehicle does not pass for floor")
    opt("--learn-floor", choices=LEARN_FLOORS, default=C.learn_floor,
        help="with --floor-eyes, where the floor's grey is first learned: "
             "'step-back' (not 1985; default since 2026-12-05): before the first look "
             f"the vehicle steps {C.learn_back_ft:g} ft back inside the clear spot it was "
             "set down in (a vehicle that does not reverse turns about, drives and turns "
             "back), so its first look's bottom rows show floor the clear spot vouches "
             "for (not under --floor-eyes off, nor with --eyes depth, which read no "
             "picture); 'off' (before): from floor the map shows free, once it shows any")
    opt("--look-ahead", action=argparse.BooleanOptionalAction, default=C.look_ahead,
        help="before a move, find the first never-seen cell on the planned path's "
             "swept band; while it is still far enough to show, cut the move there, "
             "pivot until it is in view and look (not 1985; default on since "
             "2026-12-01; --no-look-ahead: off, as before)")
    opt("--seen-cost", type=float, default=C.seen_cost, metavar="W",
        help="plan paths that keep to what was in view: A* where a cell within the "
             "vehicle's pivot circle of a never-seen cell costs 1 + W per ft "
             "(not the dissertation's search; default 0: off)")
    opt("--head", choices=HEADS, default=C.head,
        help="the rig's mount: 'fixed' (the default, pitched 25 deg down); "
             "'assist' (not 1985): the fixed rig's cycle unchanged, a head's look added "
             "only where it would stop or pivot only to look, aimed at what its way "
             "lacks; 'pan-tilt' (not 1985): on a head that pans +-90 deg and tilts "
             "0..-55 deg (PAN, TILT commands) and looks where the fixed rig pivots the "
             "vehicle only to look: at the first never-seen cell of its way, tilted "
             "down to show it, into its pivot circle, round (only 'fixed' with --pose "
             "fused)")
    opt("--min-pivot-deg", type=float, default=C.min_pivot_deg, metavar="DEG",
        help="a turn of the path's commands smaller than DEG needs no pivot circle seen "
             f"free: it moves the footprint's corners less than the planning margin "
             f"(not 1985; default {C.min_pivot_deg:g} since 2026-12-05; 0: every turn "
             "checked, before, when a 0.1 deg alignment stopped the lab 'cannot turn')")
    opt("--assist-pivot-ft", type=float, default=C.assist_pivot_ft, metavar="FT",
        help="under --head assist: a pivot may not sweep a cell free only by a "
             "blank-column assumption no look nearer than FT made (default "
             f"{C.assist_pivot_ft:g} ft, twice the nearest distance a look shows; "
             "0: off, as before 2026-12-02, when room 45 pivoted into a box)")
    opt("--rejoin", choices=REJOINS, default=C.rejoin,
        help="where a kept path resumes: 'leg' (the default since 2026-12-01: at "
             "the end of the leg nearest the vehicle) or 'waypoint' (at the waypoint "
             "nearest it, which can send it back to a corner it has just passed)")
    opt("--blind-zone", choices=BLIND_ZONES, default=C.blind_zone,
        help="plan round never-seen cells nearer than a look can show, when some "
             "path avoids them: 'short' (the default since 2026-12-01: only when at "
             "most the kept-path allowance longer), 'any', or 'off' (as before)")
    opt("--map-extent", choices=MAP_EXTENTS, default=C.map_extent,
        help="what the floor map the path is searched on covers: 'fallback' (not "
             "1985; the default since 2026-12-05): 'seen', and the walls' map in a "
             "cycle whose seen map has no path to the goal but the walls' map has; "
             "'seen' (before): every hit so far, the estimate and the goal, 2 ft "
             "round, its border blocking the search (no path: a drive toward the "
             "reachable cell nearest the goal); 'walls' (not 1985): the room's floor "
             "plan as well, every cycle")
    opt("--fine-map", choices=FINE_MAPS, default=C.fine_map,
        help="where neither map of --map-extent has a path to the goal: 'fallback' "
             "(not 1985; default) plans that cycle on the same maps with cells of half the side "
             "(0.125 ft with the default cells), the features and walls that blocked a "
             "cell drawn again on them (what the looks proved free is not resolved "
             "finer); 'off': never")
    opt("--plan-walls", choices=PLAN_WALLS, default=C.plan_walls,
        help="where the map draws the floor plan's walls: 'grown' (not 1985; default "
             "since 2026-12-04): two standard deviations of the estimate's position "
             "nearer, since the map is placed by the estimate and the plan by the "
             "room's truth; 'plan': where the plan has them")
    opt("--free-drift", choices=FREE_DRIFTS, default=C.free_drift,
        help="an older look's free space on the map: 'moves' (not 1985; default "
             "since 2026-12-04): for moves its edges beside a hit shrunk by two "
             "standard deviations of the odometry's drift since that look, a pivot's "
             "cells checked on the map before that; 'erode': shrunk for pivots too; "
             "'off': as that look proved it")
    opt("--wall-points", choices=WALL_POINTS, default=C.wall_points,
        help="under --pose walls with the rig's eyes, what fixes the estimate "
             "against the plan's walls: 'edges': the look's located points; "
             "'floor-ends' (not 1985; default): those and where the floor in view "
             "ends, a wall's foot along every blank wall")
    opt("--wall-fix-sigmas", type=float, default=C.wall_fix_sigmas, metavar="S",
        help="under --pose walls, how many standard deviations of the estimate's "
             f"heading a fix may turn it (default {C.wall_fix_sigmas:g}; 3 before "
             "2026-12-05: a skirting of the floor's grey turned it look after look)")
    opt("--wall-fix-widen", type=float, default=C.wall_fix_widen, metavar="S",
        help="under --pose walls, the standard deviations the fix's heading window "
             "grows by for each look in a row without a fix (not 1985; default "
             f"{C.wall_fix_widen:g}; 0: as before 2026-12-05): a heading the odometry "
             "threw out of the window is found again at the next look")
    opt("--wall-fix-most", type=float, default=C.wall_fix_most, metavar="S",
        help="under --pose walls: the widened window at most S standard deviations of the "
             f"prior's heading (not 1985; default {C.wall_fix_most:g} since 2026-12-06; 0: "
             "no bound, before; a wide window lets a few points that agree on a heading "
             "far off outvote the wall, rooms 321 and 329)")
    opt("--wall-fix-far", type=int, default=C.wall_fix_far, metavar="N",
        help="under --pose walls: a fix more than 3 standard deviations from the prior's "
             "heading on fewer than N points is taken only where a look 1 ft or more "
             "away shows one turning it as far the same way (not 1985; default 30; 0: off; a "
             "few points of one wall turned room 2's heading 10.6 deg the wrong way)")
    opt("--wall-fix-far-sigmas", type=float, default=C.wall_fix_far_sigmas, metavar="S",
        help="under --pose walls with --wall-fix-far: a turn more than S standard "
             f"deviations of the prior's heading is far (default {C.wall_fix_far_sigmas:g}; "
             "lower, not 1985: room 583's fix on 6 points of a far wall turned it 2.5 "
             "sigma the wrong way)")
    opt("--wall-fix-first", choices=WALL_FIX_FIRSTS, default=C.wall_fix_first,
        help="under --pose walls after looks without a fix: 'widened' (default) "
             "searches the whole widened window at once; 'base' (not 1985) the "
             "--wall-fix-sigmas window first, the widened one only where it finds no fix")
    opt("--free-gaps", choices=FREE_GAPS, default=C.free_gaps,
        help="an unknown cell between two free ones across a row or a column: "
             "'fill' it free (not 1985; default since 2026-12-05): no box fits in it "
             "that misses both, and the floor in view leaves such stripes; or 'keep' it "
             "unknown (before)")
    opt("--proof-hits", choices=PROOF_HITS, default=C.proof_hits,
        help="where the floor in view carves (--floor-eyes bound-add, carve, add, "
             "veto), where a cell some look has hit stops the proof of a picture "
             "row: 'trace': on the floor "
             "stretch an 0.8 ft obstacle would hide; 'line' (not 1985; default): anywhere on "
             "its line from the camera, so a box nearer than the picture's bottom "
             "row with a face of the floor's grey proves nothing behind it")
    opt("--free-cells", choices=FREE_CELLS, default=C.free_cells,
        help="what the floor in view and the blank-column assumption may free: 'any' "
             "cell they reach (default), or 'shadows' (not 1985): none on any "
             "column's sight line within 2 ft past where its floor run ends in that "
             "look (behind the foot of what stands there), so the floor seen beside a "
             "box's corner frees no cell along its hidden face")
    opt("--wall-runs", choices=WALL_RUNS, default=C.wall_runs,
        help="under --floor-eyes bound or bound-add, a column whose floor's grey runs on "
             "past the plan's walls or to the picture's top: 'texture' (not 1985; the "
             "default before 2026-12-08): its end is where a tiled floor's two greys are "
             "last seen in it, "
             "no farther than the walls' foot (a wall or a box face of a tile's grey "
             "stands past the last tile; a flat floor's column shows none); 'none': it "
             "shows no floor's end; 'foot' (not 1985): its end is the walls' foot less "
             "their growth, as a wall of the floor's grey shows it (a box face of that "
             "grey too: it collides); 'past': that only where the run ends past the "
             "walls, not where it reaches the picture's top; 'flat-foot' (not 1985; "
             "default): 'texture', and on a flat floor 'foot' cut at every located point within a "
             "box's width of the column, each cell proven only when a look from a "
             "bearing 20 deg away proves it too")
    opt("--flat-foot-apart", type=float, default=C.flat_foot_apart_deg, metavar="DEG",
        help="under --wall-runs flat-foot: how far apart, in degrees, the bearings of a "
             "cell from the two looks that must both prove it stand at least (default "
             f"{C.flat_foot_apart_deg:g})")
    opt("--tile-edges", choices=TILE_EDGES, default=C.tile_edges,
        help="under --floor-eyes bound-add, the floor's proof up each column's run of its "
             "learned greys: 'break' (default): a pixel of another grey ends it; 'blend' "
             "(not 1985): a lone pixel whose grey lies between those of the floor pixels "
             "above and below it does not (a tiled floor's edge, averaged by the condensing)")
    opt("--floor-end-check", choices=FLOOR_END_CHECKS, default=C.floor_end_check,
        help="under --floor-eyes bound or bound-add: 'off', or 'stereo' "
             "(not 1985): where the eyes locate a point in a column's floor run "
             "clearly nearer than the floor there, the run went on up a face or top "
             "of the floor's grey, and the column's floor ends at that point (three "
             "such points on one edge cut all of it); 'motion' (not 1985; default): that, and "
             "where a run's end moved with the camera since two earlier looks from "
             "elsewhere, it ends on an edge above the floor, and the edge is drawn "
             "occupied (a face of the floor's grey, room 860)")
    opt("--proof-heading", choices=PROOF_HEADINGS, default=C.proof_heading,
        help="under --floor-eyes bound or bound-add, where each column's floor in "
             "view ends: 'estimate': along the estimated heading; 'window' "
             "(not 1985; default): no farther than every column within --drift-sigmas of the "
             "heading's standard deviation shows, since the look may lie that far "
             "round")
    opt("--drift-sigmas", type=float, default=C.drift_sigmas, metavar="S",
        help="under --free-drift erode or moves: how many standard deviations of the drift "
             "an older look's free edge beside a hit gives up; under --proof-heading "
             "window, of the heading (default 2)")
    opt("--max-looks", type=int, default=C.max_looks, metavar="N",
        help=f"stop after N cycles, each one look of the fixed rig (default {C.max_looks} "
             "since 2026-12-07, 60 before; under --head assist a cycle's added look of the "
             "head comes on top)")
    opt("--max-stuck", type=int, default=C.max_stuck, metavar="N",
        help=f"give up after N looks in a row without progress (--progress; default "
             f"{C.max_stuck} since 2026-12-07, not 1985; 16 before, 8 before 2026-12-05), "
             "saying why")
    opt("--looks-per-viewpoint", type=int, default=C.looks_per_viewpoint, metavar="N",
        help="the looks the evidence a path lacks takes at one blocker from one place "
             "(turned to it, then looking again while it stays unresolved) before it "
             f"drives to another place to see it from (default {C.looks_per_viewpoint})")


def first_look_note(cycles, slow_s: float = 1.0) -> str:
    """The per-cycle times are means over the run; on a new machine the first
    look's scan also compiles the eyes (numba, cached after), which can be
    most of a short run's mean.  Says so when the eyes are compiled and the
    first scan took over ``slow_s`` seconds, so the mean is not read as the
    eyes' pace."""
    from diskfmt import jit
    if not jit.ENABLED or not cycles or cycles[0].scan_s <= slow_s:
        return ""       # (plain Python, RIG_NO_JIT: every look is slow, nothing compiled)
    return (f" (the first look {cycles[0].scan_s:.1f} s: the eyes compiled, cached for the "
            f"next run)")


def loop_config(args, goal, fail):
    """The :class:`planner.loop.DriveConfig` of :func:`add_loop_options`'s
    arguments; ``fail(message)`` reports a bad value (and does not return)."""
    from planner.loop import MAX_MIN_PIVOT_DEG, DriveConfig, _check_config
    from planner.octree import VolumeOfInterest
    from vehicle.profile import DEFAULT
    voi = DriveConfig.voi
    if args.cell_ft is not None:
        try:
            voi = VolumeOfInterest.for_accuracy(args.cell_ft)
        except ValueError as exc:
            fail(f"--cell-ft: {exc}")
    if not all(v > 0 for v in args.sides_apart):
        fail(f"--sides-apart {args.sides_apart[0]!r} {args.sides_apart[1]!r}: a distance in feet "
             f"and a turn in degrees, both positive")
    if not 0 <= args.min_pivot_deg <= MAX_MIN_PIVOT_DEG:
        fail(f"--min-pivot-deg {args.min_pivot_deg!r}: a turn of 0 (every turn a pivot) to "
             f"{MAX_MIN_PIVOT_DEG:g} deg")
    if args.expire_uncertain < 0:
        fail(f"--expire-uncertain: {args.expire_uncertain} looks; give 0 (off) or more")
    if not 0 <= args.seen_cost < 1e6:
        fail(f"--seen-cost {args.seen_cost!r}: an extra cost per ft, 0 (off) or more")
    if args.head != "fixed" and args.pose == "fused":
        fail(f"--pose fused with --head {args.head}: the walk's camera estimate assumes the "
             "fixed rig; use --head fixed with it, or --pose dead_reckoning or --pose walls")
    if not (math.isfinite(args.assist_pivot_ft) and 0 <= args.assist_pivot_ft <= 50):
        fail(f"--assist-pivot-ft {args.assist_pivot_ft!r}: a distance in feet, 0 (off) to 50")
    if args.margin is not None and not 0 <= args.margin < 10:
        fail(f"--margin {args.margin!r}: a planning margin in feet, at least 0 and under 10")
    profile = replace(DEFAULT, reverse=args.reverse == "on", head=args.head == "pan-tilt",
                      margin_ft=DEFAULT.margin_ft if args.margin is None else args.margin)
    cfg = DriveConfig(goal=goal, unknown=args.unknown, search=args.search,
                       max_looks=args.max_looks, max_stuck=args.max_stuck,
                       looks_per_viewpoint=args.looks_per_viewpoint, eyes=args.eyes,
                       match=args.match, disparity=args.disparity,
                       pose=args.pose, pose_method=args.pose_method,
                       clearance_at=args.clearance_at, pivot=args.pivot, growth=args.growth, voi=voi,
                       move_ring=args.move_ring, passage=args.passage, steer=args.steer,
                       occupied=args.occupied, hit_at=args.hit_at,
                       feature_pose=args.feature_pose,
                       look_around=args.look_around, turn_room=args.turn_room,
                       backing=args.backing,
                       progress=args.progress,
                       look_ahead=args.look_ahead, seen_cost=args.seen_cost,
                       uncertain=args.uncertain, track_free=args.track_free,
                       goal_region=args.goal_region, approach=args.approach, finish=args.finish, floor_eyes=args.floor_eyes,
                       expire_uncertain=args.expire_uncertain,
                       min_pivot_deg=args.min_pivot_deg,
                       blank_carve=args.blank_carve, carve=args.carve, profile=profile,
                       blank_px=args.blank_px if args.blank_px >= 0 else None,
                       blank_limit=args.blank_limit, blank_sides=args.blank_sides,
                       sight_lines=args.sight_lines, stand_in=args.stand_in,
                       learn_floor=args.learn_floor,
                       refute_hits=args.refute_hits,
                       stereo_margin=args.stereo_margin, min_range_ft=args.min_range,
                       min_confidence=args.min_confidence,
                       wall_fix_sigmas=args.wall_fix_sigmas, wall_fix_widen=args.wall_fix_widen, wall_fix_first=args.wall_fix_first,
                       wall_fix_most=args.wall_fix_most or None,
                       wall_fix_far=args.wall_fix_far,
                       wall_fix_far_sigmas=args.wall_fix_far_sigmas,
                       sides_apart=tuple(args.sides_apart), head=args.head,
                       assist_pivot_ft=args.assist_pivot_ft or None,
                       rejoin=args.rejoin, blind_zone=args.blind_zone,
                       map_extent=args.map_extent, fine_map=args.fine_map,
                       plan_walls=args.plan_walls,
                       free_drift=args.free_drift, drift_sigmas=args.drift_sigmas,
                       free_gaps=args.free_gaps, proof_heading=args.proof_heading,
                       floor_end_check=args.floor_end_check, proof_hits=args.proof_hits,
                       free_cells=args.free_cells,
                       goal_evidence=args.goal_evidence, wall_runs=args.wall_runs,
                       flat_foot_apart_deg=args.flat_foot_apart,
                       wall_hits=args.wall_hits, one_grey_runs=args.one_grey_runs,
                       tile_edges=args.tile_edges,
                       wall_points=args.wall_points,
                       blank_ft=args.blank_ft if args.blank_ft and args.blank_ft > 0 else None)
    try:
        _check_config(cfg)          # what no one option refuses (its combinations)
    except ValueError as exc:
        fail(str(exc))
    return cfg


def add_parser(sub) -> None:
    d = sub.add_parser("drive", help="drive the robot to a goal in a simulated room (closed loop)",
                       description="The goal-achievement loop of Chapter IV: look (render at the "
                                   "true pose), scan, model, octree, plan, execute the next "
                                   "command segment, repeat until the estimate is within 0.75 "
                                   "ft of the goal.  Exit 0 when reached, 3 when not, 130 on "
                                   "Ctrl-C.  The first options say where and with what "
                                   "noise; the groups after them are the loop's rules, each "
                                   "measured in docs/planner.md, its help naming the default.")
    d.add_argument("--room", type=int, metavar="SEED",
                   help="a generated room (default: the bundled lab)")
    d.add_argument("--start", metavar="X,Z[,HEADING]", help="start (ft, deg; default the room's)")
    d.add_argument("--goal", metavar="X,Z",
                   help=f"goal (ft; default {DEFAULT_LAB_GOAL} in the lab, a random reachable "
                        f"one in a generated room)")
    add_loop_options(d)
    d.add_argument("--seed", type=int, default=1985,
                   help="odometry noise seed (default 1985; bench/drive.py uses the room's)")
    d.add_argument("--no-noise", action="store_true", help="odometry noise off")
    d.add_argument("--out", default="out", help="where the pictures go (default ./out)")
    d.add_argument("--json", metavar="FILE", help="write the result as JSON")
    d.add_argument("--quiet-notes", action="store_true", help="no planner note per cycle")
    d.set_defaults(func=cmd_drive)


if __name__ == "__main__":
    p = argparse.ArgumentParser(prog="rig")
    add_parser(p.add_subparsers(dest="command", required=True))
    a = p.parse_args()
    sys.exit(a.func(a))
