"""The volumetric model (Chapter IV) on hand-made points and rays, and the
floor map (Chapter VI) projected from it."""

import numpy as np
import pytest

from planner.floormap import project_octree, true_floor_map
from planner.octree import (FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest, insert_feature,
                            insert_look, insert_rays, insert_surface, leaves, memory_bytes,
                            new_octree, query)

RES = 0.25


def tree():
    return new_octree(VolumeOfInterest(32.0, 7))


def test_volume_of_interest_depth_from_accuracy():
    assert VolumeOfInterest(32.0, 7).resolution == 0.25
    assert VolumeOfInterest.for_accuracy(0.25).depth == 7
    assert VolumeOfInterest.for_accuracy(0.2).depth == 8      # 32/2^8 = 0.125 <= 0.2
    with pytest.raises(ValueError, match="positive"):
        VolumeOfInterest.for_accuracy(0)


def test_ray_free_along_sight_line_occupied_at_point_unknown_elsewhere():
    t = tree()
    origin = (0.125, 0.125, 0.125)
    insert_rays(t, np.array([[0.125, 0.125, 5.125]]), origin)
    assert query(t, (0.125, 0.125, 5.125)) == OCCUPIED
    for z in (0.125, 1.0, 2.5, 4.8):
        assert query(t, (0.125, 0.125, z)) == FREE
    assert query(t, (0.125, 0.125, 5.6)) == UNKNOWN           # behind the point
    assert query(t, (1.125, 0.125, 2.0)) == UNKNOWN           # beside the ray
    assert query(t, (-3.0, 2.0, 2.0)) == UNKNOWN


def test_hit_wins_over_a_later_pass_through_only_after_repeated_misses():
    # OctoMap's log-odds: one hit (0.7) then one miss (0.4) stays occupied
    t = tree()
    insert_rays(t, np.array([[0.125, 0.125, 3.125]]), (0.125, 0.125, 0.125))
    insert_rays(t, np.array([[0.125, 0.125, 6.125]]), (0.125, 0.125, 0.125))
    assert query(t, (0.125, 0.125, 3.125)) == OCCUPIED
    for _ in range(3):
        insert_rays(t, np.array([[0.125, 0.125, 6.125]]), (0.125, 0.125, 0.125))
    assert query(t, (0.125, 0.125, 3.125)) == FREE


def test_feature_grown_by_its_covariance():
    t = tree()
    # sigma 0.5 ft along X, 0.1 along Y and Z: two sigma = 1 ft along X only
    n = insert_feature(t, (2.0, 0.0, 4.0), np.diag([0.25, 0.01, 0.01]))
    assert n >= 8
    assert query(t, (2.0, 0.0, 4.0)) == OCCUPIED
    assert query(t, (2.8, 0.0, 4.0)) == OCCUPIED
    assert query(t, (1.2, 0.0, 4.0)) == OCCUPIED
    assert query(t, (3.3, 0.0, 4.0)) == UNKNOWN                # beyond two sigma
    assert query(t, (2.0, 0.0, 4.6)) == UNKNOWN                # only 0.1 ft along Z


def test_surface_between_boundary_points():
    t = tree()
    insert_surface(t, (0.0, 0.0, 6.0), (3.0, 0.0, 6.0))
    for x in np.arange(0.1, 3.0, 0.25):
        assert query(t, (x, 0.0, 6.0)) == OCCUPIED
    assert query(t, (0.1, 0.0, 6.6)) == UNKNOWN
    t2 = tree()
    insert_surface(t2, (0.0, 0.0, 6.0), (2.0, 0.0, 6.0), (0.0, 2.0, 6.0))
    assert query(t2, (1.9, 1.9, 6.0)) == OCCUPIED


def test_leaves_and_memory():
    t = tree()
    insert_rays(t, np.array([[0.125, 0.125, 5.125]]), (0.125, 0.125, 0.125))
    c, s, state = leaves(t)
    occ = state == OCCUPIED
    assert occ.sum() == 1 and np.allclose(c[occ][0], (0.125, 0.125, 5.125))
    assert (state[~occ] == FREE).all()
    assert (s >= RES - 1e-9).all()
    assert memory_bytes(t) > 0


def test_floor_map_projection_over_the_height_band():
    t = tree()
    # a box face 2 ft ahead in the band, a shelf above the vehicle (Y = -2: 5 ft
    # above the floor), a ray at camera height clearing the way
    insert_surface(t, (1.0, 1.0, 2.125), (2.0, 1.0, 2.125))
    insert_surface(t, (-2.0, -2.0, 2.125), (-1.0, -2.0, 2.125))
    insert_rays(t, np.array([[0.125, 0.125, 6.125]]), (0.125, 0.125, 0.125))
    fm = project_octree(t, (-3.0, 3.0, 0.0, 8.0), band=(-0.5, 2.75))
    assert fm.cell == RES
    assert fm.state_at(1.5, 2.125) == OCCUPIED
    assert fm.state_at(-1.5, 2.125) == UNKNOWN          # above the band: not in the way
    assert fm.state_at(0.125, 3.0) == FREE
    assert fm.state_at(0.125, 6.125) == OCCUPIED
    assert fm.state_at(2.6, 7.0) == UNKNOWN


def test_true_floor_map_marks_obstacles_and_walls():
    fm = true_floor_map([(1.0, 2.0, 3.0, 4.0)], (0.0, 5.0, 0.0, 6.0), 0.25, margin=0.5)
    assert fm.state_at(1.5, 3.5) == OCCUPIED
    assert fm.state_at(0.9, 3.5) == FREE
    assert fm.state_at(2.1, 3.5) == FREE
    assert fm.state_at(-0.1, 3.0) == OCCUPIED            # beyond the wall
    assert fm.state_at(0.1, 3.0) == FREE
    # a footprint edge on a cell edge does not spill into the neighbour
    assert fm.state_at(0.875, 3.5) == FREE


def test_confirm_looks_one_look_is_uncertain_two_are_occupied():
    t = new_octree(VolumeOfInterest(32.0, 7), confirm_looks=2)
    far = np.array([[0.125, 0.125, 5.125]])
    origin = (0.125, 0.125, 0.125)
    insert_rays(t, far, origin)
    assert query(t, (0.125, 0.125, 5.125)) == UNCERTAIN   # one hit: not yet believed
    assert query(t, (0.125, 0.125, 2.0)) == FREE           # one miss: free
    insert_rays(t, far, origin)
    assert query(t, (0.125, 0.125, 5.125)) == OCCUPIED
    # a false point seen once, then seen through twice, is free
    t2 = new_octree(VolumeOfInterest(32.0, 7), confirm_looks=2)
    insert_rays(t2, np.array([[0.125, 0.125, 2.125]]), origin)
    for _ in range(3):
        insert_rays(t2, far, origin)
    assert query(t2, (0.125, 0.125, 2.125)) == FREE
    with pytest.raises(ValueError, match="confirm_looks"):
        new_octree(confirm_looks=0)


def test_insert_look_updates_each_cell_once():
    t = new_octree(VolumeOfInterest(32.0, 7), confirm_looks=2)
    pts = np.array([[0.125, 0.125, 5.125], [2.125, 0.125, 5.125]])
    covs = np.array([np.diag([0.0001, 0.0001, 0.0001])] * 2)
    extra = insert_look(t, (0.125, 0.125, 0.125), pts, covs, spans=[(0, 1)])
    assert extra == 7                 # the span's cells between the two end cells
    # one look: the end points and the span are all hit once -> uncertain
    for x in (0.125, 1.125, 2.125):
        assert query(t, (x, 0.125, 5.125)) == UNCERTAIN
    insert_look(t, (0.125, 0.125, 0.125), pts, covs, spans=[(0, 1)])
    for x in (0.125, 1.125, 2.125):
        assert query(t, (x, 0.125, 5.125)) == OCCUPIED


def test_vectorised_cells_equal_the_one_at_a_time_ones():
    from planner.octree import feature_cells, features_cells, spans_cells, surface_cells
    rng = np.random.default_rng(3)
    means = rng.uniform(-5, 5, (20, 3))
    A = rng.normal(0, 0.15, (20, 3, 3))
    covs = A @ np.transpose(A, (0, 2, 1)) + 0.001 * np.eye(3)
    one = np.unique(np.vstack([feature_cells(m, c, RES) for m, c in zip(means, covs)]), axis=0)
    assert np.array_equal(np.unique(features_cells(means, covs, RES), axis=0), one)
    spans = [(0, 1), (2, 3), (4, 9)]
    one = np.unique(np.vstack([surface_cells(means[a], means[b], RES) for a, b in spans]), axis=0)
    assert np.array_equal(np.unique(spans_cells(means, spans, RES), axis=0), one)


def test_free_looks_two_misses_needed():
    t = new_octree(VolumeOfInterest(32.0, 7), confirm_looks=2)
    far = np.array([[0.125, 0.125, 5.125]])
    insert_rays(t, far, (0.125, 0.125, 0.125))
    assert query(t, (0.125, 0.125, 2.0), free_looks=2) == UNKNOWN      # one look through
    insert_rays(t, far, (0.125, 0.125, 0.125))
    assert query(t, (0.125, 0.125, 2.0), free_looks=2) == FREE


def test_cell_centres_equal_the_plain_unique_rows():
    # the packed-key version against numpy's row-wise unique, negative
    # coordinates and points on cell edges included
    from planner.octree import cell_centres
    rng = np.random.default_rng(11)
    pts = np.vstack([rng.uniform(-40, 40, (5000, 3)),
                     rng.integers(-80, 80, (500, 3)) * 0.125])
    for res in (0.25, 0.125):
        plain = (np.unique(np.floor(pts / res), axis=0) + 0.5) * res
        assert np.array_equal(cell_centres(pts, res), plain)


def test_feature_growth_capped_at_the_same_distance_at_every_depth():
    # a feature with a 10 ft sigma along X is grown 1.5 ft each way (plus its
    # own cell) whatever the cell size: 6 cells of 0.25 ft, 12 of 0.125 ft
    from planner.octree import MAX_GROWTH_FT, features_cells
    mean = np.array([[0.01, 0.01, 0.01]])
    cov = np.diag([100.0, 1e-6, 1e-6])[None]
    for res in (0.25, 0.125):
        x = features_cells(mean, cov, res)[:, 0]
        assert len(x) == 2 * round(MAX_GROWTH_FT / res) + 1
        assert x.min() == pytest.approx(-MAX_GROWTH_FT + res / 2)
        assert x.max() == pytest.approx(MAX_GROWTH_FT + res / 2)


def test_projection_from_touched_cells_equals_the_one_from_all_leaves():
    # looks of rays carved free and hits marked (some twice: occupied, some
    # once: uncertain, some seen through again), at heights in and out of the
    # band, with big uniform regions that OctoMap prunes into larger leaves;
    # after every look the map read back from the touched cells equals the
    # map drawn from every leaf, at both depths
    from planner.octree import mark_free_rays, mark_occupied
    rng = np.random.default_rng(5)
    for depth in (7, 8):
        t = new_octree(VolumeOfInterest(32.0, depth), confirm_looks=2)
        res = t.getResolution()
        # a solid block, then carved: whole pruned leaves that later split
        block = np.stack(np.meshgrid(*[(np.arange(16) + 0.5) * res] * 3, indexing="ij"),
                         -1).reshape(-1, 3)
        mark_occupied(t, block)
        for look in range(12):
            o = np.array([rng.uniform(-2, 2), rng.uniform(-1, 1), rng.uniform(-2, 2)])
            ang = np.radians(rng.uniform(0, 360) + np.linspace(-20, 20, 40))
            ends = o + rng.uniform(1, 6, (40, 1)) * np.stack(
                [np.sin(ang), rng.uniform(-0.3, 0.3, 40), np.cos(ang)], 1)
            mark_free_rays(t, o, ends, start_ft=rng.choice([0.0, 1.0]))
            mark_occupied(t, np.unique(np.floor(ends[::2] / res), axis=0) * res + res / 2)
            assert t.log_complete
            for band, free_band in (((-0.5, 0.5), None), ((-0.3, 2.0), (0.2, 2.0))):
                for free_looks in (1, 2):
                    kw = dict(band=band, free_band=free_band, free_looks=free_looks)
                    fast = project_octree(t, (-6.0, 6.0, -6.0, 6.0), **kw)
                    full = project_octree(t, (-6.0, 6.0, -6.0, 6.0), from_leaves=True, **kw)
                    assert np.array_equal(fast.cells, full.cells)
                    assert (fast.x0, fast.z0, fast.cell) == (full.x0, full.z0, full.cell)
        states = set(np.unique(fast.cells).tolist())
        assert {FREE, OCCUPIED, UNCERTAIN, UNKNOWN} <= states
        assert t.getNumLeafNodes() < len(t.__dict__["_touched_cells"].keys)   # pruned


def test_untracked_changes_fall_back_to_all_leaves():
    t = new_octree(VolumeOfInterest(32.0, 7))
    insert_rays(t, np.array([[0.125, 0.125, 5.125]]), (0.125, 0.125, 0.125))
    assert not t.log_complete                       # OctoMap's own ray casting: not logged
    fm = project_octree(t, (-3.0, 3.0, 0.0, 8.0), band=(-0.5, 2.75))
    assert fm.state_at(0.125, 6.125) == UNKNOWN and fm.state_at(0.125, 5.125) == OCCUPIED
    assert fm.state_at(0.125, 3.0) == FREE


def test_map_losses_sorts_the_wrongly_blocked_cells_and_the_width_they_cost():
    from planner.floormap import FloorMap, map_losses
    # a room of 0.25 ft cells (38 x 38 inside, one cell of wall round it)
    # with a wall across row 8 leaving a gap of columns 5..12 (2 ft); the map
    # knows the walls and adds: the gap's left neighbour (rounding), a cell 3
    # rows from the wall (growth), an uncertain cell 11 cells from everything
    # (false), and leaves one free cell unknown
    c = 0.25
    truth = np.full((40, 40), FREE, np.uint8)
    truth[0, :] = truth[-1, :] = truth[:, 0] = truth[:, -1] = OCCUPIED
    truth[8, 1:5] = OCCUPIED
    truth[8, 13:39] = OCCUPIED
    fm = truth.copy()
    fm[8, 5] = OCCUPIED
    fm[11, 3] = OCCUPIED
    fm[28, 20] = UNCERTAIN
    fm[4, 9] = UNKNOWN
    out = map_losses(FloorMap(fm, 0.0, 0.0, c), FloorMap(truth, 0.0, 0.0, c), radius=0.5)
    assert out["blocked_rounding"] == 1 and out["blocked_rounding_uncertain"] == 0
    assert out["blocked_growth"] == 1
    assert out["blocked_false"] == 1 and out["blocked_false_uncertain"] == 1
    assert out["seen_unknown"] == 1
    assert out["true_obstacle_mapped_free"] == 0
    # the 2 ft gap passes a vehicle of radius 0.5 ft in the room; the
    # rounding cell at its side costs passable cells in it
    gap = FloorMap(truth, 0.0, 0.0, c)
    from planner.search import clearance_map
    assert clearance_map(gap, 0.5, "free").ok[8, 5:13].any()
    assert out["passable_lost_rounding"] > 0
    assert 0 < out["passable_lost_uncertain_only"] <= out["passable_lost_false"]
    assert out["passable_map"] + out["passable_lost_rounding"] + out["passable_lost_growth"] + \
        out["passable_lost_false"] == out["passable_true"]
    with pytest.raises(ValueError, match="cells differ"):
        map_losses(FloorMap(fm, 0.0, 0.0, 0.125), FloorMap(truth, 0.0, 0.0, c), 0.5)
