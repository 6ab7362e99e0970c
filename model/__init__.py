"""The robot's model of its world (Chapter III and Appendix A, A-21..A-50).

The rig (``estar``) is the robot's eyes: it locates edges relative to the left
camera with error bounds (A-1..A-20).  This package is the half the
dissertation derived and never built:

* :mod:`model.geometry` — the camera state vector Y (A-21), the feature
  transformation P_i (A-22, A-23) and the camera-relative covariance carried
  into environment coordinates (A-31/A-32).
* :mod:`model.edges` — vertical edges grouped over consecutive scan lines and
  their end points as vertex observations, each with its A-19/A-20 covariance.
* :mod:`model.symbolic` — the symbolic model of Chapter III: vertices,
  boundary lines, surfaces ("Three Dimensional Models and Model Updates").
* :mod:`model.matching` — a look's features matched to the model (predict,
  gate by covariance, grey level, one-to-one): the "symbolic accuracy".
* :mod:`model.pose` — camera position estimation: A-48 as written with its
  covariance A-50, and the named alternatives beside it.
* :mod:`model.kalman` — the static Kalman update of a feature ("Stochastic
  Updates", MAYB 79), camera error ignored (A-30) or propagated (A-29).
* :mod:`model.velocity` — velocity from successive camera positions.
* :mod:`model.mapping` — the walk: look after look into one model.
* :mod:`model.scoring` — the world's truth against the model (wrong
  correspondences, feature errors, shares inside 2 sigma).
"""
