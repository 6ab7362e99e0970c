"""The blank-column assumption kept beside what a look located
(``floor_scan(blank_px=...)``, ``DriveConfig.blank_px``), on hand-made looks of
a level camera: a box whose own edges the look did not locate, in the blank run
beside an edge located farther away (room 45, seeds 41-60)."""

import numpy as np
import pytest

from planner.evidence import Perception
from planner.loop import DriveConfig
from planner.octree import FREE, UNKNOWN, VolumeOfInterest, query
from planner.perception import FOCAL_128, CX_128, floor_scan
from rig.scan import Point
from vehicle.sim import State
from world.pose import Pose

BAND = (-1.0, 2.75)


def _edge(col, dp, ep=0.05):
    """A vertical edge located at picture column ``col``, range ``dp``, on two lines."""
    return [Point(line, 1, col, col - 10, dp, 0.0, 0.0, ep, 0.01, 0.01) for line in (50, 52)]


def _cols(fs):
    """The picture column of each free end (level camera at the origin, facing +z)."""
    return np.round(fs.free_ends[:, 0] * FOCAL_128 / fs.free_ends[:, 2] + CX_128 + 0.5).astype(int)


def test_blank_px_keeps_the_assumption_beside_the_located_columns():
    origin = np.zeros(3)
    pts = _edge(40, 5.0) + _edge(110, 6.0)        # 70 columns apart: wider than max_gap_px
    full = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0)
    near = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0, blank_px=16)
    assert sorted(_cols(full)) == [c for c in range(1, 129) if c not in (40, 110)]
    want = list(range(24, 40)) + list(range(41, 57)) + list(range(94, 110)) + \
        list(range(111, 127))
    assert sorted(_cols(near)) == want
    assert near.assumed.all()
    # the carved ones reach as far as before (the nearer edge's range between, the edge's beside)
    ranges = dict(zip(_cols(full), full.free_ends[:, 2]))
    assert np.allclose(near.free_ends[:, 2], [ranges[c] for c in _cols(near)])
    # a gap within max_gap_px is bounded by its two edges, not assumed: untouched
    close = _edge(40, 5.0) + _edge(60, 5.0)
    a = floor_scan(close, np.eye(3), origin, BAND, blank_ft=8.0, blank_px=0)
    assert sorted(_cols(a)) == list(range(41, 60))
    # a look that located nothing is governed by blank_alone alone
    assert len(floor_scan([], np.eye(3), origin, BAND, blank_ft=8.0, blank_px=16).free_ends) == 128


def test_blank_limit_sides_limits_only_the_columns_beside_the_outermost_edges():
    origin = np.zeros(3)
    pts = _edge(40, 5.0) + _edge(110, 6.0)        # 70 columns apart: wider than max_gap_px
    full = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0)
    sides = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0, blank_px=16,
                       blank_limit="sides")
    # beside the outermost edges 16 columns (toward the picture's edges), the gap whole
    assert sorted(_cols(sides)) == list(range(24, 40)) + list(range(41, 110)) + \
        list(range(111, 127))
    assert sides.assumed.all()
    ranges = dict(zip(_cols(full), full.free_ends[:, 2]))
    assert np.allclose(sides.free_ends[:, 2], [ranges[c] for c in _cols(sides)])
    gap = (_cols(sides) > 40) & (_cols(sides) < 110)
    assert np.allclose(sides.free_ends[gap, 2], 5.0)       # the nearer edge's range
    # without blank_px the limit changes nothing
    plain = floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0, blank_limit="sides")
    assert sorted(_cols(plain)) == sorted(_cols(full))
    with pytest.raises(ValueError, match="blank_limit"):
        floor_scan(pts, np.eye(3), origin, BAND, blank_ft=8.0, blank_limit="gaps")


def _model(blank_px, blank_limit="all"):
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=8.0)
    m.blank_carve = "unknown"
    m.carve = "error"
    m.blank_px = blank_px
    m.blank_limit = blank_limit
    return m


LEFT_X = Pose(0.0, 0.0, 0.0, 0.0).camera_centre("left")[0]   # the left camera's x


def _box_cells(col_lo, col_hi, z_near, z_far, res=0.25):
    """Cell centres of a box face-on to the left camera: picture columns col_lo..col_hi at
    z_near, z_far deep."""
    x0 = LEFT_X + (col_lo - 0.5 - CX_128) * z_near / FOCAL_128
    x1 = LEFT_X + (col_hi - 0.5 - CX_128) * z_near / FOCAL_128
    xs = np.arange(np.floor(x0 / res) + 1, np.floor(x1 / res)) * res + res / 2
    zs = np.arange(np.floor(z_near / res) + 1, np.floor(z_far / res)) * res + res / 2
    return [(x, z) for x in xs for z in zs]


def test_a_box_whose_edges_were_not_located_is_not_carved_beside_a_far_edge():
    # room 45's look 4: an edge located at column 68, 7.6 ft away; a box 4-5 ft
    # away in columns 20-48 whose own edges the look did not locate.  The whole
    # blank run beside the edge carves to the edge's range, through the box; at
    # most 16 columns beside the edge (1 ft wide at 7.6 ft) misses it
    look = _edge(68, 7.6, 0.1)
    box = _box_cells(20, 48, 4.0, 5.0)
    for blank_px, want in ((None, FREE), (16, UNKNOWN)):
        m = _model(blank_px)
        m.update(look, State(0.0, 0.0, 0.0), Pose, 0.0)
        y = m.points[0][1]
        states = [query(m.tree, np.array([x, y, z])) for x, z in box]
        assert set(states) == {want}, (blank_px, set(states))
        # beside the edge, its 16 columns still carved up to it
        x = LEFT_X + (60 - 0.5 - CX_128) * 6.0 / FOCAL_128
        assert query(m.tree, np.array([x, y, 6.0])) == FREE


def test_blank_limit_sides_misses_room_45s_box_and_still_carves_a_wide_gap():
    # room 45's look 4 under "sides": the box beside the one edge is not carved
    box = _box_cells(20, 48, 4.0, 5.0)
    m = _model(16, "sides")
    m.update(_edge(68, 7.6, 0.1), State(0.0, 0.0, 0.0), Pose, 0.0)
    y = m.points[0][1]
    assert {query(m.tree, np.array([x, y, z])) for x, z in box} == {UNKNOWN}
    # two edges 80 columns apart at 7.6 ft: the middle of the gap (40 columns from
    # either edge) is carved under "sides", not under "all"
    x = LEFT_X + (60 - 0.5 - CX_128) * 5.0 / FOCAL_128
    for blank_limit, want in (("sides", FREE), ("all", UNKNOWN)):
        m = _model(16, blank_limit)
        m.update(_edge(20, 7.6, 0.1) + _edge(100, 7.6, 0.1), State(0.0, 0.0, 0.0), Pose, 0.0)
        assert query(m.tree, np.array([x, m.points[0][1], 5.0])) == want, blank_limit


def test_blank_px_reaches_the_config_and_a_bad_value_is_refused():
    from planner.loop import run
    from planner.tiny import GOAL, tiny_room
    from rig.drive import add_loop_options, loop_config
    import argparse
    ap = argparse.ArgumentParser()
    add_loop_options(ap)
    assert DriveConfig.blank_px is None      # since 2026-12-03 (16 from room 45 to then)
    assert loop_config(ap.parse_args([]), (0.0, 0.0), ap.error).blank_px is None
    assert loop_config(ap.parse_args(["--blank-px", "16"]), (0.0, 0.0), ap.error).blank_px == 16
    assert loop_config(ap.parse_args(["--blank-px", "32"]), (0.0, 0.0), ap.error).blank_px == 32
    assert loop_config(ap.parse_args(["--blank-px", "-1"]), (0.0, 0.0), ap.error).blank_px is None
    with pytest.raises(ValueError, match="blank_px"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, blank_px=-2))
    assert DriveConfig.blank_limit == "all"
    assert loop_config(ap.parse_args([]), (0.0, 0.0), ap.error).blank_limit == "all"
    assert loop_config(ap.parse_args(["--blank-limit", "sides"]), (0.0, 0.0),
                       ap.error).blank_limit == "sides"
    with pytest.raises(ValueError, match="blank_limit"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, blank_limit="gaps"))
