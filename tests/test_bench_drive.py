"""bench/drive.py's task sets: the seeded rooms and the bundled lab under odometry seeds."""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import drive  # noqa: E402


def test_the_lab_is_one_task_under_as_many_odometry_seeds():
    from rig.drive import DEFAULT_LAB_GOAL
    tasks = list(drive.seeded_tasks(argparse.Namespace(lab=True, first=1984, rooms=3)))
    assert [t[0] for t in tasks] == [1984, 1985, 1986]          # the noise seeds
    assert {t[1].name for t in tasks} == {"bundled lab"}
    assert all(t[3] == DEFAULT_LAB_GOAL for t in tasks)
    assert all((t[2].x, t[2].z, t[2].heading_deg) == (0.0, 0.0, 0.0) for t in tasks)


def test_the_rooms_are_the_generated_ones_with_their_random_goals():
    tasks = list(drive.seeded_tasks(argparse.Namespace(lab=False, first=7, rooms=2)))
    assert [t[0] for t in tasks] == [7, 8]
    assert all(t[1].name != "bundled lab" for t in tasks)
    assert all(t[3] is None or len(t[3]) == 2 for t in tasks)


def test_seeds_by_list_or_the_rooms_an_earlier_run_did_not_reach(tmp_path, capsys):
    import json

    import pytest
    assert drive.parse_seeds("87, 114,401-403,114") == [87, 114, 401, 402, 403]
    for bad in ("7-5", "x", "3-", "-2", ""):
        with pytest.raises(ValueError, match="--seeds"):
            drive.parse_seeds(bad)
    earlier = tmp_path / "earlier.json"
    earlier.write_text(json.dumps({"summary": {}, "rooms": [
        {"room": 3, "reached": True}, {"room": 5, "reached": False},
        {"room": 9, "reached": False}]}))
    assert drive.unreached_seeds(str(earlier)) == [5, 9]
    tasks = list(drive.seeded_tasks(argparse.Namespace(lab=False, first=1, rooms=1,
                                                       seeds=None, unreached_in=str(earlier))))
    assert [t[0] for t in tasks] == [5, 9]
    tasks = list(drive.seeded_tasks(argparse.Namespace(lab=True, first=1, rooms=1,
                                                       seeds="1984,1986", unreached_in=None)))
    assert [t[0] for t in tasks] == [1984, 1986]
    (tmp_path / "not.json").write_text("[1, 2]")
    for argv in (["--seeds", "7-5"], ["--unreached-in", str(tmp_path / "not.json")],
                 ["--unreached-in", str(tmp_path / "missing.json")],
                 ["--seeds", "1", "--unreached-in", str(earlier)]):
        with pytest.raises(SystemExit) as e:
            drive.main(argv)
        assert e.value.code == 2
    err = capsys.readouterr().err
    assert "'7-5' is not a seed" in err and "not.json: not a bench/drive.py --out file" in err
    assert "missing.json" in err and "give one" in err
