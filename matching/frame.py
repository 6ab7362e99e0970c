"""The improved matcher's default rules over a whole frame at once, compiled.

:meth:`matching.mode.ImprovedMatcher.frame_verdicts` judges a scanned line
from its neighbours' verdicts, theirs from their neighbours', and so on, each
line's stages remembered (a scanned line's verdicts reach 22 lines either
side: the second pass one, three confirm rounds seven each).  Every stage is
a few dozen numbers a line, so the Python around them was most of a look's
scan.  :func:`frame_verdicts` makes the same stages in one compiled pass over
every line of the frame, stage by stage (every line's assignment, every
line's second pass, then each confirm round for every line), which needs no
memory of what was asked for: a line's verdicts are a function of the frame.
It covers the default rules (:func:`covers`: ``order, lr, neighbours,
region, confirm`` with the region penalty, no neighbour bonus, no rematch);
the plain matcher stays the reference and the form of every other choice,
and ``tests/test_matching_frame.py`` shows the two equal, every verdict of
every line, the floats bit for bit.

The stages, as :mod:`matching.verdict` writes them:

1. the line's candidates (:func:`matching.candidates.admissible_pairs`),
   ``lr`` (:func:`~matching.verdict._mutual_kernel`), ``region`` as a
   penalty (:func:`~matching.verdict._region_kernel`), the order-keeping
   assignment (:func:`matching.order.order_dp`) and each match's confidence
   (:func:`~matching.verdict._confidences_kernel`): the first pass;
2. the second pass: a match on no vertical line with lines IY-1, IY+1 of the
   first pass is "not on a vertical line", else its confidence is scaled by
   its support; below ``min_confidence`` it is "ambiguous";
3. ``confirm_rounds`` passes of :func:`~matching.verdict.confirm`, each line
   reading its neighbours' verdicts of the pass before.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from diskfmt.jit import jit
from .candidates import _POP, NPIX, admissible_pairs
from .order import order_dp
from .verdict import (Constraints, Params, Verdict, _confidences_kernel, _mutual_kernel,
                      _region_kernel)

LINES = 120
MAX_EDGES = 100
# reason codes of the kernel, in Verdict.reason's words
REASONS = ("matched", "no candidate", "occluded", "not mutual", "not on a vertical line",
           "ambiguous", "confirmed")
MATCHED, NO_CANDIDATE, OCCLUDED, NOT_MUTUAL, NOT_VERTICAL, AMBIGUOUS, CONFIRMED = range(7)


def covers(constraints: Constraints, params: Params) -> bool:
    """Whether :func:`frame_verdicts` makes the verdicts of these rules (the
    defaults); for any other choice the plain matcher does."""
    return (constraints == Constraints() and params.region_penalty is not None
            and params.neighbour_bonus == 0 and params.unsupported_factor is None
            and not params.drop_farther_end and params.rematch_bonus == 0)


@jit
def _half(a):
    """FORTRAN integer /2 (truncates toward zero), as candidates._half."""
    return a // 2 if a >= 0 else -((-a) // 2)


@jit
def _slice_rows(ifeat, n, rows):
    """``matching.candidates.slice_edges`` of one slice: its ``n`` features
    (``ifeat`` rows start, stop, left grey, right grey) as the columns of
    ``rows`` (x, side, edge, grey, feature, bound, width), in the order of the
    edges along the line (x, then side, then edge number)."""
    m = 0
    for k in range(1, n + 1):
        start, stop = ifeat[0, k - 1], ifeat[1, k - 1]
        width = _half(stop - start)
        left = start if k == 1 else _half(start - ifeat[1, k - 2])
        right = NPIX - stop + 1 if k >= n else _half(ifeat[0, k] - stop)
        left = max(min(left, width), 0)
        right = max(min(right, width), 0)
        rows[0, m], rows[1, m], rows[2, m], rows[3, m] = start, 0, k, ifeat[2, k - 1]
        rows[0, m + 1], rows[1, m + 1], rows[2, m + 1] = stop, 1, k + 50
        rows[3, m + 1] = ifeat[3, k - 1]
        for e in (m, m + 1):
            rows[4, e], rows[6, e] = k, stop - start
        rows[5, m], rows[5, m + 1] = left, right
        m += 2
    for a in range(1, m):                 # insertion sort of the m columns
        b = a
        while b > 0 and _after(rows, b - 1, b):
            for r in range(7):
                rows[r, b - 1], rows[r, b] = rows[r, b], rows[r, b - 1]
            b -= 1
    return m


@jit
def _after(rows, a, b):
    """Whether column ``a`` of ``rows`` sorts after column ``b`` (by x, side, edge)."""
    for r in range(3):
        if rows[r, a] != rows[r, b]:
            return rows[r, a] > rows[r, b]
    return False


@jit
def _support(matched, disp, lx, lside, n_left, lines, n_lines, side, x, d, dx, dd):
    """``matching.verdict.column_support``: how many of the ``n_lines`` lines
    ``lines`` have a matched edge of side ``side`` within ``dx`` columns of
    ``x`` at a disparity within ``dd`` of ``d``."""
    if dx < 0:
        return 0
    count = 0
    for t in range(n_lines):
        n = lines[t]
        for i in range(n_left[n]):
            if (matched[n, i] and lside[n, i] == side and abs(lx[n, i] - x) <= dx
                    and abs(disp[n, i] - d) <= dd):
                count += 1
                break
    return count


@jit
def _around(y, reach, out):
    """``matching.verdict.neighbour_lines`` of line ``y`` inside the frame."""
    n = 0
    for r in range(1, reach + 1):
        for s in (-1, 1):
            if 0 <= y + s * r <= LINES - 1:
                out[n] = y + s * r
                n += 1
    return n


# The rules' numbers, as the kernels read them (a named tuple numba passes whole).
Rules = namedtuple("Rules", "use_shift grey_penalty width_penalty lr_tolerance region_tolerance "
                   "region_penalty occlusion smooth jump_cap neighbour_reach neighbour_dx "
                   "neighbour_dd min_confidence confirm_reach confirm_support confirm_dd "
                   "confirm_rounds")


def rules_of(p: Params) -> Rules:
    """The kernels' :class:`Rules` of the matcher's ``Params``."""
    return Rules(bool(p.use_shift), float(p.grey_penalty), float(p.width_penalty),
                 float(p.lr_tolerance), float(p.region_tolerance), float(p.region_penalty),
                 float(p.occlusion), float(p.smooth), float(p.jump_cap), int(p.neighbour_reach),
                 int(p.neighbour_dx), float(p.neighbour_dd), float(p.min_confidence),
                 int(p.confirm_reach), int(p.confirm_support), float(p.confirm_dd),
                 int(p.confirm_rounds))


@jit
def _first_pass(y, nfeat, ifeat, maps, pop, r, edges, verdicts, judged, rows1, rows2):
    """Stage 1 on line ``y``: its edges into ``edges``, the assignment's verdicts
    into ``verdicts`` (every left edge: matched, or why not), its judged
    candidates (after lr and the region penalty) appended to ``judged``."""
    n_left, n_right, ledge, lx, lside, redge = edges
    matched, reason, partner, loc1, loc2, cost, conf = verdicts
    ji, jj, jcost, jloc1, jloc2, jstart = judged
    nl = _slice_rows(ifeat[y, 0], nfeat[y, 0], rows1)
    nr = _slice_rows(ifeat[y, 1], nfeat[y, 1], rows2)
    n_left[y], n_right[y] = nl, nr
    for i in range(nl):
        ledge[y, i], lx[y, i], lside[y, i] = rows1[2, i], rows1[0, i], rows1[1, i]
        matched[y, i], reason[y, i], partner[y, i] = False, NO_CANDIDATE, -1
        loc1[y, i] = loc2[y, i] = conf[y, i] = 0.0
        cost[y, i] = np.nan
    for j in range(nr):
        redge[y, j] = rows2[2, j]
    at = jstart[y]
    jstart[y + 1] = at
    if nl == 0 or nr == 0:
        return
    maps1 = np.empty((nl, 17), np.int64)
    maps2 = np.empty((nr, 17), np.int64)
    for i in range(nl):
        maps1[i] = maps[y, 0, rows1[2, i] - 1]
    for j in range(nr):
        maps2[j] = maps[y, 1, rows2[2, j] - 1]
    pairs = np.empty((nl * nr, 4), np.int64)
    scores = np.empty((nl * nr, 3), np.float64)
    k_all = admissible_pairs(rows1[np.array([0, 1, 3, 5, 6]), :nl], maps1,
                             rows2[np.array([0, 1, 3, 5, 6]), :nr], maps2, r.use_shift,
                             r.grey_penalty, r.width_penalty, float(NPIX), False, pop,
                             pairs, scores)
    if k_all == 0:
        return
    for k in range(k_all):
        reason[y, pairs[k, 0]] = OCCLUDED
    ci, cj = pairs[:k_all, 0].copy(), pairs[:k_all, 1].copy()
    keep = np.zeros(k_all, np.bool_)
    _mutual_kernel(ci, cj, scores[:k_all, 0].copy(), nl, nr, r.lr_tolerance, keep)
    kept = np.flatnonzero(keep)
    still = np.zeros(nl, np.bool_)
    for k in kept:
        still[ci[k]] = True
    for k in range(k_all):
        if not still[ci[k]]:
            reason[y, ci[k]] = NOT_MUTUAL
    n = len(kept)
    ci, cj = ci[kept], cj[kept]
    c_cost, c_loc1, c_loc2 = scores[kept, 0], scores[kept, 1], scores[kept, 2]
    c_disp = c_loc1 - c_loc2
    supported = np.zeros(n, np.bool_)
    f1 = np.empty(n, np.int64)
    f2 = np.empty(n, np.int64)
    side = np.empty(n, np.int64)
    for k in range(n):
        f1[k], f2[k], side[k] = rows1[4, ci[k]], rows2[4, cj[k]], rows1[1, ci[k]]
    _region_kernel(f1, f2, side, c_disp, r.region_tolerance, supported)
    for k in range(n):
        c_cost[k] = c_cost[k] + (0.0 if supported[k] else r.region_penalty)
        ji[at + k], jj[at + k], jcost[at + k] = ci[k], cj[k], c_cost[k]
        jloc1[at + k], jloc2[at + k] = c_loc1[k], c_loc2[k]
    jstart[y + 1] = at + n
    if n == 0:
        return
    # the pairs are in the order of (left edge, right edge): order_dp's own
    two_occlusion = 2.0 * r.occlusion
    benefit = c_cost - two_occlusion
    fwd = np.zeros(n)
    bwd = np.zeros(n)
    pred = np.full(n, -1, np.int64)
    last = order_dp(ci, cj, benefit, c_disp, r.smooth, r.jump_cap, fwd, bwd, pred)
    path = np.empty(n, np.int64)          # the best path, from its last match back
    n_path = 0
    while last >= 0:
        path[n_path] = last
        n_path += 1
        last = pred[last]
    chosen = path[:n_path][::-1].copy()
    marginal = fwd + bwd - benefit
    shares = np.zeros(len(chosen))
    _confidences_kernel(ci, cj, c_cost, chosen, marginal, two_occlusion, shares)
    for t in range(len(chosen)):
        k = chosen[t]
        i = ci[k]
        matched[y, i], reason[y, i], partner[y, i] = True, MATCHED, cj[k]
        loc1[y, i], loc2[y, i], cost[y, i], conf[y, i] = (c_loc1[k], c_loc2[k],
                                                          c_cost[k], shares[t])


@jit
def _second_pass(r, edges, verdicts, first, disp, near):
    """Stage 2 on every line: the neighbour rule on the first pass (``first``,
    ``disp``), then the ambiguity rule."""
    n_left, _, _, lx, lside, _ = edges
    matched, reason, _, _, _, _, conf = verdicts
    for y in range(len(n_left)):
        n_near = _around(y, r.neighbour_reach, near)
        for i in range(n_left[y]):
            if not matched[y, i]:
                continue
            support = _support(first, disp, lx, lside, n_left, near, n_near, lside[y, i],
                               lx[y, i], disp[y, i], r.neighbour_dx, r.neighbour_dd)
            if support == 0:
                matched[y, i], reason[y, i] = False, NOT_VERTICAL
                continue
            factor = min(1.0, 0.75 + 0.125 * support)
            if factor != 1.0:
                conf[y, i] = conf[y, i] * factor
            if conf[y, i] < r.min_confidence:
                matched[y, i], reason[y, i] = False, AMBIGUOUS


@jit
def _confirm_round(r, edges, verdicts, judged, near):
    """Stage 3, one round on every line, each reading the verdicts of the round
    before."""
    n_left, n_right, _, lx, lside, _ = edges
    matched, reason, partner, loc1, loc2, cost, conf = verdicts
    ji, jj, jcost, jloc1, jloc2, jstart = judged
    before = matched.copy()
    before_disp = loc1 - loc2
    for y in range(len(n_left)):
        at, n = jstart[y], jstart[y + 1] - jstart[y]
        if n == 0:
            continue
        n_near = _around(y, r.confirm_reach, near)
        n_lines = max(1, n_near)
        for i in range(n_left[y]):
            if before[y, i] or not (reason[y, i] == OCCLUDED or reason[y, i] == NOT_VERTICAL
                                    or reason[y, i] == AMBIGUOUS):
                continue
            k = -1
            for q in range(at, at + n):          # its own choice, or its cheapest
                if ji[q] != i:
                    continue
                if partner[y, i] >= 0:
                    if jj[q] == partner[y, i]:
                        k = q
                        break
                elif k < 0 or jcost[q] < jcost[k] or (jcost[q] == jcost[k]
                                                      and jj[q] < jj[k]):
                    k = q
            if k < 0:
                continue
            j = jj[k]
            lo, hi = -1, n_right[y]
            for a in range(n_left[y]):            # the line's matches so far
                if matched[y, a]:
                    if a < i:
                        lo = max(lo, partner[y, a])
                    elif a > i:
                        hi = min(hi, partner[y, a])
            if not lo < j < hi:
                continue
            support = _support(before, before_disp, lx, lside, n_left, near, n_near,
                               lside[y, i], lx[y, i], jloc1[k] - jloc2[k], r.neighbour_dx,
                               r.confirm_dd)
            if support < r.confirm_support:
                continue
            matched[y, i], reason[y, i], partner[y, i] = True, CONFIRMED, j
            loc1[y, i], loc2[y, i], cost[y, i] = jloc1[k], jloc2[k], jcost[k]
            conf[y, i] = support / n_lines * max(0.0, 1.0 - jcost[k] / 256.0)


@jit
def frame_kernel(nfeat, ifeat, maps, pop, r, edges, verdicts):
    """The verdicts of every line of a frame (the module docstring's stages).
    ``edges``: (``n_left``, ``n_right``: each line's edge counts; ``ledge``,
    ``lx``, ``lside``: its left edges' numbers, columns and sides in the order
    along the line; ``redge``: its right edges' numbers); ``verdicts``:
    (``matched``, ``reason``: a code of :data:`REASONS`, ``partner``: the right
    edge's position, -1 none, ``loc1``, ``loc2``, ``cost``, ``conf``), one row a
    line, one column a left edge.  ``r``: :class:`Rules`."""
    lines = nfeat.shape[0]
    room = 0                              # every line's judged candidates, one after another
    for y in range(lines):
        room += 4 * nfeat[y, 0] * nfeat[y, 1]
    judged = (np.empty(room, np.int64), np.empty(room, np.int64), np.empty(room, np.float64),
              np.empty(room, np.float64), np.empty(room, np.float64),
              np.zeros(lines + 1, np.int64))
    rows1 = np.empty((7, MAX_EDGES), np.int64)
    rows2 = np.empty((7, MAX_EDGES), np.int64)
    near = np.empty(2 * max(r.neighbour_reach, r.confirm_reach), np.int64)
    for y in range(lines):
        _first_pass(y, nfeat, ifeat, maps, pop, r, edges, verdicts, judged, rows1, rows2)
    matched, _, _, loc1, loc2, _, _ = verdicts
    _second_pass(r, edges, verdicts, matched.copy(), loc1 - loc2, near)
    for _ in range(r.confirm_rounds):
        _confirm_round(r, edges, verdicts, judged, near)


def frame_verdicts(nfeat, ifeat, maps, lines, params: Params = Params()) -> list[list[Verdict]]:
    """The verdicts of each of ``lines`` (as :meth:`ImprovedMatcher.frame_verdicts
    <matching.mode.ImprovedMatcher.frame_verdicts>` gives them under the
    default constraints and ``params``, :func:`covers`) from the frame's
    slices and maps as :func:`eyes.kernels.frame_lines_kernel` makes them:
    ``nfeat`` (120, 2), ``ifeat`` (120, 2, 4, 50), ``maps`` (120, 2, 100, 17)."""
    shape = (LINES, MAX_EDGES)
    edges = (np.zeros(LINES, np.int64), np.zeros(LINES, np.int64),
             *(np.zeros(shape, np.int64) for _ in range(4)))
    verdicts = (np.zeros(shape, np.bool_), np.zeros(shape, np.int64), np.zeros(shape, np.int64),
                *(np.zeros(shape, np.float64) for _ in range(4)))
    frame_kernel(np.asarray(nfeat, np.int64), ifeat, maps, _POP, rules_of(params), edges,
                 verdicts)
    n_left, _, ledge, lx, _, redge = edges
    return [_line_verdicts(y, n_left[y], ledge[y], lx[y], redge[y], *(a[y] for a in verdicts))
            for y in lines]


def _line_verdicts(y, n, ledge, lx, redge, matched, reason, partner, loc1, loc2, cost, conf):
    """Line y's :class:`Verdict` objects, by edge number, from the kernel's rows."""
    rows = zip(ledge[:n].tolist(), lx[:n].tolist(), matched[:n].tolist(),
               reason[:n].tolist(), partner[:n].tolist(), loc1[:n].tolist(),
               loc2[:n].tolist(), cost[:n].tolist(), conf[:n].tolist())
    right = redge.tolist()
    out = []
    for edge, x, ok, why, j, l1, l2, c, cf in sorted(rows):
        if j < 0:          # the assignment gave it no partner: the defaults, as the plain
            out.append(Verdict(y, edge, x, False, REASONS[why]))   # matcher's (NaN cost)
        else:
            out.append(Verdict(y, edge, x, ok, REASONS[why], right[j], l1, l2, c, cf))
    return out


__all__ = ["REASONS", "Rules", "covers", "frame_kernel", "frame_verdicts", "rules_of"]
