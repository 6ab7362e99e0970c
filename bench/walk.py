"""Walk benchmark: the robot's model of its world, every pose method
side by side on the same correspondences.

Sets: the bundled walk through the bundled lab, and generated rooms (seeds
1..N, each with its generated walk).  For each set and method: median and
worst camera position error (ft, on the floor) and heading error (degrees)
over looks 1.. (look 0 is the given start); looks the method fixed; then
feature RMS error against the number of looks a feature was seen in (all
features, and the same features after their 1st and 10th look), the share of
truths inside each feature's 2-sigma ellipsoid (the 3-D region holding
95.45 %), the share of wrong correspondences, and the time per look (scan +
grouping + matching + the driving method + the Kalman update, rendering not
included).  The bundled walk is also run with the A-29 Kalman alternative,
with covariance intersection, with every line scanned, without the 15 ft
range limit and without the shape gate; the bundled walk and the rooms again
with the honest-covariance options: the calibrated column error
(``--column-error calibrated``) and the measured pose floor (``--pose-floor
measured``) under A-29 and covariance intersection, the consider covariance
(``--consider``), with the measured height and tilt floor (``--tilt-floor``), the
variance factor (``--variance-factor``), track confirmation (``--confirm``:
the track-confirmed and the tentative features' shares inside 2 sigma apart) and
the ambiguity gate (``--ambiguity-gate drop|track|resolve``).

``--calibrate`` measures instead the rig's pixel errors at the true corners
(every 3rd look of the bundled walk and of the rooms' walks): the vertex
column and disparity against the true corner's projection, the numbers
behind ``model.edges.CALIBRATED_COLUMN_ERROR_PX``; and the robot's pose error
on the bundled walk against its own covariance, the numbers behind
``model.mapping.MEASURED_POSE_SIGMA_FLOOR`` and ``MEASURED_TILT_SIGMA_FLOOR``.

``--breakdown`` runs only the configuration measured against the issue's targets
and groups its truths' Mahalanobis distances (by looks seen, range, confirmation).

``--outside`` reads every truth outside 2 sigma of that configuration (and of it with the
ambiguity gate) against the world's exact geometry: a wrong stereo match or the scorer's
truth (``outside_evidence``).

``--ten-looks`` follows the features behind the ten-look target: for the named configuration
and it with ``--ambiguity-gate resolve``, every truth either run follows for ten looks, with
each run's features on it (first look, looks, error after the 1st and the 10th), and how far
leaving out one feature moves the ratio (``ten_look_census``, ``ten_look_ratio``).

``--seeds N`` runs the same two on the bundled walk with N draws of its odometry and render
noise (seeds 1985, 1986, ...): the five targets' figures per draw, and how many draws meet each;
with ``--joint`` instead the joint filter of pose and features (``--kalman joint``, model.joint)
with confirmation, and with the resolve gate (``--consider MODE``: with the joint consider
covariance; ``--resolve-only``: the resolve configurations alone).

Run:  python bench/walk.py [--rooms 10] [--looks 20] [--json FILE]
                           [--calibrate | --breakdown | --outside | --ten-looks |
                            --seeds N [--joint [--consider M] [--resolve-only]]]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from model.edges import CALIBRATED_COLUMN_ERROR_PX, E_LR  # noqa: E402
from model.geometry import wrap_deg  # noqa: E402
from model.mapping import (CHI2_3DOF_2SIGMA, FEATURE_GATE_CHI2, MEASURED_POSE_SIGMA_FLOOR,  # noqa: E402
                           MEASURED_TILT_SIGMA_FLOOR, WalkConfig, run_walk)
from rig.walk import ALL_METHODS  # noqa: E402
from world.odometry import OdometryNoise, dead_reckon  # noqa: E402
from world.render import render_look  # noqa: E402
from world.room import bundled_lab, generate_room  # noqa: E402
from world.walk import bundled_walk, generate_walk  # noqa: E402


def one_walk(room, poses, kalman="a30", seed=1985, line_step=2, max_range=15.0, shape=64,
             column_error=E_LR, pose_floor=None, keep_looks=None, **named):
    """One walk; ``named``: more WalkConfig options (consider, feature_gate, retire_unseen,
    match).  ``keep_looks``: a list that receives every rendered look (its truth)."""
    dr = dead_reckon(poses, OdometryNoise(seed=seed))

    def render(r, p, k):
        look = render_look(r, p, seed=seed + k)
        if keep_looks is not None:
            keep_looks.append(look)
        return look
    t0 = time.perf_counter()
    res = run_walk(room, poses, dr, render,
                   WalkConfig(kalman=kalman, lines=tuple(range(8, 113, line_step)),
                              max_range_ft=max_range, shape_max_bits=shape,
                              column_error_px=column_error, pose_sigma_floor=pose_floor,
                              **named))
    return res, time.perf_counter() - t0


def pixel_errors(room, poses, seed=1985, every=3, max_range=15.0) -> np.ndarray:
    """(column error, disparity error, row error) in px of every vertex observation the
    world's truth snaps to a true corner: observed minus the corner's true projection into
    the left camera (the same scan, grouping and snapping as the walk)."""
    from eyes import scan_pair
    from model.edges import Camera, group_vertical_edges, vertex_observations
    from model.geometry import camera_points, left_centre
    from model.mapping import observed_truth, truth_points
    cam, corners, lines = Camera(), truth_points(room), list(range(8, 113, 2))
    out = []
    for k, pose in enumerate(poses):
        if k % every:
            continue
        look = render_look(room, pose, seed=seed + k)
        scan = scan_pair(look.left_bi, look.right_bi, lines, "0.75", "180")
        edges = group_vertical_edges(scan.points, lines, look.left_bi, cam,
                                     right_picture=look.right_bi)
        obs = [o for o in vertex_observations(edges) if o.q[0] <= max_range]
        R = np.asarray(pose.rotation(), float)
        tl = left_centre((pose.x, getattr(pose, "y", 0.0), pose.z), R)
        _, tid = observed_truth(obs, np.asarray(look.range_left, float), tl, R, corners, cam)
        for o, j in zip(obs, tid):
            if j >= 0:
                p, x, y = camera_points(R, tl, corners[j][None])[0]
                out.append((o.col - (cam.centre_col + cam.dv * x / p),
                            o.disparity - cam.ds * cam.dv / p,
                            o.row - (cam.centre_row + cam.dv * y / p)))
    return np.array(out).reshape(-1, 3)


def calibrate(rooms: int, looks: int) -> str:
    lab = bundled_lab()
    sets = [("bundled walk", pixel_errors(lab, bundled_walk()))]
    sets.append((f"{rooms} generated rooms", np.concatenate(
        [pixel_errors(generate_room(s), generate_walk(generate_room(s), s, looks))
         for s in range(1, rooms + 1)])))
    rows = ["| set | quantity | corners | mean px | sd px | 68.3 % of abs within px | "
            "95.4 % within px | LCSL's sigma px |", "|---|---|---|---|---|---|---|---|"]
    for name, a in sets:
        for i, (what, lcsl) in enumerate((("column", E_LR / 2), ("disparity", E_LR),
                                         ("row", None))):
            e = a[:, i]
            rows.append(f"| {name} | {what} | {len(e)} | {e.mean():.2f} | {e.std():.2f} | "
                        f"{np.percentile(np.abs(e), 68.27):.2f} | "
                        f"{np.percentile(np.abs(e), 95.45):.2f} | {fmt(lcsl)} |")
    rows += ["", "| walk (fused pose) | looks | median position error ft | its claimed sigma ft "
             "(median, per axis) | median heading error deg | its claimed sigma deg | "
             "true pose inside its 95 % region |", "|---|---|---|---|---|---|---|"]
    tilt_rows = ["", "| walk (fused pose) | looks fused | median height error ft | as a sigma "
                 "(median / 0.674) ft | height 95.4 % point ft | median tilt error deg "
                 "(both horizontal axes) | as a sigma (median / 1.177) deg | its claimed "
                 "sigma deg (median) |", "|---|---|---|---|---|---|---|---|"]
    for name, kw in (("bundled, A-29", dict(kalman="a29")),
                     ("bundled, A-30 (as written)", dict(kalman="a30"))):
        res, _ = one_walk(lab, bundled_walk(), **kw)
        rows.append(pose_honesty_row(name, res))
        tilt_rows.append(tilt_honesty_row(name, res))
    return "\n".join(rows + tilt_rows)


def tilt_honesty_row(name, res) -> str:
    """The fused pose's height and tilt (the fix's alone: the odometry knows neither)
    against the truth, the numbers behind ``model.mapping.MEASURED_TILT_SIGMA_FLOOR``."""
    from scipy.spatial.transform import Rotation
    height, tilt, claimed = [], [], []
    for r in res.records[1:]:
        if r.pose is None or r.pose.method != "fused":
            continue
        t = r.true_pose
        R_true = np.asarray(t.rotation(), float)
        err = np.degrees(Rotation.from_matrix(r.pose.R @ R_true.T).as_rotvec())
        height.append(abs(r.pose.centre[1] - getattr(t, "y", 0.0)))
        tilt.append(np.hypot(err[0], err[2]))
        c = np.diag(r.pose.covariance6)
        claimed.append(np.degrees(np.sqrt((c[3] + c[5]) / 2)))
    return (f"| {name} | {len(height)} | {np.median(height):.3f} | {np.median(height) / 0.6745:.2f} | "
            f"{np.percentile(height, 95.45):.2f} | {np.median(tilt):.2f} | "
            f"{np.median(tilt) / 1.1774:.2f} | {np.median(claimed):.2f} |")


def method_errors(results) -> dict:
    out = {}
    for m in ALL_METHODS:
        errs, looks = [], 0
        for res in results:
            for r in res.records[1:]:
                looks += 1
                e = r.errors(m)
                if e is not None:
                    errs.append(e)
        a = np.array(errs).reshape(-1, 2)
        out[m] = {"fixed": len(a), "looks": looks,
                  "median_pos": float(np.median(a[:, 0])) if len(a) else None,
                  "worst_pos": float(a[:, 0].max()) if len(a) else None,
                  "median_head": float(np.median(a[:, 1])) if len(a) else None,
                  "worst_head": float(a[:, 1].max()) if len(a) else None}
    return out


def feature_stats(results) -> dict:
    hist = [h for res in results for h in res.error_history.values()]
    curve = []
    for n in (1, 2, 3, 5, 10, 15, 20):
        e = [h[n - 1] for h in hist if len(h) >= n]
        if e:
            curve.append({"looks": n, "features": len(e), "rms": float(np.sqrt(np.mean(np.square(e)))),
                          "median": float(np.median(e))})
    same = [h for h in hist if len(h) >= 10]
    first = float(np.sqrt(np.mean([h[0] ** 2 for h in same]))) if same else None
    tenth = float(np.sqrt(np.mean([h[9] ** 2 for h in same]))) if same else None
    same5 = [h for h in hist if len(h) >= 5]
    rms5 = ([float(np.sqrt(np.mean([h[k] ** 2 for h in same5]))) for k in (0, 4)]
            if same5 else [None, None])
    inside, scored, feats, conf_in, conf, filt, retired = [], 0, 0, [], 0, [], 0
    track = {"track_confirmed": [0, 0.0], "tentative": [0, 0.0]}     # n, n inside
    retired_wrong = 0
    for res in results:
        fs = res.feature_scores()
        feats += fs["features"]
        retired += len(res.model.retired)
        retired_wrong += sum(1 for v in res.model.retired.values() if v.truth is not None
                             and np.linalg.norm(v.mean - v.truth) > WRONG_FEATURE_FT)
        if fs["scored"]:
            scored += fs["scored"]
            inside.append(fs["inside_2sigma"] * fs["scored"])
            filt.append(fs["filter_inside_2sigma"] * fs["scored"])
        for k in track:
            if fs.get(k):
                track[k][0] += fs[k]
                track[k][1] += fs[f"{k}_inside_2sigma"] * fs[k]
        if fs["confirmed"]:
            conf += fs["confirmed"]
            conf_in.append(fs["confirmed_inside_2sigma"] * fs["confirmed"])
    matched = sum(r.matched for res in results for r in res.records)
    wrong = sum(r.wrong for res in results for r in res.records)
    used = sum(r.used for res in results for r in res.records)
    used_wrong = sum(r.used_wrong for res in results for r in res.records)
    look_ms = [r.times_ms["look"] for res in results for r in res.records[1:]]
    scan_ms = [r.times_ms["scan"] for res in results for r in res.records[1:]]
    return {"curve": curve, "same_features": len(same), "same_rms_1": first, "same_rms_10": tenth,
            "same5_features": len(same5), "same5_rms_1": rms5[0], "same5_rms_5": rms5[1],
            "inside_2sigma": sum(inside) / scored if scored else None, "features": feats,
            "filter_inside_2sigma": sum(filt) / scored if scored else None,
            "consider": results[0].config.consider, "retired": retired,
            "retired_wrong": retired_wrong,
            "confirmed": conf, "confirmed_inside_2sigma": sum(conf_in) / conf if conf else None,
            "confirm": results[0].config.confirm,
            **{k: n for k, (n, _) in track.items()},
            **{f"{k}_inside_2sigma": (i / n if n else None) for k, (n, i) in track.items()},
            "wrong_share": wrong / matched if matched else None,
            "used_wrong_share": used_wrong / used if used else None,
            "median_look_ms": float(np.median(look_ms)), "median_scan_ms": float(np.median(scan_ms)),
            "p90_look_ms": float(np.percentile(look_ms, 90))}


WRONG_FEATURE_FT = 0.5    # a retired vertex farther than this from its truth was a wrong one


def fmt(v, p=2):
    return "-" if v is None else f"{v:.{p}f}"


def method_table(title, errs) -> str:
    rows = [f"**{title}**", "",
            "| method | looks fixed | median position ft | worst position ft | median heading deg "
            "| worst heading deg |", "|---|---|---|---|---|---|"]
    for m, e in errs.items():
        rows.append(f"| `{m}` | {e['fixed']}/{e['looks']} | {fmt(e['median_pos'])} | "
                    f"{fmt(e['worst_pos'])} | {fmt(e['median_head'], 1)} | {fmt(e['worst_head'], 1)} |")
    return "\n".join(rows)


def feature_table(sets) -> str:
    rows = ["| set | features | RMS ft after 1 / 2 / 3 / 5 / 10 looks (features) | same features: "
            "RMS after 1st -> 10th look; 1st -> 5th | inside 2 sigma (all; confirmed) [the filter's own] | "
            "track-confirmed; tentative: inside 2 sigma (features) | "
            "retired (of them > 0.5 ft off) | wrong corr. (all / used) | ms per look "
            "(median, p90; scan) |", "|---|---|---|---|---|---|---|---|---|"]
    for name, f in sets:
        curve = " / ".join(f"{c['rms']:.2f} ({c['features']})" for c in f["curve"]
                           if c["looks"] in (1, 2, 3, 5, 10))
        same = (f"{fmt(f['same_rms_1'])} -> {fmt(f['same_rms_10'])} ({f['same_features']})"
                if f["same_features"] else "-")
        same += (f"; 1st -> 5th: {fmt(f['same5_rms_1'])} -> {fmt(f['same5_rms_5'])} "
                 f"({f['same5_features']})" if f["same5_features"] else "")
        rows.append(f"| {name} | {f['features']} | {curve} | {same} | "
                    f"{100 * (f['inside_2sigma'] or 0):.1f} %; {100 * (f['confirmed_inside_2sigma'] or 0):.1f} % ({f['confirmed']})"
                    + (f" [{100 * (f['filter_inside_2sigma'] or 0):.0f} %]" if f["consider"] else "")
                    + (f" | {100 * (f['track_confirmed_inside_2sigma'] or 0):.1f} % "
                       f"({f['track_confirmed']}); {100 * (f['tentative_inside_2sigma'] or 0):.1f} % "
                       f"({f['tentative']})" if f["confirm"] else " | -")
                    + f" | {f['retired']} ({f['retired_wrong']}) | {100 * (f['wrong_share'] or 0):.0f} % / "
                    f"{100 * (f['used_wrong_share'] or 0):.0f} % | {f['median_look_ms']:.0f}, "
                    f"{f['p90_look_ms']:.0f}; {f['median_scan_ms']:.0f} |")
    return "\n".join(rows)


def pose_honesty_row(name, res) -> str:
    """Is the robot's pose covariance honest?  Its error against its own claim, look by look."""
    err, pos_sd, head, head_sd, inside = [], [], [], [], []
    for r in res.records[1:]:
        P, t, e = r.pose_covariance, r.true_pose, r.estimates["fused"]
        d = np.array([e[0] - t.x, e[1] - t.z, np.radians(wrap_deg(e[2] - t.heading_deg))])
        err.append(np.hypot(d[0], d[1]))
        head.append(np.degrees(abs(d[2])))
        pos_sd.append(np.sqrt((P[0, 0] + P[1, 1]) / 2))
        head_sd.append(np.degrees(np.sqrt(P[2, 2])))
        inside.append(d @ np.linalg.solve(P, d) <= 7.815)      # chi-square 95 %, 3 dof
    return (f"| {name} | {len(err)} | {np.median(err):.3f} | {np.median(pos_sd):.3f} | "
            f"{np.median(head):.2f} | {np.median(head_sd):.2f} | {100 * np.mean(inside):.0f} % |")


def honest_table(rows) -> str:
    out = ["| set | fused median / worst position ft | fused median / worst heading deg |",
           "|---|---|---|"]
    for name, e in rows:
        out.append(f"| {name} | {fmt(e['median_pos'])} / {fmt(e['worst_pos'])} | "
                   f"{fmt(e['median_head'], 1)} / {fmt(e['worst_head'], 1)} |")
    return "\n".join(out)


NAMED = dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR, confirm=2)
"""The configuration docs/model.md measures against the issue's targets."""


def mahalanobis_rows(name, results) -> list[str]:
    """Where the truths outside 2 sigma are: the share inside, and beyond Mahalanobis
    distance 10, by the looks a feature was seen in, by its range at its first look and by
    track confirmation; the reported covariance (the consider covariance where kept)."""
    rows = []
    feats = []
    for res in results:
        for v in res.model.vertices.values():
            if v.truth is None:
                continue
            d = v.mean - v.truth
            m = float(np.sqrt(d @ np.linalg.solve(res.reported_covariance(v), d)))
            t = res.records[v.first_look].true_pose
            rng = float(np.hypot(v.truth[0] - t.x, v.truth[2] - t.z))
            conf = res.confirmed_by_track(v) if res.config.confirm else None
            feats.append((m, v.looks, rng, conf))
    m = np.array([f[0] for f in feats])
    looks = np.array([f[1] for f in feats])
    rng = np.array([f[2] for f in feats])
    groups = [("seen once", looks == 1), ("seen twice", looks == 2),
              ("seen 3-4 times", (looks >= 3) & (looks <= 4)),
              ("seen 5-9 times", (looks >= 5) & (looks <= 9)), ("seen 10+ times", looks >= 10),
              ("first seen at 0-5 ft", rng < 5), ("first seen at 5-10 ft", (rng >= 5) & (rng < 10)),
              ("first seen at 10-15 ft", rng >= 10)]
    if feats and feats[0][3] is not None:
        conf = np.array([f[3] for f in feats], bool)
        groups += [("track-confirmed", conf), ("tentative", ~conf)]
    for label, sel in [("all", np.ones(len(m), bool)), *groups]:
        if sel.any():
            rows.append(f"| {name} | {label} | {int(sel.sum())} | "
                        f"{100 * np.mean(m[sel] <= np.sqrt(8.0249)):.1f} % | "
                        f"{100 * np.mean(m[sel] > 10):.1f} % | {np.median(m[sel]):.2f} |")
    return rows


def breakdown(rooms: int, looks: int) -> str:
    """``--breakdown``: the named configuration on the bundled walk and the rooms, its
    truths' Mahalanobis distances grouped."""
    out = ["| set | features | n | inside 2 sigma | beyond Mahalanobis 10 | median distance |",
           "|---|---|---|---|---|---|"]
    res, _ = one_walk(bundled_lab(), bundled_walk(), **NAMED)
    out += mahalanobis_rows("bundled", [res])
    rs = [one_walk(generate_room(s), generate_walk(generate_room(s), s, looks), **NAMED)[0]
          for s in range(1, rooms + 1)]
    out += mahalanobis_rows(f"{rooms} rooms", rs)
    return "\n".join(out)


def _on_surface(origin, R, col, row, quad):
    """The point of ``quad``'s plane seen through continuous pixel (col, row) of a camera at
    ``origin`` with rotation R (world.render's pinhole: principal point (64, 60), 180 px)."""
    d = R @ np.array([(col - 64.0) / 180.0, (row - 60.0) / 180.0, 1.0])
    return origin + (quad.c - origin[quad.axis]) / d[quad.axis] * d


def outside_evidence(res, looks) -> list[dict]:
    """Every feature whose truth is outside its 2-sigma ellipsoid, read against the world's
    exact geometry at its first observation: the true disparity at the pixel the rig named
    (the renderer's range) against the rig's, whether the scorer's window (the named column
    and one either side, on the line that saw it) straddles an occluding edge (a range jump of
    more than 0.5 ft) and if so which side the feature lies on, and, for a wrong stereo match,
    how far along the named surface the right camera's partner pixel looks from the left's
    (a whole period of the surface's texture: the "picket fence")."""
    out = []
    for v in res.model.vertices.values():
        if v.truth is None or v.seen_at is None:
            continue
        d = v.mean - v.truth
        m = float(np.sqrt(d @ np.linalg.solve(res.reported_covariance(v), d)))
        if m <= np.sqrt(CHI2_3DOF_2SIGMA):
            continue
        look = looks[v.first_look]
        col, row, line, disp = v.seen_at
        h, w = look.range_left.shape
        r = int(np.clip(line if line >= 0 else np.floor(row), 0, h - 1))
        c = int(np.clip(np.floor(col), 0, w - 1))
        window = look.range_left[r, max(c - 1, 0):c + 2].astype(float)
        quad = look.room.quads[int(look.surface_left[r, c])]
        R = look.pose.rotation()
        left = look.pose.camera_centre("left")
        true_disp = 0.75 * 180.0 / float(look.range_left[r, c])
        z_feature = float((R.T @ (v.mean - left))[2])
        occluding = float(window.max() - window.min()) > 0.5
        side = None
        if occluding:
            side = ("far" if abs(z_feature - window.max()) < abs(z_feature - window.min())
                    else "near")
        pl = _on_surface(left, R, col, row, quad)
        pr = _on_surface(look.pose.camera_centre("right"), R, col - disp, row, quad)
        t = res.records[v.first_look].true_pose
        out.append({"vertex": v.id, "look": v.first_look, "looks": v.looks, "surface": quad.name,
                    "mahalanobis": m, "disparity": disp, "true_disparity": true_disp,
                    "wrong_match": abs(disp - true_disp) > 1.5, "occluding": occluding,
                    "side": side, "feature_range": z_feature,
                    "truth_z": float((R.T @ (v.truth - left))[2]),
                    "truth_range": float(np.hypot(v.truth[0] - t.x, v.truth[2] - t.z)),
                    "shift_ft": float(np.linalg.norm(pr - pl))})
    return out


def outside_tables(sets, near=None) -> str:
    """``--outside``: the census of every set, and the rows of the features whose truth was
    within 5 ft of the camera in the sets named in ``near`` (default: all)."""
    out = ["| set | outside 2 sigma | wrong stereo match (disparity off by > 1.5 px) | "
           "right match | scorer window on an occluding edge | of those, the feature on the "
           "far side |", "|---|---|---|---|---|---|"]
    for name, ev in sets:
        wrong = sum(e["wrong_match"] for e in ev)
        occl = [e for e in ev if e["occluding"]]
        out.append(f"| {name} | {len(ev)} | {wrong} | {len(ev) - wrong} | {len(occl)} | "
                   f"{sum(e['side'] == 'far' for e in occl)} |")
    out += ["", "| set | vertex | first look | looks | surface | disparity rig / true px | "
            "feature / truth range ft (along the camera's axis) | right partner's shift along the surface ft | "
            "occluding edge in the window |", "|---|---|---|---|---|---|---|---|---|"]
    for name, ev in sets:
        if near is not None and name not in near:
            continue
        for e in sorted(ev, key=lambda e: e["vertex"]):
            if e["truth_range"] < 5:
                out.append(f"| {name} | {e['vertex']} | {e['look']} | {e['looks']} | "
                           f"{e['surface']} | {e['disparity']:.1f} / {e['true_disparity']:.1f} | "
                           f"{e['feature_range']:.2f} / {e['truth_z']:.2f} | "
                           f"{e['shift_ft']:.2f} | {'yes' if e['occluding'] else 'no'} |")
    return "\n".join(out)


def outside(rooms: int, looks: int) -> str:
    """The named configuration, and it with the ambiguity gate ("track"), on the bundled walk
    and the rooms."""
    sets = []
    for label, named in (("", NAMED), (", ambiguity gate track",
                                       dict(NAMED, ambiguity_gate="track"))):
        seen: list = []
        res, _ = one_walk(bundled_lab(), bundled_walk(), keep_looks=seen, **named)
        sets.append((f"bundled{label}", outside_evidence(res, seen)))
        ev = []
        for s in range(1, rooms + 1):
            seen = []
            room = generate_room(s)
            r, _ = one_walk(room, generate_walk(room, s, looks), keep_looks=seen, **named)
            ev += outside_evidence(r, seen)
        if rooms:
            sets.append((f"{rooms} rooms{label}", ev))
    return outside_tables(sets, near=("bundled", f"{rooms} rooms"))


def truth_key(v) -> tuple:
    """Which truth a vertex stands for: its true corner's index, else its true point to
    0.1 ft (a point along an edge); features of two runs with one key are the same truth."""
    if v.truth_id >= 0:
        return ("corner", int(v.truth_id))
    return ("point", *(round(float(x), 1) for x in v.truth))


def ten_look_ratio(hist) -> dict:
    """The ten-look target's figure on error histories (one list per feature, its error
    after each look): RMS after the 1st and the 10th look over the features seen ten
    times, their ratio, and the ratio with each feature left out in turn (its least and
    greatest: how much one feature moves it)."""
    same = [np.asarray(h[:10], float) for h in hist if len(h) >= 10]
    if not same:
        return {"features": 0, "rms_1": None, "rms_10": None, "ratio": None,
                "leave_one_out": (None, None)}
    a = np.array(same)
    s1, s10 = np.square(a[:, 0]), np.square(a[:, 9])
    out = {"features": len(a), "rms_1": float(np.sqrt(s1.mean())),
           "rms_10": float(np.sqrt(s10.mean()))}
    out["ratio"] = out["rms_10"] / out["rms_1"]
    if len(a) > 1:
        loo = [np.sqrt((s10.sum() - s10[i]) / (s1.sum() - s1[i])) for i in range(len(a))]
        out["leave_one_out"] = (float(min(loo)), float(max(loo)))
    else:
        out["leave_one_out"] = (None, None)
    return out


def ten_look_census(results: dict) -> list[dict]:
    """Every truth some feature of some run followed for ten looks or more, and what each
    run (``results``: name -> WalkResult) made of it: its features on that truth (first
    look, looks, error after the 1st and the 10th look, retired or not)."""
    per_run = {}
    for name, res in results.items():
        feats = {}
        every = {**res.model.vertices, **res.model.retired}
        for vid, h in res.error_history.items():
            v = every.get(vid)
            if v is None or v.truth is None:
                continue
            feats.setdefault(truth_key(v), []).append(
                {"vertex": vid, "first_look": v.first_look, "looks": len(h),
                 "error_1": h[0], "error_10": h[9] if len(h) >= 10 else None,
                 "retired": vid in res.model.retired})
        per_run[name] = feats
    keys = {k for feats in per_run.values() for k, fs in feats.items()
            if any(f["looks"] >= 10 for f in fs)}
    rows = []
    for k in sorted(keys, key=lambda k: (k[0], k[1:])):
        rows.append({"truth": k, **{name: sorted(per_run[name].get(k, []),
                                                  key=lambda f: (f["first_look"], f["vertex"]))
                                    for name in results}})
    return rows


def ten_look_tables(results: dict) -> str:
    """``--ten-looks``: the ten-look ratio of each run with its leave-one-out range, and the
    census of the truths followed ten times in any run."""
    names = list(results)
    out = ["| run | features seen 10 times | RMS after 1st -> 10th look ft | ratio | "
           "one feature left out: ratio from .. to |", "|---|---|---|---|---|"]
    for name, res in results.items():
        r = ten_look_ratio(list(res.error_history.values()))
        lo, hi = r["leave_one_out"]
        out.append(f"| {name} | {r['features']} | {fmt(r['rms_1'], 3)} -> {fmt(r['rms_10'], 3)} "
                   f"| {fmt(100 * r['ratio'] if r['ratio'] else None, 1)} % | "
                   f"{fmt(100 * lo if lo else None, 1)} % .. {fmt(100 * hi if hi else None, 1)} % |")

    def cell(fs):
        if not fs:
            return "none"
        return "; ".join(f"v{f['vertex']} from look {f['first_look']}, {f['looks']} looks, "
                         f"{f['error_1']:.2f}" + (f" -> {f['error_10']:.2f}" if f["error_10"]
                                                  is not None else "")
                         + (" (retired)" if f["retired"] else "") for f in fs)
    out += ["", "| truth | " + " | ".join(f"{n}: its features (first look, looks, error ft "
                                          "after the 1st -> 10th look)" for n in names) + " |",
            "|---|" + "---|" * len(names)]
    for row in ten_look_census(results):
        k = row["truth"]
        label = f"corner {k[1]}" if k[0] == "corner" else f"point ({k[1]}, {k[2]}, {k[3]})"
        out.append(f"| {label} | " + " | ".join(cell(row[n]) for n in names) + " |")
    return "\n".join(out)


def ten_looks(seed: int = 1985) -> str:
    """The named configuration and it with ``--ambiguity-gate resolve`` on the bundled walk:
    which truths each follows for ten looks."""
    results = {}
    for name, kw in (("named", NAMED), ("named + resolve", dict(NAMED, ambiguity_gate="resolve"))):
        results[name], _ = one_walk(bundled_lab(), bundled_walk(), seed=seed, **kw)
    return ten_look_tables(results)


def target_figures(res) -> dict:
    """The issue's five targets' figures for one walk: median fused position (ft) and
    heading (degrees) error, the ten-look ratio (:func:`ten_look_ratio`), the share of ALL
    features' truths inside 2 sigma, and the median time per look (ms)."""
    e = method_errors([res])["fused"]
    f = feature_stats([res])
    r = ten_look_ratio(list(res.error_history.values()))
    update = [r.times_ms["update"] for r in res.records]
    return {"position_ft": e["median_pos"], "heading_deg": e["median_head"],
            "update_ms": float(np.median(update)), "update_ms_last10": float(np.median(update[-10:])),
            "final_model": res.records[-1].model_size,
            "ten_look_features": r["features"], "ten_look_ratio": r["ratio"],
            "leave_one_out": r["leave_one_out"], "inside_2sigma": f["inside_2sigma"],
            "features": f["features"], "look_ms": f["median_look_ms"]}


SEED_CONFIGS = {"named": NAMED, "named + resolve": dict(NAMED, ambiguity_gate="resolve")}
"""The configurations ``--seeds`` draws the bundled walk's noise for."""
JOINT_CONFIGS = {"joint + confirm": dict(kalman="joint", confirm=2,
                                         column_error=CALIBRATED_COLUMN_ERROR_PX),
                 "joint + confirm + resolve": dict(kalman="joint", confirm=2,
                                                   column_error=CALIBRATED_COLUMN_ERROR_PX,
                                                   ambiguity_gate="resolve")}
"""``--seeds N --joint``: the joint filter of pose and features (model.joint), with the
calibrated column error (with LCSL's 0.5 px the filter believes its pairs too much and the
pose diverges: docs/model.md).  ``--consider MODE``: the same with the joint filter's consider
covariance (model.joint.consider_joint_update); its poses and means are the plain rows'."""


def joint_consider_configs(mode: str) -> dict:
    """JOINT_CONFIGS with the joint consider covariance ``mode`` (joseph or bound)."""
    return {f"{name} + consider {mode}": dict(kw, consider=mode)
            for name, kw in JOINT_CONFIGS.items()}


def resolve_configs(configs: dict) -> dict:
    """``--resolve-only``: only the configurations with the resolve gate."""
    return {name: kw for name, kw in configs.items() if kw.get("ambiguity_gate") == "resolve"}


def seed_tables(rows) -> str:
    """``--seeds``: one row per configuration and draw (``rows``: (name, seed, figures)),
    then per configuration how many draws meet each target and the medians."""
    # the model update's time (it grows with the joint filter's state) where the rows carry it
    update = all("update_ms" in f for _, _, f in rows)
    out = ["| configuration | odometry and render seed | median position ft | median heading deg | "
           "ten-look ratio (features; one left out: from .. to) | inside 2 sigma, all features | "
           "ms per look (median) |" + (" model update ms: median, last 10 looks (model size) |"
                                       if update else ""),
           "|---|---|---|---|---|---|---|" + ("---|" if update else "")]
    for name, seed, f in rows:
        lo, hi = f["leave_one_out"]
        ratio = (f"{100 * f['ten_look_ratio']:.1f} % ({f['ten_look_features']}; "
                 f"{fmt(100 * lo if lo else None, 1)} .. {fmt(100 * hi if hi else None, 1)} %)"
                 if f["ten_look_ratio"] is not None else "- (0)")
        out.append(f"| {name} | {seed} | {f['position_ft']:.2f} | {f['heading_deg']:.2f} | {ratio} "
                   f"| {100 * f['inside_2sigma']:.1f} % of {f['features']} | {f['look_ms']:.0f} |"
                   + (f" {f['update_ms']:.0f}, {f['update_ms_last10']:.0f} ({f['final_model']}) |"
                      if update else ""))
    out += ["", "| configuration | draws | position <= 0.25 ft | heading <= 1 deg | ten-look "
            "ratio <= 50 % | inside 2 sigma >= 90 % | all four | median ratio | median inside |",
            "|---|---|---|---|---|---|---|---|---|"]
    for name in dict.fromkeys(n for n, _, _ in rows):
        fs = [f for n, _, f in rows if n == name]
        ok = np.array([[f["position_ft"] <= 0.25, f["heading_deg"] <= 1.0,
                        f["ten_look_ratio"] is not None and f["ten_look_ratio"] <= 0.5,
                        f["inside_2sigma"] >= 0.9] for f in fs])
        ratios = [f["ten_look_ratio"] for f in fs if f["ten_look_ratio"] is not None]
        out.append(f"| {name} | {len(fs)} | " + " | ".join(str(int(c)) for c in ok.sum(axis=0))
                   + f" | {int(ok.all(axis=1).sum())} | "
                   f"{fmt(100 * np.median(ratios) if ratios else None, 1)} % | "
                   f"{100 * np.median([f['inside_2sigma'] for f in fs]):.1f} % |")
    return "\n".join(out)


def seeds(n: int, configs=None) -> str:
    """The bundled walk with ``n`` draws of its noise (odometry and render seeds 1985,
    1986, ...; 1985 is the walk every other figure uses) for each configuration."""
    rows = []
    configs = configs or SEED_CONFIGS
    # each draw through every configuration in turn: their times interleaved
    for seed in range(1985, 1985 + n):
        for name, kw in configs.items():
            res, took = one_walk(bundled_lab(), bundled_walk(), seed=seed, **kw)
            rows.append((name, seed, target_figures(res)))
            f = rows[-1][2]
            print(f"{name}, seed {seed}: {took:.0f} s; {f['position_ft']:.2f} ft, "
                  f"{f['heading_deg']:.2f} deg, inside {100 * f['inside_2sigma']:.1f} %, "
                  f"look {f['look_ms']:.0f} ms, load average {os.getloadavg()[0]:.1f}",
                  file=sys.stderr)
    order = list(configs)
    rows.sort(key=lambda row: (order.index(row[0]), row[1]))
    return seed_tables(rows)


def joint_rooms(n: int, looks: int, consider: str | None = None) -> str:
    """``--joint`` without ``--seeds``: the generated rooms 1..n for the named configuration with
    resolve and the joint filter's configurations (JOINT_CONFIGS): the fused pose's median and
    worst error, the share of truths inside 2 sigma (all features; the track-confirmed ones),
    the ten-look ratio over the rooms together and the median time per look."""
    configs = {"named + resolve": SEED_CONFIGS["named + resolve"],
               **(joint_consider_configs(consider) if consider else JOINT_CONFIGS)}
    results = {name: [] for name in configs}
    for seed in range(1, n + 1):
        room = generate_room(seed)
        walk = generate_walk(room, seed, looks)
        for name, kw in configs.items():
            res, took = one_walk(room, walk, **kw)
            results[name].append(res)
            print(f"room {seed}, {name}: {took:.0f} s", file=sys.stderr)
    out = ["| configuration | position ft median / worst | heading deg median / worst | inside 2 "
           "sigma, all (confirmed) | features seen 10 times: RMS 1st -> 10th look | ms per look "
           "(median) |", "|---|---|---|---|---|---|"]
    for name, rs in results.items():
        e = method_errors(rs)["fused"]
        f = feature_stats(rs)
        conf = f.get("track_confirmed_inside_2sigma")
        ten = (f"{f['same_rms_1']:.2f} -> {f['same_rms_10']:.2f} ({f['same_features']})"
               if f["same_features"] else "- (0)")
        out.append(f"| {name} | {e['median_pos']:.2f} / {e['worst_pos']:.2f} | "
                   f"{e['median_head']:.2f} / {e['worst_head']:.1f} | "
                   f"{100 * f['inside_2sigma']:.1f} % of {f['features']} "
                   f"({fmt(100 * conf if conf is not None else None, 1)} %) | {ten} | "
                   f"{f['median_look_ms']:.0f} |")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=10)
    ap.add_argument("--looks", type=int, default=20, help="looks per generated walk")
    ap.add_argument("--bundled-looks", type=int, default=None)
    ap.add_argument("--json", help="write all figures as JSON")
    ap.add_argument("--calibrate", action="store_true",
                    help="measure the rig's pixel errors at the true corners instead")
    ap.add_argument("--breakdown", action="store_true",
                    help="only the named configuration (A-29, consider bound, tilt floor, "
                         "confirm 2): where its truths outside 2 sigma are")
    ap.add_argument("--outside", action="store_true",
                    help="only the named configuration: its truths outside 2 sigma read "
                         "against the world's geometry (wrong stereo match or scorer)")
    ap.add_argument("--ten-looks", action="store_true",
                    help="only the named configuration and it with --ambiguity-gate resolve on "
                         "the bundled walk: the truths each follows for ten looks, and how much "
                         "one feature moves the ten-look ratio")
    ap.add_argument("--joint", action="store_true",
                    help="with --seeds: the joint filter of pose and features (--kalman joint) "
                         "with confirmation, and with the resolve gate, instead of the named "
                         "two (their rows are deterministic: docs/model.md); alone: those and "
                         "the named configuration with resolve in the generated rooms")
    ap.add_argument("--consider", choices=("joseph", "bound"), default=None,
                    help="with --joint: the joint filter's configurations with its consider "
                         "covariance (--kalman joint --consider MODE); the poses and means are "
                         "the plain ones, only the reported covariance differs")
    ap.add_argument("--resolve-only", action="store_true",
                    help="with --joint: only the joint configurations with the resolve gate")
    ap.add_argument("--seeds", type=int, metavar="N", default=None,
                    help="only the named configuration and it with --ambiguity-gate resolve on "
                         "the bundled walk, with N draws of the odometry and render noise: the "
                         "targets' figures per draw")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()

    def seed_report():
        joint = joint_consider_configs(args.consider) if args.consider else JOINT_CONFIGS
        joint = resolve_configs(joint) if args.resolve_only else joint
        return seeds(args.seeds, joint if args.joint else None)
    # the modes that print one report instead of the tables, the first one asked for
    for wanted, report in ((args.joint and not args.seeds,
                            lambda: joint_rooms(args.rooms, args.looks, args.consider)),
                           (args.seeds, seed_report),
                           (args.ten_looks, ten_looks),
                           (args.outside, lambda: outside(args.rooms, args.looks)),
                           (args.breakdown, lambda: breakdown(args.rooms, args.looks)),
                           (args.calibrate, lambda: calibrate(args.rooms, args.looks))):
        if wanted:
            print(report())
            print(f"\n({time.perf_counter() - t0:.0f} s in all)")
            return 0
    lab = bundled_lab()
    poses = bundled_walk()[:args.bundled_looks]
    bundled, took = one_walk(lab, poses)
    print(f"bundled walk: {len(poses)} looks, {took:.0f} s", file=sys.stderr)
    bundled29, _ = one_walk(lab, poses, kalman="a29")
    bundled1, _ = one_walk(lab, poses, line_step=1)
    bundled_ci, _ = one_walk(lab, poses, kalman="ci")
    bundled_far, _ = one_walk(lab, poses, max_range=1e9)
    bundled_noshape, _ = one_walk(lab, poses, shape=None)
    cal, floor = CALIBRATED_COLUMN_ERROR_PX, MEASURED_POSE_SIGMA_FLOOR
    honest = {"A-29, calibrated column error": dict(kalman="a29", column_error=cal),
              "A-29, pose floor": dict(kalman="a29", pose_floor=floor),
              "A-29, calibrated column error and pose floor": dict(kalman="a29", column_error=cal,
                                                                   pose_floor=floor),
              "covariance intersection, calibrated column error": dict(kalman="ci",
                                                                       column_error=cal),
              "covariance intersection, calibrated column error and pose floor":
                  dict(kalman="ci", column_error=cal, pose_floor=floor),
              "A-29, consider covariance (bound)": dict(kalman="a29", consider="bound"),
              "A-29, consider covariance (Joseph)": dict(kalman="a29", consider="joseph"),
              "A-29, consider (bound), retire unseen 1": dict(kalman="a29", consider="bound",
                                                              retire_unseen=1),
              "A-29, consider (bound), retire unseen 1, feature gate":
                  dict(kalman="a29", consider="bound", retire_unseen=1,
                       feature_gate=FEATURE_GATE_CHI2),
              "A-29, consider (bound), variance factor": dict(kalman="a29", consider="bound",
                                                              variance_factor=True),
              "A-29, consider (bound), tilt floor": dict(kalman="a29", consider="bound",
                                                         tilt_floor=MEASURED_TILT_SIGMA_FLOOR),
              "A-29, consider (bound), tilt floor, confirm 2":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       confirm=2),
              "A-29, consider (bound), tilt floor, confirm 3":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       confirm=3),
              "A-29, consider (bound), tilt floor, variance factor, confirm 2":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       variance_factor=True, confirm=2),
              "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate drop":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       confirm=2, ambiguity_gate="drop"),
              "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate track":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       confirm=2, ambiguity_gate="track"),
              "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate resolve":
                  dict(kalman="a29", consider="bound", tilt_floor=MEASURED_TILT_SIGMA_FLOOR,
                       confirm=2, ambiguity_gate="resolve"),
              "A-29, improved stereo matcher, consider (bound)":
                  dict(kalman="a29", consider="bound", match="improved"),
              "A-29, improved stereo matcher, consider (bound), retire unseen 1":
                  dict(kalman="a29", consider="bound", match="improved", retire_unseen=1)}
    bundled_honest = {}
    for name, kw in honest.items():
        bundled_honest[name], took = one_walk(lab, poses, **kw)
        print(f"bundled, {name}: {took:.0f} s", file=sys.stderr)
    rooms_honest_sets = ("A-29", "covariance intersection, calibrated column error and pose floor",
                         "A-29, consider covariance (bound)",
                         "A-29, consider (bound), retire unseen 1",
                         "A-29, consider (bound), tilt floor, confirm 2",
                         "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate drop",
                         "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate track",
                         "A-29, consider (bound), tilt floor, confirm 2, ambiguity gate resolve")
    rooms, rooms_honest = [], {name: [] for name in rooms_honest_sets}
    for seed in range(1, args.rooms + 1):
        room = generate_room(seed)
        walk = generate_walk(room, seed, args.looks)
        res, took = one_walk(room, walk)
        rooms.append(res)
        rooms_honest["A-29"].append(one_walk(room, walk, kalman="a29")[0])
        for name in rooms_honest_sets[1:]:
            rooms_honest[name].append(one_walk(room, walk, **honest[name])[0])
        print(f"room {seed}: {took:.0f} s", file=sys.stderr)
    doc = {"bundled": method_errors([bundled]), "rooms": method_errors(rooms),
           "bundled_a29": method_errors([bundled29]), "bundled_every_line": method_errors([bundled1]),
           "bundled_ci": method_errors([bundled_ci]), "bundled_no_range_limit": method_errors([bundled_far]),
           "bundled_no_shape_gate": method_errors([bundled_noshape]),
           "bundled_honest": {n: method_errors([r]) for n, r in bundled_honest.items()},
           "rooms_honest": {n: method_errors(r) for n, r in rooms_honest.items()},
           "features": {"bundled (A-30, as written)": feature_stats([bundled]),
                        "bundled (A-29, camera error propagated)": feature_stats([bundled29]),
                        "bundled (A-30, every line scanned)": feature_stats([bundled1]),
                        "bundled (covariance intersection)": feature_stats([bundled_ci]),
                        "bundled (A-30, no range limit)": feature_stats([bundled_far]),
                        "bundled (A-30, no shape gate)": feature_stats([bundled_noshape]),
                        **{f"bundled ({n})": feature_stats([r]) for n, r in bundled_honest.items()},
                        f"{args.rooms} generated rooms (A-30)": feature_stats(rooms),
                        **{f"{args.rooms} generated rooms ({n})": feature_stats(r)
                           for n, r in rooms_honest.items()}},
           "per_room": {str(i + 1): method_errors([r]) for i, r in enumerate(rooms)}}
    print(method_table(f"Bundled walk ({len(poses)} looks)", doc["bundled"]))
    print()
    print(method_table("Bundled walk, Kalman A-29", doc["bundled_a29"]))
    print()
    print(method_table("Bundled walk, every line scanned", doc["bundled_every_line"]))
    print()
    print(method_table("Bundled walk, covariance intersection", doc["bundled_ci"]))
    print()
    print(method_table("Bundled walk, no range limit", doc["bundled_no_range_limit"]))
    print()
    print(method_table("Bundled walk, no shape gate", doc["bundled_no_shape_gate"]))
    print()
    print(method_table(f"{args.rooms} generated rooms, {args.looks} looks each (pooled)", doc["rooms"]))
    print()
    for n, e in doc["rooms_honest"].items():
        print()
        print(method_table(f"{args.rooms} generated rooms, {n}", e))
    print()
    print(honest_table([(f"bundled, {n}", d["fused"]) for n, d in
                        [("A-30 (as written)", doc["bundled"]), ("A-29", doc["bundled_a29"]),
                         ("covariance intersection", doc["bundled_ci"]),
                         *doc["bundled_honest"].items()]]))
    print()
    print(feature_table(list(doc["features"].items())))
    print(f"\n({time.perf_counter() - t0:.0f} s in all)")
    if args.json:
        Path(args.json).write_text(json.dumps(doc, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
