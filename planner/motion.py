"""What the vehicle may do on the map it has (the execution step of the closed
loop, :mod:`planner.loop`): the vehicle never drives into space no look has
shown free.

* :func:`safe_prefix`: the first ``step`` ft of the planned commands, each
  forward move cut where its swept width (and nose) would enter a cell not
  seen free or come within the vehicle's radius of an occupied or uncertain
  cell; a pivot needs its circle (or, ``pivot="swept"``, its sweep) seen free;
* what a look can show: :func:`looked_free` (the field of view just looked
  at), :func:`near_visible_ft` (nothing nearer is in the picture);
* the vehicle's own track as free space (:func:`mark_track_free`);
* the pan-tilt head (``DriveConfig.head="pan-tilt"``, a named option): where
  the head looks (:func:`head_aim`, :func:`head_look`, :func:`head_commands`);
* fetching evidence when it cannot move (``look_around="evidence"``, the default
  since 2026-12-04): the blocking cells, a viewpoint to look at them from, backing off
  (:func:`fetch_evidence`);
* the vehicle's own way back (``DriveConfig.backing="trail"``, the default since
  2026-12-07): its motions kept (:func:`push_trail`) and undone where it cannot
  turn (:func:`retrace`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import cv2
import numpy as np

from vehicle.commands import Arc, Back, Forward, Pan, Tilt, Turn
from vehicle.profile import VehicleProfile
from vehicle.sim import State, advance
from .floormap import FloorMap
from .octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN
from .planning import escape_start
from .search import NoPath, Passable, astar, clearance_at, clearance_map, segment_samples
from .trajectory import heading_to, next_segment, shorten, to_commands, wrap


def swept_poses(track, step_ft: float = 0.25, step_deg: float = 10.0) -> list:
    """The poses between consecutive poses of a track: a straight move sampled
    every ``step_ft``, a pivot every ``step_deg`` (the footprint's sweep)."""
    if not track:
        return []
    out = [track[0]]
    for a, b in zip(track[:-1], track[1:]):
        turn = wrap(b.heading_deg - a.heading_deg)
        dist = math.hypot(b.x - a.x, b.z - a.z)
        n = max(1, int(math.ceil(max(abs(turn) / step_deg, dist / step_ft))))
        for k in range(1, n + 1):
            t = k / n
            out.append(State(a.x + t * (b.x - a.x), a.z + t * (b.z - a.z),
                             wrap(a.heading_deg + t * turn)))
    return out


def mark_track_free(fm: FloorMap, track, footprint, disc_ft: float = 0.0,
                     swept_margin: float | None = None) -> None:
    """Where the vehicle has stood is free: its footprint rectangle at every
    dead-reckoned pose (and, with ``disc_ft``, a disc of that radius about the
    first pose: the clear spot it was set down in).  With ``swept_margin`` (a
    named option, ``DriveConfig.track_free="swept"``) also every pose between
    them (the footprint swept by each move and pivot), the footprint shrunk by
    that margin on every side against the estimate's error."""
    from world.collide import footprint_corners
    mask = np.zeros(fm.shape, np.uint8)
    if swept_margin is not None:
        track = swept_poses(track)
        footprint = (max(footprint[0] - 2 * swept_margin, 0.0),
                     max(footprint[1] - 2 * swept_margin, 0.0))
    for s in track:
        c = footprint_corners(s.x, s.z, s.heading_deg, footprint)
        poly = np.stack([(c[:, 0] - fm.x0) / fm.cell, (c[:, 1] - fm.z0) / fm.cell], 1)
        cv2.fillPoly(mask, [np.round(poly - 0.5).astype(np.int32)], 1)
    if disc_ft > 0 and len(track):
        i, j = fm.index(track[0].x, track[0].z)
        cv2.circle(mask, (j, i), int(math.floor(disc_ft / fm.cell)), 1, -1)
    fm.cells[mask > 0] = FREE
    if fm.assumed is not None:
        fm.assumed[mask > 0] = False      # stood on: proven


def _disc_seen_free(fm: FloorMap, x: float, z: float, radius: float) -> bool:
    """Every cell within ``radius`` of (x, z) is FREE: a pivot there is safe."""
    n = int(math.ceil(radius / fm.cell)) + 1
    i0, j0 = fm.index(x, z)
    ii, jj = np.mgrid[i0 - n:i0 + n + 1, j0 - n:j0 + n + 1]
    cx, cz = fm.centre(ii, jj)
    # cells whose square comes within the radius
    dx = np.maximum(np.abs(cx - x) - fm.cell / 2, 0)
    dz = np.maximum(np.abs(cz - z) - fm.cell / 2, 0)
    near = np.hypot(dx, dz) <= radius
    inside = (ii >= 0) & (jj >= 0) & (ii < fm.shape[0]) & (jj < fm.shape[1])
    if (near & ~inside).any():
        return False
    return bool(_proven_free(fm, ii[near], jj[near]).all())


def _proven_free(fm: FloorMap, i, j) -> np.ndarray:
    """FREE, and (on a map that says, :attr:`FloorMap.assumed`) not by
    assumption only: what a pivot's cells must be.  On a map that keeps them
    (:attr:`FloorMap.drift_kept`, ``free_drift="moves"``) a cell the drift's
    erosion took, and nothing drew over since, counts as FREE: a pivot turns the
    footprint about where it stands, and what the erosion guards against is a
    move carried by the estimate's drift into what an older look placed."""
    ok = fm.cells[i, j] == FREE
    if fm.drift_kept is not None:
        ok = ok | (fm.drift_kept[i, j] & (fm.cells[i, j] == UNKNOWN))
    return ok if fm.assumed is None else ok & ~fm.assumed[i, j]


def pivot_radius_ft(prof: VehicleProfile, margin: bool = False) -> float:
    """The circle a pivot in place needs seen free (``pivot="disc"``): the
    footprint's half diagonal (``radius_ft``); with ``margin``
    (``pivot="margin"``, a named option) plus the planning margin
    (``margin_ft``) against the estimate's error, as a forward move keeps the
    planning radius from known obstacles and ``pivot="swept"`` grows the
    footprint by the margin.  The half diagonal alone leaves a pivot no room
    for the estimate's error: in room 35 (oracle edges, ``--look-ahead``) the
    estimate stood 0.19 ft off the truth at the end of a move, the circle
    about it was seen free only because three cells of a box's side showed
    free, and the true footprint hit the box's corner 2 deg into the turn
    (docs/planner.md, "The planner's own ceiling")."""
    return prof.radius_ft + (prof.margin_ft if margin else 0.0)


def _edge_to_edge(half: float, spacing: float) -> np.ndarray:
    """Offsets from ``-half`` to ``+half``, both edges included, at most
    ``spacing`` apart: how a footprint's or a band's width is sampled (a
    range stepped from one edge stops short of the other; the band's did,
    until 2026-12-05 19:50)."""
    return np.linspace(-half, half, int(math.ceil(2 * half / spacing)) + 1)


def _swept_cells(fm: FloorMap, x: float, z: float, heading_deg: float, angle_deg: float,
                 half_width: float, half_length: float, step_deg: float = 2.0):
    """(i, j, inside): the cells a rectangle of ``half_width`` by
    ``half_length`` about (x, z) covers, its edges included (sampled a quarter
    cell apart), while it turns from ``heading_deg`` through ``angle_deg``
    (at headings at most ``step_deg`` apart; 0: where it stands), and which
    of them lie on the map."""
    q = fm.cell / 4
    across, along = (g.ravel() for g in np.meshgrid(_edge_to_edge(half_width, q),
                                                     _edge_to_edge(half_length, q)))
    n = max(1, int(math.ceil(abs(angle_deg) / step_deg)))
    hs = np.radians(heading_deg + np.linspace(0.0, angle_deg, n + 1))
    px = x + across[None] * np.cos(hs)[:, None] + along[None] * np.sin(hs)[:, None]
    pz = z - across[None] * np.sin(hs)[:, None] + along[None] * np.cos(hs)[:, None]
    i = np.floor((pz.ravel() - fm.z0) / fm.cell).astype(int)
    j = np.floor((px.ravel() - fm.x0) / fm.cell).astype(int)
    return i, j, (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])


def _pivot_seen_free(fm: FloorMap, x: float, z: float, heading_deg: float, angle_deg: float,
                     footprint, margin_ft: float, step_deg: float = 2.0,
                     ring: str = "seen", inner_ft: float = 0.0) -> bool:
    """Every cell the footprint (``(width, length)``, grown by ``margin_ft`` on
    each side) covers while it pivots about (x, z) from ``heading_deg``
    through ``angle_deg`` is FREE: sampled a quarter cell apart over the
    rectangle (its edges included) at headings at most ``step_deg`` apart.  A
    turn of a degree sweeps hardly more than the footprint itself, where the
    whole disc of :func:`_disc_seen_free` asks for every cell within the half
    diagonal whatever the angle.  With ``ring="known"`` (``pivot="swept-ring"``)
    only the bare footprint's cells must be FREE; a cell only the margin's
    ring covers may instead be one never seen, provided no look has placed
    anything (occupied, uncertain) within the planning radius of it.  The
    fixed rig never shows the floor beside the vehicle (nearer than
    :func:`near_visible_ft`), and in room 523 a pivot it needed swept one
    such cell 0.94 ft from its centre, beyond the bare footprint's 0.64 ft
    reach, 4 ft from anything seen.  The margin stands for the estimate's
    error, and a never-seen cell beside something seen may be that thing's
    unseen part: without the radius, room 857's pivot (the estimate 0.2 ft
    off) hit a box whose far part's uncertain cells lay 0.5 ft beyond the
    ring's cells (docs/planner.md, "The margin's ring").  ``inner_ft``
    (``pivot="swept-ring-inner"``, for a turn made only to look): the footprint
    grown by that much must be FREE as well, only the ring beyond it may be
    never seen: the floor in view proves a cell free up to a box face that
    stands a little way into it (room 32: 0.08 ft), and a box no look located
    leaves the cell beyond it never seen, one the bare footprint's reach misses
    by 0.03 ft."""
    def cells(grow):
        return _swept_cells(fm, x, z, heading_deg, angle_deg,
                            footprint[0] / 2 + grow, footprint[1] / 2 + grow, step_deg)

    i, j, on_map = cells(margin_ft)
    if not on_map.all():
        return False
    free = _proven_free(fm, i, j)
    if ring == "seen":
        return bool(free.all())
    bi, bj, _ = cells(min(inner_ft, margin_ft))
    if not _proven_free(fm, bi, bj).all():
        return False
    # the ring's cells not seen free: each clear of anything a look placed, by the
    # footprint's half diagonal grown by the margin (the planning radius)
    ui, uj = i[~free], j[~free]
    if not len(ui):
        return True
    reach = math.hypot(*footprint) / 2 + margin_ft
    # (on the window that holds every cell within reach of them: a pivot check is
    # made many times a cycle)
    n = int(math.ceil(reach / fm.cell))
    i0, j0 = max(int(ui.min()) - n, 0), max(int(uj.min()) - n, 0)
    window = fm.cells[i0:int(ui.max()) + n + 1, j0:int(uj.max()) + n + 1]
    return bool(_far_from_placed(window, fm.cell, reach)[ui - i0, uj - j0].all())


def _far_from_placed(cells: np.ndarray, cell_ft: float, reach_ft: float) -> np.ndarray:
    """Bool like ``cells``: no occupied or uncertain cell within ``reach_ft``,
    centre to centre (beyond the array's edge counts as nothing placed)."""
    placed = (cells == OCCUPIED) | (cells == UNCERTAIN)
    if not placed.any():
        return np.ones(cells.shape, bool)
    dist = cv2.distanceTransform((~placed).astype(np.uint8), cv2.DIST_L2,
                                 cv2.DIST_MASK_PRECISE) * cell_ft
    return dist > reach_ft + 1e-9


def clear_unseen(fm: FloorMap, reach_ft: float) -> np.ndarray:
    """(nz, nx) bool: the never-seen cells of ``fm`` with no occupied or
    uncertain cell within ``reach_ft`` of them, centre to centre (the map's
    edge counts as nothing placed).  ``DriveConfig.move_ring`` "known" (or
    "start": where the move starts) lets a forward move's band beyond the bare
    footprint cross these, as the pivot's rule under ``pivot="swept-ring"``
    lets its ring (:func:`_pivot_seen_free`)."""
    return (fm.cells == UNKNOWN) & _far_from_placed(fm.cells, fm.cell, reach_ft)


def pivot_allowed(fm: FloorMap, est: State, angle_deg: float, prof: VehicleProfile,
                  pivot_sweep=None, pivot_ft: float | None = None) -> bool:
    """A pivot of ``angle_deg`` where the estimate stands may be made: by the
    rule :func:`safe_prefix` applies to every TURN (:func:`_pivot_ok`: its
    circle of ``pivot_ft``, by default :func:`pivot_radius_ft`, seen free, or
    with ``pivot_sweep`` the cells its grown footprint sweeps).  Every pivot the loop
    issues outside a planned prefix (facing the path, turning to look) passes
    it; before 2026-12-01 18:45 the turn that faces the path after a refused
    prefix did not, and in room 35 it turned the vehicle into a box."""
    return _pivot_ok(fm, est.x, est.z, est.heading_deg, angle_deg,
                     pivot_radius_ft(prof) if pivot_ft is None else pivot_ft, pivot_sweep)


PIVOT_INNER_FT = 0.1         # pivot="swept-ring-inner": the ring's inner part seen free
SMALL_TURN_DEG = 5.0         # pivot="small-swept": a turn this small needs only its sweep


class PivotSweep(NamedTuple):
    """What a pivot judged by its sweep needs (:func:`_pivot_seen_free`):
    the footprint ``(width, length)`` grown by ``margin_ft``, for turns up to
    ``up_to_deg`` (larger ones by the disc), the margin's ``ring`` "seen"
    free or only "known" clear (``DriveConfig.pivot``: "swept",
    "small-swept", "swept-ring")."""
    footprint: tuple[float, float]
    margin_ft: float
    up_to_deg: float = math.inf
    ring: str = "seen"
    inner_ft: float = 0.0      # ring "known": the ring's first inner_ft seen free as well


def inner_ring_sweep(prof: VehicleProfile) -> PivotSweep:
    """What a turn made only to look needs under ``pivot="swept-ring-inner"``: the
    swept ring's rule with its inner :data:`PIVOT_INNER_FT` seen free."""
    return PivotSweep(prof.footprint, prof.margin_ft, ring="known", inner_ft=PIVOT_INNER_FT)


def _pivot_ok(fm: FloorMap, x: float, z: float, h: float, angle_deg: float, pivot_ft: float,
              pivot_sweep: PivotSweep | None = None) -> bool:
    """The pivot rule: ``pivot_sweep`` given and the turn no larger than its
    ``up_to_deg``: the cells the grown footprint sweeps
    (:func:`_pivot_seen_free`); otherwise the circle of ``pivot_ft`` seen
    free (:func:`_disc_seen_free`; none for ``pivot_ft`` 0)."""
    if pivot_sweep is not None and abs(angle_deg) <= pivot_sweep.up_to_deg:
        return _pivot_seen_free(fm, x, z, h, angle_deg, pivot_sweep.footprint,
                                pivot_sweep.margin_ft, ring=pivot_sweep.ring,
                                inner_ft=pivot_sweep.inner_ft)
    return pivot_ft <= 0 or _disc_seen_free(fm, x, z, pivot_ft)


HALF_FOV_DEG = 19.5          # atan(64 / 180): half the 128-px picture's width


EYES_TURN_DEG = 15.0         # a smaller turn keeps the way ahead inside the view just seen


def looked_free(fm: FloorMap, est: State, max_range: float) -> FloorMap:
    """A copy of ``fm`` whose never-seen cells inside the field of view just
    looked at (within ``max_range``) count as free: the look located nothing
    nearer there.  Occupied and uncertain cells stay as they are."""
    out = FloorMap(fm.cells.copy(), fm.x0, fm.z0, fm.cell)
    nz, nx = fm.shape
    xs, zs = fm.centre(np.arange(nz)[:, None], np.arange(nx)[None, :])
    dx, dz = xs - est.x, zs - est.z
    bearing = np.degrees(np.arctan2(dx, dz))
    off = np.abs((bearing - est.heading_deg + 180.0) % 360.0 - 180.0)
    wedge = (off <= HALF_FOV_DEG) & (np.hypot(dx, dz) <= max_range)
    out.cells[wedge & (fm.cells == UNKNOWN)] = FREE
    return out


HALF_VFOV_DEG = math.degrees(math.atan(60 / 180))     # half the 120-line picture's height


def near_visible_ft(profile: VehicleProfile, lowest_obstacle_ft: float,
                    tilt_deg: float = 0.0) -> float:
    """The distance from which an obstacle ``lowest_obstacle_ft`` tall shows in
    the picture (the lower edge of the view, pitched by the profile and tilted
    ``tilt_deg`` more by the head, reaches its top): nearer than that a look
    proves no floor free.  With the default profile (pitch -25 deg, the lower
    edge 43.4 deg down) an 0.8 ft box shows from 2.2 / tan 43.4 deg = 2.32 ft;
    tilted 25 deg more (pitch -50, the edge 68.4 deg down) from 0.87 ft; a lower
    edge at or past the vertical sees the floor at the vehicle's centre (0)."""
    down = -(profile.camera_pitch_deg + tilt_deg) + HALF_VFOV_DEG
    if down <= 0:
        return math.inf
    if down >= 90.0:
        return 0.0
    return (profile.camera_height_ft - lowest_obstacle_ft) / math.tan(math.radians(down))


def far_floor_ft(profile: VehicleProfile, tilt_deg: float = 0.0) -> float:
    """The farthest floor a look shows (the upper edge of the view, pitched by
    the profile and the head's tilt, meets the floor; inf when that edge
    looks level or up).  Pitch -25 deg: the edge 6.6 deg down, 26 ft; tilted
    to -80: 61.6 deg down, 1.6 ft.  A column that shows nothing proves nothing
    beyond it: the loop with a head bounds the blank-column assumption by it."""
    up = profile.camera_pitch_deg + tilt_deg + HALF_VFOV_DEG
    if up >= 0:
        return math.inf
    return profile.camera_height_ft / math.tan(math.radians(-up))


def head_blank_ft(blank_ft: float | None, prof: VehicleProfile, pan_deg: float,
                  tilt_deg: float, bounded: bool = False) -> float | None:
    """How far a look of the head at (``pan_deg``, ``tilt_deg``) assumes its
    blank columns free (``DriveConfig.blank_ft``; None: not at all).  A look
    the head turned assumes nothing: tilted at a box near by its whole picture
    may be one blank face (room 48, the 1985 eyes: carved free through it, a
    collision), and panned it looks where no straight-ahead look went first
    (room 98, oracle edges: a blank box face carved, a collision).  Straight
    ahead it assumes as the fixed rig, no farther than the floor it shows
    (:func:`far_floor_ft`, 26 ft on the mount: the same).  ``bounded``
    (``floor_eyes="bound"``: each assumed line ends where its column's floor
    in view ends, :func:`planner.appearance.bound_by_floor`) lets a panned
    look assume as a straight one: a side no straight look saw first ends
    the floor in the picture unless it is the floor's grey.  A tilted look
    still assumes nothing: tilted down at a box near by, a column may show
    no floor's end at all, only the face (room 237 under ``head="assist"``,
    the improved matcher: a look panned 24 deg and tilted -29 deg carved a
    strip 0.13 ft inside a box's face by its blank columns, and the next move
    touched it)."""
    if not blank_ft or tilt_deg != 0 or (pan_deg != 0 and not bounded):
        return None
    return min(blank_ft, far_floor_ft(prof))


def head_aim(x: float, z: float, heading_deg: float, cell, prof: VehicleProfile,
             lowest_obstacle_ft: float, margin_ft: float) -> tuple[float, float]:
    """(pan, tilt) in degrees that bring ``cell`` (x, z) into the picture of a
    head standing at (x, z) with the body heading ``heading_deg``
    (``DriveConfig.head="pan-tilt"``): the pan that puts the cell in the
    picture's middle column (its bearing less the heading), and the least
    downward tilt whose :func:`near_visible_ft` is no more than the cell's
    distance less ``margin_ft`` (so the look shows the top of an obstacle
    ``lowest_obstacle_ft`` tall standing there, and sees farther than a
    steeper tilt would): the lower edge must look
    ``atan((height - lowest) / (d - margin))`` down, so the pitch is
    ``HALF_VFOV_DEG`` less that, the tilt that pitch less the mount's.  Both
    clipped to the profile's limits (no tilt above the mount's pitch: 0 when
    the mount already shows it), rounded to 0.01 deg (as they are commanded)."""
    d = math.hypot(cell[0] - x, cell[1] - z)
    lo, hi = prof.pan_limits_deg
    pan = min(max(wrap(heading_to((x, z), cell) - heading_deg), lo), hi)
    tlo, thi = prof.tilt_limits_deg
    reach = d - margin_ft
    if reach <= 0:
        tilt = tlo
    else:
        down = math.degrees(math.atan2(prof.camera_height_ft - lowest_obstacle_ft, reach))
        tilt = HALF_VFOV_DEG - down - prof.camera_pitch_deg
    tilt = min(max(tilt, tlo), min(thi, 0.0))
    return round(pan, 2), round(tilt, 2)


def unseen_in_circle(fm: FloorMap, x: float, z: float, radius: float):
    """The cell nearest (x, z) among those whose square comes within ``radius``
    of it (the pivot circle, as :func:`_disc_seen_free` tests it) and that are
    neither FREE nor OCCUPIED (never seen, or hit once: another look may clear
    them): its centre, or None when there is none (off the map: None too, the
    pivot is refused for it and no look can help)."""
    n = int(math.ceil(radius / fm.cell)) + 1
    i0, j0 = fm.index(x, z)
    ii, jj = np.mgrid[i0 - n:i0 + n + 1, j0 - n:j0 + n + 1]
    inside = (ii >= 0) & (jj >= 0) & (ii < fm.shape[0]) & (jj < fm.shape[1])
    ii, jj = ii[inside], jj[inside]
    cx, cz = fm.centre(ii, jj)
    dx = np.maximum(np.abs(cx - x) - fm.cell / 2, 0)
    dz = np.maximum(np.abs(cz - z) - fm.cell / 2, 0)
    c = fm.cells[ii, jj]
    m = (np.hypot(dx, dz) <= radius) & ((c == UNKNOWN) | (c == UNCERTAIN))
    if not m.any():
        return None
    d = np.hypot(cx[m] - x, cz[m] - z)
    q = int(np.argmin(d))
    return float(cx[m][q]), float(cz[m][q])


def _band_seen(known: np.ndarray, fm: FloorMap, samples: np.ndarray, heading_rad: float,
               half_width: float) -> np.ndarray:
    """For each sample of a straight move: every cell across the vehicle's
    swept width (``half_width`` each side of the centre line, both edges
    sampled, at most half a cell apart) has been seen.  (Until 2026-12-05
    19:50 the samples ran from the left edge in steps of half a cell and
    stopped short of the right one: 0.45 ft of the grown 0.55.)"""
    right = np.array([math.cos(heading_rad), -math.sin(heading_rad)])
    offs = _edge_to_edge(half_width, fm.cell / 2)
    pts = samples[:, None, :] + offs[None, :, None] * right[None, None, :]
    i = np.floor((pts[..., 1] - fm.z0) / fm.cell).astype(int)
    j = np.floor((pts[..., 0] - fm.x0) / fm.cell).astype(int)
    inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    ok = np.zeros(i.shape, bool)
    ok[inside] = known[i[inside], j[inside]]
    return ok.all(1)


def _narrow_ok(safe: Passable, ext: np.ndarray, n: int, nose_n: int) -> np.ndarray:
    """(n,) bool: for each of the first ``n`` positions of ``ext`` (a move's samples
    and ``nose_n`` more ahead of its end), whether it and the ``nose_n`` samples
    ahead of it all lie in ``safe.narrow`` cells (planner.passage)."""
    fm = safe.fmap
    i = np.floor((ext[:, 1] - fm.z0) / fm.cell).astype(int)
    j = np.floor((ext[:, 0] - fm.x0) / fm.cell).astype(int)
    inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    good = np.zeros(len(ext), bool)
    good[inside] = safe.narrow[i[inside], j[inside]]
    return np.convolve(~good, np.ones(nose_n + 1), mode="full")[nose_n:nose_n + n] == 0


def safe_prefix(cmds, est: State, safe: Passable, seen: np.ndarray, step: float,
                 seen_eyes: np.ndarray | None = None, half_width: float = 0.5,
                 nose_ft: float = 0.5, pivot_ft: float = 0.0, pivot_sweep=None,
                 looked_deg: float | None = None, min_pivot_deg: float = 0.0,
                 margin_ft: float = 0.0):
    """The first ``step`` ft of ``cmds``, each FORWARD cut where the vehicle
    would come nearer than its radius to an occupied or uncertain cell
    (``safe``), or where its swept width (``half_width`` each side) would
    enter a cell never seen (``seen``;
    ``seen_eyes`` adds the field of view just looked at, used while the vehicle
    still faces the way it looked).  A turn is a pivot: it needs every cell
    within ``pivot_ft`` (the footprint's half diagonal) seen free, or, given
    ``pivot_sweep`` (a named option: the footprint and the margin,
    ``DriveConfig.pivot="swept"``), every cell that footprint grown by the margin
    sweeps through the turn (:func:`_pivot_seen_free`); a turn smaller than
    ``min_pivot_deg`` needs neither (``DriveConfig.min_pivot_deg``: it moves
    the footprint's corners less than the planning margin).  After turns of more
    than ``EYES_TURN_DEG`` in all it stops before the next forward move, to
    look the new way first; ``looked_deg`` (a head's pan at the look just
    taken, ``DriveConfig.head``) lets the move on when the turns' net angle
    ends within ``EYES_TURN_DEG`` of the way that look faced: the head has
    looked the new way already.  ``margin_ft`` (the planning margin in
    ``half_width`` and ``nose_ft``), on a map with :attr:`FloorMap.move_ring`
    (``DriveConfig.move_ring="known"``): the band beyond the bare footprint may
    cross the cells it marks; with :attr:`FloorMap.move_ring_start`
    (``"start"``, the default) only where the grown footprint stands at the
    move's start, which any pivot there sweeps as well.  ``safe.narrow``
    (``DriveConfig.passage`` other than "circle"): a position also passes where
    it and every sample out to the grown nose ahead of it lie in those cells
    (the grown half width clear), short of the planning radius."""
    out = []
    x, z, h = est.x, est.z, est.heading_deg
    turned = 0.0
    net = 0.0
    fm = safe.fmap
    for c in next_segment(cmds, step):
        if isinstance(c, Turn):
            if abs(c.angle_deg) >= min_pivot_deg and \
                    not _pivot_ok(fm, x, z, h, c.angle_deg, pivot_ft, pivot_sweep):
                break                     # its circle (or sweep) reaches space not seen free
            out.append(c)
            h = wrap(h + c.angle_deg)
            turned += abs(c.angle_deg)
            net += c.angle_deg
            continue
        if not isinstance(c, Forward):
            break
        looked_way = looked_deg is not None and abs(wrap(net - looked_deg)) <= EYES_TURN_DEG
        if turned > EYES_TURN_DEG and out and not looked_way:
            break                         # look the new way before driving into it
        known = seen_eyes if (seen_eyes is not None and turned <= EYES_TURN_DEG) else seen
        hr = math.radians(h)
        end = (x + c.distance_ft * math.sin(hr), z + c.distance_ft * math.cos(hr))
        s = segment_samples((x, z), end, fm.cell / 4)
        i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
        j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
        inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        # each position needs the band seen on to the vehicle's nose ahead of it
        step_s = fm.cell / 4
        m = int(math.ceil(nose_ft / step_s))
        ext = np.vstack([s, end + (np.arange(1, m + 1) * step_s)[:, None] *
                         np.array([math.sin(hr), math.cos(hr)])[None, :]])

        def band_ok(cells_known, half, nose_n):
            # each position's band (``half`` each side) seen on to ``nose_n`` samples ahead
            bs = _band_seen(cells_known, fm, ext[:len(s) + nose_n], hr, half)
            return np.convolve(~bs, np.ones(nose_n + 1), mode="full")[nose_n:nose_n + len(s)] == 0
        if fm.move_ring is None or margin_ft <= 0:
            seen_band = band_ok(known, half_width, m)
        else:
            # the band out to the margin seen or in FloorMap.move_ring (under
            # move_ring_start only where the grown footprint stands at the move's
            # start, as a pivot there may sweep it); the bare footprint's band, to
            # its own nose, seen
            ring = fm.move_ring
            if fm.move_ring_start:
                ring = np.zeros_like(ring)
                ci, cj, on_map = _swept_cells(fm, x, z, h, 0.0, half_width, nose_ft)
                ci, cj = ci[on_map], cj[on_map]
                ring[ci, cj] = fm.move_ring[ci, cj]
            seen_band = band_ok(known | ring, half_width, m) & band_ok(
                known, half_width - margin_ft, int(math.ceil((nose_ft - margin_ft) / step_s)))
        ok = np.zeros(len(s), bool)
        near = np.zeros(len(s), bool)
        if safe.at == "centre":
            # each position by its own exact distance to the blocked cells
            cl = clearance_at(safe, s)
            ok = (cl >= safe.radius - 1e-9) & seen_band & inside
            near = (cl >= cl[0] - 1e-9) & seen_band & inside
        else:
            passable = safe.ok[i[inside], j[inside]]
            if safe.narrow is not None:
                # (DriveConfig.passage "moves" and after) or the grown half width
                # clear at every position out to the grown nose ahead of it: the
                # union of those discs holds the band the grown footprint sweeps
                passable = passable | _narrow_ok(safe, ext, len(s), m)[inside]
            ok[inside] = passable & seen_band[inside]
            # the vehicle may leave a cell it stands in even if a (perhaps false)
            # obstacle came near it, as long as it gets no nearer
            cl0 = safe.clearance[i[0], j[0]] if inside[0] else 0.0
            near[inside] = (safe.clearance[i[inside], j[inside]] >= cl0 - 1e-9) & \
                seen_band[inside]
        good = ok | (near & (np.arange(len(s)) * fm.cell / 4 <= 1.0))
        bad = np.flatnonzero(~good)
        if len(bad) == 0:
            out.append(c)
            x, z = end
            continue
        k = bad[0] - 1
        d = max(0.0, k * c.distance_ft / (len(s) - 1)) if k > 0 else 0.0
        if d > 0.05:
            out.append(Forward(round(d, 3)))
        break
    return out


STEER_MAX_DEG = 10           # DriveConfig.steer: the largest heading change tried, in whole degrees
STEER_GAIN_FT = 0.25         # ... and the least it must add to the move the path's heading allows


def steered_prefix(cmds, seg, prefix, step: float, max_deg: int = STEER_MAX_DEG,
                   gain_ft: float = STEER_GAIN_FT):
    """(``[TURN t, FORWARD d]``, the change in degrees) or None
    (``DriveConfig.steer`` "idle" and "small"; not 1985): where the path's first
    leg is cut short (``seg``, :func:`safe_prefix` of ``cmds``), the same leg
    on a heading up to ``max_deg`` off the path's, in whole degrees, nearest
    first, that ``prefix`` (safe_prefix with the cycle's own map and rules)
    lets run at least ``gain_ft`` farther; of those the longest (the smallest
    change on a tie).  A path's leg is a line between
    cell centres, its band checked against cells a look may have shown only to
    within a few hundredths of a foot of it: the band's edge grazes a never-seen
    cell beside the vehicle, which the fixed rig cannot show (room 10: 2 deg
    to the left, the whole 1.3 ft).  Every move it returns passes the same
    checks as the path's own."""
    first = next_segment(cmds, step)
    lead = 0.0
    want = 0.0
    for c in first:
        if isinstance(c, Turn):
            lead += c.angle_deg
            continue
        if isinstance(c, Forward):
            want = c.distance_ft
        break
    got = _leading_forward(seg)
    if want - got < gain_ft:
        return None
    best, best_d = None, got + gain_ft - 1e-9
    for k in range(1, max_deg + 1):
        for off in (k, -k):
            trial = prefix([Turn(round(lead + off, 2)), Forward(want)])
            d = _leading_forward(trial)
            if d > best_d + 1e-9:
                best, best_d = (trial, off), d
    return best


def _leading_forward(seg) -> float:
    """The distance of the first forward move of ``seg`` after its leading turns (0 if none)."""
    for c in seg:
        if isinstance(c, Forward):
            return c.distance_ft
        if not isinstance(c, Turn):
            break
    return 0.0


def _blocker(fm: FloorMap, safe: Passable, pts, near_ft: float):
    """Where the path's execution would stop for want of evidence: the first
    sample of the path (a quarter cell apart) outside the space seen free, or
    within the vehicle's radius of an uncertain cell, and the cell to look at
    there (the nearest cell not seen free: unknown or uncertain).  None when
    the path has no such place."""
    look_at = (fm.cells == UNKNOWN) | (fm.cells == UNCERTAIN)
    if not look_at.any():
        return None
    n = int(math.ceil((safe.radius + fm.cell) / fm.cell))
    for a, b in zip(pts[:-1], pts[1:]):
        s = segment_samples(a, b, fm.cell / 4)
        i = np.floor((s[:, 1] - fm.z0) / fm.cell).astype(int)
        j = np.floor((s[:, 0] - fm.x0) / fm.cell).astype(int)
        inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        bad = ~inside
        bad[inside] = (fm.cells[i[inside], j[inside]] != FREE) | ~safe.ok[i[inside], j[inside]]
        for k in np.flatnonzero(bad):
            if not inside[k]:
                return None
            i0, j0 = i[k], j[k]
            ii, jj = fm.square_around(i0, j0, n)
            m = look_at[ii, jj]
            if not m.any():
                continue                  # near a confirmed obstacle: nothing to look at
            cx, cz = fm.centre(ii[m], jj[m])
            d = np.hypot(cx - s[k, 0], cz - s[k, 1])
            q = int(np.argmin(d))
            return float(cx[q]), float(cz[q])
    return None


def _viewpoint(fm: FloorMap, safe_seen: Passable, est: State, target, near_ft: float,
               tried, far_ft: float = 2.0):
    """A path (polyline) through space seen free to a place from which
    ``target`` can be looked at: between ``near_ft`` + 0.3 ft and ``near_ft`` +
    ``far_ft`` from it (nearer, a look proves nothing there), not within 0.5 ft
    of a place in ``tried``, the nearest such place first.  None without one."""
    p = escape_start(safe_seen, (est.x, est.z))
    si, sj = fm.index(est.x, est.z)
    if not fm.inside(si, sj) or not p.ok[si, sj]:
        return None
    _, comp = cv2.connectedComponents(p.ok.astype(np.uint8), connectivity=8)
    ii, jj = np.nonzero(comp == comp[si, sj])
    cx, cz = fm.centre(ii, jj)
    dt = np.hypot(cx - target[0], cz - target[1])
    keep = (dt >= near_ft + 0.3) & (dt <= near_ft + far_ft)
    for q in tried + [(est.x, est.z)]:
        keep &= np.hypot(cx - q[0], cz - q[1]) > 0.5
    if not keep.any():
        return None
    cx, cz = cx[keep], cz[keep]
    order = np.argsort(np.hypot(cx - est.x, cz - est.z))
    for k in order[:4]:
        v = (float(cx[k]), float(cz[k]))
        try:
            return shorten(p, astar(p, (est.x, est.z), v))
        except NoPath:
            continue
    return None


def back_prefix(est: State, dist: float, safe: Passable, seen, prof: VehicleProfile) -> list:
    """``[BACK d]``: as far as ``dist`` (at most the profile's step) straight
    back along the heading, cut by the same rules as a forward move
    (:func:`safe_prefix` on the heading turned round: the swept width and
    the tail seen free, nothing known within the radius); ``[]`` when less
    than 0.05 ft is allowed."""
    dist = min(dist, prof.step_ft)
    if dist <= 0.05:
        return []
    behind = State(est.x, est.z, wrap(est.heading_deg + 180.0))
    seg = safe_prefix([Forward(dist)], behind, safe, seen, dist, None, *prof.grown_half_ft,
                       0.0, margin_ft=prof.margin_ft)
    d = sum(c.distance_ft for c in seg if isinstance(c, Forward))
    return [Back(round(d, 3))] if d > 0.05 else []


def backs_over_map(prof: VehicleProfile, cfg) -> bool:
    """May the vehicle ``BACK`` straight over space seen free (:func:`back_prefix`):
    its profile reverses and ``cfg.backing`` is "map".  Under "trail" it backs only to
    retrace its own way (:func:`retrace`)."""
    return prof.reverse and cfg.backing == "map"


def push_trail(trail: list, cmd) -> None:
    """Add the executed motion ``cmd`` to ``trail`` (the run's own way back,
    :func:`retrace`), cancelling what it undoes: a ``BACK`` against the
    ``FORWARD`` before it, a ``TURN`` merged with the ``TURN`` before it (the
    sweep of the merged turn lies inside the two it replaces).  ``PAN``,
    ``TILT`` and ``STOP`` move no wheel and are left out; an ``ARC`` is kept
    (and ends a retrace)."""
    if not isinstance(cmd, (Turn, Back, Forward, Arc)):
        return
    if isinstance(cmd, Turn):
        if trail and isinstance(trail[-1], Turn):
            cmd = Turn(trail.pop().angle_deg + cmd.angle_deg)
        if abs(cmd.angle_deg) > 1e-6:
            trail.append(cmd)
        return
    if isinstance(cmd, Back):
        d = cmd.distance_ft
        while d > 1e-6 and trail and isinstance(trail[-1], Forward):
            f = trail.pop().distance_ft
            if f > d + 1e-6:
                trail.append(Forward(f - d))
            d -= f
        if d > 1e-6:
            trail.append(Back(d))
        return
    if isinstance(cmd, Forward) and cmd.distance_ft <= 1e-6:
        return
    trail.append(cmd)


def retrace(trail, want_ft: float) -> list:
    """The commands that undo the last motions of ``trail`` (:func:`push_trail`),
    newest first, until ``want_ft`` of travel is undone: a ``TURN`` turned
    back, a ``FORWARD`` backed (the last one cut to what is still wanted),
    a ``BACK`` driven forward again.  It stops at an ``ARC`` and at the
    trail's start.  [] when no travel would be undone (a retrace that only
    turns gets the vehicle nowhere new).

    The vehicle swept the ground of every motion it made, so their undoing
    sweeps that ground again (up to the odometry's error of the undoing):
    no look has to have shown it free."""
    out, done = [], 0.0
    for cmd in reversed(trail):
        if done >= want_ft - 1e-6 or isinstance(cmd, Arc):
            break
        if isinstance(cmd, Turn):
            out.append(Turn(-cmd.angle_deg))
        elif isinstance(cmd, (Forward, Back)):
            d = min(cmd.distance_ft, want_ft - done)
            out.append(Back(round(d, 3)) if isinstance(cmd, Forward) else Forward(round(d, 3)))
            done += d
    while out and isinstance(out[-1], Turn):
        out.pop()
    return out if done > 0.05 else []


TURN_ROOM_STEP_FT = 0.25     # turn_room="forward": the forward moves tried, this far apart


def forward_to_turn(fm: FloorMap, est: State, aims, safe: Passable, seen, prof: VehicleProfile,
                    pivot_sweep=None, pivot_ft: float | None = None,
                    step_ft: float = TURN_ROOM_STEP_FT) -> list | None:
    """``[FORWARD d, TURN t]`` for a vehicle that cannot pivot where it stands
    (``DriveConfig.turn_room="forward"``; not 1985): the shortest straight
    move along the heading, in steps of ``step_ft`` up to the profile's step,
    that the rules of every forward move allow (:func:`safe_prefix`: the
    swept width and the nose seen free, nothing known within the radius)
    and after which a pivot passes :func:`pivot_allowed`; ``t`` turns to the
    first heading of ``aims`` that may be taken there (each a function of the
    pose after the move, returning a heading in degrees or None).  None
    when no such move exists.  The pivot circle beside a vehicle is the
    floor nearest it, which the fixed rig never shows (nearer than
    :func:`near_visible_ft`); a little way on, the circle lies over floor
    the looks behind have shown."""
    n = int(math.floor(prof.step_ft / step_ft + 1e-9))
    for k in range(1, n + 1):
        d = k * step_ft
        seg = safe_prefix([Forward(d)], est, safe, seen, d, None, *prof.grown_half_ft, 0.0,
                          margin_ft=prof.margin_ft)
        if sum(c.distance_ft for c in seg if isinstance(c, Forward)) < d - 1e-6:
            return None                    # the move itself is refused from here on
        end = advance(est, Forward(d))
        for aim in aims:
            h = aim(end)
            if h is None:
                continue
            t = round(wrap(h - end.heading_deg), 2)
            if abs(t) >= 1.0 and pivot_allowed(fm, end, t, prof, pivot_sweep, pivot_ft):
                return [Forward(round(d, 3)), Turn(t)]
    return None


def fetch_evidence(fm: FloorMap, safe: Passable, seen, est: State, pts, near_ft: float,
                    prof: VehicleProfile, cfg, tried: dict):
    """(commands, note) that go and get the evidence the path lacks, or None.
    The place where the path's execution stops (:func:`_blocker`: a cell not
    seen free, or an uncertain cell within the vehicle's radius of it) is
    looked at: turned to, when it lies far enough (``near_ft``) to show in a
    look and outside the view just taken; otherwise (too near to show, or
    looked at from here already) the vehicle drives, through space seen free,
    to a place from which it can be seen (:func:`_viewpoint`), then turns to
    it.  ``tried`` maps each blocker's cell to the places it was looked at from."""
    u = _blocker(fm, safe, pts, near_ft)
    if u is None:
        return None
    return look_at(u, fm, safe, seen, est, near_ft, prof, cfg, tried)


def goal_blocker(fm: FloorMap, goal, radius: float):
    """The uncertain cell (hit by one look) nearest the goal among those within
    ``radius`` of it (centre distance), the one the refusal of a goal too near an
    obstacle on the map may owe most to: its centre (x, z), or None."""
    gi, gj = fm.index(*goal)
    n = int(math.ceil(radius / fm.cell)) + 1
    ii, jj = fm.square_around(gi, gj, n)
    m = fm.cells[ii, jj] == UNCERTAIN
    if not m.any():
        return None
    cx, cz = fm.centre(ii[m], jj[m])
    d = np.hypot(cx - goal[0], cz - goal[1])
    q = int(np.argmin(d))
    return (float(cx[q]), float(cz[q])) if d[q] <= radius else None


def _look_turn_ok(fm: FloorMap, est: State, angle_deg: float, prof: VehicleProfile, cfg) -> bool:
    """May :func:`look_at` turn in place to look: its circle seen free (the
    pivot's half diagonal, with the margin under ``pivot="margin"``); under
    ``pivot="swept-ring-inner"`` (not 1985) the swept ring's rule
    (:func:`pivot_allowed`), whose ring the circle does not check, with its
    inner ``PIVOT_INNER_FT`` seen free: a turn made only to look may wait for
    the floor beside the vehicle to be shown.  Room 32 turned to look with a
    box no look had located 0.58 ft from its centre."""
    if cfg.pivot != "swept-ring-inner":
        return _disc_seen_free(fm, est.x, est.z, pivot_radius_ft(prof, cfg.pivot == "margin"))
    return pivot_allowed(fm, est, angle_deg, prof, inner_ring_sweep(prof))


def look_at(u, fm: FloorMap, safe: Passable, seen, est: State, near_ft: float,
            prof: VehicleProfile, cfg, tried: dict):
    """(commands, note) that get a look at the cell ``u`` (fetch_evidence's
    turn, look again, back off or viewpoint), or None."""
    tried = tried.setdefault(fm.index(*u), [])
    here = (est.x, est.z)
    d = math.hypot(u[0] - here[0], u[1] - here[1])
    off = wrap(heading_to(here, u) - est.heading_deg)
    looked = sum(math.hypot(q[0] - here[0], q[1] - here[1]) <= 0.5 for q in tried)
    if d < near_ft + 0.2 and backs_over_map(prof, cfg) and abs(off) <= HALF_FOV_DEG - 4.0:
        # too near to show, and ahead: back straight off until it shows
        seg = back_prefix(est, near_ft + 0.5 - d, safe, seen, prof)
        if seg:
            return seg, f" (backing off to look at ({u[0]:.1f}, {u[1]:.1f}))"
    if d >= near_ft + 0.2 and looked < cfg.looks_per_viewpoint:
        if abs(off) <= HALF_FOV_DEG - 4.0:
            # the look just taken saw it and left it unresolved: a cell hit once
            # needs more than one look through it to be cleared; look again
            tried.append(here)
            return [], f" (looking again at ({u[0]:.1f}, {u[1]:.1f}))"
        if _look_turn_ok(fm, est, off, prof, cfg):
            return [Turn(round(off, 2))], f" (turning to look at ({u[0]:.1f}, {u[1]:.1f}))"
    seen_only = clearance_map(fm, prof.planning_radius_ft, "blocked", uncertain="blocked",
                              at=cfg.clearance_at)
    vp = _viewpoint(fm, seen_only, est, u, near_ft, tried)
    if vp is None or len(vp) < 2:
        return None
    cmds = to_commands(vp, est.heading_deg, prof.turning_radius_ft, seen_only)
    seg = safe_prefix(cmds, est, safe, seen, prof.step_ft, None, *prof.grown_half_ft,
                       pivot_radius_ft(prof, cfg.pivot == "margin"),
                       min_pivot_deg=cfg.min_pivot_deg, margin_ft=prof.margin_ft)
    if not any(isinstance(c, Forward) or abs(c.angle_deg) >= 1.0 for c in seg):
        return None
    return seg, (f" (to look at ({u[0]:.1f}, {u[1]:.1f}) from "
                 f"({vp[-1][0]:.1f}, {vp[-1][1]:.1f}))")


def first_unseen_on_band(fm: FloorMap, pts, half_width: float, ahead_ft: float):
    """The first cell along the planned path ``pts`` (a polyline from the
    vehicle) whose square the vehicle's swept width (``half_width`` each side of
    the centre line, sampled at most a quarter cell apart along and across, both
    edges included, as :func:`_band_seen` does) enters within the first
    ``ahead_ft`` of the path,
    and that no look has ever seen (UNKNOWN): its centre (x, z), or None when
    that whole band has been seen (cells off the map are left to
    :func:`safe_prefix`)."""
    left = ahead_ft
    q = fm.cell / 4
    offs = _edge_to_edge(half_width, q)
    for a, b in zip(pts[:-1], pts[1:]):
        a, b = np.asarray(a, float), np.asarray(b, float)
        length = float(np.hypot(*(b - a)))
        if length < 1e-9:
            continue
        if length > left:
            b, length = a + (b - a) * (left / length), left
        hr = math.atan2(b[0] - a[0], b[1] - a[1])
        right = np.array([math.cos(hr), -math.sin(hr)])
        s = segment_samples(tuple(a), tuple(b), q)
        p = s[:, None, :] + offs[None, :, None] * right[None, None, :]
        i = np.floor((p[..., 1] - fm.z0) / fm.cell).astype(int)
        j = np.floor((p[..., 0] - fm.x0) / fm.cell).astype(int)
        inside = (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
        unseen = np.zeros(i.shape, bool)
        unseen[inside] = fm.cells[i[inside], j[inside]] == UNKNOWN
        rows = np.flatnonzero(unseen.any(1))
        if len(rows):
            k = rows[0]
            # of that sample's unseen cells, the one nearest the centre line
            c = np.flatnonzero(unseen[k])[np.argmin(np.abs(offs[unseen[k]]))]
            cx, cz = fm.centre(i[k, c], j[k, c])
            return float(cx), float(cz)
        left -= length
        if left <= 1e-9:
            break
    return None


LOOK_AHEAD_FOV_MARGIN_DEG = 4.0    # the cell turned this far inside the view's edge


def look_ahead(seg, est: State, cell, near_ft: float, cell_ft: float):
    """The anticipatory look (``DriveConfig.look_ahead``, a named option, not
    1985): the cycle's commands ``seg`` cut where the vehicle would come nearer
    than ``near_ft`` + ``cell_ft`` to ``cell`` (the first never-seen cell on the
    path's swept band, :func:`first_unseen_on_band`: nearer, no look shows it),
    followed by the smallest pivot that brings ``cell`` inside the view
    (``HALF_FOV_DEG`` less a margin), so the next look, taken there, shows it.
    Returns the new commands, or None when nothing changes: the cell is
    already too near to show (the look came too late), or the commands never
    bring the vehicle that near and so need no cut.  Only pivots and straight
    moves are cut (an ARC leaves ``seg`` as it is).  The caller checks the
    result against the safety rules (:func:`safe_prefix`)."""
    far = near_ft + cell_ft
    x, z, h = est.x, est.z, est.heading_deg
    if math.hypot(cell[0] - x, cell[1] - z) < far:
        return None
    out = []
    for c in seg:
        if isinstance(c, Turn):
            out.append(c)
            h = wrap(h + c.angle_deg)
            continue
        if not isinstance(c, Forward):
            return None
        hr = math.radians(h)
        ux, uz = math.sin(hr), math.cos(hr)
        # the travel t at which |p + t u - cell| falls to far (the smaller root)
        rx, rz = cell[0] - x, cell[1] - z
        along = rx * ux + rz * uz
        disc = along * along - (rx * rx + rz * rz - far * far)
        if disc > 0 and along - math.sqrt(disc) < c.distance_ft:
            t = max(0.0, along - math.sqrt(disc))
            t = math.floor(t * 100) / 100          # never past the point
            if t > 0.05:
                out.append(Forward(round(t, 2)))
                x, z = x + t * ux, z + t * uz
            off = wrap(heading_to((x, z), cell) - h)
            need = abs(off) - (HALF_FOV_DEG - LOOK_AHEAD_FOV_MARGIN_DEG)
            if need > 0:
                out.append(Turn(round(math.copysign(need, off), 2)))
            return out
        out.append(c)
        x, z = x + c.distance_ft * ux, z + c.distance_ft * uz
    return None


def looked_ahead(seg, est: State, fm: FloorMap, pts, near_ft: float, safe, seen, seen_eyes,
                  prof: VehicleProfile, pivot_sweep, done: set, pivot_ft: float | None = None,
                  min_pivot_deg: float = 0.0):
    """(commands, note) of ``DriveConfig.look_ahead`` for this cycle's safe
    ``seg``, or None to drive ``seg`` as it is: the first never-seen cell on
    the swept band of the path's next step + ``near_ft`` (+ two cells), not
    turned to before (``done``), looked at while it can still show
    (:func:`look_ahead`); the new commands must pass
    :func:`safe_prefix` whole (its pivot included)."""
    half_width = prof.width_ft / 2 + prof.margin_ft
    cell = first_unseen_on_band(fm, pts, half_width, prof.step_ft + near_ft + 2 * fm.cell)
    if cell is None or fm.index(*cell) in done:
        return None
    new = look_ahead(seg, est, cell, near_ft, fm.cell)
    if not new:
        return None
    ok = safe_prefix(new, est, safe, seen, prof.step_ft, seen_eyes, half_width,
                      prof.length_ft / 2 + prof.margin_ft,
                      pivot_radius_ft(prof) if pivot_ft is None else pivot_ft, pivot_sweep,
                      min_pivot_deg=min_pivot_deg, margin_ft=prof.margin_ft)
    if len(ok) != len(new) or any(type(a) is not type(b) for a, b in zip(ok, new)):
        return None                       # its pivot (or move) breaks the safety rules
    done.add(fm.index(*cell))
    return new, f" (looking ahead at ({cell[0]:.1f}, {cell[1]:.1f}))"


def _cell_key(fm: FloorMap, cell) -> tuple[int, int]:
    """A cell's key that outlives the map (whose origin moves as it grows)."""
    return int(math.floor(cell[0] / fm.cell)), int(math.floor(cell[1] / fm.cell))


AIMED_FROM_FT = 0.3          # the head looks at one thing once from one place (this near)


def _looked_from(aimed: dict, key, x: float, z: float) -> bool:
    """The head has looked at ``key`` (a cell's :func:`_cell_key`, or a way)
    from within ``AIMED_FROM_FT`` of (x, z)."""
    return any(math.hypot(q[0] - x, q[1] - z) <= AIMED_FROM_FT for q in aimed.get(key, []))


def _aimed_from(aimed: dict, fm: FloorMap, cell, x: float, z: float) -> bool:
    return _looked_from(aimed, _cell_key(fm, cell), x, z)


def _aim(fm: FloorMap, cell, at: State, prof: VehicleProfile, cfg, aimed: dict):
    """(pan, tilt) at ``cell`` from ``at`` (:func:`head_aim`, the margin a
    cell), recorded in ``aimed``."""
    aimed.setdefault(_cell_key(fm, cell), []).append((at.x, at.z))
    return head_aim(at.x, at.z, at.heading_deg, cell, prof, cfg.lowest_obstacle_ft, fm.cell)


def shortcut_first_leg(cmds, est: State, min_ft: float = 0.3) -> list:
    """``cmds`` with a first straight move shorter than ``min_ft`` and the
    straight move after it (only turns between) replaced by one straight move
    from the estimate to where the second ends (the turn to it first, and a turn
    after it to the heading the original commands had there): a path whose
    first point is a cell centre a tenth of a foot off asks for a pivot to it,
    a step of nothing and a pivot back, and the pivots' sum stops the move as a
    turn not looked along (:func:`safe_prefix`, which still checks the new
    move whole).  Commands without such a leg are returned as they are.  Used
    with the head (``DriveConfig.head``)."""
    cmds = list(cmds)
    fwd = [k for k, c in enumerate(cmds) if isinstance(c, Forward)]
    if len(fwd) < 2 or cmds[fwd[0]].distance_ft >= min_ft or \
            not all(isinstance(c, Turn) for k, c in enumerate(cmds[:fwd[1]]) if k != fwd[0]):
        return cmds
    end = est
    for c in cmds[:fwd[1] + 1]:
        end = advance(end, c)
    d = math.hypot(end.x - est.x, end.z - est.z)
    if d < 1e-9:
        return cmds
    h = heading_to((est.x, est.z), (end.x, end.z))
    out = [Turn(round(wrap(h - est.heading_deg), 3)), Forward(round(d, 3))]
    back = wrap(end.heading_deg - h)
    if abs(back) >= 0.01:
        out.append(Turn(round(back, 3)))
    return out + cmds[fwd[1] + 1:]


def path_heading(est: State, pts, min_ft: float = 0.3) -> float | None:
    """The heading from the estimate to the first point of the path ``pts`` at
    least ``min_ft`` away (a path's first point may lie a hundredth of a foot
    off, and the bearing to it says nothing), None without one."""
    for p in pts[1:]:
        if math.hypot(p[0] - est.x, p[1] - est.z) >= min_ft:
            return heading_to((est.x, est.z), p)
    return None


def head_look(fm: FloorMap, safe: Passable, est: State, pts, goal, seg, prof: VehicleProfile,
              cfg, look_pan: float, pivot_ft: float, aimed: dict):
    """(commands, note) of the pan-tilt head (``DriveConfig.head="pan-tilt"``)
    for a cycle whose safe commands ``seg`` drive nowhere, or None (the loop
    then turns the body as without a head).  The head, not the body, looks at
    the first of:

    * the first never-seen cell on the swept band of the path's next step +
      ``near_visible_ft`` (+ two cells; :func:`first_unseen_on_band`): the
      blind zone beside the way that cut the move, tilted down to show it;
    * the never-seen (or once-hit) cell of the pivot circle nearest the
      vehicle (:func:`unseen_in_circle`): a pivot needs it seen free;
    * the cell where the path's execution stops for want of evidence
      (:func:`_blocker`: unseen, or uncertain within the radius);

    each at most once from one place (``aimed``: cell -> places); then the way
    the path turns (:func:`path_heading`), when more than ``EYES_TURN_DEG`` from
    the way the last look faced (``look_pan``), once from one place: the head
    faces the path and looks, and the next cycle's :func:`safe_prefix` lets the
    body turn and drive on at once."""
    near0 = near_visible_ft(prof, cfg.lowest_obstacle_ft)
    cands = []
    if len(pts) > 1:
        c = first_unseen_on_band(fm, pts, prof.width_ft / 2 + prof.margin_ft,
                                 prof.step_ft + near0 + 2 * fm.cell)
        if c is not None:
            cands.append((c, "the way"))
    c = unseen_in_circle(fm, est.x, est.z, pivot_ft)
    if c is not None:
        cands.append((c, "the pivot circle"))
    if len(pts) > 1:
        c = _blocker(fm, safe, pts, near0)
        if c is not None:
            cands.append((c, "the way's evidence"))
    for cell, what in cands:
        if math.hypot(cell[0] - est.x, cell[1] - est.z) < 1e-6 or \
                _aimed_from(aimed, fm, cell, est.x, est.z):
            continue
        pan, tilt = _aim(fm, cell, est, prof, cfg, aimed)
        return [Pan(pan), Tilt(tilt)], (f" (head at {what}: ({cell[0]:.1f}, {cell[1]:.1f}), "
                                        f"pan {pan:g} tilt {tilt:g})")
    way = path_heading(est, pts)
    if way is not None:
        t = wrap(way - est.heading_deg)
        lo, hi = prof.pan_limits_deg
        p = round(min(max(t, lo), hi), 2)
        key = ("way", int(round(p)))           # each way once from one place
        if abs(t) > EYES_TURN_DEG and abs(wrap(t - look_pan)) > EYES_TURN_DEG and \
                abs(wrap(p - look_pan)) > 1.0 and \
                not _looked_from(aimed, key, est.x, est.z):
            aimed.setdefault(key, []).append((est.x, est.z))
            return [Pan(p), Tilt(0.0)], f" (head to the path's way, pan {p:g})"
    return None


def head_commands(seg, est: State, fm: FloorMap, pts, prof: VehicleProfile, cfg,
                  pan: float, tilt: float, aimed: dict) -> list:
    """The cycle's commands with the pan-tilt head (``DriveConfig.head``):
    a ``seg`` that moves the body is driven with the head straight ahead
    (``PAN 0; TILT 0`` first when it is not), and is followed by the head's aim
    for the next look, from the pose the commands end at (exactly, as
    commanded): at the first never-seen cell on the swept band of the path
    beyond the move (the move's length + the next step + ``near_visible_ft`` +
    two cells), not aimed at from there before; straight ahead without one.
    A ``seg`` that moves nothing (the head's own look, or nothing) is returned
    as it is."""
    moves = any(isinstance(c, (Forward, Back)) or (isinstance(c, Turn) and c.angle_deg != 0)
                for c in seg)
    if not moves:
        return list(seg)
    body = [c for c in seg if not isinstance(c, (Pan, Tilt))]
    out = ([Pan(0.0), Tilt(0.0)] if (pan, tilt) != (0.0, 0.0) else []) + body
    end = est
    for c in body:
        end = advance(end, c)
    if len(pts) < 2:
        return out
    travel = sum(c.distance_ft for c in body if isinstance(c, (Forward, Back)))
    near0 = near_visible_ft(prof, cfg.lowest_obstacle_ft)
    cell = first_unseen_on_band(fm, pts, prof.width_ft / 2 + prof.margin_ft,
                                travel + prof.step_ft + near0 + 2 * fm.cell)
    if cell is None or math.hypot(cell[0] - end.x, cell[1] - end.z) <= fm.cell or \
            _aimed_from(aimed, fm, cell, end.x, end.z):
        return out
    p, t = _aim(fm, cell, end, prof, cfg, aimed)
    if (p, t) != (0.0, 0.0):
        out += [Pan(p), Tilt(t)]
    return out


APPROACH_STEP_DEG = 2.0      # approach="disc": the headings tried, this far apart


def disc_approach(est: State, goal, radius: float, safe: Passable, seen: np.ndarray,
                  prof: VehicleProfile, pivot_ft: float, pivot_sweep=None):
    """(commands, note) of the final move under ``DriveConfig.approach="disc"``
    (the default since 2026-12-02; "path" drives only the planned path), or
    None: of the straight moves (no longer than
    the profile's step, nor past the point of their line nearest the goal) cut
    where :func:`safe_prefix` cuts them (the swept width and nose seen, nothing
    known within the radius), the one that ends nearest the goal, when that
    end lies inside the disc of ``radius`` about it; the pivot to its heading
    must pass :func:`pivot_allowed`.  Chapter IV reaches the goal "within a
    tolerance"; the planned path ends at the goal point, and its last foot can
    need cells ahead of the vehicle's nose that no look showed free: nearer
    than ``near_visible_ft`` (2.3 ft) no look can show them, so the vehicle
    turns in place until its looks are used up (the bundled lab with oracle
    edges: 0.87 ft from its goal; docs/planner.md, "The last foot").  The
    headings tried are ``APPROACH_STEP_DEG`` apart from the vehicle's own,
    those whose line passes within ``radius`` of the goal; ties go to the
    smaller turn.  A pivot of more than ``EYES_TURN_DEG`` is
    made alone (the vehicle looks the new way before it drives, as
    :func:`safe_prefix` asks); the next cycle finds the same move ahead."""
    half_width = prof.width_ft / 2 + prof.margin_ft
    nose = prof.length_ft / 2 + prof.margin_ft
    rx, rz = goal[0] - est.x, goal[1] - est.z
    cands = []
    n = int(round(180.0 / APPROACH_STEP_DEG))
    for k in range(-n + 1, n + 1):        # turns from the heading, straight ahead among them
        turn = k * APPROACH_STEP_DEG
        h = wrap(est.heading_deg + turn)
        hr = math.radians(h)
        ux, uz = math.sin(hr), math.cos(hr)
        along = rx * ux + rz * uz
        if along <= 0.05 or abs(rx * uz - rz * ux) >= radius:
            continue                      # its line never enters the disc
        reach = math.floor(min(prof.step_ft, along) * 100) / 100
        seg = safe_prefix([Forward(reach)], State(est.x, est.z, h), safe, seen, reach,
                          None, half_width, nose, 0.0, margin_ft=prof.margin_ft)
        d = sum(c.distance_ft for c in seg if isinstance(c, Forward))
        end = (est.x + d * ux, est.z + d * uz)
        off = math.hypot(end[0] - goal[0], end[1] - goal[1])
        if d > 0.05 and off <= radius:
            cands.append((round(off, 3), abs(turn), turn, d, end))
    for off, _, turn, d, end in sorted(cands):
        pivot = [Turn(turn)] if turn != 0 else []
        if pivot and not pivot_allowed(safe.fmap, est, pivot[0].angle_deg, prof, pivot_sweep,
                                       pivot_ft):
            continue
        to = f"to ({end[0]:.2f}, {end[1]:.2f}), {off:.2f} ft from the goal"
        if abs(turn) > EYES_TURN_DEG:
            return pivot, f" (turning for the last move into the goal's disc, {to})"
        return pivot + [Forward(d)], f" (the last move into the goal's disc, {to})"
    return None
