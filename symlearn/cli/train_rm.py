"""``symlearn train --env blockworld-TASK --algo dqrm|dqn``: DQRM or DQN on a rendered block task.

The handler :func:`train_blocks` is what ``train_command`` calls for these two algorithms:

* ``--algo dqrm``: DQRM on ``--machine`` (a ``machine.json`` from ``symlearn learn rm``, its
  ``machine.labeling.json`` beside it), or on the machine inferred from the task's scripted
  demonstrations when no ``--machine`` is given, or ``--machine truth`` for the ground truth;
* ``--algo dqn``: one pair of networks on the same machine's shaped reward (``--reward shaped``,
  default) or on the environment's sparse reward (``--reward sparse``).

``--steps N`` bounds the environment steps (episodes = N / moves per episode); ``-o agent.safetensors``
writes the networks (safetensors + JSON). JSON keys: ``env``, ``algo``, ``machine``, ``success``
(greedy, mean of the last three evaluations), ``placement_error``, ``first_success_episode``,
``curve`` (one record per evaluation), ``episodes``, ``seconds``, ``files``.
"""

from __future__ import annotations

import argparse


def train_blocks(args: argparse.Namespace, out) -> None:
    from symlearn.envs.registry import Kind, names
    from symlearn.errors import DataError
    from symlearn.recipes.block_rewards import block_setup
    from symlearn.recipes.environments import resolve_env
    from symlearn.rl.dqrm import DQRMConfig, train_dqrm

    target = resolve_env(str(args.env), kind=Kind.MACHINE, what="rendered block task")
    if not target.has_kind(Kind.MACHINE):
        raise DataError(f"--algo {args.algo} trains on a rendered block task, not {args.env!r}",
                        hint="use --env " + ", ".join(names(Kind.MACHINE)))
    task = target.entry.env.kwargs["task"]
    if args.steps < 1:
        raise DataError(f"--steps must be at least 1, got {args.steps}")
    reward = getattr(args, "reward", None) or "shaped"
    if reward not in ("shaped", "sparse"):
        raise DataError(f"--reward must be shaped or sparse, got {reward!r}")
    if args.output and not str(args.output).endswith(".safetensors"):
        raise DataError(f"-o must name a .safetensors file, got {args.output!r}")
    machine = getattr(args, "machine", None) or "inferred"
    method = "dqrm" if args.algo == "dqrm" else ("dqn-shaped" if reward == "shaped" else "dqn-sparse")
    seed = getattr(args, "seed", 0) or 0
    setup = block_setup(task, machine, seed=seed)
    moves = setup.env_fn().max_moves
    episodes = max(args.steps // moves, 1)
    config = DQRMConfig(episodes=episodes, learning_rate=getattr(args, "learning_rate", None) or 1e-3,
                        updates_per_episode=8, eval_every=min(5, episodes))
    result = train_dqrm(setup.env_fn, setup.machine, setup.labeling, setup.prototypes, method=method,
                        demonstrations=setup.demonstrations, config=config, seed=seed)
    curve = [h.as_dict() for h in result.history]
    last = curve[-3:]
    doc = {"env": args.env, "algo": args.algo, "method": method, "machine": setup.source,
           "success": sum(h["success"] for h in last) / len(last),
           "placement_error": sum(h["placement_error"] for h in last) / len(last),
           "first_success_episode": next((h["episode"] for h in curve if h["success"] == 1.0), None),
           "curve": curve, "episodes": episodes, "seconds": result.seconds, "files": []}
    if args.output:
        path = result.save(args.output, {"task": task, "method": method, "episodes": episodes})
        doc["files"] = [str(path), str(path.with_suffix(".json"))]
    out.result(doc, _render)


def _render(doc: dict) -> str:
    lines = [f"{doc['env']}: {doc['method']} on {doc['machine']}, {doc['episodes']} episodes in {doc['seconds']:.1f} s",
             f"greedy success {doc['success']:.2f}, placement error {doc['placement_error']:.3f}, first success at "
             f"episode {doc['first_success_episode']}"]
    lines += [f"wrote {f}" for f in doc["files"]]
    return "\n".join(lines)


__all__ = ["train_blocks"]
