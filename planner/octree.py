"""Chapter IV, "The Volumetric Model": an octree of the volume of interest.

The dissertation (after Ruff and Ahuja) keeps a hierarchical model of the
space of interest, a cube whose successive levels halve the cells, "the number
of levels ... determined by the accuracy of representation desired"; the model
is regenerated from the symbolic model whenever it changes, and is used only
for path finding.  Here the octree is OctoMap's (the ``pyoctomap`` binding):

* **occupied** where a located feature is, each grown by its covariance
  (:func:`insert_feature`: every cell within two standard deviations), and on
  the surfaces spanned between boundary lines (:func:`insert_surface`);
* **free** along the sight line from the camera to every located point (Ruff
  and Ahuja's empty-space model: OctoMap's ray casting, :func:`insert_rays`);
* **uncertain** where hits and misses leave it undecided (one look's hit when
  ``confirm_looks`` is 2);
* **unknown** elsewhere: cells never touched are simply absent from the tree,
  as the dissertation has it ("all other volumes are merely left out").

Why ``pyoctomap`` (1.2.2): it and ``octomap-python`` (1.10.0.0) both install
from wheels for CPython 3.10-3.13 and both pass the same insert/query trial;
``pyoctomap`` bundles its shared libraries, returns ``None`` for a query of
unknown space (``octomap-python`` returns a node that raises
``NullPointerException`` when read) and reports how many points a batch
inserted.  Only what the dissertation adds on top (growth by covariance,
surfaces, the volume of interest set by the accuracy wanted) is written here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pyoctomap

FREE, OCCUPIED, UNKNOWN, UNCERTAIN = 0, 1, 2, 3
STATE_NAMES = {FREE: "free", OCCUPIED: "occupied", UNKNOWN: "unknown", UNCERTAIN: "uncertain"}


@dataclass(frozen=True)
class VolumeOfInterest:
    """The cube of Chapter IV: side ``side_ft`` with ``depth`` levels below the
    root, so the finest cell is ``side_ft / 2**depth`` (one binary digit of
    position per level)."""
    side_ft: float = 32.0
    depth: int = 7

    @property
    def resolution(self) -> float:
        return self.side_ft / 2 ** self.depth

    @classmethod
    def for_accuracy(cls, accuracy_ft: float, side_ft: float = 32.0) -> "VolumeOfInterest":
        """The fewest levels whose finest cell is no larger than ``accuracy_ft``."""
        if not accuracy_ft > 0:
            raise ValueError(f"accuracy must be positive, got {accuracy_ft!r} ft")
        depth = max(1, int(np.ceil(np.log2(side_ft / accuracy_ft))))
        if depth > 16:
            raise ValueError(f"accuracy {accuracy_ft} ft needs {depth} levels over "
                             f"{side_ft} ft; OctoMap keys allow 16")
        return cls(side_ft, depth)


class Octree(pyoctomap.OcTree):
    """OctoMap's occupancy tree, which also logs the finest cells that its
    batch updates (:meth:`updateNodes` with room coordinates, as
    :func:`mark_occupied` and :func:`mark_free_rays` make them) touch.  The
    floor map's projection (:func:`planner.floormap.project_octree`) then
    reads back only those cells since the last projection instead of every
    leaf, the cost of a look instead of the model's size.  Any other change
    (a point cloud's ray casting, a single-node or key update, clearing,
    reading a file) marks the log incomplete, and the projection then
    redraws from all leaves as before."""

    def __init__(self, resolution: float):
        self.touched: list[np.ndarray] = []      # packed keys (:func:`pack`) per update
        self.log_complete = True

    def key_of(self, coords) -> np.ndarray:
        # OctoMap's own key: the coordinate as a float point3d, then
        # floor(coordinate / resolution) (OcTreeBaseImpl::coordToKey)
        c = np.asarray(coords, np.float32).astype(np.float64).reshape(-1, 3)
        return np.floor(c * (1.0 / self.getResolution()))

    def updateNodes(self, values, update, lazy_eval=False):
        out = super().updateNodes(values, update, lazy_eval)
        if values is not None and len(values):
            if isinstance(values, np.ndarray) and values.dtype.kind == "f":
                self.touched.append(pack(self.key_of(values)))
            else:
                self.log_complete = False
        return out


def _untracked(name: str):
    """OctoMap's method ``name``, after which the change log is incomplete."""
    def method(self, *args, **kwargs):
        self.log_complete = False
        return getattr(pyoctomap.OcTree, name)(self, *args, **kwargs)
    method.__name__ = method.__qualname__ = name
    method.__doc__ = f"OctoMap's {name}; the change log is then incomplete."
    return method


for _name in ("insertPointCloud", "updateNode", "deleteNode", "clear", "read", "readBinary",
              "setResolution", "expandNode", "createNodeChild", "deleteNodeChild",
              "toMaxLikelihood"):
    setattr(Octree, _name, _untracked(_name))
del _name


def new_octree(voi: VolumeOfInterest = VolumeOfInterest(), confirm_looks: int = 1
               ) -> Octree:
    """An empty model.  OctoMap's log-odds update is +0.85 for a hit and -0.41
    for a miss (probabilities 0.7 / 0.4); a cell is OCCUPIED once its log-odds
    reach ``confirm_looks - 1`` hits above one (so ``confirm_looks`` looks
    that hit it and never miss), FREE while its log-odds are below zero (more
    misses than hits; ``free_looks`` of them, see :func:`free_below`),
    UNCERTAIN when hit but not yet confirmed, and UNKNOWN when never seen (or
    seen through too few times)."""
    tree = Octree(voi.resolution)
    if confirm_looks < 1:
        raise ValueError(f"confirm_looks must be at least 1, got {confirm_looks!r}")
    hit = math.log(tree.getProbHit() / (1 - tree.getProbHit()))
    thres_logodds = 0.0 if confirm_looks == 1 else hit * (confirm_looks - 1) + 0.05
    tree.setOccupancyThres(1.0 / (1.0 + math.exp(-thres_logodds)))
    return tree


MISS_LOGODDS = math.log(0.4 / 0.6)      # OctoMap's default miss update


def free_below(free_looks: int = 1) -> float:
    """The log-odds under which a cell counts as FREE: ``free_looks`` misses
    (net of hits) are needed."""
    if free_looks < 1:
        raise ValueError(f"free_looks must be at least 1, got {free_looks!r}")
    return 0.0 if free_looks == 1 else MISS_LOGODDS * (free_looks - 1) - 1e-3


def classify(lo, occ_lo: float, free_lo: float):
    """OCCUPIED at or above ``occ_lo``; UNCERTAIN (a possible obstacle) from 0;
    FREE below ``free_lo``; UNKNOWN between (seen through too few times)."""
    lo = np.asarray(lo, float)
    return np.where(lo >= occ_lo, OCCUPIED, np.where(lo >= 0, UNCERTAIN, np.where(
        lo < free_lo, FREE, UNKNOWN))).astype(np.uint8)


def _state(tree, node, free_lo: float = 0.0) -> int:
    return int(classify(node.getLogOdds(), tree.getOccupancyThresLog(), free_lo))


def insert_rays(tree: pyoctomap.OcTree, points: np.ndarray, origin, max_range: float = -1.0
                ) -> None:
    """Free along each sight line ``origin -> point``, occupied at the point
    (OctoMap's ray casting; one update per cell per batch, a hit winning over
    a miss in the same batch)."""
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    if len(pts):
        tree.insertPointCloud(pts, np.asarray(origin, dtype=np.float64), max_range)


_KEY_OFFSET = 1 << 20          # 21 bits per axis: +-2**20 cells


def pack(keys: np.ndarray) -> np.ndarray:
    """Integer cell keys (N, 3) as one int64 each, ordered as the rows are
    lexicographically (x, then y, then z)."""
    k = keys.astype(np.int64) + _KEY_OFFSET
    return (k[:, 0] << 42) | (k[:, 1] << 21) | k[:, 2]


def unpack(packed: np.ndarray) -> np.ndarray:
    """The (N, 3) integer cell keys of :func:`pack`."""
    p = np.asarray(packed, np.int64)
    mask = (1 << 21) - 1
    return np.stack([(p >> 42) & mask, (p >> 21) & mask, p & mask], 1) - _KEY_OFFSET


def cell_centres(points, res: float) -> np.ndarray:
    """The distinct cells (their centres) holding ``points``, in the
    lexicographic order of their keys."""
    pts = np.asarray(points, float).reshape(-1, 3)
    if not len(pts):
        return pts
    return (unpack(np.unique(pack(np.floor(pts / res)))) + 0.5) * res


def feature_cells(mean, cov, res: float, sigmas: float = 2.0) -> np.ndarray:
    """Centres of the cells a located feature occupies when grown by its
    covariance: every cell that reaches within ``sigmas`` standard deviations
    (the Mahalanobis distance of the cell's point nearest the mean), and at
    least the cell of the mean."""
    mean = np.asarray(mean, dtype=np.float64)
    cov = np.asarray(cov, dtype=np.float64)
    half = sigmas * np.sqrt(np.clip(np.diag(cov), 0, None))
    lo = np.floor((mean - half) / res)
    hi = np.floor((mean + half) / res)
    axes = [(np.arange(a, b + 1) + 0.5) * res for a, b in zip(lo, hi)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    d = np.clip(mean, grid - res / 2, grid + res / 2) - mean
    try:
        m2 = np.einsum("ni,ij,nj->n", d, np.linalg.inv(cov), d)
        cells = grid[m2 <= sigmas ** 2]
    except np.linalg.LinAlgError:
        cells = grid[:0]
    return cell_centres(np.vstack([cells, mean[None]]), res)


def surface_cells(a, b, res: float, c=None) -> np.ndarray:
    """Centres of the cells of a surface spanned by boundary points: the
    segment ``a-b`` (two ends of a surface seen on one scan line) or the
    parallelogram ``a, b, c`` (corner ``a``, edges to ``b`` and ``c``), sampled
    at half the cell size."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    n1 = max(2, int(np.ceil(np.linalg.norm(b - a) / (res / 2))) + 1)
    pts = a + np.linspace(0, 1, n1)[:, None] * (b - a)
    if c is not None:
        c = np.asarray(c, float)
        n2 = max(2, int(np.ceil(np.linalg.norm(c - a) / (res / 2))) + 1)
        t = np.linspace(0, 1, n2)
        pts = (pts[:, None, :] + t[None, :, None] * (c - a)).reshape(-1, 3)
    return cell_centres(pts, res)


def mark_occupied(tree: pyoctomap.OcTree, centres) -> int:
    """One hit for each cell centre given."""
    centres = np.ascontiguousarray(centres, dtype=np.float64).reshape(-1, 3)
    if len(centres):
        tree.updateNodes(centres, True)
    return len(centres)


def insert_feature(tree: pyoctomap.OcTree, mean, cov, sigmas: float = 2.0) -> int:
    """A located feature grown by its covariance (:func:`feature_cells`),
    marked occupied.  Returns the number of cells."""
    return mark_occupied(tree, feature_cells(mean, cov, tree.getResolution(), sigmas))


def insert_surface(tree: pyoctomap.OcTree, a, b, c=None) -> int:
    """A surface between boundary points (:func:`surface_cells`), marked occupied."""
    return mark_occupied(tree, surface_cells(a, b, tree.getResolution(), c))


MAX_GROWTH_FT = 1.5         # how far a feature is grown from its mean along an axis, at most


def features_cells(means, covs, res: float, sigmas: float = 2.0, max_cells: int | None = None
                   ) -> np.ndarray:
    """:func:`feature_cells` for many features at once (vectorised), each grown
    at most ``max_cells`` cells from its mean along an axis (default
    :data:`MAX_GROWTH_FT` in cells, so the cap is the same distance at every
    depth of the octree: 6 cells of 0.25 ft, 12 of 0.125 ft)."""
    means = np.asarray(means, float).reshape(-1, 3)
    covs = np.asarray(covs, float).reshape(-1, 3, 3)
    if not len(means):
        return means
    if max_cells is None:
        max_cells = max(1, int(round(MAX_GROWTH_FT / res)))
    half = sigmas * np.sqrt(np.clip(np.diagonal(covs, axis1=1, axis2=2), 0, None))
    k = np.minimum(np.ceil(half / res).max(0).astype(int) + 1, max_cells)
    offs = np.stack(np.meshgrid(*[np.arange(-a, a + 1) for a in k], indexing="ij"),
                    -1).reshape(-1, 3)
    base = np.floor(means / res)
    cells = (base[:, None, :] + offs[None]) + 0.5                   # (N, M, 3) in cells
    d = np.clip(means[:, None, :] / res, cells - 0.5, cells + 0.5) * res - means[:, None, :]
    try:
        inv = np.linalg.inv(covs)
    except np.linalg.LinAlgError:
        inv = np.linalg.pinv(covs)
    m2 = np.einsum("nmi,nij,nmj->nm", d, inv, d)
    inside = m2 <= sigmas ** 2
    inside[:, len(offs) // 2] = True                                   # the mean's own cell
    return cell_centres(cells[inside] * res, res)


def spans_cells(points, spans, res: float) -> np.ndarray:
    """:func:`surface_cells` for many segments at once."""
    pts = np.asarray(points, float).reshape(-1, 3)
    if not len(spans):
        return np.zeros((0, 3))
    sp = np.asarray(spans, int).reshape(-1, 2)
    a, b = pts[sp[:, 0]], pts[sp[:, 1]]
    n = np.maximum(2, np.ceil(np.linalg.norm(b - a, axis=1) / (res / 2)).astype(int) + 1)
    seg = np.repeat(np.arange(len(sp)), n)
    t = np.concatenate([np.linspace(0, 1, m) for m in n])
    samples = a[seg] + t[:, None] * (b - a)[seg]
    return cell_centres(samples, res)


def insert_look(tree: pyoctomap.OcTree, origin, points, covs=None, spans=(),
                max_range: float = -1.0) -> int:
    """One look as ONE update of each cell: sight lines free and end points
    occupied, then each further cell of the grown features and the surface
    spans occupied once (cells already hit by an end point are not hit again).
    Returns the number of occupied cells the look added beyond the end points."""
    res = tree.getResolution()
    pts = np.asarray(points, float).reshape(-1, 3)
    insert_rays(tree, pts, origin, max_range)
    extra = []
    if covs is not None:
        extra.append(features_cells(pts, covs, res))
    extra.append(spans_cells(pts, spans, res))
    cells = np.vstack(extra) if extra else np.zeros((0, 3))
    if not len(cells):
        return 0
    cells = cell_centres(cells, res)
    ends = pack(np.floor(pts / res))
    new = ~np.isin(pack(np.floor(cells / res)), ends)
    return mark_occupied(tree, cells[new])


def query(tree: pyoctomap.OcTree, point, free_looks: int = 1) -> int:
    """FREE, OCCUPIED, UNCERTAIN or UNKNOWN (never seen) at a room point."""
    node = tree.search(np.asarray(point, dtype=np.float64))
    if node is None:
        return UNKNOWN
    return _state(tree, node, free_below(free_looks))


def leaves(tree: pyoctomap.OcTree, bbx_min=None, bbx_max=None, free_looks: int = 1):
    """Every known leaf as ``(centre (N, 3), size (N,), state (N,))`` arrays —
    the pruned hierarchy, so a large uniform region is one big cell."""
    empty = np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.uint8)
    if tree.size() == 0:
        return empty
    centres, sizes, logodds = [], [], []
    for leaf in tree.begin_leafs():
        centres.append(leaf.getCoordinate())
        sizes.append(leaf.getSize())
        logodds.append(leaf.current_node.getLogOdds())
    if not centres:
        return empty
    c, s, lo = np.asarray(centres, float), np.asarray(sizes, float), np.asarray(logodds)
    if bbx_min is not None:
        keep = ((c + s[:, None] / 2 > np.asarray(bbx_min)) &
                (c - s[:, None] / 2 < np.asarray(bbx_max))).all(1)
        c, s, lo = c[keep], s[keep], lo[keep]
    state = classify(lo, tree.getOccupancyThresLog(), free_below(free_looks))
    return c, s, state


def logodds_at(tree: pyoctomap.OcTree, packed_keys: np.ndarray) -> np.ndarray:
    """The log-odds of the cells with the given packed keys (:func:`pack`),
    read from the tree (NaN for a cell not in it: unknown)."""
    res = tree.getResolution()
    centres = (unpack(packed_keys) + 0.5) * res
    out = np.full(len(centres), np.nan)
    search = tree.search
    for n, c in enumerate(centres):
        node = search(c)
        if node is not None:
            out[n] = node.getLogOdds()
    return out


def memory_bytes(tree: pyoctomap.OcTree) -> int:
    """OctoMap's own count of the tree's memory."""
    return int(tree.memoryUsage())


def sight_samples(origin, ends, res: float, stop_short, start_ft: float, begin_ft: float):
    """Samples half a cell apart along each sight line ``origin -> end``, from
    ``begin_ft`` to ``stop_short`` (default one cell) before the end; a line
    reaching no farther than ``start_ft`` has none.  ``(samples, their
    distances, samples per line)``, or None when there are none."""
    ends = np.asarray(ends, float).reshape(-1, 3)
    if not len(ends):
        return None
    stop = res if stop_short is None else stop_short
    origin = np.asarray(origin, float)
    d = ends - origin
    length = np.linalg.norm(d, axis=1)
    reach = np.maximum(length - stop - begin_ft, 0.0)
    n = np.where(length - stop > start_ft, np.floor(reach / (res / 2)).astype(int) + 1, 0)
    if n.sum() == 0:
        return None
    seg = np.repeat(np.arange(len(ends)), n)
    dist = begin_ft + np.concatenate([np.arange(m) for m in n]) * (res / 2)
    unit = d / np.maximum(length, 1e-12)[:, None]
    return origin + dist[:, None] * unit[seg], dist, n


def mark_free_rays(tree: pyoctomap.OcTree, origin, ends, stop_short: float | None = None,
                   start_ft: float = 0.0) -> int:
    """One miss for each cell along the sight lines ``origin -> end`` from
    ``start_ft`` on, stopping ``stop_short`` (default one cell) before each
    end; the ends are not hit.  Returns the number of cells."""
    res = tree.getResolution()
    along = sight_samples(origin, ends, res, stop_short, start_ft, start_ft)
    if along is None:
        return 0
    cells = cell_centres(along[0], res)
    tree.updateNodes(np.ascontiguousarray(cells), False)
    return len(cells)


def cell_keys(points, res: float) -> np.ndarray:
    """The packed keys (:func:`pack`) of the cells holding ``points``, one per point."""
    pts = np.asarray(points, float).reshape(-1, 3)
    return pack(np.floor(pts / res)) if len(pts) else np.zeros(0, np.int64)


def key_centres(packed_keys: np.ndarray, res: float) -> np.ndarray:
    """The centres of the cells of packed keys (:func:`cell_keys`)."""
    return (unpack(np.asarray(packed_keys, np.int64)) + 0.5) * res


def mark_assumed_free(tree: pyoctomap.OcTree, origin, ends, hit_keys, start_ft: float = 0.0,
                      stop_short: float | None = None, only_unknown: bool = True) -> int:
    """Sight lines free by ASSUMPTION (a column that shows nothing, see
    :func:`planner.perception.floor_scan`'s ``blank_ft``): weaker evidence
    than a hit, so each line stops short of the first cell whose packed key
    is in ``hit_keys`` (cells some look has hit, however carved since), and
    only cells not yet in the tree (unknown) get their miss; a seen cell keeps
    what the looks that saw it say.  Samples as :func:`mark_free_rays`, from
    ``start_ft`` on, ``stop_short`` (default one cell) before each end; a hit
    cell nearer than ``start_ft`` stops its line too.  Returns the number of
    cells marked."""
    keys = assumed_free_keys(tree, origin, ends, hit_keys, start_ft, stop_short, only_unknown)
    return mark_keys_free(tree, keys)


def mark_keys_free(tree: pyoctomap.OcTree, keys) -> int:
    """One miss for each packed cell key; returns how many."""
    keys = np.asarray(keys, np.int64)
    if len(keys):
        tree.updateNodes(np.ascontiguousarray((unpack(keys) + 0.5) * tree.getResolution()),
                         False)
    return len(keys)


def assumed_free_keys(tree: pyoctomap.OcTree, origin, ends, hit_keys, start_ft: float = 0.0,
                      stop_short: float | None = None, only_unknown: bool = True) -> np.ndarray:
    """The packed keys :func:`mark_assumed_free` would mark, without marking
    them (a caller that holds the assumption back until more evidence comes)."""
    res = tree.getResolution()
    none = np.zeros(0, np.int64)
    along = sight_samples(origin, ends, res, stop_short, start_ft, 0.0)
    if along is None:
        return none
    samples, dist, n = along
    keys = cell_keys(samples, res)
    hit = np.isin(keys, np.asarray(hit_keys, np.int64))
    # a sample is kept while no sample at or before it on its line is a hit cell
    m = n[n > 0]
    first = np.concatenate(([0], np.cumsum(m)[:-1]))
    run = np.cumsum(hit)
    base = np.repeat(run[first] - hit[first], m)
    keep = (run - base == 0) & (dist >= start_ft)
    keys = np.unique(keys[keep])
    if only_unknown and len(keys):
        keys = keys[np.isnan(logodds_at(tree, keys))]
    return keys.astype(np.int64)
