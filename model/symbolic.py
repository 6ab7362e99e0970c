"""The symbolic model (Chapter III, "Three Dimensional Models and Model
Updates" and "The Symbolic Model").

The text lists three tables, linked to each other:

* **vertices** — "a location, a covariance matrix, and a pointer to each of
  the two boundary lines which meet there" (:class:`Vertex`);
* **boundary lines** — "straight line approximations ... characterized by
  center point for location, a pointer to the surface it bounds, a pointer to
  the next line in the boundary, and a pointer to each end point"
  (:class:`BoundaryLine`); here at least the vertical edges the rig locates,
  grouped over consecutive scan lines (:mod:`model.edges`);
* **surfaces** — "the surface center ..., a unit normal vector estimate ...,
  a radial shape bit map, the radial scale factor, a list of boundary edge
  pointers, and a set of grey level extremes" (:class:`Surface`).  The bit
  maps of Appendix B are filled by the radial-map code where it is present;
  until then they stay ``None``.

Room coordinates, feet (see :mod:`model.geometry`).  Every location enters
with the rig's camera-relative covariance (A-19/A-20) carried into room axes
(A-31/A-32) and is then improved by the static Kalman update
(:mod:`model.kalman`).  Features the robot has turned away from stay in the
tables: the model remembers.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Vertex:
    id: int
    mean: np.ndarray                 # room location (3,)
    cov: np.ndarray                  # 3x3
    kind: str                        # "top" / "bottom" end of a vertical boundary
    grey: tuple[int, int]            # grey levels left / right of its boundary
    lines: list[int] = field(default_factory=list)    # boundary lines meeting here
    looks: int = 1                   # looks it was seen in (and updated with)
    first_look: int = 0
    last_look: int = 0
    truth: np.ndarray | None = None  # the world's true location (scoring only)
    truth_id: int = -1               # index of the true corner, -1 none
    # where its first observation was: (col, row, scanned line, disparity) in the left picture
    # of its first look (scoring only: what the scorer's truth and bench/walk.py --outside read)
    seen_at: tuple | None = None
    shape: tuple | None = None       # Appendix B rectangular map of the corner, last seen
    # the consider covariance (model.kalman.consider_update): the covariance of ``mean`` under
    # the measured errors, reported and scored but never used for matching or the pose; None
    # unless the walk's ``consider`` option is on
    report_cov: np.ndarray | None = None
    contradicted: int = 0            # looks whose matched observation failed the feature gate
    missed: int = 0                  # looks that should have seen it, well inside the view, and did not
    # the normalised innovation squared (NIS) of every look fused into it, against the
    # covariances it reports (the consider covariances where kept, else the filter's): the
    # evidence of the variance factor and of confirmation (model.mapping), scoring only
    nis: list[float] = field(default_factory=list)


@dataclass
class BoundaryLine:
    id: int
    centre: np.ndarray               # room location of its middle
    centre_cov: np.ndarray
    ends: tuple[int | None, int | None]   # vertex ids (top, bottom); None = cut off
    end_points: np.ndarray           # (2,3) top and bottom end locations
    surface: int | None = None       # the surface it bounds
    next_line: int | None = None     # the next line in that surface's boundary
    grey: tuple[int, int] = (-1, -1)
    looks: int = 1


@dataclass
class Surface:
    id: int
    centre: np.ndarray
    normal: np.ndarray
    grey_extremes: tuple[int, int]
    lines: list[int] = field(default_factory=list)
    radial_map: list[int] | None = None        # Appendix B, 16 words, most ones first
    radial_scale: float | None = None
    orientation: int | None = None             # rotation index of the radial map
    rect_map: list[int] | None = None          # Appendix B 16x16 rectangular map


@dataclass
class SymbolicModel:
    vertices: dict[int, Vertex] = field(default_factory=dict)
    lines: dict[int, BoundaryLine] = field(default_factory=dict)
    surfaces: dict[int, Surface] = field(default_factory=dict)
    # vertices taken out of the model (contradicted by later looks: the walk's feature gate),
    # kept for scoring and the record; never matched again
    retired: dict[int, Vertex] = field(default_factory=dict)

    def add_vertex(self, mean, cov, kind, grey, look: int) -> Vertex:
        vid = len(self.vertices) + len(self.retired)
        v = Vertex(vid, np.asarray(mean, float), np.asarray(cov, float), kind,
                   tuple(int(g) for g in grey), first_look=look, last_look=look)
        self.vertices[vid] = v
        return v

    def add_line(self, centre, centre_cov, ends, end_points, grey) -> BoundaryLine:
        lid = len(self.lines)
        line = BoundaryLine(lid, np.asarray(centre, float), np.asarray(centre_cov, float),
                            tuple(ends), np.asarray(end_points, float),
                            grey=tuple(int(g) for g in grey))
        self.lines[lid] = line
        for vid in ends:
            if vid is not None:
                self.vertices[vid].lines.append(lid)
        return line

    def retire(self, vid: int) -> Vertex:
        """Take a vertex out of the model (into ``retired``); its boundary lines
        lose that end."""
        v = self.vertices.pop(vid)
        self.retired[vid] = v
        for lid in v.lines:
            line = self.lines.get(lid)
            if line is not None:
                line.ends = tuple(None if e == vid else e for e in line.ends)
        return v

    def refresh_line(self, line: BoundaryLine) -> None:
        """A line whose two ends are vertices takes its centre and end points
        from them (the vertices carry the updates)."""
        top, bottom = line.ends
        for k, vid in enumerate((top, bottom)):
            if vid is not None:
                line.end_points[k] = self.vertices[vid].mean
        if top is not None and bottom is not None:
            a, b = self.vertices[top], self.vertices[bottom]
            line.centre = (a.mean + b.mean) / 2
            line.centre_cov = (a.cov + b.cov) / 4

    def vertex_arrays(self):
        """ids (N,), means (N,3), covariances (N,3,3), kinds, greys (N,2)."""
        vs = list(self.vertices.values())
        if not vs:
            return (np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 3, 3)), [],
                    np.zeros((0, 2), int))
        return (np.array([v.id for v in vs]), np.array([v.mean for v in vs]),
                np.array([v.cov for v in vs]), [v.kind for v in vs],
                np.array([v.grey for v in vs]))

    def to_json(self) -> dict:
        """Everything, as plain JSON types."""
        def arr(a):
            return None if a is None else np.round(np.asarray(a, float), 6).tolist()
        return {
            "frame": "room: x right, y down, z forward from the start pose; feet",
            "vertices": [{"id": v.id, "mean": arr(v.mean), "cov": arr(v.cov), "kind": v.kind,
                          "grey": list(v.grey), "lines": v.lines, "looks": v.looks,
                          "first_look": v.first_look, "last_look": v.last_look,
                          "truth": arr(v.truth),
                          "shape": None if v.shape is None else list(v.shape),
                          "report_cov": arr(v.report_cov), "contradicted": v.contradicted,
                          "missed": v.missed, "nis": [round(float(x), 4) for x in v.nis]}
                         for v in self.vertices.values()],
            "retired_vertices": sorted(self.retired),
            "lines": [{"id": ln.id, "centre": arr(ln.centre), "centre_cov": arr(ln.centre_cov),
                       "ends": list(ln.ends), "end_points": arr(ln.end_points),
                       "surface": ln.surface, "next_line": ln.next_line,
                       "grey": list(ln.grey), "looks": ln.looks}
                      for ln in self.lines.values()],
            "surfaces": [{"id": s.id, "centre": arr(s.centre), "normal": arr(s.normal),
                          "grey_extremes": list(s.grey_extremes), "lines": s.lines,
                          "radial_map": s.radial_map, "radial_scale": s.radial_scale,
                          "orientation": s.orientation, "rect_map": s.rect_map}
                         for s in self.surfaces.values()],
        }


def ply_text(model: SymbolicModel) -> str:
    """ASCII PLY of the vertices with their covariance (six unique entries) and
    look count; CloudCompare shows ``scalar_*`` properties as fields."""
    names = ("cxx", "cxy", "cxz", "cyy", "cyz", "czz")
    head = ["ply", "format ascii 1.0",
            "comment Holten 1985 rig, the robot's symbolic model: vertices in room "
            "coordinates (x right, y down, z forward from the start), feet",
            f"element vertex {len(model.vertices)}",
            "property float x", "property float y", "property float z",
            *(f"property float scalar_{n}" for n in names),
            "property int scalar_looks", "property int id", "end_header"]
    rows = []
    for v in model.vertices.values():
        c = v.cov
        vals = (*v.mean, c[0, 0], c[0, 1], c[0, 2], c[1, 1], c[1, 2], c[2, 2])
        rows.append(" ".join(f"{x:.6g}" for x in vals) + f" {v.looks} {v.id}")
    return "\n".join(head + rows) + "\n"
