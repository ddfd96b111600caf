"""Readable DNF artefacts from one-class trees (issue #25): digits, slivers, the unsafe-share warning.

    python benchmarks/dnf_readable.py [--json benchmarks/results/dnf_readable.json]

Three data sets, each fitted three ways in the same run with the default tree: ``readable=False``
(the data's values as thresholds, every gap kept), ``readable=True`` on the points alone
(``rounded``: fewest digits, gaps narrower than the bandwidth closed) and ``readable=True`` on the
demonstrations (``steps``, the default for demonstrations: gaps a demonstrated step crosses are
closed too):

* ``toy``: the thesis' Fig. 4.1 experts (``tests/learners/trees/test_one_class_tree.py``), 20
  episodes, seeds 0-9;
* ``point-robot``: the user environment of ``tests/support/user_envs.py`` (``PointRobot``, wall at
  x = 0.5, the ``careful_expert`` that stops 0.12 short of it), 20 episodes of 40 steps simulated
  here with the same dynamics, seeds 0-9;
* ``thermostat``: a room heated towards 26 degrees from 15-20 (1.5 degrees per step at most, heat
  loss towards an outside temperature drawn per episode in 0-10, noise 0.1), features the room
  and the outside temperature, 20 episodes of 60 steps; truly unsafe: above 28 degrees (outside the
  data's bounding box, so the truth forbids nothing inside it). The outside temperature is a
  setting of the episode, which the tree splits on.

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


def point_robot(seed: int, episodes: int = 20, wall: float = 0.5) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(episodes):
        p = rng.uniform(-0.9, -0.5, size=2)
        points = [p.copy()]
        for _ in range(40):
            action = np.array([0.1 if p[0] < wall - 0.12 else 0.0, 0.05])
            p = np.clip(p + action, -1.0, 1.0)
            points.append(p.copy())
        out.append(np.array(points))
    return out


def thermostat(seed: int, episodes: int = 20) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(episodes):
        temp, outside = rng.uniform(15, 20), rng.uniform(0, 10)
        points = [(temp, outside)]
        for _ in range(60):
            heat = float(np.clip((26.0 - temp) / 1.5, -1, 1))
            temp += 1.5 * heat - 0.05 * (temp - outside) + rng.normal(0, 0.1)
            points.append((temp, outside))
        out.append(np.array(points))
    return out


def toy(seed: int) -> list[np.ndarray]:
    from test_one_class_tree import toy_demonstrations

    return [np.asarray(t.states) for t in toy_demonstrations(seed=seed)]


def digits(value: float) -> int:
    return len(Decimal(repr(value)).normalize().as_tuple().digits) if value else 1


VARIANTS = ("before", "rounded", "steps")


def measure(episodes: list[np.ndarray], truth, variant: str) -> dict:
    from symlearn.data import Demonstrations, Trajectory

    X = np.concatenate(episodes)
    data = Demonstrations([Trajectory(states=list(e), actions=[0] * (len(e) - 1)) for e in episodes]) \
        if variant == "steps" else X
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        learner = OneClassTreeConstraint(readable=variant != "before").fit(data, ["x", "y"])
    values = [a.value for c in learner.dnf_ for a in c.atoms]
    lo, hi = np.asarray(learner.bounds_.lower), np.asarray(learner.bounds_.upper)
    axes = [np.linspace(lo[d], hi[d], 201) for d in range(2)]
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(2, -1).T
    agree = float((learner.predict(grid) == truth(grid)).mean())
    return {"conjunctions": len(learner.dnf_), "max_digits": max(map(digits, values)),
            "mean_digits": round(float(np.mean([digits(v) for v in values])), 2),
            "slivers_closed": learner.slivers_closed_, "slivers_crossed": learner.slivers_crossed_,
            "unsafe_share": round(learner.unsafe_share_, 4),
            "truth_unsafe_share": round(float(truth(grid).mean()), 4), "grid_agreement": round(agree, 4),
            "demonstrations_safe": bool(not learner.predict(X).any()),
            "warnings": [str(w.message) for w in caught if issubclass(w.category, UserWarning)]}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    from test_one_class_tree import truly_unsafe

    sets = {"toy": (toy, truly_unsafe), "point-robot": (point_robot, lambda G: G[:, 0] > 0.5),
            "thermostat": (thermostat, lambda G: G[:, 0] > 28.0)}
    rows = []
    for name, (make, truth) in sets.items():
        for seed in range(10):
            episodes = make(seed)
            for variant in VARIANTS:
                row = {"data": name, "seed": seed, "variant": variant, "readable": variant != "before",
                       **measure(episodes, truth, variant)}
                rows.append(row)
        for variant in VARIANTS:
            mine = [r for r in rows if r["data"] == name and r["variant"] == variant]
            print(f"{name:12s} {variant:8s}  conjunctions {np.mean([r['conjunctions'] for r in mine]):5.2f}  "
                  f"max digits {max(r['max_digits'] for r in mine):2d}  mean digits "
                  f"{np.mean([r['mean_digits'] for r in mine]):5.2f}  slivers {sum(r['slivers_closed'] for r in mine):2d} "
                  f"(crossed {sum(r['slivers_crossed'] for r in mine):2d})  "
                  f"unsafe share {np.mean([r['unsafe_share'] for r in mine]):.3f} (truth "
                  f"{np.mean([r['truth_unsafe_share'] for r in mine]):.3f})  grid agreement "
                  f"{np.mean([r['grid_agreement'] for r in mine]):.4f}  demos safe "
                  f"{all(r['demonstrations_safe'] for r in mine)}  warned {sum(bool(r['warnings']) for r in mine)}/10  "
                  f"setting warnings {sum(any('a setting of the episode' in w for w in r['warnings']) for r in mine)}/10",
                  flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"python": platform.python_version(), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
