"""bench/drive_options.py: its list holds only options that are not the default, its rows, its run."""

import argparse
import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))

import drive_options  # noqa: E402
from rig.drive import add_loop_options  # noqa: E402


def _parse(flags):
    ap = argparse.ArgumentParser()
    add_loop_options(ap)
    return vars(ap.parse_args(flags))


def test_every_listed_option_is_a_valid_flag_that_changes_a_default():
    defaults = _parse([])
    for flags in drive_options.OPTIONS:
        changed = {k for k, v in _parse(flags.split()).items() if v != defaults[k]}
        # a default flipped to a listed value would make its row a second default run
        assert changed, f"{flags!r} is the default"
    assert len(set(drive_options.OPTIONS)) == len(drive_options.OPTIONS)


def test_run_names_are_distinct_file_names():
    names = {drive_options.run_name(o) for o in drive_options.OPTIONS}
    assert len(names) == len(drive_options.OPTIONS)
    assert drive_options.run_name("") == "defaults"
    assert drive_options.run_name("--reverse on") == "reverse_on"


def _data(reached, collided=()):
    rooms = [{"room": n, "reached": n in reached, "collisions": int(n in collided)}
             for n in range(1, 7)]
    return {"rooms": rooms, "summary": {
        "rooms": 6, "success_rate": len(reached) / 6, "success_true_rate": 1 / 6,
        "collisions": len(collided), "ratio_max": 1.2, "looks_per_metre": 9.0,
        "map_losses_total": {"true_obstacle_mapped_free": 40}}}


def test_a_row_names_the_rooms_won_and_lost_against_the_defaults():
    base = _data({1, 2, 3})
    row = drive_options.row_of("--reverse on", _data({2, 3, 5, 6}, collided={4}), base)
    assert row["won"] == [5, 6] and row["lost"] == [1]
    assert row["collision_rooms"] == [4] and row["box_cells_free"] == 40
    assert row["reached"] == [2, 3, 5, 6]
    assert "won" not in drive_options.row_of("", base, None)


def test_a_bad_count_is_refused(capsys):
    with pytest.raises(SystemExit) as e:
        drive_options.main(["--rooms", "0"])
    assert e.value.code == 2 and "--rooms" in capsys.readouterr().err


@pytest.mark.processes
def test_the_script_runs_the_defaults_and_an_option_and_keeps_each_run(tmp_path, capsys):
    out = tmp_path / "table.json"
    argv = ["--rooms", "1", "--first", "22", "--eyes", "truth", "--option", "--goal-region point",
            "--dir", str(tmp_path / "runs"), "--out", str(out)]
    assert drive_options.main(argv) == 0
    rows = json.loads(out.read_text())["rows"]
    assert [r["option"] for r in rows] == ["(defaults)", "--goal-region point"]
    # room 22 is one the defaults reach with oracle edges (docs/planner.md)
    assert rows[0]["reached"] == [22] and rows[0]["collisions"] == 0
    kept = tmp_path / "runs" / "truth_22_22"
    assert sorted(p.name for p in kept.glob("*.json")) == ["defaults.json", "goal_region_point.json"]
    assert not list(kept.glob("*.part"))
    # a second call reads the kept runs instead of driving again
    (kept / "defaults.log").unlink()
    assert drive_options.main(argv) == 0
    assert not (kept / "defaults.log").exists()
    assert "goal-region point" in capsys.readouterr().out


@pytest.mark.processes
def test_a_run_that_fails_is_one_clear_error_naming_its_log(tmp_path, capsys):
    argv = ["--rooms", "1", "--first", "22", "--eyes", "truth", "--option", "--no-such-flag 3",
            "--dir", str(tmp_path / "runs")]
    assert drive_options.main(argv) == 1
    err = capsys.readouterr().err
    assert "--no-such-flag" in err and "no_such_flag_3.log" in err
    assert not (tmp_path / "runs" / "truth_22_22" / "no_such_flag_3.json").exists()
