"""Free space an older look proved, trusted only as far as the odometry's drift
since that look allows (``DriveConfig.free_drift``: "erode", a named option, and
"moves", the default since 2026-12-04; not 1985).

Every look's free cells are placed by the estimate of its moment; the vehicle
plans from the estimate of now.  Under dead reckoning the two differ by the noise
of every command between (``world.odometry``: a heading error of ``turn_deg`` per
command that moved, a distance error of ``distance_fraction`` of its length), so
an edge of free space an old look proved beside a box may lie, seen from the
vehicle now, inside that box.  That is how four of the six collisions traced on
seeds 1-700 came about (rooms 219, 298 and 640 under ``--look-around evidence``,
471 under the defaults: each look's free cells lie on the floor in the frame of
that look's own true pose, inside a box only in the frame of the estimate; in
177 and 659 the floor's proof itself reaches into a box; docs/planner.md, "Free
space trusted by the drift since its look").

The erosion: each FREE cell of the map that a look freed (a floor-slab cell it
marked free) stays FREE only if it lies farther from every cell a look hit
(OCCUPIED or UNCERTAIN) than ``sigmas`` standard deviations of how far the drift
since the newest such look may have moved it relative to the vehicle now.  After
``n`` commands that travelled ``D`` ft (their distance variance ``V``) that is
``sqrt(n * turn**2 * (r + D)**2 + V)``: each command's heading error turns what
the look placed about where the vehicle was at that command, a place on its way
from the look's camera to where it is now, so no farther from the cell than ``r
+ D``, where ``r`` is the nearer of the cell's distances to the look's camera and
to the vehicle now (a look turned in place, ``D = 0``, moves the cells beside the
vehicle by little).  The last look gives up nothing; the vehicle's track, its
start spot and the plan's walls are drawn after.

``free_drift="moves"`` (the default since 2026-12-04, with ``look_around="evidence"``
and ``plan_walls="grown"``) erodes the same cells for moves only: a pivot's cells are
checked on the map before the erosion (:attr:`~planner.floormap.FloorMap.drift_kept`).
Under ``"erode"`` a vehicle beside a box could not turn: the pivot's circle reaches a
cell from the box's hits, the erosion takes that cell, and no look can give it back
(nothing nearer than 2.3 ft is in view); with eyes that see everything that cost 15
points.  A pivot turns the footprint about where the estimate stands; the erosion
guards against a move the drift carries into what an older look placed.  Without the
grown walls it collided in two long drives whose estimate ended 2 ft off (rooms 7
and 272; docs/planner.md, "What the erosion costs: the pivots").

Only edges beside a hit give way: eroding every edge of free space, beside
unknown space too, stopped the vehicle in the tiny room (``planner.tiny``) at
its third look, and shrinking each look's own free columns instead (view-cone
sides and all) reached no goal in seeds 1-30 under ``--look-around evidence``."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from .floormap import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, FloorMap

DRIFT_SIGMAS = 2.0      # how many standard deviations of the drift a look's free edge gives up


@dataclass
class Odometry:
    """Running totals of the odometry's reports: the commands that moved, the
    distance they travelled (ft) and its variance (ft^2) by the noise model."""
    commands: int = 0
    path_ft: float = 0.0
    distance_var: float = 0.0

    def report(self, distance_ft: float, distance_fraction: float) -> None:
        self.commands += 1
        self.path_ft += abs(distance_ft)
        self.distance_var += (distance_fraction * distance_ft) ** 2


@dataclass
class LookFree:
    """One look's free floor columns: its camera's (x, z), the (kx, kz) octree
    keys of the floor-slab cells it marked free, and the odometry's totals when
    it was taken."""
    origin: tuple[float, float]
    columns: np.ndarray                        # (N, 2) int: kx, kz
    odometry: Odometry = field(default_factory=Odometry)


def drift_ft(r_ft, then: Odometry, now: Odometry, turn_deg: float,
             sigmas: float = DRIFT_SIGMAS) -> np.ndarray:
    """``sigmas`` standard deviations of how far a cell may have moved, relative
    to the vehicle now, by the odometry's noise between a look (totals ``then``)
    and now; ``r_ft``: the nearer of its distances to the look's camera and to
    the vehicle now (module docstring)."""
    n = max(now.commands - then.commands, 0)
    d = max(now.path_ft - then.path_ft, 0.0)
    v = max(now.distance_var - then.distance_var, 0.0)
    heading_var = n * math.radians(turn_deg) ** 2
    r = np.asarray(r_ft, float)
    return sigmas * np.sqrt(heading_var * (r + d) ** 2 + v)


def erode_by_drift(fm: FloorMap, res: float, looks: list[LookFree], now: Odometry,
                   vehicle, turn_deg: float, sigmas: float = DRIFT_SIGMAS,
                   keep_for_pivots: bool = False) -> int:
    """Turn UNKNOWN every FREE cell of ``fm`` nearer to a cell a look hit
    (OCCUPIED, UNCERTAIN) than the drift (:func:`drift_ft`) of the newest look
    of ``looks`` that freed it, the vehicle now at ``vehicle`` (x, z); ``res`` is
    the octree's cell (``fm.cell`` the same).
    Cells no look freed are left as they are.  With ``keep_for_pivots``
    (``free_drift="moves"``) the cells it took are kept as
    :attr:`~planner.floormap.FloorMap.drift_kept`, which a pivot may still count
    free (module docstring).  Returns how many cells changed."""
    nz, nx = fm.shape
    i0, j0 = int(round(fm.z0 / res)), int(round(fm.x0 / res))
    margin = np.full((nz, nx), np.nan)
    x, z = fm.centre(np.arange(nz)[:, None], np.arange(nx)[None, :])
    for lf in looks:                      # oldest first: the newest look's margin stays
        if not len(lf.columns):
            continue
        i, j = lf.columns[:, 1] - i0, lf.columns[:, 0] - j0
        ok = (i >= 0) & (j >= 0) & (i < nz) & (j < nx)
        i, j = i[ok], j[ok]
        r = np.minimum(np.hypot(x[0, j] - lf.origin[0], z[i, 0] - lf.origin[1]),
                       np.hypot(x[0, j] - vehicle[0], z[i, 0] - vehicle[1]))
        margin[i, j] = drift_ft(r, lf.odometry, now, turn_deg, sigmas)
    clear = ((fm.cells != OCCUPIED) & (fm.cells != UNCERTAIN)).astype(np.uint8)
    # distance (ft) from each cell's centre to the nearest edge of a cell a look hit
    away = cv2.distanceTransform(clear, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * res - res / 2
    freed = ~np.isnan(margin)
    lost = (fm.cells == FREE) & freed & (away < np.where(freed, margin, 0.0))
    fm.cells[lost] = UNKNOWN
    if keep_for_pivots:
        fm.drift_kept = lost
    return int(lost.sum())
