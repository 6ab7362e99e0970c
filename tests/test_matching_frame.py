"""matching.frame: the default rules over a whole frame, compiled, give the plain
matcher's verdicts (matching.mode.ImprovedMatcher.frame_verdicts), every
verdict of every line of a look, the floats bit for bit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from eyes.improved import ImprovedEyes, frame_arrays, line_data
from eyes.kernels import build_frame, new_windows
from matching import frame as frame_mod
from matching.frame import covers, frame_verdicts
from matching.mode import ImprovedMatcher
from matching.verdict import Constraints, Params
from test_matching_speed import fixture_looks


def _arrays(left, right):
    nfeat, ifeat, maps, _ = frame_arrays(build_frame(left, right), new_windows())
    return nfeat, ifeat, maps


def _plain(arrays, lines, params=Params()):
    data = [line_data(y, *arrays) for y in range(120)]
    return ImprovedMatcher(Constraints(), params).frame_verdicts(data, lines)


def _rendered_looks():
    """The fixture's looks and two more of other rooms, as the drive renders them."""
    from world.render import render_look
    from world.room import generate_room
    from world.walk import generate_walk
    looks = [pictures for pictures, _, _ in fixture_looks()]
    for seed in (7, 12):
        room = generate_room(seed)
        look = render_look(room, generate_walk(room, seed, 3)[2], seed=seed, supersample=2)
        looks.append((look.left_bi, look.right_bi))
    return looks


def test_every_line_of_a_look_is_judged_as_the_plain_matcher_judges_it():
    reasons, matched = set(), 0
    for left, right in _rendered_looks():
        arrays = _arrays(left, right)
        want = _plain(arrays, list(range(120)))
        got = frame_verdicts(*arrays, list(range(120)))
        for y, (a, b) in enumerate(zip(got, want, strict=True)):
            assert a == b, f"line {y}"
            reasons |= {v.reason for v in b}
            matched += sum(v.matched for v in b)
    # every verdict the default rules give was met, and many matches
    assert reasons == set(frame_mod.REASONS)
    assert matched > 1000


@pytest.mark.parametrize("change", [
    {"confirm_rounds": 1}, {"confirm_reach": 3, "confirm_support": 2},
    {"neighbour_reach": 2, "min_confidence": 0.3}, {"region_penalty": 16.0, "smooth": 4.0},
    {"use_shift": False, "width_penalty": 0.0}])
def test_other_weights_of_the_default_rules_too(change):
    params = replace(Params(), **change)
    assert covers(Constraints(), params)
    (left, right), _, _ = next(iter(fixture_looks()))
    arrays = _arrays(left, right)
    lines = list(range(0, 120, 3))
    assert frame_verdicts(*arrays, lines, params) == _plain(arrays, lines, params)


def test_the_kernel_as_plain_python_equals_the_compiled_one(monkeypatch):
    (left, right), lines, _ = next(iter(fixture_looks()))
    arrays = _arrays(left, right)
    compiled = frame_verdicts(*arrays, list(lines))
    monkeypatch.setattr(frame_mod, "frame_kernel",
                        getattr(frame_mod.frame_kernel, "py_func", frame_mod.frame_kernel))
    assert frame_verdicts(*arrays, list(lines)) == compiled


def test_only_the_default_rules_are_compiled():
    assert covers(Constraints(), Params())
    assert not covers(Constraints.parse("all"), Params())
    assert not covers(Constraints.parse("order,lr,neighbours,region"), Params())
    assert not covers(Constraints(), Params(region_penalty=None))
    assert not covers(Constraints(), Params(neighbour_bonus=8.0))
    assert not covers(Constraints(), Params(unsupported_factor=0.5))
    assert not covers(Constraints(), Params(drop_farther_end=True))
    assert not covers(Constraints(), Params(rematch_bonus=8.0))


def test_a_scan_under_other_rules_still_runs_the_plain_matcher(monkeypatch):
    """The eyes' scan takes the compiled rules only where they are the matcher's."""
    def refuse(*a, **k):
        raise AssertionError("compiled rules used for other constraints")
    monkeypatch.setattr(frame_mod, "frame_verdicts", refuse)
    (left, right), lines, _ = next(iter(fixture_looks()))
    other = ImprovedMatcher(Constraints.parse("order,lr,neighbours,region"))
    scan = ImprovedEyes().scan(left, right, lines, other)
    assert any(v.matched for r in scan.results for v in r.verdicts)
    with pytest.raises(AssertionError, match="compiled rules"):
        ImprovedEyes().scan(left, right, lines, ImprovedMatcher())


def test_a_frame_without_features_judges_nothing():
    arrays = (np.zeros((120, 2), np.int64), np.zeros((120, 2, 4, 50), np.int32),
              np.zeros((120, 2, 100, 17), np.int64))
    assert frame_verdicts(*arrays, [0, 60, 119]) == [[], [], []]
