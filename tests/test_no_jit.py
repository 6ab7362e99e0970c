"""``RIG_NO_JIT=1``: the rig runs end to end as plain Python (no numba), and
gives the same bytes as the compiled kernels."""

import json
import os
import subprocess
import sys

import numpy as np

from diskfmt import jit
from rig import scan as scanmod
from rig.scene import bundled_path
from rig.session import child_env
from diskfmt.layouts import decode_bi

LINES = (20, 60, 100)


def _plain_env():
    env = child_env()
    env["RIG_NO_JIT"] = "1"
    return env


def test_rig_scan_over_the_file_link_as_plain_python_equals_the_compiled_scan(tmp_path):
    # Both programs (rig's ESTAR and the nstar process it starts) inherit
    # RIG_NO_JIT; ds 0.25 so that LCSL's walk past short ranges is exercised.
    out = tmp_path / "plain.csv"
    run = subprocess.run([sys.executable, "-m", "rig.main", "scan", "--link", "file",
                          "--jhdata", str(tmp_path / "jhdata"), "--line", *map(str, LINES),
                          "--separation", "0.25", "--csv", str(out), "--quiet"],
                         env=_plain_env(), capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    left = decode_bi(bundled_path("LAB-L.BI").read_bytes())
    right = decode_bi(bundled_path("LAB-R.BI").read_bytes())
    compiled = scanmod.scan_pair(left, right, LINES, ds="0.25")
    assert len(compiled.points) > 50
    assert out.read_text() == scanmod.csv_text(compiled.points)
    posit = (tmp_path / "jhdata" / "POSIT.DT").read_bytes()
    assert posit == compiled.last_posit


_PLAIN_EXQVFL = r"""
import json, sys
import numpy as np
from diskfmt import jit
assert not jit.ENABLED, "RIG_NO_JIT=1 must turn compilation off"
from nstar.exqvfl import exqvfl_kernel
rows = json.load(sys.stdin)
out = []
for row, thr in rows:
    f = np.full((4, 50), 7, np.int32)
    n, too_many = exqvfl_kernel(np.asarray(row, np.int64), len(row), thr, f)
    out.append([int(n), bool(too_many), f.tolist()])
json.dump(out, sys.stdout)
"""


def _random_rows():
    rng = np.random.default_rng(1985)
    rows = []
    for trial in range(400):
        n = int(rng.integers(1, 129))
        kind = trial % 4
        if kind == 0:
            row = rng.integers(0, 16, n)
        elif kind == 1:                       # smooth-ish rows with gentle slopes
            row = np.clip(np.cumsum(rng.integers(-1, 2, n)) + 8, 0, 15)
        elif kind == 2:                       # flat runs with steps
            row = np.repeat(rng.integers(0, 16, n // 4 + 1), 4)[:n]
        else:
            row = np.clip(np.round(8 + 7 * np.sin(np.arange(n) / rng.uniform(1, 9))), 0, 15)
        for thr in (1, 2):
            rows.append([[int(v) for v in row], thr])
    return rows


def test_exqvfl_kernel_equals_the_same_code_run_as_plain_python():
    # The plain run is a separate interpreter with RIG_NO_JIT=1, so every
    # helper the kernel calls (ISGN, the REAL mean) is plain Python too.
    rows = _random_rows()
    run = subprocess.run([sys.executable, "-c", _PLAIN_EXQVFL], input=json.dumps(rows),
                         env=_plain_env(), capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    plain = json.loads(run.stdout)
    from nstar.exqvfl import exqvfl_kernel
    for (row, thr), (n, too_many, f) in zip(rows, plain, strict=True):
        a = np.full((4, 50), 7, np.int32)
        ra = exqvfl_kernel(np.asarray(row, np.int64), len(row), thr, a)
        assert (int(ra[0]), bool(ra[1])) == (n, too_many), (row, thr)
        assert a.tolist() == f


def test_this_process_is_compiled_when_numba_is_there():
    # The comparisons above mean something only if this side is compiled.
    if os.environ.get("RIG_NO_JIT"):
        assert not jit.ENABLED
    else:
        import importlib.util
        assert jit.ENABLED == (importlib.util.find_spec("numba") is not None)
