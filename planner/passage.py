"""Through a passage narrower than the pivot circle (``DriveConfig.passage``).

The planner grows the map by the circle the footprint sweeps pivoting, plus the
margin (0.79 ft), so a way between two boxes must leave 1.58 ft.  Chapter IV's
vehicle model names the movement directions as part of the trajectory: a
vehicle 0.8 ft wide that drives straight through needs only its width and the
margin each side (1.1 ft); it pivots only where the whole circle fits.  So:

* a **wide** cell (the planning radius clear of everything blocked) is one the
  vehicle may pivot in, as before;
* a **narrow** cell has only the grown half width (``width / 2 + margin``) clear.
  Under ``"moves"`` (the default since 2026-12-06) a forward move may cross
  narrow cells where every position of it, out to the grown nose ahead, is one
  (:func:`planner.motion.safe_prefix`, ``Passable.narrow``); the paths stay the
  circle's.  Pivots keep their own check, the footprint's sweep seen free.
* Under ``"straight"`` (a named option), where the circle finds no way to the
  goal, the path may also cross narrow cells on a straight line that runs,
  narrow cells only, from a wide cell to a wide cell (:func:`straight_runs`,
  along the grid's four axes and diagonals), or leave them along the heading
  from where the vehicle stands (:func:`heading_ray`), or end in one at a goal
  reached along such a line (:func:`goal_rays`); it is pulled taut through
  narrow cells, turning only in wide ones (:func:`shorten_straight`).

Small pure functions over boolean cell masks (rows z, columns x).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .search import Passable, line_of_sight

if TYPE_CHECKING:
    from vehicle.profile import VehicleProfile

# the grid's lines a straight run may follow: (rows, columns) per step
LINES = ((0, 1), (1, 0), (1, 1), (1, -1))


def _shift(a: np.ndarray, s: int) -> np.ndarray:
    """``a`` (1-D) moved ``s`` places on: out[k] = a[k - s], False where that is off it."""
    out = np.zeros_like(a)
    if s > 0:
        out[s:] = a[:-s]
    elif s < 0:
        out[:s] = a[-s:]
    else:
        out[:] = a
    return out


def _runs_between(wide: np.ndarray, narrow: np.ndarray, di: int, dj: int) -> np.ndarray:
    """The narrow cells whose unbroken narrow run along (di, dj), both ways,
    ends in a wide cell at each end."""
    if dj == 0:                           # a column: a row of the transposed grid
        return _runs_between(wide.T, narrow.T, 0, di).T

    def sweep(step_i: int, step_j: int) -> np.ndarray:
        # reach[c]: c is narrow and the first non-narrow cell behind it is wide,
        # column by column (the cell behind (i, j) is (i - step_i, j - step_j))
        reach = np.zeros_like(narrow)
        nx = narrow.shape[1]
        for j in (range(1, nx) if step_j > 0 else range(nx - 2, -1, -1)):
            pj = j - step_j
            reach[:, j] = narrow[:, j] & _shift(wide[:, pj] | reach[:, pj], step_i)
        return reach
    return sweep(di, dj) & sweep(-di, -dj)


def narrow_cells(p: Passable, prof: VehicleProfile) -> np.ndarray:
    """(nz, nx) bool: the cells of ``p``'s map with the profile's grown half width
    (``width / 2 + margin``) clear: those a forward move may cross."""
    return p.clearance >= prof.grown_half_ft[0] - 1e-9


def straight_runs(wide: np.ndarray, narrow: np.ndarray) -> np.ndarray:
    """(nz, nx) bool: the narrow cells (``narrow`` and not ``wide``) that lie on a
    straight line of the grid (:data:`LINES`) running through narrow cells only
    from a wide cell to a wide cell: the passages a vehicle crosses without
    pivoting in them."""
    only = narrow & ~wide
    out = np.zeros_like(wide)
    for di, dj in LINES:
        out |= _runs_between(wide, only, di, dj)
    return out


def _ray_cells(p: Passable, narrow: np.ndarray, x: float, z: float, heading_deg: float,
               max_ft: float) -> list[tuple[int, int]] | None:
    """The cells a ray from (x, z) along ``heading_deg`` passes through narrow cells
    until its first wide cell (``p.ok``; that one included); None when it leaves the
    narrow cells or the map first, or runs ``max_ft`` without a wide cell."""
    fm = p.fmap
    hr = math.radians(heading_deg)
    step = fm.cell / 4
    cells: list[tuple[int, int]] = []
    for k in range(1, int(max_ft / step) + 1):
        i, j = fm.index(x + k * step * math.sin(hr), z + k * step * math.cos(hr))
        if not fm.inside(i, j) or not narrow[i, j]:
            return None
        if not cells or cells[-1] != (i, j):
            cells.append((i, j))
        if p.ok[i, j]:
            return cells
    return None


def heading_ray(p: Passable, narrow: np.ndarray, start, heading_deg: float,
                max_ft: float = 6.0) -> list[tuple[int, int]]:
    """The cells the vehicle crosses from ``start``, a narrow cell, straight along its
    heading to the first wide cell (none when the way ahead leaves the narrow cells
    first): the one way on from a place too tight to pivot in."""
    return _ray_cells(p, narrow, start[0], start[1], heading_deg, max_ft) or []


def goal_rays(p: Passable, narrow: np.ndarray, goal, max_ft: float = 6.0
              ) -> list[tuple[int, int]]:
    """The cells of the straight lines (eight directions) from ``goal``, a narrow
    cell, through narrow cells to a wide one: the ways the vehicle may arrive
    there driving straight, having pivoted where the circle fits."""
    out: list[tuple[int, int]] = []
    for k in range(8):
        out += _ray_cells(p, narrow, goal[0], goal[1], 45.0 * k, max_ft) or []
    return out


def straight_passable(p: Passable, narrow: Passable, start, heading_deg: float, goal
                      ) -> Passable:
    """``p`` (the map grown by the planning radius) with the narrow cells a vehicle
    may cross straight opened: :func:`straight_runs`, the start's
    :func:`heading_ray` when it stands in a narrow cell, the goal's
    :func:`goal_rays` when the goal is one."""
    fm = p.fmap
    ok = p.ok | straight_runs(p.ok, narrow.ok)
    si, sj = fm.index(*start)
    if fm.inside(si, sj) and narrow.ok[si, sj] and not p.ok[si, sj]:
        for c in heading_ray(p, narrow.ok, start, heading_deg):
            ok[c] = True
    gi, gj = fm.index(*goal)
    if fm.inside(gi, gj) and narrow.ok[gi, gj] and not ok[gi, gj]:
        rays = goal_rays(p, narrow.ok, goal)
        if rays:
            ok[gi, gj] = True
            for c in rays:
                ok[c] = True
    return Passable(ok, p.clearance, p.blocked, fm, p.radius, p.unknown, p.at)


def shorten_straight(wide: np.ndarray, narrow: Passable, pts) -> list[tuple[float, float]]:
    """Pull the polyline taut as :func:`planner.trajectory.shorten` does, each
    straight piece through cells where the grown half width is clear
    (``narrow``), each corner in a ``wide`` cell (where the vehicle may pivot);
    a corner no wide point allows is kept where the search put it (the pivot's
    own check at the move decides)."""
    pts = [tuple(map(float, q)) for q in pts]
    if len(pts) <= 2:
        return pts
    fm = narrow.fmap

    def turnable(q) -> bool:
        i, j = fm.index(*q)
        return fm.inside(i, j) and bool(wide[i, j])
    out = [pts[0]]
    i = 0
    last = len(pts) - 1
    while i < last:
        j = last
        while j > i + 1 and not ((j == last or turnable(pts[j]))
                                 and line_of_sight(narrow, pts[i], pts[j])):
            j -= 1
        out.append(pts[j])
        i = j
    return out
