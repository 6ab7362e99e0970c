"""The side columns that ``blank_px`` cuts off, carved only where two looks from
poses apart both saw them blank (``FloorScan.far_ends``,
:class:`planner.perception.TwoLookSides`, ``DriveConfig.blank_sides``), on
hand-made looks of a level camera: room 45's look 4 (a box whose edges the
look did not locate, beside an edge located farther away) and a second look."""

import numpy as np
import pytest

from planner.evidence import Perception
from planner.loop import DriveConfig
from planner.octree import FREE, UNKNOWN, VolumeOfInterest, query
from planner.perception import CX_128, FOCAL_128, TwoLookSides, floor_scan
from rig.scan import Point
from vehicle.sim import State
from world.pose import Pose

BAND = (-1.0, 2.75)


def _edge(col, dp, ep=0.05):
    """A vertical edge located at picture column ``col``, range ``dp``, on two lines."""
    return [Point(line, 1, col, col - 10, dp, 0.0, 0.0, ep, 0.01, 0.01) for line in (50, 52)]


def _cols(ends, origin=np.zeros(3)):
    """The picture column of each free end (level camera facing +z)."""
    d = ends - origin
    return np.round(d[:, 0] * FOCAL_128 / d[:, 2] + CX_128 + 0.5).astype(int)


def test_the_cut_off_side_columns_come_apart_and_the_rest_is_unchanged():
    origin = np.zeros(3)
    pts = _edge(40, 5.0) + _edge(110, 6.0)        # 70 columns apart: wider than max_gap_px
    whole = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0)
    cut = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0, blank_px=16)
    # more than 16 columns beside the outermost edges, out to the picture's edges
    assert sorted(cut.far_cols) == list(range(1, 24)) + list(range(127, 129))
    assert sorted(_cols(cut.far_ends)) == sorted(cut.far_cols)
    assert not set(cut.far_cols) & set(cut.free_cols)
    # at the reach they had without blank_px: their side's edge's range
    assert np.allclose(cut.far_ends[cut.far_cols < 40, 2], 5.0)
    assert np.allclose(cut.far_ends[cut.far_cols > 110, 2], 6.0)
    ranges = dict(zip(_cols(whole.free_ends), whole.free_ends[:, 2]))
    assert np.allclose(cut.far_ends[:, 2], [ranges[c] for c in cut.far_cols])
    # nothing is cut off without blank_px
    assert whole.far_ends is None and len(whole.free_ends) == 126


def test_two_look_sides_confirms_a_cell_only_from_a_second_pose_apart():
    t = TwoLookSides(1.0, 20.0)
    keys = np.array([11, 12, 13], np.int64)
    assert len(t.confirm(keys, (0.0, 0.0, 0.0))) == 0           # the first look holds back
    assert len(t.confirm(keys, (0.6, 0.6, 15.0))) == 0          # 0.85 ft, 15 deg: too near
    assert t.confirm(keys[:1], (0.0, 1.0, 0.0)).tolist() == [11]   # 1 ft apart
    assert t.confirm(keys[1:2], (0.0, 0.0, -20.0)).tolist() == [12]  # turned 20 deg
    assert t.confirm(keys[2:], (0.0, 0.0, 359.0)).tolist() == []   # 1 deg, across 360
    assert t.confirmed == 2
    # the first look's pose is kept: a confirmed cell starts over
    assert t.confirm(keys[:1], (0.0, 1.0, 0.0)).tolist() == []
    with pytest.raises(ValueError, match="apart"):
        TwoLookSides(0.0, 20.0)


def _model(blank_sides):
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=8.0)
    m.blank_carve = "unknown"
    m.carve = "error"
    m.blank_px = 16
    if blank_sides == "two-looks":
        m.two_look_sides = TwoLookSides(1.0, 20.0)
    return m


LEFT_X = Pose(0.0, 0.0, 0.0, 0.0).camera_centre("left")[0]   # the left camera's x
BOX_X = LEFT_X + (34 - 0.5 - CX_128) * 4.5 / FOCAL_128        # a box cell: column 34 at 4.5 ft
BOX_Z = 4.5


def _state(x, z, m):
    return query(m.tree, np.array([x, m.points[0][1], z]))


def test_a_blank_side_is_carved_only_once_a_second_look_apart_saw_it_blank():
    # room 45's look 4 from the origin: one edge at column 68, 7.6 ft; the box cell
    # at column 34 (34 columns beside the edge) 4.5 ft away is in a far side column
    look = _edge(68, 7.6, 0.1)
    m = _model("two-looks")
    m.update(look, State(0.0, 0.0, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, m) == UNKNOWN         # one look: held back
    # the same look again from 0.5 ft behind, heading the same: not apart enough
    m.update(look, State(0.0, -0.5, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, m) == UNKNOWN
    # from 1.2 ft behind the origin the cell is at column ~42, still 26 columns
    # beside the edge: both looks saw it blank, so it is carved now
    col = (BOX_X - LEFT_X) * FOCAL_128 / (BOX_Z + 1.2) + CX_128 + 0.5
    assert 40 < col < 52
    m.update(look, State(0.0, -1.2, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, m) == FREE
    assert m.two_look_sides.confirmed > 0
    # "cut" (the default before 16:35): the same three looks never carve it
    d = _model("cut")
    for z in (0.0, -0.5, -1.2):
        d.update(look, State(0.0, z, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, d) == UNKNOWN


def test_a_box_face_another_look_located_stops_the_carving():
    # look 1 (the origin) has the cell in a blank far side; look 2, from the same
    # pose, locates the box's face in front of it (columns 30-38 at 4.0 ft); look 3,
    # 1.2 ft behind (apart from look 1), again has the cell in a blank far side,
    # but its sight line to the cell passes the face's hit: never carved
    m = _model("two-looks")
    m.update(_edge(68, 7.6, 0.1), State(0.0, 0.0, 0.0), Pose, 0.0)
    face = [q for c in range(30, 39) for q in _edge(c, 4.0, 0.1)]
    m.update(_edge(68, 7.6, 0.1) + face, State(0.0, 0.0, 0.0), Pose, 0.0)
    m.update(_edge(68, 7.6, 0.1), State(0.0, -1.2, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, m) != FREE
    # without look 2's face the same looks 1 and 3 carve it
    m = _model("two-looks")
    m.update(_edge(68, 7.6, 0.1), State(0.0, 0.0, 0.0), Pose, 0.0)
    m.update(_edge(68, 7.6, 0.1), State(0.0, -1.2, 0.0), Pose, 0.0)
    assert _state(BOX_X, BOX_Z, m) == FREE


def test_blank_sides_reaches_the_config_and_a_bad_value_is_refused():
    import argparse
    from planner.loop import run
    from planner.tiny import GOAL, tiny_room
    from rig.drive import add_loop_options, loop_config
    ap = argparse.ArgumentParser()
    add_loop_options(ap)
    assert DriveConfig.blank_sides == "two-looks"     # the default since 2026-12-01 16:35
    cfg = loop_config(ap.parse_args([]), (0.0, 0.0), ap.error)
    assert cfg.blank_sides == "two-looks" and cfg.sides_apart == (1.0, 20.0)
    assert loop_config(ap.parse_args(["--blank-sides", "cut"]), (0.0, 0.0),
                       ap.error).blank_sides == "cut"
    cfg = loop_config(ap.parse_args(["--blank-sides", "two-looks", "--sides-apart", "2", "30"]),
                      (0.0, 0.0), ap.error)
    assert cfg.blank_sides == "two-looks" and cfg.sides_apart == (2.0, 30.0)
    with pytest.raises(SystemExit):
        loop_config(ap.parse_args(["--sides-apart", "0", "30"]), (0.0, 0.0), ap.error)
    with pytest.raises(ValueError, match="blank_sides"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, blank_sides="both"))
    with pytest.raises(ValueError, match="apart"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, sides_apart=(1.0, -5.0)))
