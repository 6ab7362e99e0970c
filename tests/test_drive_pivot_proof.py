"""A pivot's cells proven, not only assumed (``head="assist"``:
:attr:`planner.evidence.Perception.pivot_proof`,
:func:`~planner.evidence.assumed_columns`, :attr:`planner.floormap.FloorMap.assumed`,
:func:`planner.motion.pivot_allowed`), on hand-made looks of a level camera
and hand-made maps whose answer follows from their geometry."""

import numpy as np

from planner.evidence import FreeProvenance, Perception
from planner.floormap import FloorMap
from planner.loop import DriveConfig
from planner.motion import mark_track_free, pivot_allowed
from planner.octree import FREE, VolumeOfInterest
from planner.perception import CX_128, FOCAL_128
from rig.scan import Point
from vehicle.profile import DEFAULT
from vehicle.sim import State
from world.pose import Pose

LEFT_X = Pose(0.0, 0.0, 0.0, 0.0).camera_centre("left")[0]


def _edge(col, dp, ep=0.1):
    """A vertical edge located at picture column ``col``, range ``dp``, on two lines."""
    return [Point(line, 1, col, col - 10, dp, 0.0, 0.0, ep, 0.01, 0.01) for line in (50, 52)]


def _at(col, z):
    """The floor point the level camera at the origin facing +z sees in column ``col`` at z."""
    return LEFT_X + (col - 0.5 - CX_128) * z / FOCAL_128, z


def _looked(beyond_ft):
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=8.0)
    m.blank_carve, m.carve, m.blank_px = "unknown", "error", 16   # the loop's defaults
    m.provenance = FreeProvenance()
    m.pivot_proof = beyond_ft
    m.update(_edge(68, 7.6), State(0.0, 0.0, 0.0), Pose, 0.0)   # column 54 blank, beside it
    return m, m.floor_map([(0.0, 0.0), (0.0, 8.0)])


def test_a_blank_column_is_assumed_only_beyond_the_given_distance():
    # one look: column 54 (14 beside the edge's column 68) is free by the blank-column
    # assumption alone; column 68's own line to its hit at 7.6 ft is proof
    far, near, hit_line = _at(54, 6.0), _at(54, 3.5), _at(68, 5.0)
    for beyond, far_assumed, near_assumed in ((0.0, True, True), (4.6, True, False),
                                              (7.0, False, False)):
        _, fm = _looked(beyond)
        assert fm.cells[fm.index(*far)] == FREE and fm.cells[fm.index(*near)] == FREE
        assert bool(fm.assumed[fm.index(*far)]) is far_assumed
        assert bool(fm.assumed[fm.index(*near)]) is near_assumed
        assert fm.cells[fm.index(*hit_line)] == FREE and not fm.assumed[fm.index(*hit_line)]
    m, fm = _looked(None)                       # off (the default): the map says nothing
    assert fm.assumed is None


def _open_map():
    fm = FloorMap(np.full((40, 40), FREE, np.uint8), -5.0, -5.0, 0.25)
    fm.assumed = np.zeros(fm.shape, bool)
    return fm


def test_a_pivot_needs_its_circle_free_by_more_than_the_assumption():
    # the turning circle is the footprint's half diagonal, 0.64 ft: a cell 0.5 ft
    # to the side (outside the 0.8 ft wide footprint) refuses the pivot when only
    # assumed; one 1.0 ft away does not
    at = State(0.0, 0.0, 0.0)
    fm = _open_map()
    assert pivot_allowed(fm, at, -70.0, DEFAULT)
    fm.assumed[fm.index(-0.55, 0.1)] = True
    assert not pivot_allowed(fm, at, -70.0, DEFAULT)
    fm.assumed = None                            # a map that does not say: as before
    assert pivot_allowed(fm, at, -70.0, DEFAULT)
    fm = _open_map()
    fm.assumed[fm.index(-1.1, 0.1)] = True
    assert pivot_allowed(fm, at, -70.0, DEFAULT)


def test_the_vehicle_s_track_proves_the_cells_it_stood_on():
    fm = _open_map()
    fm.assumed[:] = True
    mark_track_free(fm, [State(0.0, 0.0, 0.0)], DEFAULT.footprint)
    assert not fm.assumed[fm.index(0.0, 0.0)] and not fm.assumed[fm.index(0.3, 0.4)]
    assert fm.assumed[fm.index(0.6, 0.0)] and fm.assumed[fm.index(0.0, 0.9)]


def test_a_nearer_look_that_has_the_cell_blank_too_lifts_the_mark():
    # the assumption carves a cell once (only unknown cells), from the first and farthest
    # look; a second look 2.5 ft nearer, the same edge (7.6 ft off the origin) located at
    # column 70, has the cell (column 60 of the first look, 6 ft) 3.5 ft away on a blank
    # column 13 beside that edge: no longer assumed only from afar
    m, fm = _looked(4.6)
    cell = _at(60, 6.0)
    assert fm.assumed[fm.index(*cell)]
    m.update(_edge(70, 5.1), State(0.0, 2.5, 0.0), Pose, 0.0)
    fm = m.floor_map([(0.0, 0.0), (0.0, 8.0)])
    assert fm.cells[fm.index(*cell)] == FREE and not fm.assumed[fm.index(*cell)]
