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

from dataclasses import dataclass

import numpy as np
import pyoctomap

FREE, OCCUPIED, UNKNOWN = 0, 1, 2
STATE_NAMES = {FREE: "free", OCCUPIED: "occupied", UNKNOWN: "unknown"}


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


def new_octree(voi: VolumeOfInterest = VolumeOfInterest()) -> pyoctomap.OcTree:
    return pyoctomap.OcTree(voi.resolution)


def insert_rays(tree: pyoctomap.OcTree, points: np.ndarray, origin, max_range: float = -1.0
                ) -> None:
    """Free along each sight line ``origin -> point``, occupied at the point
    (OctoMap's ray casting; one probabilistic update per cell per batch)."""
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    if len(pts):
        tree.insertPointCloud(pts, np.asarray(origin, dtype=np.float64), max_range)


def insert_feature(tree: pyoctomap.OcTree, mean, cov, sigmas: float = 2.0) -> int:
    """A located feature grown by its covariance: every cell that reaches
    within ``sigmas`` standard deviations (the Mahalanobis distance of the
    cell's point nearest the mean) is marked occupied, and at least the cell of
    the mean.  Returns the cells marked."""
    mean = np.asarray(mean, dtype=np.float64)
    cov = np.asarray(cov, dtype=np.float64)
    res = tree.getResolution()
    half = sigmas * np.sqrt(np.clip(np.diag(cov), 0, None))
    lo = np.floor((mean - half) / res)
    hi = np.floor((mean + half) / res)
    axes = [(np.arange(a, b + 1) + 0.5) * res for a, b in zip(lo, hi)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    d = np.clip(mean, grid - res / 2, grid + res / 2) - mean
    try:
        inv = np.linalg.inv(cov)
        m2 = np.einsum("ni,ij,nj->n", d, inv, d)
        cells = grid[m2 <= sigmas ** 2]
    except np.linalg.LinAlgError:
        cells = grid[:0]
    cells = np.vstack([cells, ((np.floor(mean / res) + 0.5) * res)[None]])
    for c in cells:
        tree.updateNode(c, True)
    return len(cells)


def insert_surface(tree: pyoctomap.OcTree, a, b, c=None) -> int:
    """A surface spanned by boundary points: the segment ``a-b`` (two ends of a
    surface seen on one scan line) or the parallelogram ``a, b, c`` (corner
    ``a``, edges to ``b`` and ``c``), sampled at half the cell size and marked
    occupied.  Returns the number of samples."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    res = tree.getResolution()
    n1 = max(2, int(np.ceil(np.linalg.norm(b - a) / (res / 2))) + 1)
    s = np.linspace(0, 1, n1)
    pts = a + s[:, None] * (b - a)
    if c is not None:
        c = np.asarray(c, float)
        n2 = max(2, int(np.ceil(np.linalg.norm(c - a) / (res / 2))) + 1)
        t = np.linspace(0, 1, n2)
        pts = (pts[:, None, :] + t[None, :, None] * (c - a)).reshape(-1, 3)
    keys = np.unique(np.floor(pts / res), axis=0)
    for k in keys:
        tree.updateNode((k + 0.5) * res, True)
    return len(pts)


def query(tree: pyoctomap.OcTree, point) -> int:
    """FREE, OCCUPIED or UNKNOWN at a room point."""
    node = tree.search(np.asarray(point, dtype=np.float64))
    if node is None:
        return UNKNOWN
    return OCCUPIED if tree.isNodeOccupied(node) else FREE


def leaves(tree: pyoctomap.OcTree, bbx_min=None, bbx_max=None):
    """Every known leaf as ``(centre (3,), size, occupied)`` arrays — the pruned
    hierarchy, so a large uniform region is one big cell."""
    if tree.size() == 0:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0, bool)
    if bbx_min is None:
        it = tree.begin_leafs()
    else:
        it = tree.begin_leafs_bbx(np.asarray(bbx_min, float), np.asarray(bbx_max, float))
    centres, sizes, occ = [], [], []
    for leaf in it:
        centres.append(leaf.getCoordinate())
        sizes.append(leaf.getSize())
        occ.append(tree.isNodeOccupied(leaf))
    if not centres:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0, bool)
    return np.asarray(centres, float), np.asarray(sizes, float), np.asarray(occ, bool)


def memory_bytes(tree: pyoctomap.OcTree) -> int:
    """OctoMap's own count of the tree's memory."""
    return int(tree.memoryUsage())
