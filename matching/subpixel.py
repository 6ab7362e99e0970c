"""Sub-pixel edge positions from the grey profile of the .VD picture.

Table III's one-pixel granularity is the rig's error bound: an edge is the
index of a 128-px pixel, so a disparity is good to a pixel at best (EDISP =
ELMAX + ERMAX = 1).  The dissertation points at the remedy (Chapter III,
"Region Matching"): "if better matches are desired for location accuracy then
the actual pixels of the regions to be matched should be compared".  The
camera picture (.VD, 256x240) has twice the .BI's resolution; PRE's 2x2 shrink
makes .BI row IY of .VD rows 2*IY and 2*IY+1, and .BI column x (1-based) of
.VD columns 2x-2 and 2x-1.

A feature interval of EXQVFL is a grey step from its left grey to its right
grey; both its ends name the same step.  Its sub-pixel position is where the
mean of the two .VD rows crosses the level halfway between the two greys,
interpolated linearly between .VD pixel centres, searched over the .VD
columns the interval covers (one .BI pixel either side).  In the .BI's 1-based
index units the position is ``u/2 + 0.5`` for a crossing at continuous .VD
coordinate ``u`` (pixel k spans [k, k+1)), so that ``round(loc)`` names the
.BI pixel the step lies in.  No clean crossing (noise, a ramp without a
middle) keeps the integer location.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np


def line_profile(vd: np.ndarray, iyloc: int) -> np.ndarray:
    """The grey profile of .BI line IY in a 240x256 .VD picture: the mean of
    .VD rows 2*IY and 2*IY+1 (256 values)."""
    vd = np.asarray(vd, dtype=np.float64)
    return (vd[2 * iyloc] + vd[2 * iyloc + 1]) / 2.0


def step_position(profile: np.ndarray, start: int, stop: int, lgrey: float,
                  rgrey: float) -> float | None:
    """Sub-pixel position (1-based .BI units) of the step of feature interval
    ``start..stop`` (1-based .BI indices) from ``lgrey`` to ``rgrey``, or None."""
    if lgrey == rgrey:
        return None
    mid = (float(lgrey) + float(rgrey)) / 2.0
    lo = max(0, 2 * (start - 1) - 2)
    hi = min(len(profile) - 1, 2 * stop + 1)
    centre = (lo + hi + 1) / 2.0
    best = None
    for t in range(lo, hi):
        a, b = profile[t] - mid, profile[t + 1] - mid
        if a == 0 and b == 0:
            continue
        if (a <= 0 <= b or b <= 0 <= a) and a != b:
            u = t + 0.5 + (-a) / (b - a)
            if best is None or abs(u - centre) < abs(best - centre):
                best = u
    return None if best is None else best / 2.0 + 0.5


def refine_verdicts(verdicts, data, profiles, max_change: float | None = None) -> list:
    """Each matched verdict with ``loc1_sub``/``loc2_sub`` set from the step
    positions of its two features (the integer location where none is found).

    ``max_change`` (``Params.subpixel_max_change``; None: no limit): where the
    refined disparity differs from the integer one by more than this, the
    integer locations are kept.  The crossing is one per feature, so where one
    picture's ramp holds a second step (a box's side face only the right
    camera sees, generated room 4) the two crossings name different steps and
    the refined disparity moves by several pixels, off the integer one that
    was right."""
    prof1, prof2 = profiles
    out = []
    for v in verdicts:
        if not v.matched:
            out.append(v)
            continue
        f1 = data.features1[(v.edge - 1) % 50]
        f2 = data.features2[(v.partner - 1) % 50]
        s1 = step_position(prof1, *f1)
        s2 = step_position(prof2, *f2)
        if (s1 is None or s2 is None
                or (max_change is not None and abs((s1 - s2) - v.disparity) > max_change)):
            out.append(replace(v, loc1_sub=float(v.loc1), loc2_sub=float(v.loc2)))
        else:
            out.append(replace(v, loc1_sub=s1, loc2_sub=s2))
    return out


def subpixel_points(results, left_vd: np.ndarray, right_vd: np.ndarray,
                    max_change: float | None = 1.0, ds: float = 0.75,
                    dv: float = 180.0) -> list:
    """The located edges of a scan's line results (``estar.program.LineResult``s with an
    improved matcher's verdicts) at sub-pixel locations: each line's matched verdicts
    refined on the .VD pair ``left_vd``, ``right_vd`` (:func:`refine_verdicts`, at most
    ``max_change`` px off the integer disparity), each edge located by LCSL's equations in
    floating point there (:func:`matching.mode.located_points`; where no crossing is found,
    the integer location's).  The error bounds stay LCSL's for a one-pixel disparity
    error (EDISP = 1) at the refined disparity.  ``rig drive --disparity subpixel``:
    after a scan the drive has both cameras' .VD pictures, which ESTAR never sees.
    Returns ``rig.scan.Point``s, line by line, in the order LCSL located them."""
    from .mode import located_points
    out = []
    for r in results:
        if r.verdicts is None:
            raise ValueError(f"line {r.iyloc} has no verdicts: sub-pixel locations need "
                             "the improved matcher")
        profiles = (line_profile(left_vd, r.iyloc), line_profile(right_vd, r.iyloc))
        matched = [v for v in r.verdicts if v.matched]
        refined = refine_verdicts(matched, r, profiles, max_change)
        out += [p for p, _confidence in located_points(replace(r, verdicts=refined), ds, dv)]
    return out
