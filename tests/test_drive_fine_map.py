"""The search on half cells where no map has a way (``DriveConfig.fine_map``,
:meth:`planner.evidence.Perception.halved_map`, :meth:`planner.floormap.FloorMap.halved`).
A feature blocks the whole 0.25 ft cell it touches, and the planner keeps its radius
from every point of that cell: a way 1.9 ft wide between two faces located 0.05 ft
inside their cells' far edges leaves 1.5 ft on the map, less than the vehicle's 1.58.
On half cells the same features block 0.125 ft cells.  Hand-made maps, every cell
derived by hand, and a bench room driven both ways."""

import numpy as np
import pytest

from planner.evidence import Perception, mark_walls
from planner.floormap import FloorMap
from planner.loop import DriveConfig, FINE_MAPS, _check_config
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest
from planner.planning import plan
from vehicle.sim import State

WALL_X0 = -2.95          # the plan's left wall: the 0.25 ft cell from -3.0 reaches past it


def _two_faces():
    """A model whose confirmed features stand on the lines x = -0.95 and x = +0.95
    (z 3..7 ft, every 0.1 ft, 0.01 ft each way: two box faces 1.9 ft apart), and its
    map on 0.25 ft cells from (-3, 0), free but for the features and the plan's left
    wall at x = -2.95."""
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1)
    m.occupied = "model"
    z = np.arange(3.0, 7.0 + 1e-9, 0.1)
    pts = np.concatenate([np.column_stack([np.full(len(z), x), z]) for x in (-0.95, 0.95)])
    m.features.add_look(pts, np.repeat(np.diag([1e-4, 1e-4])[None], len(pts), 0))
    m.features.looks[:] = 2                                   # confirmed: OCCUPIED
    fm = FloorMap(np.full((40, 24), FREE, np.uint8), -3.0, 0.0, 0.25)
    m._draw_features(fm)
    walls = (WALL_X0, 3.0, -1.0, 11.0)
    mark_walls(fm, walls)
    return m, fm, walls


def test_a_map_halved_splits_every_cell_and_mask_in_four():
    cells = np.array([[FREE, OCCUPIED], [UNKNOWN, UNCERTAIN]], np.uint8)
    core = np.array([[False, False], [False, True]])
    fm = FloorMap(cells, 1.0, 2.0, 0.25, uncertain_core=core, move_ring_start=True)
    h = fm.halved()
    assert (h.x0, h.z0, h.cell, h.shape) == (1.0, 2.0, 0.125, (4, 4))
    assert (h.cells[:2, :2] == FREE).all() and (h.cells[:2, 2:] == OCCUPIED).all()
    assert (h.cells[2:, :2] == UNKNOWN).all() and (h.cells[2:, 2:] == UNCERTAIN).all()
    assert h.uncertain_core.sum() == 4 and h.uncertain_core[2:, 2:].all()
    assert h.assumed is None and h.move_ring_start
    for x, z in ((1.01, 2.01), (1.3, 2.1), (1.1, 2.4), (1.49, 2.49)):
        assert h.state_at(x, z) == fm.state_at(x, z)          # the same room, finer


def test_the_faces_and_the_wall_are_drawn_again_on_half_cells_and_nothing_else():
    m, fm, walls = _two_faces()
    # on 0.25 ft cells the faces block x -1.0..-0.75 and 0.75..1.0, the wall x < -2.75
    for x, state in ((-0.8, OCCUPIED), (-0.7, FREE), (0.8, OCCUPIED), (0.7, FREE),
                     (-2.8, OCCUPIED), (-2.7, FREE)):
        assert fm.state_at(x, 5.0) == state, x
    fine = m.halved_map(fm, walls)
    assert fine.cell == 0.125
    # the half cells the faces stand in, and the wall's past -2.95, stay blocked;
    # their neighbours, blocked before only by the rounding, are seen, not free
    for x, state in ((-0.95, OCCUPIED), (-0.8, UNKNOWN), (0.95, OCCUPIED), (0.8, UNKNOWN),
                     (-2.9, OCCUPIED), (-2.8, UNKNOWN), (-0.7, FREE), (0.0, FREE),
                     (-0.95, FREE)):
        z = 5.0 if (x, state) != (-0.95, FREE) else 8.0        # above the faces' ends
        assert fine.state_at(x, z) == state, (x, state)
    # nothing new is blocked and nothing new is free
    split = fm.halved()
    blocked = (fine.cells == OCCUPIED) | (fine.cells == UNCERTAIN)
    assert not (blocked & (split.cells != OCCUPIED)).any()
    assert ((fine.cells == FREE) == (split.cells == FREE)).all()


def test_the_way_between_the_faces_is_planned_only_on_half_cells():
    # the vehicle needs 0.79 ft of every blocked point: on 0.25 ft cells the nearest
    # centres to the gap's middle, x = +-0.125, are 0.625 ft from a face's cell; on half
    # cells x = +-0.0625 are 0.8125 and 0.9375 ft from them
    m, fm, walls = _two_faces()
    est, goal = State(0.0, 1.0, 0.0), (0.0, 9.0)
    cfg = DriveConfig(goal=goal, goal_region="point")
    assert plan(fm, est, goal, cfg)[2].startswith("goal not reachable")
    pts, _, note = plan(m.halved_map(fm, walls), est, goal, cfg)
    assert note.startswith("path to the goal")
    mid = [p for p in pts if 3.0 <= p[1] <= 7.0]
    assert all(abs(p[0]) < 0.1 for p in mid)


def test_the_option_is_checked():
    # the default since 2026-12-06 15:40 (with floor_end_check "motion"), "off" before
    assert FINE_MAPS == ("off", "fallback") and DriveConfig.fine_map == "fallback"
    with pytest.raises(ValueError, match="unknown fine_map 'half'"):
        _check_config(DriveConfig(goal=(0.0, 5.0), fine_map="half"))


def test_room_56_is_reached_on_half_cells():
    # bench room 56 (the defaults before 2026-12-06 20:30, pinned: the drive it traced):
    # the way at (-0.6, 11.1) is narrower than the vehicle on the map, and the drive
    # stops after 16 looks without progress; with the half cells as the last resort it
    # is reached, judged by the world's geometry
    from rigtools import DRIVE_BEFORE_2026_12_06_2030, assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(56, "fine_map", FINE_MAPS, **DRIVE_BEFORE_2026_12_06_2030)
    assert not res["off"].reached and res["off"].collisions == 0
    assert "narrower than the vehicle" in res["off"].reason
    assert_reached_by_the_truth(res["fallback"], goal)
    assert any("(planned on half cells)" in c.note for c in res["fallback"].cycles)


def test_room_860_the_face_of_the_floors_grey_found_by_motion_keeps_the_half_cells_off_it():
    """Bench room 860 under ``fine_map="fallback"`` (and the defaults before 2026-12-06
    20:30, pinned: the drive it traced): box 4's front (x -0.28..1.80,
    z = 4.595 ft) has a tile's grey, and the floor in view proves the floor up the
    face and into the box.  The half cells open the way toward it and the vehicle's
    pivot sweeps into the face (docs/planner.md, "The search on half cells where no
    map has a way").  With ``floor_end_check="motion"`` the runs' ends that move
    with the camera mark the face's edge, every one of its points within 0.25 ft
    of the box by the world's geometry, the cycle's note says so, and the drive ends
    without a collision."""
    from planner.evidence import tracing_perception
    from planner.loop import run
    from rigtools import DRIVE_BEFORE_2026_12_06_2030, bench_drives, bench_task
    from world.odometry import OdometryNoise
    _, res = bench_drives(860, "floor_end_check", ("stereo",), fine_map="fallback",
                          **DRIVE_BEFORE_2026_12_06_2030)
    assert res["stereo"].collisions == 1
    room, start, goal = bench_task(860)
    made = []
    moved = run(room, start, DriveConfig(goal=goal, fine_map="fallback",
                                         floor_end_check="motion",
                                         **DRIVE_BEFORE_2026_12_06_2030),
                noise=OdometryNoise(seed=860), keep_maps=False,
                perception_factory=tracing_perception(made))
    assert moved.collisions == 0
    assert any("the floor's ends moved with the camera: an edge above the floor" in c.note
               for c in moved.cycles)
    model = made[0]
    assert moved.floor["raised_columns"] == model.raised_columns > 50
    assert len(model.raised_a) > 20                  # found again by a later look: kept
    box = room.obstacles[3]
    held = [np.vstack([a, b]) for _, _, a, b in model.raised_seen]
    for x, z in np.vstack([model.raised_a, model.raised_b] + held):
        dx = max(box[0] - x, 0.0, x - box[1])
        dz = max(box[2] - z, 0.0, z - box[3])
        assert np.hypot(dx, dz) < 0.25


def test_room_157_an_edge_found_raised_by_one_wrong_estimate_is_only_held():
    """Bench room 157 under ``fine_map="fallback"``, ``floor_end_check="motion"``:
    at look 14 a wall fix turns the estimate 3.9 deg off the true heading (mended
    at look 15), and the runs' ends along the right wall's foot seem to have moved
    with the camera.  By the world's geometry that edge stands 0.5 ft or more from
    every box.  Found by no other look, it is held for a few looks and not kept,
    and the drive reaches its goal by the truth."""
    from planner.evidence import RAISED_HOLD, tracing_perception
    from planner.loop import run
    from rigtools import assert_reached_by_the_truth, bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(157)
    made = []
    res = run(room, start, DriveConfig(goal=goal, fine_map="fallback", floor_end_check="motion"),
              noise=OdometryNoise(seed=157), keep_maps=False,
              perception_factory=tracing_perception(made))
    model = made[0]
    assert [n for n, *_ in model.raised_seen] == [14]
    edge = model.raised_seen[0][1]
    assert len(edge) > 20 and min(room.clearance(x, z) for x, z in edge) > 0.5
    assert len(model.raised_a) == 0
    assert res.looks > 14 + RAISED_HOLD
    assert_reached_by_the_truth(res, goal)
