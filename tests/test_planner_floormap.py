"""planner/floormap.py: the one-cell gaps of free space (``free_gaps="fill"``)."""

import numpy as np

from planner.floormap import fill_one_cell_gaps, one_cell_gaps, true_floor_map
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN

F, O, U, C = FREE, OCCUPIED, UNKNOWN, UNCERTAIN


def test_a_gap_across_a_row_or_a_column_is_found_and_nothing_else():
    cells = np.array([[U, F, U, U, U],
                      [F, U, F, U, U],      # (1, 1): free left and right
                      [U, F, U, F, U],      # (2, 2): free left and right, and above and below
                      [U, U, F, U, U],
                      [U, U, U, U, U]], np.uint8)
    got = one_cell_gaps(cells)
    assert np.argwhere(got).tolist() == [[1, 1], [2, 2]]


def test_no_gap_from_a_diagonal_pair_an_obstacle_or_two_cells_wide():
    diagonal = np.array([[F, U, U],
                         [U, U, U],
                         [U, U, F]], np.uint8)
    assert not one_cell_gaps(diagonal)[1, 1]
    beside_hit = np.array([[F, U, O],
                           [U, U, U],
                           [F, C, F]], np.uint8)
    assert not one_cell_gaps(beside_hit)[0, 1]         # free on one side only
    assert not one_cell_gaps(beside_hit)[2, 1]         # uncertain is not unknown
    two_wide = np.array([[F, U, U, F]], np.uint8)
    assert not one_cell_gaps(two_wide).any()
    border = np.array([[U, F]], np.uint8)              # off the map is not free
    assert not one_cell_gaps(border).any()


def test_a_filled_gap_never_lands_on_a_box_where_its_neighbours_are_truly_free():
    """External truth: random boxes of at least 0.8 ft (the generated rooms'
    smallest) on the 0.25 ft grid; the map shows a random 60 % of the truly free
    cells free and everything else unknown; no gap it finds is a box cell (the
    diagonal pairs, trusted too, land on 264 box cells of these maps)."""
    rng = np.random.default_rng(7)
    found = 0
    for _ in range(40):
        boxes = []
        for _ in range(6):
            x, z = rng.uniform(-4, 3), rng.uniform(-4, 3)
            w, d = rng.uniform(0.8, 2.0), rng.uniform(0.8, 2.0)
            boxes.append((x, x + w, z, z + d))
        truth = true_floor_map(boxes, (-5.0, 5.0, -5.0, 5.0), 0.25, margin=0.0)
        cells = np.full(truth.cells.shape, UNKNOWN, np.uint8)
        shown = (truth.cells == FREE) & (rng.random(truth.cells.shape) < 0.6)
        cells[shown] = FREE
        gaps = one_cell_gaps(cells)
        found += int(gaps.sum())
        assert not (gaps & (truth.cells == OCCUPIED)).any()
    assert found > 1000                 # the test has gaps to check


def test_filling_goes_on_while_a_filled_cell_closes_the_next_gap():
    chain = np.array([[F, U, F, U, F],
                      [U, U, U, U, U],
                      [F, U, F, U, F]], np.uint8)
    # one pass fills the cells between two free ones: (0, 1), (0, 3), (2, 1), (2, 3)
    # across their rows, (1, 0), (1, 2), (1, 4) across their columns
    once = chain.copy()
    once[one_cell_gaps(chain)] = F
    assert (once[1] == [F, U, F, U, F]).all()
    # the next pass fills (1, 1) and (1, 3), now between two filled cells
    assert (fill_one_cell_gaps(chain) == F).all()
    assert not (chain == F).all()                     # (the input is not changed)
    lone = np.array([[U, F, U],
                     [F, U, U],
                     [U, U, U]], np.uint8)
    assert (fill_one_cell_gaps(lone) == lone).all()   # nothing between two free cells


def test_free_gaps_reach_the_loop_and_fill_its_map(monkeypatch, tmp_path):
    """``rig drive --free-gaps keep`` reaches DriveConfig (default ``fill`` since
    2026-12-05), a bad value is refused, and under ``fill`` the loop's drawn map has no one-cell gap left (it
    drives the tiny room to its goal on oracle edges without a collision)."""
    import pytest

    from planner.loop import DriveConfig, run, _check_config
    from planner.tiny import GOAL, tiny_room
    from rigtools import drive_config
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    assert DriveConfig.free_gaps == "fill"
    assert drive_config(monkeypatch, tmp_path).free_gaps == "fill"
    assert drive_config(monkeypatch, tmp_path, "--free-gaps", "keep").free_gaps == "keep"
    with pytest.raises(ValueError, match="free_gaps"):
        _check_config(DriveConfig(goal=GOAL, free_gaps="close"))
    res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="truth",
              sight_lines="band", free_gaps="fill"), noise=OdometryNoise(seed=1))
    assert res.reached and res.collisions == 0
    maps = [c.fmap for c in res.cycles]
    assert maps and not any(one_cell_gaps(m.cells).any() for m in maps)
