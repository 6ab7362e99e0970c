"""The joint filter's cost against the size of its state (model.joint).

The state is the floor pose and every feature, with one dense covariance, so one look's
update costs about n^2 m (n = 3 + 3 features, m = 3 x the look's used pairs) and the
memory n^2 doubles.  For each model size: the median time of one look (the odometry's
predict, 10 new features, 30 used pairs in one update; after one untimed look, as in a
walk) on synthetic features in front of the camera, by

* the plain steps (``JointFilter(reference=True)``: ``ekf_augment``, ``ekf_update_with_gain``,
  ``consider_joint_update``, each forming new n x n arrays) and the in-place working form
  (the default: preallocated state, syrk downdates), interleaved in one run;
* each without and with the consider covariance (``--consider bound``, the issue's target
  configuration; ``--consider joseph`` costs the same);
* beside the static per-feature update of the same 30 pairs (model.kalman.static_update,
  what --kalman a30/a29 does).

``--blas-threads N``: the joint filter's BLAS thread limit (model.joint.JOINT_BLAS_THREADS,
default 1; 0: no limit, OpenBLAS's own default).

Run:  python bench/joint.py [--sizes 100 300 600 1000] [--repeat 5] [--blas-threads 1]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import model.joint as joint  # noqa: E402
from model.joint import JointFilter, camera_point  # noqa: E402
from model.kalman import static_update  # noqa: E402

VARIANTS = {"plain": (True, None), "in place": (False, None),
            "plain + consider": (True, "bound"), "in place + consider": (False, "bound")}


def one_look_ms(n_features: int, repeat: int, pairs: int = 30, new: int = 10, seed: int = 1):
    """Median ms of one look for each of :data:`VARIANTS` (interleaved, the same looks), and
    of the static update of the same pairs."""
    rng = np.random.default_rng(seed)
    Cq = np.diag([0.2, 0.03, 0.03]) ** 2
    pts = np.column_stack([rng.uniform(-6, 6, n_features + new), rng.uniform(-1, 1, n_features + new),
                           rng.uniform(3, 15, n_features + new)])
    times = {name: [] for name in VARIANTS}
    static_t = []
    Ct = 2.0 * Cq
    for _ in range(repeat):
        seen = rng.choice(n_features, pairs, replace=False)
        for name, (reference, consider) in VARIANTS.items():
            jf = JointFilter((0.0, 0.0, 0.0), np.diag([0.01, 0.01, 1e-4]), consider=consider,
                             reference=reference)
            honest = [Ct] * n_features if consider else None
            jf.add_many([(k, camera_point((0.0, 0.0, 0.0), p), Cq)
                         for k, p in enumerate(pts[:n_features])], honest)
            # one look untimed first: a walk's looks reuse the state's buffers, already
            # touched (a fresh buffer's first use pays the page faults)
            jf.update([(int(k), camera_point((0.0, 0.0, 0.0), pts[k]), Cq) for k in seen[:5]],
                      16.27, [Ct] * 5 if consider else None)
            t0 = time.perf_counter()
            jf.predict((0.0, 0.05, 0.0), np.eye(3), np.diag([0.02, 0.02, 0.02]) ** 2)
            jf.add_many([(n_features + k, camera_point((0.0, 0.0, 0.0), p), Cq)
                         for k, p in enumerate(pts[n_features:])],
                        [Ct] * new if consider else None)
            jf.update([(int(k), camera_point((0.0, 0.0, 0.0), pts[k]), Cq) for k in seen], 16.27,
                      [Ct] * pairs if consider else None)
            times[name].append((time.perf_counter() - t0) * 1e3)
        means = np.array([jf.feature(int(k))[0] for k in seen])
        covs = np.array([jf.feature(int(k))[1] for k in seen])
        t0 = time.perf_counter()
        for m, c, k in zip(means, covs, seen):
            static_update(m, c, pts[k], Cq)
        static_t.append((time.perf_counter() - t0) * 1e3)
    return {name: float(np.median(t)) for name, t in times.items()}, float(np.median(static_t))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 600, 1000])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--blas-threads", type=int, default=joint.JOINT_BLAS_THREADS,
                    help="the joint filter's BLAS thread limit (0: none; default %(default)s)")
    args = ap.parse_args(argv)
    joint.JOINT_BLAS_THREADS = args.blas_threads or None
    print(f"# BLAS threads in the joint filter: {args.blas_threads or 'no limit'}; "
          f"load average {os.getloadavg()[0]:.1f}")
    print("| features in the state | state size n | covariance MB | joint look ms: plain / "
          "in place | ratio | with --consider bound: plain / in place | ratio | "
          "static update of the same 30 pairs ms |")
    print("|---|---|---|---|---|---|---|---|")
    for n in args.sizes:
        t, s = one_look_ms(n, args.repeat)
        size = 3 + 3 * (n + 10)
        print(f"| {n} | {size} | {size * size * 8 / 1e6:.1f} | {t['plain']:.1f} / "
              f"{t['in place']:.1f} | {t['plain'] / t['in place']:.1f} | "
              f"{t['plain + consider']:.1f} / {t['in place + consider']:.1f} | "
              f"{t['plain + consider'] / t['in place + consider']:.1f} | {s:.2f} |", flush=True)
    print(f"# load average {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
