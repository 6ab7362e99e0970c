"""The improved matcher against the 1985 one and OpenCV, on pictures with truth.

Scenes:

* the bundled laboratory pair (rig/data; truth LAB-RANGE.npy, occlusion truth
  from the same quads rig/scene.py renders);
* the Middlebury 2014 motorcycle pair through PRE's import path, as
  bench/accuracy.py takes it (needs scikit-image; no occlusion truth);
* generated rooms: seeded variants of rig/scene.py's renderer (boxes of
  random size and place on the floor, flat / checked / striped fronts, the
  stripes making picket fences, posters on a back wall at a random distance),
  each with its true range and its occlusion truth: the pixels of the left
  picture whose surface point the right camera does not see (hidden behind
  something nearer, or outside its picture).

Every scene is scanned once by the faithful rig over lines 7..113 (the edge
maps are the 1985 NBLOB replies); each matcher variant then works on those
lines (``matching.match_lines``) and is scored on lines 8..112, so line 8
and 112 have both neighbours, as in a streaming scan.

Scoring (bench/accuracy.py's rules): the true disparity at an edge is the
largest over columns LOC1-1 +- 1 of its row (the nearest surface); bad-1.0 /
bad-2.0 = share of edges with |disparity error| > 1 / 2 px; "within ep" =
share with |dp - true range| <= ep (LCSL's formulas in floating point); the
faithful count is the 1985 mode's located edges on the same lines.  StereoBM
and StereoSGBM (bench/accuracy.py's settings) are scored at the same pixels
(row IY, column LOC1-1) as each row's own edges, where they give an answer.
"No match" is scored against the occlusion truth at the edge's own pixel
(IY, x-1): precision = occluded share of "no match" verdicts, recall = share
of the occluded edges of the left slices that got "no match".

Run:  python bench/bench_matching.py [--out docs/matching.md] [--scenes 6]
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
# This script shares its name with the package it measures: the repository
# goes first on the path and bench/ (for accuracy.py) last.
_BENCH = str(REPO / "bench")
sys.path[:] = [str(REPO)] + [p for p in sys.path if p not in (str(REPO), _BENCH, "")] + [_BENCH]

import accuracy as acc                                  # noqa: E402
from matching import Constraints, Params, match_lines   # noqa: E402
from matching.subpixel import line_profile               # noqa: E402
from pre.condense import condense                        # noqa: E402
from rig import scene as sc                              # noqa: E402
from world.render import trace_rays                      # noqa: E402
from diskfmt.rdos import write_atomic                    # noqa: E402

BEGIN = "<!-- matching-table:begin -->"
END = "<!-- matching-table:end -->"
SCAN_LINES = range(7, 114)
SCORE_LINES = range(8, 113)
DCONS = 0.75 * 180.0


# --- scenes --------------------------------------------------------------------

@dataclass
class Scene:
    name: str
    left_bi: np.ndarray
    right_bi: np.ndarray
    left_vd: np.ndarray | None
    right_vd: np.ndarray | None
    true_disp: np.ndarray             # 120x128, 128-px columns; NaN = no truth
    occluded: np.ndarray | None       # 120x128 bool, left picture pixels the right camera misses
    quads: list | None = None         # the scene's geometry (rendered scenes): truth at the step


def occlusion_truth(quads) -> np.ndarray:
    """Left 128-px pixel centres whose surface point the right camera does not
    see: it projects outside the right picture, or the right camera's ray to
    it meets something nearer first."""
    u = 2.0 * np.arange(128) + 1.0
    v = 2.0 * np.arange(120) + 1.0
    px = np.ascontiguousarray(np.broadcast_to(((u - sc.CX) / sc.FOCAL_256)[None, :], (120, 128)))
    py = np.ascontiguousarray(np.broadcast_to(((v - sc.CY) / sc.FOCAL_256)[:, None], (120, 128)))
    z, _ = trace_rays(quads, (sc.LEFT_X, 0.0, 0.0), (px, py, np.ones_like(px)))
    x = sc.LEFT_X + z * px
    pr = (x - sc.RIGHT_X) / z
    ur = pr * sc.FOCAL_256 + sc.CX
    zr, _ = trace_rays(quads, (sc.RIGHT_X, 0.0, 0.0), (np.ascontiguousarray(pr), py, np.ones_like(px)))
    outside = (ur < 0) | (ur >= sc.WIDTH)
    hidden = zr < z * (1 - 1e-6) - 1e-6
    return outside | hidden


def generated_quads(seed: int) -> list:
    """A seeded room: 3-5 boxes on the floor, posters on the back wall."""
    rng = np.random.default_rng(10_000 + seed)
    g = lambda: int(rng.integers(1, 15))                 # noqa: E731
    q = []
    boxes = []
    for _ in range(int(rng.integers(3, 6))):
        w, h, d = rng.uniform(0.6, 2.0), rng.uniform(0.8, 2.6), rng.uniform(0.5, 1.2)
        x0, z0 = rng.uniform(-3.0, 2.5), rng.uniform(3.5, 12.0)
        kind = rng.choice(["flat", "checks", "stripes", "stripes"])
        if kind == "flat":
            front = sc.flat(g())
        elif kind == "checks":
            a, b = g(), g()
            front = sc.checks(a, b if b != a else (a + 7) % 15 + 1, rng.uniform(0.2, 0.5), 0, 1,
                              origin=(x0, sc.FLOOR_Y - h))
        else:
            a, b = g(), g()
            front = sc.stripes(a, b if b != a else (a + 7) % 15 + 1, rng.uniform(0.1, 0.3), 0,
                               origin=x0)
        boxes.append((z0, sc.box(f"box{len(boxes)}", (x0, x0 + w), (sc.FLOOR_Y - h, sc.FLOOR_Y),
                                 (z0, z0 + d), front, sc.flat(g()), sc.flat(g()))))
    for _, b in sorted(boxes, key=lambda t: t[0]):
        q += b
    back = rng.uniform(14.0, 20.0)
    for k in range(int(rng.integers(2, 5))):
        x0, y0 = rng.uniform(-3.5, 5.0), rng.uniform(-4.0, 1.0)
        q.append(sc._quad(f"poster{k}", 2, back, (x0, x0 + rng.uniform(0.5, 2.0)),
                          (y0, y0 + rng.uniform(0.5, 2.0)), sc.flat(g())))
    q.append(sc._quad("back wall", 2, back, (sc.LEFT_WALL_X, sc.RIGHT_WALL_X),
                      (sc.CEILING_Y, sc.FLOOR_Y), sc.flat(g())))
    q.append(sc._quad("left wall", 0, sc.LEFT_WALL_X, (sc.CEILING_Y, sc.FLOOR_Y), (0.0, back),
                      sc.flat(g())))
    q.append(sc._quad("right wall", 0, sc.RIGHT_WALL_X, (sc.CEILING_Y, sc.FLOOR_Y), (0.0, back),
                      sc.flat(g())))
    q.append(sc._quad("floor", 1, sc.FLOOR_Y, (sc.LEFT_WALL_X, sc.RIGHT_WALL_X), (0.0, back),
                      sc.flat(g())))
    q.append(sc._quad("ceiling", 1, sc.CEILING_Y, (sc.LEFT_WALL_X, sc.RIGHT_WALL_X), (0.0, back),
                      sc.flat(g())))
    return q


def rendered(name: str, quads, seed: int) -> Scene:
    rng = np.random.default_rng(seed)
    left = sc.add_noise(sc.quantise(sc.render_view(sc.LEFT_X, quads)), rng)
    right = sc.add_noise(sc.quantise(sc.render_view(sc.RIGHT_X, quads)), rng)
    z = sc.true_range_128(sc.LEFT_X, quads)
    return Scene(name, condense(left), condense(right), left, right, DCONS / z,
                 occlusion_truth(quads), quads)


def bundled() -> Scene:
    from diskfmt.layouts import decode_bi, decode_vd, read_file
    pics = [read_file(sc.bundled_path(n)) for n in ("LAB-L.BI", "LAB-R.BI", "LAB-L.VD", "LAB-R.VD")]
    return Scene("bundled lab pair", decode_bi(pics[0]), decode_bi(pics[1]), decode_vd(pics[2]),
                 decode_vd(pics[3]), DCONS / sc.bundled_range().astype(np.float64),
                 occlusion_truth(sc.scene_quads()), sc.scene_quads())


def motorcycle() -> Scene | None:
    try:
        from skimage.data import stereo_motorcycle
    except ImportError:
        return None
    from pre.digitize import digitize
    left, right, disp = stereo_motorcycle()
    l256 = digitize(np.ascontiguousarray(left[:, :, ::-1]), "crop")
    r256 = digitize(np.ascontiguousarray(right[:, :, ::-1]), "crop")
    gt = acc.gt_at_rig_scale(disp, acc.crop_map(*left.shape[:2]))
    return Scene("Middlebury motorcycle", condense(l256), condense(r256), l256, r256, gt, None)


def all_scenes(n_generated: int):
    yield bundled()
    m = motorcycle()
    if m is not None:
        yield m
    for s in range(1, n_generated + 1):
        yield rendered(f"generated room {s}", generated_quads(s), s)


# --- runs ----------------------------------------------------------------------

def faithful_scan(scene: Scene):
    from estar.program import in_process_rig
    from rig.scan import run_lines
    return run_lines(in_process_rig(scene.left_bi, scene.right_bi), SCAN_LINES)


@dataclass
class Edges:
    """Located edges of one method on one scene (lines 8..112)."""
    y: np.ndarray
    col: np.ndarray            # truth column of LOC1
    disp: np.ndarray
    conf: np.ndarray           # NaN for the 1985 mode
    nomatch_y: np.ndarray      # "no match" edges: row and pixel column
    nomatch_col: np.ndarray
    all_y: np.ndarray          # every left-slice edge considered
    all_col: np.ndarray
    verdicts: dict | None = None
    feature: np.ndarray | None = None   # (start, stop, lgrey, rgrey) of each located edge's
    #                                     left feature interval (the step it names)


def faithful_edges(scan) -> Edges:
    from rig.truth import truth_column
    pts = [p for p in scan.points if p.line in SCORE_LINES]
    located = {(p.line, p.edge) for p in pts}
    alle, nom = [], []
    for r in scan.results:
        if r.iyloc not in SCORE_LINES:
            continue
        for k, (start, stop, _, _) in enumerate(r.features1, start=1):
            for e, x in ((k, start), (k + 50, stop)):
                alle.append((r.iyloc, x - 1))
                if (r.iyloc, e) not in located:
                    nom.append((r.iyloc, x - 1))
    a = np.array(alle, dtype=int).reshape(-1, 2)
    n = np.array(nom, dtype=int).reshape(-1, 2)
    feats = {r.iyloc: r.features1 for r in scan.results}
    return Edges(np.array([p.line for p in pts], dtype=int),
                 np.array([truth_column(p.loc1) for p in pts], dtype=int),
                 np.array([p.disparity for p in pts], dtype=float),
                 np.full(len(pts), np.nan), n[:, 0], n[:, 1], a[:, 0], a[:, 1],
                 feature=np.array([feats[p.line][(p.edge - 1) % 50] for p in pts],
                                  dtype=float).reshape(-1, 4))


def improved_edges(scan, scene: Scene, constraints: Constraints, params: Params) -> Edges:
    from rig.truth import truth_column
    profiles = None
    if constraints.subpixel and scene.left_vd is not None:
        profiles = lambda y: (line_profile(scene.left_vd, y),           # noqa: E731
                              line_profile(scene.right_vd, y))
    verdicts = match_lines(scan.results, constraints, params, profiles)
    edges = edges_of(verdicts, {r.iyloc: r.features1 for r in scan.results})
    edges.verdicts = verdicts
    return edges


def edges_of(verdicts, features=None) -> Edges:
    """``features``: line -> its left feature list (for the truth at the step)."""
    from rig.truth import truth_column
    ys, cols, ds, cs, nom, alle, fs = [], [], [], [], [], [], []
    for y in SCORE_LINES:
        for v in verdicts.get(y, []):
            alle.append((y, v.x - 1))
            if v.matched and v.disparity_sub > 1:
                loc1 = v.loc1_sub if v.loc1_sub is not None else v.loc1
                ys.append(y)
                cols.append(truth_column(loc1))
                ds.append(v.disparity_sub)
                cs.append(v.confidence)
                if features is not None:
                    fs.append(features[y][(v.edge - 1) % 50])
            else:
                nom.append((y, v.x - 1))
    a = np.array(alle, dtype=int).reshape(-1, 2)
    n = np.array(nom, dtype=int).reshape(-1, 2)
    return Edges(np.array(ys, dtype=int), np.array(cols, dtype=int), np.array(ds), np.array(cs),
                 n[:, 0], n[:, 1], a[:, 0], a[:, 1],
                 feature=np.array(fs, dtype=float).reshape(-1, 4) if features is not None
                 else None)


HALFWIDTH = 1          # --halfwidth: truth at an edge over columns LOC1-1 +- this


def truth_at(scene: Scene, ys, cols) -> np.ndarray:
    return np.array([acc.true_disparity_at(scene.true_disp, int(y), int(c), HALFWIDTH)
                     for y, c in zip(ys, cols)], dtype=float)


# The second convention, "at the step".  EXQVFL's feature interval runs from
# the last pixel of its left grey to the first of its right grey, and both
# its ends (LOC1 = start or stop) name the one grey step between them.  At a
# depth boundary that step is the nearer surface's outline, but LOC1 - 1 +- 1
# may miss that surface: the interval's far end lies beyond the mixed pixel,
# and a mixed pixel's centre often sees the farther surface (most of
# generated room 4's edges more than 2 px wrong, docs/matching.md).  Here the truth
# is taken where the grey step is: where the left picture's .VD profile
# crosses halfway between the feature's greys (matching.subpixel's rule;
# the middle of the ramp where there is no clean crossing), and it is the
# nearest surface within STEP_HALF px of that point, from the scene's own
# geometry (rays traced through the row's centre, 5 per edge).  Only for
# scenes with geometry (the bundled pair and the generated rooms).
STEP_HALF = 0.5


def step_columns(scene: Scene, ys, features) -> np.ndarray:
    """The continuous 0-based column (pixel j spans [j, j+1)) of the grey
    step each feature ``(start, stop, lgrey, rgrey)`` of row ``ys`` names."""
    from matching.subpixel import step_position
    out = np.empty(len(ys))
    profiles = {}
    for k, (y, f) in enumerate(zip(ys, features)):
        y = int(y)
        if y not in profiles:
            profiles[y] = line_profile(scene.left_vd, y)
        start, stop, lg, rg = (int(v) for v in f)
        loc = step_position(profiles[y], start, stop, lg, rg)
        out[k] = (loc if loc is not None else (start + stop) / 2.0) - 0.5
    return out


def truth_at_step(scene: Scene, ys, features) -> np.ndarray:
    """True disparity of the nearest surface within STEP_HALF px of each
    edge's grey step (NaN for every edge of a scene without geometry)."""
    if scene.quads is None or scene.left_vd is None or features is None or not len(ys):
        return np.full(len(ys), np.nan)
    x = step_columns(scene, ys, features)
    u = 2.0 * (x[:, None] + np.linspace(-STEP_HALF, STEP_HALF, 5)[None, :])
    v = np.broadcast_to((2.0 * np.asarray(ys, dtype=float) + 1.0)[:, None], u.shape)
    px = np.ascontiguousarray((u - sc.CX) / sc.FOCAL_256)
    py = np.ascontiguousarray((v - sc.CY) / sc.FOCAL_256)
    z, _ = trace_rays(scene.quads, (sc.LEFT_X, 0.0, 0.0), (px, py, np.ones_like(px)))
    return (DCONS / z).max(axis=1)


@dataclass
class Score:
    located: int
    scored: int
    bad1: float
    bad2: float
    median: float
    within: float
    bm_bad2: float
    bm_n: int
    sgbm_bad2: float
    sgbm_n: int
    nm_precision: float
    nm_recall: float
    err: np.ndarray            # |disparity error| of scored edges
    conf: np.ndarray           # their confidence
    bad2_at_bm: float = float("nan")   # own bad-2.0 at the pixels where StereoBM answers
    step_bad2: float = float("nan")    # bad-2.0 against the truth at the step
    step_bm_bad2: float = float("nan")     # StereoBM's there, at the same pixels
    step_sgbm_bad2: float = float("nan")
    step_rescued: int = 0      # edges > 2 px off LOC1-1 +- 1's truth, within 2 px at the step


def score(scene: Scene, e: Edges, bm: np.ndarray, sgbm: np.ndarray) -> Score:
    td = truth_at(scene, e.y, e.col)
    ok = np.isfinite(td)
    err = np.abs(e.disp - td)[ok]
    m = acc.metrics(err)
    d = e.disp[ok]
    dp = DCONS / d
    ep = DCONS / (d * d - d)
    within = float(np.mean(np.abs(dp - DCONS / td[ok]) <= ep)) if ok.any() else float("nan")
    out = []
    for disp in (bm, sgbm):
        at = disp[e.y[ok], np.clip(e.col[ok], 0, 127)]
        sel = np.isfinite(at)
        bad = np.abs(at[sel] - td[ok][sel]) > 2
        out.append((float(np.mean(bad)) if sel.any() else float("nan"),
                    int(sel.sum())))
        if disp is bm:
            own_at_bm = float(np.mean(err[sel] > 2)) if sel.any() else float("nan")
    prec = rec = float("nan")
    if scene.occluded is not None:
        occ_nm = scene.occluded[e.nomatch_y, np.clip(e.nomatch_col, 0, 127)]
        occ_all = scene.occluded[e.all_y, np.clip(e.all_col, 0, 127)]
        prec = float(occ_nm.mean()) if occ_nm.size else float("nan")
        rec = float(occ_nm.sum() / occ_all.sum()) if occ_all.sum() else float("nan")
    ts = truth_at_step(scene, e.y, e.feature)
    step = [float("nan")] * 3
    rescued = 0
    sok = np.isfinite(ts)
    if sok.any():
        step[0] = float(np.mean(np.abs(e.disp[sok] - ts[sok]) > 2))
        for k, disp in enumerate((bm, sgbm), start=1):
            at = disp[e.y[sok], np.clip(e.col[sok], 0, 127)]
            sel = np.isfinite(at)
            if sel.any():
                step[k] = float(np.mean(np.abs(at[sel] - ts[sok][sel]) > 2))
        both = ok & sok
        rescued = int(np.sum((np.abs(e.disp[both] - td[both]) > 2)
                             & (np.abs(e.disp[both] - ts[both]) <= 2)))
    return Score(len(e.y), m.n, m.bad1, m.bad2, m.median_abs, within, out[0][0], out[0][1],
                 out[1][0], out[1][1], prec, rec, err, e.conf[ok], own_at_bm, *step, rescued)


DEFAULT = Constraints()                        # the default five: the four + confirm
BEFORE = replace(DEFAULT, confirm=False)       # the four: the default before 2026-12-01 14:10
FIVE = replace(BEFORE, readmit=True)           # the four + re-admission (no confirm)
TARGET = "the default five: the four + confirm"
FOUR = "the four (no confirm, the default before 2026-12-01 14:10)"
WITH_READMIT = "the four + re-admission (no confirm)"
ALL = Constraints(confirm=True, readmit=True, subpixel=True)   # rig scan --constraints all
WITH_ALL = "all seven (--constraints all: the default five + readmit, sub-pixel)"
VARIANTS = [
    ("1985 (default)", None),
    ("improved, no constraint, no minimum confidence", (Constraints.none(),
                                                        {"min_confidence": 0.0})),
    ("improved, no constraint", Constraints.none()),
    ("order (uniqueness + 1-1 DP) alone", Constraints.only("order")),
    ("left-right consistency alone", Constraints.only("lr")),
    ("neighbouring lines alone", Constraints.only("neighbours")),
    ("region first alone", Constraints.only("region")),
    ("re-admission alone", Constraints.only("readmit")),
    ("confirm alone", Constraints.only("confirm")),
    ("sub-pixel alone", Constraints.only("subpixel")),
    ("the four, no width term (as before re-admission)", (BEFORE, {"width_penalty": 0.0})),
    (FOUR, BEFORE),
    (TARGET, DEFAULT),
    ("the four + re-admission, no width term", (FIVE, {"width_penalty": 0.0})),
    (WITH_READMIT, FIVE),
    ("the four, neighbours from IY-2..IY+2", (BEFORE, {"neighbour_reach": 2})),
    ("the four + re-admission, lines assigned again with the neighbours' support "
     "(rematch_bonus 64)",
     (FIVE, {"rematch_bonus": 64.0})),
    ("the default five, confirm from two lines of IY-5..IY+5 in two passes",
     (DEFAULT, {"confirm_support": 2, "confirm_reach": 5, "confirm_rounds": 2})),
    ("the default five, neighbours from IY-2..IY+2", (DEFAULT, {"neighbour_reach": 2})),
    ("the four, region strict", (BEFORE, {"region_penalty": None})),
    ("the four + sub-pixel", replace(BEFORE, subpixel=True)),
    ("the default five + sub-pixel", replace(DEFAULT, subpixel=True)),
    ("the default five, the farther of disagreeing ends dropped",
     (DEFAULT, {"drop_farther_end": True})),
    (WITH_ALL, ALL),
]
DIAGNOSED = (FOUR, TARGET)
REASONS = ("matched", "confirmed", "readmitted", "occluded", "not mutual", "no region partner",
           "not on a vertical line", "ambiguous", "ends disagree", "no candidate")


def diagnosis(scene: Scene, verdicts, datas, params: Params) -> dict[str, tuple[int, int, int]]:
    """Per verdict reason on lines 8..112: (edges, edges whose partner was
    right, edges with some right candidate).  "Right" is bad-2.0's rule
    (within 2 px of the truth at the edge's own column).  A match, or a match
    dropped afterwards (not on a vertical line, ambiguous), is judged by its
    partner; an edge the assignment or the lr/region rules left out by its
    cheapest candidate."""
    from matching.candidates import candidates
    out: dict[str, list[int]] = {}
    for y in SCORE_LINES:
        if y not in datas:
            continue
        d = datas[y]
        c = candidates(d.features1, d.features2, d.maps1, d.maps2, use_shift=params.use_shift,
                       grey_penalty=params.grey_penalty, width_penalty=params.width_penalty)
        for v in verdicts.get(y, []):
            td = acc.true_disparity_at(scene.true_disp, y, v.x - 1, HALFWIDTH)
            row = out.setdefault(v.reason, [0, 0, 0])
            row[0] += 1
            if not np.isfinite(td):
                continue
            ks = np.flatnonzero(c.left.edge[c.i] == v.edge)
            if v.partner:
                disp = v.disparity
            elif len(ks):
                disp = float(c.disp[ks[np.argmin(c.cost[ks])]])
            else:
                disp = None
            row[1] += disp is not None and abs(disp - td) <= 2
            row[2] += bool(len(ks)) and bool(np.any(np.abs(c.disp[ks] - td) <= 2))
    return {k: tuple(v) for k, v in out.items()}


def wrong_edges(scene: Scene, verdicts, features) -> dict[str, int]:
    """The located edges more than 2 px off bench/accuracy.py's truth (LOC1-1
    +- 1), sorted by why: "right at the step" (within 2 px of the truth at
    the edge's grey step: the step is the nearer surface's outline, beyond
    the columns LOC1-1 +- 1 looks at), "ends disagree" (otherwise, where the
    feature's other end is matched to the same right feature at a disparity
    more than 2 px away: a face one camera sees inside the ramp), "wrong"
    (the rest: a wrong partner)."""
    from rig.truth import truth_column
    out = {"located": 0, "wrong by LOC1-1 +- 1": 0, "right at the step": 0,
           "ends disagree": 0, "wrong": 0}
    for y in SCORE_LINES:
        line = verdicts.get(y, [])
        ends = {((v.edge - 1) % 50, (v.partner - 1) % 50, v.edge > 50): v
                for v in line if v.matched}
        for v in line:
            if not (v.matched and v.disparity_sub > 1):
                continue
            loc1 = v.loc1_sub if v.loc1_sub is not None else v.loc1
            td = acc.true_disparity_at(scene.true_disp, y, truth_column(loc1), HALFWIDTH)
            if not np.isfinite(td):
                continue
            out["located"] += 1
            if abs(v.disparity_sub - td) <= 2:
                continue
            out["wrong by LOC1-1 +- 1"] += 1
            ts = truth_at_step(scene, [y], [features[y][(v.edge - 1) % 50]])[0]
            other = ends.get(((v.edge - 1) % 50, (v.partner - 1) % 50, v.edge <= 50))
            if np.isfinite(ts) and abs(v.disparity_sub - ts) <= 2:
                out["right at the step"] += 1
            elif other is not None and abs(other.disparity - v.disparity) > 2:
                out["ends disagree"] += 1
            else:
                out["wrong"] += 1
    return out


def evidence_table(evidence) -> str:
    keys = ("located", "wrong by LOC1-1 +- 1", "right at the step", "ends disagree", "wrong")
    head = "| scene | " + " | ".join(keys) + " |\n|" + "---|" * (1 + len(keys))
    return head + "\n" + "\n".join(
        f"| {scene} | " + " | ".join(str(ev[k]) for k in keys) + " |"
        for scene, ev in evidence.items())


def num_disparities(scene: Scene) -> int:
    """OpenCV's search range: the next multiple of 16 above the scene's largest
    true disparity on the scored lines (16 for the motorcycle, as in
    bench/accuracy.py; 48 for the bundled lab, whose waste bin is 38 px)."""
    top = float(np.nanmax(scene.true_disp[SCORE_LINES.start:SCORE_LINES.stop]))
    return int(16 * (np.floor(top / 16) + 1))


def run(n_generated: int, params: Params, progress: bool = True):
    import cv2
    cv2.setNumThreads(1)
    results = {}          # scene name -> [(variant, Score)]
    faithful_counts = {}
    diagnoses = {}        # scene name -> {variant: diagnosis}
    evidence = {}         # scene name -> wrong_edges() of the default five
    for scene in all_scenes(n_generated):
        if progress:
            print(f"  {scene.name} ...", file=sys.stderr, flush=True)
        scan = faithful_scan(scene)
        num = num_disparities(scene)
        bm = acc.matcher_disparity(acc.make_bm(num=num), scene.left_bi, scene.right_bi)
        sgbm = acc.matcher_disparity(acc.make_sgbm(num=num), scene.left_bi, scene.right_bi)
        rows = []
        for name, cons in VARIANTS:
            p = params
            if isinstance(cons, tuple):
                cons, changes = cons
                p = replace(params, **changes)
            e = faithful_edges(scan) if cons is None else improved_edges(scan, scene, cons, p)
            rows.append((name, score(scene, e, bm, sgbm)))
            if name in DIAGNOSED:
                from matching import LineData
                datas = {r.iyloc: LineData.of(r) for r in scan.results}
                diagnoses.setdefault(scene.name, {})[name] = diagnosis(scene, e.verdicts,
                                                                       datas, p)
            if name == TARGET and scene.quads is not None:
                evidence[scene.name] = wrong_edges(
                    scene, e.verdicts, {r.iyloc: r.features1 for r in scan.results})
        faithful_counts[scene.name] = rows[0][1].located
        results[scene.name] = rows
    return results, faithful_counts, diagnoses, evidence


# --- report --------------------------------------------------------------------

def pct(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{100 * x:.1f}"


def table(results, faithful) -> str:
    head = ("| scene | matcher | located (of 1985's) | bad-1.0 % | bad-2.0 % | median px | "
            "within ep % | StereoBM bad-2.0 % there (n) | StereoSGBM bad-2.0 % there (n) | "
            "no match: precision % / recall % | at the step: bad-2.0 % / StereoBM |")
    out = [head, "|" + "---|" * 11]
    for scene, rows in results.items():
        for name, s in rows:
            keep = f"{s.located} ({100 * s.located / max(1, faithful[scene]):.0f} %)"
            nm = ("-" if not np.isfinite(s.nm_precision)
                  else f"{pct(s.nm_precision)} / {pct(s.nm_recall)}")
            out.append(f"| {scene} | {name} | {keep} | {pct(s.bad1)} | {pct(s.bad2)} | "
                       f"{s.median:.2f} | {pct(s.within)} | {pct(s.bm_bad2)} ({s.bm_n}) | "
                       f"{pct(s.sgbm_bad2)} ({s.sgbm_n}) | {nm} | "
                       + ("-" if not np.isfinite(s.step_bad2)
                          else f"{pct(s.step_bad2)} / {pct(s.step_bm_bad2)}") + " |")
    return "\n".join(out)


def targets(results, faithful, variant: str = TARGET) -> str:
    """The issue's target per scene for ``variant``, under bench/accuracy.py's
    truth (LOC1-1 +- 1) and, where the scene has geometry, at the step."""
    lines = []
    for scene, rows in results.items():
        s = dict(rows)[variant]
        keep = s.located / max(1, faithful[scene])
        verdict = ("met" if (s.bad2 <= s.bm_bad2 and keep >= 0.6) else "NOT met")
        stretch = "met" if s.bad2 <= s.sgbm_bad2 else "not met"
        if np.isfinite(s.step_bad2):
            at_step = ("met" if (s.step_bad2 <= s.step_bm_bad2 and keep >= 0.6)
                       else "NOT met")
            step = (f"{pct(s.step_bad2)} / {pct(s.step_bm_bad2)} / {pct(s.step_sgbm_bad2)} | "
                    f"{at_step} | {s.step_rescued}")
        else:
            step = "- | - | -"
        lines.append(f"| {scene} | {pct(s.bad2)} | {pct(s.bm_bad2)} | {pct(s.sgbm_bad2)} | "
                     f"{100 * keep:.1f} % | {verdict} | {stretch} | {pct(s.bad2_at_bm)} | "
                     f"{step} |")
    return ("| scene | bad-2.0 % | StereoBM there | StereoSGBM there | edges kept | "
            "target (<= BM, >= 60 %) | stretch (<= SGBM) | bad-2.0 % where StereoBM answers | "
            "at the step: bad-2.0 % / StereoBM / StereoSGBM | target at the step | "
            "wrong by LOC1-1 +- 1, right at the step |"
            "\n|---|---|---|---|---|---|---|---|---|---|---|\n" + "\n".join(lines))


def diagnosis_table(diagnoses) -> str:
    """Per scene and diagnosed variant: edges per verdict reason, "n (right;
    some)": right = the partner (or cheapest candidate) within 2 px of the
    truth, some = a right candidate among all of the edge's."""
    head = ("| scene | matcher | " + " | ".join(REASONS) + " |\n|" + "---|" * (2 + len(REASONS)))
    out = [head]
    for scene, by_variant in diagnoses.items():
        for name, d in by_variant.items():
            cells = [f"{d[r][0]} ({d[r][1]}; {d[r][2]})" if r in d else "-" for r in REASONS]
            short = "the four" if name == DIAGNOSED[0] else "the default five"
            out.append(f"| {scene} | {short} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def reliability(results, variant=TARGET, bins=10, scenes=None):
    """Pooled over ``scenes`` (all when None): (lo, hi, count, wrong share
    |err| > 1) per confidence bin."""
    pick = [rows for name, rows in results.items() if scenes is None or name in scenes]
    err = np.concatenate([dict(rows)[variant].err for rows in pick])
    conf = np.concatenate([dict(rows)[variant].conf for rows in pick])
    edges = np.linspace(0, 1, bins + 1)
    out = []
    for k in range(bins):
        sel = (conf >= edges[k]) & ((conf < edges[k + 1]) if k < bins - 1 else (conf <= 1))
        out.append((edges[k], edges[k + 1], int(sel.sum()),
                    float(np.mean(err[sel] > 1)) if sel.any() else float("nan")))
    return out


def reliability_picture(series, title: str, reference: float | None = None) -> np.ndarray:
    """Bars: share of wrong matches (|error| > 1 px) per confidence bin, one
    colour per series ``[(label, rows), ...]`` with counts; ``reference``: the
    1985 mode's wrong share over all its edges, drawn across."""
    import cv2
    from rig.pictures import _text, BLACK, GRID, WHITE
    colours = ((60, 60, 200), (200, 130, 40))
    W, H, L, T, B = 760, 470, 84, 78, 96
    img = np.full((H, W, 3), WHITE, dtype=np.uint8)
    pw, ph = W - L - 30, H - T - B
    for k in range(0, 101, 20):
        y = T + ph - int(ph * k / 100)
        cv2.line(img, (L, y), (L + pw, y), GRID, 1)
        _text(img, f"{k} %", (L - 52, y + 5), 0.45)
    nb = len(series[0][1])
    bw = pw / nb
    sub = (bw - 8) / len(series)
    for s_idx, (label, rows) in enumerate(series):
        for k, (lo, hi, n, wrong) in enumerate(rows):
            x0 = int(L + k * bw + 4 + s_idx * sub)
            x1 = int(x0 + sub - 2)
            if np.isfinite(wrong):
                y = T + ph - int(ph * wrong)
                cv2.rectangle(img, (x0, y), (x1, T + ph), colours[s_idx], -1)
                _text(img, f"{100 * wrong:.0f}", (x0, y - 5), 0.36)
            _text(img, f"{n}", (x0, T + ph + 34 + 14 * s_idx), 0.33, colour=colours[s_idx])
        lx = L + 10 + 300 * s_idx
        cv2.rectangle(img, (lx, 56), (lx + 14, 68), colours[s_idx], -1)
        _text(img, label, (lx + 20, 68), 0.42)
    for k in range(nb + 1):
        _text(img, f"{k / nb:.1f}", (int(L + k * bw) - 8, T + ph + 18), 0.4)
    _text(img, "matches per bin:", (4, T + ph + 34), 0.33)
    cv2.rectangle(img, (L, T), (L + pw, T + ph), BLACK, 1)
    if reference is not None and np.isfinite(reference):
        y = T + ph - int(ph * reference)
        for x in range(L, L + pw, 12):
            cv2.line(img, (x, y), (min(x + 6, L + pw), y), BLACK, 2)
        for x in range(L + 480, L + 510, 12):
            cv2.line(img, (x, 62), (x + 6, 62), BLACK, 2)
        _text(img, f"1985 mode: {100 * reference:.0f} % wrong", (L + 516, 68), 0.42)
    _text(img, title, (L, 24), 0.55)
    _text(img, "share of matches more than 1 px wrong (%), by confidence", (L, 44), 0.42)
    _text(img, "confidence", (L + pw // 2 - 40, H - 10), 0.5)
    return img


def scan_times(repeat: int = 5) -> dict[str, float]:
    """Median seconds of a whole scan of the bundled pair (lines 8..112, direct
    link, NSTAR included) with ESTAR's 1985 lists and with the improved
    matcher (its default five constraints, and the four without confirm),
    measured in this run."""
    import statistics
    import time
    from matching.mode import ImprovedMatcher
    from rig.scan import scan_pair
    s = bundled()
    out = {}
    for name, make in (("1985", lambda: None), ("improved", ImprovedMatcher),
                       ("four", lambda: ImprovedMatcher(BEFORE))):
        scan_pair(s.left_bi, s.right_bi, matcher=make())            # warm (numba, caches)
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            scan_pair(s.left_bi, s.right_bi, matcher=make())
            times.append(time.perf_counter() - t)
        out[name] = statistics.median(times)
    return out


def params_from(pairs) -> Params:
    """``["readmit_rounds=3", ...]`` -> Params with those fields changed
    (values read as the field's type; ``none`` for an optional one)."""
    base = Params()
    changes = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        name = name.strip()
        if not sep or not hasattr(base, name):
            raise ValueError(f"--param {pair!r}: want NAME=VALUE with NAME one of "
                             + ", ".join(f.name for f in fields(Params)))
        old = getattr(base, name)
        try:
            if text.strip().lower() == "none":
                value = None
            elif isinstance(old, bool):
                value = text.strip().lower() in ("1", "true", "yes")
            elif isinstance(old, int):
                value = int(text)
            else:
                value = float(text)
        except ValueError:
            raise ValueError(f"--param {pair!r}: {text!r} is not a number") from None
        changes[name] = value
    return replace(base, **changes)


def write_out(path: Path, block: str) -> None:
    text = path.read_text() if path.exists() else ""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + BEGIN + "\n" + block + "\n" + END + rest.split(END, 1)[1]
    else:
        text = BEGIN + "\n" + block + "\n" + END + "\n"
    write_atomic(path, text.encode())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", type=int, default=6, help="generated rooms (default 6)")
    ap.add_argument("--out", type=Path, help="write the tables into this Markdown file "
                                             "(between the matching-table markers)")
    ap.add_argument("--picture", type=Path, help="write the reliability picture (PNG)")
    ap.add_argument("--halfwidth", type=int, default=1,
                    help="truth at an edge = largest true disparity over LOC1-1 +- this "
                         "(default 1, bench/accuracy.py's rule)")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                    help="change one of matching.Params for every improved row, e.g. "
                         "--param readmit_rounds=3 (repeatable)")
    args = ap.parse_args(argv)
    try:
        params = params_from(args.param)
    except ValueError as e:
        print(f"matching: {e}", file=sys.stderr)
        return 2
    global HALFWIDTH
    HALFWIDTH = args.halfwidth
    if args.scenes < 5:
        print(f"matching: --scenes {args.scenes}: the benchmark wants at least 5", file=sys.stderr)
        return 2
    results, faithful, diagnoses, evidence = run(args.scenes, params)
    rel = reliability(results)
    real = [n for n in results if not n.startswith("generated")]
    gen = [n for n in results if n.startswith("generated")]
    rel_real, rel_gen = reliability(results, scenes=real), reliability(results, scenes=gen)
    times = scan_times()
    cmd = "python bench/bench_matching.py" + (f" --scenes {args.scenes}" if args.scenes != 6 else "")
    if args.halfwidth != 1:
        cmd += f" --halfwidth {args.halfwidth}"
    cmd += "".join(f" --param {a}" for a in args.param)
    if args.out:
        cmd += f" --out {args.out}"
    if args.picture:
        cmd += f" --picture {args.picture}"
    rel_text = ("| confidence | matches | more than 1 px wrong | bundled + motorcycle | "
                "wrong there | generated rooms | wrong there |\n|---|---|---|---|---|---|---|\n"
                + "\n".join(
                    f"| {a[0]:.1f} - {a[1]:.1f} | {a[2]} | {pct(a[3])} % | {b[2]} | {pct(b[3])} % "
                    f"| {c[2]} | {pct(c[3])} % |" for a, b, c in zip(rel, rel_real, rel_gen)))
    have_moto = any("motorcycle" in k for k in results)
    block = "\n\n".join([
        table(results, faithful),
        "Targets, the default five (the four + confirm: `--match improved` with no "
        "`--constraints`).  *At the step*: a second truth, taken "
        "where the edge's grey step is (the left .VD profile's halfway crossing, the "
        "nearest surface within half a pixel of it, from the scene's geometry; "
        "`truth_at_step` in the script), beside bench/accuracy.py's LOC1-1 +- 1; the last "
        "column counts the edges the first calls more than 2 px wrong and the second "
        "within 2 px:\n\n" + targets(results, faithful),
        "Targets, the four (no confirm, the default before 2026-12-01 14:10: "
        "`--constraints order,lr,neighbours,region`):\n\n"
        + targets(results, faithful, FOUR),
        "Targets, all seven constraints (`--constraints all`: the default five + readmit, "
        "sub-pixel):\n\n" + targets(results, faithful, WITH_ALL),
        "Why the located edges of the default five are more than 2 px off bench/accuracy.py's "
        "truth (`wrong_edges` in the script; scenes with geometry):\n\n" + evidence_table(evidence),
        "Why edges get no match, and how many of them were in fact right: edges per "
        "verdict, n (right; some), where right = the partner (for a match, or one dropped "
        "afterwards by the neighbour or ambiguity rule) or else the cheapest candidate "
        "within 2 px of the truth, some = a right one among all its candidates; the four = "
        "without confirm (the default before 2026-12-01), the default five = with the "
        "confirm pass:\n\n" + diagnosis_table(diagnoses),
        "Reliability, the default five constraints (the four + confirm), all scenes "
        "pooled:\n\n" + rel_text,
        ("" if have_moto else "The motorcycle pair was left out: scikit-image is not "
                              "installed (`pip install -e .[bench]`).\n\n")
        + f"Whole scan of the bundled pair (lines 8..112, direct link, median of 5): "
          f"1985 {1000 * times['1985']:.0f} ms, improved (the default five) "
          f"{1000 * times['improved']:.0f} ms ({times['improved'] / times['1985']:.1f} x), "
          f"the four (no confirm) {1000 * times['four']:.0f} ms "
          f"({times['four'] / times['1985']:.1f} x).\n\n"
        + f"Parameters: {params}.\n\nMade by `{cmd}`."])
    print(block)
    if args.out:
        write_out(args.out, block)
    if args.picture:
        from rig.pictures import save_png
        base = np.concatenate([dict(rows)["1985 (default)"].err for rows in results.values()])
        save_png(args.picture, reliability_picture(
            [(" + ".join(n.split()[-1] if "motorcycle" in n else "bundled pair" for n in real),
              rel_real), ("generated rooms", rel_gen)],
            "Improved matcher, the default five constraints (the four + confirm)",
            float(np.mean(base > 1))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
