"""``--match 1985|improved`` in ESTAR and ``rig scan``: 1985 stays byte for byte,
the improved mode writes only the edges it vouches for, streams line by line
with the same verdicts as the batch API, and is scored against the bundled
scene's true range."""

import csv
import io

import numpy as np
import pytest

from diskfmt.dgreal import Real
from diskfmt.layouts import decode_bi, decode_posit
from estar.lcsl import locate
from estar.program import in_process_rig
from matching import Constraints, Params, match_lines
from matching.mode import ImprovedMatcher, _reach
from rig import main as rigmain
from rig import scan as scanmod
from rig.scene import bundled_path, bundled_range
from rig.session import file_link_eclipse
from rig.truth import true_range_at


def bundled_pair():
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def eclipse(matcher=None):
    return in_process_rig(*bundled_pair(), matcher=matcher)


def test_match_1985_csv_is_byte_identical_to_no_flag(tmp_path):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert rigmain.main(["scan", "--quiet", "--lines", "50", "70", "--csv", str(a)]) == 0
    assert rigmain.main(["scan", "--quiet", "--lines", "50", "70", "--match", "1985",
                         "--csv", str(b)]) == 0
    assert a.read_bytes() == b.read_bytes()
    assert a.read_text().splitlines()[0].split(",") == scanmod.CSV_COLUMNS


def test_improved_csv_keeps_the_columns_adds_confidence_and_is_more_accurate(tmp_path):
    out = tmp_path / "i.csv"
    assert rigmain.main(["scan", "--quiet", "--match", "improved", "--csv", str(out)]) == 0
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert list(rows[0].keys()) == scanmod.CSV_COLUMNS + ["confidence"]
    faithful = scanmod.scan_pair(*bundled_pair()).points
    assert 0.5 * len(faithful) < len(rows) < len(faithful)
    truth = bundled_range()

    def bad2(items):
        err = [abs(d - 135 / true_range_at(truth, y, x)) for y, x, d in items]
        return np.mean(np.array(err) > 2)
    improved = [(int(r["line"]), float(r["loc1"]), float(r["disparity"])) for r in rows]
    assert all(d > 1 for _, _, d in improved)
    assert all(0 <= float(r["confidence"]) <= 1 for r in rows)
    assert bad2(improved) < 0.05 < 0.25 < bad2([(p.line, p.loc1, p.disparity) for p in faithful])


def test_improved_posit_has_only_the_vouched_edges():
    ecl = eclipse(ImprovedMatcher())
    r = ecl.lcln(60)
    pos = decode_posit(r.posit).pos
    verdicts = {v.edge: v for v in r.verdicts}
    assert {e for e in verdicts} == {e for k in range(1, len(r.features1) + 1)
                                     for e in (k, k + 50)}
    assert any(not v.matched for v in verdicts.values())
    for e, v in verdicts.items():
        base = (e - 1) * 6
        if v.matched:
            want = locate(int(v.loc1), int(v.loc2), 60, Real.const("0.75"), Real.const("180"))
            assert pos[base:base + 6] == list(want)
        else:
            assert float(pos[base]) == -1.0


def test_streaming_verdicts_equal_the_batch_api():
    """ESTAR line by line (with every constraint fetching lines IY-26..IY+26:
    three confirm passes look at IY-7..IY+7 each, then two re-admission
    passes at IY-2..IY+2 each, the neighbour constraint at IY-1, IY+1 of those)
    gives the verdicts match_lines gives on a scan of those lines."""
    lines = range(40, 50)
    five = Constraints.parse("all")
    assert five.readmit and five.confirm
    reach = _reach(five, Params())
    assert reach == 26
    streamed = scanmod.run_lines(eclipse(ImprovedMatcher(five)), lines)
    assert any(v.reason == "confirmed" for r in streamed.results for v in r.verdicts)
    faithful = scanmod.run_lines(eclipse(), range(40 - reach, 50 + reach))
    batch = match_lines(faithful.results, five)
    for r in streamed.results:
        assert r.verdicts == batch[r.iyloc], r.iyloc


def test_streaming_rematch_equals_the_batch_api():
    """The same with the inter-scanline pass on (Params.rematch_bonus): lines
    IY-7..IY+7 are fetched."""
    p = Params(rematch_bonus=64.0)
    lines = range(44, 48)
    five = Constraints.parse("all")
    streamed = scanmod.run_lines(eclipse(ImprovedMatcher(five, params=p)), lines)
    faithful = scanmod.run_lines(eclipse(), range(37, 55))
    batch = match_lines(faithful.results, five, p)
    for r in streamed.results:
        assert r.verdicts == batch[r.iyloc], r.iyloc


def test_improved_over_the_file_link_equals_the_direct_link(tmp_path):
    lines = [30, 31, 60]
    direct = scanmod.run_lines(eclipse(ImprovedMatcher()), lines)
    with file_link_eclipse(tmp_path / "jhdata", bundled_path("LAB-L.BI"),
                           bundled_path("LAB-R.BI"), matcher=ImprovedMatcher()) as ecl:
        files = scanmod.run_lines(ecl, lines)
    assert [r.posit for r in files.results] == [r.posit for r in direct.results]
    assert (tmp_path / "jhdata" / "POSIT.DT").read_bytes() == direct.last_posit


def test_subpixel_scan_gives_fractional_locations(tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert rigmain.main(["scan", "--quiet", "--match", "improved", "--constraints", "all",
                         "--line", "60", "--csv", str(out)]) == 0
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert rows and any(float(r["loc1"]) != int(float(r["loc1"])) for r in rows)


def test_subpixel_without_vd_is_one_clear_error(tmp_path, capsys):
    import shutil
    for name in ("LAB-L.BI", "LAB-R.BI"):
        shutil.copy(bundled_path(name), tmp_path / name)
    with pytest.raises(SystemExit, match="LAB-L.VD"):
        rigmain.main(["scan", "--quiet", "--left", str(tmp_path / "LAB-L.BI"), "--right",
                      str(tmp_path / "LAB-R.BI"), "--match", "improved", "--constraints",
                      "order,subpixel", "--line", "60"])


def test_estar_refuses_subpixel_and_unknown_constraints(tmp_path, capsys):
    from estar import main as estar_main
    for match, cons in (("improved", "subpixel"), ("improved", "order,magic"),
                        ("1985", "order")):
        rc = estar_main.main(["--jhdata", str(tmp_path), "--separation", "0.75",
                              "--virtual-distance", "180", "--debug", "0", "--line", "60",
                              "--match", match, "--constraints", cons, "--quiet"])
        assert rc == 1
        err = capsys.readouterr().err
        assert err.startswith("estar: ") and err.count("\n") == 1


def test_debug_4_lists_the_verdicts_after_the_match_lists():
    from diskfmt.listing import Listing
    buf = io.StringIO()
    ecl = in_process_rig(*bundled_pair(), debug=4, listing=Listing(buf),
                         matcher=ImprovedMatcher())
    r = ecl.lcln(60)
    text = buf.getvalue()
    assert "Improved matcher (not 1985), constraints: order,lr,neighbours,region" in text
    head = text.index("Improved matcher")
    assert "INDX" in text[:head]                   # 1985's match lists (PMAL) come first
    lines = text[head:].splitlines()[2:]
    for v in r.verdicts:
        row = next(x for x in lines if x[:6].strip() == str(v.edge))
        assert ("no match" in row) == (not v.matched)


def test_vouched_points_keep_the_confident_matches_which_are_the_more_accurate():
    """``vouched_points`` (``rig drive --min-confidence``) on the bundled lab pair: at 0
    it keeps every located point; at 0.5 exactly those whose verdict's confidence is
    0.5 or more, and those are right more often, by the bundled true range, than the
    ones it leaves out."""
    from matching.mode import vouched_points
    scan = scanmod.scan_pair(*bundled_pair(), matcher=ImprovedMatcher())
    assert vouched_points(scan.results, scan.points, 0.0) == scan.points
    confidence = {(r.iyloc, v.edge): v.confidence for r in scan.results
                  for v in (r.verdicts or []) if v.matched}
    kept = vouched_points(scan.results, scan.points, 0.5)
    assert kept == [p for p in scan.points if confidence[(p.line, p.edge)] >= 0.5]
    left_out = [p for p in scan.points if p not in kept]
    assert len(left_out) > 20 and len(kept) > 20
    truth = bundled_range()

    def bad2(points):
        return np.mean([abs(p.disparity - 135 / true_range_at(truth, p.line, p.loc1)) > 2
                        for p in points])
    assert bad2(kept) < bad2(left_out)
