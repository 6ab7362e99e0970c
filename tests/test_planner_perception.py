"""The loop's perception step (planner.perception) on hand-made located points."""

import math

import numpy as np
import pytest

from planner.perception import floor_scan
from rig.scan import Point


def _pt(line, loc1, dp, ep=0.05):
    return Point(line, 1, loc1, loc1 - 10, dp, 0.0, 0.0, ep, 0.01, 0.01)


def test_floor_scan_carves_to_the_near_end_of_the_error_bound_when_asked():
    # two edges (columns 40 and 60) bound a blank face: by default the columns
    # between are free up to the nearer range (4 ft); with carve="error" up to
    # the nearer of the two ranges less their bounds: 4.0 - 0.3 and 5.0 - 0.5
    R = np.eye(3)
    origin = np.array([-0.375, 0.0, 0.0])
    pts = [_pt(50, 40, 5.0, 0.5), _pt(52, 40, 5.02, 0.5),
           _pt(50, 60, 4.0, 0.3), _pt(52, 60, 4.01, 0.3)]
    by_range = floor_scan(pts, R, origin, band=(-1.0, 2.75))
    by_error = floor_scan(pts, R, origin, band=(-1.0, 2.75), carve="error")
    assert np.allclose(by_range.free_ends[:, 2], 4.0)
    assert np.allclose(by_error.free_ends[:, 2], 3.7)
    assert np.array_equal(by_range.hits, by_error.hits)          # the hits are the same
    # outside the outermost edges, with blank columns free up to 8 ft: up to
    # the outer edge's range (less its bound with carve="error")
    blank = floor_scan(pts, R, origin, band=(-1.0, 2.75), blank_ft=8.0, carve="error")
    left = blank.free_ends[np.isclose(blank.free_ends[:, 2], 4.5)]
    right = blank.free_ends[np.isclose(blank.free_ends[:, 2], 3.7)]
    assert len(left) == 39 and len(right) == 19 + 68
    with pytest.raises(ValueError, match="carve"):
        floor_scan(pts, R, origin, band=(-1.0, 2.75), carve="nearest")


def test_a_look_that_located_nothing_carves_nothing_when_asked():
    R = np.eye(3)
    origin = np.zeros(3)
    # by default (blank columns free up to 8 ft) the whole view is carved:
    # each of the 128 columns once, at 8 ft
    alone = floor_scan([], R, origin, band=(-1.0, 2.75), blank_ft=8.0)
    assert len(alone.free_ends) == 128
    assert np.allclose(np.hypot(alone.free_ends[:, 0], alone.free_ends[:, 2]),
                       8.0 / np.cos(np.arctan((np.arange(1, 129) - 0.5 - 64) / 180)))
    none = floor_scan([], R, origin, band=(-1.0, 2.75), blank_ft=8.0, blank_alone=False)
    assert len(none.free_ends) == 0 and len(none.hits) == 0
    # a look that located one edge still carves its blank columns
    pts = [_pt(50, 40, 5.0), _pt(52, 40, 5.02)]
    some = floor_scan(pts, R, origin, band=(-1.0, 2.75), blank_ft=8.0, blank_alone=False)
    assert len(some.free_ends) == 127


def test_floor_scan_says_which_free_ends_are_assumed():
    R = np.eye(3)
    origin = np.zeros(3)
    # edges at columns 40 and 60 (20 px apart: the columns between are bounded
    # by hits) and at 110 (50 px from 60: wider than max_gap_px, free only by
    # the blank-column assumption), the sides outside by the assumption too
    pts = [_pt(50, c, 5.0) for c in (40, 60, 110)] + [_pt(52, c, 5.02) for c in (40, 60, 110)]
    fs = floor_scan(pts, R, origin, band=(-1.0, 2.75), blank_ft=8.0)
    cols = np.round(fs.free_ends[:, 0] * 180 / fs.free_ends[:, 2] + 64.5).astype(int)
    assert len(fs.assumed) == len(fs.free_ends) == 19 + 49 + 39 + 18
    assert not fs.assumed[(cols > 40) & (cols < 60)].any()
    assert fs.assumed[(cols > 60) & (cols < 110)].all()
    assert fs.assumed[(cols < 40) | (cols > 110)].all()
    # a look that located nothing: all of it assumed; without blank_ft nothing is
    assert floor_scan([], R, origin, band=(-1.0, 2.75), blank_ft=8.0).assumed.all()
    assert not floor_scan(pts, R, origin, band=(-1.0, 2.75)).assumed.any()


def test_assumed_free_stops_at_a_cell_hit_before_and_leaves_seen_cells_alone():
    from planner.octree import (FREE, UNCERTAIN, UNKNOWN, VolumeOfInterest,
                                cell_centres, cell_keys, mark_assumed_free, mark_free_rays,
                                mark_occupied, new_octree, query)
    tree = new_octree(VolumeOfInterest(32.0, 7), confirm_looks=2)      # 0.25 ft cells
    res = tree.getResolution()
    y = 0.1
    o = np.array([0.1, y, 0.1])
    # a face hit at z = 5.1 on the line x = 0.1, then carved free by a later
    # proven sight line (it is free now, but was hit)
    face = cell_centres(np.array([[0.1, y, 5.1]]), res)
    mark_occupied(tree, face)
    # a cell at x = 2.1, z = 4.1 hit once: uncertain
    other = cell_centres(np.array([[2.1, y, 4.1]]), res)
    mark_occupied(tree, other)
    for _ in range(3):                      # a hit is +0.85, a miss -0.41
        mark_free_rays(tree, o, np.array([[0.1, y, 6.1]]), start_ft=0.0)
    assert query(tree, face[0]) == FREE
    hit = cell_keys(np.vstack([face, other]), res)
    ends = np.array([[0.1, y, 8.1], [4.1, y, 8.1], [6.1, y, 0.1]])
    n = mark_assumed_free(tree, o, ends, hit, start_ft=2.3)
    # the first line: its cells before the face were already free (seen), so
    # none is marked; nothing past the face (once hit) is carved
    for z in (5.35, 6.6, 7.6):
        assert query(tree, [0.1, y, z]) == (FREE if z < 6.1 else UNKNOWN)
    # the second line passes the uncertain cell at (2.1, 4.1): carved up to it, not past
    assert query(tree, [0.85, y, 1.6]) == UNKNOWN              # nearer than start_ft
    assert query(tree, [1.6, y, 3.1]) == FREE
    assert query(tree, other[0]) == UNCERTAIN
    assert query(tree, [3.1, y, 6.1]) == UNKNOWN
    # the third line, with no hit cell on it: carved from start_ft to one cell short of its end
    assert query(tree, [2.6, y, 0.1]) == FREE and query(tree, [5.6, y, 0.1]) == FREE
    assert query(tree, [2.0, y, 0.1]) == UNKNOWN and query(tree, [6.05, y, 0.1]) == UNKNOWN
    assert n > 0
    # once more: every cell the assumption may reach is already free, none is marked
    assert mark_assumed_free(tree, o, ends, hit, start_ft=2.3) == 0
    assert query(tree, face[0]) == FREE


def test_place_point_puts_a_pitched_looks_range_where_the_edge_stands():
    """A vertical edge 6 ft ahead of a camera pitched 25 deg down, seen on
    lines 30 and 32 (above the picture's centre): ``place="point"`` puts the
    column's hit at the edge's horizontal position; the default lays the
    range along the tilted optical axis, short by the hand-derived amount."""
    from world.pose import Pose
    pose = Pose(0.0, 0.0, 30.0, -25.0)
    R, left = pose.rotation(), pose.camera_centre("left")
    p = math.radians(25.0)
    # the camera's z axis points forward and down (cos p, sin p), its y axis
    # (down the picture) back and down (-sin p, cos p): a point on line 30
    # (pixel centre 30.5, y = (30.5 - 60) / 180 of its depth) at forward
    # distance 6 ft has the depth 6 / (cos p - (30.5 - 60) / 180 sin p)
    dp = 6.0 / (math.cos(p) - (30.5 - 60) / 180 * math.sin(p))
    pts = [_pt(30, 64, dp, 0.1), _pt(32, 64, dp + 0.01, 0.1)]    # the nearer: line 30
    band = (-5.0, 5.0)
    by_point = floor_scan(pts, R, left, band, place="point")
    by_axis = floor_scan(pts, R, left, band)
    h = math.radians(30.0)
    fwd = np.array([math.sin(h), 0.0, math.cos(h)])
    ahead_point = (by_point.hits[0] - left) @ fwd
    ahead_axis = (by_axis.hits[0] - left) @ fwd
    assert abs(ahead_point - 6.0) < 1e-9
    assert abs(ahead_axis - dp * math.cos(p)) < 1e-9      # the default: short by 0.43 ft
    assert ahead_point - ahead_axis > 0.4
    assert by_point.hits[0][1] == left[1]                 # at the camera's height
    with pytest.raises(ValueError, match="place"):
        floor_scan(pts, R, left, band, place="floor")


def test_stereo_depth_is_where_the_right_camera_starts_to_see_the_column():
    # an independent check by projection: a point in left column c at depth z,
    # seen from both cameras of a pose (world.pose, 0.75 ft apart), lands in the
    # right picture's column c - 135 / z, a picture column (>= 1) exactly from
    # stereo_depth(c) on
    from planner.perception import stereo_depth
    from world.pose import Pose
    pose = Pose(0.0, 0.0, 0.0)
    for c in (2, 10, 20, 54, 100):
        z_min = float(stereo_depth([c])[0])
        assert z_min == pytest.approx(180 * 0.75 / (c - 1))
        for z, inside in ((z_min * 0.98, False), (z_min * 1.02, True)):
            x_cam = (c - 0.5 - 64) * z / 180           # the left camera's ray of column c
            p = pose.to_room(np.array([[x_cam, 0.0, z]]), "left")
            q = pose.to_camera(p, "right")[0]
            right_col = q[0] * 180 / q[2] + 64 + 0.5
            assert right_col == pytest.approx(c - 135 / z)
            assert (right_col >= 1) == inside               # the first picture column
    assert stereo_depth([1])[0] == math.inf


def test_the_stereo_margin_frees_a_column_only_where_both_cameras_see_it():
    # a look that located nothing, level camera, the blank-column assumption to
    # 8 ft: by default every column frees its line from 0; with stereo_margin
    # column c frees it only from depth 135 / (c - 1) on: column 20 from 7.1 ft,
    # column 1 (never in the right picture) nowhere, column 100 from 1.36 ft
    from planner.perception import stereo_depth
    R, origin = np.eye(3), np.zeros(3)
    plain = floor_scan([], R, origin, band=(-1.0, 2.75), blank_ft=8.0, low_y=2.2)
    both = floor_scan([], R, origin, band=(-1.0, 2.75), blank_ft=8.0, low_y=2.2,
                      stereo_margin=True)
    assert np.array_equal(plain.free_ends, both.free_ends)
    assert np.array_equal(plain.free_start, np.zeros(128))
    cols = both.free_cols
    for c in (20, 54, 100):
        k = int(np.flatnonzero(cols == c)[0])
        z = 135 / (c - 1)
        assert both.free_start[k] == pytest.approx(z * math.hypot(1, (c - 0.5 - 64) / 180))
        assert stereo_depth([c])[0] == pytest.approx(z)
    assert both.free_start[cols == 1][0] == math.inf
    # the hits' own lines are proven by the hit itself: the margin leaves them alone
    pts = [_pt(50, 10, 5.0), _pt(52, 10, 5.02)]
    a = floor_scan(pts, R, origin, band=(-1.0, 2.75), blank_ft=8.0, low_y=2.2)
    b = floor_scan(pts, R, origin, band=(-1.0, 2.75), blank_ft=8.0, low_y=2.2,
                   stereo_margin=True)
    assert np.array_equal(a.hits, b.hits) and np.array_equal(a.hit_start, b.hit_start)
