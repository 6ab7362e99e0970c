"""The joint filter's cost against the size of its state (model.joint).

The state is the floor pose and every feature, with one dense covariance, so one look's
update costs about n^2 m (n = 3 + 3 features, m = 3 x the look's used pairs) and the
memory n^2 doubles.  For each model size: the median time of one look (the odometry's
predict, 10 new features, 30 used pairs in one update) on synthetic features in front
of the camera, beside the static per-feature update of the same 30 pairs
(model.kalman.static_update, what --kalman a30/a29 does) measured in the same run, and the
same look with the joint consider covariance (``--consider joseph``: a second dense covariance
through the same predict, augment and gains), interleaved.

Run:  python bench/joint.py [--sizes 100 300 600 1000] [--repeat 5]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from model.joint import JointFilter, camera_point  # noqa: E402
from model.kalman import static_update  # noqa: E402


def one_look_ms(n_features: int, repeat: int, pairs: int = 30, new: int = 10, seed: int = 1):
    rng = np.random.default_rng(seed)
    Cq = np.diag([0.2, 0.03, 0.03]) ** 2
    pts = np.column_stack([rng.uniform(-6, 6, n_features + new), rng.uniform(-1, 1, n_features + new),
                           rng.uniform(3, 15, n_features + new)])
    joint_t, static_t, consider_t = [], [], []
    Ct = 2.0 * Cq
    for _ in range(repeat):
        seen = rng.choice(n_features, pairs, replace=False)
        for consider, times in ((None, joint_t), ("joseph", consider_t)):
            jf = JointFilter((0.0, 0.0, 0.0), np.diag([0.01, 0.01, 1e-4]), consider=consider)
            honest = [Ct] * n_features if consider else None
            jf.add_many([(k, camera_point((0.0, 0.0, 0.0), p), Cq)
                         for k, p in enumerate(pts[:n_features])], honest)
            t0 = time.perf_counter()
            jf.predict((0.0, 0.05, 0.0), np.eye(3), np.diag([0.02, 0.02, 0.02]) ** 2)
            jf.add_many([(n_features + k, camera_point((0.0, 0.0, 0.0), p), Cq)
                         for k, p in enumerate(pts[n_features:])],
                        [Ct] * new if consider else None)
            jf.update([(int(k), camera_point((0.0, 0.0, 0.0), pts[k]), Cq) for k in seen], 16.27,
                      [Ct] * pairs if consider else None)
            times.append((time.perf_counter() - t0) * 1e3)
        means = np.array([jf.feature(int(k))[0] for k in seen])
        covs = np.array([jf.feature(int(k))[1] for k in seen])
        t0 = time.perf_counter()
        for m, c, k in zip(means, covs, seen):
            static_update(m, c, pts[k], Cq)
        static_t.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(joint_t)), float(np.median(static_t)), float(np.median(consider_t))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 600, 1000])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    print("| features in the state | state size n | covariance MB | joint look ms | "
          "static update of the same 30 pairs ms | ratio | joint look with --consider joseph "
          "ms | consider / plain |")
    print("|---|---|---|---|---|---|---|---|")
    for n in args.sizes:
        j, s, c = one_look_ms(n, args.repeat)
        size = 3 + 3 * (n + 10)
        print(f"| {n} | {size} | {size * size * 8 / 1e6:.1f} | {j:.1f} | {s:.2f} | {j / s:.0f} "
              f"| {c:.1f} | {c / j:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
