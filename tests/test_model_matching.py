"""Matching a look to the model: predict, gate by covariance, grey level, one-to-one."""

import numpy as np

from model.edges import VertexObservation
from model.geometry import camera_points, left_centre, rotation_from_angles
from model.matching import match_look
from model.symbolic import SymbolicModel
from model.velocity import velocity


def setup():
    model = SymbolicModel()
    corners = np.array([[-0.5, 0.2, 6.0], [0.5, -0.5, 8.0], [1.5, 1.0, 7.0], [-0.6, 1.2, 9.0]])
    for i, c in enumerate(corners):
        model.add_vertex(c, np.eye(3) * 0.01, "top" if i % 2 == 0 else "bottom", (4, 11), look=0)
    R = rotation_from_angles(10.0)
    left = left_centre((0.3, 0.0, 0.5), R)
    q = camera_points(R, left, corners)
    obs = [VertexObservation(qi, np.diag([0.01, 0.001, 0.001]), "top" if i % 2 == 0 else "bottom",
                             64.0, 60.0, 10.0, (4, 11), i) for i, qi in enumerate(q)]
    return model, obs, left, R


def test_a_known_pose_matches_each_corner_to_itself():
    model, obs, left, R = setup()
    res = match_look(model, obs[::-1], left, R, np.diag([0.01] * 3 + [1e-4] * 3))
    assert sorted(res.pairs) == [(0, 3), (1, 2), (2, 1), (3, 0)]
    assert res.predicted_in_view == 4


def test_grey_kind_and_distance_gates():
    model, obs, left, R = setup()
    o = obs[0]
    other_grey = VertexObservation(o.q, o.cov, o.kind, o.col, o.row, o.disparity, (9, 2), 0)
    other_kind = VertexObservation(o.q, o.cov, "bottom", o.col, o.row, o.disparity, o.grey, 0)
    far = VertexObservation(o.q + [0.0, 1.0, 0.0], o.cov, o.kind, o.col, o.row, o.disparity,
                            o.grey, 0)
    for bad in (other_grey, other_kind, far):
        assert match_look(model, [bad], left, R, np.diag([0.01] * 3 + [1e-4] * 3)).pairs == []


def test_one_to_one():
    model, obs, left, R = setup()
    res = match_look(model, [obs[0], obs[0]], left, R, np.diag([0.01] * 3 + [1e-4] * 3))
    assert len(res.pairs) == 1 and res.pairs[0][0] == 0


def test_velocity_from_successive_poses():
    C = np.diag([0.01, 0.04, np.radians(1.0) ** 2])
    v = velocity((1.0, 2.0, 10.0), C, (1.6, 2.8, 20.0), C, dt=2.0)
    np.testing.assert_allclose((v.vx, v.vz, v.turn_deg_s), (0.3, 0.4, 5.0))
    assert abs(v.speed - 0.5) < 1e-12
    np.testing.assert_allclose(np.diag(v.cov), [0.02 / 4, 0.08 / 4, 2.0 / 4])


def test_shape_gate_refuses_a_different_corner():
    model, obs, left, R = setup()
    box = (0,) * 8 + (0xFFFF,) * 8
    for v in model.vertices.values():
        v.shape = box
    o = obs[0]
    same = VertexObservation(o.q, o.cov, o.kind, o.col, o.row, o.disparity, o.grey, 0, -1,
                             (0,) * 7 + (0xFFFF,) * 9)       # one column off: shifted back
    other = VertexObservation(o.q, o.cov, o.kind, o.col, o.row, o.disparity, o.grey, 0, -1,
                              (0xFFFF,) * 8 + (0,) * 8)      # the mirror corner: 256 bits apart
    cov6 = np.diag([0.01] * 3 + [1e-4] * 3)
    assert match_look(model, [same], left, R, cov6, shape_max_bits=64).pairs == [(0, 0)]
    assert match_look(model, [other], left, R, cov6, shape_max_bits=64).pairs == []
    assert match_look(model, [other], left, R, cov6, shape_max_bits=None).pairs == [(0, 0)]
