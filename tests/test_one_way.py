"""One way to do each thing (issue 8.20, 8.21): the in-process rig, an nstar
process, ESTAR's start-up protocol and the atomic publish each have one
constructor; this guard finds a hand-assembled copy anywhere in the tree."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
SOURCES = sorted(p for p in REPO.rglob("*.py")
                 if not {".venv", "build", ".git"} & set(p.relative_to(REPO).parts)
                 and p.name != "test_one_way.py")

# pattern -> the one file allowed to hold it
ONE_PLACE = {
    r"Eclipse\(\s*DirectLink\(": "estar/program.py",         # in_process_rig
    r"Eclipse\(\s*(link|FileLink)\b": "estar/program.py",    # file_link_estar
    r"\.lock\(\s*(\"ESTAR\.LCK\"|ESTAR_LOCK)": "estar/link.py",  # FileLink.open
    r"\.wait_idle\(": "estar/link.py",                        # FileLink.start
    r"\"-m\",\s*\"nstar\.main\"": "rig/session.py",          # start_nstar / nstar_command
    r"os\.replace\(|\.replace\(\s*path\s*\)|tempfile\.mkstemp": "diskfmt/rdos.py",
}
ALLOWED_ELSEWHERE = {            # tests that play a part by hand on purpose
    r"\.lock\(\s*(\"ESTAR\.LCK\"|ESTAR_LOCK)": {"tests/rigtools.py", "tests/test_rdos.py",
                                               "tests/test_hostile.py"},
}


@pytest.mark.parametrize("pattern", ONE_PLACE)
def test_each_construction_has_one_place(pattern):
    rx = re.compile(pattern)
    found = {str(p.relative_to(REPO)) for p in SOURCES if rx.search(p.read_text())}
    assert found <= {ONE_PLACE[pattern]} | ALLOWED_ELSEWHERE.get(pattern, set()), sorted(found)
