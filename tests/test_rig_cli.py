"""``rig``'s front door: bad options are one line before any work, warnings on
pairs that cannot range, the summary, the pictures it can write, --help and
--version."""

import subprocess
import sys

import cv2
import numpy as np
import pytest

from diskfmt.layouts import encode_bi
from rig import main as rigmain
from rig import scan as scanmod
from rig.scene import bundled_path
from rig.session import child_env, start_nstar


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if a scan starts: errors must come before the work."""
    def refuse(*a, **k):
        raise AssertionError("the scan started before the options were checked")
    monkeypatch.setattr(scanmod, "scan_pair", refuse)
    monkeypatch.setattr(scanmod, "run_lines", refuse)


def _one_line_error(capsys, argv):
    code = rigmain.main(argv)
    err = capsys.readouterr().err
    assert code == 1
    assert err.count("\n") == 1 and err.startswith("rig: "), err
    return err.strip()


@pytest.mark.parametrize("argv, says", [
    (["--separation", "abc"], "rig: --separation abc: not a number"),
    (["--separation", "0"], "rig: --separation 0: must be a number above 0"),
    (["--separation", "-0.5"], "rig: --separation -0.5: must be a number above 0"),
    (["--separation", "nan"], "rig: --separation nan: must be a number above 0"),
    (["--virtual-distance", "0"], "rig: --virtual-distance 0: must be a number above 0"),
    (["--lines", "60", "50"], "rig: --lines 60 50: no lines"),
    (["--lines", "0", "120"], "rig: lines must lie within 0..119 (got [120])"),
    (["--line", "-1", "60"], "rig: lines must lie within 0..119 (got [-1])"),
    (["--max-range", "0"], "rig: --max-range 0: must be a number above 0"),
])
def test_bad_values_are_one_line_before_any_work(capsys, no_work, argv, says):
    assert _one_line_error(capsys, ["scan", "--quiet", *argv]).startswith(says)


def test_bad_truth_files_are_one_line(capsys, no_work, tmp_path):
    missing = tmp_path / "none.npy"
    assert _one_line_error(capsys, ["scan", "--truth", str(missing)]) == \
        f"rig: --truth {missing}: no such file"
    small = tmp_path / "small.npy"
    np.save(small, np.zeros((10, 10)))
    assert "shape (10, 10), expected (120, 128)" in _one_line_error(
        capsys, ["scan", "--truth", str(small)])
    text = tmp_path / "t.npy"
    text.write_text("not numpy")
    assert "not a NumPy .npy file" in _one_line_error(capsys, ["scan", "--truth", str(text)])
    assert "is a directory" in _one_line_error(capsys, ["scan", "--truth", str(tmp_path)])


@pytest.mark.parametrize("option", ["--csv", "--ply", "--picture"])
def test_bad_output_paths_are_one_line_and_nothing_is_written(capsys, no_work, tmp_path,
                                                              option):
    assert f"rig: {option} {tmp_path}: is a directory" in _one_line_error(
        capsys, ["scan", option, str(tmp_path)])
    nowhere = tmp_path / "no" / "x.png"
    assert f"directory {nowhere.parent} does not exist" in _one_line_error(
        capsys, ["scan", option, str(nowhere)])
    assert list(tmp_path.iterdir()) == []


def test_output_directories_that_are_files_are_one_line(capsys, no_work, tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    assert _one_line_error(capsys, ["scan", "--line-pictures", str(f)]) == \
        f"rig: --line-pictures {f}: is a file, not a directory"
    assert _one_line_error(capsys, ["scan", "--link", "file", "--jhdata", str(f)]) == \
        f"rig: --jhdata {f}: is a file, not a directory"
    assert _one_line_error(capsys, ["demo", "--out", str(f)]) == \
        f"rig: --out {f}: is a file, not a directory"
    assert _one_line_error(capsys, ["demo", "--lines", "200"]) == \
        "rig: lines must lie within 0..119 (got [200])"


def test_picture_writes_what_its_name_says_or_refuses(capsys, tmp_path):
    gif = tmp_path / "map.gif"
    assert "can write .png or .jpg" in _one_line_error(
        capsys, ["scan", "--quiet", "--line", "60", "--picture", str(gif)])
    assert not gif.exists()
    jpg = tmp_path / "map.jpg"
    assert rigmain.main(["scan", "--quiet", "--line", "60", "--picture", str(jpg)]) == 0
    assert jpg.read_bytes()[:3] == b"\xff\xd8\xff"                     # JPEG, not PNG
    assert cv2.imread(str(jpg)).shape == (1010, 740, 3)


def test_wrong_format_pictures_say_what_they_are_and_how_to_make_a_bi(capsys, no_work,
                                                                      tmp_path):
    jpg = tmp_path / "left.jpg"
    cv2.imwrite(str(jpg), np.zeros((240, 320, 3), np.uint8))
    size = jpg.stat().st_size
    err = _one_line_error(capsys, ["scan", "--left", str(jpg), "--right",
                                   str(bundled_path("LAB-R.BI"))])
    assert err == (f"rig: --left {jpg}: not a .BI picture: {size:,} bytes, a JPEG picture; "
                   f"make a pair with `pre pair LEFT.jpg RIGHT.jpg -o NAME` "
                   f"(NAME-L.BI, NAME-R.BI)")
    err = _one_line_error(capsys, ["scan", "--left", str(bundled_path("LAB-L.BI")), "--right",
                                   str(bundled_path("LAB-R.VD"))])
    assert "32,768 bytes, the size of a 256x240 .VD picture" in err
    assert "pre shrink X.VD -o X.BI" in err


def _bi(path, picture):
    path.write_bytes(encode_bi(picture))
    return str(path)


def _pair():
    from diskfmt.layouts import decode_bi
    return (decode_bi(bundled_path("LAB-L.BI").read_bytes()),
            decode_bi(bundled_path("LAB-R.BI").read_bytes()))


def test_identical_pictures_are_warned_about(capsys, tmp_path):
    left, _ = _pair()
    a, b = _bi(tmp_path / "A.BI", left), _bi(tmp_path / "B.BI", left)
    assert rigmain.main(["scan", "--quiet", "--line", "60", "--left", a, "--right", b]) == 0
    out = capsys.readouterr()
    assert "rig: warning: the left and right pictures are identical" in out.err
    # MASL still pairs each edge with a look-alike further left: all wrong
    assert "located edges on 1 lines" in out.out


def test_a_swapped_pair_is_warned_about_and_the_right_way_round_is_not(capsys, tmp_path):
    left, right = _pair()
    lp, rp = _bi(tmp_path / "L.BI", left), _bi(tmp_path / "R.BI", right)
    assert rigmain.main(["scan", "--quiet", "--line", "60", "--left", rp, "--right", lp]) == 0
    out = capsys.readouterr()
    assert "rig: warning: the pair looks swapped" in out.err
    assert "impossible disparities: 100% of 1 lines" in out.out
    assert rigmain.main(["scan", "--quiet", "--line", "60", "--left", lp, "--right", rp]) == 0
    out = capsys.readouterr()
    assert "warning" not in out.err
    assert "impossible disparities: 0% of 1 lines" in out.out


def test_own_pair_summary_points_at_the_outputs_and_line_pictures_are_written(capsys,
                                                                               tmp_path):
    left, right = _pair()
    lp, rp = _bi(tmp_path / "L.BI", left), _bi(tmp_path / "R.BI", right)
    argv = ["scan", "--quiet", "--line", "40", "60", "--left", lp, "--right", rp,
            "--separation", "0.23", "--unit", "m"]
    assert rigmain.main(argv) == 0
    out = capsys.readouterr().out
    pts = scanmod.scan_pair(left, right, [40, 60], ds="0.23").points
    dp = sorted(p.dp for p in pts)
    assert f"{len(pts)} located edges on 2 lines" in out
    assert f"range (m): min {dp[0]:.3g}, median {np.median(dp):.3g}, max {dp[-1]:.3g}" in out
    assert "--csv FILE, --ply FILE" in out and "--picture" in out
    assert "Accuracy" not in out                     # no truth for one's own pair
    assert rigmain.main(argv + ["--line-pictures", str(tmp_path / "lines")]) == 0
    assert sorted(p.name for p in (tmp_path / "lines").iterdir()) == ["line-40.png",
                                                                       "line-60.png"]
    assert cv2.imread(str(tmp_path / "lines" / "line-60.png")).shape == (1206, 1128, 3)


def test_help_gives_defaults_units_and_examples_and_version_answers(capsys):
    help_text = rigmain.build_parser()._subparsers._group_actions[0].choices["scan"].format_help()
    for words in ("default: 0.75", "default: 180", "focal length in pixels",
                  "examples:", "rig scan --left", "rectified", "default: 8 112"):
        assert words in help_text, words
    import estar.main
    import nstar.main
    import pre.main
    for parser, prog in ((rigmain.build_parser(), "rig"), (pre.main.build_parser(), "pre"),
                         (estar.main.build_parser(), "estar"), (nstar.main.build_parser(), "nstar")):
        with pytest.raises(SystemExit) as stop:
            parser.parse_args(["--version"])
        assert stop.value.code == 0
        assert capsys.readouterr().out.startswith(prog + " "), prog


def test_estar_warns_when_nstar_serves_blank_pictures(tmp_path):
    # nstar started with no pictures and nobody at its prompts keeps the blank
    # frame store; ESTAR finds no feature in any slice and says why.
    jh = tmp_path / "jh"
    jh.mkdir()
    nstar = start_nstar(jh, None, None, quiet=True, idle_timeout=60,
                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        done = subprocess.run([sys.executable, "-m", "estar.main", "--jhdata", str(jh),
                               "--separation", "0.75", "--virtual-distance", "180", "--debug",
                               "0", "--quiet", "--line", "40", "60", "--terminate"],
                              capture_output=True, text=True, env=child_env(), timeout=120)
        nstar.wait(timeout=60)
    finally:
        if nstar.poll() is None:
            nstar.kill()
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("its pictures look blank") == 1
