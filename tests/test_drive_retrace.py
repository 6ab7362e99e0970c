"""planner/motion.py push_trail and retrace, and DriveConfig.backing="trail"
(not 1985): the vehicle backs only along its own way, undoing its last
motions where it cannot turn at all.  The trails and their undoing are worked
out by hand; the vehicle executes them with the odometry noise off, so it
must come back exactly to where it stood."""

import dataclasses
import math

import numpy as np
import pytest

from planner.loop import RETRACE_FT, DriveConfig, run
from planner.motion import push_trail, retrace
from vehicle.commands import Arc, Back, Forward, Pan, Tilt, Turn
from vehicle.profile import DEFAULT
from vehicle.sim import State, Vehicle


def _trail(*cmds):
    trail = []
    for c in cmds:
        push_trail(trail, c)
    return trail


def test_push_trail_cancels_what_a_motion_undoes():
    # turns in place merge; a look round that turns back leaves nothing
    assert _trail(Forward(1.5), Turn(35.0), Turn(-35.0)) == [Forward(1.5)]
    assert _trail(Turn(30.0), Turn(-10.0)) == [Turn(20.0)]
    # a BACK eats the FORWARD before it, and what is left of either stays
    assert _trail(Forward(1.5), Back(0.5)) == [Forward(1.0)]
    assert _trail(Forward(0.5), Forward(1.0), Back(1.25)) == [Forward(0.25)]
    assert _trail(Forward(1.0), Back(1.5)) == [Back(0.5)]
    # ... but not across a turn: the way back runs through the turn
    assert _trail(Forward(1.0), Turn(90.0), Back(0.5)) == [Forward(1.0), Turn(90.0), Back(0.5)]
    # the head moves no wheel; a zero move is no motion
    assert _trail(Forward(1.0), Pan(40.0), Tilt(-20.0), Forward(0.0), Back(1.0)) == []
    assert _trail(Arc(1.5, 45.0)) == [Arc(1.5, 45.0)]


def test_retrace_undoes_the_newest_motions_first():
    trail = _trail(Forward(1.5), Turn(-30.0), Forward(0.7), Turn(35.0), Turn(-35.0))
    # 0.7 ft back, the turn undone, then 0.8 ft more of the first move: 1.5 ft in all
    assert retrace(trail, 1.5) == [Back(0.7), Turn(30.0), Back(0.8)]
    # a turn before the undone travel is not undone as well
    assert retrace(_trail(Turn(45.0), Forward(1.0), Turn(-20.0)), 1.5) == \
        [Turn(20.0), Back(1.0)]
    # a BACK of the vehicle's own is driven forward again
    assert retrace(_trail(Forward(1.0), Turn(90.0), Back(0.5)), 1.0) == \
        [Forward(0.5), Turn(-90.0), Back(0.5)]
    # the trail is not changed: the executed undoing is pushed onto it (Drive.act)
    assert trail == [Forward(1.5), Turn(-30.0), Forward(0.7)]


def test_retrace_stops_at_an_arc_and_where_nothing_would_move():
    assert retrace(_trail(Forward(1.0), Arc(1.5, 45.0), Forward(0.5)), 1.5) == [Back(0.5)]
    assert retrace(_trail(Arc(1.5, 45.0), Turn(30.0)), 1.5) == []
    assert retrace(_trail(Turn(30.0)), 1.5) == []
    assert retrace([], 1.5) == []
    assert retrace(_trail(Forward(0.04)), 1.5) == []


def test_a_retrace_brings_the_vehicle_back_to_where_it_stood():
    """Noise off: FORWARD 1.5 north, TURN 90 (to face +x), FORWARD 1.0 east,
    a look round (TURN 35, TURN -35).  Undoing 1.5 ft of it: BACK 1.0 to the
    corner, TURN -90, BACK 0.5: at (0, 1.0) facing north, exactly; and the
    trail left is the first move's first foot."""
    prof = dataclasses.replace(DEFAULT, reverse=True)
    veh = Vehicle(np.zeros((0, 4)), (-10.0, 10.0, -10.0, 10.0), State(0.0, 0.0, 0.0), prof)
    trail = []
    for c in (Forward(1.5), Turn(90.0), Forward(1.0), Turn(35.0), Turn(-35.0)):
        assert veh.execute([c])
        push_trail(trail, c)
    assert (round(veh.true.x, 9), round(veh.true.z, 9)) == (1.0, 1.5)
    back = retrace(trail, 1.5)
    assert back == [Back(1.0), Turn(-90.0), Back(0.5)]
    assert veh.execute(back)
    for c in back:
        push_trail(trail, c)
    assert math.isclose(veh.true.x, 0.0, abs_tol=1e-9)
    assert math.isclose(veh.true.z, 1.0, abs_tol=1e-9)
    assert math.isclose(veh.true.heading_deg, 0.0, abs_tol=1e-9)
    assert veh.collisions == 0
    assert trail == [Forward(1.0)]
    assert RETRACE_FT == 1.5


def test_backing_is_checked_and_set_by_rig_drive():
    import argparse

    from planner.loop import _check_config
    from rig.drive import add_loop_options, loop_config
    with pytest.raises(ValueError, match="unknown backing 'sideways'"):
        _check_config(DriveConfig(goal=(0.0, 5.0), backing="sideways"))
    ap = argparse.ArgumentParser()
    add_loop_options(ap)
    for argv, backing, reverse in (([], DriveConfig.backing, False),
                                   (["--backing", "trail"], "trail", False),
                                   (["--backing", "map", "--reverse", "on"], "map", True)):
        cfg = loop_config(ap.parse_args(argv), (0.0, 5.0), ap.error)
        assert (cfg.backing, cfg.profile.reverse) == (backing, reverse), argv


def test_room_877_is_reached_backing_along_its_own_way():
    """bench/drive.py's room 877 under its own odometry noise: at its 26th look the
    vehicle stands 1.4 ft from the goal where its map allows no pivot and no forward
    move leads to one.  Under the defaults before 2026-12-07 12:15 (``backing="map"``
    and a vehicle that does not reverse) it gives up there after 24 looks more
    ("cannot turn", docs/planner.md).  Under ``backing="trail"`` (the default since)
    it undoes its last 1.5 ft: ``BACK 0.187`` (the last move), the turns since the move
    before undone in one (-46.6 deg), ``BACK 1.313`` (of that move's 1.488 ft); from
    there it comes round another way and reaches the goal by the truth in 33 looks,
    with no collision.  The two drives are the same until the retrace: the option
    acts only where the vehicle would otherwise stand still."""
    from rigtools import DRIVE_BEFORE_2026_12_07_1215, assert_reached_by_the_truth, bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(877)
    # (the profile does not reverse: backing="trail" lets the vehicle back, to retrace only)
    assert not DEFAULT.reverse and DriveConfig.backing == "trail"
    trail = run(room, start, DriveConfig(goal=goal), noise=OdometryNoise(seed=877),
                keep_maps=False)
    assert_reached_by_the_truth(trail, goal)
    assert trail.looks == 33 and trail.retraces == 1
    at = [i for i, c in enumerate(trail.cycles) if "back along its own way" in c.note]
    assert at == [25]
    assert trail.cycles[25].command == "BACK 0.187; TURN -46.629; BACK 1.313"
    before = run(room, start, DriveConfig(goal=goal, **DRIVE_BEFORE_2026_12_07_1215),
                 noise=OdometryNoise(seed=877), keep_maps=False)
    assert not before.reached and before.looks == 49 and before.retraces is None
    assert "cannot turn" in before.reason
    assert [c.true for c in trail.cycles[:25]] == [c.true for c in before.cycles[:25]]


def test_the_result_says_how_often_the_vehicle_retraced():
    """``--json`` carries the retraces under ``backing="trail"`` and leaves them out under
    "map" (nothing to count)."""
    from planner.tiny import GOAL, tiny_room
    for backing, want in (("trail", {"retraces": 0}), ("map", {})):
        res = run(tiny_room(), State(0.0, 0.0, 0.0),
                  DriveConfig(goal=GOAL, eyes="truth", max_looks=1, backing=backing))
        got = res.as_json()
        assert {k: got[k] for k in ("retraces",) if k in got} == want, backing


def test_room_661_does_not_retrace_out_of_the_goal_s_disc():
    """bench/drive.py's room 661 under its own odometry noise: at its 20th look the
    estimate stands 0.65 ft from the goal, inside its 0.75 ft disc, where the vehicle
    cannot turn.  Standing still there ends the run at the goal (``finish="inner"``: a
    cycle in the disc that brings it no nearer); a retrace from there backed it out of the
    disc, and it never came back (53 looks).  So no retrace is taken inside the disc: the
    drive is the same as under ``backing="map"``, and reached by the truth."""
    from rigtools import DRIVE_BEFORE_2026_12_07_1215, assert_reached_by_the_truth, bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(661)
    trail = run(room, start, DriveConfig(goal=goal), noise=OdometryNoise(seed=661),
                keep_maps=False)
    assert_reached_by_the_truth(trail, goal)
    assert trail.retraces == 0
    assert any("cannot turn" in c.note for c in trail.cycles)
    before = run(room, start, DriveConfig(goal=goal, **DRIVE_BEFORE_2026_12_07_1215),
                 noise=OdometryNoise(seed=661), keep_maps=False)
    assert [c.true for c in trail.cycles] == [c.true for c in before.cycles]
