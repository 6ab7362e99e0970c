"""From the floor map to a path and its motion commands, for the closed loop
(:mod:`planner.loop`; Chapter IV's path and trajectory generation):
:func:`plan` searches the map grown by the vehicle's radius (the
dissertation's search or A*, :mod:`planner.search`), pulls the path taut and
turns it into commands (:mod:`planner.trajectory`), keeps the previous path
while it stays good (resumed where ``DriveConfig.rejoin`` says: :func:`_still_good`),
plans round the blind zone near the vehicle under ``DriveConfig.blind_zone``
(:func:`avoid_blind`), plans to the goal's disc under ``goal_region="disc"``
(:func:`goal_target`) and heads for the reachable cell nearest an unreachable
goal.  :func:`true_optimum` is the benchmark's yardstick (A* on the TRUE
room), :func:`random_goal` a reachable goal for a generated room.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import cv2
import numpy as np

from vehicle.profile import VehicleProfile
from vehicle.sim import State
from .floormap import FloorMap, true_floor_map
from .octree import UNCERTAIN, UNKNOWN
from .search import NoPath, Passable, astar, clearance_map, hierarchical_search, line_of_sight, \
    path_length, segment_samples
from .passage import narrow_cells, shorten_straight, straight_passable
from .trajectory import shorten, to_commands

if TYPE_CHECKING:
    from .loop import DriveConfig


SEARCHES = {"dissertation": hierarchical_search, "astar": astar}


UNCERTAIN_PLANS = ("blocked", "look", "core")


GOALS = ("point", "disc")             # what the planner plans to: the goal point, or the
                                      # standable cells of the tolerance disc (goal_target)


GOAL_SLACK_FT = 0.1                   # a target cell's centre this far inside the disc


def true_optimum(room, start, goal, profile: VehicleProfile, cell: float):
    """(taut length, A* grid length) of the best path for the vehicle in the
    TRUE room at the planner's resolution, or (None, None) without one."""
    fm = true_floor_map(room.obstacles, room.bounds, cell)
    p = clearance_map(fm, profile.planning_radius_ft, "blocked")
    try:
        raw = astar(p, start, goal)
    except NoPath:
        return None, None
    return path_length(shorten(p, raw)), path_length(raw)


def _nearest_reachable(p: Passable, start, goal):
    """The passable cell reachable from the start that is nearest the goal."""
    fm = p.fmap
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    si, sj = fm.index(*start)
    if not fm.inside(si, sj) or comp[si, sj] == 0:
        return None
    ii, jj = np.nonzero(comp == comp[si, sj])
    xs, zs = fm.centre(ii, jj)
    d = np.hypot(xs - goal[0], zs - goal[1])
    k = int(np.argmin(d))
    return float(xs[k]), float(zs[k])


PASSAGES = ("circle", "moves", "straight", "stuck")   # where the vehicle may pass
                                     # (DriveConfig.passage, planner.passage): plan()
                                     # plans straight through narrow ways under "straight"
                                     # only (the loop turns "stuck" into it or "moves")
REJOINS = ("waypoint", "leg")        # where a kept path resumes (DriveConfig.rejoin, _still_good)
BLIND_ZONES = ("off", "any", "short")    # planning round the blind zone (DriveConfig.blind_zone)


def _nearest_leg(prev, start) -> int:
    """Index m of the leg prev[m]-prev[m+1] nearest the point ``start``
    (point-to-segment distance); of legs equally near (within 1e-6 ft), the
    LATER one, so a vehicle standing on a waypoint is past it."""
    a = np.asarray(prev[:-1], float)
    b = np.asarray(prev[1:], float)
    s = np.asarray(start, float)
    ab = b - a
    ll = (ab ** 2).sum(axis=1)
    t = np.clip(((s - a) * ab).sum(axis=1) / np.where(ll > 0, ll, 1.0), 0.0, 1.0)
    d = np.hypot(*(a + t[:, None] * ab - s).T)
    return int(np.flatnonzero(d <= d.min() + 1e-6)[-1])


def _still_good(p: Passable, prev, start, rejoin: str = "waypoint") -> list | None:
    """The previous path from the vehicle's new position, if still passable.

    Where it resumes (``rejoin``): ``"waypoint"`` (the loop's rule until
    2026-12-01): at the previous path's waypoint nearest the vehicle, or the
    one after it when the vehicle sees that one directly; so a vehicle that
    drove a short way past a corner (a move cut short where its way was not
    yet seen) is nearer the corner than the next one and is sent back to it,
    and from the corner forward again: the to-and-fro that used up the 60
    looks of rooms 8 11 12 15 32 34 37 40 (docs/planner.md, "The kept path
    that sent the vehicle back").  ``"leg"`` (a named option, not 1985): at
    the end of the previous path's leg nearest the vehicle (point to
    segment); when the way from the vehicle to it is not passable the path
    is not kept (the search plans anew), so a waypoint already passed is
    never gone back to.  (Resuming at the leg's start instead took room 18,
    depth eyes with the noise, back 1.5 ft to a corner it had passed.)"""
    if rejoin not in REJOINS:
        raise ValueError(f"unknown rejoin {rejoin!r}; one of {', '.join(REJOINS)}")
    if not prev or len(prev) < 2:
        return None
    if rejoin == "leg":
        rest = [tuple(start)] + [tuple(q) for q in prev[_nearest_leg(prev, start) + 1:]]
    else:
        # drop the waypoints already passed: continue from the nearest waypoint
        rest = [tuple(start)] + [tuple(q) for q in prev[1:]]
        d = [math.hypot(q[0] - start[0], q[1] - start[1]) for q in rest[1:]]
        k = int(np.argmin(d))
        if k > 0 and line_of_sight(p, start, rest[k + 1]):
            rest = [tuple(start)] + rest[k + 1:]
    if all(line_of_sight(p, a, b) for a, b in zip(rest[:-1], rest[1:])):
        return rest
    return None


ESCAPE_FT = 1.0              # as far as safe_prefix lets the vehicle leave a too-near spot


def escape_start(p: Passable, start) -> Passable:
    """When the estimate stands nearer an obstacle than the planning radius
    (a feature seen late, or a fix that moved the estimate), the cells within
    ``ESCAPE_FT`` of it that are no nearer to any obstacle count passable, so
    the search can lead the vehicle away; :func:`safe_prefix` allows exactly
    those moves.  Otherwise the planner refuses the start and the vehicle
    stays put until it gives up."""
    fm = p.fmap
    i0, j0 = fm.index(*start)
    if not fm.inside(i0, j0) or p.ok[i0, j0] or p.blocked[i0, j0]:
        return p
    cl0 = p.clearance[i0, j0]
    ii, jj = np.indices(fm.shape)
    cx, cz = fm.centre(ii, jj)
    near = np.hypot(cx - start[0], cz - start[1]) <= ESCAPE_FT
    ok = p.ok | (near & ~p.blocked & (p.clearance >= cl0 - 1e-9))
    return Passable(ok, p.clearance, p.blocked, fm, p.radius, p.unknown, p.at)


def plan(fm: FloorMap, est: State, goal, cfg: DriveConfig, prev=None):
    """(polyline, commands, note) from the estimate toward the goal, or raise
    NoPath.  The previous path is kept while it stays passable and is no more
    than ``keep_ft`` longer than a new one (no dithering between two ways round).

    Uncertain cells (hit by one look, not yet confirmed by a second) block the
    path; when none avoids them (``cfg.uncertain="blocked"``, the default until
    2026-12-05 22:40) the vehicle heads for the reachable cell nearest the goal.
    With ``"look"`` (a named option, measured and not adopted: docs/planner.md)
    the path may pass through them: the vehicle drives toward them (never
    nearer than its radius: the execution still treats them as obstacles) and
    looks again, so a second look confirms or clears them.  With ``"core"``
    (the default since 2026-12-05 22:40) only the uncertain features' cells
    within one standard deviation (``fm.uncertain_core``) are planned round,
    the same way: the path may pass between two features one look saw where
    their two-sigma growth closes the way, and the vehicle, driven only as the
    whole map allows, looks again from nearer, which fuses them into features
    of smaller covariance.

    Under ``cfg.passage="straight"`` (a named option), where no path reaches
    the goal on the map grown by the planning radius, the path may run
    straight through narrow cells, from and to cells that radius fits in
    (:mod:`planner.passage`); its note then ends "(straight through a narrow
    way)"."""
    if cfg.uncertain not in UNCERTAIN_PLANS:
        raise ValueError(f"unknown uncertain-cell plan {cfg.uncertain!r}; one of "
                         f"{', '.join(UNCERTAIN_PLANS)}")
    if cfg.rejoin not in REJOINS:
        raise ValueError(f"unknown rejoin {cfg.rejoin!r}; one of {', '.join(REJOINS)}")
    if cfg.blind_zone not in BLIND_ZONES:
        raise ValueError(f"unknown blind_zone {cfg.blind_zone!r}; one of {', '.join(BLIND_ZONES)}")
    if cfg.passage not in PASSAGES:
        raise ValueError(f"unknown passage {cfg.passage!r}; one of {', '.join(PASSAGES)}")
    if cfg.passage != "straight":
        return _plan_uncertain(fm, est, goal, cfg, prev, "circle")
    # "straight": only where the circle finds no way to the goal itself
    try:
        return _plan_uncertain(fm, est, goal, cfg, prev, "circle", nearest=False)
    except NoPath:
        pass
    try:
        pts, cmds, note = _plan_uncertain(fm, est, goal, cfg, prev, "straight", nearest=False)
        return pts, cmds, note + " (straight through a narrow way)"
    except NoPath:
        return _plan_uncertain(fm, est, goal, cfg, prev, "circle")


def _plan_uncertain(fm: FloorMap, est: State, goal, cfg: DriveConfig, prev, passage: str,
                    nearest: bool = True):
    """:func:`plan` under one ``passage``: round the uncertain cells as
    ``cfg.uncertain`` says; with ``nearest``, toward the reachable cell nearest
    a goal no path reaches."""
    if cfg.uncertain == "blocked" or not (fm.cells == UNCERTAIN).any():
        return _plan(fm, est, goal, cfg, prev, "blocked", passage, nearest)
    try:
        return _plan(fm, est, goal, cfg, prev, "blocked", passage, nearest=False)
    except NoPath as exc:
        try:
            through = "free" if cfg.uncertain == "look" else "core"
            pts, cmds, _ = _plan(fm, est, goal, cfg, prev, through, passage, nearest=False)
            return pts, cmds, (f"{exc}; through uncertain cells, to look at them"
                               if through == "free" else
                               f"{exc}; past uncertain features' outer sigma, to look again")
        except NoPath:
            return _plan(fm, est, goal, cfg, prev, "blocked", passage, nearest)


def goal_target(p: Passable, start, goal, radius: float):
    """The point the planner plans to under ``goal_region="disc"``: the goal
    itself when the vehicle may stand there and reach it from ``start``;
    otherwise, of the cells within ``radius`` of the goal (centre distance)
    that are passable and connected to the start's cell (4-connected: a
    region both searches can grow through), the one nearest the goal; the
    goal itself when there is none (the point planning then says why not).
    A cell passable on ``p`` has the vehicle's planning radius to every
    blocked cell, so the target is never in or against an obstacle."""
    fm = p.fmap
    gi, gj = fm.index(*goal)
    si, sj = fm.index(*start)
    if not fm.inside(si, sj) or not p.ok[si, sj]:
        return tuple(map(float, goal))
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=4)
    here = comp[si, sj]
    if fm.inside(gi, gj) and p.ok[gi, gj] and comp[gi, gj] == here:
        return tuple(map(float, goal))
    n = int(math.ceil(radius / fm.cell)) + 1
    ii, jj = fm.square_around(gi, gj, n)
    cx, cz = fm.centre(ii, jj)
    d = np.hypot(cx - goal[0], cz - goal[1])
    cand = (d <= radius) & p.ok[ii, jj] & (comp[ii, jj] == here)
    if not cand.any():
        return tuple(map(float, goal))
    k = np.flatnonzero(cand.ravel())[np.argmin(d[cand])]
    return float(cx.ravel()[k]), float(cz.ravel()[k])


def _reach_kernel(radius: float, cell: float) -> np.ndarray:
    """The dilation kernel of the cells some point of whose square lies within
    ``radius`` of the centre cell's centre (cells of side ``cell``)."""
    r = radius / cell
    n = int(math.ceil(r + 0.5))
    d = np.maximum(np.abs(np.arange(-n, n + 1)) - 0.5, 0.0)
    return ((d[:, None] ** 2 + d[None, :] ** 2) <= r * r + 1e-9).astype(np.uint8)


def unseen_band(fm: FloorMap, radius: float) -> np.ndarray:
    """(nz, nx) bool: the cells where the vehicle's centre would have a
    never-seen (UNKNOWN) cell within ``radius`` (some point of that cell's
    square at most ``radius`` from this cell's centre): a path through them
    asks a look to show that cell before the vehicle may drive or pivot
    there (:mod:`planner.motion`: the swept width, its nose, the pivot's
    circle).  Cells off the map do not count."""
    unknown = (fm.cells == UNKNOWN).astype(np.uint8)
    return cv2.dilate(unknown, _reach_kernel(radius, fm.cell), borderType=cv2.BORDER_CONSTANT,
                      borderValue=0) > 0


def path_cost(fm: FloorMap, pts, band: np.ndarray, weight: float) -> float:
    """The length of the polyline, each piece (a quarter cell) in a cell of
    ``band`` counted ``1 + weight`` times (the search's cost under
    ``DriveConfig.seen_cost``)."""
    total = 0.0
    for a, b in zip(pts[:-1], pts[1:]):
        s = segment_samples(a, b, fm.cell / 4)
        mid = (s[:-1] + s[1:]) / 2
        ln = np.hypot(*np.diff(s, axis=0).T)
        i = np.clip(np.floor((mid[:, 1] - fm.z0) / fm.cell).astype(int), 0, fm.shape[0] - 1)
        j = np.clip(np.floor((mid[:, 0] - fm.x0) / fm.cell).astype(int), 0, fm.shape[1] - 1)
        total += float((ln * (1.0 + weight * band[i, j])).sum())
    return total


def seen_search(p: Passable, start, goal, band: np.ndarray, weight: float):
    """The path that keeps to what was in view (``DriveConfig.seen_cost``, a
    named option, not the dissertation's): A* over the passable cells, each
    step into a cell of ``band`` (:func:`unseen_band`) costing ``1 +
    weight`` times its length, then pulled taut only through cells outside
    the band or beside the cells the search itself passed in it (so the
    pulling does not cut back across never-seen space)."""
    raw = astar(p, start, goal, band * float(weight))
    fm = p.fmap
    on = np.zeros(fm.shape, np.uint8)
    for q in raw:
        i, j = fm.index(*q)
        if fm.inside(i, j):
            on[i, j] = 1
    near = cv2.dilate(on, np.ones((3, 3), np.uint8)) > 0
    taut = Passable(p.ok & (~band | near), p.clearance, p.blocked, fm, p.radius, p.unknown,
                    p.at)
    return shorten(taut, raw)


def avoid_blind(p: Passable, start, near_ft: float, half_width: float) -> Passable:
    """``p`` with the cells closed where the vehicle's swept width would meet
    a never-seen (UNKNOWN) cell whose centre lies within ``near_ft`` of the
    vehicle at ``start``: space no look from here can show, so a move through
    it would be refused (:mod:`planner.motion`) however often the vehicle
    looked (``DriveConfig.blind_zone``, a named option, not the
    dissertation's).  A cell is closed when some point of its square lies
    within ``half_width`` of such a cell's centre (the kernel of
    :func:`unseen_band`): a planning preference, not a safety check (the
    motion checks stay as they are).  The start's own cell keeps its state."""
    fm = p.fmap
    ii, jj = np.indices(fm.shape)
    cx, cz = fm.centre(ii, jj)
    blind = (fm.cells == UNKNOWN) & (np.hypot(cx - start[0], cz - start[1]) <= near_ft)
    closed = cv2.dilate(blind.astype(np.uint8), _reach_kernel(half_width, fm.cell),
                        borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0
    ok = p.ok & ~closed
    si, sj = fm.index(*start)
    if fm.inside(si, sj):
        ok[si, sj] = p.ok[si, sj]
    return Passable(ok, p.clearance, p.blocked, fm, p.radius, p.unknown, p.at)


def _plan(fm: FloorMap, est: State, goal, cfg: DriveConfig, prev, uncertain: str,
          passage: str = "circle", nearest: bool = True):
    search = SEARCHES[cfg.search]
    if cfg.seen_cost < 0:
        raise ValueError(f"seen_cost must be 0 (off) or more, not {cfg.seen_cost!r}")
    band = unseen_band(fm, cfg.profile.radius_ft) if cfg.seen_cost > 0 else None

    found = {}

    def find(p, a, b):
        # the blind zone's comparison and the plan search one map twice: once is
        # enough (the map kept in the entry, so its id stays its own)
        key = (id(p), tuple(map(float, a)), tuple(map(float, b)))
        if key not in found:
            if narrow is not None:
                pts = shorten_straight(wide, narrow, search(p, a, b))
            elif band is None:
                pts = shorten(p, search(p, a, b))
            else:
                pts = seen_search(p, a, b, band, cfg.seen_cost)
            found[key] = (p, pts)
        return list(found[key][1])

    def cost(q):
        return path_length(q) if band is None else path_cost(fm, q, band, cfg.seen_cost)
    r = cfg.profile.planning_radius_ft
    p = escape_start(clearance_map(fm, r, cfg.unknown, uncertain=uncertain,
                                    at=cfg.clearance_at), (est.x, est.z))
    start = (est.x, est.z)
    narrow = wide = None
    if passage == "straight":
        # the narrow cells a vehicle crosses straight, pivoting only in wide ones
        prof = cfg.profile
        narrow = Passable(narrow_cells(p, prof), p.clearance, p.blocked,
                          fm, prof.grown_half_ft[0], p.unknown, p.at)
        wide = p.ok
        p = straight_passable(p, narrow, start, est.heading_deg, goal)
    aim = tuple(map(float, goal))
    if cfg.goal_region == "disc":
        aim = goal_target(p, start, goal, max(cfg.tolerance_ft - GOAL_SLACK_FT, 0.0))
    if cfg.blind_zone != "off":
        # plan round the space near the vehicle no look from here can show,
        # when some path avoids it ("short": one at most keep_ft longer than
        # the plain path); else as before
        from .motion import near_visible_ft
        prof = cfg.profile
        pb = avoid_blind(p, start, near_visible_ft(prof, cfg.lowest_obstacle_ft),
                         prof.width_ft / 2 + prof.margin_ft)
        try:
            round_ = find(pb, start, aim)
            if cfg.blind_zone == "any" or cost(round_) <= cost(find(p, start, aim)) + cfg.keep_ft:
                p = pb
        except NoPath:
            pass

    def to_goal(q) -> bool:
        # a previous path is kept only when it ends at the goal point itself,
        # as without the disc (keeping paths to a disc cell took the bundled
        # lab's drive round the far side of the table, and lost it)
        return tuple(map(float, q)) == tuple(map(float, goal))
    try:
        pts = find(p, start, aim)
        note = "path to the goal" if aim == tuple(map(float, goal)) else \
            f"path to the goal's disc at ({aim[0]:.2f}, {aim[1]:.2f})"
        old = _still_good(p, prev, start, cfg.rejoin) \
            if prev and to_goal(prev[-1]) else None
        if old is not None and cost(old) <= cost(pts) + cfg.keep_ft:
            pts, note = old, "path to the goal (kept)"
        elif prev:
            note = "path to the goal (replanned)"
    except NoPath as exc:
        if not nearest:
            raise
        # the goal itself may look blocked from afar (a far feature's grown
        # covariance): head for the reachable cell nearest it and look again
        target = _nearest_reachable(p, start, goal)
        if target is None or math.hypot(target[0] - start[0], target[1] - start[1]) < 0.3:
            raise exc
        pts = find(p, start, target)
        note = f"goal not reachable ({exc}); toward ({target[0]:.1f}, {target[1]:.1f})"
    cmds = to_commands(pts, est.heading_deg, cfg.profile.turning_radius_ft, p)
    return pts, cmds, note


def random_goal(room, start: State, profile: VehicleProfile, rng, min_ft: float = 6.0,
                cell: float = 0.25, tries: int = 200):
    """A goal the vehicle can reach from ``start`` in the TRUE room (a path
    exists at the planner's resolution) at least ``min_ft`` away, or None."""
    x0, x1, z0, z1 = room.bounds
    r = profile.planning_radius_ft
    fm = true_floor_map(room.obstacles, room.bounds, cell)
    p = clearance_map(fm, r, "blocked")
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    si, sj = fm.index(start.x, start.z)
    if not fm.inside(si, sj) or comp[si, sj] == 0:
        return None
    for _ in range(tries):
        gx, gz = float(rng.uniform(x0 + r, x1 - r)), float(rng.uniform(z0 + r, z1 - r))
        # the goal returned is rounded to 0.01 ft, and the rounded point is the one tested:
        # rounding may carry it into the next cell (room 126's did, into a cell nearer a
        # box than the radius: a goal the true room does not reach)
        gx, gz = round(gx, 2), round(gz, 2)
        if math.hypot(gx - start.x, gz - start.z) < min_ft:
            continue
        gi, gj = fm.index(gx, gz)
        if comp[gi, gj] == comp[si, sj] and room.clearance(gx, gz) >= r:
            return gx, gz
    return None


SLACK_STEP_FT = 0.125                 # task_slack's step: half a cell of the default grid


def task_slack(room, start, goal, profile: VehicleProfile, cell: float,
               step_ft: float = SLACK_STEP_FT, max_ft: float = 2.0) -> float | None:
    """How much room to spare a task leaves: the largest multiple of ``step_ft``
    (at most ``max_ft``) by which the vehicle's planning radius can grow and the
    TRUE room, on the planner's grid, still join ``start`` to ``goal`` (both
    standable, one 8-connected region).  None when they are not joined at the
    radius itself.

    Why the benchmark reports it: :func:`random_goal` accepts any goal the true
    room joins at the radius itself, and the generated rooms keep only 1.8 ft
    between boxes for a vehicle 1.58 ft across, so a map that blocks even half a
    cell more than the truth on a passage (the growth of a hit by its error, the
    drift of the estimate, the grown walls) closes it.  Success by slack says
    how much of what a drive misses is that margin (docs/planner.md)."""
    fm = true_floor_map(room.obstacles, room.bounds, cell)
    si, sj = fm.index(*start)
    gi, gj = fm.index(*goal)
    if not (fm.inside(si, sj) and fm.inside(gi, gj)):
        return None
    best = None
    for k in range(int(round(max_ft / step_ft)) + 1):
        p = clearance_map(fm, profile.planning_radius_ft + k * step_ft, "blocked")
        _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
        if comp[si, sj] == 0 or comp[si, sj] != comp[gi, gj]:
            break
        best = k * step_ft
    return best
