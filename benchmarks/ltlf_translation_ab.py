"""Before/after timing of LTLf -> DFA and of guard/automaton algebra in two source trees.

Runs the same workload alternately in a child process per tree (``--rounds`` times each, so load
on the machine hits both alike) and compares per-formula best times:

* ``translate``: :func:`symlearn.logic.ltlf.translate` on every formula of the LTLf -> DFA
  benchmark families (benchmarks/ltlf_to_dfa.py, full size, plus the 201 formulas of the public
  LTLf learning benchmark);
* ``to DFA``: the same, up to a :class:`~symlearn.logic.automata.DFA` (trees where ``translate``
  returned a separate table class call its ``to_dfa()``);
* ``guard ops``: 3000 random guards of 5 operations over 6 propositions, then evaluated;
* ``DFA ops``: products, minimisation and equivalence of 12 translated Dwyer patterns, pairwise;
* ``tlsf`` (with ``--tlsf-list FILE``, one basic TLSF path per line, e.g. files of SYNTCOMP's
  ``tlsf-fin``): ``translate`` on each file's formula, best of 3, and its state count, which must
  agree between the trees.

Make the "before" tree from a commit without touching the working copy, e.g.::

    mkdir -p /tmp/ab/before && git archive HEAD symlearn grammars | tar -x -C /tmp/ab/before
    .venv/bin/python benchmarks/ltlf_translation_ab.py /tmp/ab/before . --rounds 5
"""

from __future__ import annotations

import argparse
import json
import random
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve()


def best(fn, repeat: int) -> float:
    result = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        result = min(result, time.perf_counter() - start)
    return result


def measure(tree: Path, tlsf: list[str]) -> dict:
    """The workload in ``tree`` (run in a child process whose sys.path starts with it)."""
    sys.path.insert(0, str(tree))
    import symlearn
    from symlearn.logic.guards import Guard
    from symlearn.logic.ltlf import parse, translate

    # the family generators of this checkout (imported after symlearn: it puts its own tree first)
    sys.path.insert(1, str(HERE.parent))
    import ltlf_to_dfa as bench

    assert Path(symlearn.__file__).resolve().is_relative_to(tree.resolve()), symlearn.__file__
    families = [bench.conjunctions_of_f(8), bench.chains_of_t(10), bench.task_templates(6), bench.DWYER,
                bench.random_family([5, 10, 15, 20, 25, 30], 8, seed=2026)]
    formulas = [parse(t) for family in families for t in family]
    lines = [line.strip() for line in bench.FORMULAS_TXT.read_text().splitlines() if line.strip()]
    formulas += [parse(t, "spot") for t in lines]

    def as_dfa(f):
        result = translate(f, max_states=500_000)
        return result if hasattr(result, "minimize") else result.to_dfa()

    out = {"tree": str(tree), "sizes": [len(f) for f in families] + [len(lines)]}
    out["translate_s"] = [best(lambda f=f: translate(f, max_states=500_000), 5) for f in formulas]
    out["to_dfa_s"] = [best(lambda f=f: as_dfa(f), 5) for f in formulas]

    rng = random.Random(1)
    names = [f"p{i}" for i in range(6)]

    def guard_work():
        made = []
        for _ in range(3000):
            g = Guard.var(rng.choice(names))
            for _ in range(4):
                h = Guard.var(rng.choice(names))
                g = rng.choice([g & h, g | h, g & ~h, ~g | h])
            made.append(g)
        return sum(g.evaluate({"p1", "p3"}) for g in made)

    dfas = [as_dfa(parse(t)) for t in bench.DWYER[:12]]

    def dfa_work():
        for i, first in enumerate(dfas):
            for second in dfas[i + 1:]:
                first.product(second, "and").minimize()
                first.equivalent(second)

    out["guard_ops_s"] = best(guard_work, 7)
    out["dfa_ops_s"] = best(dfa_work, 7)
    if tlsf:
        from symlearn.logic.ltlf.tlsf import load_tlsf

        specs = [load_tlsf(path).formula for path in tlsf]
        out["tlsf_s"] = [best(lambda f=f: translate(f, max_states=500_000), 3) for f in specs]
        out["tlsf_states"] = [translate(f, max_states=500_000).n_states for f in specs]
    return out


def summarise(before: list[dict], after: list[dict]) -> list[str]:
    def per_formula(runs, key):
        return [min(r[key][i] for r in runs) for i in range(len(runs[0][key]))]

    lines = []
    for key, label in (("translate_s", "translate"), ("to_dfa_s", "to DFA")):
        a, b = per_formula(before, key), per_formula(after, key)
        lines.append(f"{label:9s}: total {sum(a) * 1000:7.1f} -> {sum(b) * 1000:7.1f} ms, ratio after/before "
                     f"{sum(b) / sum(a):.3f}; per-formula median ratio {statistics.median(y / x for x, y in zip(a, b)):.3f}")
    a, a_dfa, b = per_formula(before, "translate_s"), per_formula(before, "to_dfa_s"), per_formula(after, "translate_s")
    start = 0
    names = ["conjunctions of n F", "chains of n T", "task templates", "Dwyer patterns", "random", "LTLf benchmark"]
    for name, n in zip(names, before[0]["sizes"]):
        part = slice(start, start + n)
        lines.append(f"   {name:20s} {n:4d}: translate after/before {sum(b[part]) / sum(a[part]):.2f}, "
                     f"after translate / before translate+to_dfa {sum(b[part]) / sum(a_dfa[part]):.2f}")
        start += n
    for key, label in (("guard_ops_s", "guard ops"), ("dfa_ops_s", "DFA ops")):
        x, y = min(r[key] for r in before), min(r[key] for r in after)
        lines.append(f"{label:9s}: {x * 1000:.1f} -> {y * 1000:.1f} ms, ratio after/before {y / x:.3f}")
    if "tlsf_s" in before[0]:
        if before[0]["tlsf_states"] != after[0]["tlsf_states"]:
            lines.append("tlsf     : STATE COUNTS DIFFER " + str([(i, x, y) for i, (x, y) in enumerate(
                zip(before[0]["tlsf_states"], after[0]["tlsf_states"])) if x != y]))
        a, b = per_formula(before, "tlsf_s"), per_formula(after, "tlsf_s")
        lines.append(f"tlsf     : {len(a)} files, total {sum(a) * 1000:.1f} -> {sum(b) * 1000:.1f} ms, ratio "
                     f"{sum(b) / sum(a):.3f}; per-file median ratio {statistics.median(y / x for x, y in zip(a, b)):.3f}")
        for path, x, y in zip(before[0]["tlsf"], a, b):
            lines.append(f"   {path[-58:]:58s} {x * 1000:9.1f} -> {y * 1000:9.1f} ms  ({y / x:.2f})")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", type=Path, nargs="?", help="source tree holding symlearn/ before the change")
    parser.add_argument("after", type=Path, nargs="?", help="source tree after the change")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--json", type=Path, help="also write every measurement to this JSON file")
    parser.add_argument("--tlsf-list", type=Path, help="also time these basic TLSF files (one path per line)")
    parser.add_argument("--measure", type=Path, help=argparse.SUPPRESS)  # child process: one tree
    args = parser.parse_args()
    tlsf = [line.strip() for line in args.tlsf_list.read_text().splitlines() if line.strip()] if args.tlsf_list else []
    if args.measure:
        print(json.dumps({**measure(args.measure, tlsf), "tlsf": tlsf}))
        return
    if args.before is None or args.after is None:
        parser.error("give the two source trees")
    runs: dict[str, list[dict]] = {"before": [], "after": []}
    for _ in range(args.rounds):
        for side, tree in (("before", args.before), ("after", args.after)):
            extra = ["--tlsf-list", str(args.tlsf_list)] if args.tlsf_list else []
            done = subprocess.run([sys.executable, str(HERE), "--measure", str(tree.resolve()), *extra],
                                  capture_output=True, text=True, check=True)
            runs[side].append(json.loads(done.stdout))
    print(f"# {' '.join(sys.argv)}")
    print("\n".join(summarise(runs["before"], runs["after"])))
    if args.json:
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), **runs}) + "\n")


if __name__ == "__main__":
    main()
