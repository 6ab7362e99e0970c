"""A verdict for every located edge: matched, with a confidence, or "no match".

Chapter V ("Matches") finds the 1985 matches "in two categories, those which
were the correct features, and those which had no correct match and so were
left with the best match available", and asks for "a method for
automatically determining whether each is a good match, and which matches are
the result of a feature which has no match".  :func:`match_line` gives each
edge of the left slice (MASL's edges 1..NFEAT1 and 51..50+NFEAT1) such a
verdict, under constraints that are each switched on their own
(:class:`Constraints`):

``order``
    uniqueness and the 1-1 order-keeping assignment along the line by dynamic
    programming (Chapter V's picket fence; Ohta and Kanade 1985), see
    :mod:`matching.order`.  Off: each edge takes its cheapest partner, as
    LCSL takes the first of MASL's list.
``lr``
    left-right consistency: the right slice's edge, searched against every
    left edge, finds the same partner (within ``lr_tolerance`` of its best).
``neighbours``
    agreement with the neighbouring scan lines: an edge lies on a vertical
    line in the picture, so line IY-1 or IY+1 has an edge of the same side
    within a pixel whose match has nearly the same disparity.
``region``
    region first, then its edges (Chapter III: "Once a region match is made
    then the coinciding edges can be matched"): an edge pair counts only if
    the other ends of the two feature intervals also pass the grey rule and
    give nearly the same disparity (both ends matched together).
``confirm``
    a second look at the edges the other rules dropped (:func:`confirm`):
    an edge left with "no match" (occluded, not on a vertical line,
    ambiguous) takes its own choice (the partner the assignment had chosen,
    or its cheapest candidate when that partner is unused and keeps the
    order of the line's matches) when at least three lines of IY-7..IY+7, in
    their final verdicts, match an edge of the same side within 2 px at a
    disparity within 1 px; three passes.  Unlike ``readmit`` it never switches
    an edge to a dearer partner because the neighbours like it better: the
    neighbours only vouch for the edge's own evidence.  On by default since
    2026-12-01 (before, the default was the four above): it is the neighbours
    constraint's other half, the neighbouring lines vouching for an edge's own
    choice; with it the motorcycle meets its target (docs/matching.md), the
    walk's pose is better and its correspondences a little worse.
``readmit``
    a second pass once every line has its verdicts (:func:`readmit`): an edge
    left with "no match" takes a partner its line left unused, keeping the
    order of the line's matches, where a neighbouring line (IY-2..IY+2)
    agrees on the disparity; two passes, so a vertical line grows past a
    damaged stretch.  Only in :func:`match_lines` (and the streaming
    :class:`matching.mode.ImprovedMatcher`), which see the other lines.
    Off by default (``"all"`` includes it): on the rendered looks of the
    bundled walk 41 % of its re-admissions are more than 2 px wrong (the
    neighbours it trusts are wrong there too: repeated textures), and they
    extend vertical lines, whose ends are the walk's corners (docs/matching.md).
``subpixel``
    edge positions from the grey profile of the .VD picture (twice the .BI's
    resolution), see :mod:`matching.subpixel`; changes locations, not verdicts.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from diskfmt.jit import jit
from .candidates import Candidates, candidates
from .order import assign

CONSTRAINTS = ("order", "lr", "neighbours", "region", "confirm", "readmit", "subpixel")


@dataclass(frozen=True)
class Constraints:
    """Which constraints the improved matcher applies (see the module docstring)."""
    order: bool = True
    lr: bool = True
    neighbours: bool = True
    region: bool = True
    confirm: bool = True           # on since 2026-12-01: the neighbours' other half
    readmit: bool = False          # named, off: it hurts the walk (module docstring)
    subpixel: bool = False

    @classmethod
    def none(cls) -> "Constraints":
        return cls(**{n: False for n in CONSTRAINTS})

    @classmethod
    def only(cls, *names: str) -> "Constraints":
        """Just the named constraints (names of :data:`CONSTRAINTS`)."""
        bad = [n for n in names if n not in CONSTRAINTS]
        if bad:
            raise ValueError(f"unknown constraint {', '.join(bad)}; "
                             f"known: {', '.join(CONSTRAINTS)}")
        return cls(**{n: n in names for n in CONSTRAINTS})

    @classmethod
    def parse(cls, text: str) -> "Constraints":
        """``"all"`` (every constraint but subpixel), ``"none"`` or a comma
        list such as ``"order,lr"``."""
        text = text.strip().lower()
        if text == "all":
            return cls(readmit=True, confirm=True)
        if text in ("none", ""):
            return cls.none()
        return cls.only(*(t.strip() for t in text.split(",") if t.strip()))

    def names(self) -> list[str]:
        return [f.name for f in fields(self) if getattr(self, f.name)]


@dataclass(frozen=True)
class Params:
    """The matcher's weights, in MARF's mismatch units (0 = identical maps,
    256 = nothing in common)."""
    occlusion: float = 64.0        # cost of an edge left unmatched (a match must cost < 2x)
    smooth: float = 8.0            # per pixel of disparity change between consecutive matches
    jump_cap: float = 4.0          # ... counted up to this many pixels (depth steps are allowed)
    grey_penalty: float = 16.0     # added per grey level of difference (0 or 1)
    width_penalty: float = 4.0     # added per pixel of difference in the features' widths
    lr_tolerance: float = 64.0     # a match within this of the right edge's best partner
    region_tolerance: float = 2.0  # px: the two ends of a feature pair agree this well
    region_penalty: float | None = 64.0   # None: an edge pair without its region is dropped;
    #                                       a number: it is only charged this much more
    neighbour_dx: int = 2          # px: the same vertical line on the next scan line
    neighbour_dd: float = 2.0      # px: ... with nearly the same disparity
    neighbour_reach: int = 1       # lines IY-reach..IY+reach (not IY) may give support
    neighbour_bonus: float = 0.0   # taken off a candidate's cost per supporting line, before
    #                                the assignment (inter-scanline evidence in the costs)
    unsupported_factor: float | None = None   # None: an edge on no vertical line is "no
    #                                           match"; a number: its confidence is scaled
    min_confidence: float = 0.1    # matches below are "no match (ambiguous)"
    readmit_support: int = 1       # readmit: lines of IY-reach..IY+reach that must agree
    readmit_reach: int = 2
    readmit_dd: float = 1.0        # px: ... with a disparity this close
    readmit_cost: float = 128.0    # ... and a candidate no dearer than this
    readmit_rounds: int = 2        # passes, each seeing the re-admissions of the one before
    confirm_reach: int = 7         # confirm: lines IY-reach..IY+reach (not IY) vouch
    confirm_support: int = 3       # ... at least this many of them
    confirm_dd: float = 1.0        # px: ... with a match at a disparity this close
    confirm_rounds: int = 3        # passes, each seeing the confirmations of the one before
    drop_farther_end: bool = False   # a feature matched at both ends to one right feature
    #                                  at disparities more than region_tolerance apart: the end
    #                                  with the smaller disparity is "no match (ends disagree)"
    #                                  (a face only one camera sees inside the ramp; off)
    rematch_bonus: float = 0.0     # > 0: before re-admission, assign every line again with
    #                                this much off a candidate's cost per neighbouring line
    #                                whose verdicts agree (inter-scanline support; off)
    subpixel_max_change: float | None = 1.0    # subpixel: a refined disparity further than
    #                                            this (px) from the integer one keeps the
    #                                            integer locations (None: no limit)
    use_shift: bool = True         # loc2 = x2 - MARF's best shift (the geometric sign)


@dataclass(frozen=True)
class LineData:
    """What ESTAR has for one line: the two feature lists (``Slice.features()``
    rows ``(start, stop, lgrey, rgrey)``) and the edge bit maps IBLB1/IBLB2
    (100 x 17 words, flag word first)."""
    iyloc: int
    features1: list
    features2: list
    maps1: np.ndarray
    maps2: np.ndarray

    @classmethod
    def of(cls, result) -> "LineData":
        """From an ``estar.program.LineResult`` (which keeps its maps)."""
        return cls(result.iyloc, list(result.features1), list(result.features2),
                   np.asarray(result.maps1), np.asarray(result.maps2))


@dataclass(frozen=True)
class Verdict:
    """One edge of the left slice.  ``matched`` False means "no match" and
    ``reason`` says why: "no candidate" (nothing passes the grey rule with a
    disparity above 1), "not mutual" (lr), "no region partner" (region),
    "occluded" (the order-keeping assignment leaves it out), "not on a
    vertical line" (neighbours), "ambiguous" (confidence below the minimum),
    "ends disagree" (``Params.drop_farther_end``, off by default).
    A match the re-admission pass made has ``reason`` "readmitted"; one
    dropped afterwards keeps the partner and locations it had."""
    iyloc: int
    edge: int                  # MASL's number, 1..50 left end, 51..100 right end
    x: int                     # its 1-based slice index
    matched: bool
    reason: str
    partner: int = 0           # right-slice edge number
    loc1: float = 0.0
    loc2: float = 0.0
    cost: float = float("nan")
    confidence: float = 0.0
    loc1_sub: float | None = None   # sub-pixel locations (subpixel constraint)
    loc2_sub: float | None = None

    @property
    def disparity(self) -> float:
        return self.loc1 - self.loc2

    @property
    def disparity_sub(self) -> float:
        if self.loc1_sub is None:
            return self.disparity
        return self.loc1_sub - self.loc2_sub


def _mutual(c: Candidates, tol: float) -> np.ndarray:
    """Candidates within ``tol`` of the best cost of their left edge AND of their
    right edge (the same match found from either slice)."""
    keep = np.zeros(len(c), dtype=bool)
    if len(c) == 0:
        return keep
    _mutual_kernel(c.i, c.j, c.cost, len(c.left), len(c.right), float(tol), keep)
    return keep


@jit
def _mutual_kernel(ci, cj, cost, n_left, n_right, tol, keep):
    """:func:`_mutual` on the arrays (each edge's best cost, then the test)."""
    row_best = np.full(n_left, np.inf)
    col_best = np.full(n_right, np.inf)
    for k in range(len(ci)):
        row_best[ci[k]] = min(row_best[ci[k]], cost[k])
        col_best[cj[k]] = min(col_best[cj[k]], cost[k])
    for k in range(len(ci)):
        keep[k] = cost[k] <= row_best[ci[k]] + tol and cost[k] <= col_best[cj[k]] + tol


def _region_supported(c: Candidates, tol: float) -> np.ndarray:
    """Candidates whose features' other ends are also a candidate pair with a
    disparity within ``tol``."""
    keep = np.zeros(len(c), dtype=bool)
    if len(c) == 0:
        return keep
    _region_kernel(c.left.feature[c.i], c.right.feature[c.j], c.left.side[c.i], c.disp,
                   float(tol), keep)
    return keep


@jit
def _region_kernel(f1, f2, side, disp, tol, keep):
    """:func:`_region_supported` on the arrays: pair k is kept when a pair of
    the same two features' other ends lies within ``tol`` of its disparity
    (a line has a few dozen pairs: every two compared)."""
    for k in range(len(f1)):
        for m in range(len(f1)):
            if (f1[m] == f1[k] and f2[m] == f2[k] and side[m] != side[k]
                    and abs(disp[k] - disp[m]) <= tol):
                keep[k] = True
                break


def _support(c: Candidates, neighbours, p: Params) -> np.ndarray:
    """For every candidate, the number of neighbouring lines with a matched
    edge of the same side within ``neighbour_dx`` px whose disparity is within
    ``neighbour_dd`` of the candidate's."""
    out = np.zeros(len(c), dtype=np.int64)
    if len(c) == 0:
        return out
    side = c.left.side[c.i]
    x = c.left.x[c.i]
    d = c.disp
    for line in neighbours:
        m = [(int(v.edge > 50), v.x, v.disparity) for v in line if v.matched]
        if not m:
            continue
        ns, nx, nd = (np.asarray(a) for a in zip(*m))
        hit = ((side[:, None] == ns[None, :])
               & (np.abs(x[:, None] - nx[None, :]) <= p.neighbour_dx)
               & (np.abs(d[:, None] - nd[None, :]) <= p.neighbour_dd))
        out += hit.any(axis=1)
    return out


def _choose(c: Candidates, constraints: Constraints, p: Params):
    """Chosen candidate indices and each candidate's min-marginal cost."""
    if constraints.order:
        return assign(c.i, c.j, c.cost, c.disp, p.occlusion, p.smooth, p.jump_cap)
    marginal = c.cost - 2.0 * p.occlusion
    chosen = []
    for i in np.unique(c.i):
        ks = np.flatnonzero(c.i == i)
        k = ks[np.lexsort((c.j[ks], c.cost[ks]))[0]]        # cheapest, then leftmost
        if marginal[k] < 0:
            chosen.append(k)
    return np.array(chosen, dtype=np.int64), marginal


def _confidences(c: Candidates, chosen: np.ndarray, marginal: np.ndarray,
                 p: Params) -> list[float]:
    """For each chosen match k: its margin over its best rival (another
    partner of either of its edges), and over leaving it out, in units of
    2 x occlusion."""
    out = np.zeros(len(chosen))
    if len(chosen):
        _confidences_kernel(c.i, c.j, c.cost, chosen, marginal, 2.0 * p.occlusion, out)
    return out.tolist()


@jit
def _confidences_kernel(ci, cj, cost, chosen, marginal, two_occlusion, out):
    """:func:`_confidences` on the arrays; ``min`` and ``max`` as Python's
    (the first argument unless the second is strictly beyond it)."""
    for n in range(len(chosen)):
        k = chosen[n]
        rival = np.inf
        has_rival = False
        for m in range(len(ci)):
            if m != k and (ci[m] == ci[k] or cj[m] == cj[k]):
                has_rival = True
                if marginal[m] < rival:
                    rival = marginal[m]
        gap = two_occlusion - cost[k]
        if has_rival and rival - marginal[k] < gap:
            gap = rival - marginal[k]
        share = gap / two_occlusion
        share = share if share > 0.0 else 0.0
        out[n] = share if share < 1.0 else 1.0


def match_line(data: LineData, constraints: Constraints = Constraints(),
               params: Params = Params(), neighbours=None, profiles=None,
               cands: Candidates | None = None) -> list[Verdict]:
    """Verdicts for every edge of the left slice of one line.

    ``neighbours``: verdicts of lines IY-1 and IY+1 (and further, up to
    ``neighbour_reach``) made without the neighbour constraint (a list of lists; missing lines simply give no
    support), needed when ``constraints.neighbours``.  ``profiles``: the
    (left, right) .VD grey profiles of this line (:mod:`matching.subpixel`),
    needed when ``constraints.subpixel``.  ``cands``: the line's
    :func:`line_candidates` under ``params``, when already at hand."""
    c = line_candidates(data, params) if cands is None else cands
    assigned = line_assignment(data, c, constraints, params, neighbours)
    return assignment_verdicts(data, assigned, constraints, params, neighbours, profiles)


@dataclass(frozen=True)
class Assignment:
    """A line's matches as the assignment chose them, before the rules that
    judge each match on its own (neighbours, ambiguity, subpixel).

    Why a stage of its own: the streaming matcher's two passes over a line
    (without, then with the neighbour constraint) differ only after it, so
    it makes the assignment once (:func:`shares_assignment`), and the
    verdicts of the edges it left out are made once for both."""
    judged: Candidates             # the candidates as weighed (:func:`judged_candidates`)
    chosen: dict                   # left-edge position -> its matched Verdict
    no_match: dict                 # every other left-edge position -> its "no match" Verdict
    by_edge: list                  # the left-edge positions in the order of their edge numbers


def shares_assignment(constraints: Constraints, params: Params) -> bool:
    """Whether a line's assignment is the same with and without the neighbour
    constraint: it is unless the neighbours' support is in the costs
    (``neighbour_bonus``)."""
    return not (constraints.neighbours and params.neighbour_bonus)


def line_assignment(data: LineData, c: Candidates, constraints: Constraints, p: Params,
                    neighbours=None) -> Assignment:
    """The first stage of :func:`match_line` on the line's candidates ``c``:
    lr, region, the assignment, each match's confidence, and
    ``drop_farther_end``.  ``neighbours`` only for ``neighbour_bonus``."""
    reason = {i: "no candidate" for i in range(len(c.left))}
    if len(c) == 0:                   # most lines of a look: nothing for the rules to weigh
        return _assignment(data, c, {}, reason)
    has = set(c.i.tolist())
    for i in has:
        reason[i] = "occluded"
    if constraints.lr:
        c = c.subset(_mutual(c, p.lr_tolerance))
        for i in has - set(c.i.tolist()):
            reason[i] = "not mutual"
        has = set(c.i.tolist())
    if constraints.region:
        c = _region_weighted(c, p)
        for i in has - set(c.i.tolist()):
            reason[i] = "no region partner"
    judged = c
    evidence = c.cost                       # what a verdict reports as its cost
    if constraints.neighbours and p.neighbour_bonus:
        c = c.with_cost(c.cost - p.neighbour_bonus * _support(c, neighbours or (), p))
    chosen, marginal = _choose(c, constraints, p)
    out: dict[int, Verdict] = {}
    left = c.left
    for k, conf in zip(chosen.tolist(), _confidences(c, chosen, marginal, p)):
        i = int(c.i[k])
        out[i] = Verdict(data.iyloc, int(left.edge[i]), int(left.x[i]), True, "matched",
                         int(c.right.edge[c.j[k]]), float(c.loc1[k]), float(c.loc2[k]),
                         float(evidence[k]), conf)
    if p.drop_farther_end:
        out = dict(zip(out, farther_ends_dropped(list(out.values()), p.region_tolerance)))
    return _assignment(data, judged, out, reason)


def _assignment(data: LineData, judged: Candidates, chosen: dict, reason: dict) -> Assignment:
    left = judged.left
    no_match = {i: Verdict(data.iyloc, int(left.edge[i]), int(left.x[i]), False, reason[i])
                for i in range(len(left)) if i not in chosen}
    return Assignment(judged, chosen, no_match, sorted(range(len(left)),
                                                       key=lambda i: int(left.edge[i])))


def assignment_verdicts(data: LineData, a: Assignment, constraints: Constraints, p: Params,
                        neighbours=None, profiles=None) -> list[Verdict]:
    """The second stage of :func:`match_line`: the neighbour and ambiguity
    rules (and subpixel) on the assignment's matches, a "no match" for every
    other edge; sorted by edge number."""
    out = a.chosen
    if constraints.neighbours:
        lines = [edge_columns(line) for line in neighbours or ()]
        out = {i: _neighbour_check(v, lines, p) for i, v in out.items()}
    out = {i: (replace(v, matched=False, reason="ambiguous")
               if v.matched and v.confidence < p.min_confidence else v)
           for i, v in out.items()}
    if constraints.subpixel and profiles is not None:
        from .subpixel import refine_verdicts
        out = dict(zip(out, refine_verdicts(list(out.values()), data, profiles,
                                            p.subpixel_max_change)))
    return [out.get(i) or a.no_match[i] for i in a.by_edge]


def farther_ends_dropped(verdicts: list[Verdict], tolerance: float) -> list[Verdict]:
    """``Params.drop_farther_end``: where both ends of a left feature are
    matched to the two ends of one right feature and their disparities differ
    by more than ``tolerance``, the end with the smaller disparity becomes "no
    match (ends disagree)".

    Why (generated room 4, docs/matching.md): the two ends of a feature name
    one grey step, so they should agree.  They do not when one picture's ramp
    holds a face the other camera does not see, typically a box's side face
    next to its outline: the right camera sees a box's right side, so the
    right picture's interval is wider and its far end is the side face's
    back corner, not the front edge the left picture's step is.  That face
    lies behind the front one, so the end that names it has the smaller
    disparity; the other end names the same front edge in both pictures."""
    ends = {((v.edge - 1) % 50, (v.partner - 1) % 50, v.edge > 50): v
            for v in verdicts if v.matched}
    out = []
    for v in verdicts:
        if v.matched:
            other = ends.get(((v.edge - 1) % 50, (v.partner - 1) % 50, v.edge <= 50))
            if other is not None and other.disparity - v.disparity > tolerance:
                v = replace(v, matched=False, reason="ends disagree")
        out.append(v)
    return out


def edge_columns(verdicts: list[Verdict]) -> tuple[dict, dict]:
    """A line's matches as its neighbouring lines' rules look them up: for
    the left ends, then the right ends, the disparities of the matched
    edges at each column x."""
    at: tuple[dict, dict] = ({}, {})
    for v in verdicts:
        if v.matched:
            at[v.edge > 50].setdefault(v.x, []).append(v.disparity)
    return at


def column_support(lines, side: bool, x0: int, d: float, dx: int, dd: float) -> int:
    """How many of ``lines`` (each its :func:`edge_columns`) have a matched
    edge of the same side within ``dx`` px of column ``x0`` (integer
    columns: the columns x0-dx..x0+dx) at a disparity within ``dd`` of ``d``."""
    if dx < 0:
        return 0
    near = range(x0 - int(dx), x0 + int(dx) + 1)
    return sum(any(abs(nd - d) <= dd for x in near for nd in line[side].get(x, ()))
               for line in lines)


def _neighbour_check(v: Verdict, lines, p: Params) -> Verdict:
    """``lines``: per neighbouring line, its :func:`edge_columns`."""
    if not v.matched:
        return v
    support = column_support(lines, v.edge > 50, v.x, v.disparity, p.neighbour_dx,
                             p.neighbour_dd)
    if support == 0:
        if p.unsupported_factor is not None:
            return replace(v, confidence=v.confidence * p.unsupported_factor)
        return replace(v, matched=False, reason="not on a vertical line")
    factor = min(1.0, 0.75 + 0.125 * support)
    if factor == 1.0:                 # the confidence times 1 is itself: no new verdict
        return v
    return replace(v, confidence=v.confidence * factor)


def neighbour_lines(iyloc: int, params: Params, reach: int | None = None) -> list[int]:
    """The lines whose first-pass verdicts support line IY's: IY-1, IY+1,
    then IY-2, IY+2 ... up to ``neighbour_reach``."""
    reach = params.neighbour_reach if reach is None else reach
    return [iyloc + s * r for r in range(1, reach + 1) for s in (-1, 1)]


def line_candidates(data: LineData, p: Params) -> Candidates:
    """The candidate pairs of a line under ``p``'s cost terms."""
    return candidates(data.features1, data.features2, data.maps1, data.maps2,
                      use_shift=p.use_shift, grey_penalty=p.grey_penalty,
                      width_penalty=p.width_penalty)


def rematches(constraints: Constraints, params: Params) -> bool:
    """Whether :func:`match_lines` assigns every line again with the
    neighbours' verdicts in its costs (``Params.rematch_bonus``, with the
    neighbour constraint)."""
    return constraints.neighbours and params.rematch_bonus > 0


def rematch_params(params: Params) -> Params:
    """The parameters of that pass: support is a line of IY-readmit_reach..
    IY+readmit_reach whose verdicts (after the neighbour constraint) agree
    within ``readmit_dd``; each such line takes ``rematch_bonus`` off the
    cost, and a match no such line supports is "not on a vertical line"."""
    return replace(params, neighbour_bonus=params.rematch_bonus,
                   neighbour_dd=params.readmit_dd, neighbour_reach=params.readmit_reach)


def judged_candidates(c: Candidates, constraints: Constraints, p: Params) -> Candidates:
    """The candidates as :func:`match_line`'s assignment weighs them: only the
    mutual ones under ``lr``, with the region penalty (or without the lone
    ends, when strict) under ``region``."""
    if constraints.lr:
        c = c.subset(_mutual(c, p.lr_tolerance))
    if constraints.region:
        c = _region_weighted(c, p)
    return c


def _region_weighted(c: Candidates, p: Params) -> Candidates:
    """The ``region`` constraint on a line's candidates: those without a
    region partner cost ``region_penalty`` more, or are left out when it is
    None (strict)."""
    supported = _region_supported(c, p.region_tolerance)
    if p.region_penalty is None:
        return c.subset(supported)
    return c.with_cost(c.cost + np.where(supported, 0.0, p.region_penalty))


CONFIRMABLE = ("occluded", "not on a vertical line", "ambiguous")


def confirm(data: LineData, verdicts: list[Verdict], neighbours,
            params: Params = Params(), cands: Candidates | None = None,
            constraints: Constraints = Constraints(), columns=None) -> list[Verdict]:
    """The ``confirm`` pass: a second look at the edges the line's rules
    dropped.  An edge left without a match for a reason in
    :data:`CONFIRMABLE` keeps its *own* choice: the partner the assignment
    had given it (dropped afterwards by the neighbour or ambiguity rule), or
    else (the assignment left it out) its cheapest candidate as the
    assignment weighed it (:func:`judged_candidates`).  It takes it when that
    partner is unused, keeps the order of the line's matches, and at least
    ``confirm_support`` of the neighbouring lines' verdicts (``neighbours``:
    lines IY-confirm_reach..IY+confirm_reach) match an edge of the same side
    within ``neighbour_dx`` px at a disparity within ``confirm_dd``.

    Why: on the motorcycle the rules after the assignment dropped mostly
    right matches (the first pass the neighbour rule asks is noisy, and a
    match barely worth its cost is not a wrong one), and most right edges
    the assignment left out were dear rather than out-bid; their own
    evidence, with a vertical line two lines agree on, is what separates
    them from the wrong ones.  Unlike :func:`readmit` the neighbours never
    pick the partner: a candidate the edge's own maps do not prefer is not
    taken.  Edges are visited along the line, each confirmed match counting
    as used at once.  Reason "confirmed"; confidence = the share of the
    neighbouring lines that agree times 1 - cost/256.  ``cands``: the line's
    :func:`judged_candidates` under ``constraints``, when already at hand;
    ``columns``: the :func:`edge_columns` of each of ``neighbours``, when
    already at hand (every line's verdicts vouch for fourteen others)."""
    p = params
    c = judged_candidates(line_candidates(data, p), constraints, p) if cands is None else cands
    dropped = [v for v in verdicts if not v.matched and v.reason in CONFIRMABLE]
    if len(c) == 0 or not dropped:
        return verdicts
    # a line's few candidates as lists: looked up edge by edge below
    ci, cj, cost = c.i.tolist(), c.j.tolist(), c.cost.tolist()
    loc1, loc2 = c.loc1.tolist(), c.loc2.tolist()
    right_edge = c.right.edge.tolist()
    pos1 = {e: i for i, e in enumerate(c.left.edge.tolist())}
    pos2 = {e: j for j, e in enumerate(right_edge)}
    pairs = sorted((pos1[v.edge], pos2[v.partner]) for v in verdicts if v.matched)
    lines = [edge_columns(line) for line in neighbours] if columns is None else columns
    n_lines = max(1, len(neighbours))
    dx, dd = p.neighbour_dx, p.confirm_dd
    by_edge = {v.edge: v for v in verdicts}
    for v in sorted(dropped, key=lambda v: pos1[v.edge]):
        i = pos1[v.edge]
        if v.partner:                                   # the assignment's own choice
            ks = [k for k in range(len(ci)) if ci[k] == i and cj[k] == pos2[v.partner]]
        else:                                           # its cheapest candidate (then leftmost)
            ks = sorted((k for k in range(len(ci)) if ci[k] == i),
                        key=lambda k: (cost[k], cj[k]))
        if not ks:
            continue
        k = ks[0]
        j = cj[k]
        lo = max((b for a, b in pairs if a < i), default=-1)
        hi = min((b for a, b in pairs if a > i), default=len(c.right))
        if not lo < j < hi:                             # used, or out of order
            continue
        support = column_support(lines, v.edge > 50, v.x, loc1[k] - loc2[k], dx, dd)
        if support < p.confirm_support:
            continue
        conf = support / n_lines * max(0.0, 1.0 - cost[k] / 256.0)
        by_edge[v.edge] = replace(v, matched=True, reason="confirmed", partner=right_edge[j],
                                  loc1=loc1[k], loc2=loc2[k], cost=cost[k], confidence=conf)
        pairs = sorted(pairs + [(i, j)])
    return [by_edge[v.edge] for v in verdicts]


READMITTABLE = ("occluded", "not on a vertical line", "ambiguous", "not mutual")


def readmit(data: LineData, verdicts: list[Verdict], neighbours,
            params: Params = Params(), cands: Candidates | None = None) -> list[Verdict]:
    """The second pass: an edge left without a match (for a reason in
    :data:`READMITTABLE`) takes a partner the line's matches left unused,
    where that keeps the order of the matches along the line, when at least
    ``readmit_support`` of the neighbouring lines' final verdicts
    (``neighbours``) have a matched edge of the same side within
    ``neighbour_dx`` px at a disparity within ``readmit_dd``, and its cost is
    at most ``readmit_cost``; the cheapest such partner.  Edges are visited
    along the line, each re-admitted match counting as used at once.  The
    confidence of a re-admitted match is the share of neighbouring lines
    that agree, times 1 - cost/256.  ``cands``: the line's
    :func:`line_candidates`, when already at hand."""
    p = params
    c = line_candidates(data, p) if cands is None else cands
    if len(c) == 0:
        return verdicts
    pos1 = {int(e): i for i, e in enumerate(c.left.edge)}
    pos2 = {int(e): j for j, e in enumerate(c.right.edge)}
    pairs = sorted((pos1[v.edge], pos2[v.partner]) for v in verdicts if v.matched)
    support = _support(c, neighbours, replace(p, neighbour_dd=p.readmit_dd))
    by_edge = {v.edge: v for v in verdicts}
    n_lines = max(1, len(neighbours))
    for v in sorted(verdicts, key=lambda v: pos1[v.edge]):
        if v.matched or v.reason not in READMITTABLE:
            continue
        i = pos1[v.edge]
        lo = max((j for a, j in pairs if a < i), default=-1)
        hi = min((j for a, j in pairs if a > i), default=len(c.right))
        ok = ((c.i == i) & (c.j > lo) & (c.j < hi) & (support >= p.readmit_support)
              & (c.cost <= p.readmit_cost))
        if not ok.any():
            continue
        ks = np.flatnonzero(ok)
        k = int(ks[np.lexsort((c.j[ks], c.cost[ks]))[0]])
        conf = float(support[k]) / n_lines * max(0.0, 1.0 - float(c.cost[k]) / 256.0)
        by_edge[v.edge] = replace(v, matched=True, reason="readmitted",
                                  partner=int(c.right.edge[c.j[k]]), loc1=float(c.loc1[k]),
                                  loc2=float(c.loc2[k]), cost=float(c.cost[k]),
                                  confidence=conf)
        pairs = sorted(pairs + [(i, int(c.j[k]))])
    return [by_edge[v.edge] for v in verdicts]


def match_lines(lines, constraints: Constraints = Constraints(), params: Params = Params(),
                profiles=None) -> dict[int, list[Verdict]]:
    """Verdicts for many lines at once (the batch form of the improved mode).

    ``lines``: :class:`LineData` or ``estar.program.LineResult`` objects.
    The neighbour constraint uses the lines given (a line whose neighbour is
    not among them gets support from the other side only, as at the ends of
    a scan).  ``profiles``: a callable ``iy -> (left, right)`` grey profiles
    for the subpixel constraint."""
    datas = {d.iyloc: d for d in (x if isinstance(x, LineData) else LineData.of(x)
                                  for x in lines)}
    cands = {y: line_candidates(d, params) for y, d in datas.items()}
    first_pass = replace(constraints, neighbours=False, subpixel=False)
    first = {y: match_line(d, first_pass, replace(params, min_confidence=0.0), cands=cands[y])
             for y, d in datas.items()} if constraints.neighbours else {}
    out = {}
    again = rematches(constraints, params)
    later = ((constraints.readmit or constraints.confirm or again) and constraints.subpixel
             and profiles is not None)
    for y, d in datas.items():
        nb = [first[n] for n in neighbour_lines(y, params) if n in first]
        out[y] = match_line(d, replace(constraints, subpixel=constraints.subpixel and not later),
                            params, nb,
                            profiles(y) if (profiles and constraints.subpixel) else None,
                            cands[y])
    if again:
        p2 = rematch_params(params)
        out = {y: match_line(datas[y], replace(constraints, subpixel=False), p2,
                             [out[n] for n in neighbour_lines(y, p2) if n in out],
                             cands=cands[y]) for y in out}
    if constraints.confirm:
        judged = {y: judged_candidates(cands[y], constraints, params) for y in out}
        for _ in range(params.confirm_rounds):
            out = {y: confirm(datas[y], v, [out[n] for n in neighbour_lines(
                       y, params, params.confirm_reach) if n in out], params, judged[y])
                   for y, v in out.items()}
    if constraints.readmit:
        for _ in range(params.readmit_rounds):
            out = {y: readmit(datas[y], v, [out[n] for n in neighbour_lines(
                       y, params, params.readmit_reach) if n in out], params, cands[y])
                   for y, v in out.items()}
    if later:
        from .subpixel import refine_verdicts
        out = {y: refine_verdicts(v, datas[y], profiles(y), params.subpixel_max_change)
               for y, v in out.items()}
    return out


__all__ = ["CONSTRAINTS", "Constraints", "Params", "LineData", "Verdict", "match_line",
           "match_lines"]
