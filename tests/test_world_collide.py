"""world.collide: a vehicle footprint against obstacles and walls, on hand-made cases."""

import numpy as np
import pytest

from world.collide import footprint_corners, footprint_hits
from world.room import Room


def _room():
    return Room("toy", (), np.zeros((0, 3)), np.zeros((0, 2, 3)),
                np.array([[1.0, 2.0, 1.0, 2.0]]), (-3.0, 3.0, -3.0, 5.0))


def test_corners():
    c = footprint_corners(0, 0, 90, (1.0, 2.0))
    assert np.allclose(sorted(map(tuple, c)), [(-1, -0.5), (-1, 0.5), (1, -0.5), (1, 0.5)])
    c = footprint_corners(0, 0, 0, (1.0, 2.0, 1.0))         # centred 1 ft ahead
    assert np.allclose(c[:, 1].min(), 0.0) and np.allclose(c[:, 1].max(), 2.0)


def test_hits_obstacle_depending_on_heading():
    r = _room()
    assert not footprint_hits(r, 0.0, 0.0, 0.0, (1.0, 1.0))
    assert footprint_hits(r, 0.6, 1.5, 0.0, (1.0, 1.0))
    # half-diagonal 0.707: turned 45 degrees the corner reaches x = 1.057
    assert not footprint_hits(r, 0.35, 1.5, 0.0, (1.0, 1.0))
    assert footprint_hits(r, 0.35, 1.5, 45.0, (1.0, 1.0))
    # a diamond near the obstacle's corner, separated along the diagonal
    assert not footprint_hits(r, 0.3, 0.3, 45.0, (1.0, 1.0))


def test_hits_walls():
    r = _room()
    assert footprint_hits(r, -2.6, 0.0, 0.0, (1.0, 1.0))
    assert not footprint_hits(r, -2.4, 0.0, 0.0, (1.0, 1.0))
    assert footprint_hits(r, 0.0, 4.4, 0.0, (1.0, 2.0))
    with pytest.raises(ValueError):
        footprint_hits(r, 0, 0, 0, (1.0,))
