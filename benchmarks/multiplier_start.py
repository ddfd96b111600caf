"""Where PPO-Lagrangian's multipliers start: 0 (before) against 1 (``--multiplier-init``), every
agent otherwise at ``symlearn train``'s defaults, as a user runs it (one CLI process per run).

Why 1 is a candidate: with return-unit advantages (``advantage_scale="returns"``, the default) the
reward's and each cost's advantages are both divided by their own return scale, so a multiplier
of 1 weighs a cost as much as the reward, whatever their units. Started at 0, the multiplier
climbs by about ``--multiplier-lr`` (0.1) per iteration, and for the first ~10 iterations the
policy learns from the reward alone: enough to commit to a forbidden short cut that it never
leaves (BlockedPoint with a learned wall, seed 2 of the validation table).

Tasks: the validation table's (``benchmarks/constrained_rl_table.py``: toy, BlockedPoint,
SafeNav Point/Car Goal, each on its true cost and on its learned artefact, learned once by the
documented command) and user modules outside the package (``tests/support``): the hazard
robot with a hand-written DNF, the rover on its true cost, the sparse-reward gap grid in three
layouts, and CartPole held left of a line. Besides the starts, the variants measure a slower
policy, faster multipliers, the reward's scale floor and SB3's PPO-Lagrangian as the peer.

    python benchmarks/multiplier_start.py --seeds 0 1 2 3 4 --workers 2 \\
        --out benchmarks/results/multiplier_start

Runs append to ``OUT/runs.jsonl`` as they finish (a killed run resumes); ``OUT.json`` holds the
per-task summary: runs within the limit, mean greedy return and true cost per episode.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

import constrained_rl_table as table  # noqa: E402

from symlearn.atomic import write_text  # noqa: E402

VARIANTS = {"init 0": ["--multiplier-init", "0"], "init 1": ["--multiplier-init", "1"],
            "init 5": ["--multiplier-init", "5"],
            # the defaults (a hard constraint from 1) with the critics on raw returns
            "init 1, raw values": ["--multiplier-init", "1", "--no-normalize-values"],
            # the gap grids' exploration limit: a slower policy, a faster multiplier, and the peer
            "policy lr 2.5e-4": ["--learning-rate", "2.5e-4"], "multiplier lr 0.5": ["--multiplier-lr", "0.5"],
            "multiplier lr 0.25": ["--multiplier-lr", "0.25"],
            "sb3-ppo-lag": ["--algo", "sb3-ppo-lag"],
            # the reward's return scale held at its largest spread (LagrangianConfig.reward_scale_floor)
            "reward floor 1": ["--reward-scale-floor", "1"], "reward floor 0.1": ["--reward-scale-floor", "0.1"],
            "reward floor 0.01": ["--reward-scale-floor", "0.01"]}
USER_TASKS = {
    "hazard-robot|learned": ["--env", "point_robot_env:HazardRobot-v0", "--cost", "hazard.dnf"],
    "rover|true": ["--env", "rover_env:Rover-v0", "--algo", "ppo-lag"],
    # sparse reward 1 at the goal behind a hazard wall with one gap: the safe route is a detour
    "gap-grid|true": ["--env", "gap_grid_env:GapGrid-v0", "--algo", "ppo-lag"],
    # the same with a wall of three cells (a gap of two rows), and with a step penalty of 0.01
    "gap-grid short wall|true": ["--env", "gap_grid_env:GapGrid-v0", "--algo", "ppo-lag",
                                 "--env-kwargs", '{"wall_rows": [2, 3, 4]}'],
    "gap-grid step penalty|true": ["--env", "gap_grid_env:GapGrid-v0", "--algo", "ppo-lag",
                                   "--env-kwargs", '{"step_reward": -0.01}'],
    # CartPole with a line the cart must stay left of: balancing is easy on both sides
    "cartpole line|true": ["--env", "cartpole_cost_env:CartPoleRightOfLine-v0", "--algo", "ppo-lag"],
    # the rover's safe route is a detour the reward does not point to: at its target by 150k steps
    "rover 150k|true": ["--env", "rover_env:Rover-v0", "--algo", "ppo-lag", "--steps", "150000"],
}


def tasks() -> dict[str, list[str]]:
    """Every task's ``train`` arguments, the validation table's and the user modules'."""
    out = {}
    for task, (env, _, artefact) in table.TASKS.items():
        out[f"{task}|true"] = ["--env", env, "--algo", "ppo-lag"]
        out[f"{task}|learned"] = ["--env", env, "--cost", artefact]
    return {**out, **USER_TASKS}


def prepare(folder: Path) -> dict:
    """The user modules, the hand-written formula and the learned artefacts, in ``folder``."""
    for module in ("point_robot_env.py", "rover_env.py", "gap_grid_env.py", "cartpole_cost_env.py"):
        shutil.copy(REPO / "tests" / "support" / module, folder)
    (folder / "hazard.dnf").write_text("x > 0.4 & x < 0.6 & y < 0.6\n")
    return table.learn_artefacts(folder, list(table.TASKS))


def run(folder: Path, task: str, variant: str, seed: int) -> dict:
    args = ["train", *tasks()[task], *VARIANTS[variant], "--seed", str(seed), "--json"]
    started = time.perf_counter()
    result = table.symlearn(*args, cwd=folder)
    row = {"id": f"{task}|{variant}|s{seed}", "task": task, "variant": variant, "seed": seed,
           "command": "symlearn " + " ".join(args), "wall": round(time.perf_counter() - started, 1)}
    if result.returncode != 0:
        return {**row, "error": result.stderr.strip()[-400:]}
    doc = json.loads(result.stdout)
    return {**row, **{k: doc.get(k) for k in ("return", "cost", "learned_cost", "cost_limit", "cost_limit_from",
                                              "multipliers", "seconds", "warnings")}}


def summarise(rows: list[dict]) -> dict:
    out: dict = {}
    for row in rows:
        if "error" in row:
            continue
        entry = out.setdefault(row["task"], {}).setdefault(row["variant"], {"runs": []})
        entry["runs"].append({k: row[k] for k in ("seed", "return", "cost", "learned_cost", "multipliers")})
    for variants in out.values():
        for entry in variants.values():
            runs = entry["runs"]
            entry["n"] = len(runs)
            entry["true_cost_zero"] = sum(1 for r in runs if r["cost"] == 0)
            # the gap grids: safe *and* at the goal (their return is positive only there)
            entry["true_cost_zero_return_positive"] = sum(1 for r in runs if r["cost"] == 0 and r["return"] > 0)
            entry["mean_return"] = sum(r["return"] for r in runs) / len(runs)
            entry["mean_true_cost"] = sum(r["cost"] for r in runs) / len(runs)
    return out


def markdown(summary: dict) -> str:
    names = list(VARIANTS)
    lines = ["| task | " + " | ".join(f"{v}: true cost 0 / mean return / mean true cost" for v in names) + " |",
             "|---|" + "---|" * len(names)]
    for task, variants in summary.items():
        cells = []
        for name in names:
            e = variants.get(name)
            cells.append("--" if e is None else
                         f"{e['true_cost_zero']}/{e['n']} / {e['mean_return']:.2f} / {e['mean_true_cost']:.1f}")
        lines.append(f"| {task} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    parser.add_argument("--tasks", nargs="+", choices=list(tasks()), default=list(tasks()))
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/multiplier_start"))
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args(argv)
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    store = out / "runs.jsonl"
    rows = [json.loads(line) for line in store.read_text().splitlines()] if store.exists() else []
    artefacts = {}
    if not args.report_only:
        artefacts = prepare(out)
        finished = {r["id"] for r in rows if "error" not in r}
        jobs = [(t, v, s) for s in args.seeds for t in args.tasks for v in args.variants
                if f"{t}|{v}|s{s}" not in finished]
        print(f"{len(jobs)} runs to do", flush=True)
        with ThreadPoolExecutor(args.workers) as pool:
            for row in pool.map(lambda job: run(out, *job), jobs):
                rows = [r for r in rows if r["id"] != row["id"]] + [row]
                write_text(store, "".join(json.dumps(r) + "\n" for r in rows))
                print(row["id"], row.get("error") or f"return {row['return']:.2f} cost {row['cost']} "
                      f"multipliers {row['multipliers']}", flush=True)
    summary = summarise(rows)
    doc = {"command": "python benchmarks/multiplier_start.py " + " ".join(argv if argv is not None else sys.argv[1:]),
           "artefacts": artefacts, "summary": summary, "errors": [r for r in rows if "error" in r]}
    write_text(out.with_suffix(".json"), json.dumps(doc, indent=1))
    print(markdown(summary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
