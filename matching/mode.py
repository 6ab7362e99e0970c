"""``--match 1985|improved``: the improved matcher inside ESTAR, and the flags.

:class:`ImprovedMatcher` is handed to ``estar.program.Eclipse(matcher=...)``.
After MASL has fetched the line's edge maps (the same NBLOB traffic as 1985),
LCLN asks it for the line's tables: one entry per matched edge (its partner,
cost, LOC1, LOC2) and none for a "no match", so LCSL writes POS(1,k) = -1
there and POSIT.DT carries only the edges the matcher vouches for.  With the
``neighbours`` constraint it also asks NSTAR for the slices and edge maps of
lines IY-1 and IY+1, with ``confirm`` (in the default five since 2026-12-01)
those of lines IY-22..IY+22 (three passes looking seven lines up and down,
each line's own verdict one more); all remembered, so a scan of consecutive
lines asks for each line about once more than 1985 did.  ``--match 1985``
(the default) hands ESTAR no matcher: the 1985 lists, byte for byte.

For other commands (``rig walk``): :func:`add_arguments` registers the same
flags; ``make_matcher(args.match, constraints_from_args(args))`` turns them
into a matcher (None for 1985) to hand to ``Eclipse(matcher=...)``;
:func:`located_points` gives each located edge with its confidence.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from .verdict import (CONSTRAINTS, Assignment, Constraints, LineData, Params, Verdict,
                      assignment_verdicts, confirm, line_assignment, line_candidates,
                      edge_columns, match_line, neighbour_lines, readmit, rematch_params,
                      rematches, shares_assignment)

MODES = ("1985", "improved")
MAX_CACHED_LINES = 24
# The default five: the four + confirm (since 2026-12-01; "order,lr,neighbours,region" before).
# readmit and subpixel: named, off (verdict.py).
DEFAULT_CONSTRAINTS = "order,lr,neighbours,region,confirm"


class VerdictTables:
    """The improved verdicts in the shape LCSL reads (``entries(edge)``)."""

    def __init__(self, verdicts: list[Verdict]):
        self._rows = {v.edge: [(v.partner, int(round(v.cost)), int(v.loc1), int(v.loc2))]
                      for v in verdicts if v.matched}

    def entries(self, edge: int) -> list[tuple[int, int, int, int]]:
        return self._rows.get(edge, [])


def _ifeat_columns(sl) -> np.ndarray:
    return np.asarray([sl.ifbuf[10 + 50 * j:60 + 50 * j] for j in range(4)], dtype=np.int64)


def fetch_line(eclipse, iyloc: int) -> LineData:
    """Slices and edge maps of line IY from NSTAR, through the Eclipse's link
    (CFEAT, then the NBLOB requests MASL would make), without touching ESTAR's
    COMMON blocks."""
    from estar.masl import masl_requests
    sl1, sl2 = eclipse.cfeat(iyloc)
    maps1 = np.zeros((100, 17), dtype=np.int64)
    maps2 = np.zeros((100, 17), dtype=np.int64)
    requests = np.zeros((200, 4), dtype=np.int64)
    n = masl_requests(sl1.nfeat, _ifeat_columns(sl1), sl2.nfeat, _ifeat_columns(sl2),
                      np.zeros(100, dtype=np.bool_), np.zeros(100, dtype=np.bool_), requests)
    eclipse.link.nblob_many(requests[:n], iyloc, maps1, maps2)
    eclipse.requests += int(n)
    return LineData(iyloc, sl1.features(), sl2.features(), maps1, maps2)


class ImprovedMatcher:
    """The improved mode for ESTAR's LCLN (see the module docstring).

    ``vd``: the (left, right) 240x256 .VD pictures, needed by the
    ``subpixel`` constraint (ESTAR itself never sees them)."""

    def __init__(self, constraints: Constraints = Constraints(), params: Params = Params(),
                 vd=None):
        if constraints.subpixel and vd is None:
            raise ValueError("the subpixel constraint needs the .VD pictures")
        self.constraints, self.params, self.vd = constraints, params, vd
        # The two passes' rules, made once (not per line): the first pass
        # without the neighbour constraint and the ambiguity rule, as match_lines.
        self._first_rules = (replace(constraints, neighbours=False, subpixel=False),
                             replace(params, min_confidence=0.0))
        self._second_constraints = replace(constraints, subpixel=False)
        self._lines: dict[int, LineData] = {}
        self._frame: dict[int, LineData] | None = None    # frame_verdicts' lines
        self._first: dict[int, list[Verdict]] = {}
        self._second: dict[int, list[Verdict]] = {}
        self._rounds: dict[tuple[int, int], list[Verdict]] = {}
        self._rematch: dict[int, list[Verdict]] = {}
        self._confirms: dict[tuple[int, int], tuple[list[Verdict], list]] = {}
        self._cands: dict = {}
        self._assigned: dict[int, Assignment] = {}
        self._max_lines = max(MAX_CACHED_LINES, 2 * _reach(constraints, params) + 4)
        self._rematches = rematches(constraints, params)
        self._shares_assignment = shares_assignment(constraints, params)
        # the rounds a line's entry may have in _rounds and _confirms
        self._round_keys = range(max(params.confirm_rounds, params.readmit_rounds) + 1)

    def tables_for(self, eclipse, iyloc, features1, features2, maps1, maps2):
        """LCLN's hook: (tables for LCSL, verdicts) of line IY."""
        data = LineData(iyloc, list(features1), list(features2), np.array(maps1),
                        np.array(maps2))
        self._remember(iyloc, data)
        verdicts = self._verdicts(eclipse, iyloc, data)
        if getattr(eclipse, "debug", 0) & 4:
            eclipse.listing.records(verdict_listing(verdicts, self.constraints))
        return VerdictTables(verdicts), verdicts

    def frame_verdicts(self, frame: list[LineData], lines) -> list[list[Verdict]]:
        """The verdicts of each of ``lines`` with every line's data given at
        once (``frame``: lines 0..119, as :func:`fetch_line` would get them;
        the eyes' compiled line source, :mod:`eyes.improved`) instead of asked
        for through ESTAR's link: the verdicts :meth:`tables_for` gives ESTAR
        line by line (tests/test_eyes_improved.py).  For one frame per matcher.
        Under the default rules :func:`matching.frame.frame_verdicts` makes the
        same verdicts compiled (tests/test_matching_frame.py); this is its
        reference and the form of every other choice."""
        self._frame = {d.iyloc: d for d in frame}
        self._max_lines = max(self._max_lines, len(frame))     # every line stays held
        return [self._verdicts(None, y, self._line(None, y)) for y in lines]

    def _verdicts(self, eclipse, iyloc: int, data: LineData) -> list[Verdict]:
        profiles = None
        if self.constraints.subpixel:
            from .subpixel import line_profile
            profiles = (line_profile(self.vd[0], iyloc), line_profile(self.vd[1], iyloc))
        again = rematches(self.constraints, self.params)
        if not self.constraints.readmit and not self.constraints.confirm and not again:
            verdicts = match_line(data, self.constraints, self.params,
                                  self._neighbours(eclipse, iyloc), profiles,
                                  self._candidates(eclipse, iyloc))
        else:
            rounds = self.params.readmit_rounds if self.constraints.readmit else 0
            verdicts = self._readmitted(eclipse, iyloc, rounds)
            if profiles is not None:
                from .subpixel import refine_verdicts
                verdicts = refine_verdicts(verdicts, data, profiles,
                                           self.params.subpixel_max_change)
        return verdicts

    def _remember(self, iyloc: int, data: LineData) -> None:
        if iyloc in self._lines and not _same(self._lines[iyloc], data):
            self._first.clear()                   # new pictures: forget the old verdicts
            self._second.clear()
            self._rounds.clear()
            self._rematch.clear()
            self._confirms.clear()
            self._cands.clear()
            self._assigned.clear()
        self._lines[iyloc] = data
        while len(self._lines) > self._max_lines:
            old = next(iter(self._lines))
            del self._lines[old]
            self._first.pop(old, None)
            self._second.pop(old, None)
            self._cands.pop(old, None)
            self._assigned.pop(old, None)
            self._rematch.pop(old, None)
            for r in self._round_keys:
                for cache in (self._rounds, self._confirms):
                    cache.pop((old, r), None)

    def _line(self, eclipse, y: int) -> LineData:
        if y not in self._lines:
            self._remember(y, self._frame[y] if self._frame is not None
                           else fetch_line(eclipse, y))
        else:                                     # least recently used leaves first
            self._lines[y] = self._lines.pop(y)
        return self._lines[y]

    def _candidates(self, eclipse, y: int):
        if y not in self._cands:
            self._cands[y] = line_candidates(self._line(eclipse, y), self.params)
        return self._cands[y]

    def _assignment(self, eclipse, y: int) -> Assignment:
        """Line y's assignment as the first pass makes it: the second pass
        shares it (unless ``neighbour_bonus``), and confirm weighs its
        candidates."""
        if y not in self._assigned:
            cands = self._candidates(eclipse, y)      # (line y is held while they are)
            self._assigned[y] = line_assignment(self._lines[y], cands, self._first_rules[0],
                                                self.params)
        return self._assigned[y]

    def _neighbours(self, eclipse, y: int) -> list[list[Verdict]]:
        if not self.constraints.neighbours:
            return []
        return [self._first_pass(eclipse, n) for n in neighbour_lines(y, self.params)
                if 0 <= n <= 119]

    def _first_pass(self, eclipse, y: int) -> list[Verdict]:
        """Line y's verdicts without the neighbour constraint (as match_lines)."""
        if y not in self._first:
            constraints, params = self._first_rules
            self._first[y] = assignment_verdicts(self._line(eclipse, y),
                                                 self._assignment(eclipse, y),
                                                 constraints, params)
        return self._first[y]

    def _readmitted(self, eclipse, y: int, rounds: int) -> list[Verdict]:
        """Line y's verdicts after ``rounds`` re-admission passes (as match_lines)."""
        if rounds == 0:
            return self._confirmed(eclipse, y, self.params.confirm_rounds
                                   if self.constraints.confirm else 0)
        key = (y, rounds)
        if key not in self._rounds:
            p = self.params
            self._rounds[key] = readmit(
                self._line(eclipse, y), self._readmitted(eclipse, y, rounds - 1),
                [self._readmitted(eclipse, n, rounds - 1)
                 for n in neighbour_lines(y, p, p.readmit_reach) if 0 <= n <= 119],
                p, self._candidates(eclipse, y))
        return self._rounds[key]

    def _confirmed(self, eclipse, y: int, rounds: int) -> list[Verdict]:
        """Line y's verdicts after ``rounds`` confirm passes (as match_lines)."""
        return self._confirmed_entry(eclipse, y, rounds)[0]

    def _confirmed_entry(self, eclipse, y: int, rounds: int) -> tuple[list[Verdict], tuple]:
        """(verdicts, their edge_columns) of line y after ``rounds`` confirm
        passes, round 0 included: each line's are read by the lines IY-7..IY+7
        in turn, so the matches are made once, with the verdicts."""
        key = (y, rounds)
        entry = self._confirms.get(key)
        if entry is not None:
            return entry
        if rounds == 0:
            verdicts = self._base(eclipse, y)
        else:
            p = self.params
            # Held here, not looked up after the recursion below: fetching the
            # lines IY-22..IY+22 may push line y's entries out of the caches.
            data = self._line(eclipse, y)
            judged = self._assignment(eclipse, y).judged
            before = self._confirmed(eclipse, y, rounds - 1)
            around = [self._confirmed_entry(eclipse, n, rounds - 1)
                      for n in neighbour_lines(y, p, p.confirm_reach) if 0 <= n <= 119]
            verdicts = confirm(data, before, [v for v, _ in around], p, judged,
                               columns=[m for _, m in around])
        entry = self._confirms[key] = (verdicts, edge_columns(verdicts))
        return entry

    def _base(self, eclipse, y: int) -> list[Verdict]:
        """Line y's verdicts before re-admission: the second pass, or with
        ``rematch_bonus`` the line assigned again (as match_lines)."""
        if not self._rematches:
            return self._second_pass(eclipse, y)
        if y not in self._rematch:
            p2 = rematch_params(self.params)
            self._rematch[y] = match_line(
                self._line(eclipse, y), self._second_constraints, p2,
                [self._second_pass(eclipse, n) for n in neighbour_lines(y, p2)
                 if 0 <= n <= 119], cands=self._candidates(eclipse, y))
        return self._rematch[y]

    def _second_pass(self, eclipse, y: int) -> list[Verdict]:
        """Line y's verdicts before re-admission (as match_lines)."""
        if y not in self._second:
            data = self._line(eclipse, y)
            neighbours = self._neighbours(eclipse, y)
            if self._shares_assignment:
                self._second[y] = assignment_verdicts(data, self._assignment(eclipse, y),
                                                      self._second_constraints, self.params,
                                                      neighbours)
            else:
                self._second[y] = match_line(data, self._second_constraints, self.params,
                                             neighbours, cands=self._candidates(eclipse, y))
        return self._second[y]


def _reach(constraints: Constraints, p: Params) -> int:
    """How many lines either side of IY a line's verdicts depend on."""
    reach = p.neighbour_reach if constraints.neighbours else 0
    if rematches(constraints, p):
        reach += p.readmit_reach
    if constraints.confirm:
        reach += p.confirm_reach * p.confirm_rounds
    if constraints.readmit:
        reach += p.readmit_reach * p.readmit_rounds
    return reach


def verdict_listing(verdicts: list[Verdict], constraints: Constraints) -> list[str]:
    """Debug flag 4 in the improved mode: after 1985's match lists (PMAL), the
    verdict of every edge (not a 1985 printout)."""
    out = ["", " Improved matcher (not 1985), constraints: "
           + (",".join(constraints.names()) or "none"),
           "  EDGE   X  PARTNER  LOC1  LOC2  DISP  CONF"]
    for v in verdicts:
        if v.matched:
            out.append(f" {v.edge:5d}{v.x:4d}{v.partner:9d}{v.loc1:6.0f}{v.loc2:6.0f}"
                       f"{v.disparity:6.0f}{v.confidence:6.2f}")
        else:
            out.append(f" {v.edge:5d}{v.x:4d}  no match ({v.reason})")
    return out + [""]


def _same(a: LineData, b: LineData) -> bool:
    return (a.features1 == b.features1 and a.features2 == b.features2
            and np.array_equal(a.maps1, b.maps1) and np.array_equal(a.maps2, b.maps2))


def make_matcher(mode: str = "1985", constraints: Constraints | str = DEFAULT_CONSTRAINTS,
                 params: Params = Params(), vd=None) -> ImprovedMatcher | None:
    """None for ``"1985"`` (ESTAR's own lists), else an :class:`ImprovedMatcher`."""
    if mode not in MODES:
        raise ValueError(f"--match {mode!r}: choose 1985 or improved")
    if mode == "1985":
        return None
    if isinstance(constraints, str):
        constraints = Constraints.parse(constraints)
    return ImprovedMatcher(constraints, params, vd)


def add_arguments(parser: argparse.ArgumentParser, subpixel: bool = True) -> None:
    """``--match`` and ``--constraints`` for a command that runs ESTAR."""
    names = [n for n in CONSTRAINTS if subpixel or n != "subpixel"]
    parser.add_argument("--match", choices=MODES, default="1985",
                        help="1985: the faithful MASL/LCSL matches (default, POSIT.DT as in "
                             "1985); improved (not 1985): a verdict per edge, matched with a "
                             "confidence or 'no match'")
    parser.add_argument("--constraints", default=None, metavar="LIST",
                        help="with --match improved: a comma list of " + ", ".join(names)
                             + ", or 'all' (" + ("all seven" if subpixel else "all six")
                             + ") or 'none' (default " + DEFAULT_CONSTRAINTS + ")")


def constraints_from_args(args, subpixel: bool = True) -> Constraints:
    """The parsed ``--constraints`` (``all`` includes subpixel only where
    available); refused without ``--match improved``."""
    if args.constraints is not None and getattr(args, "match", "improved") != "improved":
        raise ValueError("--constraints only applies with --match improved")
    text = (args.constraints or DEFAULT_CONSTRAINTS).strip().lower()
    c = Constraints.parse(text)
    if text == "all":
        c = replace(c, subpixel=subpixel)
    if c.subpixel and not subpixel:
        raise ValueError("--constraints subpixel needs the .VD pictures, which estar "
                         "never sees (use rig scan)")
    return c


def locate_float(loc1: float, loc2: float, iyloc: int, ds: float, dv: float):
    """LCSL's equations (3-1..3-6, Appendix A) in floating point for
    fractional locations: (dp, dx, dy, ep, ex, ey), or None when the disparity
    is not above EDISP = 1."""
    d = float(loc1) - float(loc2)
    if d <= 1.0:
        return None
    dp = ds * dv / d
    ep = ds * dv * 1.0 / (d * d - d)
    dl, dd = float(loc1) - 60.0, float(iyloc) - 60.0
    return (dp, dl * dp / dv, dd * dp / dv, ep,
            (abs(dl) * ep + dp * 0.5 + ep * 0.5) / dv,
            (abs(dd) * ep + dp * 0.5 + ep * 0.5) / dv)


def located_points(result, ds: float = 0.75, dv: float = 180.0):
    """The located edges of one LCLN done with an :class:`ImprovedMatcher`,
    each as ``(rig.scan.Point, confidence)``: the LCSL point of the edge, or,
    where the subpixel constraint gave fractional locations, the same
    equations in floating point at those locations."""
    from rig.scan import Point, points_of_line
    verdicts = {v.edge: v for v in (result.verdicts or []) if v.matched}
    out = []
    for p in points_of_line(result):
        v = verdicts.get(p.edge)
        if v is None:
            continue
        if v.loc1_sub is not None:
            pos = locate_float(v.loc1_sub, v.loc2_sub, result.iyloc, ds, dv)
            if pos is None:
                continue
            p = Point(p.line, p.edge, v.loc1_sub, v.loc2_sub, *pos)
        out.append((p, v.confidence))
    return out


def vouched_points(results, points, min_confidence: float) -> list:
    """Those of ``points`` (``rig.scan.Point``s of the line results ``results``,
    or the same edges with another range) whose edge's verdict is a match with a
    confidence of at least ``min_confidence``: ``rig drive --min-confidence``."""
    keep = {(r.iyloc, v.edge) for r in results for v in (r.verdicts or [])
            if v.matched and v.confidence >= min_confidence}
    return [p for p in points if (p.line, p.edge) in keep]
