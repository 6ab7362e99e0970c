"""Time to render one look of the simulated world (both cameras, condense, truth).

    python bench/world_render.py [--looks N] [--room SEED]

Renders N looks spread over the bundled walk (or a generated walk in room SEED) with the
windowed tracer the robot uses and, look by look in the same run as the reference, with the
plain tracer (every quad against every ray; the pictures are checked equal).  Prints median and worst
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


def _time(room, poses, supersample):
    """Per look, the plain and the windowed tracer one after the other (so a busy machine
    slows both alike); returns (plain ms, windowed ms) lists."""
    plain, fast = [], []
    for i, p in enumerate(poses):
        t = time.perf_counter()
        lp = render_look(room, p, seed=i, supersample=supersample, windowed=False)
        t1 = time.perf_counter()
        lf = render_look(room, p, seed=i, supersample=supersample)
        t2 = time.perf_counter()
        assert np.array_equal(lp.left_vd, lf.left_vd) and np.array_equal(lp.range_left,
                                                                          lf.range_left)
        plain.append(1000 * (t1 - t))
        fast.append(1000 * (t2 - t1))
    return plain, fast


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
    print(f"{'rays/pixel':>10} {'tracer':>20} {'median ms':>10} {'worst ms':>9} {'ratio':>6}")
    render_look(room, poses[0], supersample=1)           # compile (or load) the kernel first
    for s in (4, 2, 1):
        alone = []
        for i, p in enumerate(poses):
            t = time.perf_counter()
            render_look(room, p, seed=i, supersample=s)
            alone.append(1000 * (time.perf_counter() - t))
        plain, fast = _time(room, poses, s)
        mp, mf = statistics.median(plain), statistics.median(fast)
        print(f"{s}x{s:<8} {'windowed, alone':>20} {statistics.median(alone):10.0f} "
              f"{max(alone):9.0f}")
        print(f"{'':10} {'plain, interleaved':>20} {mp:10.0f} {max(plain):9.0f}")
        print(f"{'':10} {'windowed, interleaved':>20} {mf:10.0f} {max(fast):9.0f} {mp / mf:6.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
