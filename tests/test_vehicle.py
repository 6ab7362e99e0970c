"""The motion-command language, the simulated vehicle (noise off: exact; noise
on: the dead-reckoned pose drifts, the true one follows the commands), and the
collision check of the true footprint against the true room."""

import math

import pytest

from world.collide import footprint_corners, footprint_hits_boxes
from vehicle.commands import Arc, CommandError, Forward, Stop, Turn, format_commands, parse
from vehicle.profile import DEFAULT, VehicleProfile
from vehicle.sim import State, Vehicle

OPEN = (-10.0, 10.0, -10.0, 10.0)


def test_parse_all_verbs_and_round_trip():
    text = "forward 2.5; T -30\nARC 1.5 45   # a rounded corner\nF .5;STOP"
    cmds = parse(text)
    assert cmds == [Forward(2.5), Turn(-30.0), Arc(1.5, 45.0), Forward(0.5), Stop()]
    assert format_commands(cmds) == "FORWARD 2.5; TURN -30; ARC 1.5 45; FORWARD 0.5; STOP"
    assert parse(format_commands(cmds)) == cmds
    assert parse("") == [] and parse("  ;; # nothing\n") == []


@pytest.mark.parametrize("text, message", [
    ("FORWRD 2", r"command 1 'FORWRD 2': unknown command 'FORWRD' \(expected FORWARD, BACK, TURN"),
    ("TURN 10; FORWARD", r"command 2 'FORWARD': FORWARD takes 1 number, got 0"),
    ("FORWARD 1 2", r"FORWARD takes 1 number, got 2"),
    ("ARC 1", r"ARC takes 2 numbers, got 1"),
    ("FORWARD two", r"'two' is not a number"),
    ("FORWARD 1e400", r"is not a number"),
    ("FORWARD nan", r"'nan' is not a number"),
    ("FORWARD -1", r"must not be negative \(the vehicle drives forward only\)"),
    ("TURN 181", r"TURN angle must be within -180..180"),
    ("ARC 0 90", r"ARC radius must be positive"),
    ("STOP; TURN 5", r"command 2 'TURN 5': nothing may follow STOP"),
])
def test_malformed_strings_refused_clearly(text, message):
    with pytest.raises(CommandError, match=message):
        parse(text)


def test_noise_off_executes_exactly():
    v = Vehicle([], OPEN, State(1.0, 2.0, 0.0))
    assert v.execute("FORWARD 3; TURN 90; FORWARD 2; TURN 90; FORWARD 3; TURN 90; FORWARD 2; "
                     "TURN 90")
    assert (v.true.x, v.true.z, v.true.heading_deg) == pytest.approx((1.0, 2.0, 0.0), abs=1e-9)
    assert (v.dead.x, v.dead.z, v.dead.heading_deg) == pytest.approx(
        (v.true.x, v.true.z, v.true.heading_deg), abs=1e-9)
    assert v.travelled_ft == pytest.approx(10.0)
    # a quarter circle of radius 2 to the right from heading 0 ends 2 right, 2 ahead, facing +X
    v = Vehicle([], OPEN, State(0.0, 0.0, 0.0))
    v.execute([Arc(2.0, 90.0)])
    assert (v.true.x, v.true.z, v.true.heading_deg) == pytest.approx((2.0, 2.0, 90.0), abs=1e-9)
    assert v.travelled_ft == pytest.approx(math.pi)
    assert (v.dead.x, v.dead.z) == pytest.approx((2.0, 2.0), abs=1e-9)


class FixedNoise:
    """Wheels that report 10 % too far and 2 deg too much per turn command."""
    def measure(self, d, t):
        return d * 1.1, t + (2.0 if t else 0.0)


def test_noise_moves_the_dead_reckoned_pose_not_the_true_one():
    v = Vehicle([], OPEN, State(0.0, 0.0, 0.0), noise=FixedNoise(), sweep_deg=90.0)
    v.execute("FORWARD 2; TURN 90")
    assert (v.true.x, v.true.z, v.true.heading_deg) == pytest.approx((0.0, 2.0, 90.0))
    assert v.dead.z == pytest.approx(2.2)
    assert v.dead.heading_deg == pytest.approx(92.0)


def test_footprint_corners():
    c = footprint_corners(0.0, 0.0, 90.0, (1.0, 2.0))         # facing +X: long along X
    assert sorted(map(tuple, c.round(9).tolist())) == [(-1.0, -0.5), (-1.0, 0.5), (1.0, -0.5),
                                                        (1.0, 0.5)]


def test_collision_check_against_obstacles_and_walls():
    box = [(2.0, 3.0, 2.0, 3.0)]
    fp = (1.0, 1.0)
    assert not footprint_hits_boxes(box, OPEN, 0.0, 0.0, 0.0, fp, touching_hits=False)
    assert footprint_hits_boxes(box, OPEN, 1.6, 1.6, 0.0, fp, touching_hits=False)
    assert not footprint_hits_boxes(box, OPEN, 1.45, 1.45, 0.0, fp, touching_hits=False)
    # rotated 45 deg the corner reaches 0.707 ft: now it hits
    assert footprint_hits_boxes(box, OPEN, 1.4, 2.5, 45.0, fp, touching_hits=False)
    assert not footprint_hits_boxes(box, OPEN, 1.25, 2.5, 45.0, fp, touching_hits=False)
    assert footprint_hits_boxes([], (0.0, 5.0, 0.0, 5.0), 0.3, 2.0, 0.0, fp, touching_hits=False)      # past the wall
    assert not footprint_hits_boxes([], (0.0, 5.0, 0.0, 5.0), 0.5, 2.0, 0.0, fp, touching_hits=False)  # touching is fine


def test_a_path_forced_through_a_wall_collides_and_stops():
    wall = [(-5.0, 5.0, 4.9, 5.1)]
    v = Vehicle(wall, OPEN, State(0.0, 0.0, 0.0), profile=DEFAULT)
    assert v.execute("FORWARD 10; TURN 90") is False
    assert v.collisions == 1
    # stopped with its nose short of the wall, the TURN never executed
    assert v.true.z + DEFAULT.length_ft / 2 <= 4.9 + 1e-9
    assert v.true.z + DEFAULT.length_ft / 2 > 4.9 - v.sweep_ft
    assert v.true.heading_deg == 0.0


def test_profile_default_and_validation():
    assert DEFAULT.footprint == (0.8, 1.0)
    assert DEFAULT.radius_ft == pytest.approx(math.hypot(0.8, 1.0) / 2)
    assert DEFAULT.planning_radius_ft == pytest.approx(DEFAULT.radius_ft + 0.15)
    with pytest.raises(ValueError, match="width_ft must be positive"):
        VehicleProfile(width_ft=0)


def test_back_moves_straight_backward_keeping_the_heading():
    """BACK d: the true pose d ft behind along the heading, the heading kept;
    the wheels report the distance (10 % too far here) backward too; a
    profile without reverse refuses it; the string round-trips."""
    from vehicle.commands import Back
    assert parse("B 1.5; back .5") == [Back(1.5), Back(0.5)]
    assert format_commands([Back(1.5)]) == "BACK 1.5"
    with pytest.raises(CommandError, match="BACK distance must not be negative"):
        parse("BACK -1")
    import dataclasses
    rev = dataclasses.replace(DEFAULT, reverse=True)
    v = Vehicle([], OPEN, State(0.0, 0.0, 90.0), rev, noise=FixedNoise())   # facing +X
    assert v.execute("BACK 2")
    assert (v.true.x, v.true.z, v.true.heading_deg) == pytest.approx((-2.0, 0.0, 90.0))
    assert (v.dead.x, v.dead.z) == pytest.approx((-2.2, 0.0))
    assert v.travelled_ft == pytest.approx(2.0)
    # backing into a wall behind collides like driving into one
    w = Vehicle([], (-1.0, 5.0, -5.0, 5.0), State(0.0, 0.0, 90.0), rev)
    assert not w.execute("BACK 1")
    assert w.collisions == 1 and w.true.x > -1.0 + 0.5 - 1e-9
    fwd_only = Vehicle([], OPEN, State(0.0, 0.0, 0.0))              # the default: forward only
    assert DEFAULT.reverse is False
    with pytest.raises(ValueError, match="does not allow reverse"):
        fwd_only.execute("BACK 1")
