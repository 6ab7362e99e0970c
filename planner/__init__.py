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
* :mod:`planner.loop` — the closed loop: its configuration (``DriveConfig``),
  the cycle look -> scan -> model -> octree -> plan -> execute (``run``).
* :mod:`planner.perception` — a look's located points as a floor range scan;
  :mod:`planner.depth_eyes` the diagnostic oracle that sees every pixel's range.
* :mod:`planner.evidence` — each look into the octree and floor map
  (``Perception``).
* :mod:`planner.motion` — what the vehicle may drive on that map (never into
  space no look has shown free), and fetching evidence when it cannot move.
* :mod:`planner.planning` — from the floor map to a path and motion commands.
* :mod:`planner.appearance`, :mod:`planner.features` — the floor in the
  picture, and floor features fused look by look (named options).
"""
