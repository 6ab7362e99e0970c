"""world.odometry: the noise model's statistics, and dead reckoning."""

import math

import numpy as np
import pytest

from world.odometry import OdometryNoise, dead_reckon, odometry
from world.pose import Pose
from world.walk import bundled_walk


def test_measure_statistics():
    """20000 steps of 0.75 ft and 10 degrees: distance error sd 2 % of 0.75 ft, turn error sd
    1 degree, both unbiased (within 4 standard errors)."""
    n = OdometryNoise(seed=5)
    m = np.array([n.measure(0.75, 10.0) for _ in range(20000)])
    de, te = m[:, 0] - 0.75, m[:, 1] - 10.0
    assert abs(de.mean()) < 4 * 0.015 / math.sqrt(20000)
    assert de.std() == pytest.approx(0.015, rel=0.03)
    assert abs(te.mean()) < 4 * 1.0 / math.sqrt(20000)
    assert te.std() == pytest.approx(1.0, rel=0.03)
    assert abs(np.corrcoef(de, te)[0, 1]) < 0.03


def test_noise_scales():
    n = OdometryNoise(distance_fraction=0.1, turn_deg=0.0, seed=1)
    m = np.array([n.measure(2.0, -5.0) for _ in range(5000)])
    assert np.all(m[:, 1] == -5.0)
    assert m[:, 0].std() == pytest.approx(0.2, rel=0.05)
    with pytest.raises(ValueError):
        OdometryNoise(distance_fraction=-0.1)


def test_noise_free_dead_reckoning_is_the_truth():
    w = bundled_walk()
    dr = dead_reckon(w, OdometryNoise(0.0, 0.0))
    for a, b in zip(w, dr):
        assert b.x == pytest.approx(a.x, abs=1e-3) and b.z == pytest.approx(a.z, abs=1e-3)
        assert math.cos(math.radians(a.heading_deg - b.heading_deg)) == pytest.approx(1.0)


def test_dead_reckoning_drifts_as_the_model_says():
    """Heading error after n steps is a sum of n N(0, 1 deg) errors: over 400 seeded runs of
    the bundled walk its sd at the end is sqrt(n) degrees (within 10 %)."""
    w = bundled_walk()
    n = len(w) - 1
    ends = []
    for seed in range(400):
        dr = dead_reckon(w, OdometryNoise(seed=seed))
        ends.append((dr[-1].heading_deg - w[-1].heading_deg + 180) % 360 - 180)
    assert np.std(ends) == pytest.approx(math.sqrt(n), rel=0.1)
    assert dead_reckon(w, OdometryNoise(seed=3)) == dead_reckon(w, OdometryNoise(seed=3))
    assert dead_reckon(w, OdometryNoise(seed=3))[0] == w[0]


def test_odometry_reports_each_step():
    w = [Pose(0, 0, 0), Pose(0, 0, 15), Pose(0.75 * math.sin(math.radians(15)),
                                            0.75 * math.cos(math.radians(15)), 15)]
    rep = odometry(w, OdometryNoise(0.0, 0.0))
    assert rep[0] == pytest.approx((0.0, 15.0)) and rep[1] == pytest.approx((0.75, 0.0))
