"""Where the true obstacle cells a floor map shows FREE come from
(:class:`planner.evidence.FreeProvenance`, :func:`~planner.evidence.free_obstacle_cells`,
:func:`~planner.evidence.standing_opened`; ``bench/drive.py --losses``), on
hand-made looks of a level camera and hand-made maps whose true answer is
derived from their geometry."""

import numpy as np
import pytest

from planner.evidence import BETWEEN_EDGES, BLANK_ASSUMPTION, SIGHT_TO_HIT, START_SPOT, TRACK, \
    TWO_LOOK_SIDES, FreeProvenance, Perception, cell_coverage, free_obstacle_cells, \
    standing_opened, tally_free_obstacle_cells
from planner.floormap import FloorMap
from planner.loop import DriveConfig
from planner.octree import FREE, OCCUPIED, UNKNOWN, VolumeOfInterest, cell_keys
from planner.perception import CX_128, FOCAL_128, TwoLookSides
from rig.scan import Point
from vehicle.sim import State
from world.pose import Pose

BOUNDS = (-10.0, 10.0, -4.0, 12.0)        # walls far from everything here
LEFT_X = Pose(0.0, 0.0, 0.0, 0.0).camera_centre("left")[0]


def _edge(col, dp, ep=0.1):
    """A vertical edge located at picture column ``col``, range ``dp``, on two lines."""
    return [Point(line, 1, col, col - 10, dp, 0.0, 0.0, ep, 0.01, 0.01) for line in (50, 52)]


def _at(col, z, x_cam=LEFT_X, z_cam=0.0):
    """The floor point a level camera facing +z at (x_cam, z_cam) sees in column ``col`` at z."""
    return x_cam + (col - 0.5 - CX_128) * (z - z_cam) / FOCAL_128, z


def _box(x, z, half=0.3):
    return np.array([[x - half, x + half, z - half, z + half]])


def _model(traced=True, two_looks=False, blank_ft=8.0):
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=blank_ft)
    m.blank_carve, m.carve, m.blank_px = "unknown", "error", 16
    if two_looks:
        m.two_look_sides = TwoLookSides(1.0, 20.0)
    if traced:
        m.provenance = FreeProvenance()
    return m


def _free_cells(m, box, track=()):
    fm = m.floor_map([(0.0, 0.0), (0.0, 8.0)])
    return fm, free_obstacle_cells(fm, box, BOUNDS, m.provenance, DriveConfig.band, track,
                                   (0.8, 1.0), 2.5, m.hit_keys)


def test_cell_coverage_is_the_share_of_the_cell_under_the_obstacle():
    fm = FloorMap(np.full((4, 4), FREE, np.uint8), 0.0, 0.0, 0.25)
    ij = [(0, 0), (0, 1), (1, 1), (3, 3)]
    # a box over the whole of cell (0, 0), half of (0, 1) (x 0.25-0.375), a quarter of (1, 1)
    cov = cell_coverage(fm, [(0.0, 0.375, 0.0, 0.375)], (-5, 5, -5, 5), ij)
    assert cov == pytest.approx([1.0, 0.5, 0.25, 0.0])
    # the walls: cell (3, 3) (x, z 0.75-1.0) reaches past a wall at x = 0.8 by 4/5 of its width
    assert cell_coverage(fm, [], (-5, 0.8, -5, 5), [(3, 3)]) == pytest.approx([0.8], abs=0.04)


def test_a_sight_line_through_a_box_to_a_hit_behind_it_is_traced_to_that_line():
    # one edge located at column 64, 7.6 ft (a false match through the box, or a
    # wall behind a low box); the box, whose edges the look did not locate, stands
    # across that column at 4.5 ft: its cell on the line is carved free (no
    # blank-column assumption here: it would carve the columns beside the edge)
    box = _box(*_at(64, 4.5))
    look = _edge(64, 7.6)
    m = _model(blank_ft=None)
    m.update(look, State(0.0, 0.0, 0.0), Pose, 0.0)
    fm, cells = _free_cells(m, box)
    assert cells, "the line's cells inside the box show FREE"
    assert all(c["mechanisms"] == [SIGHT_TO_HIT] for c in cells)
    assert max(c["coverage"] for c in cells) == 1.0        # a whole cell, not a sliver
    assert max(c["depth_ft"] for c in cells) > 0.125
    assert not any(c["hit"] for c in cells)              # no look located the box
    # the tracer changes nothing: the same look untraced makes the same map
    plain = _model(traced=False, blank_ft=None)
    plain.update(look, State(0.0, 0.0, 0.0), Pose, 0.0)
    assert np.array_equal(plain.floor_map([(0.0, 0.0), (0.0, 8.0)]).cells, fm.cells)
    t = tally_free_obstacle_cells(cells)
    assert t["only"] == {SIGHT_TO_HIT: len(cells)} and t["cells"] == len(cells)
    assert t["ever_hit"] == 0


def test_columns_between_two_edges_are_told_from_the_edges_own_lines():
    # edges at columns 50 and 80, 7.6 ft: the columns between are carved as bounded by them
    box = _box(*_at(65, 4.5), half=0.1)
    m = _model(blank_ft=None)
    m.update(_edge(50, 7.6) + _edge(80, 7.6), State(0.0, 0.0, 0.0), Pose, 0.0)
    _, cells = _free_cells(m, box)
    assert cells and all(BETWEEN_EDGES in c["mechanisms"] for c in cells)
    assert all(SIGHT_TO_HIT not in c["mechanisms"] for c in cells)


def test_the_blank_column_assumption_and_the_two_look_sides_are_told_apart():
    # one edge at column 68, 7.6 ft: column 54 (14 beside it) is carved by the
    # assumption; column 34 (34 beside it, cut off by blank_px 16) only where a
    # second look 1.2 ft behind also had it blank (the two-look sides)
    near = _box(*_at(54, 4.5), half=0.1)
    m = _model(two_looks=True)
    m.update(_edge(68, 7.6), State(0.0, 0.0, 0.0), Pose, 0.0)
    _, cells = _free_cells(m, near)
    assert cells and all(c["mechanisms"] == [BLANK_ASSUMPTION] for c in cells)
    x, z = _at(34, 4.5)
    far = _box(x, z, half=0.1)
    assert not _free_cells(m, far)[1]                   # held back after one look
    m.update(_edge(68, 7.6), State(0.0, -1.2, 0.0), Pose, 0.0)
    fm, cells = _free_cells(m, far)
    by = {c["ij"]: c["mechanisms"] for c in cells}
    assert TWO_LOOK_SIDES in by[fm.index(x, z)]


def test_the_track_and_the_start_spot_are_named_where_no_look_carved():
    m = _model()
    fm = FloorMap(np.full((40, 40), UNKNOWN, np.uint8), -5.0, -5.0, 0.25)
    fm.cells[20, 20] = FREE                # (0.125, 0.125): on the first pose's footprint
    fm.cells[20, 28] = FREE                # (2.125, 0.125): 2.1 ft off, in the start spot only
    boxes = [(0.0, 0.25, 0.0, 0.25), (2.0, 2.25, 0.0, 0.25)]
    hit = cell_keys(np.array([[0.125, 0.0, 0.125]]), 0.25)   # a look once hit (0.125, 0.125)
    cells = free_obstacle_cells(fm, boxes, BOUNDS, m.provenance, DriveConfig.band,
                                [State(0.0, 0.0, 0.0)], (0.8, 1.0), 2.5, hit)
    by = {c["ij"]: c["mechanisms"] for c in cells}
    assert by == {(20, 20): [START_SPOT, TRACK], (20, 28): [START_SPOT]}
    assert {c["ij"]: c["hit"] for c in cells} == {(20, 20): True, (20, 28): False}


def _wall_map():
    """A 0.25 ft map, all FREE, with a box over columns 8-11 (x 2.0-3.0) shown OCCUPIED."""
    fm = FloorMap(np.full((40, 24), FREE, np.uint8), 0.0, 0.0, 0.25)
    fm.cells[:, 8:12] = OCCUPIED
    return fm, [(2.0, 3.0, 0.0, 10.0)], (-5.0, 11.0, -5.0, 15.0)


def test_one_free_layer_on_the_face_is_covered_two_are_not():
    # one layer of whole face cells shown free (x 2.0-2.25): the vehicle may stand a
    # cell nearer, but the clearance's lower bound (a cell diagonal short) still keeps
    # its disc of 0.79 ft off the true face
    fm, box, bounds = _wall_map()
    fm.cells[10:30, 8] = FREE
    cells = free_obstacle_cells(fm, box, bounds, FreeProvenance(), DriveConfig.band)
    assert len(cells) == 20 and all(c["coverage"] == 1.0 for c in cells)
    out = standing_opened(fm, cells, box, bounds, 0.79)
    assert out["opened"] > 0 and out["opened_unsafe"] == 0
    # two layers (x 2.0-2.5): the spots opened reach into the box
    fm.cells[10:30, 9] = FREE
    cells = free_obstacle_cells(fm, box, bounds, FreeProvenance(), DriveConfig.band)
    out = standing_opened(fm, cells, box, bounds, 0.79)
    assert len(cells) == 40 and 0 < out["opened_unsafe"] <= out["opened"]


def test_a_free_cell_the_growth_of_its_neighbours_covers_opens_nothing():
    fm, box, bounds = _wall_map()
    fm.cells[10:30, 9] = FREE              # inside the box, behind its occupied face
    cells = free_obstacle_cells(fm, box, bounds, FreeProvenance(), DriveConfig.band)
    assert len(cells) == 20
    assert standing_opened(fm, cells, box, bounds, 0.79) == {"opened": 0, "opened_unsafe": 0}
    assert standing_opened(fm, [], box, bounds, 0.79) == {"opened": 0, "opened_unsafe": 0}


def test_a_perception_factory_traces_the_drive_without_changing_it():
    """``run(perception_factory=...)`` builds the run's model with the factory
    (``bench/drive.py --losses`` passes one keeping a FreeProvenance): the
    factory is called once, the traced drive and its maps are the plain drive's,
    and the provenance holds the looks' carvings."""
    from planner.evidence import MECHANISMS, tracing_perception
    from planner.loop import run
    from planner.tiny import GOAL, tiny_room
    from world.odometry import OdometryNoise

    made = []
    room, cfg = tiny_room(), DriveConfig(goal=GOAL, eyes="truth")
    plain = run(room, State(0.0, 0.0, 0.0), cfg, noise=OdometryNoise(seed=1))
    traced = run(room, State(0.0, 0.0, 0.0), cfg, noise=OdometryNoise(seed=1),
                 perception_factory=tracing_perception(made))
    assert len(made) == 1
    assert (traced.reason, traced.looks, traced.true_track, traced.estimate_track) == \
        (plain.reason, plain.looks, plain.true_track, plain.estimate_track)
    for a, b in zip(traced.cycles, plain.cycles, strict=True):
        np.testing.assert_array_equal(a.fmap.cells, b.fmap.cells)
    prov = made[0].provenance
    assert prov.misses, "a drive that looked carved no free cell"
    assert {m for per in prov.misses.values() for m in per} <= set(MECHANISMS)
    assert set(prov.first_look.values()) <= set(range(1, traced.looks + 1))


def test_free_inside_now_carries_the_map_by_the_estimates_error():
    """By hand: one FREE cell 2 ft ahead of the estimate (centre (0.125, 2.125)).
    Where the estimate is the truth it lies clear of a box at x 1.5-2.5, z 0-1;
    where the vehicle truly faces +X (heading 90 deg, the estimate 0), the cell
    is truly 2.125 ft ahead and 0.125 ft right of it: (2.125, -0.125) -> with the
    box at z -0.5-0.5 it lies 0.375 ft inside (counted at 0.25 ft, not at 0.5)."""
    from planner.evidence import free_inside_now
    fm = FloorMap(np.full((24, 24), UNKNOWN, np.uint8), -2.0, -2.0, 0.25)
    i, j = fm.index(0.1, 2.1)
    fm.cells[i, j] = FREE
    assert fm.centre(i, j) == pytest.approx((0.125, 2.125))
    box = [(1.5, 2.5, -0.5, 0.5)]
    est = State(0.0, 0.0, 0.0)
    assert free_inside_now(fm, box, est, est) == 0
    assert free_inside_now(fm, [(-0.5, 0.5, 1.5, 2.5)], est, est) == 1      # in the box as mapped
    truth = State(0.0, 0.0, 90.0)
    assert free_inside_now(fm, box, est, truth) == 1
    assert free_inside_now(fm, box, est, truth, depth_ft=0.5) == 0
    moved = State(1.0, -1.0, 90.0)                                          # and shifted
    assert free_inside_now(fm, [(2.5, 3.75, -1.75, -0.5)], est, moved) == 1   # at (3.125, -1.125)
    fm.cells[i, j] = OCCUPIED
    assert free_inside_now(fm, box, est, truth) == 0
