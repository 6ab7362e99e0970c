"""The planner: Chapter IV's volumetric model and path search, Chapter VI's floor map.

* :mod:`planner.octree` — the volumetric model (an OctoMap occupancy octree):
  occupied where features are, free along the sight lines to them, unknown
  elsewhere.
* :mod:`planner.floormap` — Chapter VI's 2-D floor map: the octree projected
  over the vehicle's height band; the true room's map at the same resolution.
* :mod:`planner.search` — the dissertation's hierarchical search (grow empty
  space from the vehicle over quadtree cells, larger cells nearer the goal
  first), the A* baseline over the same cells, the minimum-cross-section test.
* :mod:`planner.trajectory` — path optimisation under the vehicle model
  (skim walls, round corners) and the motion-command string.
* :mod:`planner.perception` — the look -> scan -> room points adapter of the
  closed loop.
"""
