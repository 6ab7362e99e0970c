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
