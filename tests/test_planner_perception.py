"""The loop's perception step (planner.perception) on hand-made located points."""

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
