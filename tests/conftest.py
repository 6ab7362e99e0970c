"""Fixtures shared by the tests (helpers in rigtools.py).

Tests that start real programs carry the ``processes`` marker: run the fast
part alone with ``pytest -m "not processes"``; the whole suite is the default."""

import sys
from pathlib import Path

import pytest

# Test helpers (appendix_d.py, rigtools.py) live beside the tests.
sys.path.insert(0, str(Path(__file__).parent))


def pytest_configure(config):
    config.addinivalue_line("markers", "processes: starts nstar, estar, rig or pre as real "
                                       "processes (deselect with -m 'not processes')")


@pytest.fixture
def rig(tmp_path):
    """(tmp, jhdata): a fresh jhdata/ beside L.BI and R.BI of rigtools.make_pair."""
    from rigtools import make_pair
    jh = tmp_path / "jhdata"
    jh.mkdir()
    make_pair(tmp_path)
    return tmp_path, jh


@pytest.fixture
def box_rig(tmp_path):
    """The in-process rig (rigtools.make_pair's pictures), for tests with no process."""
    from estar.program import in_process_rig
    from rigtools import make_pair, load_pair
    make_pair(tmp_path)
    return in_process_rig(*load_pair(tmp_path))
