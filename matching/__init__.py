"""The improved matcher: a verdict per located edge, "matched" with a
confidence or "no match", under constraints each switched on its own.

Never the default: ``estar --match improved`` and ``rig scan --match improved``
(``--match 1985``, today's behaviour, is the default and leaves POSIT.DT as it
is).  From Python::

    from matching import Constraints, match_lines
    verdicts = match_lines(scan_result.results, Constraints())    # the default five
    verdicts = match_lines(scan_result.results, Constraints.parse("all"))  # + readmit

or hand ESTAR a matcher: ``Eclipse(..., matcher=ImprovedMatcher())``.
"""

from .verdict import (CONSTRAINTS, Constraints, LineData, Params, Verdict, match_line,
                      match_lines)

__all__ = ["CONSTRAINTS", "Constraints", "LineData", "Params", "Verdict", "match_line",
           "match_lines"]
