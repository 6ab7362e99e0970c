"""bench/drive_width_bound.py: the planning radius it swaps in, and its run."""

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))

import drive_width_bound  # noqa: E402
from vehicle.profile import DEFAULT  # noqa: E402


def test_the_bound_plans_by_half_the_width_plus_the_margin_and_restores_the_disc():
    disc = DEFAULT.planning_radius_ft
    assert disc == pytest.approx(0.5 * (0.8 ** 2 + 1.0 ** 2) ** 0.5 + 0.15)   # 0.790 ft
    with drive_width_bound.planned_by_width():
        assert DEFAULT.planning_radius_ft == pytest.approx(0.8 / 2 + 0.15)      # 0.55 ft
    assert DEFAULT.planning_radius_ft == disc
    with pytest.raises(RuntimeError):
        with drive_width_bound.planned_by_width():
            raise RuntimeError("a run that fails")
    assert DEFAULT.planning_radius_ft == disc        # restored on the way out of an error too


def test_the_script_drives_each_room_both_ways_and_writes_its_summary(tmp_path, capsys):
    out = tmp_path / "bound.json"
    assert drive_width_bound.main(["--rooms", "1", "--first", "22", "--eyes", "truth",
                                   "--out", str(out)]) == 0
    got = json.loads(out.read_text())
    (row,) = got["rooms"]
    # room 22 is one the default reaches with oracle edges (docs/planner.md)
    assert row["room"] == 22 and row["default_reached"] is True
    assert got["summary"]["default_success_rate"] == 1.0
    assert got["summary"]["rooms"] == 1 and not out.with_name("bound.json.tmp").exists()
    assert "by width" in capsys.readouterr().out
