"""``rig walk`` — the robot walks a room on the 1985 eyes and keeps one model of it.

Each look: the world renders the pair at the true pose, the rig scans it
(ESTAR, lines 8..112), the located edges become vertex observations, they are
matched to the model, every pose method estimates the camera on the same
correspondences, and the driving method's pose updates the model (static
Kalman filter) and adds what is new (see :mod:`model.mapping`).

Method names (table, ``--json`` and model JSON):

==================  ==========================================================
``dead_reckoning``  the odometry alone (2 % of distance, 1 degree per turn)
``fused``           the robot's pose: the driving method's fix (``--method``)
                    combined with the odometry's prior by their covariances;
                    the model is updated with it
``a48``             Appendix A as written: A-21..A-48, covariance A-50
``rigid``           alternative (a): a true rotation, full-covariance weights
``robust``          alternative (b): (a) with wrong correspondences rejected
``floor``           alternative (c): floor-following (x, z, heading), with (b)
``kabsch``          reference: unweighted Kabsch (scipy)
``opencv``          reference: OpenCV estimateAffine3D
==================  ==========================================================

Outputs (``--out DIR``): ``model.json`` (everything: settings, every look,
the whole symbolic model), ``model.ply`` (vertices with covariance),
``map.png`` (top-down: the model with 2-sigma ellipses, the true room
outline, the true, estimated and dead-reckoned paths) and ``errors.png``
(error per look, every method).  All files are written under temporary
names and renamed once everything is computed: an interrupted walk leaves
nothing half-written.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from model.mapping import FEATURE_GATE_CHI2
from model.pose import ESTIMATORS, METHOD_NOTES

ALL_METHODS = ("dead_reckoning", "fused", *ESTIMATORS)
DEFAULT_ROOM_LOOKS = 30


class WalkInputError(ValueError):
    """Bad input to ``rig walk``: one clear message."""


# --- inputs ----------------------------------------------------------------------

def load_walk(args):
    """(room, poses, description) from the options; raises WalkInputError."""
    from world.room import bundled_lab, generate_room
    from world.walk import bundled_walk, generate_walk, read_walk
    if args.room is not None:
        room = generate_room(args.room)
        label = f"generated room {args.room}"
    else:
        room = bundled_lab()
        label = "bundled lab"
    if args.walk:
        try:
            poses = read_walk(args.walk)
        except (ValueError, OSError) as exc:
            raise WalkInputError(str(exc)) from None
        label += f", walk {args.walk}"
    elif args.room is not None:
        try:
            poses = generate_walk(room, args.room, args.looks or DEFAULT_ROOM_LOOKS)
        except ValueError as exc:
            raise WalkInputError(f"{label}: {exc}") from None
        label += f", generated walk (seed {args.room})"
    else:
        poses = bundled_walk()
        label += ", bundled walk"
    if args.looks is not None:
        if args.looks < 2:
            raise WalkInputError(f"--looks {args.looks}: a walk needs at least 2 looks")
        poses = poses[:args.looks]
    if len(poses) < 2:
        raise WalkInputError(f"{label}: only {len(poses)} pose(s); a walk needs at least 2")
    for i, p in enumerate(poses):
        x0, x1, z0, z1 = room.bounds
        if not (x0 < p.x < x1 and z0 < p.z < z1):
            raise WalkInputError(f"{label}: pose {i} (x {p.x:g}, z {p.z:g}) is outside the room "
                                 f"(x {x0:g}..{x1:g}, z {z0:g}..{z1:g})")
        if room.clearance(p.x, p.z) <= 0:
            raise WalkInputError(f"{label}: pose {i} (x {p.x:g}, z {p.z:g}) is inside an obstacle")
    return room, poses, label


# --- tables ---------------------------------------------------------------------------

def _fmt_est(e):
    return "      refused      " if e is None else f"{e[0]:6.2f} {e[1]:6.2f} {e[2]:7.1f}"


def look_table(result, driver: str) -> str:
    head = ("look  true x      z    head |    fused x      z    head |  err ft  deg | "
            "dead-rec err ft deg | seen match wrong used | model  ms")
    out = [head, "-" * len(head)]
    for r in result.records:
        t = r.true_pose
        e = r.estimates.get("fused")
        err = r.errors("fused")
        dre = r.errors("dead_reckoning")
        es = "   -     -  " if err is None else f"{err[0]:6.2f} {err[1]:5.1f}"
        out.append(f"{r.look:4d} {t.x:6.2f} {t.z:6.2f} {t.heading_deg:7.1f} | {_fmt_est(e):>24s} | "
                   f"{es} | {dre[0]:10.2f} {dre[1]:5.1f} | {r.seen:4d} {r.matched:5d} {r.wrong:5d} "
                   f"{r.used:4d} | {r.model_size:5d} {r.times_ms['look']:4.0f}"
                   + ("" if not r.driver_refused or r.look == 0 else f"  <- {r.driver_refused}"))
    return "\n".join(out)


def method_summary(result) -> list[dict]:
    """Per method: looks fixed, median/worst position and heading error (looks 1..)."""
    rows = []
    for m in ALL_METHODS:
        if m != "dead_reckoning" and m not in result.records[0].estimates:
            continue
        errs = [r.errors(m) for r in result.records[1:]]
        ok = np.array([e for e in errs if e is not None]).reshape(-1, 2)
        times = [r.times_ms[m] for r in result.records[1:] if m in r.times_ms]
        rows.append({
            "method": m, "fixed": int(len(ok)), "looks": len(errs),
            "median_position_error_ft": float(np.median(ok[:, 0])) if len(ok) else None,
            "worst_position_error_ft": float(ok[:, 0].max()) if len(ok) else None,
            "median_heading_error_deg": float(np.median(ok[:, 1])) if len(ok) else None,
            "worst_heading_error_deg": float(ok[:, 1].max()) if len(ok) else None,
            "median_solve_ms": float(np.median(times)) if times else None,
        })
    return rows


def summary_text(result, rows) -> str:
    def f(v, p=2):
        return "    -" if v is None else f"{v:{6}.{p}f}"
    out = ["method          fixed   position error ft    heading error deg   solve ms",
           "                        median    worst      median    worst",
           "--------------  -----   ------   ------      ------   ------   --------"]
    for r in rows:
        out.append(f"{r['method']:14s}  {r['fixed']:2d}/{r['looks']:<2d}   {f(r['median_position_error_ft'])}"
                   f"   {f(r['worst_position_error_ft'])}      {f(r['median_heading_error_deg'], 1)}"
                   f"   {f(r['worst_heading_error_deg'], 1)}   {f(r['median_solve_ms'], 1)}")
    fs = result.feature_scores()
    matched = sum(r.matched for r in result.records)
    wrong = sum(r.wrong for r in result.records)
    used = sum(r.used for r in result.records)
    used_wrong = sum(r.used_wrong for r in result.records)
    looks_ms = [r.times_ms["look"] for r in result.records[1:]]
    out.append("")
    out.append(f"model: {fs['features']} vertices, {len(result.model.lines)} boundary lines; "
               f"RMS error {f(fs['rms_error_ft'])} ft (median {f(fs['median_error_ft'])}); truths "
               f"inside 2 sigma {100 * (fs['inside_2sigma'] or 0):.1f} %")
    out.append(f"  confirmed (seen in 2 looks or more): {fs['confirmed']}, RMS error "
               f"{f(fs['confirmed_rms_error_ft'])} ft (median {f(fs['confirmed_median_error_ft'])}), "
               f"inside 2 sigma {100 * (fs['confirmed_inside_2sigma'] or 0):.1f} %")
    if result.config.consider:
        out.append(f"  (inside 2 sigma of the consider covariance ({result.config.consider}); of "
                   f"the filter's own: {100 * (fs['filter_inside_2sigma'] or 0):.0f} %)")
    if result.config.variance_factor:
        out.append(f"  (covariances scaled by the variance factor: global {fs['variance_factor_global']:.3f}, "
                   f"median per vertex {fs['variance_factor_median'] or 0:.3f}, never below 1)")
    if result.config.confirm is not None:
        out.append(f"  track-confirmed ({result.config.confirm} consistent looks or more): "
                   f"{fs['track_confirmed']}, RMS error {f(fs['track_confirmed_rms_error_ft'])} ft, "
                   f"inside 2 sigma {100 * (fs['track_confirmed_inside_2sigma'] or 0):.1f} %; "
                   f"tentative: {fs['tentative']}, inside 2 sigma "
                   f"{100 * (fs['tentative_inside_2sigma'] or 0):.1f} %")
    if result.config.ambiguity_gate is not None:
        out.append(f"  ambiguous stereo matches (ambiguity gate {result.config.ambiguity_gate}): "
                   f"{sum(r.ambiguous for r in result.records)} vertex observations"
                   + (f", {sum(r.resolved for r in result.records)} edges moved to the period "
                      "the model predicts" if result.config.ambiguity_gate == "resolve" else ""))
    if result.config.feature_gate or result.config.retire_unseen:
        out.append(f"  {fs['retired']} vertices retired (contradicted by later looks, or unseen "
                   "where they should have been seen)")
    out.append(f"correspondences: {matched} matched, {wrong} wrong "
               f"({100 * wrong / max(matched, 1):.0f} %); {used} used by the driving method, "
               f"{used_wrong} of them wrong ({100 * used_wrong / max(used, 1):.0f} %)")
    rl = result.rms_by_looks(12)
    out.append("feature RMS ft after n looks: " + ", ".join(
        f"{n}: {rms:.2f} ({cnt})" for n, cnt, rms in rl))
    out.append(f"time per look (scan + model + driving method): median {np.median(looks_ms):.0f} ms")
    return "\n".join(out)


# --- JSON --------------------------------------------------------------------------

# the "model" fields of the variance factor (--variance-factor) and of track confirmation
# (--confirm), present only with those options (docs/model.md)
TRACK_FIELDS = ("variance_factor_global", "variance_factor_median", "track_confirmed",
                "track_confirmed_inside_2sigma", "track_confirmed_rms_error_ft", "tentative",
                "tentative_inside_2sigma", "tentative_rms_error_ft")

def walk_json(result, label: str, rows) -> dict:
    """The ``--json`` document (the schema docs/model.md gives, plus more fields)."""
    looks = []
    for r in result.records:
        t = r.true_pose
        methods = {}
        for m in ALL_METHODS:
            if m not in r.estimates:
                continue
            e = r.estimates[m]
            err = r.errors(m)
            if e is None:
                methods[m] = {"x": None, "z": None, "heading_deg": None, "position_error_ft": None,
                              "heading_error_deg": None, "refused": r.refusals.get(m, "")}
            else:
                methods[m] = {"x": e[0], "z": e[1], "heading_deg": e[2],
                              "position_error_ft": err[0], "heading_error_deg": err[1]}
        v = r.velocity
        looks.append({
            "look": r.look, "true": {"x": t.x, "z": t.z, "heading_deg": t.heading_deg},
            "methods": methods, "seen": r.seen, "matched": r.matched, "wrong": r.wrong,
            "used": r.used, "used_wrong": r.used_wrong, "added": r.added,
            "model_size": r.model_size, "time_ms": {k: round(x, 3) for k, x in r.times_ms.items()},
            "driver_refused": r.driver_refused if r.look else None,
            **({"ambiguous": r.ambiguous} if result.config.ambiguity_gate else {}),
            **({"resolved": r.resolved} if result.config.ambiguity_gate == "resolve" else {}),
            "velocity": None if v is None else {
                "vx_ft_s": v.vx, "vz_ft_s": v.vz, "turn_deg_s": v.turn_deg_s,
                "cov": np.round(v.cov, 8).tolist()},
        })
    fs = result.feature_scores()
    return {
        "walk": label,
        "driver": result.config.driver, "kalman": result.config.kalman,
        "column_error_px": result.config.column_error_px,
        "pose_sigma_floor": result.config.pose_sigma_floor,
        "feature_gate": result.config.feature_gate, "consider": result.config.consider,
        "retire_unseen": result.config.retire_unseen,
        "variance_factor": result.config.variance_factor, "confirm": result.config.confirm,
        "tilt_floor": result.config.tilt_floor, "ambiguity_gate": result.config.ambiguity_gate,
        "match": result.config.match,
        "method_names": {m: METHOD_NOTES[m] for m in ALL_METHODS
                         if m == "dead_reckoning" or m in result.records[0].estimates},
        "looks": looks,
        "model": {"features": fs["features"], "rms_error_ft": fs["rms_error_ft"],
                  "inside_2sigma": fs["inside_2sigma"], "scored": fs["scored"],
                  "inside_mahalanobis_2": fs["inside_mahalanobis_2"],
                  "median_error_ft": fs["median_error_ft"], "confirmed": fs["confirmed"],
                  "confirmed_rms_error_ft": fs["confirmed_rms_error_ft"],
                  "confirmed_median_error_ft": fs["confirmed_median_error_ft"],
                  "confirmed_inside_2sigma": fs["confirmed_inside_2sigma"],
                  "filter_inside_2sigma": fs["filter_inside_2sigma"],
                  "retired": fs["retired"],
                  **{k: fs[k] for k in TRACK_FIELDS if k in fs},
                  "lines": len(result.model.lines),
                  "rms_by_looks": [{"looks": n, "features": c, "rms_error_ft": e}
                                   for n, c, e in result.rms_by_looks(20)]},
        "summary": rows,
    }


# --- the command -------------------------------------------------------------------

def cmd_walk(args) -> int:
    from model.mapping import WalkConfig, run_walk
    from world.odometry import OdometryNoise, dead_reckon
    from world.render import render_look
    try:
        room, poses, label = load_walk(args)
        if args.interval <= 0:
            raise WalkInputError(f"--interval {args.interval}: the time between looks must be > 0")
        if args.json and not Path(args.json).resolve().parent.is_dir():
            raise WalkInputError(f"--json {args.json}: no such directory "
                                 f"{Path(args.json).resolve().parent}")
        if Path(args.out).exists() and not Path(args.out).is_dir():
            raise WalkInputError(f"--out {args.out}: exists and is not a directory")
    except WalkInputError as exc:
        print(f"rig walk: {exc}", file=sys.stderr)
        return 2
    methods = tuple(args.methods) if args.methods else ESTIMATORS
    if args.line_step < 1:
        print(f"rig walk: --line-step {args.line_step}: must be at least 1", file=sys.stderr)
        return 2
    if args.tilt_floor is not None and args.consider is None:
        print("rig walk: --tilt-floor widens the consider covariance: use it with --consider",
              file=sys.stderr)
        return 2
    if args.consider is not None and args.kalman == "ci":
        print("rig walk: --consider follows the Kalman gain: use it with --kalman a30, a29 "
              "or joint, not ci", file=sys.stderr)
        return 2
    if args.tilt_floor is not None and args.kalman == "joint":
        print("rig walk: --tilt-floor widens the static consider covariance's camera term; "
              "the joint filter carries the pose in its state: not with --kalman joint",
              file=sys.stderr)
        return 2
    config = WalkConfig(methods=methods, driver=args.method, kalman=args.kalman,
                        match=args.match, look_interval_s=args.interval,
                        lines=tuple(range(8, 113, args.line_step)), max_range_ft=args.max_range,
                        shape_max_bits=None if args.shape_bits < 0 else args.shape_bits,
                        column_error_px=args.column_error, pose_sigma_floor=args.pose_floor,
                        feature_gate=args.feature_gate, consider=args.consider,
                        retire_unseen=args.retire_unseen,
                        variance_factor=args.variance_factor, confirm=args.confirm,
                        tilt_floor=args.tilt_floor, ambiguity_gate=args.ambiguity_gate)
    noise = OdometryNoise(seed=args.odometry_seed)
    dr = dead_reckon(poses, noise)
    out = Path(args.out)
    print(f"rig walk: {label}, {len(poses)} looks; driving method {args.method}, Kalman "
          f"{args.kalman}, stereo matcher {args.match}"
          + (f", column error {args.column_error:g} px" if args.column_error != 0.5 else "")
          + (f", pose floor {args.pose_floor[0]:g} ft {args.pose_floor[1]:g} deg"
             if args.pose_floor else "")
          + (f", feature gate {args.feature_gate:g}" if args.feature_gate else "")
          + (f", consider covariance {args.consider}" if args.consider else "")
          + (f", retire unseen {args.retire_unseen}" if args.retire_unseen else "")
          + (f", tilt floor {args.tilt_floor[0]:g} ft {args.tilt_floor[1]:g} deg"
             if args.tilt_floor else "")
          + (", variance factor" if args.variance_factor else "")
          + (f", confirm {args.confirm}" if args.confirm else "")
          + (f", ambiguity gate {args.ambiguity_gate}" if args.ambiguity_gate else ""))
    bar = None
    if not args.quiet:
        from tqdm import tqdm
        bar = tqdm(total=len(poses), desc="looks", unit="look", disable=None)
    t0 = time.perf_counter()
    try:
        result = run_walk(room, poses, dr,
                          lambda r, p, k: render_look(r, p, seed=args.render_seed + k),
                          config, progress=(lambda k: bar.update(1)) if bar else None)
    except KeyboardInterrupt:
        if bar:
            bar.close()
        print("rig walk: interrupted; nothing written", file=sys.stderr)
        return 130
    except (ValueError, RuntimeError) as exc:
        if bar:
            bar.close()
        print(f"rig walk: {exc}", file=sys.stderr)
        return 2
    finally:
        if bar:
            bar.close()
    took = time.perf_counter() - t0
    print(look_table(result, args.method))
    rows = method_summary(result)
    print()
    print(summary_text(result, rows))
    print(f"({took:.1f} s in all, rendering included)")
    doc = walk_json(result, label, rows)
    from model.symbolic import ply_text
    from .pictures import save_png
    from .walkpictures import error_plot, walk_map
    full = dict(doc)
    full["model_tables"] = result.model.to_json()
    out.mkdir(parents=True, exist_ok=True)
    images = {"map.png": walk_map(room, result, args.method),
              "errors.png": error_plot(result)}
    texts = {"model.json": json.dumps(full, indent=1) + "\n",
             "model.ply": ply_text(result.model)}
    from .scan import write_atomic
    written = [write_atomic(out / name, text) for name, text in texts.items()]
    written += [save_png(out / name, img) for name, img in images.items()]
    if args.json:
        written.append(write_atomic(args.json, json.dumps(doc, indent=1) + "\n"))
    print("wrote: " + ", ".join(str(p) for p in written))
    return 0


def _column_error(text: str) -> float:
    """--column-error: a positive number of pixels, or 'calibrated'."""
    from model.edges import CALIBRATED_COLUMN_ERROR_PX
    if text == "calibrated":
        return CALIBRATED_COLUMN_ERROR_PX
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not np.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text!r}: a positive number of pixels or 'calibrated'")
    return value


def _sigma_floor(measured_name: str, flag: str):
    """The parser of a --*-floor option: 'measured' (the constant
    ``model.mapping.<measured_name>``) or two numbers FT,DEG, not negative."""
    def parse(text: str) -> tuple[float, float]:
        if text == "measured":
            import model.mapping
            return getattr(model.mapping, measured_name)
        try:
            ft, deg = (float(v) for v in text.split(","))
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: 'measured' or FT,DEG (two numbers)")
        if not (np.isfinite(ft) and np.isfinite(deg) and ft >= 0 and deg >= 0):
            raise argparse.ArgumentTypeError(f"{text!r}: FT and DEG must be finite and not "
                                             "negative")
        return (ft, deg)
    parse.__name__ = flag             # argparse names the option's type in its errors
    return parse


_pose_floor = _sigma_floor("MEASURED_POSE_SIGMA_FLOOR", "pose floor")
_tilt_floor = _sigma_floor("MEASURED_TILT_SIGMA_FLOOR", "tilt floor")


FEATURE_GATE_DEFAULT = FEATURE_GATE_CHI2


def _feature_gate(text: str) -> float:
    """--feature-gate: a positive chi-square bound."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not np.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"{text!r}: a positive chi-square bound")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: a whole number of looks, at least 1")
    return value


def _confirm_looks(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 2:
        raise argparse.ArgumentTypeError(f"{text!r}: a whole number of consistent looks, at "
                                         "least 2 (one look confirms nothing)")
    return value


def add_parser(sub) -> argparse.ArgumentParser:
    w = sub.add_parser(
        "walk", help="walk a room: many looks, one model, where the camera is",
        description="The robot walks a simulated room on the 1985 eyes: every look is "
                    "rendered, scanned by the rig, matched to the model, the camera is "
                    "located by each method on the same correspondences, and the model "
                    "improves by the static Kalman update.  Methods: "
                    + "; ".join(f"{m}: {METHOD_NOTES[m]}" for m in ALL_METHODS) + ".",
    )
    w.add_argument("--walk", metavar="FILE",
                   help="walk CSV (header x,z,heading_deg,pitch_deg,roll_deg); default: the "
                        "bundled walk (or a generated one with --room)")
    w.add_argument("--room", type=int, metavar="SEED",
                   help="a generated room (and, without --walk, a generated walk) instead of "
                        "the bundled lab")
    w.add_argument("--looks", type=int, metavar="N", help="only the first N looks "
                   f"(a generated walk has {DEFAULT_ROOM_LOOKS} by default)")
    w.add_argument("--method", choices=ESTIMATORS, default="robust",
                   help="the method whose pose updates the model (default robust)")
    w.add_argument("--methods", nargs="+", choices=ESTIMATORS, metavar="NAME",
                   help="methods to compare on the same correspondences (default all: "
                        + ", ".join(ESTIMATORS) + ")")
    w.add_argument("--kalman", choices=("a30", "a29", "ci", "joint"), default="a30",
                   help="a30: camera error ignored, as written (default); a29: propagated; "
                        "ci: propagated and fused by covariance intersection (looks' errors "
                        "correlated); joint: one EKF over the floor pose and every feature "
                        "with their cross-covariances (model.joint), the same pairs used")
    w.add_argument("--column-error", type=_column_error, default=0.5, metavar="PX",
                   help="the column location bound of A-17 (two sigma), px: 0.5 is LCSL's "
                        "ELMAX, as written (default); 'calibrated' = 2.0, measured against the "
                        "world's true corners (docs/model.md)")
    w.add_argument("--pose-floor", type=_pose_floor, default=None, metavar="FT,DEG",
                   help="with --kalman a29 or ci: the least sigma of the camera's floor "
                        "position (ft) and heading (degrees) carried into the features; "
                        "'measured' = 0.13,0.85, the driving pose's measured error "
                        "(docs/model.md); default: the pose's own covariance")
    w.add_argument("--feature-gate", type=_feature_gate, nargs="?", const=FEATURE_GATE_DEFAULT,
                   default=None, metavar="CHI2",
                   help="the feature gate (off by default, as written): a matched observation "
                        "whose innovation is outside this chi-square bound of the feature's "
                        "and its own covariance is not fused but starts its own feature; a "
                        "feature contradicted as often as confirmed (twice at least) leaves "
                        f"the model (CHI2 default {FEATURE_GATE_DEFAULT:g}, 99.9 %%)")
    w.add_argument("--retire-unseen", type=_positive_int, default=None, metavar="N",
                   help="a vertex that N looks per look it was seen in predicted well inside "
                        "their view, and did not see, leaves the model (off by default: the "
                        "model remembers everything, as written)")
    w.add_argument("--consider", choices=("bound", "joseph"), default=None,
                   help="with --kalman a30, a29 or joint: every feature also carries the "
                        "consider covariance of its mean under the measured errors (calibrated "
                        "column error, measured disparity and row errors; a30/a29: the measured "
                        "pose floor), reported and scored but not used for matching, gating or "
                        "the pose; bound: holds whatever the looks' correlation; joseph: for "
                        "independent looks (off by default; with joint it doubles the dense "
                        "covariance work)")
    w.add_argument("--tilt-floor", type=_tilt_floor, default=None, metavar="FT,DEG",
                   help="with --consider: the least sigma of the camera's height (ft) and tilt "
                        "(degrees about each horizontal axis) in the consider covariance's "
                        "camera term; 'measured' = 0.32,3.2, the driving pose's measured error "
                        "(docs/model.md); default: the pose's own covariance")
    w.add_argument("--variance-factor", action="store_true",
                   help="scale every feature's reported covariance (the consider covariance "
                        "where kept) by the a-posteriori variance factor of its innovations, "
                        "pooled with a robust global one, never below 1; scoring and reports "
                        "only: the means, the matcher and the pose are untouched (off by default)")
    w.add_argument("--confirm", type=_confirm_looks, nargs="?", const=2, default=None,
                   metavar="M",
                   help="track confirmation: a feature with M consistent looks (its first "
                        "included; innovation inside chi-square 99 %%) and no more looks that "
                        "missed it is CONFIRMED, the others TENTATIVE: both kept and matched, "
                        "scored and reported apart (M default 2; off by default)")
    w.add_argument("--ambiguity-gate", choices=("drop", "track", "resolve"), default=None,
                   help="a vertical edge whose picture patch fits another disparity as well as "
                        "the rig's (a periodic texture matched a period off: checks, stripes) "
                        "is ambiguous: 'drop' leaves its vertices out of that look; 'track' "
                        "lets them match features the model holds (the prediction picks the "
                        "period) but start none; 'resolve' locates the edge at the other "
                        "period the model predicts (Chapter III), and where it predicts none "
                        "starts a feature only where two looks agree (off by default)")
    w.add_argument("--match", choices=("1985", "improved"), default="1985",
                   help="the rig's stereo matcher: 1985 (default, ESTAR's own lists) or "
                        "improved (the matching package's, where installed)")
    w.add_argument("--line-step", type=int, default=2, metavar="N",
                   help="scan every N-th line of 8..112 (default 2: half the scan time; "
                        "1 scans every line)")
    w.add_argument("--max-range", type=float, default=15.0, metavar="FT",
                   help="vertices farther than this are not used (default 15 ft, the range "
                        "Chapter V found the rig fairly accurate within)")
    w.add_argument("--shape-bits", type=int, default=64, metavar="N",
                   help="matching's shape gate: corner maps (Appendix B) differing in more "
                        "than N of 256 bits do not match (default 64; -1: no shape gate)")
    w.add_argument("--interval", type=float, default=1.0, metavar="S",
                   help="seconds between looks, for the velocity (default 1)")
    w.add_argument("--odometry-seed", type=int, default=1985, metavar="SEED")
    w.add_argument("--render-seed", type=int, default=1985, metavar="SEED",
                   help="sensor-noise seed of look 0 (look k uses SEED + k)")
    w.add_argument("--out", default="out/walk", help="where the model and pictures go "
                                                     "(default out/walk)")
    w.add_argument("--json", metavar="FILE", help="machine-readable summary (see rig/walk.py)")
    w.add_argument("--quiet", action="store_true", help="no progress bar")
    w.set_defaults(func=cmd_walk)
    return w
