"""Whole-picture scans: the file link and the direct link give the same POSIT.DT
line after line; points, covariance (A-20), CSV and PLY."""

import csv
import io
import subprocess
import sys

import numpy as np
import pytest

from diskfmt.layouts import decode_bi
from rig import scan as scanmod
from rig.scene import bundled_path, bundled_range
from rig.session import file_link_eclipse, child_env
from rig.truth import accuracy_table


def bundled_pair():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


@pytest.mark.processes
def test_file_link_and_direct_link_give_identical_posit_for_lines_8_to_112(tmp_path):
    left, right = bundled_pair()
    direct = scanmod.scan_pair(left, right)
    with file_link_eclipse(tmp_path / "jhdata", bundled_path("LAB-L.BI"),
                           bundled_path("LAB-R.BI")) as ecl:
        via_files = scanmod.run_lines(ecl, scanmod.DEFAULT_LINES)
    assert len(direct.results) == len(via_files.results) == 105
    for d, f in zip(direct.results, via_files.results):
        assert d.posit == f.posit, f"line {d.iyloc}"
    assert via_files.requests == direct.requests > 1000
    assert (tmp_path / "jhdata" / "POSIT.DT").read_bytes() == direct.last_posit


def test_points_use_the_first_entry_with_disparity_above_one():
    left, right = bundled_pair()
    res = scanmod.scan_pair(left, right, [60])
    r = res.results[0]
    assert res.points
    for p in res.points:
        entries = r.matches[p.edge]
        first = next(e for e in entries if e[2] - e[3] > 1)
        assert (p.loc1, p.loc2) == (first[2], first[3])
        assert p.dp == pytest.approx(0.75 * 180 / p.disparity, rel=1e-6)
        # dx is measured from column 60 (QUIRKS E6): dx = (LOC1-60) * dp / dv
        assert p.dx == pytest.approx((p.loc1 - 60) * p.dp / 180, rel=1e-5, abs=1e-6)


def test_points_carry_the_entry_their_range_came_from_at_separation_025():
    # At ds = 0.25 (DS*DV = 45) LCSL passes over any entry giving a range of
    # 1.0 or less, so "the first entry with disparity > 1" is often not the one
    # used.  Each point's disparity must give its own range: dp = 45 / disparity.
    left, right = bundled_pair()
    res = scanmod.scan_pair(left, right, ds="0.25")
    assert len(res.points) > 2000
    for p in res.points:
        assert p.dp == pytest.approx(45 / p.disparity, rel=1e-5), (p.line, p.edge)
        assert p.dx == pytest.approx((p.loc1 - 60) * p.dp / 180, rel=1e-5, abs=1e-6)
    p = next(p for p in res.points if p.line == 20 and p.edge == 58)
    assert (p.loc1, p.loc2, p.disparity, p.dp) == (128, 110, 18, 2.5)
    rows = list(csv.DictReader(io.StringIO(scanmod.csv_text(res.points))))
    row = next(r for r in rows if r["line"] == "20" and r["edge"] == "58")
    assert (row["loc1"], row["loc2"], row["disparity"], float(row["dp"])) == ("128", "110",
                                                                               "18", 2.5)
    passed_over = 0
    for r in res.results:
        for edge, pos in r.positions.items():
            if pos is not None:
                first = next(e for e in r.matches[edge] if e[2] - e[3] > 1)
                passed_over += first != r.used[edge]
    assert passed_over > 100            # the case matters on this pair (162 of 2278)


def test_covariance_is_equation_a20():
    p = scanmod.Point(60, 3, 14, 6, 16.875, -4.3125, 0.0, 2.411, 0.670, 0.054)
    c = p.covariance()
    assert np.allclose(c, np.diag([(2.411 / 2) ** 2, (0.670 / 2) ** 2, (0.054 / 2) ** 2]))
    assert c[0, 1] == c[1, 2] == c[0, 2] == 0


def _points():
    return [scanmod.Point(60, 3, 14, 6, 16.875, -4.3125, 0.0, 2.411, 0.670, 0.054),
            scanmod.Point(61, 53, 16, 8, 16.875, -4.125, 0.09375, 2.411, 0.643, 0.054)]


def test_csv_reads_back_with_count_and_values():
    rows = list(csv.DictReader(io.StringIO(scanmod.csv_text(_points()))))
    assert len(rows) == 2
    assert rows[0]["line"] == "60" and rows[0]["edge"] == "3" and rows[0]["disparity"] == "8"
    assert float(rows[0]["dp"]) == 16.875 and float(rows[1]["dy"]) == 0.09375
    assert float(rows[0]["var_p"]) == pytest.approx((2.411 / 2) ** 2)


def test_ply_reads_back_with_count_and_axes():
    text = scanmod.ply_text(_points())
    assert "element vertex 2" in text
    v = scanmod.read_ply_points(text)
    assert v.shape == (2, 11)
    # x = dx (right), y = dy (down), z = dp (range)
    assert v[0, :3] == pytest.approx([-4.3125, 0.0, 16.875])
    assert v[1, :3] == pytest.approx([-4.125, 0.09375, 16.875])
    assert v[:, 9].tolist() == [60, 61] and v[:, 10].tolist() == [3, 53]


def test_accuracy_table_is_computed_from_the_truth_file():
    left, right = bundled_pair()
    res = scanmod.scan_pair(left, right, range(40, 81, 10))
    edges = [(p.line, p.loc1, p.loc2, p.dp, p.ep) for p in res.points]
    rows = accuracy_table(edges, bands=((0, 100),), truth=bundled_range())
    assert rows[0].count == len(edges)
    # Independently: an edge is within its bound when the true range at its
    # column (min over the column and its neighbours) is inside dp +- ep.
    truth = bundled_range()
    inside = 0
    for iy, loc1, loc2, dp, ep in edges:
        z = truth[iy, max(0, loc1 - 2):loc1 + 1].min()
        inside += abs(dp - z) <= ep
    assert rows[0].share_within_bound == pytest.approx(inside / len(edges))


@pytest.mark.processes
def test_rig_scan_command_writes_csv_and_ply(tmp_path):
    csv_path, ply_path = tmp_path / "s.csv", tmp_path / "s.ply"
    done = subprocess.run([sys.executable, "-m", "rig.main", "scan", "--lines", "50", "60",
                           "--csv", str(csv_path), "--ply", str(ply_path), "--quiet"],
                          capture_output=True, text=True, env=child_env(), timeout=300)
    assert done.returncode == 0, done.stderr
    n = len(list(csv.DictReader(csv_path.open())))
    assert n > 0 and f"{n} located edges on 11 lines" in done.stdout
    assert scanmod.read_ply_points(ply_path.read_text()).shape[0] == n
    assert "median |error|" in done.stdout


@pytest.mark.processes
def test_rig_demo_runs_two_processes_and_makes_pictures(tmp_path):
    done = subprocess.run([sys.executable, "-m", "rig.main", "demo", "--lines", "60",
                           "--jhdata", str(tmp_path / "jh"), "--out", str(tmp_path / "out")],
                          capture_output=True, text=True, env=child_env(), timeout=300)
    assert done.returncode == 0, done.stderr
    assert "Feature 3-D positions." in done.stdout
    assert "matches an in-process replay" in done.stdout
    for name in ("monitor.png", "line-60.png", "topdown.png"):
        assert (tmp_path / "out" / name).stat().st_size > 1000
    assert (tmp_path / "jh" / "POSIT.DT").stat().st_size == 2560


@pytest.mark.processes
def test_rig_scan_takes_any_set_of_lines_and_refuses_lines_outside_the_picture():
    done = subprocess.run([sys.executable, "-m", "rig.main", "scan", "--line", "60", "40",
                           "--quiet"], capture_output=True, text=True, env=child_env(),
                          timeout=300)
    assert done.returncode == 0 and "on 2 lines" in done.stdout
    bad = subprocess.run([sys.executable, "-m", "rig.main", "scan", "--line", "130"],
                         capture_output=True, text=True, env=child_env(), timeout=300)
    assert bad.returncode == 1
    assert bad.stderr.strip() == "rig: lines must lie within 0..119 (got [130])"
