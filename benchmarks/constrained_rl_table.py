"""Issue 24 section 3: the constrained-RL validation table, every agent at its defaults, as a user runs it.

For each task, each constrained agent is trained twice -- on the environment's true cost
(``info["cost"]``, no ``--cost``) and on a learned artefact -- and unconstrained PPO once, seeds
``--seeds``; every cell is one ``symlearn train ... --json --log CELL.csv`` process with nothing but
the task, the agent, the cost and the seed on its command line (default budget 50,000 steps,
default cost limit 0, 10 greedy evaluation episodes):

* agents: ``ppo-lag`` (ours), ``ppo-lag-auto`` (ours with ``--reset-actor auto``: the stall rule of
  :mod:`symlearn.rl.ppo.stall`, off by default), ``sb3-ppo-lag``, ``sb3-sac-lag``
  (stable-baselines3 with our multiplier callback), and ``ppo`` (ours, unconstrained: the reward a
  constraint costs);
* tasks and their learned artefacts, each learned once (seed 0) by the documented command:
  ``toy-navigation`` (``learn dnf --env toy-navigation --n-demos 20``, the README's recipe),
  ``blocked-point`` (``learn icrl --env blocked-point``: a neural cost), ``safenav-point-goal`` and
  ``safenav-car-goal`` (``learn dnf --env ...`` at its defaults).

Reported per task x cost x agent: greedy return and true cost per episode (mean and per seed), the
final multiplier, seconds; issue 24's target on every row (true cost <= the limit wherever any peer
reaches it, return >= 0.9 x the best peer's at that cost); and a figure of the training curves
(return and true cost per episode against steps, mean over seeds) from the ``--log`` files.

    python benchmarks/constrained_rl_table.py --seeds 0 1 2 --workers 2 \\
        --out benchmarks/results/constrained_rl_table --figure docs/figures/constrained_rl_curves.png

Cells append to ``OUT/cells.jsonl`` as they finish and are skipped when the command runs again
(a killed run resumes); ``OUT/logs/`` keeps every cell's CSV; ``OUT.json`` is the summary.
Driving (highway-env, ~30 ms a step: 25 min per 50k-step run) and blocked HalfCheetah (1M steps)
are left out at this budget; their runs are in docs/BENCHMARKS.md's driving and MuJoCo sections.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import subprocess
import sys
import time
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from symlearn.atomic import write_text  # noqa: E402

# task -> (environment, the command that learns its artefact (run in OUT), the artefact's file)
TASKS = {
    "toy-navigation": ("toy-navigation", ["learn", "dnf", "--env", "toy-navigation", "--n-demos", "20",
                                          "-o", "toy.dnf"], "toy.dnf"),
    "blocked-point": ("blocked-point", ["learn", "icrl", "--env", "blocked-point", "-o", "wall.safetensors"],
                      "wall.safetensors"),
    "safenav-point-goal": ("safenav-point-goal", ["learn", "dnf", "--env", "safenav-point-goal",
                                                  "-o", "point_goal.dnf"], "point_goal.dnf"),
    "safenav-car-goal": ("safenav-car-goal", ["learn", "dnf", "--env", "safenav-car-goal", "-o", "car_goal.dnf"],
                         "car_goal.dnf"),
}
CONSTRAINED = ("ppo-lag", "sb3-ppo-lag", "sb3-sac-lag")
OURS = "ppo-lag"
# our PPO-Lagrangian with the stall rule of symlearn.rl.ppo.stall (--reset-actor auto; off by default), beside
AUTO = "ppo-lag-auto"
COSTS = ("true", "learned")


def cell_id(task: str, cost: str, algo: str, seed: int) -> str:
    return f"{task}|{cost}|{algo}|s{seed}"


def log_path(out: Path, task: str, signal: str, algo: str, seed: int) -> Path:
    """Where a cell's ``--log`` CSV lies."""
    return out / "logs" / (cell_id(task, signal, algo, seed).replace("|", "_") + ".csv")


def run_logs(out: Path, rows: list[dict], task: str, signal: str, algo: str) -> list[Path]:
    """The logs of the finished cells of one task x signal x agent (one per seed)."""
    paths = [log_path(out, task, signal, algo, r["seed"]) for r in rows
             if (r["task"], r["signal"], r["algo"]) == (task, signal, algo) and "error" not in r]
    return [p for p in paths if p.exists()]


def cells(tasks: list[str], algos: list[str], seeds: list[int]) -> list[tuple[str, str, str, int]]:
    """Seed-major, cheap agents first: a partial run is already a table of the early seeds."""
    order = {"ppo-lag": 0, AUTO: 0, "ppo": 1, "sb3-ppo-lag": 2, "sb3-sac-lag": 3}
    out = []
    for seed in seeds:
        for algo in sorted(algos, key=order.get):
            for task in tasks:
                for cost in (("none",) if algo == "ppo" else COSTS):
                    out.append((task, cost, algo, seed))
    return out


def symlearn(*args: str, cwd: Path, timeout: float = 7200) -> subprocess.CompletedProcess:
    env = {**os.environ, "SYMLEARN_QUIET": "1", "OMP_NUM_THREADS": "1"}
    return subprocess.run([sys.executable, "-m", "symlearn", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, env=env)


def learn_artefacts(out: Path, tasks: list[str]) -> dict[str, dict]:
    """Each task's artefact, learned once by its documented command (kept when already there)."""
    done = {}
    for task in tasks:
        _, command, name = TASKS[task]
        started = time.perf_counter()
        if not (out / name).exists():
            result = symlearn(*command, "--json", cwd=out)
            if result.returncode != 0:
                raise SystemExit(f"{' '.join(command)}: {result.stderr.strip()[-400:]}")
        done[task] = {"command": "symlearn " + " ".join(command), "file": name,
                      "seconds": round(time.perf_counter() - started, 1)}
    return done


def run_cell(out: Path, task: str, cost: str, algo: str, seed: int, steps: int | None = None) -> dict:
    env, _, artefact = TASKS[task]
    log = log_path(out, task, cost, algo, seed)
    # the true cost: a Lagrangian algorithm without --cost constrains the environment's info["cost"]
    args = ["train", "--env", env, "--algo", OURS if algo == AUTO else algo, "--seed", str(seed), "--json",
            "--log", str(log.relative_to(out))]
    args += ["--reset-actor", "auto"] if algo == AUTO else []
    args += ["--cost", artefact] if cost == "learned" else []
    args += ["--steps", str(steps)] if steps else []
    started = time.perf_counter()
    result = symlearn(*args, cwd=out)
    row = {"id": cell_id(task, cost, algo, seed), "task": task, "signal": cost, "algo": algo, "seed": seed,
           "command": "symlearn " + " ".join(args), "wall": round(time.perf_counter() - started, 1)}
    if result.returncode != 0:
        return {**row, "error": result.stderr.strip()[-400:]}
    doc = json.loads(result.stdout)
    return {**row, **{k: doc.get(k) for k in ("return", "cost", "violation_rate", "multipliers", "seconds", "steps",
                                              "warnings", "actor_resets", "learned_cost")}}


def read_log(path: Path) -> list[dict[str, float]]:
    """The CSV's steps, return and true cost per episode (empty cells: episodes that did not end)."""
    rows = []
    with open(path, newline="") as handle:
        for raw in csv.DictReader(handle):
            def number(key: str) -> float:
                value = raw.get(key) or ""
                return float(value) if value else math.nan
            rows.append({"steps": number("steps"), "return": number("mean_return"), "true_cost": number("true_cost")})
    return rows


def binned_curve(paths: list[Path], steps: int, bins: int = 10) -> dict[str, list[float]]:
    """Return and true cost per episode in ``bins`` windows of the run, the mean over ``paths``
    (seeds) of each run's mean over the rows in the window (NaN rows skipped)."""
    import numpy as np

    edges = np.linspace(0, steps, bins + 1)
    per_run = {"return": [], "true_cost": []}
    for path in paths:
        rows = read_log(path)
        for key in per_run:
            series = []
            for lo, hi in zip(edges[:-1], edges[1:], strict=True):
                values = [r[key] for r in rows if lo < r["steps"] <= hi and not math.isnan(r[key])]
                series.append(float(np.mean(values)) if values else math.nan)
            per_run[key].append(series)
    curve = {"steps": [float(x) for x in edges[1:]]}
    for key, runs in per_run.items():
        stacked = np.array(runs, dtype=float)
        with warnings.catch_warnings():   # a window no seed finished an episode in: NaN, said by None
            warnings.simplefilter("ignore", RuntimeWarning)
            curve[key] = [None if math.isnan(v) else round(float(v), 4)
                          for v in (np.nanmean(stacked, axis=0) if len(stacked) else [])]
    return curve


def summarise(rows: list[dict], limit: float = 0.0) -> dict:
    """Per task x cost x agent: the mean and per-seed return and true cost; issue 24's target per
    task x cost (ours within the limit wherever a peer is, and at >= 0.9 x the best safe peer's return)."""
    import numpy as np

    table: dict[str, dict] = {}
    for row in rows:
        if "error" in row:
            continue
        key = f"{row['task']}|{row['signal']}|{row['algo']}"
        entry = table.setdefault(key, {"task": row["task"], "signal": row["signal"], "algo": row["algo"],
                                       "seeds": [], "return": [], "true_cost": [], "multiplier": []})
        entry["seeds"].append(row["seed"])
        entry["return"].append(row["return"])
        entry["true_cost"].append(row["cost"])
        entry["multiplier"].append(None if not row.get("multipliers") else max(row["multipliers"]))
    for entry in table.values():
        entry["mean_return"] = float(np.mean(entry["return"]))
        costs = [c for c in entry["true_cost"] if c is not None]
        entry["mean_true_cost"] = float(np.mean(costs)) if costs else None
    targets = {}
    for task in sorted({e["task"] for e in table.values()}):
        for cost in COSTS:
            ours = table.get(f"{task}|{cost}|{OURS}")
            peers = [table[f"{task}|{cost}|{a}"] for a in CONSTRAINED if a != OURS and f"{task}|{cost}|{a}" in table]
            if ours is None or not peers:
                continue
            safe_peers = [p for p in peers if p["mean_true_cost"] is not None and p["mean_true_cost"] <= limit]
            ours_safe = ours["mean_true_cost"] is not None and ours["mean_true_cost"] <= limit
            best = max((p["mean_return"] for p in safe_peers), default=None)
            verdict = {"ours_within_limit": ours_safe, "peers_within_limit": [p["algo"] for p in safe_peers],
                       "best_safe_peer_return": best, "ours_return": ours["mean_return"]}
            if not safe_peers:
                verdict["met"] = True if ours_safe else None   # nobody reaches the limit: nothing to compare with
            else:
                scale = 0.9 if best >= 0 else 1.1   # "0.9 x" read as "at most 10 % worse" for negative returns
                verdict["met"] = ours_safe and ours["mean_return"] >= scale * best
            targets[f"{task}|{cost}"] = verdict
    return {"table": table, "targets": targets}


def figure(out: Path, rows: list[dict], path: Path, steps: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tasks = sorted({r["task"] for r in rows if "error" not in r})
    fig, axes = plt.subplots(2 * len(COSTS), len(tasks), figsize=(4.2 * len(tasks), 11), squeeze=False)
    colours = {"ppo-lag": "tab:blue", AUTO: "tab:purple", "sb3-ppo-lag": "tab:orange", "sb3-sac-lag": "tab:green",
               "ppo": "tab:gray"}
    for j, task in enumerate(tasks):
        for c, cost in enumerate(COSTS):
            for algo in (*CONSTRAINED, AUTO, "ppo"):
                wanted = "none" if algo == "ppo" else cost
                paths = run_logs(out, rows, task, wanted, algo)
                if not paths:
                    continue
                curve = binned_curve(paths, steps)
                label = algo + ("" if algo == "ppo" else f" ({cost} cost)")
                for k, key in enumerate(("return", "true_cost")):
                    ax = axes[2 * c + k][j]
                    ys = [math.nan if v is None else v for v in curve[key]]
                    ax.plot(curve["steps"], ys, color=colours[algo], label=label, marker=".", markersize=3,
                            linestyle="--" if algo == "ppo" else "-")
            for k, key in enumerate(("return per episode", "true cost per episode")):
                ax = axes[2 * c + k][j]
                ax.set_title(f"{task}: {key}\n(constrained agents on the {cost} cost)", fontsize=9)
                ax.set_xlabel("environment steps", fontsize=8)
                ax.tick_params(labelsize=7)
                ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def markdown(summary: dict) -> str:
    def cell(entry: dict | None) -> str:
        if entry is None:
            return "-"
        cost = entry["mean_true_cost"]
        seeds = " / ".join(f"{r:.2f}" for r in entry["return"])
        costs = " / ".join("n/a" if c is None else f"{c:g}" for c in entry["true_cost"])
        return f"**{entry['mean_return']:.2f}** at {'n/a' if cost is None else f'{cost:.1f}'} ({seeds}; cost {costs})"

    table = summary["table"]
    lines = ["| task | cost | ours ppo-lag | ours, --reset-actor auto | sb3-ppo-lag | sb3-sac-lag | ppo (unconstrained) "
             "| target |", "|---|---|---|---|---|---|---|---|"]
    for task in sorted({e["task"] for e in table.values()}):
        for cost in COSTS:
            verdict = summary["targets"].get(f"{task}|{cost}", {})
            met = {True: "met", False: "**not met**", None: "no agent within the limit"}.get(verdict.get("met"), "-")
            lines.append(f"| {task} | {cost} | " + " | ".join(cell(table.get(f"{task}|{cost}|{a}"))
                                                           for a in (OURS, AUTO, *CONSTRAINED[1:]))
                         + f" | {cell(table.get(f'{task}|none|ppo'))} | {met} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--tasks", nargs="+", choices=list(TASKS), default=list(TASKS))
    parser.add_argument("--algos", nargs="+", choices=(*CONSTRAINED, AUTO, "ppo"), default=[*CONSTRAINED, AUTO, "ppo"])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--steps", type=int, default=None, help="training steps per cell (default: train's own, 50k)")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/constrained_rl_table"))
    parser.add_argument("--figure", type=Path, default=Path("docs/figures/constrained_rl_curves.png"))
    parser.add_argument("--report-only", action="store_true", help="summarise the cells run so far")
    args = parser.parse_args(argv)
    out = args.out.resolve()
    (out / "logs").mkdir(parents=True, exist_ok=True)
    store = out / "cells.jsonl"
    rows = [json.loads(line) for line in store.read_text().splitlines()] if store.exists() else []
    finished = {r["id"] for r in rows if "error" not in r}
    artefacts = {}
    if not args.report_only:
        artefacts = learn_artefacts(out, args.tasks)
        todo = [c for c in cells(args.tasks, args.algos, args.seeds) if cell_id(*c) not in finished]
        print(f"{len(todo)} cells to run ({len(finished)} finished before)", flush=True)
        with ThreadPoolExecutor(args.workers) as pool:
            for row in pool.map(lambda c: run_cell(out, *c, steps=args.steps), todo):
                rows = [r for r in rows if r["id"] != row["id"]] + [row]
                write_text(store, "".join(json.dumps(r) + "\n" for r in rows))
                shown = row.get("error") or (f"return {row['return']:.2f}, true cost {row['cost']}, "
                                             f"multipliers {row['multipliers']}, {row['wall']} s")
                print(f"{row['id']}: {shown}", flush=True)
    summary = summarise(rows)
    steps = max((r.get("steps") or 0 for r in rows), default=50_000)
    figure(out, rows, args.figure, steps)
    doc = {"command": "python benchmarks/constrained_rl_table.py " + " ".join(argv if argv is not None else sys.argv[1:]),
           "machine": {"python": platform.python_version(), "cpus": os.cpu_count()}, "artefacts": artefacts,
           **summary,
           "curves": {f"{t}|{c}|{a}": binned_curve(run_logs(out, rows, t, c, a), steps)
                      for t, c, a in sorted({(r["task"], r["signal"], r["algo"]) for r in rows if "error" not in r})},
           "errors": [r for r in rows if "error" in r]}
    write_text(out.with_suffix(".json"), json.dumps(doc, indent=1))
    print(markdown(summary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
