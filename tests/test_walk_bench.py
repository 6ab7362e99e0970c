"""The walk benchmark's Mahalanobis breakdown (bench/walk.py --breakdown) on a
hand-made model: every group's count, share inside 2 sigma and share beyond 10."""

import importlib.util
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

_PATH = Path(__file__).resolve().parent.parent / "bench" / "walk.py"
_spec = importlib.util.spec_from_file_location("bench_walk", _PATH)
bw = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("bench_walk", bw)
_spec.loader.exec_module(bw)


def test_mahalanobis_rows_group_by_looks_range_and_confirmation():
    from model.mapping import WalkConfig, WalkResult
    from model.symbolic import SymbolicModel
    model = SymbolicModel()
    # unit covariances, the camera at the origin at look 0; (truth offset, looks, nis, where)
    spec = [((1, 0, 0), 1, [], (0, 0, 3)),        # seen once, 3 ft away: inside (1)
            ((20, 0, 0), 1, [], (0, 0, 8)),       # seen once, 8 ft: beyond 10 (20)
            ((2, 0, 0), 2, [1.0], (0, 0, 8)),     # seen twice, consistent: confirmed, inside
            ((0, 3, 0), 5, [1.0] * 4, (0, 0, 12))]  # seen 5 times, 12 ft: outside (3 > 2.83)
    for off, looks, nis, where in spec:
        truth = np.array(where, float)
        v = model.add_vertex(truth + off, np.eye(3), "top", (3, 9), 0)
        v.truth, v.looks, v.nis = truth, looks, nis
    rec = SimpleNamespace(true_pose=SimpleNamespace(x=0.0, z=0.0))
    res = WalkResult(WalkConfig(confirm=2), [rec], model)
    rows = {r.split(" | ")[1]: r.split(" | ")[2:] for r in bw.mahalanobis_rows("t", [res])}
    assert rows["all"][:3] == ["4", "50.0 %", "25.0 %"]
    assert rows["seen once"][:3] == ["2", "50.0 %", "50.0 %"]
    assert rows["seen twice"][:3] == ["1", "100.0 %", "0.0 %"]
    assert rows["seen 5-9 times"][:3] == ["1", "0.0 %", "0.0 %"]
    assert "seen 10+ times" not in rows
    assert rows["first seen at 0-5 ft"][0] == "1" and rows["first seen at 10-15 ft"][0] == "1"
    assert rows["track-confirmed"][:2] == ["2", "50.0 %"]      # the twice and five-times seen
    assert rows["tentative"][:3] == ["2", "50.0 %", "50.0 %"]
    assert rows["all"][3].strip(" |") == "2.50"                # median of 1, 20, 2, 3
