"""Accuracy of logic constraint inference vs. number of demonstrations and iterations (thesis 3.4.3).

    python benchmarks/logic_constraints.py [--quick] [--seeds 2] [--workers 2] [--start both] [--json OUT]

For the traffic-light and priority junctions, every number of expert demonstrations ``n`` and
every seed, it runs :class:`LogicConstraintInference` once with the largest ``eta`` and reads
the rules after ``eta`` iterations off its history (one run = one point per eta; a run with
``iterations=eta`` gives the same rules, except that it ends with one more induction over the
loop's last closure, which only the largest eta gets here). Each rule set is scored against the
ground truth with :func:`constraint_metrics`:

* a *positive* is a forbidden pair; FPR = allowed pairs the rules forbid / allowed pairs,
  FNR = forbidden pairs the rules allow / forbidden pairs, accuracy = pairs classified like the
  truth / pairs;
* ``full``: over every state-action pair of the domain (50 states x 5 actions);
* ``reach``: over every action of the states a driver reaches from the entries when it obeys
  the *true* rules (road cells, both observations): the pairs a rule-abiding car meets;
* ``fnr@learned``: FNR over the states reachable when obeying the *learned* rules (what an
  agent that trusts the rules can meet and break).

``--start`` says where the nominal MaxEnt visitation starts (``LogicConstraintInference(start=)``):
``default`` (the learner's default, the default here), ``uniform`` (every non-terminal state),
``demonstrations`` (the demonstrations' start states, the thesis' maximum-likelihood objective),
a uniform share in [0, 1] (a mixture of the two), or a comma-separated list of these; ``both`` =
``uniform,demonstrations``, ``all`` = ``default,uniform,demonstrations``. Every (domain, n, seed)
is run with each start, so the tables compare them in the same run.

The peer measured in the same run is maximum-likelihood inference alone (the same demonstrations,
horizon, sparse reward and eta, no induction, ``MLConstraintInference``'s own default start
``demonstrations``): its closed constraint set after eta iterations; it does not depend on
``--start`` and is run once per (domain, n, seed).
Timing: the mean seconds per iteration of the inference step and of the induction step over
every iteration of every run (the stage timing figure, thesis Fig. 3.6). Hanoi: the rule learned
from a few games and whether it forbids exactly the true pairs.
"""

from __future__ import annotations

import argparse
import inspect
import json
import multiprocessing
import os
import platform
import sys
import time
from typing import Any

import numpy as np

from symlearn.envs.logic_mdp import LogicMDP, logic_mdp
from symlearn.learners.constraints.constraint_metrics import constraint_metrics, reachable_pairs
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
from symlearn.rl.tabular import restrict

FULL = {"domains": ["junction-lights", "junction-priority"], "ns": [5, 15, 30, 100, 500],
        "etas": [5, 10, 20, 30], "hanoi_ns": [1, 3, 10]}
QUICK = {"domains": ["junction-lights", "junction-priority"], "ns": [5, 30], "etas": [5, 20], "hanoi_ns": [3]}

_MDPS: dict[str, LogicMDP] = {}
STARTS = ("uniform", "demonstrations")
DEFAULT_START = inspect.signature(LogicConstraintInference).parameters["start"].default
SHORTCUTS = {"both": ["uniform", "demonstrations"], "all": ["default", "uniform", "demonstrations"]}


def parse_starts(text: str) -> list[str | float]:
    """``--start``: comma-separated starts ("uniform", "demonstrations", "default" = the learner's
    default, or a uniform share in [0, 1]); "both" = uniform,demonstrations; "all" = default too."""
    starts: list[str | float] = []
    for item in SHORTCUTS.get(text.strip(), text.split(",")):
        item = item.strip()
        value = DEFAULT_START if item == "default" else item if item in STARTS else float(item)
        if value not in starts:
            starts.append(value)
    return starts


def _lm(name: str) -> LogicMDP:
    if name not in _MDPS:
        _MDPS[name] = logic_mdp(name)
    return _MDPS[name]


def _scores(lm: LogicMDP, learned: np.ndarray, reach_truth: np.ndarray) -> dict[str, Any]:
    truth, space = lm.truth_forbidden, ~lm.unavailable
    full = constraint_metrics(learned, truth, space)
    reach = constraint_metrics(learned, truth, reach_truth)
    reach_learned = reachable_pairs(lm.mdp, learned | lm.unavailable) & space
    return {"fpr": full["fpr"], "fnr": full["fnr"], "accuracy": full["accuracy"],
            "forbidden": int((learned & space).sum()),
            "reach_fpr": reach["fpr"], "reach_fnr": reach["fnr"], "reach_accuracy": reach["accuracy"],
            "fnr_at_learned": constraint_metrics(learned, truth, reach_learned)["fnr"]}


def run_one(job: tuple[str, int, int, list[int], int, tuple[str, ...]]) -> list[dict[str, Any]]:
    """One (domain, n, seed): logic inference with max(etas) iterations for every start, ML-only
    peer (once), per eta."""
    name, n, seed, etas, horizon, starts = job
    lm = _lm(name)
    demos = lm.expert_demonstrations(n, seed=seed)
    reach_truth = reachable_pairs(lm.mdp, lm.truth_forbidden) & ~lm.unavailable
    known = lm.domain.known  # moves that do not exist
    # ML inference alone after eta iterations = the closure of its first eta inferred pairs
    ml = _ml_only(lm, demos, max(etas), horizon)
    ml_scores = {}
    for eta in etas:
        forbidden = known.copy()
        for s, a in ml["pairs"][:eta]:
            forbidden[s, a] = True
        closed = restrict(lm.mdp, forbidden, protected=ml["seen"]).forbidden & ~lm.unavailable
        ml_scores[eta] = {f"ml_{k}": v for k, v in _scores(lm, closed, reach_truth).items()}
    out: list[dict[str, Any]] = []
    for start in starts:
        out += _logic_rows(lm, demos, name, n, seed, etas, horizon, start, reach_truth, ml_scores, ml)
    return out


def _logic_rows(lm, demos, name, n, seed, etas, horizon, start, reach_truth, ml_scores, ml) -> list[dict[str, Any]]:
    t0 = time.perf_counter()
    learner = LogicConstraintInference(iterations=max(etas), horizon=horizon, start=start).fit(demos, lm.domain)
    wall = time.perf_counter() - t0
    history = learner.history_
    rows = []
    for eta in etas:
        done = history[:eta]
        if len(done) == len(history):  # the run ended here (eta reached or converged)
            rules, mask = tuple(learner.rules_), learner.rule_constraints_
        else:
            rules = done[-1].rules if done else ()
            mask = lm.rule_mask(list(rules)) if rules else np.zeros_like(lm.unavailable)
        row = {"domain": name, "start": start, "n": n, "seed": seed, "eta": eta, "iterations_run": len(done),
               "stopped": learner.stopped_because_ if len(done) == len(history) else "eta",
               "rules": list(rules), **_scores(lm, mask, reach_truth), **ml_scores[eta]}
        rows.append(row)
    timing = {"domain": name, "start": start, "n": n, "seed": seed, "wall_seconds": wall,
              "final_induction_seconds": learner.final_induction_seconds_,
              "inference_seconds": [h.inference_seconds for h in history],
              "induction_seconds": [h.induction_seconds for h in history],
              "ml_only_seconds": ml["seconds"], "ml_only_iterations": len(ml["pairs"])}
    return rows + [{"timing": timing}]


#: the scores a sweep cell keeps per eta (``fpr_eta20``, ...)
CELL_SCORES = ("fpr", "fnr", "accuracy", "forbidden", "reach_fpr", "reach_fnr", "fnr_at_learned", "ml_fpr", "ml_fnr",
               "ml_reach_fnr", "ml_forbidden")


def cell(domain: str, n: int, seed: int, etas: list[int], horizon: int = 30, start: str | float = "default") -> dict:
    """One cell of ``benchmarks/sweeps/logic_constraints*.toml``: :func:`run_one` for one
    (domain, n, seed, start), its rows as metrics ``<score>_eta<eta>`` plus the rules and the
    timing of the run."""
    start = DEFAULT_START if start == "default" else start
    rows = run_one((domain, n, seed, sorted(etas), horizon, (start,)))
    timing = next(r["timing"] for r in rows if "timing" in r)
    metrics: dict[str, Any] = {}
    for row in (r for r in rows if "timing" not in r):
        for key in CELL_SCORES:
            metrics[f"{key}_eta{row['eta']}"] = row[key]
        metrics[f"rules_eta{row['eta']}"] = len(row["rules"])
        metrics[f"iterations_run_eta{row['eta']}"] = row["iterations_run"]
    metrics["rules"] = row["rules"]
    metrics["wall_seconds"] = timing["wall_seconds"]
    metrics["inference_seconds_per_iteration"] = float(np.mean(timing["inference_seconds"])) \
        if timing["inference_seconds"] else None
    metrics["induction_seconds_per_iteration"] = float(np.mean(timing["induction_seconds"])) \
        if timing["induction_seconds"] else None
    return metrics


def _ml_only(lm: LogicMDP, demos, eta: int, horizon: int) -> dict[str, Any]:
    from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference

    # the domain's moves that do not exist are its known constraints; its own default start
    learner = MLConstraintInference(reward="sparse", horizon=horizon, max_iterations=eta).fit(demos, lm.domain)
    return {"pairs": [(h.state, h.action) for h in learner.history_], "seen": learner.demonstrated_,
            "seconds": learner.seconds_}


def hanoi_rows(ns: list[int], seeds: list[int], starts: tuple[str, ...]) -> list[dict[str, Any]]:
    lm = _lm("hanoi")
    rows = []
    for start in starts:
        for n in ns:
            for seed in seeds:
                t0 = time.perf_counter()
                learner = LogicConstraintInference(iterations=3, start=start).fit(
                    lm.expert_demonstrations(n, seed=seed), lm.domain)
                rows.append({"domain": "hanoi", "start": start, "n": n, "seed": seed, "rules": learner.rules_,
                             "exact": bool(np.array_equal(learner.rule_constraints_, lm.truth_forbidden)),
                             "seconds": time.perf_counter() - t0, **learner.score()})
    return rows


def _mean_sd(values: list[float]) -> str:
    values = np.asarray(values, dtype=float)
    if values.size == 1:
        return f"{values[0]:.3f}"
    return f"{values.mean():.3f}±{values.std(ddof=1):.3f}"


def _start_label(start: str | float) -> str:
    return f"start={start}" + (" (default)" if start == DEFAULT_START else "")


def report(rows: list[dict[str, Any]], timings: list[dict[str, Any]], hanoi: list[dict[str, Any]]) -> str:
    out = []
    starts = list(dict.fromkeys(r["start"] for r in rows))
    max_eta = max(x["eta"] for x in rows)
    for name in sorted({r["domain"] for r in rows}):
        for start in starts:
            mine = [r for r in rows if r["domain"] == name and r["start"] == start]
            out.append(f"\n### {name}, {_start_label(start)}: learned rules vs. the truth (mean±sd over seeds)\n")
            out.append("| n | eta | iters run | FPR | FNR | acc | forbidden | FPR reach | FNR reach | FNR @learned "
                       "| ML-only FPR | ML-only FNR | ML-only FNR reach | ML forbidden |")
            out.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
            for n, eta in sorted({(r["n"], r["eta"]) for r in mine}):
                group = [r for r in mine if r["n"] == n and r["eta"] == eta]
                col = lambda key: _mean_sd([r[key] for r in group])  # noqa: E731
                out.append(f"| {n} | {eta} | {np.mean([r['iterations_run'] for r in group]):.1f} | {col('fpr')} | "
                           f"{col('fnr')} | {col('accuracy')} | {np.mean([r['forbidden'] for r in group]):.0f} | "
                           f"{col('reach_fpr')} | {col('reach_fnr')} | {col('fnr_at_learned')} | {col('ml_fpr')} | "
                           f"{col('ml_fnr')} | {col('ml_reach_fnr')} | {np.mean([r['ml_forbidden'] for r in group]):.0f} |")
            last = [r for r in mine if r["eta"] == max_eta]
            has = sum(any("not onRoad(V1) : dir(V1)" in rule for rule in r["rules"]) for r in last)
            exact = sum(r["fpr"] == 0 and r["fnr"] == 0 for r in last)
            out.append(f"\noff-road rule `:- not onRoad(V1) : dir(V1).` learned in {has} of {len(last)} runs "
                       f"at eta {max_eta}; rules forbid exactly the truth (FPR = FNR = 0) in {exact} of {len(last)}")
        if len(starts) > 1:
            names = " vs. ".join(f"start={st}" for st in starts)
            out.append(f"\n### {name}: {names} (same demonstrations; mean over seeds)\n")
            out.append("| n | eta | " + " | ".join(f"FPR {st} | FNR {st}" for st in starts) + " | "
                       + " | ".join(f"FNR reach {st}" for st in starts) + " | "
                       + " | ".join(f"rules {st}" for st in starts) + " |")
            out.append("|---:|---:|" + "---:|" * (4 * len(starts)))
            for n, eta in sorted({(r["n"], r["eta"]) for r in rows if r["domain"] == name}):
                g = {st: [r for r in rows if r["domain"] == name and r["start"] == st and r["n"] == n
                          and r["eta"] == eta] for st in starts}
                m = lambda st, key: f"{np.mean([r[key] for r in g[st]]):.3f}"  # noqa: E731
                k = lambda st: f"{np.mean([len(r['rules']) for r in g[st]]):.1f}"  # noqa: E731
                out.append(f"| {n} | {eta} | " + " | ".join(f"{m(st, 'fpr')} | {m(st, 'fnr')}" for st in starts)
                           + " | " + " | ".join(m(st, "reach_fnr") for st in starts) + " | "
                           + " | ".join(k(st) for st in starts) + " |")
    out.append("\n### Stage timing: mean seconds per iteration (all iterations of all runs)\n")
    out.append("| domain | start | n | inference s/iter | induction s/iter | induction share | final induction s | "
               "ML-only s/run | wall s/run |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for name in sorted({t["domain"] for t in timings}):
        for start in starts:
            for n in sorted({t["n"] for t in timings if t["domain"] == name}):
                group = [t for t in timings if t["domain"] == name and t["n"] == n and t["start"] == start]
                if not group:
                    continue
                inf = [x for t in group for x in t["inference_seconds"]]
                ind = [x for t in group for x in t["induction_seconds"]]
                share = sum(ind) / max(sum(ind) + sum(inf), 1e-12)
                out.append(f"| {name} | {start} | {n} | {np.mean(inf):.3f} | {np.mean(ind):.3f} | {share:.0%} | "
                           f"{np.mean([t['final_induction_seconds'] for t in group]):.2f} | "
                           f"{np.mean([t['ml_only_seconds'] for t in group]):.2f} | "
                           f"{np.mean([t['wall_seconds'] for t in group]):.1f} |")
    if hanoi:
        out.append("\n### Hanoi (3 iterations)\n")
        out.append("| start | n | seed | rules | forbids exactly the truth | FPR | FNR | s |")
        out.append("|---|---:|---:|---|---|---:|---:|---:|")
        for r in hanoi:
            out.append(f"| {r['start']} | {r['n']} | {r['seed']} | {' '.join(f'`{x}`' for x in r['rules'])} | "
                       f"{r['exact']} | {r['fpr']:.3f} | {r['fnr']:.3f} | {r['seconds']:.1f} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="n in 5, 30; eta in 5, 20; one seed")
    parser.add_argument("--seeds", type=int, default=None, help="number of seeds (default 2, quick 1)")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--horizon", type=int, default=30)
    parser.add_argument("--start", default="default",
                        help=f"where the nominal visitation starts: default (the learner's, {DEFAULT_START}), "
                             "uniform, demonstrations, a uniform share in [0, 1], or a comma-separated list; "
                             "'both' = uniform,demonstrations; 'all' = default,uniform,demonstrations")
    parser.add_argument("--ns", default=None, help="comma-separated n (overrides the plan)")
    parser.add_argument("--etas", default=None, help="comma-separated eta (overrides the plan)")
    parser.add_argument("--json", metavar="OUT", help="write every row and timing as JSON")
    args = parser.parse_args(argv)
    plan = dict(QUICK if args.quick else FULL)
    if args.ns:
        plan["ns"] = [int(x) for x in args.ns.split(",")]
    if args.etas:
        plan["etas"] = sorted(int(x) for x in args.etas.split(","))
    starts = tuple(parse_starts(args.start))
    seeds = list(range(args.seeds if args.seeds is not None else (1 if args.quick else 2)))
    command = "python benchmarks/logic_constraints.py " + " ".join(sys.argv[1:] if argv is None else argv)
    print(f"command: {command.strip()}")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cpus, python {platform.python_version()}, "
          f"{args.workers} worker process(es)")
    print(f"settings: n in {plan['ns']}, eta in {plan['etas']}, seeds {seeds}, horizon {args.horizon}, "
          f"start {', '.join(map(str, starts))}")
    started = time.perf_counter()
    jobs = [(name, n, seed, plan["etas"], args.horizon, starts) for name in plan["domains"]
            for n in sorted(plan["ns"], reverse=True) for seed in seeds]
    results: list[list[dict[str, Any]]] = []
    if args.workers > 1:
        with multiprocessing.get_context("fork").Pool(args.workers) as pool:
            for i, result in enumerate(pool.imap_unordered(run_one, jobs), 1):
                results.append(result)
                print(f"  [{i}/{len(jobs)}] {time.perf_counter() - started:.0f} s", file=sys.stderr, flush=True)
    else:
        results = [run_one(job) for job in jobs]
    rows = [r for result in results for r in result if "timing" not in r]
    timings = [r["timing"] for result in results for r in result if "timing" in r]
    hanoi = hanoi_rows(plan["hanoi_ns"], seeds, starts)
    total = time.perf_counter() - started
    print(report(rows, timings, hanoi))
    print(f"\ntotal {total:.0f} s")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump({"command": command.strip(), "seeds": seeds, "plan": plan, "horizon": args.horizon,
                       "start": args.start, "starts": list(starts), "default_start": DEFAULT_START,
                       "seconds": total, "rows": rows, "timings": timings, "hanoi": hanoi}, handle, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
