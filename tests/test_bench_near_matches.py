"""bench/near_matches.py: the located points in front of the truth, by range band."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import near_matches  # noqa: E402
from rig.scan import Point  # noqa: E402


def _pt(dp, ep=0.1):
    return Point(50, 1, 40, 30, dp, 0.0, 0.0, ep, 0.01, 0.01)


def test_a_point_is_false_when_it_lies_its_bound_or_half_a_foot_in_front_of_the_truth():
    points = [_pt(2.6), _pt(2.7), _pt(2.9, ep=0.8), _pt(3.2), _pt(5.0), _pt(13.0), _pt(2.0)]
    truth = [3.2,       2.9,       3.6,              3.3,       4.0,       20.0,      9.0]
    # 2.6 against 3.2: 0.6 ft in front, false; 2.7 / 2.9: 0.2, not; 2.9 with ep 0.8 against
    # 3.6: 0.7 ft, within its bound, not; 3.2 / 3.3 not; 5.0 behind the truth, not; 13 and
    # 2.0 ft lie outside the bands and are not counted
    n, bad = near_matches.false_by_range(points, truth, bands=(2.5, 3.0, 3.5, 12.0))
    assert n.tolist() == [3, 1, 1]
    assert bad.tolist() == [1, 0, 0]


def test_a_bad_count_is_refused(capsys):
    import pytest
    with pytest.raises(SystemExit):
        near_matches.main(["--rooms", "-1"])
    assert "--rooms" in capsys.readouterr().err
