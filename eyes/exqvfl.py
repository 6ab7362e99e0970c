"""EXQVFL (EXQVFL.FR, Appendix F) for the eyes: the same feature lists as
:func:`nstar.exqvfl.exqvfl_kernel`, with the listing's labels turned into
plain loops.

The reference keeps one ``label`` variable and dispatches on it at every
pixel, as the listing reads; compiled, that dispatch and the sign calls are
most of its time.  Here each label is a loop of its own and control passes
between them only where the listing jumps:

* label 100 skips a flat run in one tight loop (no dispatch per flat pixel);
* label 110 (a gentle change waiting for its confirming step, one flat pixel
  tolerated) and label 120 (how far the slope runs; one small opposite or
  flat step survived) compare ``step * ISLP > 0`` instead of ``ISGN(step) ==
  ISLP`` (ISLP is never 0 there);
* label 120 starts with ``IVPRE = IPIX(IPRE)`` always (every way in leaves
  ``IVRE = IPIX(INEXT)``), so it reads pixels, not carried state;
* labels 200 (store, the three-pixel means), 300 (end of line) and 410 (merge
  touching narrow features) are the reference's, unchanged.

``tests/test_eyes_exqvfl.py`` checks it equals the reference (NFEAT, the
too-many exit and the whole IFEAT table, entries past NFEAT included) on
every row of the bundled and motorcycle pairs and on thousands of random
4-bit rows."""

from __future__ import annotations

import numpy as np

from diskfmt.jit import jit
from nstar.exqvfl import NFMAX, end_of_line_grey, suppress_overlaps


def new_work(npix: int = 128) -> np.ndarray:
    """Work space for :func:`exqvfl_fast` on lines of up to ``npix`` pixels:
    the steps, where the next non-zero step is, how long each run of one
    sign is (1-based, as the listing indexes)."""
    return np.zeros((3, npix + 2), dtype=np.int64)


@jit
def _mean_of(total, count):
    """:func:`nstar.exqvfl.mean_plus_half` for a ``count`` known where it is
    called (1, 2 or 3): the compiler then divides by a constant, by a
    multiply, instead of issuing a hardware division per feature."""
    if count == 2:
        return (2 * total + 2) // 4
    if count == 3:
        return (2 * total + 3) // 6
    return total


@jit
def line_transitions(ipix, ilast, work):
    """The per-line facts labels 100 and 120 need, in two branch-free passes:
    ``step[i] = IPIX(i+1) - IPIX(i)``; ``next_change[i]`` the first ``j >= i``
    with a non-zero step (``ILAST`` if none); ``run[i]`` how many steps of
    the sign of ``step[i]`` follow one another from ``i`` (0 on a flat)."""
    step = work[0]
    next_change = work[1]
    run = work[2]
    step[ilast] = 0
    next_change[ilast] = ilast
    run[ilast] = 0
    # carried in registers, not reloaded: each is a chain from the line's end
    sign_after = 0
    change_after = ilast
    run_after = 0
    for i in range(ilast - 1, 0, -1):
        d = ipix[i] - ipix[i - 1]
        step[i] = d
        sign = int(d > 0) - int(d < 0)          # int(): plain Python (RIG_NO_JIT) too
        moving = sign != 0
        change_after = i if moving else change_after
        run_after = (run_after + 1 if sign == sign_after else 1) if moving else 0
        next_change[i] = change_after
        run[i] = run_after
        sign_after = sign


@jit
def exqvfl_fast(ipix, ilast, ithr, ifeat, work):
    """EXQVFL(ILAST, IPIX, NFEAT, IFEAT, ITHR) as
    :func:`nstar.exqvfl.exqvfl_kernel` takes and returns it: ``ipix[k-1]`` is
    IPIX(k), ``ifeat`` the (4, 50) IFEAT table updated in place; returns
    ``(NFEAT, too_many)``.  ``work``: :func:`new_work` (at least ILAST + 2
    columns), overwritten."""
    line_transitions(ipix, ilast, work)
    step = work[0]
    next_change = work[1]
    run = work[2]
    jloc = 1
    ipre = 1
    nfeat = 0
    inum = 0
    iloc = 0
    ivpre = 0
    inext = 0
    islp = 1
    while True:
        # Label 100: start a new slope search; a flat run is skipped at once.
        at_end = False
        while True:
            iloc = next_change[ipre]
            ipre = iloc + 1
            if ipre > ilast:
                at_end = True
                break
            ichg = step[iloc]
            islp = 1 if ichg > 0 else -1
            inext = ipre
            if ichg > ithr or -ichg > ithr:
                break                                    # steep: GOTO 120
            # Label 110: gentle, wait for a step of the same sign; one flat allowed.
            ivpre = ipix[ipre - 1]
            ipass = 0
            confirmed = False
            while True:
                inext += 1
                if inext > ilast:
                    at_end = True
                    break
                idiff = ipix[inext - 1] - ivpre
                if idiff * islp > 0:
                    confirmed = True
                    break                                # GOTO 120
                if idiff != 0 or ipass == 1:
                    break                                # GOTO 100
                ipass = 1
            if at_end or confirmed:
                break
        if at_end:
            break                                        # label 300
        # Label 120: a valid slope; a run of steps of its sign is passed at once,
        # then one small opposite or flat step is survived if the slope resumes.
        ipre = inext
        while True:
            if step[ipre] * islp > 0:
                ipre += run[ipre]
            inext = ipre + 1
            if inext > ilast:
                break
            idiff = step[ipre]
            if idiff > ithr or -idiff > ithr:
                break
            inext += 1                                   # does the slope resume?
            if inext > ilast:
                break
            if (ipix[inext - 1] - ipix[ipre - 1]) * islp > 0:
                ipre = inext
                continue
            break
        ivpre = ipix[ipre - 1]
        # Label 200: store the feature.
        inum = iloc - jloc + 1
        if inum == 1:                    # the means with constant divisors (no division)
            ivave = ipix[jloc - 1]
            iv1 = ivave
        elif inum == 2:
            ivave = _mean_of(ipix[jloc - 1] + ipix[jloc], 2)
            iv1 = ivave
        elif inum == 3:
            ivave = _mean_of(ipix[jloc - 1] + ipix[jloc] + ipix[jloc + 1], 3)
            iv1 = ivave
        else:
            ivave = _mean_of(ipix[jloc - 1] + ipix[jloc] + ipix[jloc + 1], 3)
            iv1 = _mean_of(ipix[iloc - 1] + ipix[iloc - 2] + ipix[iloc - 3], 3)
        if nfeat >= NFMAX:                               # label 500
            return nfeat, True
        nfeat += 1
        ifeat[0, nfeat - 1] = iloc
        ifeat[1, nfeat - 1] = ipre
        ifeat[2, nfeat - 1] = iv1
        ifeat[3, nfeat - 1] = ivpre
        if nfeat > 1:
            ifeat[3, nfeat - 2] = ivave
        if inext > ilast:
            break                                        # label 300
        inext = ipre
        jloc = ipre

    # Label 300: end of the line.
    if nfeat <= 0:
        return nfeat, False
    end_of_line_grey(ipix, ilast, ifeat, nfeat, jloc, iloc, inum)
    # Label 410: suppress overlapping edge features (merge touching narrow ones).
    return suppress_overlaps(ifeat, nfeat), False
