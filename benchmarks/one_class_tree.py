"""One-class decision tree: fit time on 10^5 x 20, the thesis toy, and the binned KDE.

    python benchmarks/one_class_tree.py [--quick] [--repeats 3] [--json benchmarks/results/one_class_tree.json]

* ``fit``: :class:`OneClassTreeConstraint` (defaults) on 10^5 points x 20 features -- five
  Gaussian clusters (sd 0.5, centres uniform in [0, 10]^20), one feature replaced by a discrete
  one (4 values), one by uniform noise on [0, 1] -- and on 10^5 x 20 uniform points; the
  median of ``--repeats`` fits, with the tree's leaves and the DNF's size. The peer, in the
  same run on the same data: scikit-learn's ``IsolationForest(n_estimators=100)`` fit (also a
  one-class tree model, not interpretable as a formula). Target: our fit <= 10 s.
* ``toy``: the thesis' Fig. 4.1 (experts along [0.1, 0.7] x [0.1, 0.3] then up
  [0.7, 0.9] x [0.1, 0.9]) for 10 seeds: leaves, whether the root splits on phi0 as in Fig. 4.2,
  the leaf boxes, and the share of a 201 x 201 grid of [0, 1]^2 that the DNF classifies like
  the true unsafe set.
* ``kde``: the node density estimate of the tree (histogram + FFT smoothing, reflected) for
  one feature of 10^5 points on 256 bins vs ``scipy.stats.gaussian_kde`` evaluated on the same
  256 points with the same bandwidth: time ratio and the largest difference away from the
  edges (relative to the peak).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "learners" / "trees"))

from symlearn.learners.trees import OneClassTreeConstraint, binned_kde  # noqa: E402


def mixture(n: int, k: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    centers = rng.uniform(0, 10, (5, k))
    X = centers[rng.integers(0, 5, n)] + rng.normal(0, 0.5, (n, k))
    X[:, 3] = rng.integers(0, 4, n)
    X[:, 7] = rng.uniform(0, 1, n)
    return X


def timed(fn, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def bench_fit(n: int, k: int, repeats: int) -> list[dict]:
    from sklearn.ensemble import IsolationForest

    rows = []
    for name, X in (("clusters", mixture(n, k)), ("uniform", np.random.default_rng(1).uniform(0, 1, (n, k)))):
        ours, learner = timed(lambda: OneClassTreeConstraint().fit(X), repeats)
        peer, _ = timed(lambda: IsolationForest(n_estimators=100, random_state=0).fit(X), repeats)
        metrics = learner.result_.metrics
        rows.append({"data": name, "n": n, "k": k, "fit_seconds": ours, "isolation_forest_seconds": peer,
                     "ratio_vs_isolation_forest": ours / peer, "n_leaves": metrics["n_leaves"],
                     "depth": metrics["depth"], "n_conjunctions": metrics["n_conjunctions"],
                     "n_atoms": metrics["n_atoms"], "timings": learner.result_.timings})
        print(f"fit {name:9s} {n} x {k}: ours {ours:.2f} s, IsolationForest {peer:.2f} s "
              f"(ratio {ours / peer:.2f}); {metrics['n_leaves']} leaves, depth {metrics['depth']}, "
              f"{metrics['n_conjunctions']} conjunctions")
    return rows


def bench_toy(seeds: int) -> list[dict]:
    from test_one_class_tree import grid, toy_demonstrations, truly_unsafe

    X = grid(0.0, 1.0, 201)
    rows = []
    for seed in range(seeds):
        learner = OneClassTreeConstraint().fit(toy_demonstrations(seed=seed), ["phi0", "phi1"])
        agree = float((learner.dnf_.evaluate(X, ["phi0", "phi1"]) == truly_unsafe(X)).mean())
        rows.append({"seed": seed, "n_leaves": learner.tree_.n_leaves,
                     "root_feature": learner.feature_names_[learner.tree_.root.feature]
                     if learner.tree_.root.feature is not None else None,
                     "boxes": [[list(b.lower), list(b.upper)] for b in learner.safe_boxes_],
                     "grid_agreement": agree})
        print(f"toy seed {seed}: {learner.tree_.n_leaves} leaves, root on {rows[-1]['root_feature']}, "
              f"grid agreement {agree:.4f}")
    return rows


def bench_kde(n: int, repeats: int) -> dict:
    from scipy.stats import gaussian_kde

    rng = np.random.default_rng(0)
    values = np.concatenate([rng.normal(0, 1, n // 2), rng.normal(6, 0.5, n - n // 2)])
    lo, hi, G, h = values.min(), values.max(), 256, 0.2

    def ours():
        counts = np.bincount(np.minimum(((values - lo) / (hi - lo) * G).astype(np.int64), G - 1), minlength=G)
        return binned_kde(counts[None].astype(float), h / (hi - lo) * G)[0]

    centers = lo + (np.arange(G) + 0.5) * (hi - lo) / G
    t_ours, density = timed(ours, repeats)
    t_scipy, theirs = timed(lambda: gaussian_kde(values, bw_method=h / values.std(ddof=1))(centers), repeats)
    density = density / (density.sum() * (hi - lo) / G)
    interior = (centers > lo + 4 * h) & (centers < hi - 4 * h)
    error = float(np.max(np.abs(density - theirs)[interior]) / theirs.max())
    print(f"kde {n} points, {G} bins: ours {t_ours * 1e3:.2f} ms, scipy gaussian_kde {t_scipy * 1e3:.1f} ms "
          f"(ratio {t_ours / t_scipy:.4f}); max interior difference {error:.4f} of the peak")
    return {"n": n, "bins": G, "ours_seconds": t_ours, "scipy_seconds": t_scipy, "ratio_vs_scipy": t_ours / t_scipy,
            "max_interior_difference_over_peak": error}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^4 points, 1 repeat, 3 toy seeds")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", type=Path, default=None, help="write the raw results here")
    args = parser.parse_args(argv)
    n = 10_000 if args.quick else 100_000
    repeats = 1 if args.quick else args.repeats
    machine = {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
               "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__}
    print(f"machine: {machine['processor']}, {machine['cpus']} cpus, python {machine['python']}, numpy {np.__version__}")
    results = {"command": "python benchmarks/one_class_tree.py " + " ".join(argv if argv is not None else sys.argv[1:]),
               "machine": machine, "fit": bench_fit(n, 20, repeats), "toy": bench_toy(3 if args.quick else 10),
               "kde": bench_kde(n, repeats)}
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=2) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
