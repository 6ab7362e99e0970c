"""planner/planning.py: the benchmark's yardsticks on hand-made rooms."""

from types import SimpleNamespace

import pytest

from planner.planning import task_slack
from vehicle.profile import DEFAULT

CELL = 0.25


def _gap_room(left_edge: float, right_edge: float):
    """A room 8 ft wide crossed at z 5..6 by two boxes that leave a gap from
    ``left_edge`` to ``right_edge`` (on cell edges); start (0, 0), goal (0, 10)."""
    return SimpleNamespace(bounds=(-4.0, 4.0, -3.0, 14.0),
                           obstacles=[(-4.0, left_edge, 5.0, 6.0), (right_edge, 4.0, 5.0, 6.0)])


@pytest.mark.parametrize("edges, slack", [
    # 11 free cells: the middle column's centre is 6 cells from both boxes' cells, so
    # its clearance (the planner's "anywhere" bound) is (6 - sqrt 2) x 0.25 = 1.146 ft,
    # 0.356 ft over the radius 0.790: two steps of 0.125 ft fit, a third does not
    ((-1.25, 1.5), 0.25),
    # 9 free cells (2.25 ft, the least this vehicle passes): (5 - sqrt 2) x 0.25 = 0.896 ft,
    # 0.106 ft over the radius: not one step to spare
    ((-1.0, 1.25), 0.0),
    # 7 free cells: (4 - sqrt 2) x 0.25 = 0.646 ft, under the radius: no way at all
    ((-0.75, 1.0), None),
])
def test_task_slack_is_the_margin_a_gap_leaves(edges, slack):
    assert DEFAULT.planning_radius_ft == pytest.approx(0.790, abs=5e-4)
    room = _gap_room(*edges)
    assert task_slack(room, (0.0, 0.0), (0.0, 10.0), DEFAULT, CELL) == slack


def test_task_slack_of_an_open_room_is_the_goals_own_room():
    # no boxes; the goal 1.5 ft from the back wall (z1 = 14): its cell's centre 12.625 ft,
    # the first cell past the wall (margin) 14.125: 6 cells, (6 - sqrt 2) x 0.25 = 1.146 ft
    room = SimpleNamespace(bounds=(-4.0, 4.0, -3.0, 14.0), obstacles=[])
    assert task_slack(room, (0.0, 0.0), (0.0, 12.5), DEFAULT, CELL) == 0.25
    # and capped at max_ft where nothing is near
    assert task_slack(room, (0.0, 0.0), (0.0, 5.0), DEFAULT, CELL, max_ft=0.5) == 0.5


def test_a_random_goal_is_tested_where_it_is_returned():
    """random_goal rounds the goal to 0.01 ft; the rounded point is the one the true
    room must join to the start.  Room 126's draw (-2.087.., 10.75..) rounded into the
    next cell, nearer a box than the radius (slack None before the fix); that draw is
    now refused and the next one taken."""
    import numpy as np
    from planner.planning import random_goal
    from vehicle.sim import State
    from world.room import generate_room
    room = generate_room(126)
    goal = random_goal(room, State(0.0, 0.0, 0.0), DEFAULT, np.random.default_rng(126))
    assert goal != (-2.09, 10.75)
    assert goal == (round(goal[0], 2), round(goal[1], 2))
    assert room.clearance(*goal) >= DEFAULT.planning_radius_ft
    assert task_slack(room, (0.0, 0.0), goal, DEFAULT, CELL) is not None
