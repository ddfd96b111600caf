"""Readable DNF artefacts from one-class trees (issue #25): digits, slivers, the unsafe-share warning.

    python benchmarks/dnf_readable.py [--json benchmarks/results/dnf_readable.json]

Two data sets, each fitted twice in the same run with the default tree: ``readable=False`` (the
data's values as thresholds, every gap kept: the formula of the previous commit) and
``readable=True`` (the default now):

* ``toy``: the thesis' Fig. 4.1 experts (``tests/learners/trees/test_one_class_tree.py``), 20
  episodes, seeds 0-9;
* ``point-robot``: the user environment of ``tests/support/user_envs.py`` (``PointRobot``, wall at
  x = 0.5, the ``careful_expert`` that stops 0.12 short of it), 20 episodes of 40 steps simulated
  here with the same dynamics, seeds 0-9.

Per fit: conjunctions, the largest and mean number of significant digits of the thresholds, gaps
closed, the unsafe share of the data's bounding box (exact: the leaves are disjoint boxes), the
agreement of ``predict`` with the truth on a 201 x 201 grid of the bounding box, and whether the
formula keeps every demonstration point safe.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import warnings
from decimal import Decimal
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "learners" / "trees"))

from symlearn.learners.trees import OneClassTreeConstraint  # noqa: E402


def point_robot(seed: int, episodes: int = 20, wall: float = 0.5) -> np.ndarray:
    rng = np.random.default_rng(seed)
    points = []
    for _ in range(episodes):
        p = rng.uniform(-0.9, -0.5, size=2)
        points.append(p.copy())
        for _ in range(40):
            action = np.array([0.1 if p[0] < wall - 0.12 else 0.0, 0.05])
            p = np.clip(p + action, -1.0, 1.0)
            points.append(p.copy())
    return np.array(points)


def toy(seed: int) -> np.ndarray:
    from test_one_class_tree import toy_demonstrations

    return np.concatenate([np.asarray(t.states) for t in toy_demonstrations(seed=seed)])


def digits(value: float) -> int:
    return len(Decimal(repr(value)).normalize().as_tuple().digits) if value else 1


def measure(X: np.ndarray, truth, readable: bool) -> dict:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        learner = OneClassTreeConstraint(readable=readable).fit(X, ["x", "y"])
    values = [a.value for c in learner.dnf_ for a in c.atoms]
    lo, hi = np.asarray(learner.bounds_.lower), np.asarray(learner.bounds_.upper)
    axes = [np.linspace(lo[d], hi[d], 201) for d in range(2)]
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(2, -1).T
    agree = float((learner.predict(grid) == truth(grid)).mean())
    return {"conjunctions": len(learner.dnf_), "max_digits": max(map(digits, values)),
            "mean_digits": round(float(np.mean([digits(v) for v in values])), 2),
            "slivers_closed": learner.slivers_closed_, "unsafe_share": round(learner.unsafe_share_, 4),
            "truth_unsafe_share": round(float(truth(grid).mean()), 4), "grid_agreement": round(agree, 4),
            "demonstrations_safe": bool(not learner.predict(X).any()),
            "warnings": [str(w.message) for w in caught if issubclass(w.category, UserWarning)]}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    from test_one_class_tree import truly_unsafe

    sets = {"toy": (toy, truly_unsafe), "point-robot": (point_robot, lambda G: G[:, 0] > 0.5)}
    rows = []
    for name, (make, truth) in sets.items():
        for seed in range(10):
            X = make(seed)
            for readable in (False, True):
                row = {"data": name, "seed": seed, "readable": readable, **measure(X, truth, readable)}
                rows.append(row)
        for readable in (False, True):
            mine = [r for r in rows if r["data"] == name and r["readable"] == readable]
            print(f"{name:12s} readable={readable!s:5s}  conjunctions {np.mean([r['conjunctions'] for r in mine]):5.2f}  "
                  f"max digits {max(r['max_digits'] for r in mine):2d}  mean digits "
                  f"{np.mean([r['mean_digits'] for r in mine]):5.2f}  slivers {sum(r['slivers_closed'] for r in mine):2d}  "
                  f"unsafe share {np.mean([r['unsafe_share'] for r in mine]):.3f} (truth "
                  f"{np.mean([r['truth_unsafe_share'] for r in mine]):.3f})  grid agreement "
                  f"{np.mean([r['grid_agreement'] for r in mine]):.4f}  demos safe "
                  f"{all(r['demonstrations_safe'] for r in mine)}  warned {sum(bool(r['warnings']) for r in mine)}/10",
                  flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"python": platform.python_version(), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
