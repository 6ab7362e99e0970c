"""world.pose: the rig's orientation conventions, checked against OpenCV's Rodrigues."""

import cv2
import numpy as np
import pytest

from world.pose import Pose, wrap_deg


def _rod(axis, deg):
    R, _ = cv2.Rodrigues(np.asarray(axis, dtype=float) * np.radians(deg))
    return R


@pytest.mark.parametrize("h, p, r", [(0, 0, 0), (30, 0, 0), (-75, 4, -3), (170, -6, 8)])
def test_rotation_is_heading_then_pitch_then_roll(h, p, r):
    R = Pose(1.0, 2.0, h, p, r).rotation()
    want = _rod([0, 1, 0], h) @ _rod([1, 0, 0], p) @ _rod([0, 0, 1], r)
    assert np.allclose(R, want, atol=1e-12)
    assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0)


def test_identity_pose_is_exact():
    R = Pose(0, 0, 0).rotation()
    assert np.array_equal(R, np.eye(3))
    assert np.array_equal(Pose(0, 0, 0).camera_centre("left"), [-0.375, 0.0, 0.0])
    assert np.array_equal(Pose(0, 0, 0).camera_centre("right"), [0.375, 0.0, 0.0])


def test_sign_conventions():
    fwd = lambda p: p.rotation()[:, 2]          # noqa: E731
    assert np.allclose(fwd(Pose(0, 0, 90)), [1, 0, 0])           # right turn -> +X
    assert fwd(Pose(0, 0, 0, pitch_deg=10))[1] < 0                # nose up -> -Y
    assert Pose(0, 0, 0, roll_deg=10).rotation()[1, 0] > 0        # x axis toward +Y
    # heading 90: the left camera is behind (toward +Z), the right one toward -Z
    assert np.allclose(Pose(0, 0, 90).camera_centre("left"), [0, 0, 0.375])
    assert np.allclose(Pose(2, 3, 0, y=0.5).camera_centre("right"), [2.375, 0.5, 3])


def test_to_camera_and_back():
    pose = Pose(1.5, -2.0, 37.0, 3.0, -2.0, 0.1)
    pts = np.array([[0.0, 1.0, 5.0], [3.0, -2.0, 9.0]])
    cam = pose.to_camera(pts, "right")
    assert np.allclose(cam, (pts - pose.camera_centre("right")) @ pose.rotation())
    assert np.allclose(pose.to_room(cam, "right"), pts)


def test_bad_values_and_side():
    with pytest.raises(ValueError, match="heading_deg"):
        Pose(0, 0, float("nan"))
    with pytest.raises(ValueError, match="side"):
        Pose(0, 0, 0).camera_centre("middle")
    assert wrap_deg(190) == -170 and wrap_deg(-180) == -180
