"""The improved matcher's faster scan gives the same scan, bit for bit.

``planner.loop.scan_look(..., "improved")`` is the bulk of the drive loop's
cycle, so the streaming matcher shares work between its passes and lines and
finds a line's candidate pairs in one compiled pass.  None of it may change a
result: tests/data/improved_scans.json.gz holds looks of generated rooms (the
pictures, rendered by world.render) with their scans as the plain matcher
(commit add8861, before the speed-up) gave them, every located point and
every verdict with its floats as ``repr`` writes them (exactly).  To write it
again from a tree of that commit::

    PYTHONPATH=<tree> python tests/test_matching_speed.py
"""

from __future__ import annotations

import base64
import gzip
import json
import sys
from dataclasses import astuple
from pathlib import Path

import numpy as np

FIXTURE = Path(__file__).parent / "data" / "improved_scans.json.gz"
LOOKS = ((1, 1), (2, 3), (3, 0))        # (generated room, look of its generated walk)


def scan_record(scan) -> dict:
    """A scan's points and verdicts as JSON text per line (floats by repr)."""
    return {"points": json.dumps([astuple(p) for p in scan.points]),
            "lines": {str(r.iyloc): json.dumps([astuple(v) for v in r.verdicts])
                      for r in scan.results},
            "requests": scan.requests}


def render_fixture_looks():
    """The pictures of :data:`LOOKS`, as the drive renders a look (2x2 rays per pixel)."""
    from world.render import render_look
    from world.room import generate_room
    from world.walk import generate_walk
    out = []
    for seed, k in LOOKS:
        room = generate_room(seed)
        look = render_look(room, generate_walk(room, seed, k + 1)[k], seed=1000 * seed + k,
                           supersample=2)
        out.append((look.left_bi, look.right_bi))
    return out


def write_fixture() -> None:
    from planner.loop import DriveConfig, scan_look
    lines = DriveConfig.__dataclass_fields__["lines"].default
    looks = []
    for left, right in render_fixture_looks():
        looks.append({"left": base64.b64encode(left.astype(np.uint8).tobytes()).decode(),
                      "right": base64.b64encode(right.astype(np.uint8).tobytes()).decode(),
                      "shape": list(left.shape), "dtype": str(left.dtype), "lines": list(lines),
                      "scan": scan_record(scan_look(left, right, lines, "improved"))})
    FIXTURE.parent.mkdir(exist_ok=True)
    FIXTURE.write_bytes(gzip.compress(json.dumps(looks).encode(), mtime=0))


def fixture_looks():
    for look in json.loads(gzip.decompress(FIXTURE.read_bytes())):
        pictures = [np.frombuffer(base64.b64decode(look[k]), dtype=np.uint8)
                    .reshape(look["shape"]).astype(look["dtype"]) for k in ("left", "right")]
        yield pictures, tuple(look["lines"]), look["scan"]


def test_the_scan_of_a_look_is_the_plain_matchers_bit_for_bit():
    """The drive's scan (the eyes' line source, eyes.improved) and ESTAR's with
    the matcher (whose count of NBLOB round trips is the plain matcher's too)."""
    from matching.mode import make_matcher
    from planner.loop import scan_look
    from rig.scan import scan_pair
    reasons = set()
    for (left, right), lines, want in fixture_looks():
        estar = scan_record(scan_pair(left, right, lines, matcher=make_matcher("improved")))
        assert estar["requests"] == want["requests"]
        assert estar["lines"] == want["lines"] and estar["points"] == want["points"]
        got = scan_record(scan_look(left, right, lines, "improved"))
        assert got["lines"].keys() == want["lines"].keys()
        for y in want["lines"]:
            assert got["lines"][y] == want["lines"][y], f"line {y}"
            reasons |= {v[4] for v in json.loads(want["lines"][y])}
        assert got["points"] == want["points"]
    # the looks exercise every rule of the default five
    assert {"matched", "confirmed", "occluded", "not on a vertical line", "ambiguous",
            "not mutual", "no candidate"} <= reasons


def test_the_fixtures_pictures_are_the_renderers():
    """The stored pictures are the looks world.render gives today (else the
    fixture no longer names what it claims to)."""
    for (left, right), ((want_l, want_r), _, _) in zip(render_fixture_looks(), fixture_looks()):
        assert np.array_equal(left, want_l) and np.array_equal(right, want_r)


def test_the_streaming_matcher_equals_the_batch_api_on_a_rendered_look():
    """ESTAR line by line with the matcher (its shared assignment, its kept
    neighbour matches) against match_lines, the plain batch form, on the
    1985 lists of every line of a look."""
    from estar.program import in_process_rig
    from matching import Constraints, match_lines
    from matching.mode import make_matcher
    from rig.scan import run_lines
    (left, right), _, _ = next(fixture_looks())
    streamed = run_lines(in_process_rig(left, right, matcher=make_matcher("improved")),
                         range(30, 60, 3))
    faithful = run_lines(in_process_rig(left, right), range(0, 120))
    batch = match_lines(faithful.results, Constraints())
    for r in streamed.results:
        assert r.verdicts == batch[r.iyloc], r.iyloc


def _fixture_lines():
    from matching.verdict import LineData
    from rig.scan import run_lines
    from estar.program import in_process_rig
    out = []
    for (left, right), _, _ in fixture_looks():
        scan = run_lines(in_process_rig(left, right), range(0, 120, 4))
        out += [LineData.of(r) for r in scan.results if r.features1 and r.features2]
    return out


def test_the_compiled_pair_search_equals_its_plain_python_and_marfs_shift_search():
    from matching.candidates import _POP, admissible_pairs, best_shift, shape_costs, slice_edges
    plain_pairs = getattr(admissible_pairs, "py_func", admissible_pairs)
    plain_shift = getattr(best_shift, "py_func", best_shift)
    lines = _fixture_lines()
    assert len(lines) > 20
    found = 0
    for d in lines:
        left, right = slice_edges(d.features1), slice_edges(d.features2)
        rows1 = np.stack((left.x, left.side, left.grey, left.bound, left.width))
        rows2 = np.stack((right.x, right.side, right.grey, right.bound, right.width))
        maps1, maps2 = d.maps1[left.edge - 1], d.maps2[right.edge - 1]
        for use_shift, cap, width_penalty in ((True, False, 4.0), (False, True, 0.0)):
            outs = []
            for fn in (admissible_pairs, plain_pairs):
                pairs = np.full((len(left) * len(right), 4), -7, dtype=np.int64)
                scores = np.full((len(left) * len(right), 3), np.nan)
                n = fn(rows1, maps1, rows2, maps2, use_shift, 16.0, width_penalty, 128.0, cap,
                       _POP, pairs, scores)
                outs.append((n, pairs, scores))
            assert outs[0][0] == outs[1][0]
            assert np.array_equal(outs[0][1], outs[1][1])
            assert np.array_equal(outs[0][2], outs[1][2], equal_nan=True)
            n, pairs, scores = outs[0]
            found += n
            for (i, j, s, v), (cost, loc1, loc2) in zip(pairs[:n], scores[:n]):
                # the shift and mismatch of the array search (shape_costs), the
                # cost and locations of the array formulas
                bound = min(left.bound[i], right.bound[j])
                want = shape_costs(maps1[i][None, 1:], maps2[j][None, 1:], np.array([bound]),
                                   cap)
                assert (s, v) == (want[0][0], want[1][0])
                assert best_shift(maps1[i], maps2[j], bound, cap, _POP) == (s, v) \
                    == plain_shift(maps1[i], maps2[j], bound, cap, _POP)
                want_cost = (np.array([v]) + 16.0 * np.abs(left.grey[[i]] - right.grey[[j]])
                             + width_penalty * np.abs(left.width[[i]] - right.width[[j]]))
                assert cost == want_cost[0]
                assert (loc1, loc2) == (left.x[i], right.x[j] - (s if use_shift else 0))
    assert found > 50
    # random maps, every bound, both overflow rules
    r = np.random.default_rng(5)
    for _ in range(200):
        m1 = np.concatenate(([1], r.integers(-32768, 32768, 16)))
        m2 = np.concatenate(([1], r.integers(0, 1 << 16, 16) & r.integers(0, 1 << 16, 16)))
        bound = int(r.integers(0, 20))
        for cap in (False, True):
            s, v = shape_costs(m1[None, 1:], m2[None, 1:], np.array([bound]), cap)
            assert best_shift(m1, m2, bound, cap, _POP) == (s[0], v[0])


def _mutual_plain(c, tol):
    """verdict._mutual as written before it was compiled."""
    row_best = np.full(len(c.left), np.inf)
    col_best = np.full(len(c.right), np.inf)
    np.minimum.at(row_best, c.i, c.cost)
    np.minimum.at(col_best, c.j, c.cost)
    return (c.cost <= row_best[c.i] + tol) & (c.cost <= col_best[c.j] + tol)


def _region_supported_plain(c, tol):
    """verdict._region_supported as written before it was compiled."""
    f1, f2, side = c.left.feature[c.i], c.right.feature[c.j], c.left.side[c.i]
    best = {}
    for a, b, s, d in zip(f1.tolist(), f2.tolist(), side.tolist(), c.disp.tolist()):
        best.setdefault((a, b, s), []).append(d)
    keep = np.zeros(len(c), dtype=bool)
    for k, (a, b, s, d) in enumerate(zip(f1.tolist(), f2.tolist(), side.tolist(),
                                         c.disp.tolist())):
        other = best.get((a, b, 1 - s))
        keep[k] = other is not None and min(abs(d - o) for o in other) <= tol
    return keep


def _confidences_plain(c, chosen, marginal, p):
    """verdict._confidences as written before it was compiled."""
    if len(chosen) == 0:
        return []
    rivals = (c.i[chosen, None] == c.i[None, :]) | (c.j[chosen, None] == c.j[None, :])
    rivals[np.arange(len(chosen)), chosen] = False
    best_rival = np.where(rivals, marginal[None, :], np.inf).min(axis=1)
    out = []
    for k, rival, has_rival in zip(chosen.tolist(), best_rival.tolist(),
                                   rivals.any(axis=1).tolist()):
        gap = 2.0 * p.occlusion - float(c.cost[k])
        if has_rival:
            gap = min(gap, rival - float(marginal[k]))
        out.append(min(1.0, max(0.0, gap / (2.0 * p.occlusion))))
    return out


def test_the_compiled_lr_and_region_rules_equal_their_plain_python():
    """The lr and region rules and the confidences on every line of the
    fixture looks with pairs (at tolerances and occlusion costs that split
    them), compiled and as plain Python."""
    from matching import verdict
    from matching.verdict import Constraints, Params, _choose, line_candidates
    lines = _fixture_lines()
    seen = kept_lr = kept_region = 0
    shares = set()
    for d in lines:
        c = line_candidates(d, Params())
        if len(c) == 0:
            continue
        seen += len(c)
        for tol in (0.0, 1.0, 2.0, 16.0, 64.0):
            lr = verdict._mutual(c, tol)
            assert np.array_equal(lr, _mutual_plain(c, tol))
            region = verdict._region_supported(c, tol)
            assert np.array_equal(region, _region_supported_plain(c, tol))
            kept_lr += int(lr.sum())
            kept_region += int(region.sum())
        for occlusion in (8.0, 64.0, 200.0):
            p = Params(occlusion=occlusion)
            chosen, marginal = _choose(c, Constraints(), p)
            every = np.arange(len(c))                   # each pair as if chosen: every rival
            for picked in (chosen, every):
                got = verdict._confidences(c, picked, marginal, p)
                assert got == _confidences_plain(c, picked, marginal, p)
                shares.update(got)
    # each rule keeps some pairs and drops others
    assert seen > 200 and 0 < kept_lr < 5 * seen and 0 < kept_region < 5 * seen
    assert {0.0, 1.0} < shares                          # both clamps and values between
    # the kernels' own bodies run as plain Python give the same
    c = next(line_candidates(d, Params()) for d in lines if len(line_candidates(d, Params())) > 8)
    for kernel, args in ((verdict._mutual_kernel, (c.i, c.j, c.cost, len(c.left), len(c.right),
                                                    64.0)),
                         (verdict._region_kernel, (c.left.feature[c.i], c.right.feature[c.j],
                                                   c.left.side[c.i], c.disp, 2.0))):
        outs = []
        for fn in (kernel, getattr(kernel, "py_func", kernel)):
            out = np.zeros(len(c), dtype=bool)
            fn(*args, out)
            outs.append(out)
        assert np.array_equal(*outs)
    every = np.arange(len(c))
    _, marginal = _choose(c, Constraints(), Params())
    outs = []
    for fn in (verdict._confidences_kernel, getattr(verdict._confidences_kernel, "py_func",
                                                    verdict._confidences_kernel)):
        out = np.zeros(len(c))
        fn(c.i, c.j, c.cost, every, marginal, 128.0, out)
        outs.append(out)
    assert np.array_equal(*outs)


def test_the_column_lookup_counts_what_a_pass_over_every_match_counts():
    """column_support on edge_columns against the rule read literally: a line
    supports when any matched edge of the same side lies within dx px and
    dd px of disparity (random lines; dx 0, 2, 2.5 and -1)."""
    from matching.verdict import Verdict, column_support, edge_columns
    rng = np.random.default_rng(8)
    lines = []
    for y in range(14):
        vs = []
        for e in rng.choice(np.arange(1, 101), size=int(rng.integers(0, 12)), replace=False):
            x = int(rng.integers(1, 40))
            loc2 = float(x - rng.integers(2, 9))
            vs.append(Verdict(y, int(e), x, bool(rng.random() < 0.8), "matched", 1,
                              float(x), loc2, 10.0, 0.5))
        lines.append(vs)
    columns = [edge_columns(v) for v in lines]
    counted = set()
    for _ in range(400):
        side, x0 = bool(rng.random() < 0.5), int(rng.integers(1, 40))
        d, dx, dd = float(rng.integers(2, 9)), [0, 2, 2.5, -1][int(rng.integers(0, 4))], 1.0
        want = sum(any(v.matched and (v.edge > 50) == side and abs(v.x - x0) <= dx
                       and abs(v.disparity - d) <= dd for v in line) for line in lines)
        assert column_support(columns, side, x0, d, dx, dd) == want
        counted.add(want)
    assert len(counted) >= 4


def test_the_scan_bench_times_this_tree(capsys):
    """bench/bench_scan.py, one look, this tree alone (its worker is a process of its own)."""
    import importlib.util
    path = Path(__file__).resolve().parent.parent / "bench" / "bench_scan.py"
    spec = importlib.util.spec_from_file_location("bench_scan", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    assert bench.main(["--rooms", "1", "--looks", "1", "--rounds", "1",
                       "--reference", "none"]) == 0
    out = capsys.readouterr().out
    assert "1 looks (1 rooms x 1)" in out and "this tree" in out


if __name__ == "__main__":
    write_fixture()
    sys.exit(0)
