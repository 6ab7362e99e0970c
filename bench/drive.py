"""Benchmark of the closed loop (``rig drive``) on seeded rooms.

For each of ``--rooms`` generated rooms (seeds 1..N) a random goal the
vehicle can reach in the TRUE room (a path exists for its planning radius at
the planner's resolution, at least 6 ft from the start), then the drive with
odometry noise.  Reported per room and overall: success (by the loop's own
test, its estimate within the tolerance of the goal, and ``success_true_rate``:
those whose TRUE pose ended within it too), collisions of the
TRUE footprint with the TRUE room along the executed motion, executed path
length against the true optimum (A* on the true room at the same resolution,
pulled taut), looks per metre, time per cycle with and without the look's
rendering, octree memory; and the dissertation's search against A* on the
same final map of each run, from the start to the goal (path length pulled
taut, and time).

    python bench/drive.py --rooms 20 [--pose fused] [--eyes truth] [--search astar] [--unknown blocked]
    python bench/drive.py --seeds 87,114,401-410                  # these seeds only
    python bench/drive.py --unreached-in run.json --max-stuck 24  # only the rooms run.json did not reach
    python bench/drive.py --rooms 20 --cell-ft 0.125 --losses    # the octree one level deeper
    python bench/drive.py --rooms 20 --first 21 --blank-carve unknown --carve error
    python bench/drive.py --rooms 20 --occupied model --feature-pose drift --losses
    python bench/drive.py --rooms 20 --goal-region point          # plan to the goal point (before 12-05)
    python bench/drive.py --rooms 20 --floor-eyes carve --losses  # the floor in view proves free space
    python bench/drive.py --first 101 --rooms 200 --floor-eyes off   # the blank-column assumption unbounded (the default before 2026-12-02)
    python bench/drive.py --rooms 20 --expire-uncertain 3 --losses  # once-hit cells in view expire
    python bench/drive.py --rooms 20 --eyes depth [--no-noise]    # the planner's own share
    python bench/drive.py --rooms 20 --eyes depth --pivot small-swept   # a small turn by its sweep
    python bench/drive.py --rooms 20 --eyes depth --seen-cost 8   # paths that keep to what was in view
    python bench/drive.py --rooms 20 --eyes depth --no-noise --no-look-ahead   # no look before the blind zone (the default before 2026-12-01)
    python bench/drive.py --rooms 20 --eyes depth --head pan-tilt   # the rig on a pan-tilt head (not 1985)
    python bench/drive.py --rooms 20 --pose walls --eyes depth --head pan-tilt   # the estimate fixed against the plan's walls
    python bench/drive.py --rooms 20 --eyes depth --map-extent walls   # plan to the walls, not only the seen extent
    python bench/drive.py --rooms 100 --losses --sight-lines band  # sight lines free the whole band (the default before 2026-12-01)
    python bench/drive.py --rooms 100 --losses --sight-lines band --stand-in majority  # before the floor's grey is learned, only a majority grey stands in
    python bench/drive.py --rooms 100 --losses --look-around sweep --free-drift off --plan-walls plan  # the defaults before 2026-12-04
    python bench/drive.py --rooms 100 --losses --free-gaps fill   # one-cell gaps in free space filled
    python bench/drive.py --lab --first 1980 --rooms 20   # the bundled lab, 20 odometry noise seeds

``--occupied model`` draws the map's occupied cells from floor features fused look by look
(planner.features); the summary then adds ``honest_2sigma``: the share of fused features
whose 2-sigma ellipse reaches the true outline.

``--floor-eyes`` (planner.appearance; ``bound-add`` by default) adds per room the floor's learned greys,
the cells the floor in view proved free and the located points it vetoed; the summary sums
the last two (``floor_cells``, ``vetoed_points``).

``--expire-uncertain N`` adds per room, and sums in the summary, ``expired_uncertain``: the
uncertain cells that expired to unknown after N looks had them in view with no hit.

Each room's ``slack_ft`` is the room to spare its task leaves
(planner.planning.task_slack: how far the vehicle's radius can grow and the true room
still join start and goal); the summary's ``success_by_slack`` counts the rooms reached
in bins of it (under 0.25 ft, 0.25-0.5 ft, 0.5 ft or more).

``--free-gaps fill`` (a named option) shows free every unknown cell between two free ones
across a row or a column (planner.floormap.one_cell_gaps).

``--free-drift erode`` or ``moves`` (the default) adds per room, and sums in the summary, ``drift_eroded``: the FREE
cells the final map gave up to the odometry's drift since the looks that freed them.

Each room also reports ``free_inside_now`` (summed as ``free_inside_now_total``):
the final map's FREE cells a quarter foot or more inside a box as the vehicle
stands at the end, each carried from the estimate's frame into the room by the
true pose (planner.evidence.free_inside_now).  The map is placed by the
estimate, so the count of ``--losses`` against the room itself also shows a
drifted estimate's whole map turned; this one shows what the vehicle, driving
by its estimate, would find inside a box.

``--losses`` sorts each run's final map against the true room: the cells it
blocks wrongly (the cell rounding of hits, growth, false matches), the true
obstacle cells it shows free, and the passable cells each kind costs.  It
also traces those free obstacle cells (``free_obstacle_cells`` per room,
``free_obstacle_cells_total``): which carving freed each (a sight line to a
hit, the columns between edges, the blank-column assumption, the two-look
sides, the floor in view, the start spot, the vehicle's track), how much of
the cell the obstacle covers and how deep inside it the cell's centre lies,
and the standing spots they open that are truly too near an obstacle
(``opened_unsafe``: a disc of the planning radius; ``..._turning_circle``:
of the vehicle's own).

The camera estimate's error (``--pose``: the symbolic model's fused pose or
dead reckoning) is reported against the true track, with the dead-reckoned
pose's error on the same run beside it.  The summary ends with the rooms by how their
drives ended (``stop_reasons``: reached, narrower than the vehicle, the goal too near an
obstacle on the map, cannot turn, ...).

``--eyes depth`` (planner.depth_eyes, a diagnostic oracle) sees the true range at every
pixel, and ``--no-noise`` turns the odometry noise off: together they leave the planner
and the loop alone to fail.

Each look is scanned with the improved stereo matcher (package ``matching``, on
the eyes' compiled slices and edge maps since 2026-12-07; the drive's default
since 2026-12-05); ``--match 1985`` scans it with the 1985 eyes instead;
``scan_ms_per_cycle`` is the scan's own share of the time.  ``work_ms`` is
wall-clock time, which the machine's other work stretches; ``work_cpu_ms`` the
same span in the loop thread's CPU time.

Numbers go into docs/planner.md with the command that made them.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

FT_PER_M = 3.28084


def search_side_by_side(fmap, start, goal, radius):
    """Both searches on one map: (dissertation ft, ms, A* ft, ms) or Nones."""
    from planner.search import NoPath, astar, clearance_map, hierarchical_search, path_length
    from planner.trajectory import shorten
    p = clearance_map(fmap, radius, "free", uncertain="blocked")
    out = []
    for search in (hierarchical_search, astar):
        t = time.perf_counter()
        try:
            raw = search(p, start, goal)
            ln = path_length(shorten(p, raw))
            raw_ln = path_length(raw)
        except NoPath:
            ln = raw_ln = None
        out += [ln, raw_ln, 1e3 * (time.perf_counter() - t)]
    return out


STOP_KINDS = (                     # (kind, a phrase of the loop's reason), first match wins
    ("reached", "goal reached"),
    ("collision", "hit something"),
    ("narrower than the vehicle", "narrower than the vehicle"),
    ("goal too near an obstacle on the map", "from an obstacle; the vehicle needs"),
    ("cannot turn", "cannot turn"),
    ("path kept, turning to look", "turning to look"),
    ("looks used up", "looks used up"),
    ("path kept, not driven", "(kept)"),
)


def stop_kind(reason: str) -> str:
    """The kind of a drive's ending, for the table of stop reasons."""
    for kind, phrase in STOP_KINDS:
        if phrase in reason:
            return kind
    return "other"


SLACK_BINS = ((0.0, 0.25), (0.25, 0.5), (0.5, None))     # ft of slack: (from, below)


def success_by_slack(rows) -> dict:
    """Success by the room to spare each task leaves (``slack_ft``): per bin of
    :data:`SLACK_BINS` the rooms reached, the rooms and the rate."""
    out = {}
    for lo, hi in SLACK_BINS:
        name = f"{lo:g}-{hi:g} ft" if hi is not None else f">={lo:g} ft"
        got = [r for r in rows if r["slack_ft"] is not None and r["slack_ft"] >= lo
               and (hi is None or r["slack_ft"] < hi)]
        n_ok = sum(bool(r["reached"]) for r in got)
        out[name] = {"reached": n_ok, "rooms": len(got),
                     "rate": n_ok / len(got) if got else None}
    return out


def final_map_losses(room, fmap, radius):
    """planner.floormap.map_losses of a run's final map against the TRUE room
    drawn on the same grid."""
    from planner.floormap import map_losses, true_floor_map
    ex = fmap.extent()
    bx0, bx1, bz0, bz1 = room.bounds
    margin = max(bx0 - ex[0], ex[1] - bx1, bz0 - ex[2], ex[3] - bz1, 0.0) + fmap.cell
    return map_losses(fmap, true_floor_map(room.obstacles, room.bounds, fmap.cell, margin), radius)


def traced_run(room, start, cfg, noise):
    """planner.loop.run with its Perception keeping a FreeProvenance (which
    carving freed each cell; the drive is the same): (result, perception)."""
    from planner.evidence import tracing_perception
    from planner.loop import run
    made = []
    res = run(room, start, cfg, noise=noise, perception_factory=tracing_perception(made))
    return res, made[0]


def free_obstacle_report(room, res, model, cfg):
    """planner.evidence.free_obstacle_cells of the final map, summed, with
    the standing spots they open (planner.evidence.standing_opened)."""
    from planner.evidence import free_obstacle_cells, standing_opened, tally_free_obstacle_cells
    from vehicle.profile import DEFAULT
    fm = res.cycles[-1].fmap
    cells = free_obstacle_cells(fm, room.obstacles, room.bounds, model.provenance, cfg.band,
                                res.estimate_track, DEFAULT.footprint, cfg.start_clear_ft,
                                model.hit_keys)
    out = tally_free_obstacle_cells(cells)
    out.update(standing_opened(fm, cells, room.obstacles, room.bounds,
                               DEFAULT.planning_radius_ft))
    strict = standing_opened(fm, cells, room.obstacles, room.bounds, DEFAULT.planning_radius_ft,
                             reach=DEFAULT.radius_ft)
    out["opened_unsafe_turning_circle"] = strict["opened_unsafe"]
    return out


def _add_tally(total, t):
    for k, v in t.items():
        if isinstance(v, dict):
            _add_tally(total.setdefault(k, {}), v)
        else:
            total[k] = total.get(k, 0) + v


def parse_seeds(text: str) -> list[int]:
    """``--seeds``: a comma list of seeds and ranges ("87,114,401-410"), in order,
    each once.  ValueError naming the bad part."""
    out, seen = [], set()
    for part in text.split(","):
        part = part.strip()
        lo, sep, hi = part.partition("-")
        try:
            a = int(lo)
            b = int(hi) if sep else a
        except ValueError:
            raise ValueError(f"--seeds: {part!r} is not a seed or a range like 401-410") from None
        if a < 0 or b < a:
            raise ValueError(f"--seeds: {part!r} is not a seed or a range like 401-410")
        for k in range(a, b + 1):
            if k not in seen:
                seen.add(k)
                out.append(k)
    return out


def unreached_seeds(path: str) -> list[int]:
    """``--unreached-in``: the seeds a bench run's ``--out`` JSON did not reach.
    ValueError naming the file when it is not such a file."""
    try:
        rows = json.loads(open(path).read())["rooms"]
        return [int(r["room"]) for r in rows if not r["reached"]]
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ValueError(f"--unreached-in {path}: not a bench/drive.py --out file ({e})") from None


def task_seeds(args) -> list[int]:
    """The seeds the bench runs: ``--seeds`` or ``--unreached-in`` when given,
    else ``--first`` .. ``--first + --rooms - 1``."""
    if getattr(args, "seeds", None):
        return parse_seeds(args.seeds)
    if getattr(args, "unreached_in", None):
        return unreached_seeds(args.unreached_in)
    return list(range(args.first, args.first + args.rooms))


def seeded_tasks(args):
    """(seed, room, start state, goal or None) for the seeded rooms the bench runs
    (:func:`task_seeds`); under ``--lab`` the bundled lab and its default goal, the
    seed the odometry noise's (the lab's one task under draws of the dead
    reckoning)."""
    from planner.planning import random_goal
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.room import bundled_lab, generate_room
    if getattr(args, "lab", False):
        from rig.drive import DEFAULT_LAB_GOAL
        room = bundled_lab()
        s = room.start
        for seed in task_seeds(args):
            yield seed, room, State(s.x, s.z, s.heading_deg), DEFAULT_LAB_GOAL
        return
    for seed in task_seeds(args):
        room = generate_room(seed)
        s = room.start
        start = State(s.x, s.z, s.heading_deg)
        yield seed, room, start, random_goal(room, start, DEFAULT, np.random.default_rng(seed))


def true_maps(args) -> int:
    """The dissertation's search and A* side by side on the true floor map of
    each room (start to its random goal): length pulled taut, raw length, ms."""
    from planner.floormap import true_floor_map
    from vehicle.profile import DEFAULT
    ratios, raw_ratios, t_d, t_a = [], [], [], []
    print(f"{'room':>4} {'diss ft':>7} {'A* ft':>6} {'diss raw':>8} {'A* raw':>6} {'diss ms':>7} "
          f"{'A* ms':>6}")
    for seed, room, start, goal in seeded_tasks(args):
        if goal is None:
            continue
        fm = true_floor_map(room.obstacles, room.bounds, 0.25)
        d, d_raw, dms, a, a_raw, ams = search_side_by_side(fm, (start.x, start.z), goal,
                                                           DEFAULT.planning_radius_ft)
        print(f"{seed:>4} {d:>7.2f} {a:>6.2f} {d_raw:>8.2f} {a_raw:>6.2f} {dms:>7.1f} {ams:>6.1f}")
        ratios.append(d / a)
        raw_ratios.append(d_raw / a_raw)
        t_d.append(dms)
        t_a.append(ams)
    print(f"dissertation / A*: taut length median {np.median(ratios):.3f} max {np.max(ratios):.3f}; "
          f"raw {np.median(raw_ratios):.3f}; ms median {np.median(t_d):.1f} / {np.median(t_a):.1f}")
    return 0


def main(argv=None) -> int:
    from rig.drive import add_loop_options
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=20)
    ap.add_argument("--first", type=int, default=1, help="first room seed")
    ap.add_argument("--seeds", metavar="LIST",
                    help="the seeds to run instead of --first/--rooms: a comma list of "
                         "seeds and ranges, e.g. 87,114,401-410")
    ap.add_argument("--unreached-in", metavar="JSON",
                    help="run only the seeds an earlier run's --out JSON did not reach (an "
                         "option that only acts where a drive would stop, --max-stuck or "
                         "--max-looks, drives the reached ones the same)")
    ap.add_argument("--lab", action="store_true",
                    help="drive the bundled lab to its default goal instead, once per "
                         "odometry noise seed --first .. --first + --rooms - 1 (rig drive "
                         "--seed; its default is 1985)")
    ap.add_argument("--no-noise", action="store_true",
                    help="odometry noise off (a diagnostic: the estimate is the true pose, "
                         "so what fails is neither the dead reckoning's drift nor, with "
                         "--eyes depth, the eyes)")
    add_loop_options(ap)
    ap.add_argument("--losses", action="store_true",
                    help="also sort the final map's wrongly blocked cells (cell rounding of "
                         "hits, growth, false matches) and the passable cells each costs, "
                         "against the true room (planner.floormap.map_losses); and trace the "
                         "true obstacle cells it shows free: which carving freed each, how "
                         "much of it the obstacle covers, the standing spots they open "
                         "(planner.evidence.free_obstacle_cells)")
    ap.add_argument("--out", help="write per-room results and the summary as JSON")
    ap.add_argument("--true-maps", action="store_true",
                    help="only the two searches on the TRUE floor maps of the rooms (no drive)")
    args = ap.parse_args(argv)
    if args.seeds and args.unreached_in:
        ap.error("--seeds and --unreached-in: give one")
    try:
        task_seeds(args)
    except ValueError as e:
        ap.error(str(e))
    if args.true_maps:
        return true_maps(args)

    from planner.evidence import free_inside_now
    from planner.loop import run
    from planner.planning import task_slack
    from rig.drive import loop_config
    from vehicle.profile import DEFAULT
    from world.odometry import OdometryNoise
    voi = loop_config(args, (0.0, 0.0), ap.error).voi

    rows = []
    print(f"{'room':>4} {'goal':>14} {'ok':>3} {'coll':>4} {'looks':>5} {'trav ft':>7} "
          f"{'opt ft':>6} {'ratio':>5} {'ms/cyc':>6} {'+look':>6} {'KiB':>5} "
          f"{'diss ft':>7} {'A* ft':>6} {'diss ms':>7} {'A* ms':>6} {'est err':>7} {'dr err':>6}  reason")
    for seed, room, start, goal in seeded_tasks(args):
        if goal is None:
            print(f"{seed:>4} no reachable goal; skipped")
            continue
        cfg = loop_config(args, goal, ap.error)
        noise = None if args.no_noise else OdometryNoise(seed=seed)
        if args.losses:
            res, model = traced_run(room, start, cfg, noise)
        else:
            res = run(room, start, cfg, noise=noise)
        last = res.cycles[-1] if res.cycles else None
        # both searches on the final model, from the start to the goal
        side = search_side_by_side(last.fmap, (start.x, start.z), goal,
                                   DEFAULT.planning_radius_ft) if last else [None] * 6
        ratio = res.travelled_ft / res.optimal_ft if (res.reached and res.optimal_ft) else None
        row = {"room": seed, "goal": goal, "reached": res.reached, "reason": res.reason,
               "collisions": res.collisions, "looks": res.looks,
               "travelled_ft": res.travelled_ft, "optimal_ft": res.optimal_ft,
               "ratio": ratio,
               # the room to spare the task leaves in the true room (planner.planning.task_slack)
               "slack_ft": task_slack(room, (start.x, start.z), goal, DEFAULT, voi.resolution),
               "work_ms_per_cycle": res.work_ms_per_cycle,
               "work_cpu_ms_per_cycle": res.work_cpu_ms_per_cycle,
               "work_ms_per_look": res.work_ms_per_look,
               "scan_ms_per_cycle": res.scan_ms_per_cycle,
               "ms_per_cycle_with_look": 1e3 * res.seconds_per_cycle,
               "octree_bytes": res.octree_bytes, "final_true_error_ft": res.final_true_error_ft,
               "dissertation_ft": side[0], "dissertation_raw_ft": side[1],
               "dissertation_ms": side[2], "astar_ft": side[3], "astar_raw_ft": side[4],
               "astar_ms": side[5],
               # mean and final distance of the estimate / dead reckoning from the truth
               "estimate_error_ft_mean": float(np.mean(res.track_errors())),
               "estimate_error_ft_final": float(res.track_errors()[-1]),
               "dead_error_ft_mean": float(np.mean(res.track_errors(res.dead_track))),
               "dead_error_ft_final": float(res.track_errors(res.dead_track)[-1])}
        if res.features is not None:
            from planner.features import honesty, true_outline
            share, n = honesty(res.features, true_outline(room))
            row.update(features=len(res.features), features_fused=res.features.fused,
                       features_started=res.features.started,
                       honest_2sigma=share, honest_features=n)
        if res.floor:
            row.update(res.floor)
        if res.expired_uncertain is not None:
            row["expired_uncertain"] = res.expired_uncertain
        if res.wall_fixes is not None:
            row["wall_fixes"] = res.wall_fixes
        if res.drift_eroded is not None:
            row["drift_eroded"] = res.drift_eroded
        if res.retraces is not None:
            row["retraces"] = res.retraces
        if last:
            # the final map's free cells inside a box as the vehicle stands now (its frame)
            row["free_inside_now"] = free_inside_now(last.fmap, room.obstacles,
                                                     res.estimate_track[-1], res.true_track[-1])
        if args.losses and last:
            row["map_losses"] = final_map_losses(room, last.fmap, DEFAULT.planning_radius_ft)
            row["free_obstacle_cells"] = free_obstacle_report(room, res, model, cfg)
        rows.append(row)

        def f(v, w, d=1):
            return f"{'-':>{w}}" if v is None else f"{v:>{w}.{d}f}"
        print(f"{seed:>4} ({goal[0]:5.1f},{goal[1]:5.1f}) {'yes' if res.reached else 'no':>3} "
              f"{res.collisions:>4} {res.looks:>5} {res.travelled_ft:>7.1f} "
              f"{f(res.optimal_ft, 6)} {f(ratio, 5, 2)} {res.work_ms_per_cycle:>6.0f} "
              f"{1e3 * res.seconds_per_cycle:>6.0f} {res.octree_bytes / 1024:>5.0f} "
              f"{f(side[0], 7)} {f(side[3], 6)} {f(side[2], 7)} {f(side[5], 6)} "
              f"{row['estimate_error_ft_final']:>7.2f} {row['dead_error_ft_final']:>6.2f}  "
              f"{res.reason[:70]}", flush=True)
    if not rows:
        print("no rooms")
        return 1
    ok = [r for r in rows if r["reached"]]
    tolerance_ft = cfg.tolerance_ft
    trav_m = sum(r["travelled_ft"] for r in rows) / FT_PER_M
    looks = sum(r["looks"] for r in rows)
    ratios = [r["ratio"] for r in ok if r["ratio"]]
    both = [r for r in rows if r["dissertation_ft"] and r["astar_ft"]]
    summary = {
        "rooms": len(rows), "lab": args.lab, "odometry_noise": not args.no_noise, "unknown": args.unknown, "search": args.search, "eyes": args.eyes,
        "match": args.match,
        "pose": args.pose, "pose_method": args.pose_method, "margin_ft": args.margin,
        "clearance_at": args.clearance_at, "pivot": args.pivot, "growth": args.growth, "uncertain": args.uncertain,
        "look_around": args.look_around, "look_ahead": args.look_ahead, "head": args.head, "assist_pivot_ft": args.assist_pivot_ft or None, "rejoin": args.rejoin, "blind_zone": args.blind_zone, "map_extent": args.map_extent, "plan_walls": args.plan_walls, "free_drift": args.free_drift, "free_gaps": args.free_gaps, "wall_points": args.wall_points, "proof_heading": args.proof_heading, "floor_end_check": args.floor_end_check, "proof_hits": args.proof_hits, "free_cells": args.free_cells, "looks_per_viewpoint": args.looks_per_viewpoint, "drift_sigmas": args.drift_sigmas, "min_range_ft": args.min_range, "min_confidence": args.min_confidence, "disparity": args.disparity, "wall_fix_far_sigmas": args.wall_fix_far_sigmas, "wall_fix_sigmas": args.wall_fix_sigmas, "wall_fix_widen": args.wall_fix_widen, "wall_fix_first": args.wall_fix_first, "seen_cost": args.seen_cost, "progress": args.progress, "reverse": args.reverse, "backing": args.backing, "move_ring": args.move_ring, "passage": args.passage,
        "track_free": args.track_free, "blank_carve": args.blank_carve, "carve": args.carve,
        "blank_px": args.blank_px if args.blank_px >= 0 else None,
        "blank_limit": args.blank_limit, "blank_sides": args.blank_sides,
        "sight_lines": args.sight_lines, "stand_in": args.stand_in, "learn_floor": args.learn_floor,
        "sides_apart": list(args.sides_apart),
        "occupied": args.occupied, "hit_at": args.hit_at,
        "feature_pose": args.feature_pose, "goal_region": args.goal_region, "approach": args.approach, "finish": args.finish,
        "floor_eyes": args.floor_eyes, "expire_uncertain": args.expire_uncertain,
        "min_pivot_deg": args.min_pivot_deg,
        "cell_ft": voi.resolution, "octree_depth": voi.depth,
        "success_rate": len(ok) / len(rows),
        # the loop stops on its estimate; by the truth the vehicle may still be farther out
        "success_true_rate": sum(r["final_true_error_ft"] <= tolerance_ft for r in ok) / len(rows),
        "true_error_ft_reached_max": max((r["final_true_error_ft"] for r in ok), default=None),
        "collisions": sum(r["collisions"] for r in rows),
        "free_inside_now_total": sum(r.get("free_inside_now", 0) for r in rows),
        "ratio_median": float(np.median(ratios)) if ratios else None,
        "ratio_max": float(np.max(ratios)) if ratios else None,
        "looks_per_metre": looks / trav_m if trav_m else None,
        "work_ms_per_cycle_median": float(np.median([r["work_ms_per_cycle"] for r in rows])),
        "work_ms_per_look_median": float(np.median([r["work_ms_per_look"] for r in rows])),
        "work_cpu_ms_per_cycle_median": float(np.median([r["work_cpu_ms_per_cycle"]
                                                         for r in rows])),
        "scan_ms_per_cycle_median": float(np.median([r["scan_ms_per_cycle"] for r in rows])),
        "ms_per_cycle_with_look_median": float(np.median([r["ms_per_cycle_with_look"]
                                                          for r in rows])),
        "octree_kib_median": float(np.median([r["octree_bytes"] for r in rows])) / 1024,
        "octree_kib_max": max(r["octree_bytes"] for r in rows) / 1024,
        "dissertation_over_astar_length_median":
            float(np.median([r["dissertation_ft"] / r["astar_ft"] for r in both])) if both
            else None,
        "dissertation_ms_median": float(np.median([r["dissertation_ms"] for r in both]))
        if both else None,
        "astar_ms_median": float(np.median([r["astar_ms"] for r in both])) if both else None,
        "maps_both_found": len(both),
        "estimate_error_ft_final_median": float(np.median([r["estimate_error_ft_final"]
                                                           for r in rows])),
        "estimate_error_ft_final_max": float(np.max([r["estimate_error_ft_final"] for r in rows])),
        "dead_error_ft_final_median": float(np.median([r["dead_error_ft_final"] for r in rows])),
        "dead_error_ft_final_max": float(np.max([r["dead_error_ft_final"] for r in rows])),
        "estimate_error_ft_mean_median": float(np.median([r["estimate_error_ft_mean"]
                                                          for r in rows])),
        "dead_error_ft_mean_median": float(np.median([r["dead_error_ft_mean"] for r in rows])),
    }
    honest = [r for r in rows if r.get("honest_features")]
    if honest:
        # the share of fused features whose 2-sigma ellipse reaches the true
        # outline, over all rooms (planner.features.honesty; honest: 86.5 % or more)
        n = sum(r["honest_features"] for r in honest)
        summary["honest_2sigma"] = sum(r["honest_2sigma"] * r["honest_features"]
                                       for r in honest) / n
        summary["honest_features"] = n
    if any("vetoed_points" in r for r in rows):
        summary["vetoed_points"] = sum(r.get("vetoed_points", 0) for r in rows)
        summary["floor_cells"] = sum(r.get("floor_cells", 0) for r in rows)
    if any("expired_uncertain" in r for r in rows):
        summary["expired_uncertain"] = sum(r.get("expired_uncertain", 0) for r in rows)
    if any("drift_eroded" in r for r in rows):
        summary["drift_eroded"] = sum(r.get("drift_eroded", 0) for r in rows)
    if any("wall_fixes" in r for r in rows):
        # --pose walls: the looks fixed against the plan's walls, of all looks
        summary["wall_fixes"] = sum(r.get("wall_fixes", 0) for r in rows)
        summary["wall_fix_share"] = summary["wall_fixes"] / max(1, looks)
    summary["success_by_slack"] = success_by_slack(rows)
    kinds = {}
    for r in rows:
        kinds.setdefault(stop_kind(r["reason"]), []).append(r["room"])
    summary["stop_reasons"] = kinds
    if args.losses:
        keys = [k for k in rows[0].get("map_losses", {}) if k != "cell_ft"]
        summary["map_losses_total"] = {k: sum(r["map_losses"][k] for r in rows
                                              if "map_losses" in r) for k in keys}
        total = {}
        for r in rows:
            if "free_obstacle_cells" in r:
                _add_tally(total, r["free_obstacle_cells"])
        summary["free_obstacle_cells_total"] = total
    print()
    for k, v in summary.items():
        print(f"{k:40s} {v if not isinstance(v, float) else round(v, 3)}")
    if args.out:
        from rig.scan import write_atomic
        write_atomic(args.out, json.dumps({"summary": summary, "rooms": rows}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
