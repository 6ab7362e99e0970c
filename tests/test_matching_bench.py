"""The matching benchmark's truth (bench/bench_matching.py): the occlusion mask of a
box before a wall against the same geometry worked out by hand, and the
generated rooms render deterministically."""

import importlib.util
import sys
from pathlib import Path

import numpy as np

from rig import scene as sc

_PATH = Path(__file__).resolve().parent.parent / "bench" / "bench_matching.py"
_spec = importlib.util.spec_from_file_location("bench_matching", _PATH)
bm = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("bench_matching", bm)
_spec.loader.exec_module(bm)

WALL_Z, BOX_Z, BOX_X = 12.0, 4.0, (-0.5, 0.5)


def box_before_wall():
    return sc.box("box", BOX_X, (-1.0, 1.0), (BOX_Z, BOX_Z + 1.0), sc.flat(9), sc.flat(9),
                  sc.flat(9)) + [
        sc._quad("wall", 2, WALL_Z, (-40.0, 40.0), (-40.0, 40.0), sc.flat(4))]


def test_occlusion_truth_of_a_box_before_a_wall():
    occ = bm.occlusion_truth(box_before_wall())
    row = 60                                   # through the box (pixel centre y = 0.5/360*Z)
    u = 2.0 * np.arange(128) + 1.0
    px = (u - sc.CX) / sc.FOCAL_256
    x_box = sc.LEFT_X + BOX_Z * px             # where the left ray meets the box's front plane
    on_box = (x_box >= BOX_X[0]) & (x_box <= BOX_X[1])
    x_wall = sc.LEFT_X + WALL_Z * px
    # the right camera's ray to the wall point crosses the box front at
    x_cross = sc.RIGHT_X + (x_wall - sc.RIGHT_X) * BOX_Z / WALL_Z
    hidden = ~on_box & (x_cross >= BOX_X[0]) & (x_cross <= BOX_X[1])
    ur = (x_wall - sc.RIGHT_X) / WALL_Z * sc.FOCAL_256 + sc.CX
    outside = (ur < 0) | (ur >= sc.WIDTH)
    want = hidden | outside
    # the first 135/12 = 11.25 columns of the left picture lie left of the right one's
    assert np.flatnonzero(outside).tolist() == list(range(11))
    # the hidden band is the strip left of the box, as wide as the disparity difference
    band = np.flatnonzero(hidden)
    assert band.max() < np.flatnonzero(on_box).min()
    assert abs(len(band) - (135 / BOX_Z - 135 / WALL_Z)) <= 1
    assert np.array_equal(occ[row], want)


def test_generated_rooms_are_seeded_and_differ():
    def geometry(seed):
        return [(q.name, q.axis, q.c, q.lo, q.hi) for q in bm.generated_quads(seed)]
    assert geometry(1) == geometry(1) != geometry(2)
    room = bm.rendered("r", bm.generated_quads(3), 3)          # rendering: rig.scene's own
    assert room.occluded.any() and np.isfinite(room.true_disp).all()
    assert room.left_bi.shape == (120, 128) and room.left_vd.shape == (240, 256)


def test_param_flags_change_params_and_refuse_bad_ones():
    p = bm.params_from(["readmit_rounds=3", "region_penalty=none", "occlusion=70"])
    assert (p.readmit_rounds, p.region_penalty, p.occlusion) == (3, None, 70.0)
    assert p.smooth == bm.Params().smooth
    for bad in (["nonsense=1"], ["occlusion"], ["readmit_rounds=many"]):
        try:
            bm.params_from(bad)
        except ValueError as e:
            assert "--param" in str(e)
        else:
            raise AssertionError(bad)


def test_diagnosis_counts_reasons_against_the_truth():
    """On the hand-made stack of tests/test_matching.py (E at 50 with its
    maps damaged on line 60): without re-admission line 60's E is "occluded"
    and its cheapest candidate is right; with it, E is "readmitted" and right
    (with confirm instead: "confirmed" and right).
    A truth that puts E at disparity 8 instead makes the same edges wrong."""
    from test_matching import jump_line
    from matching import Constraints, match_lines
    from dataclasses import replace as dc_replace
    stack = jump_line()
    datas = {d.iyloc: d for d in stack}
    truth = np.full((120, 128), 8.0)
    truth[:, 45:53] = 12.0                  # E's columns (x 50 -> column 49, +-1)
    scene = bm.Scene("hand-made", None, None, None, None, truth, None)
    p = bm.Params()
    four = Constraints(confirm=False)       # the default before 2026-12-01
    before = bm.diagnosis(scene, match_lines(stack, four, p), datas, p)
    assert before["occluded"] == (2, 2, 2)              # edges 2 and 52 of line 60
    assert before["matched"][0] == before["matched"][1] == 6 * 7 - 2
    five = dc_replace(four, readmit=True)
    now = bm.diagnosis(scene, match_lines(stack, five, p), datas, p)
    assert now["readmitted"] == (2, 2, 2) and "occluded" not in now
    flat = bm.Scene("hand-made", None, None, None, None, np.full((120, 128), 8.0), None)
    wrong = bm.diagnosis(flat, match_lines(stack, five, p), datas, p)
    assert wrong["readmitted"] == (2, 0, 0)
    confirmed = bm.diagnosis(scene, match_lines(stack, Constraints(), p), datas, p)   # default
    assert confirmed["confirmed"] == (2, 2, 2) and "occluded" not in confirmed


def test_truth_at_the_step_sees_the_box_whose_outline_the_edge_is():
    """The box's right side (x = 0.5 ft at Z = 4) falls at 128-px column
    (0.5 + 0.375) / 4 * 180 + 64 = 103.375: pixel 103 is mixed and its centre
    sees the wall.  EXQVFL's feature there runs from the last box pixel (1-based
    103) to the first wall pixel (105); its right end LOC1 = 105 is scored by
    bench/accuracy.py's rule over columns 103..105, all wall (135/12 = 11.25),
    though the step it names is the box's outline (135/4 = 33.75).  The truth
    at the step finds the box; an edge inside the wall's flat grey, far from
    the box, gets the wall either way; a scene without geometry gets NaN."""
    quads = box_before_wall()
    left = sc.quantise(sc.render_view(sc.LEFT_X, quads))
    truth = bm.DCONS / sc.true_range_128(sc.LEFT_X, quads)
    scene = bm.Scene("box", None, None, left, None, truth, None, quads)
    row = 60
    assert truth[row, 102] == 135 / BOX_Z and truth[row, 103] == 135 / WALL_Z
    assert bm.acc.true_disparity_at(truth, row, 105 - 1, 1) == 135 / WALL_Z
    feature = (103, 105, 9, 4)
    x = bm.step_columns(scene, [row], [feature])
    assert abs(x[0] - 103.375) < 0.25
    at_step = bm.truth_at_step(scene, [row], [feature, ])
    assert at_step[0] == 135 / BOX_Z
    far = bm.truth_at_step(scene, np.array([row, row]), np.array([feature, (20, 22, 4, 4)]))
    assert far[0] == 135 / BOX_Z and far[1] == 135 / WALL_Z   # no step: the ramp's middle
    blind = bm.Scene("box", None, None, left, None, truth, None)
    assert np.isnan(bm.truth_at_step(blind, [row], [feature])).all()


def test_the_first_targets_row_is_the_default_matcher():
    """The tables' "default" rows are what --match improved runs: the default
    five (the four + confirm since 2026-12-01); "the four" is the old default
    without confirm."""
    from dataclasses import replace as dc_replace
    from matching import Constraints
    from matching.mode import make_matcher
    variants = dict(bm.VARIANTS)
    assert variants[bm.TARGET] == Constraints() == make_matcher("improved").constraints
    assert variants[bm.FOUR] == dc_replace(Constraints(), confirm=False)
    assert bm.DIAGNOSED == (bm.FOUR, bm.TARGET)
    assert "default five" in bm.TARGET and "no confirm" in bm.FOUR
