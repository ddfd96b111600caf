"""The LTL learners' specialised evaluators versus the core's vectorised evaluator, in one run.

Two learners score many candidate formulas on one fixed set of traces and keep their own
evaluators; this script measures what they would cost with the core's
:func:`symlearn.logic.ltlf.vectorized.evaluate` instead, and checks that both give the same
verdicts.

1. ``ltl_bitsets`` (separating formulas, ``learn_ltl``): every formula of size <= 4 (quick: 3)
   over the propositions of one of the largest benchmark samples and the operators ``! X F G &
   | -> U``, the first levels of the enumeration. The learner needs each candidate's truth values at *every* position of every
   trace (to deduplicate candidates and to build larger ones), not only its verdict.

   * ``bitsets``: operand words stacked, one :func:`ltl_bitsets.apply` per operator and level;
   * ``core kernels``: the core's bool ``[trace, step]`` representation and its private
     temporal kernels, batched the same way (all candidates of one operator in one call);
   * ``core evaluate``: :func:`vectorized.evaluate` once per formula (verdicts only: less than
     the learner needs, so a lower bound on what this path would cost).

2. ``spec_templates`` (task specifications from demonstrations): counts of expert and nominal
   traces satisfying every ``F p``, ``G p`` and ``p T q`` over ``P`` atoms (one atom per visited
   state, as with learned propositions), versus :func:`vectorized.evaluate` per instantiation.

    .venv/bin/python benchmarks/ltl_evaluators.py            # default sizes (about a minute)
    .venv/bin/python benchmarks/ltl_evaluators.py --quick    # smaller sizes
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from symlearn.data.ltl_samples import load_sample  # noqa: E402
from symlearn.learners.temporal import ltl_bitsets, spec_templates  # noqa: E402
from symlearn.logic.ltlf import ast  # noqa: E402
from symlearn.logic.ltlf import vectorized as core  # noqa: E402

SAMPLES = REPO.parent / "shared" / "benchmarks" / "ltlf_learning" / "dev"
# the largest samples of the dev set: 6 propositions, 100 + 100 traces of length 64 (quick: 16)
SAMPLE = "Subset/trace_length=64number_atomic_propositions=6number_positive_traces=100" \
         "number_negative_traces=100subset_size=4seed=1004.json"
QUICK_SAMPLE = "Subset/trace_length=16number_atomic_propositions=6number_positive_traces=100" \
               "number_negative_traces=100subset_size=4seed=1070.json"
UNARY = ("!", "X", "F", "G")
BINARY = ("&", "|", "->", "U")
_NODE = {"!": ast.Not, "X": ast.Next, "F": ast.Eventually, "G": ast.Always,
         "&": ast.And, "|": ast.Or, "->": ast.Implies, "U": ast.Until}


def best_time(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


# -- 1. separating formulas --------------------------------------------------------------------
def candidates(props: list[str], max_size: int):
    """Every formula up to ``max_size`` nodes, as (op, left, right) recipes over earlier ids.

    Level by level as the enumerator builds them (without its deduplication): unary operators
    over level s-1, binary ones over levels s1 + s2 = s-1.
    """
    recipes = [("atom", p, None) for p in props]
    levels = {1: list(range(len(props)))}
    for size in range(2, max_size + 1):
        level = []
        for op in UNARY:
            for i in levels[size - 1]:
                level.append(len(recipes))
                recipes.append((op, i, None))
        for op in BINARY:
            for left_size in range(1, size - 1):
                for i in levels[left_size]:
                    for j in levels[size - 1 - left_size]:
                        level.append(len(recipes))
                        recipes.append((op, i, j))
        levels[size] = level
    return recipes


def formula_of(recipes, k, memo):
    if k not in memo:
        op, a, b = recipes[k]
        if op == "atom":
            memo[k] = ast.Prop(a)
        elif b is None:
            memo[k] = _NODE[op](formula_of(recipes, a, memo))
        else:
            memo[k] = _NODE[op](formula_of(recipes, a, memo), formula_of(recipes, b, memo))
    return memo[k]


def by_level_and_op(recipes):
    """Group recipe ids as the enumerator does: one batch per (level, operator)."""
    groups: dict[tuple, list[int]] = {}
    level = {}
    for k, (op, a, b) in enumerate(recipes):
        level[k] = 1 if op == "atom" else 1 + level[a] + (level[b] if b is not None else 0)
        if op != "atom":
            groups.setdefault((level[k], op), []).append(k)
    return groups


def run_bitsets(frame, recipes, groups):
    values = {k: frame.propositions[a] for k, (op, a, _) in enumerate(recipes) if op == "atom"}
    for (_, op), ids in sorted(groups.items()):
        left = np.stack([values[recipes[k][1]] for k in ids])
        right = np.stack([values[recipes[k][2]] for k in ids]) if recipes[ids[0]][2] is not None else None
        out = ltl_bitsets.apply(op, frame, left, right)
        values.update(zip(ids, out))
    return {k: ltl_bitsets.first_bits(v[None])[0] for k, v in values.items()}


def core_kernel(op, alive, a, b=None):
    """One operator over stacked bool matrices with the core evaluator's kernels."""
    if op == "!":
        return ~a & alive
    if op == "X":
        return core._shift(a, alive, strong=True)
    if op == "F":
        return core._eventually(a, alive)
    if op == "G":
        return ~core._eventually(~a, alive) & alive
    if op == "&":
        return a & b
    if op == "|":
        return a | b
    if op == "->":
        return (~a | b) & alive
    return core._until(a, b, alive)


def run_core_kernels(batch, recipes, groups):
    n, width = batch.n_traces, batch.max_length
    alive1 = np.arange(width)[None, :] < batch.lengths[:, None]
    values = {}
    for k, (op, a, _) in enumerate(recipes):
        if op == "atom":
            m = batch.props.get(a)
            values[k] = np.zeros((n, width), bool) if m is None else m
    for (_, op), ids in sorted(groups.items()):
        m = len(ids)
        alive = np.tile(alive1, (m, 1))
        left = np.concatenate([values[recipes[k][1]] for k in ids])
        right = np.concatenate([values[recipes[k][2]] for k in ids]) if recipes[ids[0]][2] is not None else None
        out = core_kernel(op, alive, left, right).reshape(m, n, width)
        values.update(zip(ids, out))
    return {k: v[:, 0] for k, v in values.items()}


def run_core_evaluate(batch, formulas):
    return {k: core.evaluate(f, batch) for k, f in formulas.items()}


def separating(quick: bool, repeat: int) -> dict:
    path = SAMPLES / (QUICK_SAMPLE if quick else SAMPLE)
    sample = load_sample(path)
    traces = list(sample.positive) + list(sample.negative)
    props = list(sample.propositions)
    max_size = 3 if quick else 4
    recipes = candidates(props, max_size)
    groups = by_level_and_op(recipes)
    memo: dict = {}
    formulas = {k: formula_of(recipes, k, memo) for k in range(len(recipes))}
    frame = ltl_bitsets.Frame.from_traces(traces, props)
    batch = core.TraceBatch.from_traces(traces)

    ours = run_bitsets(frame, recipes, groups)
    kernels = run_core_kernels(batch, recipes, groups)
    evaluated = run_core_evaluate(batch, formulas)
    agree = all(np.array_equal(ours[k], kernels[k]) and np.array_equal(ours[k], evaluated[k]) for k in formulas)
    t_bits = best_time(lambda: run_bitsets(frame, recipes, groups), repeat)
    t_kernels = best_time(lambda: run_core_kernels(batch, recipes, groups), repeat)
    t_eval = best_time(lambda: run_core_evaluate(batch, formulas), max(1, repeat // 2))
    return {"sample": str(path.relative_to(SAMPLES)), "max_size": max_size, "traces": len(traces),
            "positions": int(sum(len(t) for t in traces)), "longest": max(len(t) for t in traces),
            "propositions": len(props), "candidates": len(recipes), "verdicts_agree": agree,
            "bitsets_ms": 1000 * t_bits, "core_kernels_ms": 1000 * t_kernels, "core_evaluate_ms": 1000 * t_eval,
            "speedup_vs_core_kernels": t_kernels / t_bits, "speedup_vs_core_evaluate": t_eval / t_bits}


# -- 2. specification templates ----------------------------------------------------------------
def template_counts(bounds_e, bounds_n):
    return {t: (bounds_e.counts(t), bounds_n.counts(t)) for t in spec_templates.TEMPLATES}


def run_templates(expert, nominal, atom_of_state):
    e = spec_templates.TraceBounds.from_traces(expert, atom_of_state)
    n = spec_templates.TraceBounds.from_traces(nominal, atom_of_state)
    return template_counts(e, n)


def run_core_templates(expert, nominal, atom_of_state, names):
    def labels(traces):
        return core.TraceBatch.from_traces([[{names[p] for p in np.flatnonzero(atom_of_state[s])} for s in t]
                                            for t in traces])

    batches = (labels(expert), labels(nominal))
    n_atoms = len(names)
    out = {}
    for template in spec_templates.TEMPLATES:
        shape = (n_atoms, n_atoms) if template == "T" else (n_atoms,)
        counts = [np.zeros(shape, dtype=np.int64) for _ in batches]
        for atoms in np.ndindex(*shape):
            if template == "T" and atoms[0] == atoms[1]:
                continue  # best_candidate never picks p T p
            f = spec_templates.instantiate(template, [names[i] for i in atoms])
            for c, batch in zip(counts, batches):
                c[atoms] = core.evaluate(f, batch).sum()
        out[template] = tuple(counts)
    return out


def templates(quick: bool, repeat: int) -> dict:
    rng = np.random.default_rng(0)
    n_states, n_traces, length = (40, 30, 30) if quick else (100, 50, 60)
    # random walks on a ring of states: one atom per state, as with learned propositions
    def walks(k):
        return [np.cumsum(rng.choice([-1, 0, 1], size=length)) % n_states for _ in range(k)]

    expert, nominal = walks(n_traces), walks(n_traces)
    atom_of_state = np.eye(n_states, dtype=bool)
    names = [f"s{i}" for i in range(n_states)]
    ours = run_templates(expert, nominal, atom_of_state)
    theirs = run_core_templates(expert, nominal, atom_of_state, names)
    off_diagonal = ~np.eye(n_states, dtype=bool)
    agree = all(np.array_equal(ours[t][i][off_diagonal] if t == "T" else ours[t][i],
                               theirs[t][i][off_diagonal] if t == "T" else theirs[t][i])
                for t in spec_templates.TEMPLATES for i in range(2))
    t_ours = best_time(lambda: run_templates(expert, nominal, atom_of_state), repeat)
    t_core = best_time(lambda: run_core_templates(expert, nominal, atom_of_state, names), 1)
    return {"atoms": n_states, "traces": 2 * n_traces, "length": length,
            "instantiations": 2 * n_states + n_states * (n_states - 1), "counts_agree": agree,
            "templates_ms": 1000 * t_ours, "core_evaluate_ms": 1000 * t_core, "speedup": t_core / t_ours}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smaller sample and sizes")
    parser.add_argument("--repeat", type=int, default=5, help="best of this many runs")
    parser.add_argument("--json", type=Path, help="also write the results to this JSON file")
    args = parser.parse_args()
    print(f"# {' '.join(sys.argv)}")
    print(f"# machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, "
          f"numpy {np.__version__}")
    sep = separating(args.quick, args.repeat)
    print(f"\n## ltl_bitsets: {sep['candidates']} formulas of size <= {sep['max_size']} on {sep['sample']} "
          f"({sep['traces']} traces, {sep['positions']} positions, longest {sep['longest']}, "
          f"{sep['propositions']} propositions); verdicts agree: {sep['verdicts_agree']}")
    print(f"   bitsets {sep['bitsets_ms']:.2f} ms | core kernels, batched {sep['core_kernels_ms']:.2f} ms | "
          f"core evaluate per formula {sep['core_evaluate_ms']:.1f} ms")
    print(f"   bitsets speed-up: {sep['speedup_vs_core_kernels']:.1f}x vs the core kernels, "
          f"{sep['speedup_vs_core_evaluate']:.0f}x vs core evaluate")
    tpl = templates(args.quick, args.repeat)
    print(f"\n## spec_templates: {tpl['instantiations']} instantiations of F p, G p, p T q over {tpl['atoms']} atoms, "
          f"{tpl['traces']} traces of {tpl['length']} steps; counts agree: {tpl['counts_agree']}")
    print(f"   templates {tpl['templates_ms']:.2f} ms | core evaluate per instantiation {tpl['core_evaluate_ms']:.0f} ms"
          f" | speed-up {tpl['speedup']:.0f}x")
    if args.json:
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "separating": sep, "templates": tpl},
                                        indent=1) + "\n")


if __name__ == "__main__":
    main()
