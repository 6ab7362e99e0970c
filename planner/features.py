"""Chapter IV's octree "regenerated from the symbolic model whenever the model
changes": the floor features the map's occupied cells are drawn from.

Per-look accumulation (the loop's default, ``DriveConfig.occupied="looks"``)
puts every look's hits into the octree grown by THAT look's covariance and
never shrinks them: a far look's coarse hit keeps its wide growth after a
near look has located the same corner to a few hundredths of a foot.  Here
(``occupied="model"``) each look's floor-scan hits are

* **associated** with the floor features already in the model: the nearest by
  the Mahalanobis distance of their 2-D (x, z) difference under the summed
  covariances, within a chi-square gate, one-to-one within a look
  (:func:`associate`);
* **fused** into them by the static Kalman update of the model package
  (:func:`model.kalman.static_update`, Chapter III's MAYB 79 filter: one
  feature, many looks), or start new features when none is within the gate;
* placed from the ESTIMATED pose, so the pose's own uncertainty is added to
  each observation's covariance (:func:`pose_point_covariance`: position
  error plus heading error times the lever arm), the dead-reckoned pose's
  covariance propagated by the odometry's noise model
  (:func:`vehicle.sim.odometry_covariance`);
* retired when later looks see through their cell (the octree's log-odds of
  the cell below its free threshold: more misses than hits).

The occupied and uncertain cells are then regenerated from the features every
cycle (:meth:`FloorFeatures.cells`): a feature seen in ``confirm_looks`` looks
occupied, else uncertain, each grown by its FUSED covariance (two standard
deviations, capped at :data:`planner.octree.MAX_GROWTH_FT` as the per-look
growth is), and the surface spans between neighbouring hits of one look
drawn between the features those hits fused into.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from model.kalman import static_update
from .octree import MAX_GROWTH_FT

GATE_CHI2 = 9.21             # chi-square, 2 degrees of freedom, 99 %
TWO_SIGMA_SHARE_2D = 1 - np.exp(-2.0)   # a 2-D Gaussian's share within Mahalanobis 2: 86.5 %


def pose_point_covariance(points_xz, pivot_xz, pose_cov) -> np.ndarray:
    """(N, 2, 2): the covariance a pose error gives points placed from that
    pose.  ``pose_cov`` is the (x, z, heading in radians) covariance of the
    vehicle at ``pivot_xz``; a point at offset v = p - pivot moves by the
    position error plus the heading error times d v / d heading, which for a
    heading measured from +z toward +x is (v_z, -v_x)."""
    p = np.asarray(points_xz, float).reshape(-1, 2)
    v = p - np.asarray(pivot_xz, float)
    J = np.zeros((len(p), 2, 3))
    J[:, 0, 0] = J[:, 1, 1] = 1.0
    J[:, 0, 2] = v[:, 1]
    J[:, 1, 2] = -v[:, 0]
    return J @ np.asarray(pose_cov, float) @ np.swapaxes(J, 1, 2)


def _inv2(S):
    """Inverses of a stack of 2x2 matrices (closed form)."""
    a, b, c, d = S[..., 0, 0], S[..., 0, 1], S[..., 1, 0], S[..., 1, 1]
    det = a * d - b * c
    det = np.where(np.abs(det) < 1e-300, 1e-300, det)
    out = np.empty_like(S)
    out[..., 0, 0], out[..., 0, 1] = d / det, -b / det
    out[..., 1, 0], out[..., 1, 1] = -c / det, a / det
    return out


def mahalanobis2(feat_mean, feat_cov, obs, obs_cov) -> np.ndarray:
    """(F, O): squared Mahalanobis distance of every observation from every
    feature under the summed covariance (the innovation's)."""
    d = np.asarray(obs, float)[None, :, :] - np.asarray(feat_mean, float)[:, None, :]
    Si = _inv2(np.asarray(feat_cov, float)[:, None] + np.asarray(obs_cov, float)[None])
    return np.einsum("foi,foij,foj->fo", d, Si, d)


def associate(feat_mean, feat_cov, obs, obs_cov, gate: float = GATE_CHI2) -> np.ndarray:
    """For each observation the index of its feature, or -1: the nearest pair
    by Mahalanobis distance first, each feature and each observation used at
    most once (one look sees a corner once), pairs beyond ``gate`` never."""
    n_obs = len(obs)
    out = np.full(n_obs, -1, int)
    if not len(feat_mean) or not n_obs:
        return out
    d2 = mahalanobis2(feat_mean, feat_cov, obs, obs_cov)
    f, o = np.nonzero(d2 <= gate)
    order = np.argsort(d2[f, o], kind="stable")
    used_f = np.zeros(len(feat_mean), bool)
    for k in order:
        if out[o[k]] < 0 and not used_f[f[k]]:
            out[o[k]] = f[k]
            used_f[f[k]] = True
    return out


def fuse2(mean, cov, z, R):
    """The static Kalman update (model.kalman.static_update) of 2-D (x, z)
    features: embedded in 3-D with an independent, unit third axis that the
    update leaves out of the (x, z) block."""
    def up(m2, c2):
        m3 = np.zeros(m2.shape[:-1] + (3,))
        m3[..., [0, 2]] = m2
        c3 = np.zeros(c2.shape[:-2] + (3, 3))
        c3[..., 1, 1] = 1.0
        c3[..., 0, 0], c3[..., 0, 2] = c2[..., 0, 0], c2[..., 0, 1]
        c3[..., 2, 0], c3[..., 2, 2] = c2[..., 1, 0], c2[..., 1, 1]
        return m3, c3
    m, P = static_update(*up(np.asarray(mean, float), np.asarray(cov, float)),
                         *up(np.asarray(z, float), np.asarray(R, float)))
    return m[..., [0, 2]], P[..., [0, 2], :][..., [0, 2]]


def ellipse_cells(means, covs, res: float, sigmas: float = 2.0, max_cells: int | None = None
                  ) -> np.ndarray:
    """(M, 2) distinct integer cells (floor(x / res), floor(z / res)) the 2-D
    features cover when grown by their covariance: every cell whose nearest
    point to the mean lies within ``sigmas`` standard deviations, and the
    mean's own cell; at most ``max_cells`` cells from the mean along an axis
    (default :data:`~planner.octree.MAX_GROWTH_FT`).  The floor-plane slice of
    :func:`planner.octree.features_cells` (tested equal)."""
    means = np.asarray(means, float).reshape(-1, 2)
    covs = np.asarray(covs, float).reshape(-1, 2, 2)
    if not len(means):
        return np.zeros((0, 2), np.int64)
    if max_cells is None:
        max_cells = max(1, int(round(MAX_GROWTH_FT / res)))
    half = sigmas * np.sqrt(np.clip(np.diagonal(covs, axis1=1, axis2=2), 0, None))
    k = np.minimum(np.ceil(half / res).max(0).astype(int) + 1, max_cells)
    offs = np.stack(np.meshgrid(np.arange(-k[0], k[0] + 1), np.arange(-k[1], k[1] + 1),
                                indexing="ij"), -1).reshape(-1, 2)
    base = np.floor(means / res)
    cells = base[:, None, :] + offs[None] + 0.5
    d = np.clip(means[:, None, :] / res, cells - 0.5, cells + 0.5) * res - means[:, None, :]
    m2 = np.einsum("nmi,nij,nmj->nm", d, _inv2(covs), d)
    inside = m2 <= sigmas ** 2
    inside[:, len(offs) // 2] = True                                   # the mean's own cell
    return np.unique(np.floor(cells[inside]).astype(np.int64), axis=0)


def segment_cells(a, b, res: float) -> np.ndarray:
    """(M, 2) distinct integer cells of the segments a-b, sampled at half a cell."""
    a, b = np.asarray(a, float).reshape(-1, 2), np.asarray(b, float).reshape(-1, 2)
    if not len(a):
        return np.zeros((0, 2), np.int64)
    n = np.maximum(2, np.ceil(np.linalg.norm(b - a, axis=1) / (res / 2)).astype(int) + 1)
    seg = np.repeat(np.arange(len(a)), n)
    t = np.concatenate([np.linspace(0, 1, m) for m in n])
    pts = a[seg] + t[:, None] * (b - a)[seg]
    return np.unique(np.floor(pts / res).astype(np.int64), axis=0)


@dataclass
class FloorFeatures:
    """The floor features of the symbolic model the map is drawn from: 2-D
    (x, z) means and covariances, the number of looks fused into each,
    whether each is alive (not yet seen through), and the surface spans
    between features (a pair of feature ids -> the looks that saw it)."""
    gate: float = GATE_CHI2
    mean: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    cov: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    looks: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    alive: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    spans: dict = field(default_factory=dict)
    seen_pose_cov: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    fused: int = 0               # observations fused into an existing feature so far
    started: int = 0             # observations that started a feature

    def __len__(self) -> int:
        return int(self.alive.sum())

    def add_look(self, obs, obs_cov, spans=(), near=None, near_ft: float | None = None,
                 drift_cov=None) -> np.ndarray:
        """One look's observations ((O, 2) means, (O, 2, 2) covariances, the
        pose's share already in them) into the model; ``spans`` are pairs of
        observation indices.  Only alive features within ``near_ft`` of
        ``near`` are candidates (a look sees no farther).  Returns the
        feature id of each observation.

        ``drift_cov`` (the pose's (x, z, heading) covariance now, with
        ``near`` the vehicle's position): the features are kept in the
        dead-reckoned frame, so a feature last seen under the pose covariance
        P_then is uncertain in the current frame by the drift since,
        ``P_now - P_then`` carried by its lever arm from ``near``; that is
        added to its covariance before it is gated and fused (the
        observations then carry no pose share of their own).  A feature this
        look did not see keeps its covariance (in the frame it was last seen
        in)."""
        obs = np.asarray(obs, float).reshape(-1, 2)
        obs_cov = np.asarray(obs_cov, float).reshape(-1, 2, 2)
        cand = np.flatnonzero(self.alive)
        if near is not None and near_ft is not None and len(cand):
            cand = cand[np.hypot(*(self.mean[cand] - np.asarray(near, float)).T) <= near_ft]
        if drift_cov is not None and len(cand):
            D = np.asarray(drift_cov, float)[None] - self.seen_pose_cov[cand]
            w, V = np.linalg.eigh((D + np.swapaxes(D, 1, 2)) / 2)
            D = (V * np.clip(w, 0, None)[:, None, :]) @ np.swapaxes(V, 1, 2)
            v = self.mean[cand] - np.asarray(near, float)
            J = np.zeros((len(cand), 2, 3))
            J[:, 0, 0] = J[:, 1, 1] = 1.0
            J[:, 0, 2], J[:, 1, 2] = v[:, 1], -v[:, 0]
            prior = self.cov[cand] + J @ D @ np.swapaxes(J, 1, 2)
        else:
            prior = self.cov[cand]
        match = associate(self.mean[cand], prior, obs, obs_cov, self.gate)
        ids = np.full(len(obs), -1, int)
        ids[match >= 0] = cand[match[match >= 0]]
        old = ids >= 0
        if old.any():
            f = ids[old]
            # only the features this look saw move into the current frame
            self.mean[f], self.cov[f] = fuse2(self.mean[f], prior[match[old]], obs[old],
                                              obs_cov[old])
            if drift_cov is not None:
                self.seen_pose_cov[f] = np.asarray(drift_cov, float)
            self.looks[f] += 1
            self.fused += int(old.sum())
        new = np.flatnonzero(~old)
        if len(new):
            ids[new] = len(self.mean) + np.arange(len(new))
            self.mean = np.vstack([self.mean, obs[new]])
            self.cov = np.concatenate([self.cov, obs_cov[new]])
            self.looks = np.concatenate([self.looks, np.ones(len(new), int)])
            self.alive = np.concatenate([self.alive, np.ones(len(new), bool)])
            seen = np.zeros((len(new), 3, 3)) if drift_cov is None else \
                np.repeat(np.asarray(drift_cov, float)[None], len(new), 0)
            self.seen_pose_cov = np.concatenate([self.seen_pose_cov, seen])
            self.started += len(new)
        for a, b in spans:
            key = (int(min(ids[a], ids[b])), int(max(ids[a], ids[b])))
            if key[0] != key[1]:
                self.spans[key] = self.spans.get(key, 0) + 1
        return ids

    def retire(self, seen_through: np.ndarray) -> int:
        """Retire the alive features flagged in ``seen_through`` (one bool per
        feature); returns how many."""
        gone = self.alive & np.asarray(seen_through, bool)
        self.alive &= ~gone
        return int(gone.sum())

    def cells(self, res: float, confirm_looks: int, sigmas: float = 2.0):
        """(occupied, uncertain): (M, 2) integer cells (x, z) of the features
        seen in at least ``confirm_looks`` looks and of the others, each grown
        by its fused covariance, and of the spans between alive features
        (occupied when ``confirm_looks`` looks saw the span).  A cell in both
        is occupied."""
        return (self._cells(res, confirm_looks, sigmas, confirmed=True),
                self._cells(res, confirm_looks, sigmas, confirmed=False))

    def uncertain_cells(self, res: float, confirm_looks: int, sigmas: float) -> np.ndarray:
        """The uncertain part of :meth:`cells` alone (drawn at another
        ``sigmas``: ``DriveConfig.uncertain="core"``'s one sigma)."""
        return self._cells(res, confirm_looks, sigmas, confirmed=False)

    def _cells(self, res: float, confirm_looks: int, sigmas: float, confirmed: bool):
        sure = self.alive & (self.looks >= confirm_looks)
        sel = sure if confirmed else self.alive & ~sure
        out = [ellipse_cells(self.mean[sel], self.cov[sel], res, sigmas)]
        if self.spans:
            pairs = np.array(list(self.spans.keys()), int)
            seen = np.array(list(self.spans.values()), int)
            ok = self.alive[pairs[:, 0]] & self.alive[pairs[:, 1]] & \
                ((seen >= confirm_looks) == confirmed)
            out.append(segment_cells(self.mean[pairs[ok, 0]], self.mean[pairs[ok, 1]], res))
        return np.vstack(out)


def honesty(features: FloorFeatures, outline, near_ft: float = 1.0, min_looks: int = 2):
    """How honest the fused covariances are: of the alive features fused from
    at least ``min_looks`` looks that lie within ``near_ft`` of the true room's
    outline (``outline`` (K, 2): points along every obstacle's footprint and
    the walls, :func:`true_outline`), the share whose 2-sigma ellipse reaches
    the outline (the smallest Mahalanobis distance to its points at most 2).
    A located edge lies somewhere on an outline, so an honest covariance holds
    it in at least the share a 2-D Gaussian has within 2 sigma (86.5 %).
    Returns (share or None, how many features)."""
    sel = np.flatnonzero(features.alive & (features.looks >= min_looks))
    outline = np.asarray(outline, float).reshape(-1, 2)
    if not len(sel) or not len(outline):
        return None, 0
    inside, n = 0, 0
    for i in sel:
        d = outline - features.mean[i]
        near = np.hypot(d[:, 0], d[:, 1]) <= near_ft
        if not near.any():
            continue
        n += 1
        m2 = np.einsum("ni,ij,nj->n", d[near], _inv2(features.cov[i]), d[near])
        inside += bool(m2.min() <= 4.0)
    return (inside / n if n else None), n


def true_outline(room, step_ft: float = 0.01) -> np.ndarray:
    """(K, 2) points ``step_ft`` apart along the (x, z) outline of every
    obstacle footprint and of the walls."""
    out = []
    for x0, x1, z0, z1 in list(np.asarray(room.obstacles, float)) + [room.bounds]:
        for a, b in (((x0, z0), (x1, z0)), ((x1, z0), (x1, z1)), ((x1, z1), (x0, z1)),
                     ((x0, z1), (x0, z0))):
            n = max(2, int(np.ceil(np.hypot(b[0] - a[0], b[1] - a[1]) / step_ft)) + 1)
            out.append(np.linspace(a, b, n))
    return np.vstack(out)
