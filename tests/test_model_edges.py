"""Vertical edges grouped over scan lines and their vertex observations,
against values worked out by hand from A-6..A-8, A-13, A-17, A-18, A-20."""

import numpy as np
import pytest

from model.edges import group_vertical_edges, locate, Camera, vertex_observations
from rig.scan import Point


def pts(lines, loc1, disparity, edge=1):
    return [Point(y, edge, loc1, loc1 - disparity, 0, 0, 0, 0, 0, 0) for y in lines]


def test_locate_hand_example():
    # column 69.5 (LOC1 70), row 20.0, disparity 10, ds 0.75, dv 180:
    # dp = 135/10 = 13.5; dx = 5.5*13.5/180 = 0.4125; dy = -40*13.5/180 = -3.0
    # ep = 135*1/(100 - 10) = 1.5; ex = (5.5*1.5 + 13.5*0.5 + 1.5*0.5)/180 = 0.0875
    # ey (eD = 1) = (40*1.5 + 13.5 + 1.5)/180 = 75/180
    q, C = locate(69.5, 20.0, 10.0, Camera(), e_d=1.0)
    np.testing.assert_allclose(q, [13.5, 0.4125, -3.0])
    np.testing.assert_allclose(np.diag(C), [0.75 ** 2, 0.04375 ** 2, (75 / 360) ** 2])
    assert locate(64, 60, 1.0, Camera()) is None          # disparity not above 1 px (LCSL)


def test_two_edges_and_their_vertices():
    lines = range(8, 113)
    points = pts(range(20, 41), 70, 10) + pts(range(30, 51), 90, 20, edge=51)
    edges = group_vertical_edges(points, lines)
    assert len(edges) == 2
    a, b = edges
    assert a.lines == tuple(range(20, 41)) and b.lines == tuple(range(30, 51))
    tops = [v for v in vertex_observations(edges) if v.kind == "top"]
    # the corner lies between the last line without the edge and the first with it
    assert tops[0].row == pytest.approx(20.0) and tops[0].col == pytest.approx(69.5)
    q, C = locate(69.5, 20.0, 10.0, Camera(), e_d=1.0)
    np.testing.assert_allclose(tops[0].q, q)
    np.testing.assert_allclose(tops[0].cov, C)
    bottom = [v for v in a.vertices if v.kind == "bottom"][0]
    assert bottom.row == pytest.approx(41.0)


def test_clipped_ends_are_not_vertices_and_disparity_jumps_split():
    lines = range(8, 113)
    edges = group_vertical_edges(pts(range(8, 30), 50, 12), lines)
    assert len(edges) == 1 and edges[0].top_clipped
    assert [v.kind for v in edges[0].vertices] == ["bottom"]
    split = group_vertical_edges(pts(range(40, 50), 60, 8) + pts(range(50, 60), 60, 12), lines)
    assert len(split) == 2


def test_short_chains_are_dropped_and_line_gaps_bridged():
    lines = range(8, 113)
    assert group_vertical_edges(pts(range(40, 43), 60, 8), lines) == []     # 3 lines < 4
    gapped = pts(range(40, 46), 60, 8) + pts(range(48, 54), 60, 8)           # 2 lines missing
    assert len(group_vertical_edges(gapped, lines)) == 1


def test_wrong_stereo_match_is_dropped_by_the_grey_check():
    left = np.full((120, 128), 5, np.uint8)
    left[:, 69:] = 12                         # a step at column 69 in the left picture
    right = np.full((120, 128), 5, np.uint8)
    right[:, 59:] = 12                        # ... and 10 px left in the right picture
    good = pts(range(30, 40), 70, 10)
    assert len(group_vertical_edges(good, range(8, 113), left, right_picture=right)) == 1
    wrong = pts(range(30, 40), 70, 25)        # paired with a place where the right picture is flat
    assert group_vertical_edges(wrong, range(8, 113), left, right_picture=right) == []


def test_surface_between_two_edges_of_one_feature():
    from model.edges import surface_observations
    left = np.full((120, 128), 5, np.uint8)
    left[:, 70:90] = 11
    left[40, 75] = 13                          # the lightest pixel inside
    # feature 3 of each line: its left end (edge 3) at LOC1 71, its right end (edge 53) at 90
    points = pts(range(30, 50), 71, 10, edge=3) + pts(range(30, 50), 90, 10, edge=53)
    edges = group_vertical_edges(points, range(8, 113), left)
    surfaces = surface_observations(edges, left)
    assert len(surfaces) == 1
    s = surfaces[0]
    assert (s.left_edge, s.right_edge) == (0, 1) and s.lines == tuple(range(30, 50))
    assert s.grey_extremes == (11, 13)
    np.testing.assert_allclose(s.centre, (edges[0].centre + edges[1].centre) / 2)


def test_corner_map_of_a_box_corner():
    from model.edges import corner_map
    pic = np.full((120, 128), 5, np.uint8)
    pic[40:, 70:] = 12                       # a lighter box whose top-left corner is (col 70, row 40)
    # the window: columns 62..77, rows 40..55; set where nearer the right-side grey (12)
    words = corner_map(pic, 70.0, 40.0, "top", (5, 12))
    assert words == (0,) * 8 + (0xFFFF,) * 8
    # the bottom view of the same corner sees the background above it: nothing set
    assert corner_map(pic, 70.0, 40.0, "bottom", (5, 12)) == (0,) * 16


def test_calibrated_column_error_hand_example():
    # the hand example above with the column bound 2.0 px instead of LCSL's 0.5:
    # ex = (5.5*1.5 + 13.5*2 + 1.5*2)/180 = 38.25/180; range and vertical bounds unchanged
    from model.edges import CALIBRATED_COLUMN_ERROR_PX
    q0, C0 = locate(69.5, 20.0, 10.0, Camera(), e_d=1.0)
    q, C = locate(69.5, 20.0, 10.0, Camera(), e_d=1.0, e_col=CALIBRATED_COLUMN_ERROR_PX)
    np.testing.assert_array_equal(q, q0)
    np.testing.assert_allclose(np.diag(C), [0.75 ** 2, (38.25 / 360) ** 2, (75 / 360) ** 2])
    assert locate(64, 60, 1.0, Camera(), e_col=2.0) is None   # LCSL's refusal is kept
    e = group_vertical_edges(pts(range(20, 41), 70, 10), range(8, 113), column_error=2.0)
    v = e[0].vertices[0]
    np.testing.assert_allclose(v.cov, locate(v.col, v.row, v.disparity, Camera(), e_d=1.0,
                                             e_col=2.0)[1])
    d = group_vertical_edges(pts(range(20, 41), 70, 10), range(8, 113))[0].vertices[0]
    assert v.cov[1, 1] > 4 * d.cov[1, 1] and v.cov[0, 0] == d.cov[0, 0]


def test_calibrated_bound_covers_the_measured_column_error_monte_carlo():
    # the measured column error of the rig at true corners is nearly uniform over +-1.5 px
    # (sd 0.96-0.99 px, bench/walk.py --calibrate); a true corner at 10 ft on the optical
    # axis, seen with such errors: LCSL's 0.5 px bound (sigma about 0.3 px with the range
    # term of A-17) puts about a fifth of the true lateral offsets inside 2 sigma, the
    # calibrated 2.0 px bound all of them
    rng = np.random.default_rng(7)
    cam = Camera()
    dp, col = 10.0, 64.0
    true_x = (col - cam.centre_col) * dp / cam.dv
    disparity = cam.ds * cam.dv / dp
    errs = rng.uniform(-1.5, 1.5, 20000)
    share = {}
    for e_col in (0.5, 2.0):
        inside = 0
        for d in errs[:2000]:
            q, C = locate(col + d, 60.0, disparity, cam, e_col=e_col)
            inside += abs(q[1] - true_x) <= 2 * np.sqrt(C[1, 1])
        share[e_col] = inside / 2000
    assert 0.15 < share[0.5] < 0.45
    assert share[2.0] == 1.0


def _edge_at(col, disparity, lines=(40, 42, 44, 46)):
    from model.edges import EdgeObservation
    n = len(lines)
    return EdgeObservation(tuple(lines), (col + 0.5,) * n, (float(disparity),) * n,
                           np.zeros(3), np.eye(3), (3, 12), False, False)


def test_stereo_ambiguity_flags_a_picket_fence_and_not_a_lone_edge():
    """Hand-made pairs, the right picture the left one moved by a true disparity of 20 px
    (right[x] = left[x + 20]).  Worked out by hand: comparing the left patch (3 px either
    side of the edge, 4 lines) with the right one at disparity d compares the left picture
    with itself moved by 20 - d."""
    from model.edges import is_ambiguous, stereo_ambiguity
    x = np.arange(128 + 20)
    # stripes 4 px wide (period 8): the rig took disparity 28, one period off; the true 20
    # and every other period fit as well (0 grey levels off): the first of them is d = 12
    stripes = np.where((x // 4) % 2 == 0, 3, 12)
    left, right = np.tile(stripes[:128], (120, 1)), np.tile(stripes[20:], (120, 1))
    score = stereo_ambiguity(left, right, _edge_at(72, 28), (9.0, 135.0))
    assert score == (0.0, 0.0, 12.0) and is_ambiguous(score)
    # one step (5 | 12 at column 70), matched right: any other disparity misses the step by
    # 3 px at least, 3 of the 7 px wrong by 7 levels = 3.0 on average, first at d = 9
    step = np.where(x >= 70, 12, 5)
    left, right = np.tile(step[:128], (120, 1)), np.tile(step[20:], (120, 1))
    score = stereo_ambiguity(left, right, _edge_at(70, 20), (9.0, 135.0))
    assert score == (0.0, 3.0, 9.0) and not is_ambiguous(score)
    # a patch hanging over the picture's side has no score
    assert stereo_ambiguity(left, right, _edge_at(1, 20), (9.0, 135.0)) is None


def test_alternative_disparities_are_the_picket_fence_periods():
    """The stripes of the test above (period 8 px, true disparity 20, the rig's 28): every
    disparity 20 + 8n fits as well as the rig's.  The patch (columns 69..75) stays inside
    the right picture up to disparity 69, so the fits are d = 12, 20, 36, .., 68: offsets
    -16, -8, 8, .., 40 from 28, nearest first; one step has none."""
    from model.edges import Camera, VertexObservation, alternative_disparities, locate, shifted_vertex
    x = np.arange(128 + 20)
    stripes = np.where((x // 4) % 2 == 0, 3, 12)
    left, right = np.tile(stripes[:128], (120, 1)), np.tile(stripes[20:], (120, 1))
    assert alternative_disparities(left, right, _edge_at(72, 28), (9.0, 135.0)) == \
        [-8, 8, -16, 16, 24, 32, 40]
    step = np.where(x >= 70, 12, 5)
    left, right = np.tile(step[:128], (120, 1)), np.tile(step[20:], (120, 1))
    assert alternative_disparities(left, right, _edge_at(70, 20), (9.0, 135.0)) == []
    # the corner located again one period nearer in disparity: A-6's range 0.75 * 180 / 20
    q, C = locate(72.5, 39.5, 28.0, Camera(), e_d=1.5)
    v = VertexObservation(q, C, "top", 72.5, 39.5, 28.0, (3, 12), 0, 40)
    w = shifted_vertex(v, -8, Camera(), e_d=1.5)
    assert w.disparity == 20.0 and w.q[0] == pytest.approx(6.75)
    np.testing.assert_allclose(w.cov, locate(72.5, 39.5, 20.0, Camera(), e_d=1.5)[1])
    assert (w.col, w.row, w.kind, w.line) == (v.col, v.row, v.kind, v.line)
    assert shifted_vertex(v, -27.5, Camera()) is None        # LCSL's refusal (disparity 0.5)
