"""The thesis' realistic traffic experiment (section 2.5.3, Fig. 2.3 in shape) on our highway.

Two tasks, ``driving-velocity`` (speed along the road at most 25 m/s) and ``driving-distance`` (a
gap of at least 10 m to the car ahead), from :mod:`symlearn.envs.driving.traffic_constraints`.
Per task and seed, every cell is the real command a user runs, in a child process, with nothing
but the budget on its command line (the learners' and the agents' defaults otherwise):

* ``symlearn learn icrl --env TASK --method M --steps N --iterations I`` for each method (MCE-ICRL
  by default; ``--methods`` adds Malik et al.'s ME-ICRL, VME-ICRL and GACL): 20 IDM/MOBIL
  demonstrations that obey the constraint, the policy of the last iteration evaluated on 20
  episodes against the true constraint, the learned cost's recovery of the true unsafe set;
* ``symlearn train --env TASK --algo ppo --steps N``: the unconstrained agent (what the
  constraint costs), and ``--algo ppo-lag``: PPO-Lagrangian on the true cost, limit 0 -- the
  thesis' "expert trained with the ground truth".

    python benchmarks/icrl_driving.py --steps 80000 --iterations 5 --seeds 0
    python benchmarks/icrl_driving.py --table benchmarks/results/icrl_driving.json   # the table again

Writes ``benchmarks/results/icrl_driving.json`` (every cell's command and JSON output) and prints
a Markdown table. highway-env steps at ~30 ms; ours at a few hundred steps a second, so the
thesis' 10^6-step runs are out of reach here: the budget is named in the table.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
RESULTS = HERE / "results" / "icrl_driving.json"
TASKS = ("driving-velocity", "driving-distance")


def _run(words: list[str]) -> dict:
    """``symlearn WORDS --json`` in a child process: its JSON document, or the error's tail."""
    env = {**os.environ, "OMP_NUM_THREADS": "1", "PYTHONPATH": str(REPO)}
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "symlearn", "-q", *words, "--json"], capture_output=True,
                          text=True, env=env)
    seconds = time.perf_counter() - started
    if done.returncode != 0:
        return {"error": done.stderr.strip()[-500:], "seconds": seconds}
    doc = json.loads(done.stdout)
    doc["wall_seconds"] = seconds
    return doc


def cells(task: str, seed: int, steps: int, iterations: int, methods: list[str]) -> list[dict]:
    rows = []
    for method in methods:
        words = ["learn", "icrl", "--env", task, "--method", method, "--steps", str(steps),
                 "--iterations", str(iterations), "--seed", str(seed)]
        rows.append({"task": task, "seed": seed, "agent": method, "command": "symlearn " + " ".join(words),
                     "result": _run(words)})
        print(task, seed, method, json.dumps({k: rows[-1]["result"].get(k) for k in
                                              ("reward", "violation_rate", "recovery_auc", "error")}), flush=True)
    for algo in ("ppo", "ppo-lag"):
        words = ["train", "--env", task, "--algo", algo, "--steps", str(steps), "--seed", str(seed)]
        rows.append({"task": task, "seed": seed, "agent": algo, "command": "symlearn " + " ".join(words),
                     "result": _run(words)})
        print(task, seed, algo, json.dumps({k: rows[-1]["result"].get(k) for k in
                                            ("return", "cost", "violation_rate", "error")}), flush=True)
    return rows


def _reward(result: dict) -> float | None:
    return result.get("reward", result.get("return"))


def table(doc: dict) -> str:
    """Markdown: per task and agent, reward and violation rate (mean over seeds, then per seed)."""
    lines = ["| task | agent | reward | violation rate | recovery AUC | cost inputs | seconds |",
             "|---|---|---|---|---|---|---|"]
    groups: dict[tuple[str, str], list[dict]] = {}
    for row in doc["rows"]:
        groups.setdefault((row["task"], row["agent"]), []).append(row["result"])
    for (task, agent), results in groups.items():
        ok = [r for r in results if "error" not in r]
        if not ok:
            lines.append(f"| {task} | {agent} | error: {results[0]['error'][-120:]} | | | | |")
            continue

        def mean(values: list) -> str:
            values = [v for v in values if v is not None]
            return f"{sum(values) / len(values):.3g}" if values else "n/a"

        inputs = {", ".join(r["cost_inputs"]["names"] or []) for r in ok if r.get("cost_inputs")}
        lines.append(f"| {task} | {agent} | {mean([_reward(r) for r in ok])} | {mean([r.get('violation_rate') for r in ok])} "
                     f"| {mean([r.get('recovery_auc') for r in ok])} | {'; '.join(sorted(inputs))} "
                     f"| {mean([r['wall_seconds'] for r in ok])} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=80_000, help="PPO steps per run (80,000)")
    parser.add_argument("--iterations", type=int, default=5, help="ICRL iterations (5)")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--tasks", nargs="+", default=list(TASKS), choices=TASKS)
    parser.add_argument("--methods", nargs="+", default=["mce-icrl"],
                        choices=["mce-icrl", "me-icrl", "vme-icrl", "gacl"])
    parser.add_argument("--json", type=Path, default=RESULTS)
    parser.add_argument("--table", type=Path, help="print the table of a recorded run and stop")
    args = parser.parse_args(argv)
    if args.table:
        print(table(json.loads(args.table.read_text())))
        return 0
    started, load = time.perf_counter(), os.getloadavg()[0]
    rows = [row for task in args.tasks for seed in args.seeds
            for row in cells(task, seed, args.steps, args.iterations, args.methods)]
    doc = {"command": "python benchmarks/icrl_driving.py " + " ".join(argv if argv is not None else sys.argv[1:]),
           "steps": args.steps, "iterations": args.iterations, "seeds": args.seeds, "load_average_start": load,
           "seconds": time.perf_counter() - started, "rows": rows}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(doc, indent=1) + "\n")
    print(table(doc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
