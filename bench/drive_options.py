"""Every named option of the drive measured again against the defaults, on the same seeds.

The loop's defaults moved many times (docs/planner.md, "Measured"); an option
rejected under one day's defaults may win under another's.  This script runs
``bench/drive.py --losses`` once with the defaults and once per option (each a
separate process, ``--jobs`` at a time), and prints one row per option: success
(by the loop's estimate and by the true pose), the rooms won and lost against
the defaults, collisions, path / optimum at most, looks per metre and the true
box cells its final maps show free.

    python bench/drive_options.py --rooms 100                      # the built-in list below
    python bench/drive_options.py --first 101 --rooms 200 --option "--reverse on --backing map" --option "--goal-region point"
    python bench/drive_options.py --rooms 100 --eyes truth         # every option with oracle edges

Each run's JSON is kept in ``--dir`` (one file per option, the name its flags), so
a run cut short by Ctrl-C picks up where it stopped (a kept run is reused as it is:
after a change to the code, give a fresh ``--dir``); ``--out`` writes the table as JSON.  Numbers go into docs/planner.md with the command that made them.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

# Named options, each off by default, that were measured and not adopted under
# the defaults of their day (docs/planner.md says where and why); last, the
# defaults of 2026-12-04 and of 2026-12-05 turned back one at a time and together, and
# the 1985 matcher, one-cell gaps kept unknown, every turn a pivot, no step back to
# learn the floor, the fix's window never widened, the pivot's disc, the goal planned
# to as a point, 8 looks without progress, each look's hits as the map's obstacles, no
# move on to turn, the seen map alone, the margin's ring seen free and the plan
# stopped by the outer sigma (the improved matcher, the fill, the smallest turns
# unchecked, the step back, the widening, the swept pivot, the goal's disc, 16 looks,
# the fused features, forward to turn, the walls' map where the seen one has no way,
# the ring's never-seen cells away from anything seen and the plan past the once-seen
# features' outer sigma are the defaults since 2026-12-05); the hits the plan's walls
# explain starting features and a tiled floor's one-grey runs proving the floor anywhere
# (the defaults before 2026-12-06 20:30), alone and together; the run ended as soon as
# the estimate enters the goal's disc (the default before 2026-12-07); 60 looks and 16
# looks without progress (the defaults before 2026-12-07 06:30 and 08:30); no backing
# along its own way where it cannot turn (the default before 12:15); two looks
# from one place at a blocker, not three; the two heads.  Expiry is
# measured on each look's hits and on the fused features.
OPTIONS = [
    "--clearance-at anywhere-exact",
    "--clearance-at centre",
    "--reverse on --backing map",
    "--progress evidence",
    "--uncertain look",
    "--refute-hits through",
    "--refute-hits under",
    "--expire-uncertain 3 --occupied looks",
    "--expire-uncertain 2",
    "--goal-evidence off",
    "--wall-runs texture",
    "--wall-runs none",
    "--wall-runs foot",
    "--wall-runs past",
    "--tile-edges blend",
    "--wall-hits feature",
    "--one-grey-runs prove",
    "--wall-hits feature --one-grey-runs prove",
    "--finish edge",
    "--max-looks 60",
    "--max-stuck 16",
    "--backing map",
    "--looks-per-viewpoint 2",
    "--min-confidence 0.2",
    "--disparity subpixel",
    "--wall-fix-far-sigmas 2",
    "--free-cells shadows",
    "--free-cells shadows --reverse on --backing map",
    "--pivot small-swept",
    "--track-free swept",
    "--stand-in majority",
    "--growth across",
    "--rejoin waypoint",
    "--wall-fix-first base",
    "--move-ring known",
    "--move-ring seen",
    "--passage circle",
    "--passage straight",
    "--passage stuck",
    "--steer off",
    "--steer small",
    "--steer small --pivot swept-ring-inner",
    "--fine-map off",
    "--floor-end-check stereo",
    "--fine-map off --floor-end-check stereo",
    "--wall-fix-most 0",
    "--wall-fix-far 0",
    "--goal-evidence off --wall-fix-far 0",
    "--sight-lines band",
    "--blank-carve always",
    "--free-drift erode",
    "--look-around sweep",
    "--free-drift off",
    "--plan-walls plan",
    "--look-around sweep --free-drift off --plan-walls plan",
    "--pose dead_reckoning",
    "--wall-points edges",
    "--proof-heading estimate",
    "--floor-end-check off",
    "--proof-hits trace",
    "--hit-at axis",
    "--min-range 2.5",
    "--wall-fix-sigmas 3",
    "--pose dead_reckoning --wall-points edges --proof-heading estimate --floor-end-check off "
    "--proof-hits trace --hit-at axis --min-range 2.5 --wall-fix-sigmas 3",
    "--match 1985",
    "--free-gaps keep",
    "--min-pivot-deg 0",
    "--learn-floor off",
    "--wall-fix-widen 0",
    "--pivot disc",
    "--goal-region point",
    "--max-stuck 8",
    "--occupied looks",
    "--turn-room off",
    "--map-extent seen",
    "--pivot swept",
    "--uncertain blocked",
    "--head assist",
    "--head pan-tilt",
]

HERE = Path(__file__).resolve().parent


def run_name(flags: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", flags.lower()).strip("_") or "defaults"


def run_one(flags: str, common: list[str], directory: Path) -> Path:
    """One bench/drive.py run; its JSON is reused when it is already there."""
    out = directory / f"{run_name(flags)}.json"
    if out.exists():
        return out
    tmp = out.with_suffix(".part")
    log = out.with_suffix(".log")
    cmd = [sys.executable, str(HERE / "drive.py"), *common, "--losses", *flags.split(),
           "--out", str(tmp)]
    with open(log, "w") as fh:
        done = subprocess.run(cmd, stdout=fh, stderr=subprocess.STDOUT)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {done.returncode}); see {log}")
    tmp.replace(out)  # published whole: a later run never reads half a file
    return out


def row_of(flags: str, data: dict, base: dict | None) -> dict:
    s = data["summary"]
    reached = {r["room"] for r in data["rooms"] if r["reached"]}
    row = {"option": flags or "(defaults)", "rooms": s["rooms"],
           "success_rate": s["success_rate"], "success_true_rate": s["success_true_rate"],
           "collisions": s["collisions"],
           "collision_rooms": [r["room"] for r in data["rooms"] if r["collisions"]],
           "ratio_max": s["ratio_max"], "looks_per_metre": s["looks_per_metre"],
           "box_cells_free": s["map_losses_total"]["true_obstacle_mapped_free"],
           "reached": sorted(reached)}
    if base is not None:
        before = {r["room"] for r in base["rooms"] if r["reached"]}
        row["won"] = sorted(reached - before)
        row["lost"] = sorted(before - reached)
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=100)
    ap.add_argument("--first", type=int, default=1, help="first room seed")
    ap.add_argument("--eyes", choices=("rig", "truth", "depth"), default="rig")
    ap.add_argument("--option", action="append", metavar="FLAGS",
                    help="an option's flags as one string, e.g. \"--reverse on\" "
                         "(repeatable; without it the built-in list of rejected options)")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time (default 2)")
    ap.add_argument("--dir", default="out/drive-options",
                    help="where each run's JSON and log are kept, and reused by a later call "
                         "(default out/drive-options; give a fresh one after a code change)")
    ap.add_argument("--out", help="write the table as JSON")
    args = ap.parse_args(argv)
    if args.rooms < 1 or args.first < 1 or args.jobs < 1:
        ap.error("--rooms, --first and --jobs must be at least 1")
    options = args.option or OPTIONS
    common = ["--rooms", str(args.rooms), "--first", str(args.first), "--eyes", args.eyes]
    directory = Path(args.dir) / f"{args.eyes}_{args.first}_{args.first + args.rooms - 1}"
    directory.mkdir(parents=True, exist_ok=True)

    t0 = time.time()
    runs = [""] + [o for o in options if o]
    print(f"{len(runs)} runs of {args.rooms} rooms, {args.jobs} at a time, into {directory}",
          flush=True)
    results = {}
    pool = ThreadPoolExecutor(args.jobs)
    try:
        futures = {flags: pool.submit(run_one, flags, common, directory) for flags in runs}
        for n, (flags, fut) in enumerate(futures.items(), 1):
            results[flags] = json.loads(fut.result().read_text())
            print(f"[{n}/{len(runs)}] {flags or '(defaults)'} done, "
                  f"{time.time() - t0:.0f} s", flush=True)
    except KeyboardInterrupt:
        # the runs under way had the Ctrl-C too; none queued may start after it
        pool.shutdown(cancel_futures=True)
        print("stopped; the runs finished so far are kept in", directory, file=sys.stderr)
        return 130
    except RuntimeError as e:
        pool.shutdown(cancel_futures=True)
        print(f"drive_options: {e}", file=sys.stderr)
        return 1
    pool.shutdown()

    base = results[""]
    rows = [row_of(flags, results[flags], None if flags == "" else base) for flags in runs]
    print(f"\n{'option':32s} {'ok %':>5} {'true %':>6} {'coll':>4} {'ratio':>5} {'looks/m':>7} "
          f"{'box free':>8}  won / lost")
    for r in rows:
        ratio = "-" if r["ratio_max"] is None else f"{r['ratio_max']:.2f}"
        wl = "" if "won" not in r else (f"+{' '.join(map(str, r['won'])) or '-'} / "
                                        f"-{' '.join(map(str, r['lost'])) or '-'}")
        print(f"{r['option']:32s} {100 * r['success_rate']:5.1f} {100 * r['success_true_rate']:6.1f} "
              f"{r['collisions']:>4} {ratio:>5} {r['looks_per_metre'] or 0:7.1f} "
              f"{r['box_cells_free']:>8}  {wl}")
    if args.out:
        tmp = Path(args.out).with_suffix(".part")
        tmp.write_text(json.dumps({"first": args.first, "rooms": args.rooms, "eyes": args.eyes,
                                   "rows": rows}, indent=1) + "\n")
        tmp.replace(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
