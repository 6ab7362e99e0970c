"""The simulated world the robot walks through.

The 1985 laboratory is lost; the rig's bundled pair (``rig/scene.py``) is a synthetic lab seen
from one pose.  This package renders that lab, and seeded rooms like it, from any pose, with the
rig's camera geometry and PRE's condense, and keeps the truth of every look (pose, range per
pixel, the room's corners and vertical edges) so the model built from the rig's eyes can be
scored.  Modules:

* :mod:`world.pose` -- the rig's pose (position, heading, pitch, roll; equation A-21's full
  orientation) and its camera centres;
* :mod:`world.room` -- rooms: the bundled lab closed behind the start, and generated rooms;
* :mod:`world.render` -- a look: both cameras rendered, condensed, with truth and projection;
* :mod:`world.walk` -- the bundled walk, generated walks, walk CSV files;
* :mod:`world.odometry` -- dead reckoning with a documented noise model;
* :mod:`world.collide` -- a vehicle footprint against obstacles and walls.

See docs/world.md.
"""
