"""The loop's diagnostic depth eyes (``DriveConfig.eyes="depth"``,
planner.depth_eyes): the true range at every pixel as a floor range scan.
External truth: the rendered room's own geometry and a floor plane's ranges
derived by hand."""

import math

import numpy as np
import pytest

from planner.depth_eyes import camera_points, depth_floor_scan
from planner.evidence import Perception
from planner.loop import DriveConfig, run
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest, query
from planner.perception import floor_scan
from rig.scene import flat
from vehicle.profile import DEFAULT
from vehicle.sim import State
from world.pose import Pose
from world.room import FLOOR_Y, full_box, make_room, quad
from world.render import render_look

BAND = DriveConfig.band
BOX_X, BOX_Z = (-1.5, 1.5), (5.0, 6.0)        # a blank box face 5 ft ahead, 1.5 ft tall


def _blank_box_room():
    """8 ft x 14 ft, irregularly banded walls and tiled floor (edges for the rig's
    eyes everywhere else), one box of ONE grey on every face."""
    from planner.tiny import bands, tiles
    x0, x1, z0, z1 = -4.0, 4.0, -2.0, 12.0
    quads = full_box("box", BOX_X, (FLOOR_Y - 1.5, FLOOR_Y), BOX_Z, flat(9), flat(9), flat(9))
    quads += [quad("back wall", 2, z1, (x0, x1), (-5.0, FLOOR_Y), bands(3, 0, x0, x1)),
              quad("front wall", 2, z0, (x0, x1), (-5.0, FLOOR_Y), bands(4, 0, x0, x1)),
              quad("left wall", 0, x0, (-5.0, FLOOR_Y), (z0, z1), bands(5, 2, z0, z1)),
              quad("right wall", 0, x1, (-5.0, FLOOR_Y), (z0, z1), bands(6, 2, z0, z1)),
              quad("floor", 1, FLOOR_Y, (x0, x1), (z0, z1), tiles(7)),
              quad("ceiling", 1, -5.0, (x0, x1), (z0, z1), flat(12))]
    return make_room("blank box", quads, [(BOX_X, BOX_Z)], (x0, x1, z0, z1), ceiling_y=-5.0)


@pytest.fixture(scope="module")
def look():
    pose = Pose(0.0, 0.0, 0.0, DEFAULT.camera_pitch_deg)
    return pose, render_look(_blank_box_room(), pose, supersample=1)


def _on_face(hits):
    """Hits in front of the face's middle (away from its vertical edges)."""
    return hits[(hits[:, 0] > -1.2) & (hits[:, 0] < 1.2) & (hits[:, 2] < 5.5)]


def test_depth_eyes_hit_the_blank_face_at_its_true_range(look):
    pose, lk = look
    fs = depth_floor_scan(lk.range_left, pose.rotation(), pose.camera_centre("left"), BAND)
    face = _on_face(fs.hits)
    # from x = -1.2 to the picture's right edge (20 deg right of the heading): ~60 columns
    assert len(face) >= 50
    assert np.allclose(face[:, 2], BOX_Z[0], atol=0.01)       # at the face, not in front of it
    assert np.allclose(fs.hits[:, 1], 0.0)                     # at the camera's height
    assert not fs.assumed.any() and len(fs.assumed) == len(fs.free_ends)
    assert len(fs.hit_cols) == len(fs.hits) and len(set(fs.hit_cols)) == len(fs.hits)
    # every column of the picture has its hit or its free end (the back wall is 12 ft away)
    assert sorted(fs.hit_cols.tolist() + fs.free_cols.tolist()) == list(range(1, 129))


def test_the_rig_eyes_locate_nothing_on_the_blank_face(look):
    # the face the depth eyes see is one the edge-based eyes cannot: no edge on it
    from eyes import scan_pair
    pose, lk = look
    scan = scan_pair(lk.left_bi, lk.right_bi, lines=DriveConfig.lines)
    fs = floor_scan(scan.points, pose.rotation(), pose.camera_centre("left"), BAND,
                    blank_ft=None, place="point")
    face = _on_face(fs.hits)
    # (what they do locate there are false matches on the floor's tiles, nearer)
    assert not (np.abs(face[:, 2] - BOX_Z[0]) < 0.3).any()


def test_depth_eyes_mark_the_face_occupied_and_the_floor_before_it_free(look):
    pose, lk = look
    m = Perception(VolumeOfInterest(32.0, 7), BAND, 12.0, 2, 1, near_ft=2.3, blank_ft=8.0)
    m.blank_carve = "unknown"
    n = m.update([], State(0.0, 0.0, 0.0), Pose, DEFAULT.camera_pitch_deg, depth=lk.range_left)
    assert n > 100
    y = m.points[0][1]
    for x in (-0.6, 0.0, 0.6):
        # the face's cell (z 5.0..5.25): hit by this one look (uncertain until confirmed)
        assert query(m.tree, np.array([x, y, 5.1])) in (UNCERTAIN, OCCUPIED)
        # the floor before it, from near_ft on, free; nearer than that the look proves nothing
        for z in (2.6, 3.5, 4.5):
            assert query(m.tree, np.array([x, y, z])) == FREE, (x, z)
        assert query(m.tree, np.array([x, y, 1.0])) == UNKNOWN
        # behind the face: never seen
        assert query(m.tree, np.array([x, y, 5.6])) == UNKNOWN
    # a second look from the same place confirms the face
    m.update([], State(0.0, 0.0, 0.0), Pose, DEFAULT.camera_pitch_deg, depth=lk.range_left)
    assert query(m.tree, np.array([0.0, y, 5.1])) == OCCUPIED


def _floor_only(pitch_deg):
    """The range per pixel of a camera 3 ft over a bare floor, by hand: the ray
    R @ (u, v, 1) meets Y = 3 at t = 3 / (its Y), and Z (camera axis) is t."""
    R = Pose(0.0, 0.0, 0.0, pitch_deg).rotation()
    u = (np.arange(128) + 0.5 - 64) / 180
    v = (np.arange(120) + 0.5 - 60) / 180
    dy = R[1, 0] * u[None, :] + R[1, 1] * v[:, None] + R[1, 2]
    assert (dy > 0).all()
    return R, 3.0 / dy


def test_a_column_showing_only_floor_is_free_to_the_farthest_floor_it_shows():
    R, z = _floor_only(-45.0)
    origin = np.zeros(3)
    fs = depth_floor_scan(z, R, origin, BAND, max_range=12.0)
    assert len(fs.hits) == 0 and len(fs.free_ends) == 128
    # the top line's ray, 45 - atan(59.5 / 180) deg down at the centre column
    down = math.radians(45.0) - math.atan(59.5 / 180)
    d = np.hypot(fs.free_ends[:, 0], fs.free_ends[:, 2])
    centre = np.flatnonzero(fs.free_cols == 64)[0]
    # column 64's centre is half a pixel left of the axis: its top ray reaches a little farther
    assert d[centre] == pytest.approx(3.0 / math.tan(down), rel=2e-3)
    # every column: its top line's ray to the floor, one at a time
    for col in (1, 30, 64, 65, 100, 128):
        ray = R @ np.array([(col - 0.5 - 64) / 180, -59.5 / 180, 1.0])
        k = np.flatnonzero(fs.free_cols == col)[0]
        assert fs.free_ends[k, [0, 2]] == pytest.approx(3.0 / ray[1] * ray[[0, 2]])
    assert not fs.assumed.any()
    # the farthest floor beyond range: free to the range only
    fs = depth_floor_scan(z, R, origin, BAND, max_range=4.0)
    assert np.allclose(np.hypot(fs.free_ends[:, 0], fs.free_ends[:, 2]), 4.0)


def test_camera_points_are_the_pixel_rays_scaled_by_z():
    z = np.full((120, 128), 2.0)
    p = camera_points(z)
    assert p[60, 64] == pytest.approx([0.5 / 180 * 2, 0.5 / 180 * 2, 2.0])
    assert p[0, 0] == pytest.approx([-63.5 / 180 * 2, -59.5 / 180 * 2, 2.0])


def test_the_loop_drives_the_tiny_room_on_depth_eyes_and_refuses_unknown_eyes():
    from planner.tiny import GOAL, tiny_room
    from world.odometry import OdometryNoise
    room = tiny_room()
    res = run(room, State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="depth"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.travelled_ft <= 1.3 * res.optimal_ft
    with pytest.raises(ValueError, match="unknown eyes 'sonar'"):
        run(room, State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="sonar"))


def test_rig_drive_and_the_bench_take_eyes_depth(monkeypatch, tmp_path):
    from rigtools import drive_config
    assert drive_config(monkeypatch, tmp_path, "--eyes", "depth").eyes == "depth"
    assert drive_config(monkeypatch, tmp_path).eyes == "rig"            # never the default
    with pytest.raises(SystemExit):
        drive_config(monkeypatch, tmp_path, "--eyes", "sonar")
    assert drive_config(monkeypatch, tmp_path, "--pivot", "swept").pivot == "swept"
    assert drive_config(monkeypatch, tmp_path).pivot == DriveConfig.pivot



def test_a_swept_pivot_needs_only_the_cells_its_footprint_sweeps():
    # planner.loop's pivot="swept" (a named option).  All free but one unknown cell,
    # x 0.5..0.75, z 0..0.25, beside the vehicle at the origin facing +z: within the
    # half diagonal (0.64 ft) the default's whole disc asks for, outside the bare
    # footprint (0.8 x 1.0 ft: x up to 0.4)
    from planner.floormap import FloorMap
    from planner.motion import _disc_seen_free, _pivot_seen_free
    fm = FloorMap(np.full((24, 24), FREE, np.uint8), -3.0, -3.0, 0.25)
    fm.cells[fm.index(0.6, 0.1)] = UNKNOWN
    foot = DEFAULT.footprint
    assert not _disc_seen_free(fm, 0.0, 0.0, DEFAULT.radius_ft)
    assert _pivot_seen_free(fm, 0.0, 0.0, 0.0, 0.0, foot, 0.0)
    # 2 deg: the right side's front half moves out to x = 0.4 cos 2 + 0.25 sin 2 = 0.41
    assert _pivot_seen_free(fm, 0.0, 0.0, 0.0, 2.0, foot, 0.0)
    assert _pivot_seen_free(fm, 0.0, 0.0, 0.0, -2.0, foot, 0.0)
    # 20 deg right: the right side's point 0.3 ft ahead reaches (0.48, 0.15); 0.4 ft
    # ahead (0.51, 0.24): into the cell.  45 deg left: 0.35 ft behind, (0.53, 0.04)
    assert not _pivot_seen_free(fm, 0.0, 0.0, 0.0, 20.0, foot, 0.0)
    assert not _pivot_seen_free(fm, 0.0, 0.0, 0.0, -90.0, foot, 0.0)
    # the margin grows the footprint: x up to 0.55 covers the cell before any turn
    assert not _pivot_seen_free(fm, 0.0, 0.0, 0.0, 0.0, foot, DEFAULT.margin_ft)
    # off the map: never free
    assert not _pivot_seen_free(fm, -2.9, 0.0, 0.0, 5.0, foot, 0.0)


@pytest.mark.processes
def test_bench_drive_runs_depth_eyes_without_odometry_noise(tmp_path):
    """bench/drive.py --eyes depth --no-noise as a user runs it: the estimate
    is then the true pose, look for look."""
    import json
    import subprocess
    import sys
    from pathlib import Path
    out = tmp_path / "b.json"
    bench = Path(__file__).resolve().parents[1] / "bench" / "drive.py"
    r = subprocess.run([sys.executable, str(bench), "--rooms", "1", "--first", "6",
                        "--max-looks", "3", "--eyes", "depth", "--no-noise", "--out", str(out)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    data = json.loads(out.read_text())
    assert data["summary"]["eyes"] == "depth" and data["summary"]["odometry_noise"] is False
    room = data["rooms"][0]
    assert room["collisions"] == 0 and room["travelled_ft"] > 0
    assert room["estimate_error_ft_final"] < 1e-9 and room["dead_error_ft_final"] < 1e-9
