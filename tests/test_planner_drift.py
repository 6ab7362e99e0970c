"""An older look's free space shrunk by the odometry's drift since that look
(``planner.drift``, ``DriveConfig.free_drift``: "erode", a named option, and "moves",
the default since 2026-12-04).  Hand-made looks and maps; every margin derived by hand
from the noise model of ``world.odometry`` (1 deg per command, 2 % of the distance);
the two drives that show why "moves" goes with grown walls (rooms 7 and 272)."""

import math

import numpy as np
import pytest

from planner.drift import LookFree, Odometry, drift_ft, erode_by_drift
from planner.floormap import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, FloorMap
from planner.loop import Drive, DriveConfig, _check_config
from planner.evidence import Perception
from planner.tiny import GOAL, tiny_room
from vehicle.commands import Forward, Turn
from vehicle.sim import State
from world.odometry import OdometryNoise

RES = 0.25
FAR = (100.0, 100.0)                    # the vehicle now, far from every cell


def test_drift_by_hand():
    then = Odometry()
    now = Odometry(commands=4, path_ft=2.0, distance_var=0.01)
    # 2 sigma of sqrt(4 (1 deg)^2 (3 + 2)^2 + 0.01)
    want = 2 * math.sqrt(4 * math.radians(1.0) ** 2 * 25 + 0.01)
    assert drift_ft(3.0, then, now, 1.0) == pytest.approx(want)
    assert drift_ft(3.0, now, now, 1.0) == 0.0           # the last look: nothing since
    assert drift_ft(3.0, then, now, 0.0) == pytest.approx(2 * 0.1)   # no heading noise
    assert drift_ft([0.0, 3.0], then, now, 1.0, sigmas=1.0)[1] == pytest.approx(want / 2)


def test_report_counts_commands_and_their_distance_variance():
    o = Odometry()
    o.report(1.5, 0.02)
    o.report(0.0, 0.02)                                   # a turn in place
    assert (o.commands, o.path_ft) == (2, 1.5)
    assert o.distance_var == pytest.approx((0.02 * 1.5) ** 2)


def _map(ring=OCCUPIED, n=20):
    """A 20 x 20 map of 0.25 ft cells from (0, 0), UNKNOWN but for the FREE block of
    rows and columns 2..11 (x, z 0.5..3.0 ft), the ring of cells round it in the
    state ``ring`` (hit cells: the block's edge is 0.5 and 3.0 ft), and the one FREE
    cell (15, 15)."""
    cells = np.full((n, n), UNKNOWN, np.uint8)
    cells[1:13, 1:13] = ring
    cells[2:12, 2:12] = FREE
    cells[15, 15] = FREE
    return FloorMap(cells, 0.0, 0.0, RES)


def _columns(i0, i1, j0, j1):
    """The (kx, kz) keys of rows i0..i1-1, columns j0..j1-1 of :func:`_map`."""
    i, j = np.mgrid[i0:i1, j0:j1]
    return np.stack([j.ravel(), i.ravel()], 1)


def test_a_look_without_drift_since_keeps_all_it_freed():
    fm = _map()
    before = fm.cells.copy()
    look = LookFree((0.0, 0.0), _columns(2, 12, 2, 12), Odometry())
    assert erode_by_drift(fm, RES, [look], Odometry(), FAR, 1.0) == 0
    assert (fm.cells == before).all()


def test_an_older_look_gives_up_its_edge_by_its_drift():
    """The look freed the block from a camera at (1.75, 1.75), its centre; since then
    10 commands and no distance: the margin at r ft is 2 sqrt(10) (1 deg) r = 0.110 r
    ft.  A cell stays where its centre is at least the margin inside the free space's
    edge beside the hit cells."""
    fm = _map()
    look = LookFree((1.75, 1.75), _columns(2, 12, 2, 12), Odometry())
    lost = erode_by_drift(fm, RES, [look], Odometry(commands=10), FAR, 1.0)
    k = 2 * math.sqrt(10) * math.radians(1.0)
    inside = np.zeros(fm.shape, bool)
    inside[2:12, 2:12] = True
    kept = np.zeros(fm.shape, bool)
    for i in range(2, 12):
        for j in range(2, 12):
            x, z = (j + 0.5) * RES, (i + 0.5) * RES
            to_edge = min(x - 0.5, 3.0 - x, z - 0.5, 3.0 - z)
            kept[i, j] = to_edge >= k * math.hypot(x - 1.75, z - 1.75)
    assert kept.sum() < inside.sum() and kept[6, 6]       # the middle stays, edges go
    assert lost == int((inside & ~kept).sum())
    assert ((fm.cells == UNKNOWN) & inside == inside & ~kept).all()
    # cells no look freed are left as they are (the track, the start spot are drawn after)
    assert (fm.cells[1, 1:13] == OCCUPIED).all() and fm.cells[15, 15] == FREE


def test_the_newest_look_that_freed_a_cell_sets_its_margin():
    fm = _map()
    old = LookFree((1.75, 1.75), _columns(2, 12, 2, 12), Odometry())
    new = LookFree((1.75, 1.75), _columns(2, 4, 2, 12), Odometry(commands=10))
    erode_by_drift(fm, RES, [old, new], Odometry(commands=10), FAR, 1.0)
    assert (fm.cells[2:4, 2:12] == FREE).all()            # the newer look's, kept whole
    assert (fm.cells[11, [2, 11]] == UNKNOWN).all()        # the older look's far corners


def test_a_cell_beside_the_vehicle_after_a_turn_in_place_moves_by_little():
    """Turned in place since the look (40 commands, no distance), a cell 2 ft from the
    look's camera but beside the vehicle now gives up the drift at its distance to the
    vehicle: the vehicle at (1.75, 0.625), in front of the block's near edge row 2."""
    fm = _map()
    look = LookFree((1.75, 4.0), _columns(2, 12, 2, 12), Odometry())
    erode_by_drift(fm, RES, [look], Odometry(commands=40), (1.75, 0.625), 1.0)
    k = 2 * math.sqrt(40) * math.radians(1.0)
    # row 3 (z 0.875, 0.375 ft inside the edge), column 7 (x 1.875): 0.27 ft from the
    # vehicle, 3.1 ft from the camera
    assert 0.375 >= k * math.hypot(0.125, 0.25) and 0.375 < k * math.hypot(0.125, 3.125)
    assert fm.cells[3, 7] == FREE
    fm = _map()
    erode_by_drift(fm, RES, [look], Odometry(commands=40), FAR, 1.0)
    assert fm.cells[3, 7] == UNKNOWN                       # from far, it gives way


def test_only_an_edge_beside_a_hit_gives_way():
    """Misplaced free space matters where it reaches into something: an edge beside
    UNKNOWN space stays (eroding there too stopped the vehicle in the tiny room's
    third look), an edge beside an UNCERTAIN cell (hit once) gives way as beside an
    OCCUPIED one."""
    look = LookFree((1.75, 1.75), _columns(2, 12, 2, 12), Odometry())
    fm = _map(ring=UNKNOWN)
    assert erode_by_drift(fm, RES, [look], Odometry(commands=10), FAR, 1.0) == 0
    lost = {}
    for ring in (OCCUPIED, UNCERTAIN):
        fm = _map(ring=ring)
        lost[ring] = erode_by_drift(fm, RES, [look], Odometry(commands=10), FAR, 1.0)
    assert lost[OCCUPIED] == lost[UNCERTAIN] > 0


def test_the_option_is_checked_and_records_each_look():
    with pytest.raises(ValueError, match="free_drift"):
        _check_config(DriveConfig(goal=GOAL, free_drift="shrink"))
    for bad in (0, -1.0, 10, float("nan"), "2"):
        with pytest.raises(ValueError, match="drift_sigmas"):
            _check_config(DriveConfig(goal=GOAL, drift_sigmas=bad))
    d = Drive(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, free_drift="erode"),
              OdometryNoise(seed=1), False, Perception)
    assert d.model.look_free == [] and d.model.odometry == Odometry()
    ok, _ = d.act([Turn(10.0), Forward(1.0)], d.veh.dead)
    assert ok
    o = d.model.odometry
    assert o.commands == 2
    # the dead-reckoned distance, 1 ft give or take the 2 % noise
    assert o.path_ft == pytest.approx(1.0, abs=0.1)
    assert o.distance_var == pytest.approx((0.02 * o.path_ft) ** 2)
    # off: nothing recorded
    off = Drive(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, free_drift="off"),
                OdometryNoise(seed=1), False, Perception)
    assert off.model.look_free is None and off.model.odometry is None


def test_closed_loop_reaches_the_tiny_room_goal_with_the_erosion():
    """The loop still drives on what the newest looks prove (the tiny room's straight
    way, oracle edges as in tests/test_drive.py), and each look was recorded."""
    from planner.loop import run
    made = []

    def factory(*a):
        made.append(Perception(*a))
        return made[-1]
    res = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes="truth", sight_lines="band", free_drift="erode"),
              noise=OdometryNoise(seed=1), perception_factory=factory)
    assert res.reached, res.reason
    assert res.collisions == 0
    model = made[0]
    assert len(model.look_free) == model.look_no == res.looks
    assert all(len(lf.columns) for lf in model.look_free)
    commands = [lf.odometry.commands for lf in model.look_free]
    assert commands == sorted(commands) and commands[-1] > 0
    assert isinstance(res.drift_eroded, int) and res.drift_eroded >= 0
    assert res.as_json()["drift_eroded"] == res.drift_eroded
    off = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes="truth", sight_lines="band", free_drift="off"),
              noise=OdometryNoise(seed=1))
    assert off.drift_eroded is None and "drift_eroded" not in off.as_json()


def test_the_erosion_refuses_a_pivot_beside_a_hit():
    """Why the erosion costs eyes that see everything 15 points (docs/planner.md, "What
    the erosion costs: the pivots"): the vehicle stands at (1.75, 1.2), its pivot circle
    (the half diagonal, 0.64 ft) reaching row 2 of the free block, whose cells' centres
    lie 0.125 ft from the edge of the hit ring (row 1).  Freed by a look one step back
    (2 commands, 1.5 ft) their margins stay under 0.125 ft and the pivot is allowed;
    freed by a look two steps back (4 commands, 3 ft) they are over it, those cells turn
    unknown and a turn of half a degree is refused, though nothing moved."""
    from planner.motion import pivot_allowed
    from vehicle.profile import DEFAULT
    here = State(1.75, 1.2, 90.0)
    disc_row2 = [(2, j) for j in range(5, 9)]            # x 1.25..2.25: within 0.64 ft
    for j in (4, 9):                                      # and no farther along the row
        dx = min(abs(j * RES - 1.75), abs((j + 1) * RES - 1.75))
        assert math.hypot(dx, 1.2 - 0.75) > DEFAULT.radius_ft
    fm = _map()
    assert pivot_allowed(fm, here, -0.5, DEFAULT)         # no erosion: allowed
    for steps, allowed in ((1, True), (2, False)):
        d = 1.5 * steps
        since = Odometry(commands=2 * steps, path_ft=d, distance_var=steps * (0.02 * 1.5) ** 2)
        look = LookFree((1.75, 1.2 - d), _columns(2, 12, 2, 12), Odometry())
        r = [math.hypot((j + 0.5) * RES - 1.75, 1.2 - 0.625) for _, j in disc_row2]
        margins = drift_ft(r, Odometry(), since, 1.0)
        assert ((margins < 0.125) if allowed else (margins > 0.125)).all()
        fm = _map()
        erode_by_drift(fm, RES, [look], since, (here.x, here.z), 1.0)
        assert all((fm.cells[i, j] == FREE) == allowed for i, j in disc_row2)
        assert pivot_allowed(fm, here, -0.5, DEFAULT) == allowed


def test_moves_keeps_what_the_erosion_took_for_pivots_only():
    """``free_drift="moves"`` (the default since 2026-12-04): the same map as the test
    above, the look two steps back.  The erosion takes the same cells (the map a move is
    checked on is the same), but keeps them aside, and a pivot counts them free; a cell
    drawn over since (the plan's walls, the track: anything not UNKNOWN) counts as drawn."""
    from planner.motion import pivot_allowed
    from vehicle.profile import DEFAULT
    here = State(1.75, 1.2, 90.0)
    since = Odometry(commands=4, path_ft=3.0, distance_var=2 * (0.02 * 1.5) ** 2)
    look = LookFree((1.75, -1.8), _columns(2, 12, 2, 12), Odometry())
    eroded, kept = _map(), _map()
    n = erode_by_drift(eroded, RES, [look], since, (here.x, here.z), 1.0)
    assert erode_by_drift(kept, RES, [look], since, (here.x, here.z), 1.0,
                          keep_for_pivots=True) == n > 0
    assert (kept.cells == eroded.cells).all() and eroded.drift_kept is None
    assert kept.drift_kept.sum() == n and (kept.cells[kept.drift_kept] == UNKNOWN).all()
    assert not pivot_allowed(eroded, here, -0.5, DEFAULT)
    assert pivot_allowed(kept, here, -0.5, DEFAULT)
    kept.cells[2, 7] = OCCUPIED                            # drawn over since: not free
    assert kept.drift_kept[2, 7] and not pivot_allowed(kept, here, -0.5, DEFAULT)


@pytest.mark.parametrize("seed", [7, 272])
def test_moves_goes_with_grown_walls(seed):
    """Rooms 7 and 272 (the 1985 eyes, the odometry noise and goal of the bench's seed):
    with pivots given back (``free_drift="moves"``) and the plan's walls where the truth
    has them, the drive goes on for over 50 looks until the estimate is about 2 ft off,
    and the true footprint meets the room (room 7: the east wall, the estimate 1.7 ft
    west of the truth); with the walls grown by the estimate's 2 sigma (the default) the
    same drive does not collide (docs/planner.md, "What the erosion costs: the pivots")."""
    from planner.loop import run
    from rigtools import DRIVE_BEFORE_2026_12_05, bench_task
    room, start, goal = bench_task(seed)
    res = {walls: run(room, start, DriveConfig(goal=goal, plan_walls=walls,
                                               **DRIVE_BEFORE_2026_12_05),
                      noise=OdometryNoise(seed=seed), keep_maps=False)
           for walls in ("plan", "grown")}
    assert DriveConfig(goal=goal).free_drift == "moves"
    assert res["plan"].collisions == 1 and "hit something" in res["plan"].reason
    assert res["plan"].looks > 50 and res["plan"].final_true_error_ft > 1.5
    assert res["grown"].collisions == 0
