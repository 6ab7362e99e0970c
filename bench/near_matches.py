"""How often the 1985 matcher's located points lie in front of the truth, by their range.

The drive trusts a located point from ``DriveConfig.min_range_ft`` on (3 ft since
2026-12-05, 2.5 ft before).  This measures why: the rig's eyes scan looks of the
bundled lab and of generated rooms (from each room's start, turned -40, 0 and +40
deg, and 1.5 ft on along each of those headings where the vehicle fits), and each
located point's range (LCSL's dp) is held against the TRUE range at its pixel
(``Look.range_left``, the nearest surface over the edge's +-1 columns, as
``--eyes truth`` takes it).  A point counts as false when it lies more than
``max(0.5 ft, its own error bound ep)`` in front of the truth: a surface where
there is none, the kind that closes a passage.  Reported per range band: points,
false points and their share.

    python bench/near_matches.py                  # the lab and rooms 1-15
    python bench/near_matches.py --rooms 40 --out near.json
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

BANDS_FT = (2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0, 12.0)


def false_by_range(points, true_range, bands=BANDS_FT):
    """(points, false points) per band ``[bands[k], bands[k + 1])`` of the located
    range: ``points`` rig.scan Points, ``true_range`` the true range at each."""
    dp = np.array([p.dp for p in points], float)
    ep = np.array([p.ep for p in points], float)
    truth = np.asarray(true_range, float)
    false = (truth - dp) > np.maximum(0.5, ep)
    k = np.searchsorted(np.asarray(bands), dp, side="right") - 1
    inside = (k >= 0) & (k < len(bands) - 1)
    n = np.bincount(k[inside], minlength=len(bands) - 1)
    bad = np.bincount(k[inside], weights=false[inside], minlength=len(bands) - 1)
    return n.astype(int), bad.astype(int)


def _poses(room):
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    s = room.start
    for turn in (-40.0, 0.0, 40.0):
        h = s.heading_deg + turn
        for ahead in (0.0, 1.5):
            x = s.x + ahead * math.sin(math.radians(h))
            z = s.z + ahead * math.cos(math.radians(h))
            if room.clearance(x, z) >= DEFAULT.radius_ft:
                yield State(x, z, h)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=15, help="generated rooms 1..N beside the lab")
    ap.add_argument("--out", help="write the table as JSON")
    args = ap.parse_args(argv)
    if args.rooms < 0:
        ap.error(f"--rooms must be 0 or more, not {args.rooms}")
    from planner.loop import DriveConfig, scan_look, true_range_points
    from rig.scan import write_atomic
    from vehicle.profile import DEFAULT
    from vehicle.sim import camera_pose
    from world.render import render_look
    from world.room import bundled_lab, generate_room
    lines = DriveConfig(goal=(0.0, 0.0)).lines
    n = np.zeros(len(BANDS_FT) - 1, int)
    bad = np.zeros(len(BANDS_FT) - 1, int)
    looks = 0
    for room in [bundled_lab()] + [generate_room(s) for s in range(1, args.rooms + 1)]:
        for state in _poses(room):
            look = render_look(room, camera_pose(state, 0.0, 0.0, DEFAULT))
            points = scan_look(look.left_bi, look.right_bi, lines, "1985").points
            a, b = false_by_range(points, [t.dp for t in true_range_points(points, look)])
            n += a
            bad += b
            looks += 1
    rows = []
    print(f"{looks} looks of the bundled lab and rooms 1-{args.rooms}")
    print(f"{'range ft':>10} {'points':>7} {'false':>6} {'share':>6}")
    for k in range(len(n)):
        share = bad[k] / n[k] if n[k] else None
        rows.append({"from_ft": BANDS_FT[k], "to_ft": BANDS_FT[k + 1], "points": int(n[k]),
                     "false": int(bad[k]), "false_share": share})
        print(f"{BANDS_FT[k]:4.1f}-{BANDS_FT[k + 1]:4.1f} {n[k]:>7d} {bad[k]:>6d} "
              f"{'-' if share is None else f'{100 * share:5.1f}%':>6}")
    if args.out:
        write_atomic(args.out, json.dumps({"looks": looks, "rooms": args.rooms, "bands": rows},
                                          indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
