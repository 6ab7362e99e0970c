"""``rig posit``: a two-terminal run's POSIT.DT as a table and CSV, checked
against the same lines scanned in this process."""

import subprocess
import sys

import pytest

from rig import main as rigmain
from rig import scan as scanmod
from rig.scene import bundled_path
from rig.session import child_env, start_nstar
from diskfmt.layouts import decode_bi


def _two_terminal_run(jh, ds, lines):
    nstar = start_nstar(jh, bundled_path("LAB-L.BI"), bundled_path("LAB-R.BI"), quiet=True,
                        idle_timeout=60)
    try:
        done = subprocess.run([sys.executable, "-m", "estar.main", "--jhdata", str(jh),
                               "--separation", ds, "--virtual-distance", "180", "--debug", "0",
                               "--quiet", "--line", *map(str, lines), "--terminate"],
                              capture_output=True, text=True, env=child_env(), timeout=120)
        nstar.wait(timeout=60)
    finally:
        if nstar.poll() is None:
            nstar.kill()
    assert done.returncode == 0, done.stderr


@pytest.fixture(scope="module")
def posit_025(tmp_path_factory):
    """POSIT.DT of nstar + estar as two processes, lines 40 then 60, ds 0.25."""
    jh = tmp_path_factory.mktemp("jh")
    _two_terminal_run(jh, "0.25", [40, 60])
    return jh


def test_posit_of_a_two_process_run_gives_the_last_lines_points(posit_025, tmp_path, capsys):
    jh = posit_025
    out = tmp_path / "last.csv"
    assert rigmain.main(["posit", str(jh / "POSIT.DT"), "--separation", "0.25",
                         "--csv", str(out)]) == 0
    shown = capsys.readouterr()
    assert "warning" not in shown.err
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    line60 = [p for p in scanmod.scan_pair(left, right, [40, 60], ds="0.25").points
              if p.line == 60]
    assert len(line60) > 20
    # line, LOC1, LOC2 recovered from the REALs alone, every value to the bit
    assert out.read_text() == scanmod.csv_text(line60)
    assert f"{len(line60)} located edges" in shown.out


def test_posit_with_the_wrong_separation_keeps_the_values_and_says_so(posit_025, tmp_path,
                                                                      capsys):
    jh = posit_025
    out = tmp_path / "p.csv"
    assert rigmain.main(["posit", str(jh / "POSIT.DT"), "--separation", "0.5",
                         "--csv", str(out)]) == 0
    err = capsys.readouterr().err
    assert "do not fit --separation 0.5" in err
    rows = out.read_text().splitlines()[1:]
    assert rows and all(r.startswith(",") for r in rows)            # no line, no LOC1/LOC2


def test_posit_of_another_file_says_what_it_is(tmp_path, capsys):
    bad = tmp_path / "POSIT.DT"
    bad.write_bytes(bundled_path("LAB-L.BI").read_bytes())
    assert rigmain.main(["posit", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.strip() == (f"rig: {bad}: not a POSIT.DT: 30,720 bytes; ESTAR writes one "
                           f"(2,560 bytes) in its JHDATA after every line")
