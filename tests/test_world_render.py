"""world.render: the bundled pair reproduced bit for bit, corners on their predicted pixels at
several poses (pitch and roll too), the windowed tracer equal to the plain one, determinism."""

import numpy as np
import pytest

from diskfmt.layouts import encode_bi, encode_vd
from rig.scene import bundled_path, flat, range_npy_bytes
from world.pose import Pose
from world.render import (LeftTheRoom, _directions, _grid, _trace_windows, render_camera, render_look,
                          project, trace_grid, trace_rays, visible)
from world.room import bundled_lab, full_box, generate_room, make_room, quad


@pytest.fixture(scope="module")
def lab():
    return bundled_lab()


@pytest.fixture(scope="module")
def lab_look(lab):
    return render_look(lab, Pose(0, 0, 0))


def test_pose_zero_reproduces_the_bundled_files_byte_for_byte(lab_look):
    assert encode_vd(lab_look.left_vd) == bundled_path("LAB-L.VD").read_bytes()
    assert encode_vd(lab_look.right_vd) == bundled_path("LAB-R.VD").read_bytes()
    assert encode_bi(lab_look.left_bi) == bundled_path("LAB-L.BI").read_bytes()
    assert encode_bi(lab_look.right_bi) == bundled_path("LAB-R.BI").read_bytes()
    assert range_npy_bytes(lab_look.range_left) == bundled_path("LAB-RANGE.npy").read_bytes()


def test_same_look_twice_same_bytes(lab):
    pose = Pose(1.2, 3.4, 25.0, 2.0, -1.5)
    a, b = render_look(lab, pose, seed=7), render_look(lab, pose, seed=7)
    for name in ("left_vd", "right_vd", "left_bi", "right_bi", "range_left", "range_right"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name
    c = render_look(lab, pose, seed=8)
    assert not np.array_equal(a.left_vd, c.left_vd)
    assert np.array_equal(a.range_left, c.range_left)


# --- a test room: one bright box in a dark room ------------------------------------------------

BOX_X, BOX_Y, BOX_Z = (-1.0, 1.0), (-1.0, 3.0), (8.0, 10.0)


def _test_room():
    quads = full_box("box", BOX_X, BOX_Y, BOX_Z, flat(15), flat(15), flat(15))
    y0, y1, x0, x1, z0, z1 = -5.0, 3.0, -6.0, 6.0, -6.0, 16.0
    quads += [quad("back", 2, z1, (x0, x1), (y0, y1), flat(2)),
              quad("front", 2, z0, (x0, x1), (y0, y1), flat(2)),
              quad("left", 0, x0, (y0, y1), (z0, z1), flat(2)),
              quad("right", 0, x1, (y0, y1), (z0, z1), flat(2)),
              quad("floor", 1, y1, (x0, x1), (z0, z1), flat(2)),
              quad("ceiling", 1, y0, (x0, x1), (z0, z1), flat(2))]
    return make_room("test box", quads, [(BOX_X, BOX_Z)], (x0, x1, z0, z1))


POSES = [Pose(0, 0, 0), Pose(0.3, 1.0, 5.0), Pose(-0.4, 0.5, -8.0, pitch_deg=4.0),
         Pose(0.2, -0.5, 6.0, pitch_deg=-3.0, roll_deg=5.0), Pose(0.0, 1.5, -3.0, roll_deg=-7.0),
         Pose(0.1, 2.0, 2.0, pitch_deg=2.5, roll_deg=2.5, y=0.3)]


def _unit(v):
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("pose", POSES)
@pytest.mark.parametrize("side", ["left", "right"])
def test_box_corner_lands_on_its_predicted_pixel(pose, side):
    """The front face's top-left corner (X=-1, Y=-1, Z=8) projected by ``project``: the 2x2
    block of 256-px pixels around it is partly covered; 2 px into the wedge between the projected edges the
    picture is the box (15), 2 px the other way the room (2); and the box's left edge crosses
    the rows below the corner where the projected edge line says, within 0.25 px (256 px),
    measured from the grey coverage of the noise-free picture."""
    room = _test_room()
    corner = np.array([BOX_X[0], BOX_Y[0], BOX_Z[0]])
    down = corner + [0.0, 1.0, 0.0]              # along the left edge
    right = corner + [1.0, 0.0, 0.0]             # along the top edge
    col, row, _ = project(np.stack([corner, down, right]), pose, side)
    c = np.array([2 * col[0], 2 * row[0]])       # 256-px continuous coordinates
    a = np.array([2 * col[1], 2 * row[1]]) - c
    b = np.array([2 * col[2], 2 * row[2]]) - c
    grey = render_camera(room.quads, pose.camera_centre(side), pose.rotation())
    r0, c0 = int(round(c[1])) - 1, int(round(c[0])) - 1     # the 2x2 block around the corner
    assert 2 < grey[r0:r0 + 2, c0:c0 + 2].mean() < 15
    inward = _unit(_unit(a) + _unit(b))
    i = c + 2.5 * inward
    o = c - 2.5 * inward
    assert grey[int(i[1]), int(i[0])] == 15
    assert grey[int(o[1]), int(o[0])] == 2
    for k in (3, 5, 8):                          # rows below the corner
        v = int(c[1]) + k + 0.5                  # row centre
        u_edge = c[0] + a[0] * (v - c[1]) / a[1]
        lo = int(u_edge) - 4
        cover = (grey[int(v), lo:lo + 9] - 2.0) / 13.0      # box on the right of the edge
        measured = lo + 9 - cover.sum()
        assert abs(measured - u_edge) < 0.25, (k, measured, u_edge)


@pytest.mark.parametrize("pose", POSES[:3])
def test_range_truth_is_camera_z_of_the_face(pose):
    room = _test_room()
    look = render_look(room, pose, noise=0.0)
    p = np.array([0.0, 1.0, BOX_Z[0]])          # middle of the front face
    col, row, _ = look.project(p[None, :])
    r, c = int(row[0]), int(col[0])
    # the ray through that pixel's centre meets the plane Z = 8 at camera z = t
    d = pose.rotation() @ np.array([(c + 0.5 - 64) / 180, (r + 0.5 - 60) / 180, 1.0])
    t = (BOX_Z[0] - pose.camera_centre("left")[2]) / d[2]
    assert look.range_left[r, c] == pytest.approx(t, rel=1e-6)
    assert room.quads[look.surface_left[r, c]].name == "box front"


def test_windowed_trace_equals_plain_trace(lab):
    px, py = _grid(1)
    for pose in (Pose(0, 0, 0), Pose(2.0, 6.0, 80.0, 3.0, -4.0), Pose(-3.0, 2.0, -120.0),
                 Pose(6.0, 17.5, 45.0, 0.0, 0.0), Pose(-3.615, -4.6, 0.0),
                 Pose(-3.62, -4.75, 30.0, 2.0, 1.0)):
        # (the last two: the left camera 1 cm and 5.5 cm from the left wall)
        for side in ("left", "right"):
            o, R = pose.camera_centre(side), pose.rotation()
            t, which, d = trace_grid(lab.quads, o, R, px, py)
            t0, which0 = trace_rays(lab.quads, o, _directions(R, px, py))
            assert np.array_equal(which, which0) and np.array_equal(t, t0)
            # the numpy windowed path (used without numba) too
            t1, which1, _ = _trace_windows(lab.quads, o, R, px, py, tuple(d))
            assert np.array_equal(which1, which0) and np.array_equal(t1, t0)


def test_visible_vertices(lab):
    look = render_look(lab, Pose(0, 0, 0), supersample=1)
    idx, crc = look.visible_vertices()
    names = {lab.vertex_labels[i] for i in idx}
    assert {"waste bin", "crate", "bookcase", "door frame"} <= names
    assert (crc[:, 0] >= 0).all() and (crc[:, 0] < 128).all()
    # the middle of the crate's back face is hidden behind its front
    hidden = np.array([-0.5, 1.5, 6.0])
    assert not visible(lab, Pose(0, 0, 0), hidden[None, :])[0]
    # and the front wall is behind the camera
    assert not visible(lab, Pose(0, 0, 0), np.array([[0.0, 0.0, -5.0]]))[0]


def test_a_camera_outside_the_room_is_refused(lab):
    with pytest.raises(LeftTheRoom):
        render_look(lab, Pose(0, 40, 0), supersample=1)


def test_generated_room_renders_from_its_start():
    look = render_look(generate_room(3), Pose(0, 0, 0), supersample=1)
    assert look.left_bi.shape == (120, 128) and look.left_bi.max() <= 15
