"""world.walk: the bundled walk is deterministic, Cart-like and collision free; walk files."""

import math

import pytest

from world.odometry import step_motion
from world.pose import Pose
from world.room import bundled_lab, generate_room
from world.walk import (BUNDLED_WALK, CLEARANCE_FT, bundled_walk, generate_walk,
                        make_bundled_walk, parse_walk, read_walk, walk_csv, write_walk)


def _check_cart(poses, room):
    for a, b in zip(poses, poses[1:]):
        turn, dist, drive = step_motion(a, b)
        assert abs(turn) <= 15.0 + 1e-9
        assert dist <= 0.7502
        assert dist < 1e-12 or abs(drive) < 0.02          # drives straight ahead
    for p in poses:
        assert room.is_free(p.x, p.z, 0.9 * CLEARANCE_FT), p


def test_bundled_walk_shape():
    w = bundled_walk()
    assert w[0] == Pose(0, 0, 0)
    assert 100 <= len(w) <= 120                               # twice round the lab
    _check_cart(w, bundled_lab())
    steps = [step_motion(a, b)[1] for a, b in zip(w, w[1:])]
    assert sum(d > 0.7 for d in steps) >= 0.7 * len(steps)   # mostly full 0.75 ft steps
    assert math.hypot(w[-1].x, w[-1].z) < 1.5                 # a loop back near the start


def test_bundled_walk_keeps_corners_in_view_for_ten_looks_and_more():
    # the reason it goes round twice: many of the room's true corners (within the 15 ft the
    # model uses, in the scanned rows, occlusion ignored) lie in view of 10 looks or more;
    # on the first lap alone, or on the first 56 looks, far fewer
    import numpy as np
    from model.geometry import left_centre
    from model.matching import in_view
    lab, w = bundled_lab(), bundled_walk()
    corners = np.unique(np.round(np.asarray(lab.vertices, float).reshape(-1, 3), 6), axis=0)

    def looks_in_view(poses):
        n = np.zeros(len(corners), int)
        for p in poses:
            R = np.asarray(p.rotation(), float)
            left = left_centre((p.x, p.y, p.z), R)
            near = np.linalg.norm(corners - left, axis=1) <= 15.0
            n += in_view(corners, left, R) & near
        return n

    n = looks_in_view(w)
    half = looks_in_view(w[:len(w) // 2])
    assert (n >= 10).sum() >= 30
    assert (n >= 10).sum() >= 2 * (half >= 10).sum()
    # the second lap passes where the first did
    first = np.array([(p.x, p.z) for p in w[:len(w) // 2]])
    for p in w[len(w) // 2:]:
        assert np.min(np.hypot(first[:, 0] - p.x, first[:, 1] - p.z)) < 0.8


def test_bundled_walk_is_deterministic_and_equals_the_shipped_file(tmp_path):
    """Regression guard: the shipped CSV is what the code computes, byte for byte."""
    text = walk_csv(make_bundled_walk())
    assert text == walk_csv(make_bundled_walk())
    assert BUNDLED_WALK.read_text() == text
    p = write_walk(tmp_path / "w.csv", bundled_walk())
    assert p.read_bytes() == BUNDLED_WALK.read_bytes()
    assert read_walk(p) == bundled_walk()


def test_generated_walks():
    room = generate_room(4)
    w = generate_walk(room, 9, 50)
    assert len(w) == 50 and w[0] == room.start
    assert w == generate_walk(room, 9, 50)
    assert w != generate_walk(room, 10, 50)
    _check_cart(w, room)
    travelled = sum(step_motion(a, b)[1] for a, b in zip(w, w[1:]))
    assert travelled > 15.0
    wob = generate_walk(room, 9, 20, wobble_deg=2.0)
    assert all(abs(p.pitch_deg) <= 2 and abs(p.roll_deg) <= 2 for p in wob)
    assert any(p.pitch_deg != 0 for p in wob)


def test_walk_csv_round_trip_with_y(tmp_path):
    poses = [Pose(1.25, -2.5, 30.0, 1.5, -0.5, 0.25), Pose(0, 0, 0)]
    p = write_walk(tmp_path / "y.csv", poses)
    assert p.read_text().splitlines()[0] == "x,z,heading_deg,pitch_deg,roll_deg,y"
    assert read_walk(p) == poses


@pytest.mark.parametrize("text, msg", [
    ("", "empty"),
    ("x,z,heading\n1,2,3\n", "header"),
    ("x,z,heading_deg,pitch_deg,roll_deg\n1,2,3,0\n", "line 2: expected 5"),
    ("x,z,heading_deg,pitch_deg,roll_deg\n1,2,3,0,0\n1,two,3,0,0\n", "line 3: not a number"),
    ("x,z,heading_deg,pitch_deg,roll_deg\n1,2,nan,0,0\n", "finite"),
    ("x,z,heading_deg,pitch_deg,roll_deg\n", "no poses"),
])
def test_bad_walk_files(text, msg):
    with pytest.raises(ValueError, match=msg):
        parse_walk(text, "w.csv")


def test_unreadable_walk_file(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        read_walk(tmp_path / "missing.csv")


def test_a_walk_with_nowhere_to_go_is_refused():
    from world.room import make_room
    lab = bundled_lab()
    # a 3 x 3 ft pen around the start: with 1.2 ft clearance only 0.6 ft of it is free
    pen = [((-3.0, 3.0), (1.5, 2.5)), ((-3.0, 3.0), (-2.5, -1.5)),
           ((-3.0, -1.5), (-2.5, 2.5)), ((1.5, 3.0), (-2.5, 2.5))]
    with pytest.raises(ValueError, match="no goal"):
        generate_walk(make_room("pen", lab.quads, pen, lab.bounds), 1, 10)
    tight = [((-3.0, 3.0), (1.0, 2.0))]
    with pytest.raises(ValueError, match="start"):
        generate_walk(make_room("tight", lab.quads, tight, lab.bounds), 1, 10)
