"""The goal as a region (``DriveConfig.goal_region="disc"``): the planner plans
to the standable cell nearest the goal inside the loop's goal tolerance, on
hand-made maps whose geometry says where the vehicle may stand."""

import math

import numpy as np
import pytest

from planner.floormap import true_floor_map
from planner.loop import DriveConfig
from planner.planning import GOAL_SLACK_FT, goal_target, plan
from planner.search import NoPath, clearance_map, hierarchical_search, segment_samples
from vehicle.profile import DEFAULT
from vehicle.sim import State

ROOM = (0.0, 12.0, 0.0, 12.0)
CELL = 0.25
WALL_X = 6.0                       # a wall filling x >= 6 ft, the goal hugging its face
R = DEFAULT.planning_radius_ft     # 0.79 ft


def wall_map():
    return true_floor_map([(WALL_X, 12.0, 0.0, 12.0)], ROOM, CELL, margin=0.0)


def test_a_goal_hugging_a_wall_refused_as_a_point_reached_as_a_disc():
    goal = (WALL_X - 0.55, 6.1)                  # 0.55 ft from the face: the vehicle cannot stand there
    start = State(2.0, 6.0, 90.0)
    fm = wall_map()
    p = clearance_map(fm, R, "free", uncertain="blocked")
    with pytest.raises(NoPath, match="from an obstacle; the vehicle needs"):
        hierarchical_search(p, (start.x, start.z), goal)
    pts, cmds, note = plan(fm, start, goal, DriveConfig(goal=goal, goal_region="disc"))
    end = pts[-1]
    tol = DriveConfig.tolerance_ft
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) <= tol - GOAL_SLACK_FT + 1e-9
    assert "disc" in note
    # never through the wall, nor nearer its face than the planning radius less
    # nothing: every point of the path has the radius to the TRUE face
    for a, b in zip(pts[:-1], pts[1:]):
        s = segment_samples(a, b, CELL / 8)
        assert (WALL_X - s[:, 0] >= R - 1e-9).all()
    # the target is the passable cell nearest the goal inside the disc (brute force)
    ii, jj = np.nonzero(p.ok)
    cx, cz = fm.centre(ii, jj)
    d = np.hypot(cx - goal[0], cz - goal[1])
    inside = d <= tol - GOAL_SLACK_FT
    assert inside.any()
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) == pytest.approx(d[inside].min())
    # standing there, the loop's success test (the disc) holds
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) <= tol


def test_a_standable_goal_is_planned_to_itself():
    goal = (3.0, 9.0)
    fm = wall_map()
    p = clearance_map(fm, R, "free", uncertain="blocked")
    assert goal_target(p, (2.0, 6.0), goal, 0.65) == goal
    pts, _, note = plan(fm, State(2.0, 6.0, 0.0), goal, DriveConfig(goal=goal, goal_region="disc"))
    assert pts[-1] == goal and note == "path to the goal"


def test_no_standable_cell_in_the_disc_leaves_the_point_plan_saying_why():
    goal = (WALL_X - 0.2, 6.0)                   # every cell within 0.65 ft lacks the radius
    fm = wall_map()
    p = clearance_map(fm, R, "free", uncertain="blocked")
    assert goal_target(p, (2.0, 6.0), goal, 0.65) == goal
    with pytest.raises(NoPath, match="from an obstacle"):
        hierarchical_search(p, (2.0, 6.0), goal_target(p, (2.0, 6.0), goal, 0.65))


def test_a_disc_cell_cut_off_from_the_start_is_not_the_target():
    # a second wall closes the start off from the near side of the goal's disc:
    # the disc's cells beyond it are standable but not reachable
    fm = true_floor_map([(WALL_X, 12.0, 0.0, 12.0), (0.0, 12.0, 7.0, 7.25)], ROOM, CELL,
                        margin=0.0)
    p = clearance_map(fm, R, "free", uncertain="blocked")
    goal = (WALL_X - 0.55, 8.2)                 # above the cross wall, start below it
    assert goal_target(p, (2.0, 4.0), goal, 0.65) == goal


def test_goal_region_is_checked_and_reaches_the_loop_by_its_flags(tmp_path, monkeypatch):
    from planner.loop import run
    from planner.tiny import GOAL, tiny_room
    from rigtools import drive_config
    with pytest.raises(ValueError, match="goal_region"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, goal_region="area"))
    cfg = drive_config(monkeypatch, tmp_path, "--goal-region", "disc")
    assert cfg.goal_region == "disc"
    assert drive_config(monkeypatch, tmp_path).goal_region == "disc"      # since 2026-12-05
    assert drive_config(monkeypatch, tmp_path, "--goal-region", "point").goal_region == "point"
