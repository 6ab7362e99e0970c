"""The improved matcher on hand-made lines whose right answer is known:
a picket fence whose first picket only the left camera sees, an occluded feature
that must get "no match", a line where the 1985 matcher (MASL + LCSL, run here
on the same maps) takes a wrong partner; each constraint on its own; the
MARF measure, the DP kernel and the sub-pixel step against independent
computations."""

from dataclasses import replace

import numpy as np
import pytest

from diskfmt.dgreal import Real
from estar.lcsl import lcsl, locate
from estar.masl import MatchTables, masl
from masl_wrappers import marf_shift
from matching import Constraints, LineData, Params, match_line, match_lines
from matching.candidates import candidates, shape_cost, slice_edges
from matching.mode import (DEFAULT_CONSTRAINTS, VerdictTables, constraints_from_args,
                           locate_float, make_matcher)
from matching.order import assign, order_dp
from matching.subpixel import step_position



def random_map(seed: int) -> list[int]:
    """A 17-word edge map (flag 1, then 16 columns of about 8 bits each)."""
    r = np.random.default_rng(seed)
    cols = [int(sum(1 << b for b in r.choice(16, 8, replace=False))) for _ in range(16)]
    return [1] + cols


def damaged(m: list[int], flips: int, seed: int) -> list[int]:
    """``m`` with ``flips`` set bits cleared: mismatch 256*f/(2n-f) at shift 0."""
    r = np.random.default_rng(seed)
    out = list(m)
    bits = [(c, b) for c in range(1, 17) for b in range(16) if out[c] >> b & 1]
    for k in r.choice(len(bits), flips, replace=False):
        c, b = bits[k]
        out[c] &= ~(1 << b)
    return out


class Line:
    """A hand-made line: features (start, stop, lgrey, rgrey) with a map for
    each end, in both slices."""

    def __init__(self):
        self.f = ([], [])
        self.maps = (np.zeros((100, 17), dtype=np.int64), np.zeros((100, 17), dtype=np.int64))

    def add(self, side: int, start: int, lg: int, rg: int, left_map, right_map, width=2):
        k = len(self.f[side]) + 1
        self.f[side].append((start, start + width, lg, rg))
        self.maps[side][k - 1] = left_map
        self.maps[side][k + 49] = right_map
        return k

    def data(self, iy=60) -> LineData:
        return LineData(iy, list(self.f[0]), list(self.f[1]), self.maps[0].copy(),
                        self.maps[1].copy())


def all_on(data: LineData, constraints=Constraints()):
    """Verdicts of ``data``'s line with the line repeated above and below (a
    vertical edge), so the neighbour constraint has lines to look at."""
    stack = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in (data.iyloc - 1, data.iyloc, data.iyloc + 1)]
    return match_lines(stack, constraints)[data.iyloc]


def matched(verdicts):
    return {v.edge: v for v in verdicts if v.matched}


def faithful_disparities(data: LineData) -> dict[int, int]:
    """MASL + LCSL of 1985 on the line's maps: edge -> located disparity."""
    class NoFetch:
        def nblob_many(self, requests, *a):
            assert len(requests) == 0                  # every map is already there
    cols = [[np.array([f[j] for f in fs] + [0] * (50 - len(fs))) for j in range(4)]
            for fs in (data.features1, data.features2)]
    tables = MatchTables()
    masl(data.iyloc, len(data.features1), cols[0], len(data.features2), cols[1],
         data.maps1.copy(), data.maps2.copy(), tables, NoFetch())
    pos = [Real.from_int(0)] * 640
    lcsl(data.iyloc, len(data.features1), tables, pos, Real.const("0.75"), Real.const("180"))
    out = {}
    for e in [k for k in range(1, len(data.features1) + 1)] + \
             [k + 50 for k in range(1, len(data.features1) + 1)]:
        entry = next((x for x in tables.entries(e) if x[2] - x[3] > 1), None)
        if entry is not None and pos[(e - 1) * 6].m > 0:
            out[e] = entry[2] - entry[3]
    return out


# --- the picket fence ---------------------------------------------------------

PICKET_UP, PICKET_DOWN = (random_map(1), random_map(2)), (random_map(3), random_map(4))
ANCHOR = (random_map(5), random_map(6))
D_TRUE = 10


def picket_fence() -> tuple[LineData, dict[int, int | None]]:
    """Five identical pickets 8 px apart in the left slice at disparity 10; the
    first is outside the right picture; a different feature (a door jamb)
    stands beside them on the same wall.  Returns the line and the true
    right-slice feature of each left feature (None: not in the right picture)."""
    line = Line()
    for side, shift in ((0, 0), (1, D_TRUE)):
        for x in (6, 14, 22, 30, 38):
            if x - shift >= 1:
                line.add(side, x - shift, 3, 12, *PICKET_UP)
                line.add(side, x - shift + 3, 12, 3, *PICKET_DOWN)
        line.add(side, 60 - shift, 3, 8, *ANCHOR)
    # features: left  1,2=picket@6  3,4=@14 ... 9,10=@38  11=anchor
    #           right 1,2=picket@4(=left @14) ... 7,8=@28   9=anchor@50
    truth = {1: None, 2: None}
    for k in range(3, 11):
        truth[k] = k - 2
    truth[11] = 9
    return line.data(), truth


def test_picket_fence_1985_takes_wrong_partners():
    data, _ = picket_fence()
    disp = faithful_disparities(data)
    wrong = [e for e, d in disp.items() if d != D_TRUE]
    assert len(wrong) >= 8, disp            # "the best match available": the first picket


def test_picket_fence_order_constraint_solves_it():
    data, truth = picket_fence()
    v = match_line(data, Constraints.only("order"))
    m = matched(v)
    for k, partner in truth.items():
        for e, pe in ((k, partner), (k + 50, partner and partner + 50)):
            if partner is None:
                assert e not in m, f"edge {e} is outside the right picture"
            else:
                assert e in m and m[e].partner == pe, (e, m.get(e))
                assert m[e].disparity == D_TRUE
    first = [x for x in v if x.edge in (1, 51)]
    assert all(x.reason == "occluded" for x in first)


def test_picket_fence_all_constraints_keep_the_answer():
    data, truth = picket_fence()
    lines = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in (59, 60, 61)]
    m = matched(match_lines(lines, Constraints())[60])
    assert {e: x.disparity for e, x in m.items()} == {
        e: D_TRUE for k, p in truth.items() if p is not None for e in (k, k + 50)}


def test_without_order_the_fence_stays_ambiguous():
    """Without the order constraint the pickets are told apart by nothing: with
    no minimum confidence some take wrong partners; by default their
    confidence (no margin over the rival pickets) makes them "ambiguous"."""
    data, _ = picket_fence()
    m = matched(match_line(data, Constraints.none(), Params(min_confidence=0.0)))
    assert any(x.disparity != D_TRUE for x in m.values())
    assert all(x.confidence == 0 for x in m.values() if x.disparity != D_TRUE)
    v = match_line(data, Constraints.none())
    assert all(x.disparity == D_TRUE for x in v if x.matched)
    assert sum(x.reason == "ambiguous" for x in v) >= 8


# --- an occluded feature --------------------------------------------------------

def occluded_line():
    """Left slice: A at 30, F at 50, B at 70; right slice: A at 22, G at 35, B
    at 62 (disparity 8).  F (greys 9->5) is hidden from the right camera; G
    has F's greys and a shape somewhat like it (about 100 of 256 apart), and
    G's true partner is left feature G' at 43, which looks exactly like it."""
    line = Line()
    a, b = (random_map(11), random_map(12)), (random_map(13), random_map(14))
    g = (random_map(15), random_map(16))
    f = (damaged(g[0], 40, 1), damaged(g[1], 40, 2))
    line.add(0, 30, 4, 11, *a)
    line.add(0, 43, 9, 5, *g)
    line.add(0, 50, 9, 5, *f)
    line.add(0, 70, 6, 14, *b)
    line.add(1, 22, 4, 11, *a)
    line.add(1, 35, 9, 5, *g)
    line.add(1, 62, 6, 14, *b)
    return line.data()


def test_occluded_feature_gets_no_match():
    data = occluded_line()
    disp = faithful_disparities(data)
    assert disp.get(3) == 50 - 35 and disp.get(53) == 15     # 1985: the best match available
    for cons in (Constraints(), Constraints.only("order"), Constraints.only("lr")):
        v = {x.edge: x for x in all_on(data, cons)}
        assert not v[3].matched and not v[53].matched, cons
        assert v[3].reason in ("occluded", "not mutual", "ambiguous")
        for e, d in ((1, 8), (2, 8), (4, 8), (51, 8), (52, 8), (54, 8)):
            assert v[e].matched and v[e].disparity == d, (cons, e, v[e])


def test_lr_reports_not_mutual():
    v = {x.edge: x for x in match_line(occluded_line(), Constraints.only("lr"),
                                       Params(lr_tolerance=8))}
    assert v[3].reason == "not mutual"


# --- a wrong partner in 1985, the right one here ---------------------------------

def crossing_line():
    """C at 20 and A at 30 in the left slice, C' at 12 and A' at 22 in the right
    (disparity 8).  A looks a little more like C' (5 bits off) than like its
    own partner A' (10 bits off), so 1985 takes C' for A (disparity 18)."""
    line = Line()
    c = (random_map(21), random_map(22))
    a = (damaged(c[0], 5, 3), damaged(c[1], 5, 4))
    a_right = (damaged(c[0], 15, 3), damaged(c[1], 15, 4))
    line.add(0, 20, 5, 10, *c)
    line.add(0, 30, 5, 10, *a)
    line.add(1, 12, 5, 10, *c)
    line.add(1, 22, 5, 10, *a_right)
    return line.data()


def test_1985_picks_a_wrong_partner_the_improved_mode_does_not():
    data = crossing_line()
    disp = faithful_disparities(data)
    assert disp[2] == 18 and disp[52] == 18                      # A -> C': wrong
    for cons in (Constraints(), Constraints.only("order")):
        m = matched(all_on(data, cons))
        assert {e: x.disparity for e, x in m.items()} == {1: 8, 2: 8, 51: 8, 52: 8}, cons
        assert m[2].partner == 2 and m[52].partner == 52


def test_confidence_is_lower_for_the_contested_match():
    m = matched(match_line(crossing_line(), Constraints.only("order")))
    assert 0 <= m[2].confidence < m[1].confidence <= 1


# --- neighbours and regions -----------------------------------------------------

def test_neighbour_constraint_needs_a_vertical_line():
    data = crossing_line()
    p = Params(min_confidence=0.0)
    lone = match_lines([data], Constraints.only("neighbours"), p)[60]
    assert not any(v.matched for v in lone)
    assert {v.reason for v in lone} == {"not on a vertical line"}
    stack = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in (59, 60, 61)]
    assert matched(match_lines(stack, Constraints.only("neighbours"), p)[60])


def test_neighbour_reach_two_finds_support_two_lines_away():
    data = crossing_line()
    p = Params(min_confidence=0.0)
    stack = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in (58, 60, 62)]
    near = match_lines(stack, Constraints.only("neighbours"), p)[60]
    assert {v.reason for v in near} == {"not on a vertical line"}
    far = match_lines(stack, Constraints.only("neighbours"), replace(p, neighbour_reach=2))[60]
    assert matched(far).keys() == {1, 2, 51, 52}


def test_neighbour_bonus_lets_the_supported_partner_win():
    """A feature whose own map is damaged on line 60 loses to leaving it out
    (see jump_line); with lines 59 and 61 matching it at its disparity, the
    bonus taken off its cost makes the assignment take it."""
    stack = jump_line()
    cons = FOUR
    plain = {v.edge: v for v in match_lines(stack, cons)[60]}
    assert not plain[2].matched and plain[2].reason == "occluded"
    bonus = {v.edge: v for v in match_lines(stack, cons, Params(neighbour_bonus=32))[60]}
    assert bonus[2].matched and bonus[2].disparity == 12
    assert bonus[2].cost == plain_cost(stack[3], 2)          # the reported cost is the evidence


def jump_line(right_e: int = 38, hurt=(60,), lines=range(57, 64)) -> list[LineData]:
    """Lines ``lines`` (57..63): A at 30 and B at 70 at disparity 8, between
    them E at 50 whose partner is at 38 (disparity 12: a jump of 4 px either
    side; on line 60 at ``right_e``).  On the lines in ``hurt`` (60) E's left
    maps are damaged (a cost near 110), so the order-keeping assignment there
    prefers to leave E out rather than pay two disparity jumps; elsewhere
    they are clean copies."""
    a, b, e = ((random_map(41 + 2 * k), random_map(42 + 2 * k)) for k in range(3))
    out = []
    for y in lines:
        line = Line()
        e_left = (damaged(e[0], 77, 7), damaged(e[1], 77, 8)) if y in hurt else e
        line.add(0, 30, 4, 11, *a)
        line.add(0, 50, 9, 5, *e_left)
        line.add(0, 70, 6, 14, *b)
        line.add(1, 22, 4, 11, *a)
        line.add(1, (right_e if y == 60 else 38), 9, 5, *e)
        line.add(1, 62, 6, 14, *b)
        out.append(line.data(y))
    return out


def plain_cost(data: LineData, edge: int) -> float:
    c = candidates(data.features1, data.features2, data.maps1, data.maps2)
    k = [n for n in range(len(c)) if c.left.edge[c.i[n]] == edge
         and c.right.edge[c.j[n]] == edge]
    return float(c.cost[k[0]])


FOUR = replace(Constraints(), confirm=False)   # the four: the default before 2026-12-01
READMIT = replace(FOUR, readmit=True)          # the four + readmit (named, off by default)


def test_readmit_is_named_and_off_by_default():
    """Re-admission puts wrong matches into the walk's looks (docs/matching.md),
    so it is off unless asked for: not in Constraints(), not in the streaming
    matcher make_matcher("improved") gives (rig walk's), in "all"."""
    assert not Constraints().readmit and READMIT.readmit
    assert Constraints.parse("all") == replace(READMIT, confirm=True)
    assert make_matcher("improved").constraints == Constraints()
    stack = jump_line()
    assert match_lines(stack, FOUR) == match_lines(stack, replace(READMIT, readmit=False))
    assert not {v.edge: v for v in match_lines(stack, FOUR)[60]}[2].matched
    assert match_lines(stack) == match_lines(stack, replace(READMIT, readmit=False,
                                                            confirm=True))


def test_readmit_takes_the_unused_partner_the_neighbours_agree_on():
    stack = jump_line()
    assert 96 < plain_cost(stack[3], 2) < 128
    before = {v.edge: v for v in match_lines(stack, FOUR)[60]}
    assert not before[2].matched and not before[52].matched
    after = {v.edge: v for v in match_lines(stack, READMIT)[60]}
    for e in (2, 52):
        assert after[e].matched and after[e].reason == "readmitted", after[e]
        assert after[e].partner == e and after[e].disparity == 12
        assert 0 < after[e].confidence <= 1
    for e in (1, 3, 51, 53):                                  # the rest as before
        assert after[e] == before[e] and after[e].disparity == 8


def test_readmit_wants_the_neighbours_disparity():
    """The same line with E's partner on line 60 two pixels off the
    neighbours' disparity (14, not 12): no neighbour agrees, no re-admission."""
    stack = jump_line(right_e=36)
    after = {v.edge: v for v in match_lines(stack, READMIT)[60]}
    assert not after[2].matched and not after[52].matched


def test_rematch_assigns_the_line_again_with_the_neighbours_in_its_costs():
    """rematch_bonus (off by default): line 60 assigned again with 64 off E's
    cost for each of lines 58..62 whose verdicts have E at its disparity; the
    assignment itself then takes E (no re-admission needed)."""
    stack = jump_line()
    cons = FOUR
    assert not {v.edge: v for v in match_lines(stack, cons)[60]}[2].matched
    again = {v.edge: v for v in match_lines(stack, cons, Params(rematch_bonus=64))[60]}
    for e in (2, 52):
        assert again[e].matched and again[e].reason == "matched" and again[e].disparity == 12
    assert again[2].cost == plain_cost(stack[3], 2)
    off = replace(cons, neighbours=False)                     # needs the neighbour constraint
    assert match_lines(stack, off, Params(rematch_bonus=64)) == match_lines(stack, off)


def test_a_second_readmit_pass_grows_the_vertical_line():
    """E damaged on lines 58..62: the first pass re-admits it on 58, 59, 61
    and 62 (clean lines 56, 57, 63, 64 within reach), line 60 only sees
    damaged lines until the second pass, which sees their re-admissions."""
    stack = jump_line(hurt=range(58, 63), lines=range(55, 66))
    one = {v.edge: v for v in match_lines(stack, READMIT, Params(readmit_rounds=1))[60]}
    assert not one[2].matched
    for y in (59, 61):
        assert {v.edge: v for v in match_lines(stack, READMIT,
                                               Params(readmit_rounds=1))[y]}[2].matched
    two = {v.edge: v for v in match_lines(stack, READMIT)[60]}
    assert two[2].matched and two[2].reason == "readmitted" and two[2].disparity == 12


def test_readmit_keeps_the_order_and_uses_no_partner_twice():
    """Every line of the bundled-like stack: re-admitted matches keep the
    left-to-right order of the line's matches and take unused partners."""
    for y, vs in match_lines(jump_line(), READMIT).items():
        m = sorted((v.x, v.partner) for v in vs if v.matched)
        partners = [pt for _, pt in m]
        assert len(set(partners)) == len(partners)
        locs = sorted((v.loc1, v.loc2) for v in vs if v.matched)
        assert [b for _, b in locs] == sorted(b for _, b in locs), y


CONFIRM = Constraints()       # the default five: the four + confirm (since 2026-12-01)


def test_confirm_is_in_the_default_five():
    """The lead's decision of 2026-12-01: confirm (the neighbours constraint's
    other half) is a default constraint; the four without it are still one
    --constraints list away, and "all" still has it."""
    assert Constraints().confirm and Constraints.parse("all").confirm
    assert Constraints().names() == ["order", "lr", "neighbours", "region", "confirm"]
    assert Constraints.parse("order,lr,neighbours,region,confirm") == Constraints()
    assert Constraints.parse(DEFAULT_CONSTRAINTS) == Constraints()
    assert make_matcher("improved").constraints == Constraints()
    four = Constraints.parse("order,lr,neighbours,region")
    assert four == FOUR and not four.confirm and four.names() == ["order", "lr",
                                                                  "neighbours", "region"]
    assert make_matcher("improved", "order,lr,neighbours,region").constraints == FOUR
    stack = jump_line()                      # the four leave E out, the default keeps it
    assert not {v.edge: v for v in match_lines(stack, FOUR)[60]}[2].matched
    assert {v.edge: v for v in match_lines(stack)[60]}[2].reason == "confirmed"


def test_confirm_keeps_the_match_the_assignment_left_out():
    """jump_line: E's maps are damaged on line 60 (cost near 110), so the
    assignment there leaves it out ("occluded") rather than pay two
    disparity jumps, though its one candidate is its true partner.  Lines
    57..59 and 61..63 match E at that disparity (12): confirm keeps it."""
    stack = jump_line()
    before = {v.edge: v for v in match_lines(stack, FOUR)[60]}
    assert not before[2].matched and before[2].reason == "occluded"
    after = {v.edge: v for v in match_lines(stack, CONFIRM)[60]}
    for e in (2, 52):
        assert after[e].matched and after[e].reason == "confirmed", after[e]
        assert after[e].partner == e and after[e].disparity == 12
        assert after[e].cost == plain_cost(stack[3], e)
        assert 0 < after[e].confidence <= 1
    for e in (1, 3, 51, 53):                                  # the rest as before
        assert after[e] == before[e] and after[e].disparity == 8


def test_confirm_keeps_the_match_the_neighbour_rule_dropped():
    """E damaged on lines 59 and 61 only: line 60's assignment takes E at its
    true disparity, but the neighbour rule, which asks the noisy first pass
    of lines 59 and 61 (where E was left out), drops it as "not on a
    vertical line".  Lines 57, 58, 62 and 63 match E at 12: kept."""
    stack = jump_line(hurt=(59, 61))
    before = {v.edge: v for v in match_lines(stack, FOUR)[60]}
    assert not before[2].matched and before[2].reason == "not on a vertical line"
    assert before[2].partner == 2 and before[2].disparity == 12
    after = {v.edge: v for v in match_lines(stack, CONFIRM)[60]}
    assert after[2].matched and after[2].reason == "confirmed"
    assert after[2].partner == 2 and after[2].disparity == 12


def test_confirm_wants_three_lines_at_the_edges_own_disparity():
    """E's partner on line 60 two pixels off (disparity 14): no line agrees,
    not confirmed.  With E damaged on lines 59..63, only lines 57 and 58
    match it (at 12): two lines are not enough for one pass."""
    after = {v.edge: v for v in match_lines(jump_line(right_e=36), CONFIRM)[60]}
    assert not after[2].matched and after[2].reason == "occluded"
    few = jump_line(hurt=range(59, 64), lines=range(57, 64))
    v = {x.edge: x for x in match_lines(few, CONFIRM, Params(confirm_rounds=1))[60]}
    assert not v[2].matched
    v = {x.edge: x for x in match_lines(few, CONFIRM, Params(confirm_rounds=1,
                                                               confirm_support=2))[60]}
    assert v[2].matched and v[2].reason == "confirmed"


def test_confirm_still_refuses_the_fence_and_the_occluded_feature():
    """A vertical picket fence (15 lines): the first picket, which only the
    left camera sees, stays "no match" (its cheapest candidate is the second
    picket's partner, already taken), every other picket keeps its true
    partner.  The occluded feature of occluded_line on 15 lines: still no
    match (its look-alike's partner belongs to the look-alike)."""
    data, truth = picket_fence()
    lines = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in range(53, 68)]
    m = matched(match_lines(lines, CONFIRM)[60])
    assert {e: x.disparity for e, x in m.items()} == {
        e: D_TRUE for k, p in truth.items() if p is not None for e in (k, k + 50)}
    data = occluded_line()
    lines = [LineData(y, data.features1, data.features2, data.maps1, data.maps2)
             for y in range(53, 68)]
    for y, vs in match_lines(lines, CONFIRM).items():
        v = {x.edge: x for x in vs}
        assert not v[3].matched and not v[53].matched, (y, v[3])


def test_region_constraint_wants_both_ends():
    """A feature whose right end has no admissible partner (grey 14 vs 7)
    loses its left end's match too under 'region'."""
    line = Line()
    m = (random_map(31), random_map(32))
    line.add(0, 30, 4, 14, *m)
    line.add(1, 22, 4, 7, *m)
    data = line.data()
    assert matched(match_line(data, Constraints.none())).keys() == {1}
    strict = Params(region_penalty=None)
    v = {x.edge: x for x in match_line(data, Constraints.only("region"), strict)}
    assert not v[1].matched and v[1].reason == "no region partner"
    # the default only charges the lone end one occlusion's worth more
    v = {x.edge: x for x in match_line(data, Constraints.only("region"))}
    assert v[1].matched and v[1].cost == Params().region_penalty


# --- the pieces against independent computations ----------------------------------

def test_shape_cost_is_marfs_search():
    for seed in range(40):
        r = np.random.default_rng(seed)
        m1 = [1] + [int(x) for x in r.integers(0, 1 << 16, 16)]
        m2 = [1] + [int(x) & int(y) for x, y in zip(m1[1:], r.integers(0, 1 << 16, 16))]
        bound = int(r.integers(0, 9))
        mloc, mnval, _ = marf_shift(m1, m2, bound)
        assert shape_cost(m1, m2, bound, cap_overflow=True) == (mloc, mnval)


def test_shape_cost_of_hand_counted_maps():
    m = [1] + [0b1111] * 16                           # 64 bits
    half = [1] + [0b0011] * 16                        # 32 bits, all inside m
    assert shape_cost(m, m, 3) == (0, 0)
    assert shape_cost(m, half, 0) == (0, 32 * 256 // 96)
    assert shape_cost([1] + [0] * 16, [1] + [0] * 16, 2) == (0, 256)


def test_edges_follow_the_line_with_masl_bounds():
    e = slice_edges([(10, 14, 3, 9), (20, 22, 9, 3)])
    assert e.x.tolist() == [10, 14, 20, 22]
    assert e.edge.tolist() == [1, 51, 2, 52]
    # left end of feature 1: min(start=10, half width 2) = 2; gap to feature 2 is 6 -> 3 > 2
    assert e.bound.tolist() == [2, 2, 1, 1]


def test_candidates_need_grey_side_maps_and_disparity():
    data = crossing_line()
    c = candidates(data.features1, data.features2, data.maps1, data.maps2)
    pairs = {(int(c.left.edge[i]), int(c.right.edge[j])) for i, j in zip(c.i, c.j)}
    assert pairs == {(1, 1), (2, 1), (2, 2), (51, 51), (52, 51), (52, 52)}


def test_width_penalty_charges_the_difference_in_widths():
    """The same grey step seen 2 px wide in one slice and 5 px in the other
    costs 3 x width_penalty more (Params default 4; 0 is MARF's shape alone)."""
    line = Line()
    m = (random_map(51), random_map(52))
    line.add(0, 30, 4, 11, *m, width=2)
    line.add(1, 22, 4, 11, *m, width=5)
    d = line.data()
    plain = candidates(d.features1, d.features2, d.maps1, d.maps2)
    charged = candidates(d.features1, d.features2, d.maps1, d.maps2, width_penalty=4.0)
    assert len(plain) == 2 and np.array_equal(charged.cost, plain.cost + 12.0)
    assert Params().width_penalty == 4.0


def test_dp_kernel_equals_its_plain_python():
    kernel = getattr(order_dp, "py_func", order_dp)
    for seed in range(10):
        r = np.random.default_rng(seed)
        k = 60
        ci = np.sort(r.integers(0, 20, k))
        cj = r.integers(0, 20, k)
        o = np.lexsort((cj, ci))
        ci, cj = ci[o], cj[o]
        ben = r.uniform(-100, 20, k)
        disp = r.uniform(2, 30, k)
        outs = []
        for fn in (order_dp, kernel):
            f, b, p = np.zeros(k), np.zeros(k), np.zeros(k, dtype=np.int64)
            outs.append((fn(ci, cj, ben, disp, 8.0, 4.0, f, b, p), f, b, p))
        assert outs[0][0] == outs[1][0]
        for x, y in zip(outs[0][1:], outs[1][1:]):
            assert np.allclose(x, y)


def test_dp_against_brute_force():
    """The best order-keeping 1-1 assignment of a small random grid, by trying
    every subset of candidates."""
    from itertools import combinations
    for seed in range(8):
        r = np.random.default_rng(100 + seed)
        ci = r.integers(0, 5, 9)
        cj = r.integers(0, 5, 9)
        cost = r.uniform(0, 200, 9)
        disp = r.uniform(2, 12, 9)
        chosen, _ = assign(ci, cj, cost, disp, 64.0, 8.0, 4.0)

        def total(sel):
            sel = sorted(sel, key=lambda k: (ci[k], cj[k]))
            t = sum(cost[k] - 128.0 for k in sel)
            t += sum(8.0 * min(abs(disp[a] - disp[b]), 4.0) for a, b in zip(sel, sel[1:]))
            return t

        def valid(sel):
            sel = sorted(sel, key=lambda k: (ci[k], cj[k]))
            return all(ci[a] < ci[b] and cj[a] < cj[b] for a, b in zip(sel, sel[1:]))
        best = min((total(s) for n in range(10) for s in combinations(range(9), n) if valid(s)))
        assert valid(chosen) and total(chosen) == pytest.approx(best)


def test_step_position_finds_the_crossing():
    profile = np.full(256, 3.0)
    profile[61:] = 11.0
    profile[60] = 7.0                 # the step's middle at .VD 60.5 (pixel centre)
    # 128-px index units: 60.5 / 2 + 0.5
    assert step_position(profile, 29, 32, 3, 11) == pytest.approx(60.5 / 2 + 0.5)
    profile[60] = 5.0                 # a quarter of the way: the crossing moves right
    assert step_position(profile, 29, 32, 3, 11) == pytest.approx((60.5 + 2 / 6) / 2 + 0.5)
    assert step_position(profile, 29, 32, 3, 3) is None


def test_locate_float_is_lcsl_in_floating_point():
    for loc1, loc2, iy in ((40, 30, 60), (100, 91, 20), (12, 4, 110)):
        exact = [float(v) for v in locate(loc1, loc2, iy, Real.const("0.75"), Real.const("180"))]
        assert np.allclose(locate_float(loc1, loc2, iy, 0.75, 180.0), exact, rtol=1e-5)
    assert locate_float(30.5, 29.6, 60, 0.75, 180.0) is None


def test_verdict_tables_feed_lcsl():
    data = crossing_line()
    v = match_line(data, Constraints.only("order"))
    pos = [Real.from_int(7)] * 640
    lcsl(60, 2, VerdictTables(v), pos, Real.const("0.75"), Real.const("180"))
    assert float(pos[(2 - 1) * 6]) == pytest.approx(0.75 * 180 / 8, rel=1e-5)


def test_modes_and_flags():
    assert make_matcher("1985") is None
    assert make_matcher("improved", "order,lr").constraints == Constraints.only("order", "lr")
    with pytest.raises(ValueError):
        make_matcher("1986")
    with pytest.raises(ValueError):
        Constraints.parse("order,magic")

    class A:
        match = "improved"
        constraints = "all"
    assert constraints_from_args(A(), subpixel=True).subpixel
    assert not constraints_from_args(A(), subpixel=False).subpixel
    A.constraints = "subpixel"
    with pytest.raises(ValueError, match="VD"):
        constraints_from_args(A(), subpixel=False)
    A.constraints = None
    assert constraints_from_args(A()) == Constraints()
    A.match, A.constraints = "1985", "order"
    with pytest.raises(ValueError, match="--match improved"):
        constraints_from_args(A())


def side_face_line() -> LineData:
    """A box's right outline: the left picture's step from the box's grey 2 to
    the wall's 13 is two pixels wide (40..42); the right camera also sees the
    box's right side face, so its interval runs from the front edge to the
    side face's back corner, five pixels (30..35).  Both ends look alike in
    both pictures.  The left ends (front edge in both) give the box's
    disparity 10; the right ends (front edge against back corner) give 7.
    A feature elsewhere (60..62 against 50..52) agrees at both ends."""
    line = Line()
    line.add(0, 40, 2, 13, random_map(1), random_map(2))
    line.add(1, 30, 2, 13, random_map(1), random_map(2), width=5)
    line.add(0, 60, 13, 6, random_map(3), random_map(4))
    line.add(1, 50, 13, 6, random_map(3), random_map(4))
    return line.data()


def test_drop_farther_end_keeps_the_front_edge_of_a_side_face():
    data = side_face_line()
    stack = [replace(data, iyloc=y) for y in (59, 60, 61)]
    before = matched(match_lines(stack, Constraints())[60])
    assert before[1].disparity == 10 and before[51].disparity == 7     # 7 is wrong
    assert before[2].disparity == before[52].disparity == 10
    p = Params(drop_farther_end=True)
    after = {v.edge: v for v in match_lines(stack, Constraints(), p)[60]}
    assert after[1].matched and after[1].disparity == 10
    assert not after[51].matched and after[51].reason == "ends disagree"
    assert after[2].matched and after[52].matched                      # agreeing ends stay
    # within the region tolerance the ends agree: nothing is dropped
    loose = {v.edge: v for v in match_lines(stack, Constraints(),
                                            replace(p, region_tolerance=3.0))[60]}
    assert loose[51].matched and loose[51].disparity == 7
    assert Params().drop_farther_end is False                          # named, off


def test_subpixel_keeps_the_integer_disparity_when_the_crossings_name_different_steps():
    """The side face of side_face_line() in grey profiles: the left picture's
    step 2 -> 13 crosses halfway at .VD 131.5 (128-px 66.25); the right one has
    the front edge 2 -> 4 at .VD 81 and the side face's back corner 4 -> 13 at
    .VD 88.9, where its only halfway crossing is.  The refined disparity of the
    front edge's match (integer 66 - 41 = 25) would be 66.25 - 44.9 = 21.3, the
    back corner's: more than a pixel off, so the integer locations stay
    (Params.subpixel_max_change = 1, the default; None refines anyway).  A
    feature whose ramps agree is refined."""
    from matching import Verdict
    from matching.subpixel import refine_verdicts
    def profile(*runs):                # (first .VD column, grey) ... in order
        out = np.empty(256)
        for (a, g), (b, _) in zip(runs, runs[1:] + ((256, 0),)):
            out[a:b] = g
        return out
    left = profile((0, 6.0), (40, 13.0), (100, 2.0), (131, 7.5), (132, 13.0))
    right = profile((0, 6.0), (20, 13.0), (60, 2.0), (81, 4.0), (89, 13.0))
    data = LineData(60, [(20, 22, 6, 13), (66, 68, 2, 13)], [(10, 12, 6, 13), (41, 46, 2, 13)],
                    np.zeros((100, 17), dtype=np.int64), np.zeros((100, 17), dtype=np.int64))
    front = Verdict(60, 2, 66, True, "matched", 2, 66.0, 41.0, 10.0, 0.9)
    plain = Verdict(60, 1, 20, True, "matched", 1, 20.0, 10.0, 10.0, 0.9)
    s1 = step_position(left, 66, 68, 2, 13)
    s2 = step_position(right, 41, 46, 2, 13)
    assert s1 == pytest.approx(66.25) and s2 - 0.5 == pytest.approx((88.5 + 3.5 / 9) / 2)
    kept, refined = refine_verdicts([front, plain], data, (left, right), Params().subpixel_max_change)
    assert Params().subpixel_max_change == 1.0
    assert (kept.loc1_sub, kept.loc2_sub) == (66.0, 41.0)
    assert refined.disparity_sub == pytest.approx(step_position(left, 20, 22, 6, 13)
                                                  - step_position(right, 10, 12, 6, 13))
    assert abs(refined.disparity_sub - 10) <= 1 and refined.loc1_sub != 20.0
    anyway = refine_verdicts([front], data, (left, right), None)[0]
    assert anyway.disparity_sub == pytest.approx(s1 - s2) and anyway.disparity_sub < 22


def test_subpixel_points_of_a_rendered_look_lie_nearer_the_truth():
    """``subpixel_points`` (``rig drive --disparity subpixel``) on a rendered look of
    generated room 3 from its start, four ways: the same edges as LCSL's points (less
    any whose refined disparity falls to 1 px or under), each disparity at most a pixel
    from its integer one, those without a crossing unchanged; against the world's true range
    at the edge's pixel, the median error at most half LCSL's whole-pixel one.  Without
    the improved matcher's verdicts it is refused."""
    from matching.subpixel import subpixel_points
    from planner.loop import camera_pose, scan_look
    from vehicle.profile import DEFAULT
    from world.render import render_look
    from rigtools import bench_task
    room, start, _goal = bench_task(3)
    errors = {"pixel": [], "subpixel": []}
    moved = 0
    for heading in (0.0, 90.0, 180.0, 270.0):
        look = render_look(room, camera_pose(type(start)(start.x, start.z, heading), 0.0, 0.0,
                                             DEFAULT), seed=3)
        scan = scan_look(look.left_bi, look.right_bi, range(8, 113, 2), "improved")
        pixel = {(p.line, p.edge): p for p in scan.points}
        sub = subpixel_points(scan.results, look.left_vd, look.right_vd)
        assert {(p.line, p.edge) for p in sub} <= set(pixel)
        for p in sub:
            q = pixel[(p.line, p.edge)]
            assert abs((p.loc1 - p.loc2) - (q.loc1 - q.loc2)) <= 1.0   # Params.subpixel_max_change
            assert abs(p.loc1 - q.loc1) <= 2
            if (p.loc1, p.loc2) == (q.loc1, q.loc2):
                assert p.dp == pytest.approx(q.dp, rel=1e-5)
            else:
                moved += 1
        for name, points in (("pixel", list(pixel.values())), ("subpixel", sub)):
            for p in points:
                c = int(round(p.loc1)) - 1
                truth = float(look.range_left[p.line, max(c - 1, 0):c + 2].min())
                if 3.0 <= truth <= 12.0:
                    errors[name].append(abs(p.dp - truth))
    assert moved > 100 and min(len(e) for e in errors.values()) > 200
    assert np.median(errors["subpixel"]) <= 0.5 * np.median(errors["pixel"])
    with pytest.raises(ValueError, match="improved matcher"):
        subpixel_points(scan_look(look.left_bi, look.right_bi, [60], "1985").results,
                        look.left_vd, look.right_vd)
