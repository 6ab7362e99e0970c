"""A sight line to a located point frees the height band only where its ray
runs low (``DriveConfig.sight_lines="low"``, ``floor_scan(low_y=...)``,
:func:`planner.perception.low_start`), on hand-made looks of the drive's own
camera (3 ft up, pitched 25 deg down) whose answer is derived here from the
ray's geometry: a ray through picture line ``l`` drops ``Y`` ft over ``D`` ft
of floor, so at ``r`` ft it is ``Y * r / D`` below the camera, and an obstacle
0.8 ft tall (top at room Y 2.2) would cross it from ``r = 2.2 * D / Y`` on."""

import math

import numpy as np
import pytest

from planner.evidence import SIGHT_TO_HIT, FreeProvenance, Perception, free_obstacle_cells
from planner.floormap import FLOOR_Y
from planner.loop import DriveConfig
from planner.octree import FREE, OCCUPIED, UNCERTAIN, UNKNOWN, VolumeOfInterest
from planner.perception import CX_128, CY_128, FOCAL_128, floor_scan, low_start
from rig.scan import Point
from vehicle.sim import State
from world.pose import Pose

PITCH = -25.0
POSE = Pose(0.0, 0.0, 0.0, PITCH)
R = POSE.rotation()
LEFT = POSE.camera_centre("left")
LOW_Y = FLOOR_Y - 0.8                     # the lowest obstacle's top (0.8 ft boxes)
BAND = DriveConfig.band
BOUNDS = (-10.0, 10.0, -4.0, 12.0)
WALL_FT = 8.0                             # the located edge's horizontal distance


def _ray(col, line):
    """The room direction of picture column ``col`` (1-based), line ``line``."""
    return R @ np.array([(col - 0.5 - CX_128) / FOCAL_128, (line + 0.5 - CY_128) / FOCAL_128,
                         1.0])


def _on_wall(col, line, dist=WALL_FT):
    """(range dp, room point) of the point column ``col``, line ``line`` sees at
    ``dist`` ft of floor from the left camera."""
    u = _ray(col, line)
    dp = dist / math.hypot(u[0], u[2])
    return dp, LEFT + dp * u


def _edge(col, lines, dist=WALL_FT, ep=0.1):
    """A vertical edge at ``dist`` ft located on ``lines`` of column ``col``."""
    return [Point(line, 1, col, col - 10, _on_wall(col, line, dist)[0], 0.0, 0.0, ep, 0.01,
                  0.01) for line in lines]


def _drop(line, dist=WALL_FT):
    return _on_wall(64, line, dist)[1][1] - LEFT[1]


def _lines_down_to(y_max, dist=WALL_FT):
    """The drive's scan lines (8, 10, ... 112) whose point at ``dist`` lies in the
    band no lower than room Y ``y_max``."""
    return [ln for ln in range(8, 113, 2)
            if BAND[0] <= _on_wall(64, ln, dist)[1][1] <= min(y_max, BAND[1])]


def test_low_start_is_where_the_ray_drops_to_the_lowest_obstacles_top():
    o = np.array([0.0, 0.0, 0.0])
    pts = np.array([[0.0, 2.0, 8.0],          # drops 2 ft over 8: at 2.2 ft only past 8.8
                    [6.0, 2.75, 8.0],         # 2.75 ft over 10 (6, 8): 2.2 ft at 8 ft
                    [0.0, -0.3, 8.0],         # a rising ray never gets there
                    [0.0, 0.0, 5.0]])         # nor a level one
    assert low_start(pts, o, 2.2) == pytest.approx([8.8, 8.0, math.inf, math.inf])
    assert low_start(pts, o, 0.0) == pytest.approx([0.0] * 4)   # nothing to hide under


def _box_over_which(top_y, near=4.2, far=4.8):
    """A box across column 64 from ``near`` to ``far`` ft whose top is at room Y
    ``top_y``, and the scan lines of the wall edge behind it that still show
    over it (their ray at the box's far face above its top)."""
    x = LEFT[0] + (64 - 0.5 - CX_128) / FOCAL_128 * 4.5
    box = np.array([[x - 0.3, x + 0.3, near, far]])
    return box, _lines_down_to(top_y * WALL_FT / far)


def _model(sight_lines, place="axis"):
    m = Perception(VolumeOfInterest(32.0, 7), BAND, 12.0, 2, 1, near_ft=2.3, blank_ft=None)
    m.blank_carve, m.carve, m.blank_px = "unknown", "error", 16
    m.sight_lines, m.place = sight_lines, place
    m.provenance = FreeProvenance()
    return m


def _free_along(m, col=64):
    """The horizontal distances (ft from the left camera) of the FREE cells on
    the floor map along column ``col``'s bearing, sampled every 0.05 ft."""
    fm = m.floor_map([(0.0, 0.0), (0.0, 9.0)])
    u = _ray(col, 60)
    u = np.array([u[0], u[2]]) / math.hypot(u[0], u[2])
    out = []
    for r in np.arange(0.05, WALL_FT, 0.05):
        i, j = fm.index(LEFT[0] + r * u[0], LEFT[2] + r * u[1])
        if fm.cells[i, j] == FREE:
            out.append(r)
    return fm, np.array(out)


def test_a_wall_point_over_a_low_box_no_longer_frees_the_box():
    # a box 1.5 ft tall (top at Y 1.5) 4.2-4.8 ft away; the wall edge 8 ft away shows
    # over it down to Y 1.5 * 8 / 4.8 = 2.5, so its lowest located point drops 2.5 ft
    # over 8 (within a line's step) and its ray reaches Y 2.2 at 2.2 * 8 / 2.5 = 7.04 ft
    box, lines = _box_over_which(FLOOR_Y - 1.5)
    look = _edge(64, lines)
    y_low = _drop(lines[-1])
    assert 2.4 < y_low <= 2.5
    fs = floor_scan(look, R, LEFT, BAND, low_y=LOW_Y)
    assert fs.hit_start == pytest.approx([2.2 * WALL_FT / y_low], rel=1e-6)
    assert fs.hit_start[0] > 7.0
    # the floor scan is otherwise the same: the same hit where it was
    plain = floor_scan(look, R, LEFT, BAND)
    assert np.allclose(fs.hits, plain.hits) and plain.hit_start is None

    band = _model("band")
    band.update(look, State(0.0, 0.0, 0.0), Pose, PITCH)
    fm = band.floor_map([(0.0, 0.0), (0.0, 9.0)])
    freed = free_obstacle_cells(fm, box, BOUNDS, band.provenance, BAND)
    assert freed and all(c["mechanisms"] == [SIGHT_TO_HIT] for c in freed)

    low = _model("low")
    low.update(look, State(0.0, 0.0, 0.0), Pose, PITCH)
    fm, along = _free_along(low)
    assert not free_obstacle_cells(fm, box, BOUNDS, low.provenance, BAND)
    assert low.seen_over > 0                 # the rest of the line: seen over, not proven
    # the loop's "axis" placement lays the hit along the pitched axis, short of 8 ft
    # (the nearest supported point's range times about cos 25 deg): before 7.04 ft,
    # so this line frees nothing at all
    hit_d = math.hypot(fs.hits[0, 0] - LEFT[0], fs.hits[0, 2] - LEFT[2])
    assert hit_d < fs.hit_start[0] and not len(along)
    # placed at the point's own horizontal distance (8 ft), the line frees from 7.04 ft
    # to a cell before the hit, and still nothing of the box
    low = _model("low", place="point")
    low.update(look, State(0.0, 0.0, 0.0), Pose, PITCH)
    fm, along = _free_along(low)
    assert not free_obstacle_cells(fm, box, BOUNDS, low.provenance, BAND)
    assert len(along) and along.min() >= fs.hit_start[0] - 0.25
    assert along.max() <= WALL_FT


def test_a_bare_floor_still_frees_the_far_part_of_the_line():
    # no box: the edge shows down to the band's bottom (Y 2.75); its lowest ray reaches
    # Y 2.2 at 2.2 * 8 / y_low ft (about 0.8 of the way); the band rule freed from 2.3 ft
    lines = _lines_down_to(BAND[1])
    look = _edge(64, lines)
    y_low = _drop(lines[-1])
    assert 2.65 < y_low <= 2.75
    start = 2.2 * WALL_FT / y_low
    band, low = _model("band", "point"), _model("low", "point")
    for m in (band, low):
        m.update(look, State(0.0, 0.0, 0.0), Pose, PITCH)
    _, along_band = _free_along(band)
    _, along_low = _free_along(low)
    assert along_band.min() < 2.6                            # from the near limit
    assert along_low.min() == pytest.approx(start, abs=0.3)   # from where the ray runs low
    # the far part is freed as before: every distance free there under "band" still is
    far = along_band[along_band >= start + 0.25]
    assert len(far) and np.isin(np.round(far, 2), np.round(along_low, 2)).all()


def test_a_point_low_on_the_floor_frees_most_of_its_line():
    # a located point 0.25 ft above the floor (Y 2.75) at 4 ft: free from 3.2 ft
    lines = _lines_down_to(BAND[1], dist=4.0)
    fs = floor_scan(_edge(64, lines, dist=4.0), R, LEFT, BAND, low_y=LOW_Y)
    assert fs.hit_start[0] == pytest.approx(2.2 * 4.0 / _drop(lines[-1], 4.0), rel=1e-6)
    assert 3.1 < fs.hit_start[0] < 3.4


def test_columns_between_and_beside_take_their_bounding_hits_start():
    # two edges 20 columns apart, one showing down to the band's bottom, one only to
    # Y 2.0: the columns between take the later (larger) start, the blank ones beside
    # each outermost edge that edge's own
    low_lines, high_lines = _lines_down_to(BAND[1]), _lines_down_to(2.0)
    look = _edge(50, low_lines) + _edge(70, high_lines)
    fs = floor_scan(look, R, LEFT, BAND, blank_ft=8.0, blank_px=16, low_y=LOW_Y)
    s50, s70 = fs.hit_start
    assert s50 < s70
    cols = np.asarray(fs.free_cols)
    assert fs.free_start[(cols > 50) & (cols < 70)] == pytest.approx(s70)
    assert fs.free_start[cols < 50] == pytest.approx(s50)
    assert fs.free_start[cols > 70] == pytest.approx(s70)
    assert fs.far_start[np.asarray(fs.far_cols) < 50] == pytest.approx(s50)


def _floor_picture(face_cols=None):
    """The left picture of a bare floor (grey 3) out to the wall's foot 8 ft
    away, the wall (grey 9) above; ``face_cols`` (0-based): columns where a
    face of the floor's grey goes on up to the picture's top row."""
    from planner.appearance import floor_rays
    pic = np.full((120, 128), 9, np.uint8)
    pic[floor_rays(R, LEFT).dist <= WALL_FT] = 3
    if face_cols is not None:
        pic[:, face_cols] = 3
    return pic


@pytest.mark.parametrize("how", ["bound", "bound-add", "carve"])
def test_the_learned_floor_proves_the_part_a_high_point_does_not(how):
    """A wall edge 8 ft away located down to 2.5 ft below the camera only (as
    over a box): under ``low`` its line proves the band from 7.04 ft on
    (2.2 x 8 / 2.5).  The floor's grey learned, the picture shows the floor
    out to the wall's foot, which proves its trace from 2.33 ft (the near
    limit) to a cell short of 8 ft: ``bound-add`` and ``carve`` carve that,
    ``bound`` does not.  Where a face of the floor's grey runs up to the
    picture's top (columns 44-84) the column shows no end of the floor:
    ``bound-add`` proves nothing there, ``carve`` carves the same proof as
    before, which is the hazard of a face of the floor's grey."""
    lines = _lines_down_to(2.5)
    look = _edge(64, lines)
    start = 2.2 * WALL_FT / _drop(lines[-1])
    assert 7.0 < start < 7.3
    along = {}
    for face in (None, slice(44, 85)):
        m = _model("low", place="point")
        m.floor_eyes = how
        m.floor_hist[3] = 1000.0                 # the floor's grey, as if learned
        m.update(look, State(0.0, 0.0, 0.0), Pose, PITCH, None, None, _floor_picture(face))
        along[face is None] = _free_along(m)[1]
    bare, face = along[True], along[False]
    assert len(bare) and bare.max() <= WALL_FT
    if how == "bound":
        assert bare.min() >= start - 0.3 and face.min() >= start - 0.3
        return
    # the floor's proof: from the near limit, 2.2 ft + 1/3 of the bottom row's 3.5 ft
    assert bare.min() < 2.6
    assert np.isin(np.round(np.arange(2.6, 7.5, 0.05), 2), np.round(bare, 2)).all()
    if how == "bound-add":
        assert not len(face) or face.min() >= start - 0.3
    else:
        assert face.min() < 2.6


def test_the_default_is_low_and_a_bad_value_is_refused():
    assert DriveConfig((0.0, 0.0)).sight_lines == "low"
    from planner.loop import run
    from world.room import generate_room
    room = generate_room(1)
    s = room.start
    with pytest.raises(ValueError, match="sight_lines"):
        run(room, State(s.x, s.z, s.heading_deg), DriveConfig((0.0, 0.0), sight_lines="ray"))


def test_a_look_that_located_nothing_frees_only_the_far_part_under_low_all():
    # nothing located, blank_ft 8: "low" keeps the assumption whole (start 0); "low-all"
    # takes the blank view as a surface at 8 ft seen down to the band's bottom (Y 2.75):
    # its lowest ray reaches Y 2.2 at 8 * 2.2 / 2.75 = 6.4 ft
    low = floor_scan([], R, LEFT, BAND, blank_ft=8.0, low_y=LOW_Y)
    assert len(low.free_ends) == 128 and np.all(low.free_start == 0.0)
    both = floor_scan([], R, LEFT, BAND, blank_ft=8.0, low_y=LOW_Y, blind_low=True)
    assert both.free_start == pytest.approx(np.full(128, 8.0 * 2.2 / 2.75))
    # a look that located something is not changed by it
    look = _edge(64, _lines_down_to(BAND[1]))
    a = floor_scan(look, R, LEFT, BAND, blank_ft=8.0, blank_px=16, low_y=LOW_Y)
    b = floor_scan(look, R, LEFT, BAND, blank_ft=8.0, blank_px=16, low_y=LOW_Y, blind_low=True)
    assert np.array_equal(a.free_start, b.free_start)
    m = _model("low-all")
    m.blank_ft = 8.0
    m.update([], State(0.0, 0.0, 0.0), Pose, PITCH)
    _, along = _free_along(m)
    assert len(along) and along.min() >= 6.4 - 0.25


def test_a_hits_line_ends_at_the_near_end_of_its_error_bound():
    # a point 0.25 ft above the floor at 6 ft, located with a 2-sigma bound of 0.8 ft of
    # range: along the floor that is 0.8 * 6 / range ft, and the line stops that far short
    # (it may lie that far behind the face it is on); from 0.8 * 6 ft on it is low enough
    lines = _lines_down_to(BAND[1], dist=6.0)
    look = _edge(64, lines, dist=6.0, ep=0.8)
    fs = floor_scan(look, R, LEFT, BAND, low_y=LOW_Y, place="point")
    dp = min(p.dp for p in look)                           # the nearest supported range
    assert fs.hit_short == pytest.approx([0.8 * 6.0 / dp], rel=1e-3)
    m = _model("low", place="point")
    m.update(look, State(0.0, 0.0, 0.0), Pose, PITCH)
    _, along = _free_along(m)
    assert len(along)
    assert along.min() >= fs.hit_start[0] - 0.25
    assert along.max() <= 6.0 - fs.hit_short[0] + 0.25 and along.max() < 5.6


def test_the_depth_eyes_are_not_changed_by_it():
    # the depth eyes see the box face itself in the band (every pixel has its range), so
    # their floor scan has no start and "low" leaves their map as it was
    rng = np.full((120, 128), 6.0)
    maps = []
    for v in ("band", "low"):
        m = _model(v)
        m.update([], State(0.0, 0.0, 0.0), Pose, PITCH, depth=rng)
        maps.append(m.floor_map([(0.0, 0.0), (0.0, 9.0)]).cells)
    assert np.array_equal(*maps) and (maps[0] == FREE).any()


def test_the_tiny_room_under_low_frees_no_floor_before_8_ft_and_stops_safely():
    # the tiny room's floor is bare: the edge eyes locate only its walls and its box.  Straight
    # ahead the nearest located points are the back wall's, 10 ft away; the lowest of them in
    # the band (its bottom, 2.75 ft below the camera) drops to the lowest obstacle's top
    # (2.2 ft below it) only 2.2 * 10 / 2.75 = 8 ft out.  So under low the first look frees
    # the line x = 0 nowhere between the start spot (free to 2.5 ft, grown to its cell) and
    # 8 ft, where band frees all of it; the drive then never proves the way free and stops,
    # without a collision (the loop's tiny-room tests pin band for that reason); under the
    # dead-reckoned estimate and the floor in view's rules before 2026-12-05, as traced.
    # Without the step back that learns the floor's grey (learn_floor "off", before
    # 2026-12-05 09:30) the floor in view proves nothing either: the same first look.
    # With it (the default since) that look's floor proof frees the whole line, as the
    # room's truth has it (the box stands at x 1.2-2.6), and the defaults, the rig's own
    # eyes, reach the goal; without it they stop as above.
    from planner.loop import run
    from rigtools import DRIVE_BEFORE_2026_12_05
    from planner.tiny import GOAL, tiny_room
    from world.odometry import OdometryNoise
    zs = np.arange(3.125, 8.0, 0.25)
    for lines, learn, free in (("band", "off", True), ("low", "off", False),
                               ("low", "step-back", True)):
        fm = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, eyes="truth",
                 sight_lines=lines, learn_floor=learn, max_looks=1)).cycles[0].fmap
        assert [fm.state_at(0.1, z) == FREE for z in zs] == [free] * len(zs), (lines, learn)
    res = run(tiny_room(), State(0.0, 0.0, 0.0),
              DriveConfig(goal=GOAL, eyes="truth", **DRIVE_BEFORE_2026_12_05),
              noise=OdometryNoise(seed=1), keep_maps=False)
    assert not res.reached and "without progress" in res.reason
    assert res.collisions == 0 and res.travelled_ft < 2.5
    for learn, reached in (("off", False), ("step-back", True)):
        res = run(tiny_room(), State(0.0, 0.0, 0.0), DriveConfig(goal=GOAL, learn_floor=learn),
                  noise=OdometryNoise(seed=1), keep_maps=False)
        assert res.reached == reached and res.collisions == 0, (learn, res.reason)


# --- refute_hits="under": a hit cell a later sight line passes under -------------------

def _lines_between(y_min, y_max, dist):
    """The drive's scan lines whose point at ``dist`` ft lies at room Y ``y_min``..``y_max``."""
    return [ln for ln in range(8, 113, 2) if y_min <= _on_wall(64, ln, dist)[1][1] <= y_max]


def _state_at_hit(m, fs_hit):
    fm = m.floor_map([(0.0, 0.0), (0.0, 9.0)])
    return fm.state_at(fs_hit[0], fs_hit[2])


def _two_looks(first, refute):
    m = _model("low")
    m.refute_hits = refute
    m.update(first, State(0.0, 0.0, 0.0), Pose, PITCH)
    hit = floor_scan(first, R, LEFT, BAND, low_y=LOW_Y).hits[0]
    before = _state_at_hit(m, hit)
    # the second look: the wall edge at 8 ft shown down to the band's bottom, its lowest
    # ray dropping 2.65-2.75 ft over 8 ft (2.75 * r / 8 below the camera at r ft)
    m.update(_edge(64, _lines_down_to(BAND[1])), State(0.0, 0.0, 0.0), Pose, PITCH)
    return m, hit, before, _state_at_hit(m, hit)


def test_a_false_hit_a_later_ray_passes_under_shows_unknown_never_free():
    # a false match: an "edge" 4.5 ft away located only 0.5-1.2 ft below the camera (1.8-2.5 ft
    # above the floor).  A real surface there, standing on the floor, would stop the
    # second look's ray, which is 2.75 * 4.5 / 8 = 1.55 ft down there (1.4 ft a cell
    # nearer): lower than the claimed point, and it reached the wall at 8 ft
    lines = _lines_between(0.5, 1.2, 4.5)
    assert len(lines) >= 2
    first = _edge(64, lines, dist=4.5, ep=0.05)
    drop = floor_scan(first, R, LEFT, BAND, low_y=LOW_Y).hit_drop[0]
    assert 1.1 < drop <= 1.2
    m, hit, before, after = _two_looks(first, "under")
    assert before == UNCERTAIN and after == UNKNOWN and m.refuted > 0
    # without the option the hit stays (the ray over it, nearer than 2.2 * 8 / 2.75 = 6.4 ft,
    # proves nothing there under low)
    m, hit, before, after = _two_looks(first, "off")
    assert before == after == UNCERTAIN and m.refuted == 0


def test_a_real_low_boxs_hit_is_not_refuted_by_a_ray_over_it():
    # a real box 1.5 ft tall 4.2-4.8 ft away: its near face's vertical edge located from its
    # top (1.5 ft below the camera) to the band's bottom; the wall edge behind shows over it
    # only down to 1.5 * 8 / 4.8 = 2.5 ft at 8 ft, a ray 2.5 * 4.2 / 8 = 1.31 ft down at the
    # face: over the box's top, above every point of its edge.  Nothing is refuted
    face = _edge(64, _lines_between(1.5, BAND[1], 4.2), dist=4.2, ep=0.05)
    m = _model("low")
    m.refute_hits = "under"
    m.update(face, State(0.0, 0.0, 0.0), Pose, PITCH)
    hit = floor_scan(face, R, LEFT, BAND, low_y=LOW_Y).hits[0]
    assert _state_at_hit(m, hit) == UNCERTAIN
    _, over = _box_over_which(FLOOR_Y - 1.5)
    m.update(_edge(64, over), State(0.0, 0.0, 0.0), Pose, PITCH)
    assert _state_at_hit(m, hit) == UNCERTAIN and m.refuted == 0
    # the face's claim is its lowest located point, near the band's bottom (2.75 ft down):
    # even a ray to the floor line at 8 ft (2.75 * 4 / 8 = 1.4 ft down there) passes over it
    m.update(_edge(64, _lines_down_to(BAND[1])), State(0.0, 0.0, 0.0), Pose, PITCH)
    assert _state_at_hit(m, hit) == UNCERTAIN and m.refuted == 0


def test_refute_hits_is_off_by_default_and_a_bad_value_is_refused():
    from planner.loop import run
    from world.room import bundled_lab
    assert DriveConfig.refute_hits == "off"
    with pytest.raises(ValueError, match="refute_hits"):
        run(bundled_lab(), State(0.0, 0.0, 0.0), DriveConfig(goal=(4.5, 11.0), refute_hits="x"))


# --- refute_hits="through": a hit a later, nearer look sees through --------------------

NEARER = 1.5                              # the second look stands this much nearer (ft)


def _through_model():
    m = _model("low")
    m.refute_hits = "through"
    return m


def _seen_at(point, z_cam):
    """The scan lines within 4 of where the room ``point`` shows from the left
    camera moved ``z_cam`` ft forward (the same heading and pitch: R is the
    same), and its column."""
    c = R.T @ (np.asarray(point) - (LEFT + np.array([0.0, 0.0, z_cam])))
    col = c[0] / c[2] * FOCAL_128 + CX_128 + 0.5
    row = c[1] / c[2] * FOCAL_128 + CY_128 - 0.5
    return c[2], int(round(col)), [ln for ln in range(8, 113, 2) if abs(ln - row) <= 4]


def _far_edge(col, lines, dist, ep=0.1):
    """:func:`_edge` located from the nearer camera, ``dist`` ft of floor from it
    (R is the same, so the range along the axis is the same function of dist)."""
    return _edge(col, lines, dist, ep)


def _false_hit_then(second, state=State(0.0, NEARER, 0.0)):
    m = _through_model()
    first = _edge(64, _lines_between(0.5, 1.2, 4.5), dist=4.5, ep=0.05)
    m.update(first, State(0.0, 0.0, 0.0), Pose, PITCH)
    fs = floor_scan(first, R, LEFT, BAND, low_y=LOW_Y)
    before = _state_at_hit(m, fs.hits[0])
    m.update(second(fs), state, Pose, PITCH)
    return m, fs, before, _state_at_hit(m, fs.hits[0])


def test_a_hit_a_nearer_look_sees_through_shows_unknown_never_free():
    # a false match 4.5 ft away (0.5-1.2 ft below the camera).  From 1.5 ft nearer its
    # located point is 3 ft ahead on the axis; the second look locates a wall edge 6.5 ft
    # of floor away on the very pixels where that point would show: its rays went through
    # the place the hit says is solid
    def wall_behind(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        assert 2.5 <= z < fs.hit_range[0] and len(lines) >= 2
        return _far_edge(col, lines, 6.5)
    m, fs, before, after = _false_hit_then(wall_behind)
    assert fs.hit_xyz[0][2] == pytest.approx(4.5, abs=0.01)      # at its 4.5 ft, in 3-D
    assert before == UNCERTAIN and after == UNKNOWN and m.refuted > 0
    assert m.seen_through[:1].all()


def test_a_hit_seen_again_where_it_is_is_not_refuted():
    # the same point located again from nearer (a real edge): confirmed, not refuted
    def same_place(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        return _far_edge(col, lines, 4.5 - NEARER, ep=0.05)
    m, fs, before, after = _false_hit_then(same_place)
    assert before == UNCERTAIN and after != UNKNOWN and m.refuted == 0
    assert not m.seen_through.any()


def test_a_point_beyond_within_the_error_bounds_or_alone_refutes_nothing():
    # 0.3 ft behind the claim, located within 0.35 ft (the claim's 2 sigma, 0.05 ft, and
    # the point's ep, 0.3 ft, summed): they may be one surface, not seen through
    def just_behind(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        return _far_edge(col, lines, 4.5 - NEARER + 0.3, ep=0.3)
    m, _, before, after = _false_hit_then(just_behind)
    assert before == after == UNCERTAIN and m.refuted == 0

    # one located point beyond (a false match of the later look, perhaps): not enough
    def one_point(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        return _far_edge(col, lines[:1], 6.5) + _edge(20, [60, 62], 6.5)
    m, _, before, after = _false_hit_then(one_point)
    assert before == after == UNCERTAIN and m.refuted == 0


def test_an_edge_seen_again_beside_the_surface_behind_it_is_not_refuted():
    # an occluding boundary: the later look locates the claim's edge again at its place
    # (two lines, its column) and the wall behind it beside it (two lines, the next
    # column): the edge is there, so it is not seen through
    def edge_and_wall(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        return _far_edge(col, lines[:2], 4.5 - NEARER, ep=0.05) + \
            _far_edge(col + 1, lines[1:3], 6.5)
    m, _, before, after = _false_hit_then(edge_and_wall)
    assert before == UNCERTAIN and after != UNKNOWN and m.refuted == 0

    # the same wall with the edge seen on one line only (a false match there is as likely):
    # seen through
    def one_line_and_wall(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
        return _far_edge(col, lines[:1], 4.5 - NEARER, ep=0.05) + \
            _far_edge(col + 1, lines[1:3], 6.5)
    m, _, before, after = _false_hit_then(one_line_and_wall)
    assert before == UNCERTAIN and after == UNKNOWN and m.refuted > 0


def test_a_look_no_nearer_than_the_hits_own_refutes_nothing():
    # a later look from the very place of the first, locating a wall 8 ft away on the
    # hit's own pixels: it sees the claim no more sharply than the look that located it
    # (one of the two is a false match, and which is not known), so it is not taken
    # against it
    def wall_from_there(fs):
        z, col, lines = _seen_at(fs.hit_xyz[0], 0.0)
        assert z == pytest.approx(fs.hit_range[0]) and len(lines) >= 2
        return _far_edge(col, lines, 8.0)
    m, _, before, after = _false_hit_then(wall_from_there, State(0.0, 0.0, 0.0))
    assert before == after == UNCERTAIN and m.refuted == 0


def test_a_confirmed_cell_stays_and_a_refuted_one_comes_back_when_hit_again():
    m = _through_model()
    first = _edge(64, _lines_between(0.5, 1.2, 4.5), dist=4.5, ep=0.05)
    fs = floor_scan(first, R, LEFT, BAND, low_y=LOW_Y)
    z, col, lines = _seen_at(fs.hit_xyz[0], NEARER)
    m.update(first, State(0.0, 0.0, 0.0), Pose, PITCH)
    m.update(first, State(0.0, 0.0, 0.0), Pose, PITCH)        # hit twice: occupied
    assert _state_at_hit(m, fs.hits[0]) == OCCUPIED
    m.update(_far_edge(col, lines, 6.5), State(0.0, NEARER, 0.0), Pose, PITCH)
    assert m.seen_through[:2].all()                          # both of its hits
    assert _state_at_hit(m, fs.hits[0]) == OCCUPIED          # confirmed cells never go
    # a refuted once-hit cell, located again, is back
    m, fs, before, after = _false_hit_then(lambda fs: _far_edge(
        *_seen_at(fs.hit_xyz[0], NEARER)[1:], 6.5))
    assert after == UNKNOWN
    m.update(first, State(0.0, 0.0, 0.0), Pose, PITCH)
    assert _state_at_hit(m, fs.hits[0]) in (UNCERTAIN, OCCUPIED)


def test_refute_hits_through_reaches_the_loop():
    from rig.drive import add_loop_options, loop_config
    import argparse
    ap = argparse.ArgumentParser()
    add_loop_options(ap)
    cfg = loop_config(ap.parse_args(["--refute-hits", "through"]), (4.5, 11.0), ap.error)
    assert cfg.refute_hits == "through"
