"""An uncertain (once-hit) cell that later looks had in view without locating
anything there expires to UNKNOWN (``DriveConfig.expire_uncertain``,
``Perception.expire_in_view``), on hand-made looks of a level camera; under
``occupied="model"`` the floor feature one look placed is retired so
(``Perception.expire_features_in_view``), and the same looks give the same map."""

import pytest

from planner.evidence import Perception
from planner.loop import DriveConfig, run
from planner.octree import OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest, query
from planner.tiny import GOAL, tiny_room
from rig.scan import Point
from vehicle.sim import State
from world.pose import Pose

RES = 0.25


def _edge(col, dp, ep=0.05):
    """A vertical edge located at picture column ``col``, range ``dp``, on two lines."""
    return [Point(line, 1, col, col - 10, dp, 0.0, 0.0, ep, 0.01, 0.01) for line in (50, 52)]


MAPS = ["looks", "model"]


def _model(expire=2, occupied="looks"):
    m = Perception(VolumeOfInterest(32.0, 7), DriveConfig.band, 12.0, 2, 1,
                   near_ft=2.3, blank_ft=8.0)
    m.blank_carve = "unknown"              # the loop's default: assumption never past a hit
    m.expire_uncertain = expire
    m.occupied = occupied
    return m


def _look(m, points, x, z, heading=0.0):
    m.update(points, State(x, z, heading), Pose, 0.0)
    return m.floor_map([(0.0, 0.0), (0.0, 9.0)])


def _first_hit(m):
    """Room point (x, z) and octree point of the one edge the first look located."""
    hit = m.points[0]
    return (hit[0], hit[2]), hit


@pytest.mark.parametrize("occupied", MAPS)
def test_a_cell_hit_once_and_then_in_view_of_two_blank_looks_is_unknown(occupied):
    m = _model(2, occupied)
    fm = _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, p = _first_hit(m)
    assert abs(xz[1] - 5.0) < 1e-9 and fm.state_at(*xz) == UNCERTAIN
    # a look from 1 ft nearer sees nothing in that column (blank: nothing located)
    fm = _look(m, [], 0.0, 1.0)
    assert fm.state_at(*xz) == UNCERTAIN                  # one look is not enough
    fm = _look(m, [], 0.0, 1.0)
    assert fm.state_at(*xz) == UNKNOWN                    # the second: expired
    assert (fm.cells == UNCERTAIN).sum() == 0             # every grown cell of the hit too
    # the octree keeps its evidence (the assumption never carved the hit cell)
    assert query(m.tree, p) == UNCERTAIN
    assert m.expired_total >= 1
    # off: the same looks leave it uncertain
    off = _model(0, occupied)
    for pts, z in ((_edge(64, 5.0), 0.0), ([], 1.0), ([], 1.0)):
        fm = _look(off, pts, 0.0, z)
    assert fm.state_at(*xz) == UNCERTAIN


@pytest.mark.parametrize("occupied", MAPS)
def test_a_cell_located_again_is_occupied_and_never_expires(occupied):
    m = _model(2, occupied)
    _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, _ = _first_hit(m)
    fm = _look(m, _edge(64, 4.0), 0.0, 1.0)                # the same edge, 1 ft nearer
    assert fm.state_at(*xz) == OCCUPIED
    for _ in range(3):
        fm = _look(m, [], 0.0, 1.0)
    assert fm.state_at(*xz) == OCCUPIED                    # confirmed: stays


@pytest.mark.parametrize("occupied", MAPS)
def test_an_expired_cell_located_again_comes_back(occupied):
    m = _model(2, occupied)
    _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, _ = _first_hit(m)
    for _ in range(2):
        fm = _look(m, [], 0.0, 1.0)
    assert fm.state_at(*xz) == UNKNOWN
    fm = _look(m, _edge(64, 4.0), 0.0, 1.0)
    # the cell's log-odds reach the confirmed level; a retired feature stays
    # retired, so the corner comes back as a new feature seen once
    assert fm.state_at(*xz) == (OCCUPIED if occupied == "looks" else UNCERTAIN)


def test_a_feature_a_look_located_again_starts_its_count_over():
    # blank, located again (fused: confirmed, never expires) ...
    m = _model(2, "model")
    _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, _ = _first_hit(m)
    _look(m, [], 0.0, 1.0)
    assert m.feature_unseen[0] == 1
    fm = _look(m, _edge(64, 4.0), 0.0, 1.0)
    assert m.feature_unseen[0] == 0 and m.features.looks[0] == 2
    for _ in range(3):
        fm = _look(m, [], 0.0, 1.0)
    assert fm.state_at(*xz) == OCCUPIED and m.expired_total == 0
    # ... and a hit within two standard deviations and a cell of a feature it
    # is not fused into counts as seeing it: two corners located 5 ft away with
    # a 0.2 ft range error, then one hit between them 0.5 ft farther, which
    # starts a feature of its own (their lateral error is 0.005 ft)
    m = _model(2, "model")
    _look(m, _edge(60, 5.0, 0.4) + _edge(68, 5.0, 0.4), 0.0, 0.0)
    for _ in range(2):
        _look(m, _edge(64, 4.5), 0.0, 1.0)
    assert m.features.looks.tolist() == [1, 1, 2]
    assert m.expired_total == 0 and m.features.alive.all()


@pytest.mark.parametrize("occupied", MAPS)
@pytest.mark.parametrize("where", ["behind", "hidden", "too near", "too far"])
def test_a_cell_out_of_view_stays_uncertain(where, occupied):
    m = _model(2, occupied)
    _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, _ = _first_hit(m)
    for _ in range(3):
        if where == "behind":                              # facing away
            fm = _look(m, [], 0.0, 1.0, 180.0)
        elif where == "hidden":                            # an edge 2 ft nearer in its column
            fm = _look(m, _edge(64, 3.0), 0.0, 0.0)
        elif where == "too near":                          # 1.5 ft: below the picture
            fm = _look(m, [], 0.0, 3.5)
        else:                                              # beyond the range the eyes locate
            fm = _look(m, [], 0.0, -8.0)
        assert fm.state_at(*xz) == UNCERTAIN


@pytest.mark.parametrize("occupied", MAPS)
def test_a_look_through_a_blank_face_between_two_edges_does_not_count(occupied):
    # the columns between two edges 4 ft away are bounded by them (a face may
    # stand between): the cell 5 ft away, behind, is not in view
    m = _model(2, occupied)
    _look(m, _edge(64, 5.0), 0.0, 0.0)
    xz, _ = _first_hit(m)
    for _ in range(3):
        fm = _look(m, _edge(50, 3.0) + _edge(78, 3.0), 0.0, 1.0)
    assert fm.state_at(*xz) == UNCERTAIN


def test_expire_uncertain_checked_and_passed_by_rig_drive(tmp_path, monkeypatch):
    from rigtools import drive_config
    with pytest.raises(ValueError, match="expire_uncertain"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, expire_uncertain=-1))
    assert drive_config(monkeypatch, tmp_path, "--expire-uncertain", "2", "--occupied",
                        "looks").expire_uncertain == 2
    assert drive_config(monkeypatch, tmp_path, "--expire-uncertain", "3").expire_uncertain == 3
    assert drive_config(monkeypatch, tmp_path).expire_uncertain == 0


@pytest.mark.parametrize("occupied", MAPS)
def test_the_tiny_room_is_reached_with_expiry(occupied):
    from world.odometry import OdometryNoise
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py);
    # wall_hits "feature" (the default before 2026-12-06 20:30): the once-seen features
    # that expire here are the walls' own hits, which "plan" starts no feature from (11
    # features started against 98, none to expire)
    res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="truth",
                                                             expire_uncertain=2, sight_lines="band",
                                                             occupied=occupied, wall_hits="feature"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.as_json()["expired_uncertain"] == res.expired_uncertain > 0
    # (nothing expires without expire_uncertain, nor the goal's blocker: goal_evidence off)
    assert "expired_uncertain" not in run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(
        goal=GOAL, eyes="truth", max_looks=1, goal_evidence="off")).as_json()
