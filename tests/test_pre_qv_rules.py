"""The Queen Victoria production system (Chapter II): Table I, each of the 50
productions on a short symbol string, and whole lines reduced by hand."""

import pytest

from pre.qv_production import (RULES, RULE_BY_ID, Sym, apply_rule, classify, initial_symbols,
                               matches, qv_line, rewrite, symbols_text)


def _syms(text):
    """'S | G+ s G- | S' -> symbols; each symbol spans one pixel step, so the
    k-th symbol (1-based) covers pixels k..k+1; greys are the pixel numbers."""
    kinds = text.replace("|", " ").split()
    return [Sym(k, i + 1, i + 2, i + 1, i + 2) for i, k in enumerate(kinds)]


def _show(syms):
    return " ".join(f"{s.kind}[{s.start}-{s.stop}]" for s in syms)


# One line per production: the string (alpha | LHS | beta, the rule applied at
# the LHS) and the string after one application, intervals written by hand.
# alpha and beta are one S each: the context is carried over untouched.
PER_RULE = {
    "R1": ("S | s s | S", "S[1-2] S[2-4] S[4-5]"),
    "R2": ("S | G+ s G- | S", "S[1-2] G+[2-3] S[3-4] G-[4-5] S[5-6]"),
    "R3": ("S | G- s G+ | S", "S[1-2] G-[2-3] S[3-4] G+[4-5] S[5-6]"),
    "R4": ("G+ | S S | G-", "G+[1-2] S[2-4] G-[4-5]"),
    "R5": ("G+ | s S | G-", "G+[1-2] S[2-4] G-[4-5]"),
    "R6": ("G+ | S s | G-", "G+[1-2] S[2-4] G-[4-5]"),
    "R7": ("S | e- | S", "S[1-2] G-[2-3] S[3-4]"),
    "R8": ("S | e+ | S", "S[1-2] G+[2-3] S[3-4]"),
    "R9": ("S | G+ e+ | S", "S[1-2] G+[2-4] S[4-5]"),
    "R10": ("S | G- e- | S", "S[1-2] G-[2-4] S[4-5]"),
    "R11": ("S | G- G- | S", "S[1-2] G-[2-4] S[4-5]"),
    "R12": ("S | G+ G+ | S", "S[1-2] G+[2-4] S[4-5]"),
    "R13": ("S | G+ g+ G+ | S", "S[1-2] G+[2-5] S[5-6]"),
    "R14": ("S | G- g- G- | S", "S[1-2] G-[2-5] S[5-6]"),
    "R15": ("G+ | S g- G- | S", "G+[1-2] S[2-3] G-[3-5] S[5-6]"),
    "R16": ("G- | S g+ G+ | S", "G-[1-2] S[2-3] G+[3-5] S[5-6]"),
    "R17": ("S | G- g- S | G+", "S[1-2] G-[2-4] S[4-5] G+[5-6]"),
    "R18": ("S | G+ g+ S | G-", "S[1-2] G+[2-4] S[4-5] G-[5-6]"),
    "R19": ("S | G- g- G+ | S", "S[1-2] G-[2-4] G+[4-5] S[5-6]"),
    "R20": ("S | G+ g+ G- | S", "S[1-2] G+[2-4] G-[4-5] S[5-6]"),
    "R21": ("S | G+ g- G- | S", "S[1-2] G+[2-3] G-[3-5] S[5-6]"),
    "R22": ("S | G- g+ G+ | S", "S[1-2] G-[2-3] G+[3-5] S[5-6]"),
    "R23": ("G+ | s g- g+ | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R24": ("G+ | s g+ g- | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R25": ("G+ | g- g+ s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R26": ("G+ | g+ g- s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R27": ("G+ | S g- g+ | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R28": ("G+ | S g+ g- | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R29": ("G+ | g- g+ S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R30": ("G+ | g+ g- S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R31": ("S | G+ g- S | G-", "S[1-2] G+[2-3] S[3-5] G-[5-6]"),
    "R32": ("S | G- g+ S | G+", "S[1-2] G-[2-3] S[3-5] G+[5-6]"),
    "R33": ("G- | S g- G+ | S", "G-[1-2] S[2-4] G+[4-5] S[5-6]"),
    "R34": ("G+ | S g+ G- | S", "G+[1-2] S[2-4] G-[4-5] S[5-6]"),
    "R35": ("S | G+ g- G+ | S", "S[1-2] G+[2-5] S[5-6]"),
    "R36": ("S | G- g+ G- | S", "S[1-2] G-[2-5] S[5-6]"),
    "R37": ("G+ | s g- s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R38": ("G+ | s g+ s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R39": ("G+ | S g- S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R40": ("G+ | S g+ S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R41": ("G+ | S g- s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R42": ("G+ | S g+ s | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R43": ("G+ | s g- S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R44": ("G+ | s g+ S | G-", "G+[1-2] S[2-5] G-[5-6]"),
    "R45": ("S | G+ s G+ | S", "S[1-2] G+[2-5] S[5-6]"),
    "R46": ("S | G- s G- | S", "S[1-2] G-[2-5] S[5-6]"),
    "R47": ("S | g+ g+ | S", "S[1-2] G+[2-4] S[4-5]"),
    "R48": ("S | g- g- | S", "S[1-2] G-[2-4] S[4-5]"),
    "R49": ("S | G+ g+ | G-", "S[1-2] G+[2-4] G-[4-5]"),
    "R50": ("S | G- g- | G+", "S[1-2] G-[2-4] G+[4-5]"),
}


def test_fifty_rules_and_a_test_for_each():
    assert [r.rid for r in RULES] == [f"R{k}" for k in range(1, 51)]
    assert set(PER_RULE) == set(RULE_BY_ID)


@pytest.mark.parametrize("rid", [f"R{k}" for k in range(1, 51)])
def test_each_production_on_a_short_string(rid):
    text, expected = PER_RULE[rid]
    rule = RULE_BY_ID[rid]
    at = len(text.split("|")[0].split())
    assert tuple(text.split("|")[1].split()) == rule.lhs
    syms = _syms(text)
    assert matches(rule, syms, at)
    out = syms[:at] + apply_rule(rule, syms, at) + syms[at + len(rule.lhs):]
    assert _show(out) == expected


def test_no_two_productions_share_a_left_side():
    # The printed R21 (G+ g- G+ -> G+ G-) shares R35's left side with another
    # right side; the repaired set is deterministic.
    lhs = [r.lhs for r in RULES]
    assert len(set(lhs)) == len(lhs)


def test_productions_keep_edge_direction():
    # A rising edge is never made out of falling symbols only, and vice versa.
    for r in RULES:
        k = 0
        for kind, n in r.rhs:
            part = r.lhs[k:k + n]
            k += n
            if kind == "G+":
                assert any(s in ("G+", "e+", "g+") for s in part), r
                assert not any(s in ("G-", "e-") for s in part), r
            if kind == "G-":
                assert any(s in ("G-", "e-", "g-") for s in part), r
                assert not any(s in ("G+", "e+") for s in part), r


def test_merged_symbol_keeps_outer_greys():
    syms = [Sym("G+", 4, 6, 2, 9), Sym("g+", 6, 7, 9, 10), Sym("G+", 7, 9, 10, 14)]
    (new,) = apply_rule(RULE_BY_ID["R13"], syms, 0)
    assert new == Sym("G+", 4, 9, 2, 14)


@pytest.mark.parametrize("d,t,sym", [
    (-3, 2, "e-"), (-2, 2, "g-"), (-1, 2, "g-"), (0, 2, "s"), (1, 2, "g+"), (2, 2, "g+"),
    (3, 2, "e+"), (15, 2, "e+"), (-1, 0, "e-"), (1, 0, "e+"), (0, 0, "s")])
def test_table_i(d, t, sym):
    assert classify(d, t) == sym


def test_initial_symbols_carry_pixel_pairs():
    syms = initial_symbols([4, 4, 9, 8], 2)
    assert syms == [Sym("s", 1, 2, 4, 4), Sym("e+", 2, 3, 4, 9), Sym("g-", 3, 4, 9, 8)]


def _line(px, t=2):
    return [(s.kind, s.start, s.stop, s.left, s.right) for s in qv_line(px, t)]


def test_step_edge_line():
    # 3 3 3 3 12 12 12: s s s e+ s s -> S G+ S
    assert _line([3, 3, 3, 3, 12, 12, 12]) == [
        ("S", 1, 4, 3, 3), ("G+", 4, 5, 3, 12), ("S", 5, 7, 12, 12)]


def test_noise_spike_is_smoothed():
    # 5 5 6 5 5: s g+ g- s -> R24 (s g+ g- -> S), then R6 -> one S
    trace = []
    out = rewrite(initial_symbols([5, 5, 6, 5, 5], 2), trace=trace)
    assert symbols_text(out) == "S"
    assert trace[0] == "R24"
    assert (out[0].start, out[0].stop) == (1, 5)


def test_gentle_ramp_becomes_an_edge():
    # 2 2 4 6 8 8: s g+ g+ g+ s -> S G+ S (R47 then R49), the ramp 2..6 steps
    assert _line([2, 2, 4, 6, 8, 8]) == [
        ("S", 1, 2, 2, 2), ("G+", 2, 5, 2, 8), ("S", 5, 6, 8, 8)]


def test_ramp_with_a_flat_step_is_one_edge():
    # 1 5 5 9: e+ s e+ -> G+ s G+ -> R45 -> G+
    assert _line([1, 5, 5, 9]) == [("G+", 1, 4, 1, 9)]


def test_plateau_between_opposite_edges():
    # 1 9 9 1: e+ s e- -> G+ s G- -> R2 -> G+ S G-
    assert _line([1, 9, 9, 1]) == [("G+", 1, 2, 1, 9), ("S", 2, 3, 9, 9), ("G-", 3, 4, 9, 1)]


def test_line_ends_read_as_smooth():
    # a single flat step at the start: s e- ... the sentinel S takes it (R6)
    assert _line([7, 7, 1, 1]) == [("S", 1, 2, 7, 7), ("G-", 2, 3, 7, 1), ("S", 3, 4, 1, 1)]
    # a gentle step after an edge at the end of the line joins the edge (R49)
    assert _line([1, 1, 9, 10]) == [("S", 1, 2, 1, 1), ("G+", 2, 4, 1, 10)]


def test_only_terminals_remain_on_a_noisy_line():
    px = [3, 4, 3, 3, 2, 9, 10, 9, 9, 5, 4, 4, 5, 4, 12, 12, 11, 12, 1]
    out = qv_line(px, 2)
    assert all(s.kind in ("S", "G+", "G-") for s in out)
    # the intervals tile the line, neighbours sharing their boundary pixel
    assert out[0].start == 1 and out[-1].stop == len(px)
    assert all(a.stop == b.start for a, b in zip(out, out[1:]))


def test_every_rule_has_a_quirks_line():
    from pathlib import Path
    text = (Path(__file__).resolve().parents[1] / "QUIRKS.md").read_text()
    pre_section = text.split("## PRE", 1)[1]
    for r in RULES:
        assert f"\n| {r.rid} | " in pre_section, r.rid


def _rewrite_reference(syms, rules):
    """The productions as the module describes them, tried rule by rule at each
    position with no index (the plain form of qv_production.rewrite)."""
    from pre.qv_production import _MAXLEN, apply_rule, matches
    s = list(syms)
    pos = 0
    while pos < len(s):
        for rule in rules:
            if matches(rule, s, pos):
                s[pos:pos + len(rule.lhs)] = apply_rule(rule, s, pos)
                pos = max(0, pos - (_MAXLEN - 1))
                break
        else:
            pos += 1
    return s


def test_indexed_rewrite_equals_trying_every_rule_in_order():
    import random
    from pre.qv_production import EXTENDED_RULES, RULES, Sym, rewrite
    rng = random.Random(1985)
    kinds = ["e-", "g-", "s", "g+", "e+", "S", "G+", "G-"]
    for trial in range(80):
        n = rng.randint(1, 40)
        syms = [Sym(rng.choice(kinds), i + 1, i + 2, rng.randint(0, 15), rng.randint(0, 15))
                for i in range(n)]
        for rules in (RULES, EXTENDED_RULES):
            assert rewrite(syms, rules) == _rewrite_reference(syms, rules), trial
