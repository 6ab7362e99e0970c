"""world.room: the bundled lab's truth from rig/scene.py's numbers; generated rooms are closed."""

import numpy as np
import pytest

from rig import scene
from world.pose import Pose
from world.render import render_look, trace_rays
from world.room import bundled_lab, generate_room
from world.walk import generate_walk


def test_bundled_lab_truth_from_the_scene_table():
    lab = bundled_lab()
    assert lab.bounds == (-4.0, 7.0, -5.0, 19.0)
    obstacles = {tuple(o) for o in lab.obstacles.tolist()}
    assert obstacles == {(-0.2, 0.8, 3.5, 4.2), (-1.0, 0.0, 5.0, 6.0), (-0.2, 2.0, 7.0, 9.0),
                         (-3.4, -2.0, 11.0, 12.2), (3.0, 5.0, 14.0, 15.0)}
    verts = {tuple(v) for v in lab.vertices.tolist()}
    for x in scene.CRATE_X:                      # the crate's 8 corners
        for y in scene.CRATE_Y:
            for z in scene.CRATE_Z:
                assert (x, y, z) in verts
    assert (scene.DOOR_FRAME_X[0], scene.DOOR_FRAME_Y[0], scene.BACK_Z) in verts
    assert (-4.0, 3.0, -5.0) in verts            # a room corner behind the start
    edges = {(e[0, 0], e[0, 2]): (e[0, 1], e[1, 1]) for e in lab.vertical_edges}
    # crate checks every 0.35 ft across the front, full height; the carton's tape band
    for x in (-0.65, -0.3):
        assert edges[(x, 5.0)] == pytest.approx(scene.CRATE_Y)
    for x in (-2.9 - 0.12, -2.9 + 0.12):
        assert edges[(round(x, 9), 11.0)] == pytest.approx(scene.CARTON_Y)
    # the back wall's corners and the door's sides run their full height
    assert edges[(-4.0, 19.0)] == (scene.CEILING_Y, scene.FLOOR_Y)
    assert edges[(-3.25, 19.0)] == pytest.approx(scene.DOOR_FRAME_Y)
    assert all(e[0, 1] < e[1, 1] for e in lab.vertical_edges)      # top above bottom
    assert len(lab.edge_labels) == len(lab.vertical_edges)


def test_bookcase_binder_edges_per_shelf():
    """The binders' edges stop at the shelf boards (every 1.3 ft, 0.12 ft thick)."""
    lab = bundled_lab()
    book = [e for e, lab_ in zip(lab.vertical_edges, lab.edge_labels)
            if lab_ == "bookcase texture" and 3.1 + 1e-6 < e[0, 0] < 4.9 - 1e-6]
    # independently: shelf k starts the cycle of binder widths 0.37*k ft in
    widths = [0.25, 0.35, 0.3, 0.4, 0.26, 0.32, 0.38, 0.28, 0.34, 0.24, 0.4, 0.3]
    cum = np.concatenate([[0.0], np.cumsum(widths)])
    want = set()
    for k in range(5):
        for m in range(-1, 2):
            for c in cum[:-1]:
                x = scene.BOOKCASE_X[0] - 0.37 * k + c + m * cum[-1]
                if 3.1 + 1e-6 < x < 4.9 - 1e-6:
                    want.add((round(x, 6), k))
    got = {(round(e[0, 0], 6), int(round((e[0, 1] - scene.BOOKCASE_Y[0]) / 1.3))) for e in book}
    assert got == want
    for e in book:
        k = (e[0, 1] - scene.BOOKCASE_Y[0] - 0.12) / 1.3
        assert k == pytest.approx(round(k), abs=1e-6)
        assert e[1, 1] - e[0, 1] == pytest.approx(min(1.18, scene.FLOOR_Y - e[0, 1]), abs=1e-6)


def test_clearance_and_free_floor():
    lab = bundled_lab()
    assert lab.clearance(0.0, 0.0) == pytest.approx(3.5)      # to the bin's front
    assert lab.clearance(0.3, 4.0) < 0                        # inside the bin
    assert not lab.is_free(-5.0, 0.0)
    with pytest.raises(ValueError, match="outside the free floor"):
        lab.check_pose(Pose(0.0, 30.0, 0.0))


def _sphere(n):
    i = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * i / n)
    th = np.pi * (1 + 5 ** 0.5) * i
    return np.stack([np.cos(th) * np.sin(phi), np.cos(phi), np.sin(th) * np.sin(phi)])


@pytest.mark.parametrize("seed", range(10))
def test_generated_rooms_are_closed(seed):
    """From 15 random free points, rays in 2000 directions all hit something."""
    room = generate_room(seed)
    rng = np.random.default_rng(seed)
    x0, x1, z0, z1 = room.bounds
    d = _sphere(2000)
    n = 0
    while n < 15:
        x, z = rng.uniform(x0, x1), rng.uniform(z0, z1)
        if not room.is_free(x, z, 0.3):
            continue
        n += 1
        _, which = trace_rays(room.quads, np.array([x, rng.uniform(-1, 1), z]), tuple(d))
        assert (which >= 0).all(), (seed, x, z)
    # and a few walk poses render
    for p in generate_walk(room, seed, 12, wobble_deg=3.0)[::5]:
        render_look(room, p, supersample=1)


def test_generated_rooms_vary_and_repeat():
    a, b = generate_room(1), generate_room(2)
    assert a.bounds != b.bounds
    generate_room.cache_clear()
    again = generate_room(1)
    assert again is not a and again.bounds == a.bounds
    assert np.array_equal(again.vertices, a.vertices)
    assert np.array_equal(again.vertical_edges, a.vertical_edges)
    assert [q.name for q in again.quads] == [q.name for q in a.quads]
    for r in (a, b):
        assert len(r.obstacles) >= 3
        assert r.is_free(0.0, 0.0, 2.5)             # the start is clear
        assert any("poster" in q.name or "door" in q.name for q in r.quads)


def test_bad_room_seed():
    with pytest.raises(ValueError, match="seed"):
        generate_room(-1)
