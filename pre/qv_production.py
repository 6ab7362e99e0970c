"""The Queen Victoria algorithm as the production system of Chapter II (HOLT 85).

NSTAR runs a procedural version of the algorithm (EXQVFL, ``nstar/exqvfl.py``);
Chapter II describes the original form, which PRE's command 3 ("Cartoon the
image using horizontal and verical QV") needs and which the PRE listing leaves
empty:

1. the differences ``d_i = x_(i+1) - x_i`` of successive pixels are compared
   with the noise threshold T and mapped to the five *initial symbols* of
   Table I: ``e-`` (d < -T), ``g-`` (-T <= d < 0), ``s`` (d = 0), ``g+``
   (0 < d <= T), ``e+`` (T < d);
2. the production rules ``alpha X beta -> alpha Y beta`` are applied until no
   rule applies; what remains is a string of *terminal symbols*: ``S`` (smooth
   interval), ``G+`` (positive-going edge interval), ``G-`` (negative-going).

Every symbol carries its pixel interval and the grey levels at its two ends, so
the terminal string is the feature list of the line.  The rule list of the
dissertation is OCR text: :data:`RULES` is our reconstruction, each rule with
the text as read and what we run (QUIRKS.md, PRE section, R1-R50).

Reading of the notation (our decisions, QUIRKS.md P-lines):

* pixel indices are 1-based, as in EXQVFL: ``d_i`` covers pixels i and i+1, so
  neighbouring symbols share their boundary pixel;
* a rewrite replaces consecutive symbols by new ones; each new symbol is made of
  a consecutive group of the old ones (interval = from the first start to the
  last stop, left grey of the first, right grey of the last);
* rules are tried at the leftmost position first and, at one position, in the
  order of the list; after a rewrite the scan resumes two symbols to the left
  (a rule is at most three symbols long, so nothing further left can have
  changed);
* the two ends of the line read as smooth context: the string is bracketed by
  zero-width ``S`` sentinels, so "a flat step next to the end" or "a gentle
  step after an edge at the end of the line" reduce like their inner
  counterparts; the sentinels are dropped afterwards;
* an initial symbol that no rule can remove (a case the 50 rules do not cover)
  is finally read as the terminal it is closest to: ``s`` and ``g`` as ``S``,
  ``e`` as ``G`` (none of our test strings needs this; it is counted and
  reported).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

TERMINALS = ("S", "G+", "G-")
INITIALS = ("e-", "g-", "s", "g+", "e+")


@dataclass(frozen=True)
class Sym:
    """One symbol of the string: its kind, pixel interval (1-based, inclusive)
    and the grey levels at its left and right ends."""
    kind: str
    start: int
    stop: int
    left: int
    right: int

    @property
    def terminal(self) -> bool:
        return self.kind in TERMINALS


@dataclass(frozen=True)
class Rule:
    """``alpha LHS beta -> alpha RHS beta``.  ``rhs`` lists the new symbols as
    (kind, number of LHS symbols it is made of), in order."""
    rid: str
    group: str
    read: str          # the rule as the OCR text gives it
    lhs: tuple[str, ...]
    rhs: tuple[tuple[str, int], ...]
    note: str = ""     # "" = read as printed; else what was repaired / why

    def __str__(self) -> str:
        left = " ".join(self.lhs)
        right = " ".join(k for k, _ in self.rhs)
        return f"{self.rid}: a {left} b -> a {right} b"


def _r(rid, group, read, lhs, rhs, note=""):
    lhs_t = tuple(lhs.split())
    rhs_t = tuple((k, int(n)) for k, n in (p.split(":") for p in rhs.split()))
    assert sum(n for _, n in rhs_t) == len(lhs_t), rid
    return Rule(rid, group, read, lhs_t, rhs_t, note)


# The 50 productions of Chapter II, in the order of the text.  ``read`` is the
# OCR line (q and g are the same glyph to the scanner; '+' stands for '->'
# where the arrow was lost).  Groups follow the text's headings.
RULES: tuple[Rule, ...] = (
    # Simple productions - smooth interval generation
    _r("R1", "smooth interval generation", "a s s b + a S b", "s s", "S:2"),
    _r("R2", "smooth interval generation", "a G+ sG- b + a G+ SG- b", "G+ s G-", "G+:1 S:1 G-:1"),
    _r("R3", "smooth interval generation", "a G- sG+ b -> a G- SG+ b", "G- s G+", "G-:1 S:1 G+:1"),
    # Smooth interval continuation
    _r("R4", "smooth interval continuation", "a SS b -> a S b", "S S", "S:2"),
    _r("R5", "smooth interval continuation", "a sS b + a S b", "s S", "S:2"),
    _r("R6", "smooth interval continuation", "a SS b -> a S b", "S s", "S:2",
       "printed as a second `S S -> S` (R4); the mirror of R5 is missing without it"),
    # Edge interval continuation (R7, R8 generate edges from steep steps)
    _r("R7", "edge interval continuation", "a e- b -> a G- b", "e-", "G-:1"),
    _r("R8", "edge interval continuation", "a e+ b -> a G+ b", "e+", "G+:1"),
    _r("R9", "edge interval continuation", "a G+ e+ b -> a G+ b", "G+ e+", "G+:2"),
    _r("R10", "edge interval continuation", "a G- e- b -> a G- b", "G- e-", "G-:2"),
    _r("R11", "edge interval continuation", "a G- G- b -> a G- b", "G- G-", "G-:2"),
    _r("R12", "edge interval continuation", "a G+ G+ b + a G+ b", "G+ G+", "G+:2"),
    _r("R13", "edge interval continuation", "a G+ g+ G+ b -> a G+ b", "G+ g+ G+", "G+:3"),
    _r("R14", "edge interval continuation", "a G- g- G- b + a G- b", "G- g- G-", "G-:3"),
    _r("R15", "edge interval continuation", "a Sg- G- b -> a SG- b", "S g- G-", "S:1 G-:2"),
    _r("R16", "edge interval continuation", "a Sg+G+ b -> a SG+ b", "S g+ G+", "S:1 G+:2"),
    _r("R17", "edge interval continuation", "a G- g- S b -> a G- S b", "G- g- S", "G-:2 S:1"),
    _r("R18", "edge interval continuation", "a G+ q+ S b -> a G+ S b", "G+ g+ S", "G+:2 S:1"),
    _r("R19", "edge interval continuation", "a G- g- G+ b -> a G- G+ b", "G- g- G+", "G-:2 G+:1"),
    _r("R20", "edge interval continuation", "a G+ g+ G- b -> a G+ G- b", "G+ g+ G-", "G+:2 G-:1"),
    _r("R21", "edge interval continuation", "a G+ g- G+ b -> a G+ G- b", "G+ g- G-", "G+:1 G-:2",
       "printed `G+ g- G+ -> G+ G-`: turns a rising edge falling, and its left side is R35's; "
       "the missing mirror of R22 fits"),
    _r("R22", "edge interval continuation", "a G- g+ G+ b -> a G- G+ b", "G- g+ G+", "G-:1 G+:2"),
    # Edge interval generation from gentle steps: not in the OCR text (see R47-R50 below).
    # Noise suppression productions - smoothing noise spikes
    _r("R23", "smoothing noise spikes", "a sq- q+ b -> a S b", "s g- g+", "S:3"),
    _r("R24", "smoothing noise spikes", "a sq+ q- b -> a S b", "s g+ g-", "S:3"),
    _r("R25", "smoothing noise spikes", "a q- q+ s b + a S b", "g- g+ s", "S:3"),
    _r("R26", "smoothing noise spikes", "a q+ q- s b -> a S b", "g+ g- s", "S:3"),
    _r("R27", "smoothing noise spikes", "a Sg- g+ b -> a S b", "S g- g+", "S:3"),
    _r("R28", "smoothing noise spikes", "a Sg+ g- b -> a S b", "S g+ g-", "S:3"),
    _r("R29", "smoothing noise spikes", "a q- q+ S b -> a S b", "g- g+ S", "S:3"),
    _r("R30", "smoothing noise spikes", "a q+ q- S b -> a S b", "g+ g- S", "S:3"),
    _r("R31", "smoothing noise spikes", "a G+ q- S b -> a G+ S b", "G+ g- S", "G+:1 S:2"),
    _r("R32", "smoothing noise spikes", "a G-g+S b -> a G-S b", "G- g+ S", "G-:1 S:2"),
    _r("R33", "smoothing noise spikes", "a Sg- G+ b -> a SG+ b", "S g- G+", "S:2 G+:1"),
    _r("R34", "smoothing noise spikes", "a Sg+ G- b -> a SG- b", "S g+ G-", "S:2 G-:1"),
    _r("R35", "smoothing noise spikes", "a G+ g- G+ b -> a G+ b", "G+ g- G+", "G+:3"),
    _r("R36", "smoothing noise spikes", "a G- g+ G- b -> a G- b", "G- g+ G-", "G-:3"),
    # Ignoring gradual changes
    _r("R37", "ignoring gradual changes", "a sq- s b + a S b", "s g- s", "S:3"),
    _r("R38", "ignoring gradual changes", "a sg+ s b -> a S b", "s g+ s", "S:3"),
    _r("R39", "ignoring gradual changes", "a Sq- S b -> a S b", "S g- S", "S:3"),
    _r("R40", "ignoring gradual changes", "a Sq+ S b -> a S b", "S g+ S", "S:3"),
    _r("R41", "ignoring gradual changes", "a Sq- S b -> a S b", "S g- s", "S:3",
       "printed as a second `S g- S -> S` (R39); R42 is `S g+ s`, its mirror is missing without it"),
    _r("R42", "ignoring gradual changes", "a Sg+ s b + a S b", "S g+ s", "S:3"),
    _r("R43", "ignoring gradual changes", "a sg- S b -> a S b", "s g- S", "S:3"),
    _r("R44", "ignoring gradual changes", "a sg+ S b + a S b", "s g+ S", "S:3"),
    _r("R45", "ignoring gradual changes", "a G+ s G+ b -> a G+ b", "G+ s G+", "G+:3"),
    _r("R46", "ignoring gradual changes", "a G- s G- b -> a G- b", "G- s G-", "G-:3"),
    # Not in the OCR text: the four productions that make an edge out of gentle
    # steps of one sign (without them a slow ramp never becomes an edge).
    _r("R47", "edge interval generation (reconstructed)", "(not in the text)", "g+ g+", "G+:2",
       "reconstructed: a gentle step confirmed by a second one of the same sign is an edge "
       "(EXQVFL label 110 does the same)"),
    _r("R48", "edge interval generation (reconstructed)", "(not in the text)", "g- g-", "G-:2",
       "reconstructed: mirror of R47"),
    _r("R49", "edge interval generation (reconstructed)", "(not in the text)", "G+ g+", "G+:2",
       "reconstructed: a gentle step continues a rising edge (EXQVFL label 120 continues a "
       "slope on any step of its sign)"),
    _r("R50", "edge interval generation (reconstructed)", "(not in the text)", "G- g-", "G-:2",
       "reconstructed: mirror of R49"),
)

RULE_BY_ID = {r.rid: r for r in RULES}

# A named option, not the default: four productions beyond the fifty that let
# an edge pause for one flat step before a gentle step of its own sign (what
# EXQVFL's label 120 allows).  On the bundled laboratory pair they remove
# nearly all left-over initial symbols and most disagreements with EXQVFL
# (docs/pre.md).
EXTRA_RULES: tuple[Rule, ...] = (
    _r("X1", "flat pause in an edge (option)", "(not in the text)", "G+ s g+", "G+:3"),
    _r("X2", "flat pause in an edge (option)", "(not in the text)", "G- s g-", "G-:3"),
    _r("X3", "flat pause in an edge (option)", "(not in the text)", "g+ s G+", "G+:3"),
    _r("X4", "flat pause in an edge (option)", "(not in the text)", "g- s G-", "G-:3"),
)
EXTENDED_RULES = RULES + EXTRA_RULES


def rule_set(extended: bool = False) -> tuple[Rule, ...]:
    """The 50 productions (default) or the 50 plus the four X-rules."""
    return EXTENDED_RULES if extended else RULES


_MAXLEN = max(len(r.lhs) for r in EXTENDED_RULES)


# --- Table I -------------------------------------------------------------------

def classify(d: int, t: int) -> str:
    """Table I: the initial symbol of one pixel difference d against threshold T."""
    if d < -t:
        return "e-"
    if d < 0:
        return "g-"
    if d == 0:
        return "s"
    if d <= t:
        return "g+"
    return "e+"


def initial_symbols(pixels: Sequence[int], t: int) -> list[Sym]:
    """The string of initial symbols of a line: one per pair of neighbours,
    symbol i (1-based) covering pixels i and i+1."""
    px = [int(v) for v in pixels]
    return [Sym(classify(px[i + 1] - px[i], t), i + 1, i + 2, px[i], px[i + 1])
            for i in range(len(px) - 1)]


# --- rewriting -----------------------------------------------------------------

def _merge(kind: str, group: Sequence[Sym]) -> Sym:
    first, last = group[0], group[-1]
    return Sym(kind, first.start, last.stop, first.left, last.right)


def apply_rule(rule: Rule, syms: Sequence[Sym], at: int) -> list[Sym]:
    """The symbols that replace ``syms[at:at+len(lhs)]`` under ``rule``."""
    old = syms[at:at + len(rule.lhs)]
    new, k = [], 0
    for kind, n in rule.rhs:
        new.append(_merge(kind, old[k:k + n]))
        k += n
    return new


def matches(rule: Rule, syms: Sequence[Sym], at: int) -> bool:
    n = len(rule.lhs)
    if at + n > len(syms):
        return False
    return all(syms[at + j].kind == rule.lhs[j] for j in range(n))


def _by_first_symbol(rules: Sequence[Rule]) -> dict[str, list[tuple[int, tuple, Rule]]]:
    """The rules grouped by the first symbol of their left side, each group in
    list order, as (length, rest of the left side, rule): at one position only
    the group of the symbol there can match, and trying it in order is trying
    the whole list in order."""
    index: dict[str, list[tuple[int, tuple, Rule]]] = {}
    for rule in rules:
        if not 1 <= len(rule.lhs) <= 3:          # rewrite() compares at most three symbols
            raise ValueError(f"rule {rule.rid}: a left side of {len(rule.lhs)} symbols")
        index.setdefault(rule.lhs[0], []).append((len(rule.lhs), rule.lhs[1:], rule))
    return index


def rewrite(syms: Sequence[Sym], rules: Sequence[Rule] = RULES, trace=None) -> list[Sym]:
    """Apply the productions until none applies (leftmost position first, list
    order at one position).  ``trace`` (a list) receives the ids of the rules
    in the order they fired."""
    s = list(syms)
    kinds = [sym.kind for sym in s]          # kept beside s: matching reads only kinds
    index = _by_first_symbol(rules)
    back = _MAXLEN - 1
    pos = 0
    while pos < len(kinds):
        for n, rest, rule in index.get(kinds[pos], ()):
            if pos + n <= len(kinds) and (n == 1 or (kinds[pos + 1] == rest[0] and (
                    n == 2 or kinds[pos + 2] == rest[1]))):
                new = apply_rule(rule, s, pos)
                s[pos:pos + n] = new
                kinds[pos:pos + n] = [sym.kind for sym in new]
                if trace is not None:
                    trace.append(rule.rid)
                pos = pos - back if pos > back else 0
                break
        else:
            pos += 1
    return s


def _sentinel(at: int, grey: int) -> Sym:
    return Sym("S", at, at, grey, grey)


def finish(syms: Sequence[Sym]) -> list[Sym]:
    """Read initial symbols that no rule removed as their nearest terminal and
    merge neighbours of one kind (what R4, R11, R12 would do)."""
    out: list[Sym] = []
    for sym in syms:
        kind = sym.kind
        if kind in ("s", "g+", "g-"):
            kind = "S"
        elif kind in ("e+", "e-"):
            kind = "G" + kind[1]
        sym = Sym(kind, sym.start, sym.stop, sym.left, sym.right)
        if out and out[-1].kind == kind:
            out[-1] = _merge(kind, [out[-1], sym])
        else:
            out.append(sym)
    return out


def qv_line(pixels: Sequence[int], t: int, rules: Sequence[Rule] = RULES,
            stats: dict | None = None) -> list[Sym]:
    """The Queen Victoria production system on one line of pixels: Table I,
    then the productions, with the line's ends read as smooth context.
    Returns the terminal string (S, G+, G-), each with its pixel interval and
    end grey levels.  ``stats`` (a dict) counts rewrites and leftovers."""
    px = [int(v) for v in pixels]
    if len(px) < 2:
        return [Sym("S", 1, len(px), px[0], px[0])] if px else []
    body = initial_symbols(px, t)
    trace: list[str] = []
    s = rewrite([_sentinel(1, px[0])] + body + [_sentinel(len(px), px[-1])], rules, trace)
    # Drop the sentinels: a sentinel merged into a real S leaves the interval
    # unchanged (zero width); one left alone is removed.
    s = [sym for sym in s if not (sym.kind == "S" and sym.start == sym.stop)]
    left_over = sum(1 for sym in s if not sym.terminal)
    if stats is not None:
        stats["rewrites"] = stats.get("rewrites", 0) + len(trace)
        stats["leftover"] = stats.get("leftover", 0) + left_over
        for rid in trace:
            stats.setdefault("fired", {}).setdefault(rid, 0)
            stats["fired"][rid] += 1
    return finish(s)


def symbols_text(syms: Sequence[Sym]) -> str:
    """A terminal (or any) string written as its symbol names."""
    return " ".join(sym.kind for sym in syms)


def edge_intervals(syms: Sequence[Sym]) -> list[tuple[int, int, int, int]]:
    """The edge intervals (G+ and G-) of a terminal string as EXQVFL-style
    (start, stop, left grey, right grey), 1-based pixel indices."""
    return [(s.start, s.stop, s.left, s.right) for s in syms if s.kind in ("G+", "G-")]


def smooth_level(pixels: np.ndarray, sym: Sym) -> int:
    """The grey level of a smooth interval: the mean of its pixels, rounded
    half up (integer arithmetic, as the NOVA would)."""
    seg = np.asarray(pixels[sym.start - 1:sym.stop], dtype=np.int64)
    return int((2 * int(seg.sum()) + seg.size) // (2 * seg.size))
