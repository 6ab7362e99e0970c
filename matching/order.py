"""Uniqueness and order along the line: a 1-1 assignment by dynamic programming.

Chapter V ("Matches"): the "picket fence" of identical features "can only be
solved for identical components by matching the first or the last in the
sequence, then using a 1-1 matching along the sequences".  Ohta and Kanade
(*Stereo by intra- and inter-scanline search using dynamic programming*, IEEE
PAMI 7(2), 1985) made that 1-1, order-keeping matching of the edges of two
scan lines a shortest path through the grid of (left edge, right edge)
pairs.  This module is that intra-scanline search over the candidate pairs
of :mod:`matching.candidates`:

* a path is a sequence of matches whose left edges and right edges both
  increase along the line (so no edge is used twice, and the order of the
  features is kept: the uniqueness and ordering constraints);
* every edge left out costs ``occlusion`` (Ohta and Kanade's cost of a
  vertical or horizontal step; here, an edge seen in one picture only);
* every match costs its shape/grey cost; consecutive matches pay
  ``smooth`` per pixel of disparity change, at most ``jump_cap`` pixels (the
  relative geometric position of Chapter III: neighbouring features on one
  surface have nearly the same disparity, so a fence is locked to the
  features it stands between).

Equivalently each match earns ``cost - 2*occlusion`` (negative when worth
taking) and the best path minimises the sum plus the disparity terms.  The
forward and backward passes also give, for every candidate, the cost of the
best path through it (its *min-marginal*); the gap between a match's and its
best rival's (another partner of either of its edges) is the margin the
confidence is built from.
"""

from __future__ import annotations

import numpy as np

from diskfmt.jit import jit


@jit
def order_dp(ci, cj, benefit, disp, smooth, jump_cap, fwd, bwd, pred):
    """The intra-scanline search over K candidates sorted by (ci, cj).
    Fills ``fwd`` (best path ending at k), ``bwd`` (best path starting at k),
    ``pred`` (predecessor on the best path ending at k, -1 none).  Returns
    the index of the last match of the best path, -1 when matching nothing
    is best."""
    k_count = len(ci)
    for k in range(k_count):
        best = 0.0
        p = -1
        for q in range(k):
            if ci[q] < ci[k] and cj[q] < cj[k]:
                v = fwd[q] + smooth * min(abs(disp[k] - disp[q]), jump_cap)
                if v < best:
                    best = v
                    p = q
        fwd[k] = benefit[k] + best
        pred[k] = p
    for k in range(k_count - 1, -1, -1):
        best = 0.0
        for q in range(k + 1, k_count):
            if ci[q] > ci[k] and cj[q] > cj[k]:
                v = bwd[q] + smooth * min(abs(disp[k] - disp[q]), jump_cap)
                if v < best:
                    best = v
        bwd[k] = benefit[k] + best
    last = -1
    best = 0.0
    for k in range(k_count):
        if fwd[k] < best:
            best = fwd[k]
            last = k
    return last


def assign(ci, cj, cost, disp, occlusion: float, smooth: float, jump_cap: float):
    """Run :func:`order_dp`; returns (chosen candidate indices, min-marginal
    cost of the best path through each candidate).  Inputs need not be sorted."""
    ci = np.asarray(ci, dtype=np.int64)
    cj = np.asarray(cj, dtype=np.int64)
    k = len(ci)
    if k == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    order = np.lexsort((cj, ci))
    sci, scj = ci[order], cj[order]
    benefit = np.asarray(cost, dtype=np.float64)[order] - 2.0 * occlusion
    sdisp = np.asarray(disp, dtype=np.float64)[order]
    fwd = np.zeros(k)
    bwd = np.zeros(k)
    pred = np.full(k, -1, dtype=np.int64)
    last = order_dp(sci, scj, benefit, sdisp, float(smooth), float(jump_cap), fwd, bwd, pred)
    chosen = []
    while last >= 0:
        chosen.append(int(order[last]))
        last = int(pred[last])
    marginal = np.empty(k)
    marginal[order] = fwd + bwd - benefit
    return np.array(chosen[::-1], dtype=np.int64), marginal
