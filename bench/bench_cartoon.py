"""Benchmark: ``pre cartoon`` (the Queen Victoria production system, both
passes) on the bundled laboratory pictures.

The reference in the same run is the production system tried the plain way:
every rule, in list order, at every position (what ``rewrite`` did before it
indexed the rules by their first symbol).  Both must give the same picture;
the ratio is reported.

Run:  python bench/bench_cartoon.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from diskfmt.layouts import decode_bi           # noqa: E402
from pre import qv_production                    # noqa: E402
from pre.cartoon import cartoon                  # noqa: E402
from rig.scene import bundled_path               # noqa: E402


def plain_rewrite(syms, rules=qv_production.RULES, trace=None):
    s = list(syms)
    pos = 0
    while pos < len(s):
        for rule in rules:
            if qv_production.matches(rule, s, pos):
                s[pos:pos + len(rule.lhs)] = qv_production.apply_rule(rule, s, pos)
                if trace is not None:
                    trace.append(rule.rid)
                pos = max(0, pos - (qv_production._MAXLEN - 1))
                break
        else:
            pos += 1
    return s


def best_of(repeat, fn):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    for name in ("LAB-L.BI", "LAB-R.BI"):
        pic = decode_bi(bundled_path(name).read_bytes())
        fast, a = best_of(args.repeat, lambda: cartoon(pic))
        indexed = qv_production.rewrite
        qv_production.rewrite = plain_rewrite
        try:
            plain, b = best_of(1, lambda: cartoon(pic))
        finally:
            qv_production.rewrite = indexed
        same = (a.picture == b.picture).all()
        print(f"{name}: cartoon {fast * 1000:.0f} ms; plain rule-by-rule {plain * 1000:.0f} ms "
              f"({plain / fast:.0f}x); same picture: {'yes' if same else 'NO'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
