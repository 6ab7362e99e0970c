"""Which looks put the cells that block the goal on the map, and why.

For a drive that stops on "the goal ... is X ft from an obstacle", every
occupied or uncertain cell of the final floor map within the planning radius
of the goal is traced back to the looks whose grown hits hold it: the hit's
picture column and lines, the located range (LCSL's dp) against the TRUE
range at the same pixel (``Look.range_left``), the range's error bound, the
covariance's 2-sigma extent along and across the sight line, whether the cell
is the hit's own cell, its covariance growth or a surface span, and the
located point's true distance to the nearest surface (placed by the TRUE
pose: ``Room.clearance``, negative inside an obstacle).  Distances are the exact
gap between the goal cell's square and the blocked one; the planner's default
(``clearance_map(at="anywhere")``) refuses by a lower bound, up to 0.41 cell
less off the diagonals, so it can refuse a goal with no cell listed here (its
message gives both).  The map's border, blocked to the planner, is reported
when it lies within the radius.  A diagnostic: the
drive is not changed (the floor scan and the renderer are only wrapped).

    python bench/goal_blockers.py                 # the bundled lab (rig drive)
    python bench/goal_blockers.py --room 12       # a generated room, its bench goal
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np


def _source_points(rec):
    """The located point each hit of the look stands on (floor_scan's own
    choice: the nearest point of its column that another agrees with)."""
    from planner.perception import camera_points, filter_points
    pts, R, origin, band, max_range = rec["points"], rec["R"], rec["left"], rec["band"], \
        rec["max_range"]
    xyz_c, cov_c, line, loc1, ep = camera_points(pts)
    keep = filter_points(xyz_c, ep, max_range)
    room = xyz_c @ np.asarray(R).T + np.asarray(origin)
    keep &= (room[:, 1] >= band[0]) & (room[:, 1] <= band[1])
    kept = np.flatnonzero(keep)
    out = {}
    for c in rec["fs"].hit_cols:
        idx = kept[loc1[kept].astype(int) == c]
        z = xyz_c[idx, 2]
        tol = np.maximum(ep[idx], 0.05 * z)
        votes = (np.abs(z[:, None] - z[None, :]) <= tol[:, None]).sum(1)
        sup = np.flatnonzero(votes >= 2)
        k = sup[np.argmin(z[sup])]
        agree = idx[np.abs(z - z[k]) <= tol[k]]
        out[int(c)] = (int(idx[k]), agree.tolist(), xyz_c, cov_c, line, loc1, ep)
    return out


def trace(room, start, goal, cfg, noise):
    import planner.evidence as ev
    import world.render as wr
    from planner.loop import run
    from planner.octree import (OCCUPIED, UNCERTAIN, cell_centres, features_cells,
                                spans_cells)
    from vehicle.profile import DEFAULT

    records, cur = [], {}
    orig_fs, orig_render = ev.floor_scan, wr.render_look

    def render(*a, **k):
        cur["look"] = orig_render(*a, **k)
        return cur["look"]

    def fs_wrap(points, R, left, band, max_range, **kw):
        fs = orig_fs(points, R, left, band, max_range, **kw)
        records.append(dict(points=points, R=R, left=left, band=band, max_range=max_range,
                            fs=fs, look=cur["look"]))
        return fs
    ev.floor_scan, wr.render_look = fs_wrap, render
    try:
        res = run(room, start, cfg, noise=noise)
    finally:
        ev.floor_scan, wr.render_look = orig_fs, orig_render
    res.floor_scans = records            # for a caller that looks further
    res.border_ft = None
    fm = res.cycles[-1].fmap
    r = DEFAULT.planning_radius_ft
    cell = fm.cell
    blockers = []
    # the planner gives the goal its cell's clearance (the cross section anywhere
    # in it): the exact gap between its square and a blocked one, as here
    gi, gj = fm.index(*goal)
    gx, gz = fm.centre(gi, gj)
    # clearance_map counts the map's border as blocked: a ring of squares just outside it
    res_border = min(gi, fm.shape[0] - 1 - gi, gj, fm.shape[1] - 1 - gj) * cell
    for i, j in zip(*np.nonzero(np.isin(fm.cells, (OCCUPIED, UNCERTAIN)))):
        cx, cz = fm.centre(i, j)
        dx = max(abs(gx - cx) - cell, 0.0)
        dz = max(abs(gz - cz) - cell, 0.0)
        if math.hypot(dx, dz) < r:
            blockers.append((float(cx), float(cz), "occupied" if fm.cells[i, j] == OCCUPIED
                             else "uncertain", math.hypot(dx, dz)))
    if res_border < r:
        res.border_ft = round(float(res_border), 2)
    res_ft = cfg.voi.resolution
    out = []
    for cx, cz, state, dist in sorted(blockers, key=lambda b: b[3]):
        key = (math.floor(cx / res_ft), math.floor(cz / res_ft))
        hits = []
        for look_no, rec in enumerate(records, 1):
            fs = rec["fs"]
            if not len(fs.hits):
                continue
            src = None
            for h in range(len(fs.hits)):
                own = cell_centres(fs.hits[h:h + 1], res_ft)
                grow = features_cells(fs.hits[h:h + 1], fs.hit_cov[h:h + 1], res_ft)
                span = spans_cells(fs.hits, [s for s in fs.spans if h in s], res_ft)
                how = None
                for name, cells in (("own", own), ("growth", grow), ("span", span)):
                    if len(cells) and np.any((np.floor(cells[:, 0] / res_ft) == key[0]) &
                                             (np.floor(cells[:, 2] / res_ft) == key[1])):
                        how = name
                        break
                if how is None:
                    continue
                if src is None:
                    src = _source_points(rec)
                col = int(fs.hit_cols[h])
                k, agree, xyz_c, cov_c, line, loc1, ep = src[col]
                look = rec["look"]
                true_r = float(look.range_left[line[k], max(col - 2, 0):min(col + 1, 128)].min())
                tp = look.pose
                p_true = xyz_c[k] @ tp.rotation().T + tp.camera_centre("left")
                u = fs.hits[h] - fs.origin
                u[1] = 0.0
                u /= max(np.linalg.norm(u), 1e-12)
                C = fs.hit_cov[h]
                along = 2 * math.sqrt(max(u @ C @ u, 0.0))
                v = np.array([u[2], 0.0, -u[0]])
                across = 2 * math.sqrt(max(v @ C @ v, 0.0))
                hits.append({"look": look_no, "how": how, "col": col,
                             "lines": sorted(set(int(line[a]) for a in agree)),
                             "range_ft": round(float(xyz_c[k, 2]), 2),
                             "true_range_ft": round(true_r, 2),
                             "ep_ft": round(float(ep[k]), 2),
                             "two_sigma_along_ft": round(along, 2),
                             "two_sigma_across_ft": round(across, 2),
                             "hit_xz": [round(float(fs.hits[h, 0]), 2),
                                        round(float(fs.hits[h, 2]), 2)],
                             "camera_xz": [round(float(fs.origin[0]), 2),
                                           round(float(fs.origin[2]), 2)],
                             "point_true_clearance_ft": round(room.clearance(p_true[0],
                                                                             p_true[2]), 2)})
        out.append({"cell": [cx, cz], "state": state, "from_goal_cell_ft": round(dist, 2),
                    "cell_true_clearance_ft": round(room.clearance(cx, cz), 2), "hits": hits})
    return res, out


def main(argv=None) -> int:
    from rig.drive import DEFAULT_LAB_GOAL, add_loop_options, loop_config
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    from world.room import bundled_lab
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--room", type=int, help="a generated room's seed (default: the bundled lab)")
    ap.add_argument("--json", help="write the trace as JSON")
    add_loop_options(ap)
    args = ap.parse_args(argv)
    if args.room is None:
        room, goal, seed = bundled_lab(), DEFAULT_LAB_GOAL, 1985
        s = room.start
        start = State(s.x, s.z, s.heading_deg)
    else:
        import importlib.util
        from pathlib import Path
        spec = importlib.util.spec_from_file_location("bench_drive", Path(__file__).with_name("drive.py"))
        bd = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(bd)
        ns = argparse.Namespace(first=args.room, rooms=1)
        _, room, start, goal = next(bd.seeded_tasks(ns))
        seed = args.room
        if goal is None:
            ap.error(f"room {args.room} has no reachable goal")
    cfg = loop_config(args, goal, ap.error)
    res, out = trace(room, start, goal, cfg, OdometryNoise(seed=seed))
    print(f"reached {res.reached}, {res.looks} looks: {res.reason}")
    if res.border_ft is not None:
        print(f"the map's border (blocked to the planner) is {res.border_ft:.2f} ft from the "
              f"goal's cell")
    for b in out:
        print(f"cell ({b['cell'][0]:.3f}, {b['cell'][1]:.3f}) {b['state']}, "
              f"{b['from_goal_cell_ft']:.2f} ft from the goal's cell, true clearance "
              f"{b['cell_true_clearance_ft']:.2f} ft")
        for h in b["hits"]:
            print("   ", json.dumps(h))
    if args.json:
        from rig.scan import write_atomic
        write_atomic(args.json, json.dumps({"reached": res.reached, "reason": res.reason,
                                            "border_ft": res.border_ft, "blockers": out},
                                           indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
