"""Reward-machine inference from images on the five rendered block tasks (thesis section 7.6, Table 7.1).

For every task (Stack-2, Place-2, Pyramid-3, Stack-3, Place-3; one demonstration per ordering)
and every rendering-noise seed, :class:`RewardMachineInference` with its data-derived defaults:

* ``defaults``     isomorphic to the ground-truth machine? the same machine once every state is
                   named after its prototype's true configuration? prototype (cluster) purity,
                   states, eps, min samples, kappa, seconds (features + clustering + machine);
* ``sensitivity``  the same with eps or kappa 30 % below / above its default (features cached),
                   and a wider sweep of factors 0.25 .. 2.5 (``sweep``, the figure) to show where it breaks;
* ``features``     PCA (default) against a convolutional autoencoder trained on the frames and a
                   random convolutional network (same pooling and lighting normalisation);
* ``peers``        the automaton step alone on the same label sequences (each demonstration's
                   labels with blanks and repeats removed): Algorithm 7.1 against dfa-identify
                   (the smallest DFA accepting the demonstrations and rejecting their proper
                   prefixes, SAT) and AALpy's RPNI on the same positives and negatives: states
                   (live ones: a complete DFA's rejecting sink is not counted), whether the live
                   part is isomorphic to the ground-truth machine, seconds.

No per-task setting exists anywhere: the defaults are derived from each data set by the same rule.

    nice -n 10 .venv/bin/python benchmarks/rm_inference.py            # 5 tasks x 5 seeds
    nice -n 10 .venv/bin/python benchmarks/rm_inference.py --quick    # 2 seeds, PCA and random CNN only

Raw results: ``benchmarks/results/rm_inference.json``; figures ``docs/figures/rm_inference_prototypes.png``
(the prototypes of every task, seed 0) and ``docs/figures/rm_inference_sensitivity.png``.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

TASKS = ("stack-2", "place-2", "pyramid-3", "stack-3", "place-3")
VARIANTS = {"eps -30%": ("eps", 0.7), "eps +30%": ("eps", 1.3), "kappa -30%": ("kappa", 0.7),
            "kappa +30%": ("kappa", 1.3)}
SWEEP = (0.25, 0.4, 0.55, 0.7, 1.0, 1.3, 1.6, 2.0, 2.5)  # factors on the derived eps / kappa (the figure)


def score(demos, learner) -> dict:
    from symlearn.learners.reward_machines.compare import isomorphic, same_machine, state_matching
    from symlearn.learners.reward_machines.machine_building import machine_from_edges
    from symlearn.learners.reward_machines.prototypes import purity

    s = demos.task.truth_structure()
    truth = machine_from_edges(s["propositions"], s["edges"], s["initial"], s["accepting"])
    labels = [label for t in demos.front for label in t.labels]
    matched = state_matching([labels[i] for i in learner.prototype_indices_])
    weighted, per_cluster = purity(learner.cluster_labels_, np.concatenate(demos.configurations))
    return {"isomorphic": isomorphic(learner.machine_, truth),
            "same_machine": same_machine(learner.machine_, truth, matched, s["propositions"]),
            "states": learner.machine_.n_states, "true_states": truth.n_states,
            "purity": weighted, "min_cluster_purity": min(per_cluster) if per_cluster else 0.0,
            "eps": learner.eps_, "min_samples": learner.min_samples_, "kappa": learner.kappa_,
            "multiple_label_frames": learner.result_.metrics["multiple_label_frames"],
            "seconds": learner.result_.timings["total"], "features_seconds": learner.result_.timings["features"]}


def words_of(learner) -> list[tuple[str, ...]]:
    """Each demonstration's labels with blanks, the initial state's proposition and repeats removed."""
    initial = learner.labeling_.propositions[learner.machine_.initial]
    words = []
    for word in learner.label_words_:
        letters = []
        for label in word:
            if len(label) == 1 and (p := next(iter(label))) != initial and (not letters or letters[-1] != p):
                letters.append(p)
        words.append(tuple(letters))
    return words


def live_graph_isomorphic(transitions: dict, initial, accepting: set, truth) -> tuple[int, bool]:
    """Live states (those that can still accept) of a peer's DFA and whether that part is the truth's graph."""
    from symlearn.learners.reward_machines.compare import isomorphic
    from symlearn.learners.reward_machines.machine_building import machine_from_edges

    states = sorted({initial, *transitions, *(t for row in transitions.values() for t in row.values())}, key=repr)
    live, changed = set(accepting), True
    while changed:
        changed = False
        for q in states:
            if q not in live and any(t in live for t in transitions.get(q, {}).values()):
                live.add(q)
                changed = True
    order = sorted(live, key=lambda q: (q != initial, repr(q)))
    index = {q: i for i, q in enumerate(order)}
    edges = {(index[q], f"x{index[t]}"): index[t] for q in order for t in transitions.get(q, {}).values()
             if t in live and t != q}
    if initial not in live:
        return 0, False
    peer = machine_from_edges([f"x{i}" for i in range(len(order))], edges, 0, [index[q] for q in accepting])
    return len(order), isomorphic(peer, truth)


def peers(demos, learner) -> dict:
    """Algorithm 7.1 vs dfa-identify vs AALpy RPNI on the same label sequences (see the module docstring)."""
    from symlearn.learners.reward_machines.machine_building import infer_transitions, machine_from_edges

    s = demos.task.truth_structure()
    truth = machine_from_edges(s["propositions"], s["edges"], s["initial"], s["accepting"])
    words = words_of(learner)
    alphabet = sorted({p for w in words for p in w})
    positives = sorted(set(words))
    negatives = sorted({w[:i] for w in positives for i in range(len(w))} - set(positives))
    out = {}
    names = learner.labeling_.propositions
    tick = time.perf_counter()
    delta = infer_transitions([[{p} for p in w] for w in words], {p: k for k, p in enumerate(names)},
                              learner.machine_.initial)
    seconds = time.perf_counter() - tick
    ends = set()
    for w in words:
        u = learner.machine_.initial
        for p in w:
            u = delta.get((u, p), u)
        ends.add(u)
    merged: dict = {}
    for (q, p), v in delta.items():
        merged.setdefault(q, {})[p] = v
    states, iso = live_graph_isomorphic(merged, learner.machine_.initial, ends, truth)
    out["algorithm_7_1"] = {"states": states, "isomorphic": iso, "seconds": seconds}
    try:
        from dfa_identify import find_dfa

        tick = time.perf_counter()
        found = find_dfa(accepting=[list(w) for w in positives], rejecting=[list(w) for w in negatives],
                         alphabet=frozenset(alphabet))
        seconds = time.perf_counter() - tick
        table = {q: {a: found._transition(q, a) for a in alphabet} for q in found.states()}
        states, iso = live_graph_isomorphic(table, found.start, {q for q in found.states() if found._label(q)}, truth)
        out["dfa_identify"] = {"states": states, "isomorphic": iso, "seconds": seconds}
    except ImportError:
        out["dfa_identify"] = None
    try:
        from aalpy.learning_algs import run_RPNI

        data = [(tuple(w), True) for w in positives] + [(tuple(w), False) for w in negatives]
        tick = time.perf_counter()
        model = run_RPNI(data, automaton_type="dfa", print_info=False)
        seconds = time.perf_counter() - tick
        table = {q: dict(q.transitions) for q in model.states}
        states, iso = live_graph_isomorphic(table, model.initial_state, {q for q in model.states if q.is_accepting},
                                            truth)
        out["aalpy_rpni"] = {"states": states, "isomorphic": iso, "seconds": seconds}
    except ImportError:
        out["aalpy_rpni"] = None
    return out


def fit(demos, **kwargs):
    from symlearn.errors import DataError
    from symlearn.learners.reward_machines.rm_inference import RewardMachineInference

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return RewardMachineInference(**kwargs).fit(demos.front), None
        except DataError as exc:
            return None, str(exc)


def run(seeds: list[int], feature_kinds: list[str]) -> dict:
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations
    from symlearn.learners.reward_machines.features import clear_cache

    rows, sensitivity, features, grids, peer_rows, sweep = [], [], [], {}, [], []
    for task in TASKS:
        for seed in seeds:
            tick = time.perf_counter()
            demos = demonstrations(task, seed=seed)
            render = time.perf_counter() - tick
            clear_cache()  # the defaults' time includes computing the features
            learner, error = fit(demos)
            row = {"task": task, "seed": seed, "frames": sum(len(t) for t in demos.front),
                   "demonstrations": len(demos.front), "render_seconds": render}
            row.update(score(demos, learner) if learner else {"error": error, "isomorphic": False})
            rows.append(row)
            print(f"{task:10s} seed {seed}: iso {row['isomorphic']} purity {row.get('purity', 0):.3f} "
                  f"states {row.get('states')} ({row.get('seconds', 0):.2f} s)", flush=True)
            if learner is None:
                continue
            if seed == seeds[0]:
                grids[task] = learner.prototype_frames_
            peer_rows.append({"task": task, "seed": seed, **peers(demos, learner)})
            for name, (what, factor) in VARIANTS.items():
                value = (learner.eps_ if what == "eps" else learner.kappa_) * factor
                varied, error = fit(demos, **{what: value})
                entry = {"task": task, "seed": seed, "variant": name, "value": value}
                entry.update(score(demos, varied) if varied else {"error": error, "isomorphic": False})
                sensitivity.append(entry)
            for what in ("eps", "kappa"):
                for factor in SWEEP:
                    value = (learner.eps_ if what == "eps" else learner.kappa_) * factor
                    varied, _ = fit(demos, **{what: value})
                    sweep.append({"task": task, "seed": seed, "parameter": what, "factor": factor,
                                  "isomorphic": bool(varied is not None and score(demos, varied)["isomorphic"])})
            for kind in feature_kinds:
                clear_cache()
                other, error = fit(demos, features=kind)
                entry = {"task": task, "seed": seed, "features": kind}
                entry.update(score(demos, other) if other else {"error": error, "isomorphic": False})
                features.append(entry)
    return {"defaults": rows, "sensitivity": sensitivity, "sweep": sweep, "features": features,
            "peers": peer_rows}, grids


def summarise(result: dict, feature_kinds: list[str]) -> dict:
    def rate(entries):
        return {"isomorphic": f"{sum(e['isomorphic'] for e in entries)}/{len(entries)}",
                "min_purity": min((e.get("purity", 0.0) for e in entries), default=0.0)}

    summary = {"defaults": rate(result["defaults"]),
               "defaults_per_task": {t: rate([r for r in result["defaults"] if r["task"] == t]) for t in TASKS},
               "seconds_max": max((r.get("seconds", 0) for r in result["defaults"]), default=0),
               "seconds_mean": float(np.mean([r.get("seconds", 0) for r in result["defaults"]])),
               "sensitivity": {v: rate([e for e in result["sensitivity"] if e["variant"] == v]) for v in VARIANTS},
               "sweep": {what: {str(f): f"{sum(e['isomorphic'] for e in result['sweep'] if e['parameter'] == what and e['factor'] == f)}"
                                        f"/{sum(1 for e in result['sweep'] if e['parameter'] == what and e['factor'] == f)}"
                                for f in SWEEP} for what in ("eps", "kappa")},
               "features": {"pca": rate(result["defaults"]), **{
                   k: {**rate([e for e in result["features"] if e["features"] == k]),
                       "seconds_mean": float(np.mean([e.get("seconds", 0) for e in result["features"]
                                                      if e["features"] == k]))} for k in feature_kinds}}}
    summary["peers"] = {}
    for name in ("algorithm_7_1", "dfa_identify", "aalpy_rpni"):
        found = [r[name] for r in result["peers"] if r.get(name)]
        if found:
            summary["peers"][name] = {"isomorphic": f"{sum(f['isomorphic'] for f in found)}/{len(found)}",
                                      "seconds_mean": float(np.mean([f["seconds"] for f in found])),
                                      "states_by_task": {t: sorted({r[name]["states"] for r in result["peers"]
                                                                    if r["task"] == t and r.get(name)}) for t in TASKS}}
    return summary


def figures(grids: dict, result: dict, folder: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from symlearn.atomic import write_bytes

    written = []
    columns = max(len(g) for g in grids.values())
    fig, axes = plt.subplots(len(grids), columns, figsize=(1.6 * columns, 1.7 * len(grids)), squeeze=False)
    for r, (task, images) in enumerate(grids.items()):
        for c in range(columns):
            ax = axes[r, c]
            ax.axis("off")
            if c < len(images):
                ax.imshow(images[c], interpolation="nearest")
                ax.set_title(f"{task} u{c}", fontsize=7)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    plt.close(fig)
    written.append(write_bytes(folder / "rm_inference_prototypes.png", buffer.getvalue()))

    fig, ax = plt.subplots(figsize=(6, 3.2))
    for what, colour in (("eps", "tab:blue"), ("kappa", "tab:orange")):
        shares = [np.mean([e["isomorphic"] for e in result["sweep"] if e["parameter"] == what and e["factor"] == f])
                  for f in SWEEP]
        ax.plot(SWEEP, shares, "o-", color=colour, label=f"{what} x factor")
    ax.axvspan(0.7, 1.3, color="grey", alpha=0.15, label="+-30 %")
    ax.set_xscale("log")
    ax.set_xticks(SWEEP)
    ax.set_xticklabels([str(f) for f in SWEEP])
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("factor on the derived default")
    ax.set_ylabel("share isomorphic to truth")
    ax.set_title("Sensitivity of the inferred machine (5 tasks x seeds)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    plt.close(fig)
    written.append(write_bytes(folder / "rm_inference_sensitivity.png", buffer.getvalue()))
    return written


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="2 seeds; PCA and random CNN only")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--output", type=Path, default=REPO / "benchmarks" / "results" / "rm_inference.json")
    parser.add_argument("--figures", type=Path, default=REPO / "docs" / "figures")
    args = parser.parse_args()
    seeds = list(range(2 if args.quick else args.seeds))
    kinds = ["random-cnn"] if args.quick else ["autoencoder", "random-cnn"]
    started = time.perf_counter()
    load_before = os.getloadavg()
    result, grids = run(seeds, kinds)
    from symlearn.atomic import write_text

    import sklearn
    import torch

    doc = {"benchmark": "rm_inference",
           "command": "benchmarks/rm_inference.py" + (" --quick" if args.quick else f" --seeds {args.seeds}"),
           "machine": {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
                       "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
                       "sklearn": sklearn.__version__, "torch": torch.__version__,
                       "load_average_before": load_before, "load_average_after": os.getloadavg()},
           "seeds": seeds, "seconds": time.perf_counter() - started,
           "summary": summarise(result, kinds), **result}
    args.output.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.output, json.dumps(doc, indent=1, default=float) + "\n")
    args.figures.mkdir(parents=True, exist_ok=True)
    files = figures(grids, result, args.figures)
    print(json.dumps(doc["summary"], indent=1))
    print("wrote", args.output, *files)


if __name__ == "__main__":
    main()
