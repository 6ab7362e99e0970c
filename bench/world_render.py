"""Time to render one look of the simulated world (both cameras, condense, truth).

    python bench/world_render.py [--looks N] [--room SEED]

Renders the first N looks of the bundled walk (or of a generated walk in room SEED) with the
windowed tracer the robot uses, and, in the same run as the reference, with the plain tracer
(every quad against every ray; tested to give the same pictures).  Prints median and worst
milliseconds per look and the ratio, for 4x4 rays per pixel (the bundled pair's, the default)
and for 2x2 and 1x1 (faster, coarser anti-aliasing).
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np                                          # noqa: E402

from world.render import render_look                        # noqa: E402
from world.room import bundled_lab, generate_room           # noqa: E402
from world.walk import bundled_walk, generate_walk          # noqa: E402


def _time(room, poses, **kw):
    ms = []
    for i, p in enumerate(poses):
        t = time.perf_counter()
        look = render_look(room, p, seed=i, **kw)
        ms.append(1000 * (time.perf_counter() - t))
    return ms, look


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--looks", type=int, default=12, help="looks to render (default 12)")
    ap.add_argument("--room", type=int, help="a generated room's seed (default: the bundled lab)")
    a = ap.parse_args(argv)
    if a.room is None:
        room, walk = bundled_lab(), bundled_walk()
    else:
        room = generate_room(a.room)
        walk = generate_walk(room, a.room, a.looks)
    step = max(1, len(walk) // a.looks)
    poses = walk[::step][: a.looks]
    print(f"{room.name}: {len(room.quads)} quads, {len(poses)} looks of the walk (every {step})")
    print(f"{'rays/pixel':>10} {'tracer':>9} {'median ms':>10} {'worst ms':>9} {'ratio':>6}")
    for s in (4, 2, 1):
        plain, lp = _time(room, poses, supersample=s, windowed=False)
        fast, lf = _time(room, poses, supersample=s)
        assert np.array_equal(lp.left_vd, lf.left_vd) and np.array_equal(lp.range_left, lf.range_left)
        mp, mf = statistics.median(plain), statistics.median(fast)
        print(f"{s}x{s:<8} {'plain':>9} {mp:10.0f} {max(plain):9.0f}")
        print(f"{'':10} {'windowed':>9} {mf:10.0f} {max(fast):9.0f} {mp / mf:6.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
