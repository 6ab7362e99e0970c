"""The pan-tilt head (``DriveConfig.head="pan-tilt"``, ``rig drive --head pan-tilt``,
not 1985, off by default): the PAN and TILT commands, the simulated vehicle's head,
what a tilted look can show, where the head looks (angles derived by hand on
hand-made maps), a panned look against a turned body, and the loop in the tiny
room."""

import math

import numpy as np
import pytest

from planner.floormap import FloorMap
from planner.loop import DriveConfig, run
from planner.motion import HALF_VFOV_DEG, far_floor_ft, head_aim, head_blank_ft, head_commands, head_look, \
    near_visible_ft, safe_prefix, shortcut_first_leg, unseen_in_circle
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN
from planner.search import clearance_map
from planner.tiny import GOAL, tiny_room
from vehicle.commands import CommandError, Forward, Pan, Tilt, Turn, format_commands, parse
from vehicle.profile import DEFAULT, PAN_TILT, VehicleProfile
from vehicle.sim import State, Vehicle, camera_pose
from world.odometry import OdometryNoise


def free_map():
    """16 x 16 ft, 0.25 ft cells, all seen free; the origin at a cell corner."""
    return FloorMap(np.full((64, 64), FREE, np.uint8), -8.0, -8.0, 0.25)


class Cfg:                    # what the head's functions read of a DriveConfig
    lowest_obstacle_ft = 0.8


# --- the command language -------------------------------------------------------------

def test_pan_and_tilt_parse_format_and_round_trip():
    cmds = parse("pan 40; TILT -30.5\nP -12; TI 0; FORWARD 1")
    assert cmds == [Pan(40.0), Tilt(-30.5), Pan(-12.0), Tilt(0.0), Forward(1.0)]
    text = format_commands(cmds)
    assert text == "PAN 40; TILT -30.5; PAN -12; TILT 0; FORWARD 1"
    assert parse(text) == cmds


@pytest.mark.parametrize("text, words", [
    ("PAN", "PAN takes 1 number, got 0"),
    ("TILT 1 2", "TILT takes 1 number, got 2"),
    ("PAN left", "'left' is not a number"),
    ("PAN 200", "PAN angle must be within -180..180 deg"),
    ("TILT -181", "TILT angle must be within -180..180 deg"),
    ("LOOK 3", "expected FORWARD, BACK, TURN, ARC, PAN, TILT or STOP"),
])
def test_malformed_head_commands_are_refused_with_a_clear_message(text, words):
    with pytest.raises(CommandError, match=words.replace("(", r"\(").replace(")", r"\)")):
        parse(text)


# --- the simulated vehicle ------------------------------------------------------------

def vehicle(profile=PAN_TILT, noise=None):
    return Vehicle(np.zeros((0, 4)), (-10.0, 10.0, -10.0, 10.0), State(0.0, 0.0, 10.0),
                   profile, noise)


def test_pan_and_tilt_move_the_head_only_and_exactly():
    v = vehicle(noise=OdometryNoise(seed=3))
    assert v.execute("PAN 40; TILT -30")
    assert (v.pan_deg, v.tilt_deg) == (40.0, -30.0)
    assert v.true == State(0.0, 0.0, 10.0) and v.dead == State(0.0, 0.0, 10.0)
    assert v.travelled_ft == 0.0 and v.collisions == 0
    assert len(v.true_track) == 1 and len(v.dead_track) == 1     # no motion reported
    assert v.execute("PAN 0")                                    # absolute, not relative
    assert (v.pan_deg, v.tilt_deg) == (0.0, -30.0)


def test_head_commands_leave_the_body_and_its_dead_reckoning_as_without_them():
    """The odometry draws its noise per reported motion: the head reports none, so the
    same noise seed gives the same dead-reckoned track with the head commands between."""
    a, b = vehicle(noise=OdometryNoise(seed=7)), vehicle(noise=OdometryNoise(seed=7))
    a.execute("FORWARD 1.2; PAN 30; TILT -20; TURN 15; PAN -45; FORWARD 0.8")
    b.execute("FORWARD 1.2; TURN 15; FORWARD 0.8")
    assert a.true_track == b.true_track and a.dead_track == b.dead_track
    assert a.dead != a.true                                      # the noise was on
    assert (a.pan_deg, a.tilt_deg) == (-45.0, -20.0)


@pytest.mark.parametrize("text, words", [
    ("PAN 95", "PAN 95: outside the head's limits -90..90 deg (VehicleProfile.pan_limits_deg)"),
    ("PAN -90.5", "outside the head's limits -90..90 deg"),
    ("TILT 5", "TILT 5: outside the head's limits -55..0 deg (VehicleProfile.tilt_limits_deg)"),
    ("TILT -60", "outside the head's limits -55..0 deg"),
])
def test_head_angles_outside_the_profiles_limits_are_refused_before_anything_moves(text, words):
    v = vehicle()
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        v.execute("FORWARD 1; " + text)
    assert v.true == State(0.0, 0.0, 10.0) and (v.pan_deg, v.tilt_deg) == (0.0, 0.0)


def test_a_profile_without_a_head_refuses_pan_and_tilt():
    v = vehicle(DEFAULT)
    for text in ("PAN 0", "TILT 0"):
        with pytest.raises(ValueError, match="has no head"):
            v.execute(text)
    with pytest.raises(ValueError, match="must hold 0"):
        VehicleProfile(head=True, tilt_limits_deg=(-55.0, -10.0))


# --- what a tilted look shows ---------------------------------------------------------

def test_near_visible_for_a_tilt_derived_by_hand():
    # the picture's lower edge looks the pitch plus half the 120-line view (atan(60/180) =
    # 18.435 deg) down; an 0.8 ft box top, 3 - 0.8 = 2.2 ft below the camera, shows from
    # 2.2 / tan(edge)
    assert HALF_VFOV_DEG == pytest.approx(18.4349, abs=1e-4)
    assert near_visible_ft(DEFAULT, 0.8) == pytest.approx(2.2 / math.tan(math.radians(43.4349)),
                                                          abs=1e-5)
    assert near_visible_ft(DEFAULT, 0.8) == pytest.approx(2.3236, abs=1e-4)
    # tilted 25 deg more (pitch -50): the edge 68.435 deg down, 2.2 / 2.5302 = 0.8695 ft
    assert near_visible_ft(PAN_TILT, 0.8, -25.0) == pytest.approx(0.8695, abs=1e-4)
    # tilted 55 deg (pitch -80): the edge 98.4 deg down, past the vertical: nothing too near
    assert near_visible_ft(PAN_TILT, 0.8, -55.0) == 0.0
    # the farthest floor: the upper edge 25 - 18.435 = 6.565 deg down, 3 / 0.11509 = 26.07 ft;
    # at pitch -80, 61.565 deg down: 3 / 1.8466 = 1.62 ft
    assert far_floor_ft(DEFAULT) == pytest.approx(26.07, abs=0.01)
    assert far_floor_ft(PAN_TILT, -55.0) == pytest.approx(1.6246, abs=1e-3)


def test_a_look_the_head_turned_assumes_nothing_of_its_blank_columns():
    assert head_blank_ft(8.0, PAN_TILT, 0.0, 0.0) == 8.0         # straight ahead: the fixed rig's
    assert head_blank_ft(30.0, PAN_TILT, 0.0, 0.0) == pytest.approx(26.07, abs=0.01)
    assert head_blank_ft(8.0, PAN_TILT, 20.0, 0.0) is None
    assert head_blank_ft(8.0, PAN_TILT, 0.0, -10.0) is None
    assert head_blank_ft(None, PAN_TILT, 0.0, 0.0) is None
    # bounded by the floor in view (floor_eyes="bound"): panned as straight; tilted,
    # still nothing (a column of a near box's face shows no floor's end: room 237)
    assert head_blank_ft(8.0, PAN_TILT, 20.0, 0.0, bounded=True) == 8.0
    assert head_blank_ft(8.0, PAN_TILT, 0.0, -55.0, bounded=True) is None
    assert head_blank_ft(8.0, PAN_TILT, 24.0, -29.0, bounded=True) is None
    assert head_blank_ft(None, PAN_TILT, 20.0, 0.0, bounded=True) is None


def test_the_heads_aim_at_a_hand_made_cell():
    # the cell (1, 1) from (0, 0) heading 0: bearing 45 deg; 1.414 ft away, less the margin
    # 0.25: 1.1642 ft; the box top 2.2 ft down there: atan(2.2 / 1.1642) = 62.114 deg, so
    # the pitch 18.435 - 62.114 = -43.679 deg, the tilt -43.679 + 25 = -18.68 deg
    pan, tilt = head_aim(0.0, 0.0, 0.0, (1.0, 1.0), PAN_TILT, 0.8, 0.25)
    assert pan == 45.0
    assert tilt == -18.68
    assert near_visible_ft(PAN_TILT, 0.8, tilt) == pytest.approx(math.sqrt(2) - 0.25, abs=0.01)
    # from (2, -1) heading 90 (facing +X): the cell (1, 1) bears -26.57 deg, so pan
    # -26.57 - 90 = -116.57: beyond the head's -90
    assert head_aim(2.0, -1.0, 90.0, (1.0, 1.0), PAN_TILT, 0.8, 0.25)[0] == -90.0
    # far away: no tilt at all (the mount already shows it), never above the mount's pitch
    assert head_aim(0.0, 0.0, 0.0, (0.5, 5.0), PAN_TILT, 0.8, 0.25) == \
        (round(math.degrees(math.atan2(0.5, 5.0)), 2), 0.0)
    # nearer than the margin: the head's lowest tilt
    assert head_aim(0.0, 0.0, 0.0, (0.1, 0.1), PAN_TILT, 0.8, 0.25) == (45.0, -55.0)


def test_a_look_with_the_head_panned_is_the_look_of_the_body_turned_as_much():
    from world.render import render_look
    room = tiny_room()
    a = render_look(room, camera_pose(State(0.5, 1.0, 10.0), 30.0, -20.0, PAN_TILT), seed=5,
                    supersample=1)
    b = render_look(room, camera_pose(State(0.5, 1.0, 40.0), 0.0, -20.0, PAN_TILT), seed=5,
                    supersample=1)
    c = render_look(room, camera_pose(State(0.5, 1.0, 40.0), 0.0, 0.0, PAN_TILT), seed=5,
                    supersample=1)
    assert np.array_equal(a.left_bi, b.left_bi) and np.array_equal(a.right_bi, b.right_bi)
    assert np.array_equal(a.range_left, b.range_left)
    assert not np.array_equal(a.left_bi, c.left_bi)          # the tilt shows something else
    # the head at 0/0 is exactly the fixed rig's pose
    p = camera_pose(State(0.5, 1.0, 180.0), 0.0, 0.0, DEFAULT)
    assert (p.heading_deg, p.pitch_deg) == (180.0, -25.0)


# --- where the head looks -------------------------------------------------------------

def test_the_nearest_cell_of_the_pivot_circle_not_seen_free():
    fm = free_map()
    assert unseen_in_circle(fm, 0.1, 0.1, 0.64) is None
    fm.cells[fm.index(-0.6, 0.1)] = UNKNOWN      # square -0.75..-0.5: 0.6 ft from (0.1, 0.1)
    fm.cells[fm.index(0.1, -0.9)] = UNCERTAIN    # square z -1..-0.75: 0.85 ft: outside
    fm.cells[fm.index(0.6, 0.1)] = OCCUPIED      # occupied: no look clears it
    assert unseen_in_circle(fm, 0.1, 0.1, 0.64) == (-0.625, 0.125)
    fm.cells[fm.index(0.1, 0.7)] = UNCERTAIN     # square z 0.5..0.75: 0.4 ft, centre 0.525
    assert unseen_in_circle(fm, 0.1, 0.1, 0.64) == (0.125, 0.625)


def test_the_head_looks_at_the_blind_cell_beside_the_way_then_at_the_pivot_circle():
    fm = free_map()
    est = State(0.0, 0.0, 0.0)
    path = [(0.0, 0.0), (0.0, 6.0)]
    fm.cells[fm.index(0.6, 1.1)] = UNKNOWN       # on the band (0.55 ft each side), 1.24 ft away
    fm.cells[fm.index(-0.6, -0.1)] = UNKNOWN     # in the pivot circle (0.64 ft)
    safe = clearance_map(fm, PAN_TILT.planning_radius_ft, "free", uncertain="blocked")
    aimed = {}
    got = head_look(fm, safe, est, path, (0.0, 6.0), [], PAN_TILT, Cfg, 0.0, 0.64, aimed)
    # the band's cell (0.625, 1.125): bearing atan(0.625 / 1.125) = 29.05 deg; 1.287 ft, less
    # 0.25: atan(2.2 / 1.037) = 64.77 deg down, the tilt 18.435 - 64.77 + 25 = -21.33 deg
    assert got[0] == [Pan(29.05), Tilt(-21.33)]
    got = head_look(fm, safe, est, path, (0.0, 6.0), [], PAN_TILT, Cfg, 29.05, 0.64, aimed)
    # aimed at once from here: next, the pivot circle's (-0.625, -0.125): bearing -101.3
    # deg, beyond the head's -90; 0.637 ft, less 0.25: atan(2.2 / 0.387) = 80.0 deg down,
    # the tilt -36.6 deg
    assert got[0] == [Pan(-90.0), Tilt(-36.58)]


def test_a_move_is_driven_with_the_head_ahead_and_followed_by_the_next_aim():
    fm = free_map()
    est = State(0.0, 0.0, 0.0)
    path = [(0.0, 0.0), (0.0, 6.0)]
    fm.cells[fm.index(-0.3, 3.4)] = UNKNOWN      # on the band beyond a 1.5 ft move
    out = head_commands([Forward(1.5)], est, fm, path, PAN_TILT, Cfg, 30.0, -20.0, {})
    # from (0, 1.5): the cell (-0.375, 3.375) bears atan(-0.375 / 1.875) = -11.31 deg, 1.912 ft
    # away, less 0.25: atan(2.2 / 1.662) = 52.93 deg down: the tilt -9.49 deg
    assert out == [Pan(0.0), Tilt(0.0), Forward(1.5), Pan(-11.31), Tilt(-9.49)]
    # a look of the head's own (no body motion) is left as it is
    assert head_commands([Pan(10.0), Tilt(-5.0)], est, fm, path, PAN_TILT, Cfg, 0.0, 0.0,
                         {}) == [Pan(10.0), Tilt(-5.0)]


def test_a_turn_the_head_has_looked_along_is_driven_on_at_once():
    fm = free_map()
    safe = clearance_map(fm, PAN_TILT.planning_radius_ft, "free", uncertain="blocked")
    seen = fm.cells != UNKNOWN
    cmds = [Turn(40.0), Forward(1.0)]
    est = State(0.0, 0.0, 0.0)
    assert safe_prefix(cmds, est, safe, seen, 1.5, None, 0.55, 0.65, 0.64) == [Turn(40.0)]
    assert safe_prefix(cmds, est, safe, seen, 1.5, None, 0.55, 0.65, 0.64,
                       looked_deg=35.0) == cmds
    assert safe_prefix(cmds, est, safe, seen, 1.5, None, 0.55, 0.65, 0.64,
                       looked_deg=0.0) == [Turn(40.0)]


def test_a_first_leg_of_a_tenth_of_a_foot_is_cut_short_by_the_straight_line():
    est = State(0.0, 0.0, 0.0)
    cmds = [Turn(90.0), Forward(0.1), Turn(-90.0), Forward(2.0), Turn(30.0), Forward(1.0)]
    # the second leg ends at (0.1, 2.0) heading 0: straight there, atan(0.1 / 2) = 2.862 deg,
    # sqrt(4.01) = 2.0025 ft, then back to heading 0 and on as before
    assert shortcut_first_leg(cmds, est) == [Turn(2.862), Forward(2.002), Turn(-2.862),
                                             Turn(30.0), Forward(1.0)]
    long = [Turn(90.0), Forward(0.5), Turn(-90.0), Forward(2.0)]
    assert shortcut_first_leg(long, est) == long
    assert shortcut_first_leg([Turn(5.0), Forward(0.1)], est) == [Turn(5.0), Forward(0.1)]


# --- the loop -------------------------------------------------------------------------

def test_the_loop_refuses_an_unknown_head_and_the_fused_estimate_with_a_head():
    with pytest.raises(ValueError, match="unknown head 'swivel'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, head="swivel"))
    with pytest.raises(ValueError, match="pose 'fused'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, head="pan-tilt",
                                                           pose="fused"))


@pytest.mark.parametrize("head", ["pan-tilt", "assist"])
def test_rig_drive_refuses_the_fused_estimate_with_either_head(tmp_path, head):
    from rig.main import main
    with pytest.raises(SystemExit, match=f"--pose fused with --head {head}: .*--head fixed"):
        main(["drive", "--head", head, "--pose", "fused", "--out", str(tmp_path)])


def test_the_loop_with_the_head_reaches_the_tiny_rooms_goal_driving_with_the_head_ahead():
    """Depth eyes (the planner's own share), the vehicle set down facing 60 deg off the
    goal: the head looks before the body turns; no collision; every body motion is made
    with the head straight ahead and every head angle within the limits."""
    from world.odometry import OdometryNoise
    res = run(tiny_room(), State(0.0, 0.0, 60.0),
              DriveConfig(goal=GOAL, eyes="depth", head="pan-tilt"), noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.travelled_ft <= 1.3 * res.optimal_ft
    pan = tilt = 0.0
    aims = 0
    for cyc in res.cycles:
        for c in parse(cyc.command) if cyc.command else []:
            if isinstance(c, Pan):
                pan = c.angle_deg
                assert -90.0 <= pan <= 90.0
                aims += pan != 0.0
            elif isinstance(c, Tilt):
                tilt = c.angle_deg
                assert -55.0 <= tilt <= 0.0
            else:
                assert (pan, tilt) == (0.0, 0.0), cyc.command
    assert aims >= 1                                    # the head was used


def test_the_default_loop_issues_no_head_command():
    from world.odometry import OdometryNoise
    res = run(tiny_room(), State(0.0, 0.0, 60.0), DriveConfig(goal=GOAL, eyes="depth"),
              noise=OdometryNoise(seed=1))
    assert res.reached and res.collisions == 0
    assert not any("PAN" in c.command or "TILT" in c.command for c in res.cycles)


# --- head="assist": the head's looks added to the fixed rig's -----------------------------

def _commands(res):
    return [c.command for c in res.cycles]


def test_assist_without_a_stop_to_look_is_the_fixed_rigs_cycle():
    """Depth eyes, set down facing the goal: the fixed rig never stops or pivots only to
    look, so the assisting head never looks and every command is the fixed rig's."""
    fixed = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="depth"))
    assist = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="depth",
                                                               head="assist"))
    assert fixed.reached and all("FORWARD" in c for c in _commands(fixed))
    assert _commands(assist) == _commands(fixed)
    assert [c.head_looks for c in assist.cycles] == [0] * len(assist.cycles)
    assert assist.looks == fixed.looks


def test_assist_adds_the_heads_look_where_the_fixed_rig_pivots_only_to_look():
    """Set down 60 deg off the goal: the fixed rig's first cycle is a pivot only to look
    (a TURN of about -60 deg, no move: -62.7 since ``look_around="evidence"`` aims it
    where the path lacks evidence, -60 toward the path before).  With the assisting head
    the same cycle takes a second look, the head aimed (head_aim) at the first never-seen
    cell of the way, and the cycle's commands are decided again with it; the looks
    counted are both; no PAN or TILT is commanded (the body always drives with the head
    ahead)."""
    start = State(0.0, 0.0, 60.0)
    fixed = run(tiny_room(), start, DriveConfig(goal=GOAL, eyes="depth"))
    kind, angle = fixed.cycles[0].command.split(" ")
    assert kind == "TURN" and -65.0 < float(angle) < -55.0
    res = run(tiny_room(), start, DriveConfig(goal=GOAL, eyes="depth", head="assist"))
    first = res.cycles[0]
    assert first.head_looks == 1 and "assist: head at the way" in first.note
    # the aim is head_aim's at the cell the note names (to 0.1 ft), from the start
    cell = tuple(float(v) for v in first.note.split("way: (")[1].split(")")[0].split(", "))
    pan, tilt = head_aim(0.0, 0.0, 60.0, cell, PAN_TILT, Cfg.lowest_obstacle_ft, 0.25)
    got_pan = float(first.note.split("pan ")[1].split(" ")[0])
    got_tilt = float(first.note.split("tilt ")[1].rstrip(")"))
    assert abs(got_pan - pan) < 1.5 and abs(got_tilt - tilt) < 1.5   # (the note rounds the cell)
    assert -90.0 < got_pan < -45.0                # toward the goal, which lies 60 deg left
    assert res.looks == len(res.cycles) + sum(c.head_looks for c in res.cycles)
    assert res.reached and res.collisions == 0
    assert not any("PAN" in c or "TILT" in c for c in _commands(res))


def test_assist_times_both_looks_of_a_cycle(monkeypatch):
    """A cycle the head's look is added to scans twice: its scan and work times hold
    both looks (they once held only the second), and the time per look counts both."""
    import time
    import planner.loop as loop
    real = loop.scan_look

    def slow_scan(*args, **kw):                 # each scan takes at least 0.2 s
        time.sleep(0.2)
        return real(*args, **kw)

    monkeypatch.setattr(loop, "scan_look", slow_scan)
    res = run(tiny_room(), State(0.0, 0.0, 60.0), DriveConfig(goal=GOAL, eyes="depth",
                                                              head="assist", max_looks=2))
    first = res.cycles[0]
    assert first.head_looks == 1
    assert first.scan_s >= 0.4 and first.work_s >= first.scan_s
    assert all(c.scan_s >= 0.2 * (1 + c.head_looks) for c in res.cycles)
    total = sum(c.work_s for c in res.cycles)
    assert res.work_ms_per_look == pytest.approx(1e3 * total / res.looks)
    assert res.looks == len(res.cycles) + 1


def test_assist_refuses_the_fused_estimate():
    with pytest.raises(ValueError, match="assist.*pose 'fused'"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, head="assist",
                                                           pose="fused"))


def test_assist_in_room_7_does_not_drive_into_the_wall_its_drift_moved():
    """The traced collision (docs/planner.md, "The head that only adds looks"): room 7,
    the 1985 eyes, the odometry noise of seed 7.  The estimate drifts 1.05 ft toward the
    right-hand wall; a blank column's assumed floor, stopped only by the floor plan's wall
    (placed by the truth), ran that far past the wall the vehicle met, and a pivot at look
    29 hit it.  With the assumption stopped 2 sigma of the estimate short of the plan it
    does not (without that: 1 collision after 17.6 ft).  (``assist_pivot_ft`` off: with
    it the drive stops after 4.5 ft, before the wall, for a pivot its rule refuses; so
    does it with ``floor_eyes="bound"``, after 8 ft: the assumption is unbounded here,
    as when it was traced.)"""
    from rigtools import DRIVE_BEFORE_2026_12_04, DRIVE_BEFORE_2026_12_05, bench_task
    room, start, goal = bench_task(7)
    res = run(room, start, DriveConfig(goal=goal, head="assist", assist_pivot_ft=None,
                                       floor_eyes="off", **{**DRIVE_BEFORE_2026_12_04,
                                          **DRIVE_BEFORE_2026_12_05}),
              noise=OdometryNoise(seed=7), keep_maps=False)
    assert res.collisions == 0 and "hit something" not in res.reason
    assert res.travelled_ft > 15.0          # it went as far as where it used to collide


def test_assist_in_room_45_pivots_only_on_cells_a_look_proved_near_enough():
    """The traced collision (docs/planner.md, "The head that only adds looks"): room 45,
    oracle edges, the odometry noise of seed 45.  The fixed rig's own look from the start
    (heading 49 deg) carved the corner of a blank box 6.3 ft away by the blank-column
    assumption; no look ever located that box, and the head's tilted looks at it 1.1-1.4 ft
    away, assuming nothing, neither confirmed nor refuted it; a pivot "turning to look"
    beside the corner, its circle free on the map, swung the vehicle's corner into it.
    With ``assist_pivot_ft`` (the default under assist) no pivot counts such cells free;
    nor, without it, with the assumption bounded by the floor in view (``floor_eyes``
    "bound", the default since 2026-12-02; traced with it "off")."""
    from rigtools import DRIVE_BEFORE_2026_12_04, DRIVE_BEFORE_2026_12_05, bench_task
    room, start, goal = bench_task(45)
    runs = {(ft, fe): run(room, start, DriveConfig(goal=goal, head="assist", eyes="truth",
                                                   assist_pivot_ft=ft, floor_eyes=fe,
                                                   **{**DRIVE_BEFORE_2026_12_04,
                                                      **DRIVE_BEFORE_2026_12_05}),
                          noise=OdometryNoise(seed=45), keep_maps=False)
            for ft, fe in ((None, "off"), (4.64, "off"), (None, "bound"))}
    assert runs[None, "off"].collisions == 1 and "hit something" in runs[None, "off"].reason
    for ok in (runs[4.64, "off"], runs[None, "bound"]):
        assert ok.collisions == 0 and "hit something" not in ok.reason


def test_assist_pivot_ft_reaches_the_loop_by_its_flag_and_is_checked(tmp_path, monkeypatch):
    """``rig drive --assist-pivot-ft FT`` (0: off) sets ``DriveConfig.assist_pivot_ft``;
    a negative or absurd distance is one clear error."""
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path).assist_pivot_ft == 4.64
    assert drive_config(monkeypatch, tmp_path, "--assist-pivot-ft", "3").assist_pivot_ft == 3.0
    assert drive_config(monkeypatch, tmp_path, "--assist-pivot-ft", "0").assist_pivot_ft is None
    from rig.main import main
    for bad in ("-1", "nan", "99"):
        with pytest.raises(SystemExit) as e:
            main(["drive", "--out", str(tmp_path), "--assist-pivot-ft", bad])
        # SystemExit(message): the interpreter prints it to stderr and exits 1
        assert e.value.code not in (0, None) and "--assist-pivot-ft" in str(e.value.code)
