"""Free floor from what the picture shows (planner.appearance): the floor
point of each pixel by hand, the floor run of a column, the proven strip's
geometry, and, on a rendered look of the tiny room, against the world's truth
(which surface each pixel shows, where the box stands)."""

import math

import numpy as np
import pytest

from planner.appearance import (BOUNDING, ROWS, STAND_INS, floor_end, floor_greys, floor_proof, floor_rays,
                                floor_run, keep_before_hit, nearest_greys, run_reach,
                                training_mask, vetoed)
from planner.floormap import FREE, OCCUPIED, empty_map
from planner.tiny import BOX, tiny_room
from rig.scan import Point
from world.pose import Pose
from world.render import render_look

PITCH = -25.0
H = 3.0


def _look():
    room = tiny_room()
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    return room, pose, render_look(room, pose, seed=7, supersample=2)


def test_floor_point_of_a_pixel_by_hand():
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    # the bottom row's centre: 25 deg + atan(59.5 / 180) below the horizon, 3 ft up
    down = math.radians(25.0) + math.atan(59.5 / 180.0)
    assert rays.dist[119, 63:65].mean() == pytest.approx(H / math.tan(down), rel=2e-3)
    # a row above the horizon's depression meets the floor farther on; the
    # distance grows upward, row by row
    assert (np.diff(rays.dist[:, 64]) < 0).all()
    # the ray through the picture's centre: 25 deg down, along the heading (+Z)
    c = pose.camera_centre("left")
    assert rays.z[59:61, 63:65].mean() == pytest.approx(H / math.tan(math.radians(25.0)), rel=1e-2)
    assert rays.x[59:61, 63:65].mean() == pytest.approx(c[0], abs=0.02)


def test_floor_run_of_a_column():
    pic = np.full((ROWS, 128), 9, np.uint8)
    pic[70:, 10] = 6                       # floor from row 70 down
    pic[:, 20] = 6                         # floor all the way up
    pic[:, 30] = 6
    pic[119, 30] = 2                       # the bottom row is not floor
    greys = np.zeros(16, bool)
    greys[6] = True
    top = floor_run(pic, greys)
    # the run's own top pixel is left out (it may straddle what stands on the floor)
    assert top[10] == 71 and top[20] == 1 and top[30] == ROWS and top[0] == ROWS


def test_floor_greys_need_enough_samples_and_a_share():
    h = np.zeros(16)
    h[5] = 150
    assert floor_greys(h) is None                      # fewer than 200 samples
    h[5], h[7], h[12] = 900, 300, 20
    g = floor_greys(h)
    assert np.flatnonzero(g).tolist() == [5, 7]        # 12 has 1.6 %, under the 10 % share


def test_proof_runs_from_the_near_limit_to_the_run_and_the_clip():
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    top = np.full(128, ROWS)
    top[64] = 60                                       # floor seen up to row 60 in one column
    res, h = 0.25, 0.8
    clip = np.full(128, 100.0)
    pts, ray, dist, proving = floor_proof(rays, top, clip, h, res)
    assert proving.all()                               # no lead-in: every sample proves
    # an obstacle h tall nearer than d (1 - h / H) would not hide the floor at
    # d: from the bottom row's d_b (1 - h / H) = 2.33 ft on (the near limit)
    d_b = rays.dist[119, 64]
    assert dist.min() == pytest.approx(d_b * (1 - h / H), abs=1e-9)
    assert dist.max() <= rays.dist[60, 64] - res + 1e-9
    assert dist.max() >= rays.dist[60, 64] - res - res / 2
    # cut at the column's clip
    clip[64] = 4.0
    _, _, dist, _ = floor_proof(rays, top, clip, h, res)
    assert dist.max() <= 4.0 - res + 1e-9
    # no run, no proof
    assert floor_proof(rays, np.full(128, ROWS), clip, h, res) is None


def test_the_proofs_rays_and_steps_equal_the_column_by_column_ones():
    """floor_proof's rows and steps, made array-wise, against the loops it
    was written with: a column, then a ray, at a time."""
    from planner.appearance import proof_rows, ray_steps
    rng = np.random.default_rng(11)
    compared = 0
    for _ in range(20):
        top = rng.integers(1, ROWS + 1, 128)
        top[rng.random(128) < 0.3] = ROWS                 # columns without a run
        for row_step in (1, 4):
            rr, cc = [], []
            for c in np.flatnonzero(top < ROWS):
                rows = np.unique(np.concatenate([np.arange(top[c], ROWS, row_step),
                                                 [top[c], ROWS - 1]]))
                rr.append(rows)
                cc.append(np.full(len(rows), c))
            got = proof_rows(top, row_step)
            for a, b in zip(got, (np.concatenate(rr), np.concatenate(cc)), strict=True):
                assert a.dtype == b.dtype and np.array_equal(a, b)
            compared += len(got[0])
        n = rng.integers(0, 30, 400)
        lead = np.where(n > 0, rng.integers(0, 20, 400), 0)
        for lead_in in (lead, np.zeros(400, int)):
            ray, k = ray_steps(lead_in, n)
            assert np.array_equal(ray, np.repeat(np.arange(400), n + lead_in))
            want = np.concatenate([np.arange(-a, m) for a, m in zip(lead_in, n)])
            assert k.dtype == want.dtype and np.array_equal(k, want)
    assert compared > 10000
    assert len(proof_rows(np.full(128, ROWS), 4)[0]) == 0
    pose = Pose(0.3, -0.7, 20.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    assert floor_proof(rays, np.full(128, ROWS), np.full(128, 9.0), 0.8, 0.25) is None


def test_a_lead_in_stops_a_proof_that_lies_past_a_hit_nearer_than_its_trace():
    """proof_hits="line" (room 293): a box 1.25 ft ahead, nearer than the
    picture's bottom row, whose face of the floor's grey fills the bottom
    rows.  Its hit cell lies before every trace (which starts 2.33 ft
    out), so the trace alone never meets it; the lead-in does, and no
    proving sample past it is kept.  The proving samples are the same
    with or without the lead-in."""
    from planner.octree import cell_keys
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    top = np.full(128, ROWS)
    top[64] = 60
    res, h = 0.25, 0.8
    clip = np.full(128, 100.0)
    pts, ray, dist, _ = floor_proof(rays, top, clip, h, res)
    lpts, lray, ldist, proving = floor_proof(rays, top, clip, h, res, lead_in=True)
    assert ldist[proving] == pytest.approx(dist) and lray[proving].tolist() == ray.tolist()
    for k in np.unique(lray):             # each ray led in from its camera's foot
        lead, trace = ldist[(lray == k) & ~proving], ldist[(lray == k) & proving]
        assert lead.min() < res / 2 and lead.max() < trace.min()
        assert np.diff(np.sort(ldist[lray == k])) == pytest.approx(res / 2)   # one spacing
    hit = cell_keys(np.array([[rays.origin[0], rays.origin[1], rays.origin[2] + 1.25]]), res)
    keys, lkeys = cell_keys(pts, res), cell_keys(lpts, res)
    assert keep_before_hit(keys, ray, hit).all()                      # the trace misses it
    kept = keep_before_hit(lkeys, lray, hit) & proving
    assert not kept.any()                                             # the line does not
    assert floor_proof(rays, np.full(128, ROWS), clip, h, res, lead_in=True) is None


def test_a_proof_stops_before_the_first_hit_cell_of_its_ray():
    keys = np.array([1, 2, 3, 4, 10, 11, 12])
    ray = np.array([0, 0, 0, 0, 1, 1, 1])
    keep = keep_before_hit(keys, ray, [3, 10])
    assert keep.tolist() == [True, True, False, False, False, False, False]
    assert keep_before_hit(keys, ray, []).all()


def test_training_pixels_need_their_whole_hiding_stretch_free():
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    fm = empty_map((-8.0, 8.0, -2.0, 14.0), 0.25, fill=FREE)
    all_free = training_mask(rays, fm, 0.8)
    assert all_free[119].all() and not all_free[0].any()     # the top row is 25 ft out
    fm.cells[fm.index(0.0, 5.0)] = OCCUPIED
    some = training_mask(rays, fm, 0.8)
    lost = all_free & ~some
    assert lost.any()
    # every pixel lost has the occupied cell on its stretch d (1 - h/H) .. d
    r, c = np.nonzero(lost)
    d = rays.dist[r, c]
    x, z = rays.x[r, c], rays.z[r, c]
    o = rays.origin
    to_cell = np.hypot(0.125 - o[0], 5.125 - o[2])
    assert (d * (1 - 0.8 / H) <= to_cell + 0.4).all() and (d >= to_cell - 0.4).all()


def _cells_free(fm, x, z):
    """Which points (x, z) lie in a FREE cell of the map, array-wise (as
    planner.appearance judged them before the trace was compiled)."""
    i = np.floor((z - fm.z0) / fm.cell)
    j = np.floor((x - fm.x0) / fm.cell)
    ok = np.isfinite(i) & np.isfinite(j)
    i = np.where(ok, i, -1).astype(int)
    j = np.where(ok, j, -1).astype(int)
    inside = ok & (i >= 0) & (j >= 0) & (i < fm.shape[0]) & (j < fm.shape[1])
    out = np.zeros(np.shape(x), bool)
    out[inside] = fm.cells[i[inside], j[inside]] == FREE
    return out


def _training_mask_step_by_step(rays, known, lowest_ft, max_ft=12.0, whole_trace=False):
    """training_mask as it was written before its trace was compiled: every
    pixel still in, one step of the trace at a time."""
    from planner.appearance import training_traces
    ok, steps = training_traces(rays, known.cell, lowest_ft, max_ft, whole_trace)
    idx = np.flatnonzero(ok)
    fx, fz = rays.x.ravel(), rays.z.ravel()
    for s in steps:
        x = rays.origin[0] + s * (fx[idx] - rays.origin[0])
        z = rays.origin[2] + s * (fz[idx] - rays.origin[2])
        idx = idx[_cells_free(known, x, z)]
    out = np.zeros(ok.size, bool)
    out[idx] = True
    return out.reshape(ok.shape)


@pytest.mark.parametrize("whole_trace", [False, True])
def test_the_compiled_training_trace_equals_the_step_by_step_one(whole_trace):
    """Random maps and camera poses, some cells on a trace's very edge: the
    same pixels, compiled (numba) and as plain Python."""
    import planner.appearance as appearance
    rng = np.random.default_rng(3)
    kept = partial = 0
    for k in range(12):
        pose = Pose(float(rng.uniform(-2, 2)), float(rng.uniform(-2, 2)),
                    float(rng.uniform(-180, 180)), PITCH)
        rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
        fm = empty_map((-10.0, 10.0 - 0.25 * (k % 3), -10.0, 14.0), 0.25, fill=FREE)
        fm.cells[rng.random(fm.cells.shape) < 0.01 * (k % 4)] = OCCUPIED
        want = _training_mask_step_by_step(rays, fm, 0.8, whole_trace=whole_trace)
        got = training_mask(rays, fm, 0.8, whole_trace=whole_trace)
        assert np.array_equal(got, want)
        plain = getattr(appearance._trace_free, "py_func", None)
        if plain is not None and k < 2:
            original = appearance._trace_free
            appearance._trace_free = plain
            try:
                assert np.array_equal(training_mask(rays, fm, 0.8, whole_trace=whole_trace),
                                      want)
            finally:
                appearance._trace_free = original
        kept += int(got.sum())
        partial += 0 < got.sum() < _training_mask_step_by_step(
            rays, empty_map((-10.0, 10.0, -10.0, 14.0), 0.25, fill=FREE), 0.8,
            whole_trace=whole_trace).sum()
    assert kept > 1000 and partial >= 3              # occupied cells cut some pixels


def test_the_floor_run_of_a_rendered_look_shows_only_floor():
    """Against the world's truth: the tiny room's floor is grey 6 and nothing
    else in the look shares it, so every pixel of every run shows the floor
    quad, and the proof stays out of the box and inside the walls."""
    room, pose, look = _look()
    floor_q = [k for k, q in enumerate(room.quads) if q.name == "floor"]
    greys = np.zeros(16, bool)
    greys[6] = True
    top = floor_run(look.left_bi, greys)
    assert (top < ROWS).sum() > 100                   # most columns show floor
    rows = np.arange(ROWS)[:, None]
    in_run = rows >= top[None, :]
    assert np.isin(look.surface_left[in_run], floor_q).all()
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    pts, _, _, _ = floor_proof(rays, top, np.full(128, 12.0), 0.8, 0.25)
    (bx0, bx1), _, (bz0, bz1) = BOX
    inside_box = (pts[:, 0] > bx0) & (pts[:, 0] < bx1) & (pts[:, 2] > bz0) & (pts[:, 2] < bz1)
    assert not inside_box.any()
    x0, x1, z0, z1 = room.bounds
    assert ((pts[:, 0] > x0) & (pts[:, 0] < x1) & (pts[:, 2] > z0) & (pts[:, 2] < z1)).all()


@pytest.mark.parametrize("x, z", [(1.0, 0.0), (1.7, 0.5)])
def test_the_floor_seen_past_a_boxs_edge_frees_no_cell_of_it_under_shadows(x, z):
    """The floor in view beside the tiny room's box (x 1.2-2.6, z 3.5-4.5),
    from the left of its left face (the left camera at x 0.625, the face
    seen) and from behind its front (x 1.325, the front 3 ft away, nearer
    than the bottom row's floor at 3.2 ft: no floor in those columns, as in
    room 230), on a grid offset 0.15 ft in x (the face 0.05 ft into the cell
    x 1.15-1.4, which it covers four fifths of: a box is seldom on the grid).
    A proof sample anywhere frees such a cell ("any"); less the cells in the
    shadows of the look's run ends (:func:`run_shadows`, "shadows") the proof
    frees no cell the box covers half of, and keeps nine tenths of its cells."""
    from planner.appearance import run_shadows
    from planner.octree import cell_keys, unpack
    room = tiny_room()
    pose = Pose(x, z, 0.0, PITCH)
    look = render_look(room, pose, seed=7, supersample=2)
    greys = np.zeros(16, bool)
    greys[6] = True
    top = floor_run(look.left_bi, greys, bridge=True)      # as the loop bounds (bridged)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    shift = np.array([0.15, 0.0, 0.0])
    (bx0, bx1), _, (bz0, bz1) = BOX

    def box_share(keys):
        k = unpack(np.unique(keys))
        x0, z0 = k[:, 0] * 0.25 + 0.15, k[:, 2] * 0.25
        wx = np.clip(np.minimum(x0 + 0.25, bx1) - np.maximum(x0, bx0), 0, None)
        wz = np.clip(np.minimum(z0 + 0.25, bz1) - np.maximum(z0, bz0), 0, None)
        return wx * wz / 0.0625

    pts, _, _, _ = floor_proof(rays, top, np.full(128, 12.0), 0.8, 0.25)
    keys = cell_keys(pts - shift, 0.25)
    assert box_share(keys).max() == pytest.approx(0.8)     # the cells x 1.15-1.4
    shadows = cell_keys(run_shadows(rays, top, 0.25, 0.8) - shift, 0.25)
    kept = keys[~np.isin(keys, shadows)]
    assert box_share(kept).max() < 0.5
    assert len(np.unique(kept)) > 0.85 * len(np.unique(keys))


def test_run_shadows_by_hand():
    """A level-ish look's shadows: a column whose run ends at row r casts
    its line from that row's floor point (the straddling pixel's) to 2 ft
    past it; a column with no floor from the near limit of a 0.8 ft obstacle
    at the bottom row's floor (1 - 0.8 / 3 of its distance); a run to the
    top casts none."""
    from planner.appearance import SHADOW_FT, run_shadows
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    top = np.full(128, 1)                      # every run up to the top: no shadow
    assert len(run_shadows(rays, top, 0.25, 0.8)) == 0
    top[40] = 80                               # ends at row 80: its foot the row 79 point
    top[90] = ROWS                             # no floor at all
    pts = run_shadows(rays, top, 0.25, 0.8)
    o = rays.origin
    d = np.hypot(pts[:, 0] - o[0], pts[:, 2] - o[2])
    bearing = np.arctan2(pts[:, 0] - o[0], pts[:, 2] - o[2])
    bearings = []
    for col, row, start in ((40, 79, rays.dist[79, 40]),
                            (90, 119, (1 - 0.8 / H) * rays.dist[119, 90])):
        b = math.atan2(rays.x[row, col] - o[0], rays.z[row, col] - o[2])
        bearings.append(b)
        on = np.isclose(bearing, b, atol=1e-9)
        assert d[on].min() == pytest.approx(start)
        # (to 2 ft past the foot, the samples half a cell apart from the start)
        assert d[on].max() == pytest.approx(rays.dist[row, col] + SHADOW_FT, abs=0.125)
        assert np.allclose(np.diff(np.sort(d[on])), 0.125)
        assert np.allclose(pts[on, 1], o[1])
    assert np.isclose(bearing[:, None], bearings, atol=1e-9).any(axis=1).all()   # no others


def _pt(line, loc1, dp, ep=0.05):
    return Point(line, 1, loc1, loc1 - 10, dp, 0.0, 0.0, ep, 0.01, 0.01)


def test_veto_leaves_out_a_point_on_floor_in_view_and_keeps_the_box():
    room, pose, look = _look()
    greys = np.zeros(16, bool)
    greys[6] = True
    top = floor_run(look.left_bi, greys)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    reach = run_reach(rays, top)
    c = int(np.argmax(reach))                          # the column that shows floor farthest
    far = reach[max(c - 1, 0):c + 2].min()
    line = 60
    # a false match 5 ft along the ray of line 60 (which meets the floor 6.4 ft
    # out): 0.9 ft above the floor, 4.5 ft away, with the floor behind it in view
    false_near = _pt(line, c + 1, 5.0)
    # the box's true range at one of its pixels (the world's truth)
    box_q = [k for k, q in enumerate(room.quads) if q.name.startswith("box")]
    br, bc = np.argwhere(np.isin(look.surface_left, box_q))[len(box_q) * 40]
    true_box = _pt(int(br), int(bc) + 1, float(look.range_left[br, bc]))
    assert far > 6.5
    mask = vetoed([false_near, true_box], rays, top, 0.25)
    assert mask.tolist() == [True, False]


@pytest.mark.parametrize("how", ["carve", "add", "veto"])
def test_the_loop_with_the_floor_in_view_reaches_the_tiny_rooms_goal(how):
    from planner.loop import DriveConfig, run
    from planner.tiny import GOAL
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    # band: the tiny room's bare floor frees nothing before 8 ft under low (test_drive_sight_lines.py)
    res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="truth",
                                                             floor_eyes=how, sight_lines="band"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert res.floor["floor_greys"] == [6]             # the tiny room's floor, learned
    assert res.floor["floor_cells"] > 0
    if how != "veto":
        assert res.floor["vetoed_points"] == 0
    assert res.as_json()["floor"] == res.floor


def test_floor_eyes_checked_and_passed_by_rig_drive(tmp_path, monkeypatch):
    from planner.loop import DriveConfig, run
    from planner.tiny import GOAL
    from rigtools import drive_config
    from vehicle.sim import State
    with pytest.raises(ValueError, match="floor_eyes"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, floor_eyes="on"))
    assert drive_config(monkeypatch, tmp_path, "--floor-eyes", "veto").floor_eyes == "veto"
    assert drive_config(monkeypatch, tmp_path).floor_eyes == "bound-add"   # since 2026-12-03
    assert drive_config(monkeypatch, tmp_path, "--floor-eyes", "off").floor_eyes == "off"
    assert drive_config(monkeypatch, tmp_path, "--floor-eyes", "bound").floor_eyes == "bound"


def test_add_carves_both_the_floor_in_view_and_the_assumption():
    from eyes import scan_pair
    from planner.evidence import Perception
    from planner.loop import DriveConfig, true_range_points
    from planner.motion import near_visible_ft
    from planner.octree import FREE as F
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    room, pose, look = _look()
    pts = true_range_points(scan_pair(look.left_bi, look.right_bi,
                                      lines=tuple(range(8, 113, 2))).points, look)
    free = {}
    for how in ("off", "carve", "add"):
        m = Perception(DriveConfig.voi, DriveConfig.band, 12.0, 2, 1,
                       near_visible_ft(DEFAULT, 0.8), 8.0)
        m.blank_carve, m.carve, m.floor_eyes = "unknown", "error", how
        m.floor_hist[6] = 1000.0                     # the floor's grey, as if learned
        m.update(pts, State(0.0, 0.0, 0.0), Pose, PITCH, None, None, look.left_bi)
        free[how] = m.floor_map([(0.0, 0.0), (0.0, 9.0)]).cells == F
    assert free["carve"].sum() > 0 and free["off"].sum() > 0
    assert (free["add"] >= free["carve"]).all() and (free["add"] >= free["off"]).all()
    assert free["add"].sum() > max(free["carve"].sum(), free["off"].sum())


def test_bound_pulls_each_assumed_line_back_to_its_columns_floor_in_view():
    from planner.appearance import bound_by_floor
    origin = np.array([1.0, -3.0, 2.0])
    # three lines 8 ft long (horizontally), in columns 10, 20, 30 (1-based)
    dirs = np.array([[0.6, 0.8], [0.0, 1.0], [-0.8, 0.6]])
    ends = np.column_stack([origin[0] + 8 * dirs[:, 0], np.full(3, -3.0),
                            origin[2] + 8 * dirs[:, 1]])
    reach = np.zeros(128)
    reach[9], reach[19], reach[29] = 4.0, 10.0, 0.0
    out, kept = bound_by_floor(ends, [10, 20, 30], origin, reach)
    assert kept.tolist() == [True, True, False]       # no floor in view: no line at all
    d = np.hypot(out[:, 0] - origin[0], out[:, 2] - origin[2])
    assert d[:2] == pytest.approx([4.0, 8.0])         # cut to 4 ft; 8 ft is within 10
    assert out[0, [0, 2]] == pytest.approx(origin[[0, 2]] + 4.0 * dirs[0])   # same bearing
    assert (out[:, 1] == -3.0).all()
    assert bound_by_floor(np.zeros((0, 3)), [], origin, reach)[0].shape == (0, 3)


def test_nearest_greys_are_the_bottom_rows():
    pic = np.full((ROWS, 128), 9, np.uint8)
    pic[-4:] = 3
    pic[-4:, :20] = 4                                  # 16 % of the bottom rows
    pic[-1, 0] = 12                                    # one pixel: under the share
    assert np.flatnonzero(nearest_greys(pic)).tolist() == [3, 4]
    # "majority": only a grey with more than half of them (the box face's 16 % is not)
    assert np.flatnonzero(nearest_greys(pic, min_share=STAND_INS["majority"])).tolist() == [3]
    pic[-4:, :64] = 4                                  # an even split: no grey stands in
    assert not nearest_greys(pic, min_share=STAND_INS["majority"]).any()
    assert (floor_run(pic, nearest_greys(pic, min_share=STAND_INS["majority"])) == ROWS).all()


def test_a_majority_stand_in_keeps_a_near_box_face_from_passing_for_floor():
    """Room 256 by hand: the first look, the floor's grey not yet learned, a
    box face (grey 4) stands in the middle third of the view from the bottom
    row to the middle row, the floor (grey 3) beside it, a wall (9) above.
    Under ``stand_in="tenth"`` the face's 31 % of the bottom rows passes for
    floor, its run ends at the face's top (5.9 ft), and the blank-column
    assumption carves the floor behind the face's foot: inside the box.  Under
    "majority" the face's columns assume nothing; the floor's beside it are
    carved alike."""
    from planner.evidence import Perception
    from planner.loop import DriveConfig, _perception
    from planner.octree import FREE as F
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    pic = np.full((ROWS, 128), 9, np.uint8)
    pic[60:] = 3
    pic[60:, 40:80] = 4
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))

    def free_share(stand_in, c0, c1):
        """Share of the floor points of rows 66-117, columns c0..c1 - 1 the look frees."""
        # (the blank columns laid along the pitched axis, as traced: hit_at "axis")
        m = _perception(DriveConfig(goal=(0.0, 9.0), stand_in=stand_in, sight_lines="band",
                                    hit_at="axis"), DEFAULT, Perception)
        m.update([], State(0.0, 0.0, 0.0), Pose, PITCH, None, None, pic)
        fm = m.floor_map([(0.0, 0.0), (0.0, 9.0)])
        xs, zs = rays.x[66:118, c0:c1].ravel(), rays.z[66:118, c0:c1].ravel()
        return np.mean([fm.state_at(x, z) == F for x, z in zip(xs, zs)])

    assert free_share("tenth", 52, 68) == 1.0          # behind the face's foot: carved
    assert free_share("majority", 52, 68) == 0.0
    for c0, c1 in ((5, 35), (85, 115)):                # the floor beside the face
        assert free_share("majority", c0, c1) == free_share("tenth", c0, c1) > 0.8


def test_stand_in_checked_and_passed_by_rig_drive(tmp_path, monkeypatch):
    from planner.loop import DriveConfig, run
    from planner.tiny import GOAL
    from rigtools import drive_config
    from vehicle.sim import State
    with pytest.raises(ValueError, match="stand_in"):
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, stand_in="half"))
    assert drive_config(monkeypatch, tmp_path).stand_in == "tenth"
    assert drive_config(monkeypatch, tmp_path, "--stand-in", "majority").stand_in == "majority"


def test_a_tall_box_hides_more_than_the_lowest_obstacles_stretch():
    """The training pixels of ``whole_trace``: a box as tall as the camera
    1.5 ft ahead hides the floor at 5 ft, though the stretch a 0.8 ft box
    could hide it from (3.7-5 ft) is free."""
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    fm = empty_map((-6.0, 6.0, -2.0, 14.0), 0.25, fill=FREE)
    i0 = int((1.5 - fm.z0) / fm.cell)                 # a row of cells 1.5-1.75 ft ahead
    fm.cells[i0, :] = OCCUPIED
    plain = training_mask(rays, fm, 0.8, 12.0)
    whole = training_mask(rays, fm, 0.8, 12.0, whole_trace=True)
    assert plain.sum() > 5000                         # the stretch rule does not see the box
    assert not whole.any()                            # every ray's trace crosses it
    fm.cells[i0, :] = FREE
    every_second = np.zeros_like(plain)
    every_second[::2, ::2] = True                     # whole_trace's sample of the pixels
    assert (training_mask(rays, fm, 0.8, 12.0, whole_trace=True) == plain & every_second).all()


@pytest.mark.parametrize("seed, box", [(237, 5), (177, 0)])
def test_bound_keeps_the_blank_assumption_out_of_the_boxes_it_drove_into(seed, box):
    """Seeds 237 and 177 (the collisions on the seeds the rules were not made
    on, docs/planner.md): a look that located nothing faces a blank box face
    (237), a box only the left camera saw (177).  Under the defaults the
    blank-column assumption carves the box's cells and the vehicle drives
    into it; with ``bound`` the same looks end at the box's foot in the
    picture: no cell of that box is ever free on the map, no collision."""
    from planner.evidence import Perception
    from planner.floormap import FREE as MAP_FREE
    from planner.loop import DriveConfig, run
    from rigtools import DRIVE_BEFORE_2026_12_04, DRIVE_BEFORE_2026_12_05, bench_task
    from world.odometry import OdometryNoise
    room, start, goal = bench_task(seed)
    x0, x1, z0, z1 = room.obstacles[box]
    freed = {}
    for how in ("off", "bound"):
        worst = [0]

        def traced(*args):
            model = Perception(*args)
            update = model.update

            def counted(*a, **k):
                n = update(*a, **k)
                fm = model.floor_map([(x0, z0), (x1, z1)])
                zs = fm.z0 + (np.arange(fm.shape[0]) + 0.5) * fm.cell
                xs = fm.x0 + (np.arange(fm.shape[1]) + 0.5) * fm.cell
                inside = ((zs > z0) & (zs < z1))[:, None] & ((xs > x0) & (xs < x1))[None, :]
                worst[0] = max(worst[0], int((inside & (fm.cells == MAP_FREE)).sum()))
                return n
            model.update = counted
            return model
        res = run(room, start, DriveConfig(goal=goal, floor_eyes=how, **{**DRIVE_BEFORE_2026_12_04,
                                              **DRIVE_BEFORE_2026_12_05}),
                  noise=OdometryNoise(seed=seed), perception_factory=traced)
        freed[how] = (worst[0], res.collisions)
    assert freed["off"][0] > 5 and freed["off"][1] == 1    # the hazard, as traced
    assert freed["bound"] == (0, 0)


def test_bridge_passes_a_lone_pixel_not_two():
    pic = np.full((ROWS, 128), 6, np.uint8)
    pic[:40, :] = 9                                   # something stands from row 40 up
    pic[100, 10] = 9                                  # one pixel moved by the noise
    pic[100:102, 20] = 9                              # two rows: something on the floor
    pic[119, 30] = 9                                  # the bottom row, floor above it
    greys = np.zeros(16, bool)
    greys[6] = True
    plain, bridged = floor_run(pic, greys), floor_run(pic, greys, bridge=True)
    assert plain[0] == bridged[0] == 41               # the run's top pixel left out
    assert plain[10] == 102 and bridged[10] == 41
    assert plain[20] == bridged[20] == 103
    assert plain[30] == ROWS and bridged[30] == 41


def test_a_run_past_the_walls_foot_shows_no_floors_end():
    """The floor plan's walls 5 ft ahead: a run whose top's floor point lies
    past them went on up a surface of the floor's grey."""
    from planner.appearance import past_walls
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    row_at = {ft: int(np.argmin(np.abs(rays.dist[:, 64] - ft))) for ft in (4.0, 6.0)}
    top = np.full(128, ROWS)
    top[60], top[64] = row_at[4.0], row_at[6.0]
    out = past_walls(rays, top, (-5.0, 5.0, -1.0, 5.0))
    assert np.flatnonzero(out).tolist() == [64]
    # floor_end: where the picture shows the floor end; nowhere past the walls or
    # up to the picture's top row (the floor, or a face of its grey, goes on)
    top[100] = 1
    end = floor_end(rays, top, (-5.0, 5.0, -1.0, 5.0))
    assert end[60] == pytest.approx(rays.dist[top[60], 60]) and 3.9 < end[60] < 4.1
    assert end[64] == end[100] == 0.0 and end[0] == 0.0       # (column 0: no run)
    assert floor_end(rays, top)[64] == pytest.approx(rays.dist[top[64], 64])
    # far off a row spans a good part of a foot of floor: the run's end is known no better
    far = np.full(128, ROWS)
    r15 = int(np.argmin(np.abs(rays.dist[:, 64] - 15.0)))
    far[64] = r15
    step = rays.dist[r15 - 1, 64] - rays.dist[r15 + 1, 64]
    assert 0.5 < step < 1.2
    end = rays.z[r15, 64]
    assert not past_walls(rays, far, (-5.0, 5.0, -1.0, end - 0.4 * step)).any()
    assert past_walls(rays, far, (-5.0, 5.0, -1.0, end - 1.1 * step))[64]
    # and no better than the heading is known, times its distance
    assert not past_walls(rays, far, (-5.0, 5.0, -1.0, end - 2.0), heading_sd=0.1).any()


def test_within_heading_cuts_each_column_to_its_heading_window():
    """By hand: near the centre the 128-column picture turns 1/180 rad a
    column, so a 0.02 rad window (2 sigma of 0.01 rad) round column 64
    (atan(0.5/180) = 0.00278 rad) holds columns 61-67 (column 68 is
    atan(4.5/180) - 0.00278 = 0.0222 rad off); a column within 0.02 rad of
    the picture's outermost column may look past it (column 0 at
    atan(-63.5/180) = -0.3391 rad; column 4 at atan(-59.5/180), 0.0199 rad
    from it, column 5 0.0249 rad)."""
    from planner.appearance import within_heading
    reach = np.full(128, 5.0)
    reach[64] = 2.0
    out = within_heading(reach, 0.01, sigmas=2.0)
    assert np.flatnonzero(out == 2.0).tolist() == list(range(61, 68))
    assert np.flatnonzero(out == 0.0).tolist() == [0, 1, 2, 3, 4, 123, 124, 125, 126, 127]
    assert (out[(out != 2.0) & (out != 0.0)] == 5.0).all()
    assert (within_heading(reach, 0.0) == reach).all()          # a known heading: as shown
    assert reach[64] == 2.0 and reach[63] == 5.0                 # the input is left alone


def _one_box_room(name, bx, bz, height, front, side, top):
    """The tiny room's walls and a flat floor of grey 6 with one box (shades
    ``front`` for its front and back, ``side``, ``top``)."""
    from planner.tiny import BOUNDS, bands
    from rig.scene import flat
    from world.room import FLOOR_Y, full_box, make_room, quad
    x0, x1, z0, z1 = BOUNDS
    quads = full_box("box", bx, (FLOOR_Y - height, FLOOR_Y), bz, front, side, top)
    quads += [quad("back wall", 2, z1, (x0, x1), (-5.0, FLOOR_Y), bands(3, 0, x0, x1)),
              quad("front wall", 2, z0, (x0, x1), (-5.0, FLOOR_Y), bands(4, 0, x0, x1)),
              quad("left wall", 0, x0, (-5.0, FLOOR_Y), (z0, z1), bands(5, 2, z0, z1)),
              quad("right wall", 0, x1, (-5.0, FLOOR_Y), (z0, z1), bands(6, 2, z0, z1)),
              quad("floor", 1, FLOOR_Y, (x0, x1), (z0, z1), flat(6)),
              quad("ceiling", 1, -5.0, (x0, x1), (z0, z1), flat(12))]
    return make_room(name, quads, [(bx, bz)], BOUNDS, ceiling_y=-5.0)


def _low_box_room():
    """One low box of flat greys (1.5 ft tall, x 1-2.5, z 5-6.5) right of the
    view's centre."""
    from rig.scene import flat
    bx, bz = (1.0, 2.5), (5.0, 6.5)
    return _one_box_room("low box room", bx, bz, 1.5, flat(12), flat(10), flat(14)), bx, bz


def test_the_heading_window_keeps_a_look_laid_down_8_deg_off_out_of_the_box():
    """The look taken facing +Z and laid down by an estimate 8 deg off (the
    1985 eyes' dead reckoning drifts that far in 20 looks, rooms 6, 34, 49):
    the floor seen left of the box is proven inside it, 0.2 ft and more from
    its sides.  With the heading's standard deviation 4 deg,
    ``proof_heading="window"`` proves none of it, and a look whose heading
    is known proves as much as before."""
    from eyes import scan_pair
    from planner.evidence import FLOOR_IN_VIEW, FreeProvenance, Perception
    from planner.loop import DriveConfig, true_range_points
    from planner.motion import near_visible_ft
    from planner.octree import FREE as F
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    room, bx, bz = _low_box_room()
    look = render_look(room, Pose(0.0, 0.0, 0.0, PITCH), seed=7, supersample=2)
    pts = true_range_points(scan_pair(look.left_bi, look.right_bi,
                                      lines=tuple(range(8, 113, 2))).points, look)

    def proven_in_box(how, off_deg, sd_deg):
        m = Perception(DriveConfig.voi, DriveConfig.band, 12.0, 2, 1,
                       near_visible_ft(DEFAULT, 0.8), 8.0)
        m.blank_carve, m.carve, m.floor_eyes, m.proof_heading = "unknown", "error", "bound-add", how
        m.floor_hist[6] = 1000.0                     # the floor's grey, as if learned
        m.provenance = FreeProvenance()
        cov = np.diag([0.0, 0.0, math.radians(sd_deg) ** 2])
        m.update(pts, State(0.0, 0.0, off_deg), Pose, PITCH, None, cov, look.left_bi)
        fm = m.floor_map([(0.0, 0.0), (0.0, 9.0)])
        cols = m.provenance.columns(fm.cell, DriveConfig.band)
        i0, j0 = int(round(fm.z0 / fm.cell)), int(round(fm.x0 / fm.cell))
        n = 0
        for i, j in np.argwhere(fm.cells == F):
            x, z = fm.x0 + (j + 0.5) * fm.cell, fm.z0 + (i + 0.5) * fm.cell
            if bx[0] + 0.2 < x < bx[1] - 0.2 and bz[0] + 0.2 < z < bz[1] - 0.2 and \
                    FLOOR_IN_VIEW in cols.get((j0 + j, i0 + i), {}):
                n += 1
        return n, m.floor_cells

    assert proven_in_box("estimate", 8.0, 4.0)[0] >= 3
    assert proven_in_box("window", 8.0, 4.0)[0] == 0
    assert proven_in_box("window", 0.0, 0.0) == proven_in_box("estimate", 0.0, 0.0)


def _point_on_ray(rays, row, col, horiz_ft, ep=0.05):
    """A located point (rig.scan Point) on the ray of pixel (row, col),
    ``horiz_ft`` from the camera horizontally."""
    from planner.appearance import CX, CY, FOCAL
    u = np.array([(col + 0.5 - CX) / FOCAL, (row + 0.5 - CY) / FOCAL, 1.0])
    w = rays.R @ u
    dp = horiz_ft / math.hypot(w[0], w[2])
    return Point(row, 1, col + 1, col + 1, dp, u[0] * dp, u[1] * dp, ep, 0.01, 0.01)


def test_a_point_located_at_a_floor_end_nearer_than_it_ends_the_floor_there():
    """By hand: column 64's floor runs to the row whose floor lies 6 ft away.
    A point located on that row's ray only 4 ft away stands 1 ft off the
    floor (3 (1 - 4/6)): the run went up a face of the floor's grey, and the
    column's floor ends at the point less its range error; so does a point
    lower in the run nearer than its own row's floor.  A point where its
    pixel's floor lies (an obstacle's foot, a tile's edge), or rows above
    the run, changes nothing."""
    from planner.appearance import raised_ends
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    row6 = int(np.argmin(np.abs(rays.dist[:, 64] - 6.0)))
    top = np.full(128, ROWS)
    top[64] = row6
    reach = floor_end(rays, top)
    assert reach[64] == pytest.approx(rays.dist[row6, 64])
    raised = _point_on_ray(rays, row6, 64, 4.0, ep=0.2)
    out = raised_ends([raised], rays, top, reach)
    assert out[64] == pytest.approx(3.8)
    assert (np.delete(out, 64) == np.delete(reach, 64)).all()
    assert reach[64] == pytest.approx(rays.dist[row6, 64])             # left alone
    # a neighbouring column's point counts too (its edge may fall a column off)
    assert raised_ends([_point_on_ray(rays, row6, 65, 4.0, ep=0.2)], rays, top,
                       reach)[64] == pytest.approx(3.8)
    foot = _point_on_ray(rays, row6, 64, reach[64])
    assert (raised_ends([foot], rays, top, reach) == reach).all()
    above = _point_on_ray(rays, row6 - 10, 64, 4.0)             # above the run: not its
    assert (raised_ends([above], rays, top, reach) == reach).all()
    # inside the run: 20 rows down the floor lies 4.66 ft off; a point 2.5 ft off there
    # stands 3 (1 - 2.5/4.66) = 1.4 ft up (a box top of the floor's grey, room 278)
    low = row6 + 20
    assert 4.6 < rays.dist[low, 64] < 4.7
    on_top = _point_on_ray(rays, low, 64, 2.5, ep=0.1)
    assert raised_ends([on_top], rays, top, reach)[64] == pytest.approx(2.4)
    on_floor = _point_on_ray(rays, low, 64, rays.dist[low, 64])   # a tile's edge
    assert (raised_ends([on_floor], rays, top, reach) == reach).all()
    assert (raised_ends([], rays, top, reach) == reach).all()


def test_a_striped_face_of_the_floors_grey_ends_no_floor_behind_it():
    """A box 3.5 ft tall (above the camera) whose side facing the rig has the
    floor's grey 6 with a vertical stripe of grey 15, 1.2-2.6 ft away: the
    floor run goes on up the face to the stripe, whose lower edge passes for
    a floor end 3.7-17 ft off, six of them inside the box.  The eyes locate the
    stripe's edges on the face; with them every column's floor end lies in
    front of the face (the world's geometry: the plane x = 1.2 ft), but
    where the face stands nearer than the picture's bottom row."""
    from eyes import scan_pair
    from planner.appearance import raised_ends
    from planner.loop import true_range_points
    from rig.scene import flat

    def striped(axis, centre):
        return lambda X, Y, Z: np.where(np.abs((X, Y, Z)[axis] - centre) < 0.15, 15.0, 6.0)
    bx, bz = (1.2, 3.0), (0.5, 5.0)
    room = _one_box_room("striped face", bx, bz, 3.5, striped(0, 2.0), striped(2, 2.5), flat(14))
    pose = Pose(0.0, 0.0, 20.0, PITCH)
    look = render_look(room, pose, seed=7, supersample=2)
    greys = np.zeros(16, bool)
    greys[6] = True
    top = floor_run(look.left_bi, greys, bridge=True)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    reach = floor_end(rays, top)
    pts = true_range_points(scan_pair(look.left_bi, look.right_bi,
                                      lines=tuple(range(8, 113, 2))).points, look)

    def behind_the_face(r):
        cols = np.flatnonzero(r > 0)
        row = np.minimum(top[cols], ROWS - 1)
        d = rays.dist[row, cols]
        x = rays.origin[0] + (rays.x[row, cols] - rays.origin[0]) * r[cols] / d
        z = rays.origin[2] + (rays.z[row, cols] - rays.origin[2]) * r[cols] / d
        return cols[(x > bx[0] + 0.1) & (z > bz[0]) & (z < bz[1])]   # (a row's footprint)
    assert len(behind_the_face(reach)) >= 5                   # the hazard, as shown (6)
    # one column is left, a known limit: column 101 meets the face 2.29 ft away, nearer
    # than the bottom row's floor (3.2 ft), so its run is face from the bottom up and ends
    # in row 118, below the last scan line (112): no point is located there to check it
    assert behind_the_face(raised_ends(pts, rays, top, reach)).tolist() == [101]
    assert top[101] == 118
    # the loop leaves out points nearer than 2.5 ft along the optical axis; the pitch puts
    # even these, 1.2-2.6 ft off across the floor, past it, so the loop cuts the same
    assert min(q.dp for q in pts) >= 2.5
    assert behind_the_face(raised_ends(pts, rays, top, reach, min_range_ft=2.5)).tolist() == [101]


def test_the_floor_proofs_safety_options_reach_the_loop(monkeypatch, tmp_path):
    """``--proof-heading``, ``--floor-end-check`` and ``--proof-hits`` reach
    DriveConfig (defaults ``window``, ``stereo``, ``line`` since 2026-12-05, the
    check ``motion`` since 2026-12-06 15:40; ``estimate``, ``off``, ``trace``: the
    drive before) and the loop's map, bad
    values are refused, where nothing uses them they change nothing, and the tiny
    room is driven to its goal with all three without a collision."""
    from planner.loop import DriveConfig, _check_config, _perception, run
    from planner.evidence import Perception
    from planner.tiny import GOAL
    from rigtools import drive_config
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    cfg = drive_config(monkeypatch, tmp_path)
    # (floor_end_check "stereo" from 2026-12-05 to 2026-12-06 15:40, "motion" since)
    assert (cfg.proof_heading, cfg.floor_end_check, cfg.proof_hits) == ("window", "motion", "line")
    cfg = drive_config(monkeypatch, tmp_path, "--proof-heading", "estimate", "--floor-end-check",
                       "off", "--proof-hits", "trace", "--drift-sigmas", "1.5")
    assert (cfg.proof_heading, cfg.floor_end_check, cfg.proof_hits) == ("estimate", "off", "trace")
    assert drive_config(monkeypatch, tmp_path, "--floor-end-check",
                        "stereo").floor_end_check == "stereo"
    m = _perception(drive_config(monkeypatch, tmp_path, "--drift-sigmas", "1.5"), DEFAULT,
                    Perception)
    assert (m.proof_heading, m.heading_sigmas, m.floor_end_check, m.proof_hits) == \
        ("window", 1.5, "motion", "line")
    for name, bad in (("proof_heading", "sigma"), ("floor_end_check", "on"),
                      ("proof_hits", "all")):
        with pytest.raises(ValueError, match=name):
            _check_config(DriveConfig(goal=GOAL, **{name: bad}))
    # without the floor in view nothing uses them: the same map either way
    before = dict(proof_heading="estimate", floor_end_check="off", proof_hits="trace")
    maps = [run(tiny_room(), State(0.0, 0.0, 0.0),
                DriveConfig(goal=GOAL, eyes="truth", floor_eyes="off", max_looks=2, **how),
                noise=OdometryNoise(seed=1)).cycles[-1].fmap.cells for how in ({}, before)]
    assert np.array_equal(*maps)
    # (oracle edges and band sight lines, as the tiny room's other loop tests)
    res = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes="truth", sight_lines="band", proof_heading="window",
                          floor_end_check="stereo", proof_hits="line"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0
    assert 0 < res.floor["floor_cells"]


def test_free_cells_reaches_the_loop_and_the_tiny_room_is_reached_under_shadows(
        monkeypatch, tmp_path):
    """``--free-cells`` (default ``any``; ``shadows`` named, not 1985) reaches
    DriveConfig and the loop's Perception, a bad value is refused, and the
    tiny room is driven to its goal under ``shadows`` without a collision;
    the loop's look keeps its shadows and proves no cell in them."""
    from planner.evidence import Perception, tracing_perception
    from planner.loop import DriveConfig, _check_config, _perception, run
    from planner.tiny import GOAL
    from rigtools import drive_config
    from vehicle.profile import DEFAULT
    from vehicle.sim import State
    from world.odometry import OdometryNoise
    assert drive_config(monkeypatch, tmp_path).free_cells == "any"
    cfg = drive_config(monkeypatch, tmp_path, "--free-cells", "shadows")
    assert cfg.free_cells == "shadows"
    assert _perception(cfg, DEFAULT, Perception).free_cells == "shadows"
    with pytest.raises(ValueError, match="free_cells"):
        _check_config(DriveConfig(goal=GOAL, free_cells="centre"))
    for how in ("any", "shadows"):
        made = []
        run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, max_looks=2, free_cells=how),
            noise=OdometryNoise(seed=1), perception_factory=tracing_perception(made))
        model = made[0]
        assert len(model._proved) > 0                     # the floor in view proved cells
        # its last look's shadows: none under "any"; under "shadows" none of them proved
        assert (len(model._shadow_keys) > 0) == (how == "shadows")
        assert not np.isin(model._proved, model._shadow_keys).any()
    res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, free_cells="shadows"),
              noise=OdometryNoise(seed=1))
    assert res.reached, res.reason
    assert res.collisions == 0


def test_a_raised_edge_carries_along_the_runs_top_to_columns_without_a_point():
    """The run's top a straight edge across columns 56-72 (a row a column)
    and three points located on it, in columns 60, 64 and 68, each at 2/3
    of its row's floor distance (1 ft up): every column of the edge ends at
    the least such share of its own floor end; beyond a jump of 10 rows
    (column 73 on) another edge, left alone.  One point alone (a false
    match, as likely) cuts only its own columns."""
    from planner.appearance import raised_ends
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    row6 = int(np.argmin(np.abs(rays.dist[:, 64] - 6.0)))
    top = np.full(128, ROWS)
    cols = np.arange(56, 73)
    top[cols] = row6 + (cols - 64)
    top[73:80] = row6 + 20
    reach = floor_end(rays, top)
    on_edge = [_point_on_ray(rays, top[c], c, 2 / 3 * rays.dist[top[c], c], ep=0.0)
               for c in (60, 64, 68)]
    out = raised_ends(on_edge, rays, top, reach)
    # each point counts in its neighbours' columns too: the least share of all
    share = min(2 / 3 * rays.dist[top[c], c] / rays.dist[top[c], n]
                for c in (60, 64, 68) for n in (c - 1, c, c + 1))
    assert 0.64 < share <= 2 / 3
    want = reach.copy()
    want[cols] = np.minimum(share * rays.dist[top[cols], cols], reach[cols])
    for c in (60, 64, 68):                  # and a point's own distance in its columns
        want[c - 1:c + 2] = np.minimum(want[c - 1:c + 2], 2 / 3 * rays.dist[top[c], c])
    assert out[cols] == pytest.approx(want[cols])
    assert (out[cols] < reach[cols]).all()
    assert (out[73:80] == reach[73:80]).all() and (out[:56] == reach[:56]).all()
    one = raised_ends(on_edge[1:2], rays, top, reach)
    assert np.flatnonzero(one != reach).tolist() == [63, 64, 65]
    # points nearer than min_range_ft (the loop passes the floor scan's 2.5 ft) are not used
    assert max(q.dp for q in on_edge) < 6.0
    assert (raised_ends(on_edge, rays, top, reach, min_range_ft=6.0) == reach).all()


def test_a_look_reads_the_floor_except_off_or_depth_eyes_under_a_bound():
    """The one predicate for both Perception.update's picture work and the
    drive's step back: the depth eyes assume nothing, so a bounding
    floor_eyes has nothing to bound."""
    from planner.appearance import reads_floor
    assert not reads_floor("off", False) and not reads_floor("off", True)
    for eyes in BOUNDING:
        assert reads_floor(eyes, False) and not reads_floor(eyes, True)
    for eyes in ("carve", "veto", "add"):
        assert reads_floor(eyes, False) and reads_floor(eyes, True)


def test_a_run_up_a_wall_of_the_floors_grey_ends_at_the_walls_foot_under_foot():
    """``wall_runs="foot"``: the columns floor_end gives no end (a run past the
    plan's walls, 5 ft ahead, or up to the picture's top) end at the walls' foot
    instead, less a row's floor footprint and twice the heading's sigma times the
    distance; a column that shows its end keeps it.  ``"past"``: only the first."""
    from planner.appearance import wall_foot_reach
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    row_at = {ft: int(np.argmin(np.abs(rays.dist[:, 64] - ft))) for ft in (4.0, 6.0)}
    top = np.full(128, ROWS)
    top[60], top[64], top[100] = row_at[4.0], row_at[6.0], 1
    within = (-5.0, 5.0, -1.0, 5.0)
    none = floor_end(rays, top, within)
    foot = floor_end(rays, top, within, wall_runs="foot")
    assert foot[60] == none[60] and 3.9 < foot[60] < 4.1           # its own end
    assert none[64] == none[100] == 0.0 and foot[0] == 0.0          # (column 0: no run)
    # the floor point each ends at lies before the wall at z = 5 by a row's footprint
    # there (about 0.1 ft) at most; column 100 looks to the right, where the side
    # wall (x = 5) is still farther than the far one
    def end_point(c, reach):
        k = int(np.flatnonzero(rays.dist[:, c] == reach[c])[0])
        return rays.x[k, c], rays.z[k, c]
    for c in (64, 100):
        x, z = end_point(c, foot)
        assert 4.75 < z < 5.0 and abs(x) < 5.0, c
    # a heading known to 0.05 rad takes 2 x 0.05 x 5 ft = 0.5 ft more off
    assert 4.25 < end_point(64, floor_end(rays, top, within, 0.05, "foot"))[1] < 4.5
    assert np.array_equal(wall_foot_reach(rays, within)[[64, 100]], foot[[64, 100]])
    # "past": only the run that ends past the walls; the one up to the top row shows none
    past = floor_end(rays, top, within, wall_runs="past")
    assert past[64] == foot[64] and past[60] == foot[60] and past[100] == 0.0


def test_room_341_is_reached_when_a_run_up_a_wall_of_a_tiles_grey_ends_before_it(
        monkeypatch, tmp_path):
    # bench/drive.py's room 341 under its own odometry noise: the floor's tiles are of
    # greys 3 and 5, the right wall of 5, and the goal lies 5.8 ft before that wall.
    # Every run toward it goes on up the wall, so under "none" nothing there is proven
    # and the run stops unreached (its 90 looks used up; with 16 without progress, before
    # 2026-12-07 08:30, it gave up at look 86; with 60 looks, before 06:30, they were
    # used up); under "foot" (its end at the walls' foot) and "texture" (its end where the
    # tiles are last seen; the default from 2026-12-06, and since 2026-12-08 on a tiled
    # floor under "flat-foot") the goal is reached.  The world's exact geometry
    # judges it.  ("foot" is not the default: a box of the floor's grey before such a wall
    # it proves free as well, rooms 95 and 248, docs/planner.md.)
    from planner.loop import DriveConfig, _check_config
    from rigtools import assert_reached_by_the_truth, bench_drives, drive_config
    assert drive_config(monkeypatch, tmp_path).wall_runs == "flat-foot"
    assert drive_config(monkeypatch, tmp_path, "--wall-runs", "texture").wall_runs == "texture"
    assert drive_config(monkeypatch, tmp_path, "--wall-runs", "foot").wall_runs == "foot"
    assert drive_config(monkeypatch, tmp_path, "--wall-runs", "none").wall_runs == "none"
    with pytest.raises(ValueError, match="wall_runs"):
        _check_config(DriveConfig(goal=(0.0, 7.0), wall_runs="wall"))
    monkeypatch.undo()                                  # (drive_config stubs the loop)
    goal, res = bench_drives(341, "wall_runs", ("none", "foot", "texture"))
    assert not res["none"].reached and res["none"].reason.startswith("stopped")
    assert res["none"].collisions == 0
    assert_reached_by_the_truth(res["foot"], goal)
    assert_reached_by_the_truth(res["texture"], goal)


def test_room_31_is_reached_when_a_flat_floors_run_up_a_wall_of_its_grey_ends_at_its_foot(
        monkeypatch, tmp_path):
    # bench/drive.py's room 31 under its own odometry noise: a flat floor of grey 6, its
    # left and back walls of 6 too, no skirting.  Every run toward them goes on up the
    # wall to the picture's top row and, with no tiles, shows no end: under "texture" the
    # run stops unreached (24 looks without progress); under "flat-foot" (the default since
    # 2026-12-08) such runs prove
    # the floor to the walls' foot where two looks from bearings 20 deg apart agree and no
    # located point stands within a box's width, and the goal is reached.  The world's
    # exact geometry judges it.
    from planner.loop import DriveConfig
    from rigtools import assert_reached_by_the_truth, bench_drives, drive_config
    from world.room import generate_room
    assert drive_config(monkeypatch, tmp_path, "--wall-runs", "flat-foot").wall_runs == \
        "flat-foot"
    monkeypatch.undo()                                  # (drive_config stubs the loop)
    shades = {q.name: str(q.shade) for q in generate_room(31).quads}
    assert shades["floor"] == shades["left wall"] == shades["back wall"] == "flat(6)"
    assert not any("skirting" in name for name in shades)
    goal, res = bench_drives(31, "wall_runs", ("texture", "flat-foot"))
    assert not res["texture"].reached and res["texture"].reason.startswith("stopped after")
    assert res["texture"].collisions == 0
    assert_reached_by_the_truth(res["flat-foot"], goal)


def test_the_floors_texture_ends_at_the_foot_of_a_face_of_one_of_its_greys():
    """texture_end by hand: a floor tiled in greys 4 and 6 (tiles 6 rows tall in
    the picture) up to row 70, and above it a face of grey 6 spotted with 5s (the
    noise moves a pixel one level; the condensing truncates): the texture is
    seen to the last tile edge below the face, the nearest row of the window
    holding it.  A flat floor (greys 3 and 4) shows none, and no window above
    the run's top counts."""
    from planner.appearance import texture_end
    rows = np.arange(ROWS)[:, None]
    pic = np.where((rows // 6) % 2, 4, 6) * np.ones((1, 128), int)
    pic[:70] = 6
    pic[:70:7, ::3] = 5
    pic[:, 100:] = np.where((rows + np.arange(28)) % 5 == 0, 3, 4)      # flat, noisy
    greys = np.zeros(16, bool)
    greys[[3, 4, 5, 6]] = True
    top = np.zeros(128, int)
    end = texture_end(pic, greys, top)
    # the face (rows up to 69) stands on a tile of grey 4 (rows 70-71): the last
    # window holding both greys is rows 68-70, and its nearest row is 70
    assert np.all(end[:100] == 70)
    assert np.all(end[100:] == ROWS)
    top[:50] = 90
    assert np.all(texture_end(pic, greys, top)[:50] == 96)    # rows 90-95 are 4, 96- 6
    not_floor = greys.copy()
    not_floor[4] = False                                      # grey 4 is not the floor's
    assert np.all(texture_end(pic, not_floor, np.zeros(128, int)) == ROWS)


def test_a_face_of_a_tile_grey_keeps_the_floors_texture_proof_before_its_foot():
    """``wall_runs="texture"`` on a rendered look of bench/drive.py's room 773: its
    floor is tiled in greys 3 and 5, and the camera stands 4.3 ft before box 4,
    whose front shows a tile grey.  The face's columns run up to the picture's top
    row.  ``foot`` ends those runs at the walls' foot, 19 ft out, through the box.
    ``texture`` ends them where the tiles are last seen, and the world's truth
    shows floor at every such end, and none of the column's floor out to it in the
    box.  A column whose run has its
    own end keeps it."""
    from planner.appearance import texture_end
    from world.room import generate_room
    room = generate_room(773)
    box = room.obstacles[3]
    pose = Pose(0.2, box[2] - 4.3, 0.0, PITCH)
    look = render_look(room, pose, seed=3, supersample=2)
    pic = look.left_bi
    floor = [i for i, q in enumerate(room.quads) if q.name == "floor"][0]
    greys = floor_greys(np.bincount(pic[look.surface_left == floor].astype(int), minlength=16))
    assert list(np.flatnonzero(greys)) == [3, 5]
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    top = floor_run(pic, greys, bridge=True)
    texture = texture_end(pic, greys, top)
    within = (-6.065, 4.135, -4.521, 20.235)                # the room's walls
    none = floor_end(rays, top, within)
    foot = floor_end(rays, top, within, wall_runs="foot")
    tex = floor_end(rays, top, within, wall_runs="texture", texture=texture)
    face = [c for c in range(128) if top[c] <= 1 and
            room.quads[look.surface_left[0, c]].name == "box 4 front"]
    assert len(face) > 30
    cols = np.arange(128)
    own = none > 0
    assert np.array_equal(tex[own], none[own]) and np.all(none[face] == 0)
    def proven_in_box(c, reach):
        # the floor points of the column's pixels out to ``reach`` (a pixel's bearing
        # changes with its row under the camera's pitch), inside box 4
        rows = np.flatnonzero(rays.dist[:, c] <= reach)
        return [box[0] < rays.x[r, c] < box[1] and box[2] < rays.z[r, c] < box[3] for r in rows]
    # through the box (but at the face's right end, where the lower pixels' floor
    # points bear past the box's side)
    through = [c for c in face if any(proven_in_box(c, foot[c]))]
    assert len(through) > 50 and through == face[:len(through)]
    shown = [c for c in face if tex[c] > 0]
    assert len(shown) > 20
    for c in shown:
        row = int(texture[c])
        assert room.quads[look.surface_left[row, c]].name == "floor"
        assert tex[c] == rays.dist[row, c]
        assert not any(proven_in_box(c, tex[c]))          # before the face, or beside it


def test_blend_passes_a_tiles_averaged_edge_and_not_a_face_of_its_grey():
    """floor_run(blend=True) by hand, the floor's greys 3 and 5 (a tiled floor):
    a lone 4 between a 3 below and a 5 above (a tile's edge the condensing
    averaged) continues the run; a 4 between two 3s, two 4s in a row (a face of
    grey 4 standing on the floor), and a 4 under a 6 (not a floor grey) end it."""
    greys = np.zeros(16, bool)
    greys[[3, 5]] = True
    pic = np.full((ROWS, 128), 3)
    pic[:60, :] = 5
    pic[60, 0] = 4                       # the edge between the 5s above and the 3s below
    pic[80, 1] = 4                       # a 4 within the 3s
    pic[59:61, 2] = 4                    # two rows of 4
    pic[60, 3], pic[59, 3] = 4, 6        # a 4 under a grey the floor does not have
    plain = floor_run(pic, greys)
    blend = floor_run(pic, greys, blend=True)
    assert plain[0] == 62 and blend[0] == 1                 # (row 0's top left out)
    assert plain[1] == blend[1] == 82
    assert plain[2] == blend[2] == 62
    assert plain[3] == blend[3] == 62
    assert blend[5] == plain[5] == 1                        # a sharp edge, 5 on 3


def _ends_seen(origin, edge, k):
    """Where a run ends, on the floor, seen from the camera's floor position
    ``origin``: at points ``edge`` (N, 2) with k = H / (H - h) (1: on the floor)."""
    o = np.asarray(origin, float)
    return o + k * (np.asarray(edge, float) - o)


def _proves_all(xz):
    return np.ones(len(np.asarray(xz).reshape(-1, 2)), bool)


def test_an_end_that_moves_with_the_camera_is_raised_by_hand():
    """raised_by_motion on hand-made ends: a box top's edge 1 ft up (H = 3 ft, so
    k = 3 / 2 = 1.5) along z = 5 ft, and a floor edge (k = 1) along z = 7 ft, seen
    from three places.  The raised ends give k = 1.5 and the edge's points
    exactly back; the floor's ends none.  One earlier look alone, or two from
    one place, or one that did not prove the floor at the end, do not do."""
    from planner.appearance import LookEnds, raised_by_motion
    xs = np.array([-0.4, 0.0, 0.4])
    top_edge = np.column_stack([xs, np.full(3, 5.0)])
    floor_edge = np.column_stack([xs, np.full(3, 7.0)])
    places = [np.array([0.0, 0.0]), np.array([0.3, 1.0]), np.array([0.1, 2.2])]

    def seen(o):
        return np.vstack([_ends_seen(o, top_edge, 1.5), _ends_seen(o, floor_edge, 1.0)])

    earlier = [LookEnds(o, seen(o), _proves_all) for o in places[:2]]
    now = places[2]
    k = raised_by_motion(seen(now), now, earlier)
    assert k[:3] == pytest.approx(1.5, abs=1e-9)
    assert np.isnan(k[3:]).all()
    back = now + (seen(now)[:3] - now) / k[:3, None]
    assert back == pytest.approx(top_edge, abs=1e-9)
    assert np.isnan(raised_by_motion(seen(now), now, earlier[1:])).all()
    twice = [LookEnds(places[1], seen(places[1]), _proves_all)] * 2
    assert np.isnan(raised_by_motion(seen(now), now, twice)).all()
    unproved = [LookEnds(o, seen(o), lambda xz: np.zeros(len(xz), bool)) for o in places[:2]]
    assert np.isnan(raised_by_motion(seen(now), now, unproved + earlier[1:])).all()


def test_a_chance_end_on_the_line_and_an_edge_along_the_move_are_not_raised():
    """A floor end at E, where one earlier look has some other end on the line
    E + t (C - C') (the next tile's edge, by chance) and the other has none,
    is not raised; nor is one beside an edge the camera moved along, whose
    ends string along the line and fit any k."""
    from planner.appearance import LookEnds, raised_by_motion
    now, a, b = np.array([0.0, 2.0]), np.array([0.0, 0.0]), np.array([0.5, 1.0])
    e = np.array([[0.0, 6.0]])
    chance = LookEnds(a, np.array([[0.0, 7.0]]), _proves_all)     # t = 0.5 from a
    empty = LookEnds(b, np.array([[3.0, 3.0]]), _proves_all)
    assert np.isnan(raised_by_motion(e, now, [chance, empty])).all()
    # an edge along z at x = 0.1 (the move's direction from a), seen by both looks
    along = np.column_stack([np.full(20, 0.1), np.linspace(6.3, 9.0, 20)])
    both = [LookEnds(a, along, _proves_all), LookEnds(np.array([0.05, 1.0]), along, _proves_all)]
    assert np.isnan(raised_by_motion(e, now, both)).all()


def test_raised_columns_need_a_neighbour_that_agrees():
    """raised_columns: a raised column counts only beside another within two
    columns whose k agrees within a tenth, and a look's raised columns only
    when three are left."""
    from planner.appearance import LookEnds, raised_columns
    places = [np.array([0.0, 0.0]), np.array([0.3, 1.0])]
    now = np.array([0.1, 2.2])
    edge = np.column_stack([np.linspace(-0.6, 0.6, 7), np.full(7, 5.0)])
    ends = np.full((128, 2), np.nan)
    ends[60:67] = _ends_seen(now, edge, 1.5)
    ends[10] = _ends_seen(now, [[-3.0, 4.0]], 2.0)[0]          # a lone raised column
    earlier = [LookEnds(o, np.vstack([_ends_seen(o, edge, 1.5),
                                      _ends_seen(o, [[-3.0, 4.0]], 2.0)]), _proves_all)
               for o in places]
    k = raised_columns(ends, now, earlier)
    assert np.flatnonzero(np.isfinite(k)).tolist() == list(range(60, 67))
    assert k[60:67] == pytest.approx(1.5)
    assert np.isnan(raised_columns(ends, now, earlier, min_columns=8)).all()


def test_a_face_of_the_floors_grey_is_found_raised_from_three_rendered_looks():
    """raised_by_motion on rendered looks of bench/drive.py's room 860: box 4's
    front (z = 4.595 ft, 0.908 ft tall: k = 3 / 2.092 = 1.434 at its top) has a
    tile's grey, so the runs of the columns in front of it go on up the face.
    Seen from 4.3 and 3.4 ft before it, and now from 2.5 ft, every run that
    ends on the face is raised, with k no more than the top's and at least
    1.3, and the edge's points it gives lie within 0.1 ft of the face.  No run
    that ends on the floor or at a wall's skirting is."""
    from planner.appearance import LookEnds, raised_by_motion
    from world.room import generate_room
    room = generate_room(860)
    box = room.obstacles[3]
    floor = [i for i, q in enumerate(room.quads) if q.name == "floor"][0]
    looks = []
    for seed, (x, before) in enumerate(((0.3, 4.3), (1.2, 3.4), (0.76, 2.5))):
        pose = Pose(x, box[2] - before, 0.0, PITCH)
        look = render_look(room, pose, seed=3 + seed, supersample=2)
        pic = look.left_bi
        greys = floor_greys(np.bincount(pic[look.surface_left == floor].astype(int),
                                        minlength=16))
        assert list(np.flatnonzero(greys)) == [3, 5]
        rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
        top = floor_run(pic, greys, bridge=True)
        cols = np.flatnonzero((top > 1) & (top < ROWS))
        ends = np.column_stack([rays.x[top[cols], cols], rays.z[top[cols], cols]])
        on = [room.quads[look.surface_left[top[c] - 1, c]].name for c in cols]
        looks.append((pose.camera_centre("left")[[0, 2]], ends, on))
    now, ends, on = looks[2]
    k = raised_by_motion(ends, now, [LookEnds(o, e, _proves_all) for o, e, _ in looks[:2]])
    face = np.array([name == "box 4 front" for name in on])
    assert face.sum() > 80
    assert np.isfinite(k[face]).all()
    assert (k[face] >= 1.3).all() and (k[face] <= 3.0 / (3.0 - 0.908) + 1e-3).all()
    edge = now + (ends[face] - now) / k[face, None]
    assert np.abs(edge[:, 1] - box[2]).max() < 0.1
    flat = np.array([name == "floor" or "skirting" in name for name in on])
    assert flat.sum() > 20 and np.isnan(k[flat]).all()


def test_a_located_point_cuts_the_floor_ends_within_a_box_width_of_its_column():
    """By hand (``wall_runs="flat-foot"``): a point located on the ray of row 40, column
    64, 4 ft out horizontally, its range error 0.2 ft.  A box face 1 ft wide beside it
    spans 1 ft x 180 px / its range columns either side: those of the given columns end
    at the point less its error, the others and the columns not given keep their ends;
    a point nearer than the scan's minimum range cuts nothing."""
    from planner.appearance import beside_points
    pose = Pose(0.0, 0.0, 0.0, PITCH)
    rays = floor_rays(pose.rotation(), pose.camera_centre("left"))
    p = _point_on_ray(rays, 40, 64, 4.0, ep=0.2)
    half = math.ceil(1.0 * 180.0 / p.dp)
    assert half == math.ceil(180.0 / p.dp) and 20 < half < 45
    reach = np.full(128, 9.0)
    columns = np.ones(128, bool)
    columns[70] = False
    out = beside_points([p], rays, reach, columns, 1.0)
    cut = np.zeros(128, bool)
    cut[64 - half:64 + half + 1] = True
    cut[70] = False
    assert out[cut] == pytest.approx(3.8)
    assert (out[~cut] == 9.0).all()
    assert (beside_points([p], rays, reach, columns, 1.0, min_range_ft=p.dp + 0.1) == 9.0).all()
    near = np.full(128, 2.0)                     # an end nearer than the point stays
    assert (beside_points([p], rays, near, columns, 1.0) == 2.0).all()


def test_a_cell_is_confirmed_by_a_second_look_from_another_bearing():
    """``BearingsApart(20)``: a cell 5 ft ahead, first held from (0, 0); a look from
    (0.5, 0) sees it 5.7 deg apart (held still, the first position kept), one from (2, 0)
    21.8 deg apart confirms it, and it is held no longer; a cell at (3, 5) those two
    looks see 19.7 deg apart stays held."""
    from planner.perception import BearingsApart
    b = BearingsApart(20.0)
    keys, centres = np.array([7, 8]), np.array([[0.0, 5.0], [3.0, 5.0]])
    assert len(b.confirm(keys, centres, (0.0, 0.0))) == 0
    assert len(b.confirm(keys[:1], centres[:1], (0.5, 0.0))) == 0
    assert b.confirm(keys, centres, (2.0, 0.0)).tolist() == [7]    # cell 8: 31.0, 11.3 deg
    assert 7 not in b.first and b.first[8] == (0.0, 0.0) and b.confirmed == 1
    with pytest.raises(ValueError, match="positive angle"):
        BearingsApart(0.0)


def test_room_95_keeps_out_of_a_box_face_of_the_floors_grey_only_under_bearings_30_deg_apart(
        monkeypatch, tmp_path):
    # bench/drive.py's room 95 under its own odometry noise, with the evidence looked at once
    # from each place (looks_per_viewpoint 1, a named option): box 5's front (x -6.81..-4.95
    # at z 4.29, 2.8 ft tall) is of grey 5 on a flat floor of 5, before a left wall of 5.
    # Under flat-foot with bearings 20 deg apart (the default) two looks 22 deg apart (looks
    # 4 and 20) prove its front row of cells, the vehicle drives up to the face and its
    # pivot there runs into the box; with 30 deg (`--flat-foot-apart 30`) it keeps out.
    # The world's exact geometry judges both: the true footprint against the true room.
    from planner.loop import HIT, DriveConfig, _check_config
    from rigtools import bench_drives, drive_config
    from world.room import generate_room
    assert drive_config(monkeypatch, tmp_path, "--flat-foot-apart",
                        "30").flat_foot_apart_deg == 30.0
    monkeypatch.undo()                                  # (drive_config stubs the loop)
    for bad in (0.0, -5.0, 180.0, True):
        with pytest.raises(ValueError, match="flat_foot_apart_deg must be"):
            _check_config(DriveConfig(goal=(0.0, 5.0), flat_foot_apart_deg=bad))
    shades = {q.name: str(q.shade) for q in generate_room(95).quads}
    assert shades["floor"] == shades["box 5 front"] == shades["left wall"] == "flat(5)"
    goal, res = bench_drives(95, "flat_foot_apart_deg", (20.0, 30.0), looks_per_viewpoint=1)
    assert res[20.0].collisions == 1 and res[20.0].reason == HIT
    end = res[20.0].true_track[-1]
    assert -6.81 < end.x < -4.947 and 4.293 - 1.0 < end.z < 4.293   # before box 5's front
    assert res[30.0].collisions == 0
