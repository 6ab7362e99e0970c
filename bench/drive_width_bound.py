"""An upper bound, measured: would the drive reach more goals if the planner
needed only the vehicle's WIDTH to pass, not its turning circle?

The planner and the motion checks take the vehicle as a disc of its
footprint's half diagonal plus the planning margin (0.64 + 0.15 ft), so a
passage must leave 1.58 ft; the most common stop of the 1985 eyes is "the way
... is narrower than the vehicle (1.58 ft) ... where it leaves 1.29 ft".  A
0.8 ft wide vehicle driving straight through needs only its width and the
margin each side (1.1 ft).  This script drives each seeded room of
``bench/drive.py`` (the same rooms, starts, goals and odometry noise, the
default ``DriveConfig`` but for ``--eyes``) with the profile's
``planning_radius_ft`` replaced, for the run only, by half the width plus the
margin (0.55 ft): every passage and every forward move is then planned and
checked as if the vehicle were that narrow (pivots still need the whole
footprint's circle seen free).  It is a diagnostic, not a vehicle model: the
corners of the real footprint are not checked on a forward move, so a
collision here is the price of the bound, not a bug of the loop.

    python bench/drive_width_bound.py --rooms 100 [--eyes truth] [--out FILE]

Prints one row per room and the success, by the loop's test and by the true
pose, the collisions, and the rooms won and lost against the default run
(the same rooms driven as ``bench/drive.py`` drives them, in the same run).
"""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import contextmanager
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from drive import seeded_tasks  # noqa: E402  (bench/drive.py)


@contextmanager
def planned_by_width():
    """``VehicleProfile.planning_radius_ft`` is half the width plus the margin
    inside this block (every profile; restored after)."""
    from vehicle.profile import VehicleProfile
    disc = VehicleProfile.planning_radius_ft
    VehicleProfile.planning_radius_ft = property(lambda p: p.width_ft / 2 + p.margin_ft)
    try:
        yield
    finally:
        VehicleProfile.planning_radius_ft = disc


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rooms", type=int, default=20, help="seeds 1..N (default 20)")
    ap.add_argument("--first", type=int, default=1, help="first room seed")
    ap.add_argument("--eyes", choices=("rig", "truth", "depth"), default="rig")
    ap.add_argument("--out", help="write the rows and the summary as JSON here")
    args = ap.parse_args(argv)
    if args.rooms < 1 or args.first < 0:
        ap.error("--rooms must be 1 or more and --first 0 or more")
    from planner.loop import DriveConfig, run
    from world.odometry import OdometryNoise
    rows = []
    for seed, room, start, goal in seeded_tasks(args):
        if goal is None:
            continue
        cfg = DriveConfig(goal=goal, eyes=args.eyes)
        base = run(room, start, cfg, noise=OdometryNoise(seed=seed), keep_maps=False)
        with planned_by_width():
            thin = run(room, start, cfg, noise=OdometryNoise(seed=seed), keep_maps=False)
        row = {"room": seed, "default_reached": base.reached, "reached": thin.reached,
               "reached_true": thin.reached and thin.final_true_error_ft <= cfg.tolerance_ft,
               "collisions": thin.collisions, "default_collisions": base.collisions,
               "reason": thin.reason}
        rows.append(row)
        print(f"{seed:>4} default {'yes' if base.reached else 'no':>3}  by width "
              f"{'yes' if thin.reached else 'no':>3}  coll {thin.collisions}  {thin.reason[:80]}",
              flush=True)
    n = len(rows)
    summary = {
        "rooms": n, "eyes": args.eyes,
        "default_success_rate": sum(r["default_reached"] for r in rows) / n,
        "success_rate": sum(r["reached"] for r in rows) / n,
        "success_true_rate": sum(r["reached_true"] for r in rows) / n,
        "collisions": sum(r["collisions"] for r in rows),
        "default_collisions": sum(r["default_collisions"] for r in rows),
        "won": [r["room"] for r in rows if r["reached"] and not r["default_reached"]],
        "lost": [r["room"] for r in rows if r["default_reached"] and not r["reached"]],
        "collided": [r["room"] for r in rows if r["collisions"]],
    }
    for k, v in summary.items():
        print(f"{k:<24} {v}")
    if args.out:
        tmp = Path(args.out + ".tmp")
        tmp.write_text(json.dumps({"summary": summary, "rooms": rows}, indent=1))
        tmp.replace(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
