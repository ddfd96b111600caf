"""Issue 24: neural MCE-ICRL's learned cost on detour tasks (lava_grid, speed_cart) and BlockedPoint.

For each task and seed (experts and demonstrations made once in ``--keep FOLDER`` and reused):

    symlearn train --env MOD:ID --algo ppo-lag -o expert.safetensors    (true cost; once)
    symlearn data record --env MOD:ID --policy expert.safetensors -o demos.npz   (once)
    symlearn learn icrl --env MOD:ID --demos demos.npz -o cost.safetensors [ICRL FLAGS]
    symlearn train --env MOD:ID --cost cost.safetensors                 (ppo-lag defaults)

and ``symlearn learn icrl --env blocked-point`` (reward, violation, recovery AUC). lava_grid's
learned cost is also printed over the 7 x 7 grid (the lava column is x = 3, y = 1..5).

    python benchmarks/icrl_detour.py --keep /tmp/detour --label after --seeds 0 1 2

``--label`` names the runs (they replace earlier runs of the same label, task and seed in
``--out``); ``--flags`` adds flags to every ``learn icrl``. Results: benchmarks/results/icrl_detour.json
(docs/BENCHMARKS.md, "Learned neural costs on detour tasks").
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fresh_user_crl import MODULES_ROUND2, TASKS_ROUND2, symlearn  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def lava_map(cost_path: Path, folder: Path) -> list[list[float]]:
    """The learned cost per step on each cell of the 7 x 7 grid (rows y = 6 .. 0)."""
    import numpy as np
    sys.path.insert(0, str(folder))
    import lava_grid  # noqa: F401  (registers LavaGrid-v0)
    from symlearn.learners.neural.neural_cost import NeuralCost

    cost = NeuralCost.load(cost_path)
    cells = np.array([[x, y] for y in range(6, -1, -1) for x in range(7)], np.float32)
    values = np.asarray(cost(cells)).reshape(7, 7)
    return [[round(float(v), 3) for v in row] for row in values]


def run(task: str, seed: int, folder: Path, label: str, flags: list[str]) -> dict:
    s = ["--seed", str(seed)]
    if task == "blocked_point":
        rec = symlearn([*s, "--json", "-q", "learn", "icrl", "--env", "blocked-point", *flags], folder)
        r = rec.get("result", {})
        out = {"task": task, "seed": seed, "label": label, "flags": flags, "seconds": rec["seconds"], "rc": rec["rc"],
               **{k: r.get(k) for k in ("reward", "violation_rate", "recovery_auc", "recovery_iou", "lambda")},
               "stderr": None if r else rec.get("stderr_tail")}
        print(task, seed, label, {k: out[k] for k in ("reward", "violation_rate", "recovery_auc")}, flush=True)
        return out
    env_id = TASKS_ROUND2[task]
    base = folder / f"{task}_s{seed}"
    base.mkdir(parents=True, exist_ok=True)
    expert, demos = base / "expert.safetensors", base / "demos.npz"
    if not demos.exists():
        symlearn(["train", "--env", env_id, *s, "--json", "--algo", "ppo-lag", "-o", str(expert)], folder)
        symlearn(["data", "record", "--env", env_id, "--policy", str(expert), *s, "-o", str(demos)], folder)
    cost = base / f"cost_{label}.safetensors"
    learn = symlearn([*s, "--json", "-q", "learn", "icrl", "--env", env_id, "--demos", str(demos), "-o", str(cost), *flags], folder)
    train = symlearn(["train", "--env", env_id, *s, "--json", "--cost", str(cost)], folder)
    out = {"task": task, "seed": seed, "label": label, "flags": flags, "learn_rc": learn["rc"], "learn_seconds": learn["seconds"],
           "lambda": learn.get("result", {}).get("metrics", {}).get("lambda"),
           "learn_final_sample": learn.get("result", {}).get("metrics", {}).get("final_sample"),
           "learn_history": [{k: h.get(k) for k in ("iteration", "lambdas", "reward", "violation_rate")}
                             for h in learn.get("result", {}).get("history", []) or []],
           "train_rc": train["rc"], "train": {k: train.get("result", {}).get(k) for k in ("return", "cost")},
           "train_stderr": train["stderr_tail"][-600:] if train["rc"] else None,
           "learn_stderr": learn["stderr_tail"][-600:] if learn["rc"] else None}
    if task == "lava_grid" and cost.exists():
        out["cost_map"] = lava_map(cost, folder)
    print(task, seed, label, out["train"], out["lambda"], flush=True)
    if "cost_map" in out:
        for row in out["cost_map"]:
            print("   ", " ".join(f"{v:6.2f}" for v in row), flush=True)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tasks", nargs="+", default=["lava_grid", "speed_cart", "blocked_point"])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--keep", type=Path, required=True)
    p.add_argument("--label", default="defaults")
    p.add_argument("--flags", default="", help="flags added to every learn icrl")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", type=Path, default=ROOT / "benchmarks/results/icrl_detour.json")
    a = p.parse_args()
    a.keep.mkdir(parents=True, exist_ok=True)
    for name, source in MODULES_ROUND2.items():
        (a.keep / f"{name}.py").write_text(source.lstrip())
    jobs = [(t, s) for t in a.tasks for s in a.seeds]
    with ThreadPoolExecutor(a.workers) as pool:
        results = list(pool.map(lambda j: run(*j, a.keep, a.label, a.flags.split()), jobs))
    previous = json.loads(a.out.read_text()) if a.out.exists() else {"runs": []}
    done = {(r["task"], r["seed"], r["label"]) for r in results}
    kept = [r for r in previous["runs"] if (r["task"], r["seed"], r["label"]) not in done]
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps({**previous, "runs": kept + results}, indent=1))
    print("wrote", a.out)


if __name__ == "__main__":
    main()
