"""Specification learning from demonstrations on the eight office/craft tasks.

For every task, with propositions given and learned, and every seed:

* ``ours``        SpecLearner (information gain + policy updates by CRM Q-learning + pruning);
                  ``ours_unpruned`` is the same run's formula before pruning;
* ``no-updates``  the same learner whose nominal policy stays random (baseline i); without
                  pruning, to bound run time (compare it with ``ours_unpruned``);
* ``scarlet``     Scarlet (Scarlet-ltl) fed expert traces as positives and random-walk traces
                  as negatives (baseline ii; propositions given only: with learned propositions
                  every state would be a proposition, far beyond its reach).
* ``positive-only`` Roy et al.'s positive-only LTLf (the thesis' baseline ii,
                  :mod:`symlearn.learners.temporal.positive_only_ltl`), fed the expert traces only:
                  the most specific formula of size <= ``--po-max-size`` true on every expert
                  trace, its language compared on a universe of traces over the letters the
                  world can show (so ``G !n`` counts as more specific), bounded by
                  ``--po-timeout`` (best formula enumerated so far on timeout, reported). With
                  propositions given only by default, as in the thesis (intractable with learned
                  ones); ``--po-props given learn`` also tries learned ones: one proposition per
                  cell an expert visits, every other cell the empty letter.

Each learned formula is turned into a nominal policy (DFA -> reward machine -> CRM Q-learning),
whose greedy rollouts (ties broken at random, 20 of them) are checked against the ground-truth
formula: success rate; expected policy entropy (per step, divided by log 4); formula length
(syntax-tree nodes); iterations; wall time. Also the number-of-demonstrations ablation
(5, 10, 20, 50) on the office tasks.

    .venv/bin/python benchmarks/spec_learning.py --quick          # 1 seed, a subset, minutes
    .venv/bin/python benchmarks/spec_learning.py --seeds 5        # everything
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

ALL_TASKS = ["office-1", "office-2", "office-3", "office-4", "craft-1", "craft-2", "craft-3", "craft-4"]
QUICK_TASKS = ["office-1", "office-2", "office-3", "craft-1"]


# --- evaluation of a formula -------------------------------------------------------------------
def evaluate_formula(formula, env, truth: str, labeling, seed: int) -> dict:
    """Train a nominal policy on ``formula`` by CRM Q-learning and score it on ``truth``."""
    from symlearn.backends.reward_machine import task_machine
    from symlearn.envs.spec_experts import successor_table
    from symlearn.logic.ltlf import holds, parse
    from symlearn.rl.crm_q_learning import crm_q_learning, policy_entropy, sample_episodes

    succ = successor_table(env)
    machine = task_machine(formula)
    n = succ.shape[0]
    steps = min(400 * n * (1 + machine.n_states // 8), 4_000_000)
    result = crm_q_learning(succ, [labeling.label(s) for s in range(n)], machine, env.state_of(env.start),
                            n_steps=steps, n_envs=128, horizon=env.max_steps, seed=seed)
    truth_f = parse(truth)
    greedy = sample_episodes(result, 20, seed=seed, greedy=True)
    success = float(np.mean([holds(truth_f, [env.labeling.label(int(s)) for s in p]) for p in greedy]))
    return {"success": success, "entropy": policy_entropy(result, sample_episodes(result, 20, seed=seed + 1))}


# --- Scarlet (baseline ii), a minimal adapter: trace file in, best formula of its CSV out -----------
_SCARLET_RUN = """
import sys
from Scarlet.inferLTL import inferLTL
from Scarlet.sample import Sample
s = Sample(positive=[], negative=[])
s.readFromFile(sys.argv[1])
inferLTL(s, sys.argv[2], ['F', 'G', 'X', '!', '&', '|'], 'SC', 0, False, False, 0, {})
"""


def scarlet(positives, negatives, alphabet, timeout: float) -> tuple[str | None, float, bool]:
    """Scarlet's formula (its syntax) for label words, seconds, and whether it finished in time."""
    def line(word):
        return ";".join(",".join("1" if p in label else "0" for p in alphabet) for label in word)

    with tempfile.TemporaryDirectory() as tmp:
        trace_file, csv_file = os.path.join(tmp, "sample.trace"), os.path.join(tmp, "out.csv")
        with open(trace_file, "w") as f:
            f.write("\n".join(line(w) for w in positives) + "\n---\n")
            f.write("\n".join(line(w) for w in negatives) + "\n---\n")
            f.write("F,G,X,!,&,|\n---\n" + ",".join(alphabet) + "\n")
        t0 = time.perf_counter()
        finished = True
        try:
            subprocess.run([sys.executable, "-c", _SCARLET_RUN, trace_file, csv_file], timeout=timeout,
                           capture_output=True, check=False)
        except subprocess.TimeoutExpired:
            finished = False
        seconds = time.perf_counter() - t0
        formula = None
        if os.path.exists(csv_file):
            with open(csv_file) as f:
                rows = list(csv.reader(f))[1:]
            if rows:
                formula = rows[-1][2]
        return formula, seconds, finished


def _scarlet_peer(positives, negatives, alphabet, timeout: float) -> tuple[str | None, float, bool]:
    """Through the project's Scarlet adapter (symlearn.learners.temporal.scarlet_peer) when it can start its
    child process here, else through the minimal subprocess adapter above."""
    try:
        from symlearn.data.ltl_samples import sample_from_traces
        from symlearn.learners.temporal.scarlet_peer import run_scarlet

        result = run_scarlet(sample_from_traces(positives, negatives, propositions=alphabet), timeout=timeout)
        return result.formula, result.seconds, result.finished
    except (ImportError, AssertionError):  # e.g. "daemonic processes are not allowed to have children"
        return scarlet(positives, negatives, alphabet, timeout)


# --- one job -----------------------------------------------------------------------------------
def run_job(job: dict) -> dict:
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task
    from symlearn.learners.temporal.spec_from_demos import SpecLearner
    from symlearn.logic.ltlf import parse, size

    task = get_task(job["task"])
    env = task.make_env()
    demos = expert_demonstrations(task, job["n_demos"], seed=job["seed"], env=env)
    row = dict(job)
    t0 = time.perf_counter()
    try:
        if job["method"] in ("ours", "no-updates"):
            ours = job["method"] == "ours"
            learner = SpecLearner(propositions=job["props"], policy_updates=ours, prune=ours, random_state=job["seed"])
            learner.fit(demos, env)
            row.update(formula=str(learner.formula_), length=learner.length_, iterations=learner.iterations_,
                       unpruned_length=size(learner.unpruned_formula_), success=learner.success_rate(task.formula),
                       entropy=learner.entropy_, seconds=time.perf_counter() - t0)
        elif job["method"] == "positive-only":
            row.update(positive_only(task, env, demos, job))
        else:  # scarlet
            rng = np.random.default_rng(job["seed"])
            alphabet = list(env.labeling.propositions)
            positives = [[env.labeling.label(int(s)) for s in t.states] for t in demos]
            negatives = []
            for _ in range(len(demos)):
                s, word = env.state_of(env.start), []
                for _ in range(env.max_steps + 1):
                    word.append(env.labeling.label(s))
                    s = env.next_state(s, int(rng.integers(4)))
                negatives.append(word)
            text, seconds, finished = _scarlet_peer(positives, negatives, alphabet, job["scarlet_timeout"])
            row.update(formula=text, finished=finished, seconds=seconds, iterations=None)
            if text is None:
                row.update(success=0.0, entropy=None, length=None)
            else:
                formula = parse(text)
                row.update(length=size(formula), **evaluate_formula(formula, env, task.formula, env.labeling,
                                                                   job["seed"]))
    except Exception as exc:  # a failed run is a result too; keep going
        row.update(error=f"{type(exc).__name__}: {exc}", success=0.0, seconds=time.perf_counter() - t0)
    print(f"  {job['task']:9s} {job['props']:5s} {job['method']:13s} seed {job['seed']} n={job['n_demos']:2d}: "
          f"success {row.get('success')} length {row.get('length')} {row.get('seconds', 0):.1f}s "
          f"{row.get('formula') or row.get('error', '')}", flush=True)
    return row


def positive_only(task, env, demos, job: dict) -> dict:
    """Roy et al.'s positive-only LTLf on the expert label words, then the common scoring."""
    from symlearn.grounding.labeling import Labeling
    from symlearn.learners.temporal.positive_only_ltl import PositiveOnlyLtlLearner
    from symlearn.logic.ltlf import size

    if job["props"] == "given":
        labeling = env.labeling
    else:  # one proposition per cell an expert visits (no nominal policy here to show others)
        visited = sorted({int(s) for t in demos for s in t.states})
        labeling = Labeling({s: {f"c{s}"} for s in visited})
    positives = [[labeling.label(int(s)) for s in t.states] for t in demos]
    letters = {labeling.label(s) for s in range(int(env.observation_space.n))}
    learner = PositiveOnlyLtlLearner(max_size=job.get("po_max_size", 6), timeout=job.get("po_timeout", 60.0),
                                     letters=sorted(letters, key=sorted), random_state=job["seed"])
    learner.fit(positives, list(labeling.propositions))
    search = learner.search_
    formula = learner.formula_
    out = {"formula": str(formula), "length": size(formula), "iterations": None,
           "finished": search.stopped_by == "max_size", "stopped_by": search.stopped_by,
           "complete_up_to": search.complete_up_to, "candidates": search.candidates,
           "universe": search.universe, "letters": search.letters, "seconds": search.seconds,
           "learn_seconds": search.seconds,
           "propositions": len(labeling.propositions)}
    out.update(evaluate_formula(formula, env, task.formula, labeling, job["seed"]))
    return out


def cell(task: str, props: str, method: str, seed: int, n_demos: int = 50, scarlet_timeout: float = 120.0,
         po_max_size: int = 6, po_timeout: float = 60.0) -> dict:
    """One cell of ``benchmarks/sweeps/spec_learning*.toml``: :func:`run_job`'s row for one
    (task, propositions, method, seed) as metrics (a failed run keeps success 0 and its error,
    as in the script's table)."""
    row = run_job(dict(task=task, props=props, method=method, seed=seed, n_demos=n_demos,
                       scarlet_timeout=scarlet_timeout, po_max_size=po_max_size, po_timeout=po_timeout))
    keys = ("success", "entropy", "length", "unpruned_length", "iterations", "seconds", "formula", "error",
            "finished", "stopped_by")
    return {k: row.get(k) for k in keys}


# --- aggregation -------------------------------------------------------------------------------
def _mean(values):
    values = [v for v in values if v is not None]
    return (statistics.fmean(values), statistics.pstdev(values)) if values else (None, None)


def _fmt(pair, digits=2):
    m, s = pair
    return "-" if m is None else f"{m:.{digits}f}" + (f" ± {s:.{digits}f}" if s else "")


def summarise(rows: list[dict]) -> list[dict]:
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["task"], r["props"], r["method"], r["n_demos"]), []).append(r)
    table = []
    for (task, props, method, n), rs in sorted(groups.items(), key=lambda kv: (ALL_TASKS.index(kv[0][0]), kv[0][1:])):
        table.append({
            "task": task, "props": props, "method": method, "n_demos": n, "runs": len(rs),
            "success": _mean([r.get("success") for r in rs]), "entropy": _mean([r.get("entropy") for r in rs]),
            "length": _mean([r.get("length") for r in rs]), "unpruned_length": _mean([r.get("unpruned_length") for r in rs]),
            "iterations": _mean([r.get("iterations") for r in rs]), "seconds": _mean([r.get("seconds") for r in rs]),
            "errors": sum(1 for r in rs if "error" in r),
            "learn_seconds": _mean([r.get("learn_seconds") for r in rs]),
            "unfinished": sum(1 for r in rs if r.get("finished") is False),
        })
    return table


def markdown(table: list[dict]) -> str:
    lines = ["| task | props | method | n | runs | success | entropy | length | (unpruned) | iterations | seconds |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for t in table:
        note = (f" ({t['errors']} errors)" if t["errors"] else "") + (f" ({t['unfinished']} timed out)" if t["unfinished"] else "")
        lines.append(f"| {t['task']} | {t['props']} | {t['method']}{note} | {t['n_demos']} | {t['runs']} | "
                     f"{_fmt(t['success'])} | {_fmt(t['entropy'], 3)} | {_fmt(t['length'], 1)} | "
                     f"{_fmt(t['unpruned_length'], 1)} | {_fmt(t['iterations'], 1)} | {_fmt(t['seconds'], 1)} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1 seed, office-1..3 and craft-1, short Scarlet timeout")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--tasks", nargs="*", default=None)
    parser.add_argument("--n-demos", type=int, default=50)
    parser.add_argument("--scarlet-timeout", type=float, default=120.0)
    parser.add_argument("--no-scarlet", action="store_true")
    parser.add_argument("--no-baselines", action="store_true")
    parser.add_argument("--ablation", action="store_true", help="also the 5..50 demonstrations ablation (office)")
    parser.add_argument("--ablation-only", action="store_true")
    parser.add_argument("--methods", nargs="*", choices=("ours", "no-updates", "scarlet", "positive-only"),
                        help="run only these methods (default: all)")
    parser.add_argument("--po-max-size", type=int, default=6, help="positive-only: formula size bound")
    parser.add_argument("--po-timeout", type=float, default=60.0, help="positive-only: seconds per run")
    parser.add_argument("--po-props", nargs="*", choices=("given", "learn"), default=["given"],
                        help="positive-only: with which propositions (default: given, as in the thesis)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="benchmarks/results/spec_learning.json")
    args = parser.parse_args(argv)

    seeds = 1 if args.quick else args.seeds
    tasks = args.tasks or (QUICK_TASKS if args.quick else ALL_TASKS)
    timeout = min(args.scarlet_timeout, 30.0) if args.quick else args.scarlet_timeout
    jobs = []
    if not args.ablation_only:
        for seed in range(seeds):
            for task in tasks:
                for props in ("given", "learn"):
                    methods = ["ours"] if args.no_baselines else ["ours", "no-updates"]
                    if props == "given" and not (args.no_scarlet or args.no_baselines):
                        methods.append("scarlet")
                    if props in args.po_props and not args.no_baselines:
                        methods.append("positive-only")
                    if args.methods:
                        methods = [m for m in methods if m in args.methods]
                    jobs += [dict(task=task, props=props, method=m, seed=seed, n_demos=args.n_demos,
                                  scarlet_timeout=timeout, po_max_size=args.po_max_size,
                                  po_timeout=args.po_timeout) for m in methods]
    if args.ablation or args.ablation_only:
        for seed in range(seeds):
            for task in [t for t in tasks if t.startswith("office")]:
                for props in ("given", "learn"):
                    for n in (5, 10, 20):  # 50 is the main run
                        jobs.append(dict(task=task, props=props, method="ours", seed=seed, n_demos=n,
                                         scarlet_timeout=timeout, ablation=True))
    command = "python benchmarks/spec_learning.py " + " ".join(argv if argv is not None else sys.argv[1:])
    print(f"{command}\n{len(jobs)} runs on {args.workers} worker(s); {platform.platform()}, {os.cpu_count()} cores",
          flush=True)
    t0 = time.perf_counter()
    if args.workers > 1:
        with ProcessPoolExecutor(args.workers) as pool:
            rows = list(pool.map(run_job, jobs))
    else:
        rows = [run_job(j) for j in jobs]
    table = summarise(rows)
    print()
    print(markdown(table))
    print(f"\ntotal wall time {time.perf_counter() - t0:.0f} s")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    from symlearn.atomic import write_text

    write_text(out, json.dumps({"command": command, "machine": platform.platform(), "rows": rows, "table": table},
                               indent=1, default=str) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
