"""Matching what a look sees to what the model holds (Chapter III: the
"symbolic accuracy" every later step rests on; Appendix A's first problem,
"modelled feature points must be matched reliably to 'seen' feature points").

As the chapter orders it: predict each model feature into the new look from
the prior pose, keep only candidates within their covariance (the gate is a
chi-square bound on the Mahalanobis distance with the model's covariance, the
rig's covariance carried into room axes (A-31) and the prior pose's own
uncertainty), then within the grey levels ("approximate matches in grey
level, then approximate matches in shape"), and finally one-to-one: the
assignment of least total distance (scipy's ``linear_sum_assignment``).
Shape: with ``shape_max_bits`` each candidate's corner map (an Appendix B
rectangular map, :func:`model.edges.corner_map`) is compared with the model
vertex's by :func:`model.bitmaps.shifted_compare` and the pair refused above
that many differing bits; without it the grey levels and the kind of vertex
(top or bottom end of a vertical boundary) are the whole characterisation.

Another model matcher plugs in through :data:`MATCHERS`: any callable with
:func:`match_look`'s signature returning a :class:`MatchResult`.  (``rig walk
--match improved`` is a different seam: the improved STEREO matcher of the
``matching`` package inside ESTAR, handed to :func:`rig.scan.scan_pair` by :func:`model.mapping.run_walk`.)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

GATE_CHI2 = 16.27      # chi-square 99.9 % point, 3 degrees of freedom
GREY_TOLERANCE = 2     # grey levels (0..15) either side of the edge
SHAPE_MAX_BITS = None  # Appendix B shape gate: most differing bits of 256 (None: no gate)


@dataclass
class MatchResult:
    pairs: list[tuple[int, int]]            # (model vertex id, observation index)
    predicted_in_view: int = 0              # model vertices predicted inside the picture
    candidates: int = 0                     # gated (vertex, observation) candidates
    notes: dict = field(default_factory=dict)


def _skew_stack(w):
    S = np.zeros((len(w), 3, 3))
    S[:, 0, 1], S[:, 0, 2] = -w[:, 2], w[:, 1]
    S[:, 1, 0], S[:, 1, 2] = w[:, 2], -w[:, 0]
    S[:, 2, 0], S[:, 2, 1] = -w[:, 1], w[:, 0]
    return S


def in_view(X, left, R, first_row: float = 8, last_row: float = 113, dv: float = 180.0,
            min_range: float = 1.0, margin: float = 0.0) -> np.ndarray:
    """Which room points the left camera at (left, R) would see in the scanned rows."""
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    v = (X - left) @ R
    with np.errstate(divide="ignore", invalid="ignore"):
        col = 64.0 + dv * v[:, 0] / v[:, 2]
        row = 60.0 + dv * v[:, 1] / v[:, 2]
    return ((v[:, 2] > min_range) & (col >= -margin) & (col < 128 + margin)
            & (row >= first_row - margin) & (row <= last_row + margin))


def _gated(model, observations, prior_left, prior_R, prior_cov6, gate, grey_tolerance, rows):
    """The covariance, kind and grey gates: (ids, visible, cand, d2, ok), or None when
    nothing can match (then ``visible`` alone: an int)."""
    ids, means, covs, kinds, greys = model.vertex_arrays()
    n_obs = len(observations)
    if len(ids) == 0 or n_obs == 0:
        return 0
    R = np.asarray(prior_R, dtype=np.float64)
    left = np.asarray(prior_left, dtype=np.float64)
    visible = in_view(means, left, R, rows[0], rows[1])
    # keep vertices near the view too: the prior may be off by a few degrees
    widened = in_view(means, left, R, rows[0], rows[1], margin=15.0)
    cand = np.flatnonzero(widened)
    if len(cand) == 0:
        return int(visible.sum())
    q = np.array([o.q for o in observations])
    Cq = np.array([o.cov for o in observations])
    M = np.column_stack([R[:, 2], R[:, 0], R[:, 1]])
    X_obs = left + q @ M.T                                       # A-23 at the prior pose
    C_obs = np.einsum("ij,njk,lk->nil", M, Cq, M)
    w = X_obs - left
    J = np.zeros((n_obs, 3, 6))
    J[:, :, :3] = np.eye(3)
    J[:, :, 3:] = -_skew_stack(w)
    C_pose = np.einsum("nij,jk,nlk->nil", J, np.asarray(prior_cov6, float), J)
    r = X_obs[:, None, :] - means[cand][None, :, :]              # (n_obs, n_cand, 3)
    S = C_obs[:, None] + C_pose[:, None] + covs[cand][None]
    d2 = np.einsum("nma,nmab,nmb->nm", r, np.linalg.inv(S), r)
    kind_obs = np.array([o.kind for o in observations])
    kind_mod = np.array(kinds)[cand]
    g_obs = np.array([o.grey for o in observations])
    g_mod = greys[cand]
    ok = (d2 <= gate) & (kind_obs[:, None] == kind_mod[None, :])
    if grey_tolerance is not None:
        ok &= np.all(np.abs(g_obs[:, None, :] - g_mod[None, :, :]) <= grey_tolerance, axis=2)
    return ids, visible, cand, d2, ok


def gated_distances(model, observations, prior_left, prior_R, prior_cov6,
                    gate: float = GATE_CHI2, grey_tolerance: int = GREY_TOLERANCE,
                    rows=(8, 113)) -> np.ndarray:
    """Per observation, the least Mahalanobis distance (squared) to a model vertex that
    :func:`match_look`'s covariance, kind and grey gates admit; inf where none does (the
    model predicts no feature there).  For choosing among a picket fence's periods."""
    g = _gated(model, observations, prior_left, prior_R, prior_cov6, gate, grey_tolerance, rows)
    if not isinstance(g, tuple):
        return np.full(len(observations), np.inf)
    _, _, _, d2, ok = g
    return np.where(ok, d2, np.inf).min(axis=1)


def match_look(model, observations, prior_left, prior_R, prior_cov6, gate: float = GATE_CHI2,
               grey_tolerance: int = GREY_TOLERANCE, rows=(8, 113),
               shape_max_bits: int | None = SHAPE_MAX_BITS, model_shapes=None) -> MatchResult:
    """Match a look's vertex observations (``model.edges.VertexObservation``)
    to the model's vertices (``model.symbolic.SymbolicModel``)."""
    g = _gated(model, observations, prior_left, prior_R, prior_cov6, gate, grey_tolerance, rows)
    if not isinstance(g, tuple):
        return MatchResult([], g, 0)
    ids, visible, cand, d2, ok = g
    if shape_max_bits is not None:
        # Appendix B: the corner maps compared at horizontal offsets -2..2 (B-1's count)
        from .bitmaps import shifted_compare
        shapes = [model.vertices[int(ids[c])].shape for c in cand]
        for i, j in zip(*np.nonzero(ok)):
            a, b = observations[i].shape, shapes[j]
            if a is not None and b is not None and shifted_compare(b, a, 2)[0] > shape_max_bits:
                ok[i, j] = False
    cost = np.where(ok, d2, np.inf)
    pairs = []
    if ok.any():
        from scipy.optimize import linear_sum_assignment
        rows_i, cols_j = linear_sum_assignment(np.where(ok, cost, 1e9))
        pairs = [(int(ids[cand[j]]), int(i)) for i, j in zip(rows_i, cols_j) if ok[i, j]]
    return MatchResult(pairs, int(visible.sum()), int(ok.sum()))


MATCHERS: dict[str, Callable[..., MatchResult]] = {"text": match_look}
