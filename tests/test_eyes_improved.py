"""eyes.improved: the improved matcher on the eyes' compiled line source gives
the scan ESTAR gives with the matcher (rig.scan.scan_pair(..., matcher=...)),
line for line, on the rendered looks of tests/data/improved_scans.json.gz."""

from __future__ import annotations

import numpy as np
import pytest

from estar.program import in_process_rig
from eyes.improved import ImprovedEyes, frame_lines, scan_pair
from eyes.kernels import build_frame, frame_lines_kernel, new_windows
from matching.mode import fetch_line, make_matcher
from rig import scan as scanmod
from test_matching_speed import fixture_looks

RESULT_FIELDS = ("iyloc", "features1", "features2", "matches", "positions", "posit",
                 "requests", "used", "verdicts")


def _looks():
    return [pictures for pictures, _, _ in fixture_looks()]


def test_every_lines_slices_and_maps_are_nstars_over_the_link():
    for left, right in _looks():
        data, requests = frame_lines(build_frame(left, right), new_windows())
        eclipse = in_process_rig(left, right)
        for y in range(120):
            before = eclipse.requests
            want = fetch_line(eclipse, y)
            got = data[y]
            assert got.iyloc == y
            assert got.features1 == want.features1 and got.features2 == want.features2, y
            assert np.array_equal(got.maps1, want.maps1), y
            assert np.array_equal(got.maps2, want.maps2), y
            assert requests[y] == eclipse.requests - before
        assert sum(len(d.features1) for d in data) > 100
        assert sum(int(d.maps1[:, 0].sum()) for d in data) > 100   # maps were made


def test_the_line_kernel_as_plain_python_equals_the_compiled_one():
    plain = getattr(frame_lines_kernel, "py_func", frame_lines_kernel)
    left, right = _looks()[1]
    outs = []
    for fn in (frame_lines_kernel, plain):
        arrays = (np.full((120, 2), -3, np.int64), np.full((120, 2, 4, 50), -3, np.int32),
                  np.full((120, 2, 100, 17), -3, np.int64), np.full(120, -3, np.int64))
        fn(build_frame(left, right), new_windows(), *arrays)
        outs.append(arrays)
    for a, b in zip(*outs):
        assert np.array_equal(a, b)
    assert (outs[0][2][:, :, :, 1:] < 0).any()           # signed words were met


@pytest.mark.parametrize("order", ["drive", "reversed", "sparse"])
def test_the_scan_is_estars_with_the_matcher_line_for_line(order):
    looks = list(fixture_looks())
    for (left, right), lines, _ in looks if order == "drive" else looks[:1]:
        lines = {"drive": list(lines), "reversed": list(lines)[::-1],
                 "sparse": [3, 119, 0, 57, 58, 90]}[order]
        want = scanmod.scan_pair(left, right, lines, matcher=make_matcher("improved"))
        got = ImprovedEyes().scan(left, right, lines)
        assert got.lines == want.lines
        assert got.points == want.points
        assert len(got.points) > (20 if order != "sparse" else 0)
        for a, b in zip(got.results, want.results, strict=True):
            for name in RESULT_FIELDS:
                assert getattr(a, name) == getattr(b, name), (a.iyloc, name)
            assert np.array_equal(a.maps1, b.maps1) and np.array_equal(a.maps2, b.maps2)
        # ESTAR's count also holds the matcher's own fetches; here MASL's only
        assert got.requests == sum(r.requests for r in want.results) < want.requests


def test_one_object_scans_many_looks_as_fresh_ones():
    eyes = ImprovedEyes()
    for (left, right), lines, _ in fixture_looks():
        assert eyes.scan(left, right, lines).points == scan_pair(left, right, lines).points


def test_bad_input_is_refused():
    flat = np.full((120, 128), 7, dtype=np.uint8)
    with pytest.raises(ValueError, match="left picture is"):
        scan_pair(flat[:100], flat)
    with pytest.raises(ValueError, match="within 0..119"):
        scan_pair(flat, flat, [120])
    with pytest.raises(ValueError, match="subpixel"):
        scan_pair(flat, flat, [60], matcher=make_matcher("improved", "order,subpixel",
                                                         vd=(None, None)))
    assert scan_pair(flat, flat, [60]).points == []
