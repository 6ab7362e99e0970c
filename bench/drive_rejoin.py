"""Where the kept path resumes, measured: ``DriveConfig.rejoin`` side by side.

Each seeded room of ``bench/drive.py`` (the same rooms, starts and goals,
the same loop options and odometry noise) is driven twice in one run, once
with ``rejoin="waypoint"`` (the kept path resumes at its waypoint nearest
the vehicle: the loop's rule until 2026-12-01) and once with ``rejoin="leg"``
(it resumes at the end of its leg nearest the vehicle:
``planner.planning._still_good``).  Per room: reached, collisions, looks,
path / optimum and the stop reason of each; overall for each rule: success,
collisions, path / optimum median and max, looks per metre, the stop kinds,
and the rooms one rule reaches and the other does not.

    python bench/drive_rejoin.py --rooms 40 --eyes depth --no-noise
    python bench/drive_rejoin.py --rooms 100 --eyes truth --out rejoin.json
    python bench/drive_rejoin.py --rooms 100 --eyes depth --no-noise \
        --variants rejoin=leg rejoin=leg,blind_zone=true     # any DriveConfig fields

``--variants`` names the runs to compare (each a comma-separated list of
``DriveConfig`` fields set on top of the options; the default: ``rejoin=waypoint``
and ``rejoin=leg``); the first is the reference the others are counted against.

(``rig drive`` and ``bench/drive.py`` do not take ``--rejoin`` yet; this
script builds their ``DriveConfig`` from the same options and sets the one
field.)
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from drive import FT_PER_M, seeded_tasks, stop_kind  # noqa: E402  (bench/drive.py)

RULES = ("rejoin=waypoint", "rejoin=leg")


def parse_variant(text: str, base) -> dict:
    """{field: value} of a variant ``"field=value,field=value"``, each value
    converted to the type of ``base``'s field (bool: true / false)."""
    out = {}
    for item in text.split(","):
        name, eq, value = item.partition("=")
        if not eq or not hasattr(base, name):
            raise ValueError(f"variant {text!r}: {item!r} is not FIELD=VALUE of a DriveConfig field")
        now = getattr(base, name)
        if isinstance(now, bool):
            if value not in ("true", "false"):
                raise ValueError(f"variant {text!r}: {name} is true or false, not {value!r}")
            out[name] = value == "true"
        else:
            out[name] = type(now)(value)
    return out


def summary(rows, name):
    """The overall figures of one variant over the rooms run."""
    runs = [r[name] for r in rows]
    ok = [r for r in runs if r["reached"]]
    ratios = [r["ratio"] for r in ok if r["ratio"]]
    metres = sum(r["travelled_ft"] for r in runs) / FT_PER_M
    kinds: dict = {}
    for r, run in zip(rows, runs):
        kinds.setdefault(stop_kind(run["reason"]), []).append(r["room"])
    return {"rooms": len(runs), "reached": len(ok), "success_rate": len(ok) / len(runs),
            "collisions": sum(r["collisions"] for r in runs),
            "ratio_median": float(np.median(ratios)) if ratios else None,
            "ratio_max": float(np.max(ratios)) if ratios else None,
            "looks_per_metre": sum(r["looks"] for r in runs) / metres if metres else None,
            "looks": sum(r["looks"] for r in runs),
            "stop_reasons": kinds}


def main(argv=None) -> int:
    from rig.drive import add_loop_options, loop_config
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=20)
    ap.add_argument("--first", type=int, default=1, help="first room seed")
    ap.add_argument("--no-noise", action="store_true", help="odometry noise off (a diagnostic)")
    add_loop_options(ap)
    ap.add_argument("--variants", nargs="+", default=list(RULES), metavar="FIELD=VALUE[,…]",
                    help="the runs to compare, the first the reference (default: "
                         "rejoin=waypoint rejoin=leg)")
    ap.add_argument("--out", help="write per-room results and the summaries as JSON")
    args = ap.parse_args(argv)

    from planner.loop import run
    from world.odometry import OdometryNoise

    names = list(args.variants)
    if len(set(names)) != len(names) or not names:
        ap.error("--variants: give one or more different variants")
    rows = []
    t0 = time.perf_counter()
    print(f"{'room':>4}  " + "  ".join(f"{n}: ok coll looks ratio" for n in names)
          + "  reasons")
    try:
        for seed, room, start, goal in seeded_tasks(args):
            if goal is None:
                print(f"{seed:>4} no reachable goal; skipped")
                continue
            base = loop_config(args, goal, ap.error)
            row = {"room": seed, "goal": goal}
            for name in names:
                try:
                    cfg = dataclasses.replace(base, **parse_variant(name, base))
                except ValueError as exc:
                    ap.error(f"--variants: {exc}")
                noise = None if args.no_noise else OdometryNoise(seed=seed)
                res = run(room, start, cfg, noise=noise, keep_maps=False)
                ratio = res.travelled_ft / res.optimal_ft if (res.reached and res.optimal_ft) \
                    else None
                row[name] = {"reached": res.reached, "reason": res.reason,
                             "collisions": res.collisions, "looks": res.looks,
                             "travelled_ft": res.travelled_ft, "optimal_ft": res.optimal_ft,
                             "ratio": ratio}
            rows.append(row)

            def cell(r, width):
                ratio = "-" if r["ratio"] is None else f"{r['ratio']:.2f}"
                return f"{'yes' if r['reached'] else 'no':>3} {r['collisions']:>4} " \
                       f"{r['looks']:>5} {ratio:>5}".rjust(width)
            print(f"{seed:>4}  " + "  ".join(cell(row[n], len(n) + 21) for n in names) + "  "
                  + " | ".join(row[n]["reason"][:48] for n in names), flush=True)
    except KeyboardInterrupt:
        print("stopped by Ctrl-C; the rooms finished so far follow")
    if not rows:
        print("no rooms")
        return 1
    out = {"variants": {n: summary(rows, n) for n in names}}
    ref = names[0]
    for n in names[1:]:
        out["variants"][n]["reaches_reference_does_not"] = [
            r["room"] for r in rows if r[n]["reached"] and not r[ref]["reached"]]
        out["variants"][n]["reference_reaches_this_does_not"] = [
            r["room"] for r in rows if r[ref]["reached"] and not r[n]["reached"]]
    out["seconds"] = time.perf_counter() - t0
    print()
    f = (lambda v: "-" if v is None else f"{v:.2f}")
    for n in names:
        s = out["variants"][n]
        print(f"{n}: {s['reached']}/{s['rooms']} reached ({100 * s['success_rate']:.1f} %), "
              f"{s['collisions']} collisions, path/optimum median {f(s['ratio_median'])} "
              f"max {f(s['ratio_max'])}, {f(s['looks_per_metre'])} looks per metre, "
              f"{s['looks']} looks")
        print("    stops: " + "; ".join(f"{k} {' '.join(map(str, v))}"
                                         for k, v in s["stop_reasons"].items()))
        if n != ref:
            print(f"    reaches, {ref} does not: {s['reaches_reference_does_not']}; "
                  f"{ref} reaches, this does not: {s['reference_reaches_this_does_not']}")
    print(f"{out['seconds']:.0f} s")
    if args.out:
        tmp = Path(args.out).with_suffix(Path(args.out).suffix + ".tmp")
        tmp.write_text(json.dumps({"summary": out, "rooms": rows}, indent=1) + "\n")
        tmp.replace(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
