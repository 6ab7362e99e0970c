"""The loop's steps by name (planner.loop: ``_check_config``, ``Drive``): every
configuration value the loop does not know refused before the room is read, and
the execute step's bookkeeping against the exact geometry of a straight move."""

import math

import numpy as np
import pytest

from planner.loop import Drive, DriveConfig, _check_config
from planner.evidence import Perception
from planner.tiny import GOAL, tiny_room
from vehicle.commands import Forward, Turn
from vehicle.sim import State


@pytest.mark.parametrize("field", [
    "match", "pose", "eyes", "pivot", "look_around", "progress", "uncertain", "track_free",
    "goal_region", "floor_eyes", "blank_carve", "blank_limit", "blank_sides", "sight_lines",
    "occupied", "hit_at", "feature_pose", "approach", "head", "refute_hits", "learn_floor",
    "turn_room"])
def test_an_unknown_value_is_refused_by_name_before_the_room_is_read(field):
    from planner.loop import run
    cfg = DriveConfig(goal=GOAL, **{field: "nonsense"})
    with pytest.raises(ValueError, match=r"'nonsense'; one of "):
        _check_config(cfg)
    # no room at all: the check comes before anything reads it
    with pytest.raises(ValueError, match="nonsense"):
        run(None, State(0.0, 0.0, 0.0), cfg)


@pytest.mark.parametrize("kw, words", [
    (dict(blank_px=-1), "blank_px must be 0 or more"),
    (dict(expire_uncertain=-2), "expire_uncertain must be a whole number"),
    (dict(expire_uncertain=1.5), "expire_uncertain must be a whole number"),
    (dict(expire_uncertain=True), "expire_uncertain must be a whole number"),
    (dict(head="assist", pose="fused"), "head 'assist' with pose 'fused'"),
    (dict(head="pan-tilt", pose="fused"), "head 'pan-tilt' with pose 'fused'"),
    # 2.0 ft back and the turn's 0.64 ft circle there leave the 2.5 ft clear spot
    (dict(learn_floor="step-back", learn_back_ft=2.0), r"\(2\.64 ft\) must stay inside"),
    (dict(learn_floor="step-back", learn_back_ft=0.0), "must stay inside"),
])
def test_values_out_of_range_and_the_head_with_the_walk_are_refused(kw, words):
    with pytest.raises(ValueError, match=words):
        _check_config(DriveConfig(goal=GOAL, **kw))


def test_the_defaults_and_the_named_options_pass_the_check():
    for kw in ({}, dict(head="pan-tilt"), dict(head="assist"), dict(pose="fused"),
               dict(blank_px=None, expire_uncertain=3, refute_hits="through",
                    occupied="looks")):
        assert _check_config(DriveConfig(goal=GOAL, **kw)) is None


def test_act_moves_the_vehicle_and_keeps_the_estimate_on_the_odometry():
    # no odometry noise: the dead-reckoned pose is the true one, exactly
    room = tiny_room()
    start = State(0.0, 0.0, 30.0)
    drive = Drive(room, start, DriveConfig(goal=GOAL), None, False, Perception)
    drive.sweep = 3                       # looks turned in place before this move
    ok, moved = drive.act([Forward(1.5)], drive.current())
    assert ok and moved == pytest.approx(1.5)
    end = drive.veh.true
    assert (end.x, end.z) == pytest.approx((1.5 * math.sin(math.radians(30.0)),
                                            1.5 * math.cos(math.radians(30.0))))
    # the estimate's track is the dead reckoning's, the same poses (to rounding: the
    # dead reckoning moves along the mean heading)
    assert drive.est_track[0] == start and drive.est_track[-1] == drive.veh.dead
    assert (drive.veh.dead.x, drive.veh.dead.z) == pytest.approx((end.x, end.z), abs=1e-12)
    assert drive.sweep == 0               # it moved: the sweep starts again
    assert not np.any(drive.dead_cov)     # no noise model: no covariance grows
    drive.sweep = 2
    ok, moved = drive.act([Turn(40.0)], drive.current())
    assert ok and moved == 0.0 and drive.sweep == 2   # a pivot in place is no move
    assert drive.veh.true.heading_deg == pytest.approx(70.0)


def test_progress_under_moved_counts_looks_without_motion():
    drive = Drive(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL), None, False,
                  Perception)
    for n in (1, 2):
        drive.count_progress(0.0, None, None)
        assert drive.stuck == n
    drive.count_progress(0.06, None, None)      # more than 0.05 ft: progress
    assert drive.stuck == 0


@pytest.mark.parametrize("reverse", [False, True])
def test_the_step_back_stands_the_vehicle_behind_its_start_and_learns_the_floor(reverse):
    """``learn_floor="step-back"`` with the noise off: before the first look
    the vehicle stands exactly 1.25 ft behind its start, heading as it was
    (a forward-only vehicle by TURN 180, FORWARD 1.25, TURN -180; one that
    reverses and backs over the map, ``backing="map"``, by BACK 1.25), and that one
    look learns the tiny room's floor
    grey (6, its floor quad's) from the clear spot's floor; without the step
    the look shows none of the clear spot and learns nothing."""
    from dataclasses import replace
    from planner.loop import run
    from vehicle.profile import DEFAULT
    prof = replace(DEFAULT, reverse=reverse)
    learned = {}
    for how in ("off", "step-back"):
        res = run(tiny_room(), State(0.0, 0.0, 0.0),
                  DriveConfig(goal=GOAL, floor_eyes="bound", learn_floor=how, max_looks=1,
                              profile=prof, backing="map"))
        learned[how] = res.floor
        if how == "step-back":
            look_pose = res.cycles[0].true
            assert (look_pose.x, look_pose.z) == pytest.approx((0.0, -1.25), abs=1e-9)
            assert look_pose.heading_deg == pytest.approx(0.0, abs=1e-9)
            assert res.collisions == 0
    assert learned["off"]["floor_greys"] == [] and learned["off"]["floor_samples"] == 0
    assert learned["step-back"]["floor_greys"] == [6]
    assert learned["step-back"]["floor_samples"] >= 200


def test_the_step_back_is_in_the_commands_of_a_forward_only_vehicle():
    d = Drive(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, floor_eyes="bound", learn_floor="step-back"), None, False,
              Perception)
    cmds, ok = d.step_back()
    assert ok and cmds == "TURN 180; FORWARD 1.25; TURN -180"
    assert (d.veh.true.x, d.veh.true.z) == pytest.approx((0.0, -1.25))
    assert [(s.x, s.z) for s in d.est_track][-1] == pytest.approx((0.0, -1.25))
    assert d.veh.travelled_ft == pytest.approx(1.25)


def test_rig_drive_passes_learn_floor_and_steps_back_only_where_a_look_reads_the_floor(
        tmp_path, monkeypatch):
    from planner.loop import steps_back
    from rigtools import drive_config
    cfg = drive_config(monkeypatch, tmp_path)
    assert cfg.learn_floor == "step-back" and steps_back(cfg)       # since 2026-12-05
    assert not steps_back(drive_config(monkeypatch, tmp_path, "--learn-floor", "off"))
    # nothing would learn from it: without the floor eyes, or with the depth eyes under
    # the bounding floor eyes (they read no picture); the depth eyes' "carve" reads one
    assert not steps_back(drive_config(monkeypatch, tmp_path, "--floor-eyes", "off"))
    assert not steps_back(drive_config(monkeypatch, tmp_path, "--eyes", "depth"))
    assert steps_back(drive_config(monkeypatch, tmp_path, "--eyes", "depth",
                                   "--floor-eyes", "carve"))
    assert steps_back(drive_config(monkeypatch, tmp_path, "--eyes", "truth"))


def test_rig_drive_refuses_a_start_too_near_something_for_the_step_back(tmp_path, monkeypatch):
    """The bundled lab's front wall is at z -5: a start at (0, -3.2) is 1.8 ft from it,
    enough for the vehicle (0.79 ft) but not for the step back (1.25 ft and the turn's
    0.64 ft circle there): one clear error naming the start and the way round it."""
    from rig.main import main
    from rigtools import drive_config
    with pytest.raises(SystemExit) as exc:
        main(["drive", "--out", str(tmp_path), "--start", "0,-3.2"])
    assert str(exc.value.code) == (
        "rig drive: the start (0, -3.2) ft is 1.80 ft from an obstacle or wall; the step back "
        "that learns the floor's grey needs 1.89 ft all round (--learn-floor off: no step back)")
    assert not list(tmp_path.iterdir())
    cfg = drive_config(monkeypatch, tmp_path, "--start", "0,-3.2", "--learn-floor", "off")
    assert cfg.learn_floor == "off"


def test_max_stuck_gives_up_after_that_many_looks_without_a_move(monkeypatch, tmp_path):
    """A goal in the tiny room's box (x 1.2..2.6, z 3.5..4.5) is never
    reachable and the vehicle never moves after its first look: the drive gives up after exactly
    ``max_stuck`` looks, saying why; ``rig drive --max-stuck`` sets it, and a
    count below 1 is refused.  (Each look's hits in the octree, occupied="looks": the fused
    features draw the box's seen face thinner, and the goal's disc then holds unknown
    floor behind the box, which the planner may aim at; turn_room="off": with "forward"
    the vehicle moves on to where it can turn; and fine_map="off": on half cells the
    goal's disc, which reaches 0.25 ft past the box's near face, has a way to it; and
    backing="map": under "trail" the vehicle backs along its step back's way.)"""
    from planner.loop import run
    from world.odometry import OdometryNoise
    from rigtools import drive_config
    assert DriveConfig.max_stuck == 24                  # since 2026-12-07 08:30 (16 before)
    assert drive_config(monkeypatch, tmp_path, "--max-stuck", "3").max_stuck == 3
    for n in (2, 3):
        res = run(tiny_room(), State(0.0, 0.0, 0.0),
                  DriveConfig(goal=(1.9, 4.0), eyes="truth", max_stuck=n, occupied="looks",
                              turn_room="off", fine_map="off", backing="map"),
                  noise=OdometryNoise(seed=1))
        assert len(res.cycles) == n
        assert res.reason.startswith(f"stopped after {n} looks without progress: goal not "
                                     "reachable")
        assert not res.reached and res.collisions == 0
    for name in ("max_stuck", "max_looks"):
        for bad in (0, -1, 2.5, True):
            with pytest.raises(ValueError, match=name):
                _check_config(DriveConfig(goal=GOAL, **{name: bad}))


def test_room_220_is_reached_in_its_65th_look_under_90_looks_and_not_under_60(
        monkeypatch, tmp_path):
    """``max_looks`` 90 (the default since 2026-12-07 06:30; 60 before): bench/drive.py's
    room 220 under its own odometry noise uses up 60 looks without reaching its goal and
    reaches it in 65 under 90, with no collision, its true pose inside the goal's disc
    (the world's exact geometry judges it).  The first 60 looks are the same drive: the
    count only bounds the loop.  ``rig drive --max-looks`` sets it."""
    from rigtools import assert_reached_by_the_truth, bench_drives, drive_config
    assert DriveConfig.max_looks == 90
    assert drive_config(monkeypatch, tmp_path, "--max-looks", "60").max_looks == 60
    monkeypatch.undo()                                  # (drive_config stubs the loop)
    goal, res = bench_drives(220, "max_looks", (60, 90))
    assert not res[60].reached and res[60].reason == "stopped: 60 looks used up"
    assert res[60].collisions == 0
    assert_reached_by_the_truth(res[90], goal)
    assert res[90].looks == 65
    assert [c.true for c in res[90].cycles[:60]] == [c.true for c in res[60].cycles]


def test_room_144_is_reached_under_24_looks_without_progress_and_not_under_16():
    """``max_stuck`` 24 (the default since 2026-12-07 08:30; 16 before): bench/drive.py's
    room 144 under its own odometry noise makes no progress for 16 looks in a row and gives
    up at its 31st look under 16; under 24 it moves on and the goal is reached by the
    truth in 45, with no collision.  The two runs are the same drive until the first gives
    up: the count only decides when to stop.  ``rig drive --max-stuck`` sets it (the test
    above).  (Room 337, traced first, reaches its goal in 34 looks under both counts on
    the machine of 2026-12-08, with the code its test had passed on (2f58fe6): most
    likely that machine's library versions turn the drive another way, not traced; 144
    is another of the five rooms the 24 looks won.)"""
    from rigtools import assert_reached_by_the_truth, bench_drives
    goal, res = bench_drives(144, "max_stuck", (16, 24))
    assert not res[16].reached and res[16].looks == 31
    assert res[16].reason.startswith("stopped after 16 looks without progress")
    assert res[16].collisions == 0
    assert_reached_by_the_truth(res[24], goal)
    assert res[24].looks == 45
    n = len(res[16].cycles)
    assert [c.true for c in res[24].cycles[:n]] == [c.true for c in res[16].cycles]
