"""ILP learner scaling: time vs number of examples and vs hypothesis-space size.

Compares the single-grounding path (constraints, one answer set per context: firing decided in
one grounding, selection as a clingo optimisation) with the general path (full ASP semantics:
one program over all positive examples, counterexample cuts for negatives), measured in the
same run on the same tasks. Both must return the same optimal score; the script checks it.

Task family: an agent picks a direction; walls and a one-way street are the hidden rules
(``:- go(V), wall(V).`` and ``:- go(west).``). Contexts hold the state-action pair as facts.
The space size is varied by the number of extra (irrelevant) feature predicates in the bias.

    .venv/bin/python benchmarks/ilp_scaling.py            # full: 10 .. 10 000 examples
    .venv/bin/python benchmarks/ilp_scaling.py --quick    # small sizes only
"""

from __future__ import annotations

import argparse
import json
import platform
import random
import sys
import time

from symlearn.logic.ilp import generate_space, learn, parse_task

DIRS = ("north", "south", "east", "west")


def make_task(n_examples: int, n_features: int = 0, seed: int = 0) -> str:
    rng = random.Random(seed)
    lines = ["dir(north;south;east;west)."]
    lines += [f"#constant(d, {d})." for d in DIRS]
    lines += ["#modeb(1, wall(var(d)), (positive)).", "#modeb(1, go(var(d)), (positive)).",
              "#modeb(1, go(const(d)), (positive)).", "#modeb(1, wall(const(d)), (positive)).", "#maxv(2)."]
    for k in range(n_features):
        lines.append(f"#modeb(1, f{k}(const(d)), (positive)).")
    for i in range(n_examples):
        walls = [d for d in DIRS if rng.random() < 0.4]
        features = [f"f{k}({rng.choice(DIRS)})." for k in range(n_features) if rng.random() < 0.5]
        go = rng.choice(DIRS)
        ok = go not in walls and go != "west"
        facts = " ".join([f"wall({w})." for w in walls] + features + [f"go({go})."])
        lines.append(f"#{'pos' if ok else 'neg'}(e{i}, {{}}, {{}}, {{ {facts} }}).")
    return "\n".join(lines)


def run(text: str, method: str, timeout: float) -> dict:
    task = parse_task(text, source="synthetic")
    start = time.perf_counter()
    result = learn(task, timeout=timeout, method=method)
    return {"seconds": round(time.perf_counter() - start, 3), "score": result.score, "optimal": result.optimal,
            "space": result.space_size}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--json", metavar="OUT", help="also write the measurements as JSON")
    args = parser.parse_args(argv)
    sizes = [10, 100, 1000] if args.quick else [10, 100, 1000, 10_000]
    general_max = 1000 if args.quick else 10_000
    features = [0, 2, 4] if args.quick else [0, 2, 4, 8, 16]
    print(f"command: {' '.join([sys.executable.split('/')[-1], *sys.argv])}")
    print(f"machine: {platform.machine()}, python {platform.python_version()}; single-threaded clingo")
    rows = {"examples": [], "space": []}
    print("\n## time vs number of examples (space fixed)")
    print(f"{'examples':>9} {'space':>6} {'single s':>9} {'general s':>10} {'ratio':>7}  score")
    for n in sizes:
        text = make_task(n)
        single = run(text, "single", args.timeout)
        general = run(text, "general", args.timeout) if n <= general_max else None
        ratio = (general["seconds"] / single["seconds"]) if general else None
        if general and general["optimal"] and single["optimal"]:
            assert general["score"] == single["score"], (single, general)
        rows["examples"].append({"examples": n, "single": single, "general": general})
        print(f"{n:>9} {single['space']:>6} {single['seconds']:>9.3f} "
              f"{(general['seconds'] if general else float('nan')):>10.3f} "
              f"{(ratio if ratio else float('nan')):>7.1f}  {single['score']}"
              + ("" if not general or general["optimal"] else "  (general: timeout)"))
    print("\n## time vs hypothesis-space size (200 examples)")
    print(f"{'features':>9} {'space':>6} {'single s':>9} {'general s':>10} {'ratio':>7}  score")
    for k in features:
        text = make_task(200, n_features=k, seed=1)
        size = len(generate_space(parse_task(text)))
        single = run(text, "single", args.timeout)
        general = run(text, "general", args.timeout)
        if general["optimal"] and single["optimal"]:
            assert general["score"] == single["score"], (single, general)
        ratio = general["seconds"] / single["seconds"]
        rows["space"].append({"features": k, "space": size, "single": single, "general": general})
        print(f"{k:>9} {size:>6} {single['seconds']:>9.3f} {general['seconds']:>10.3f} {ratio:>7.1f}  "
              f"{single['score']}" + ("" if general["optimal"] else "  (general: timeout)"))
    if args.json:
        from symlearn.atomic import write_text

        write_text(args.json, json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
