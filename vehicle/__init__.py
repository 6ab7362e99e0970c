"""The vehicle: its profile, its motion-command language and a simulated vehicle.

* :mod:`vehicle.profile` — footprint, camera height, turning radius, step, the
  pan-tilt head (off by default).
* :mod:`vehicle.commands` — the motion-command language (Chapter IV: "the
  sequence of vehicle motions ... stored as the motion command string"), in the
  spirit of the HERO-1 and Stanford Cart: ``FORWARD ft``, ``TURN deg``,
  ``ARC radius deg``, ``PAN deg`` and ``TILT deg`` (a head, as the HERO-1's),
  ``STOP``; parser with clear errors.
* :mod:`vehicle.sim` — a simulated vehicle that executes a command string with
  odometry noise: the true pose and the dead-reckoned pose; its true footprint
  is checked against the true room by :mod:`world.collide`.
"""
