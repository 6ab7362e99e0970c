"""A tiny deterministic room for the closed loop's end-to-end test and demo:
8 ft wide, 12 ft deep, walls in irregular vertical bands (edges everywhere
for the rig's eyes, none periodic: regular stripes alias the matcher), a
floor of irregular tiles (so that sight lines reach low over the floor), one
banded box 5 ft tall (seen over its whole height) off the straight line, the start at the origin facing +Z, the
goal 7 ft ahead."""

from __future__ import annotations

import numpy as np

from rig.scene import flat
from world.room import FLOOR_Y, full_box, make_room, quad

BOUNDS = (-4.0, 4.0, -2.0, 10.0)
BOX = ((1.2, 2.6), (FLOOR_Y - 5.0, FLOOR_Y), (3.5, 4.5))
GOAL = (0.0, 7.0)


def bands(seed: int, axis: int, lo: float, hi: float, greys=(13, 4, 10, 2, 14, 7, 11, 5)):
    """Vertical bands 0.3..1.1 ft wide across ``axis`` (0: X, 2: Z), seeded."""
    rng = np.random.default_rng(seed)
    edges = lo + np.cumsum(rng.uniform(0.3, 1.1, size=int((hi - lo) / 0.3) + 2))
    g = np.array(greys, float)

    def shade(X, Y, Z):
        k = np.searchsorted(edges, (X, Y, Z)[axis])
        return g[k % len(g)]
    return shade


def tiles(seed: int, size: float = 1.0, greys=(3, 9, 5, 12, 7, 14, 4, 10)):
    """Floor tiles of irregular greys (seeded), ``size`` ft square."""
    rng = np.random.default_rng(seed)
    table = rng.integers(0, len(greys), size=(64, 64))
    g = np.array(greys, float)

    def shade(X, Y, Z):
        i = np.floor(X / size).astype(int) % 64
        j = np.floor(Z / size).astype(int) % 64
        return g[table[i, j]]
    return shade


def tiny_room():
    x0, x1, z0, z1 = BOUNDS
    y0, y1 = -5.0, FLOOR_Y
    quads = full_box("box", BOX[0], BOX[1], BOX[2], bands(1, 0, *BOX[0], greys=(14, 3, 9)),
                     bands(2, 2, *BOX[2], greys=(12, 2, 8)), flat(9))
    quads += [
        quad("back wall", 2, z1, (x0, x1), (y0, y1), bands(3, 0, x0, x1)),
        quad("front wall", 2, z0, (x0, x1), (y0, y1), bands(4, 0, x0, x1)),
        quad("left wall", 0, x0, (y0, y1), (z0, z1), bands(5, 2, z0, z1)),
        quad("right wall", 0, x1, (y0, y1), (z0, z1), bands(6, 2, z0, z1)),
        quad("floor", 1, y1, (x0, x1), (z0, z1), flat(6)),
        quad("ceiling", 1, y0, (x0, x1), (z0, z1), flat(12)),
    ]
    return make_room("tiny room", quads, [(BOX[0], BOX[2])], BOUNDS, ceiling_y=y0)
