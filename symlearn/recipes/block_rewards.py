"""Everything DQRM needs on a rendered block task, from the task's name (a recipe).

:func:`block_setup` renders the scripted demonstrations, infers the machine and its labeling from
the front camera (or takes the ground-truth machine, or a machine file written by ``symlearn learn
rm`` with its labeling beside it), shapes it (``Psi = gamma ** d``), takes the top-down frames of
the prototypes for the place network, and replays the demonstrator's actions for the replay buffers.
It is a recipe because it joins an environment (``envs``) and a learner (``learners``), which
neither layer may do itself. ``symlearn train --env blockworld-stack2 --algo dqrm|dqn``, the ``rm``
demo and ``benchmarks/dqrm_blocks.py`` use it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np


@dataclass
class BlockSetup:
    task: str
    env_fn: Any
    machine: Any  # shaped reward machine
    labeling: Any  # info -> propositions
    prototypes: np.ndarray  # top-down image per machine state
    demonstrations: list  # action lists of the scripted demonstrator
    source: str


def _top_prototypes_of_truth(task) -> np.ndarray:
    from symlearn.envs.rendered_blocks.render import top_down_view

    names = [name for name, _, _ in task.blocks]
    return np.stack([top_down_view(names, task.layout(c)) for c in task.configurations()])


def block_setup(task: str, machine: str = "inferred", *, seed: int = 0, gamma: float = 0.9) -> BlockSetup:
    """``machine``: ``"inferred"``, ``"truth"`` or the path of a machine JSON from ``learn rm``."""
    from symlearn.backends.goal_shaping import shape
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations
    from symlearn.envs.rendered_blocks.env import RenderedBlocksEnv
    from symlearn.envs.rendered_blocks.tasks import TASKS
    from symlearn.errors import DataError
    from symlearn.learners.reward_machines.machine_building import machine_from_edges

    if task not in TASKS:
        raise DataError(f"unknown block task {task!r}", hint="tasks: " + ", ".join(TASKS))
    env = RenderedBlocksEnv(task)
    actions = []
    for order in env.task.orderings():
        env.reset(seed=seed)
        run = []
        while (action := env.expert_action(order)) is not None:
            run.append(action)
            env.step(action)
        actions.append(run)
    if machine == "truth":
        s = env.task.truth_structure()
        truth = machine_from_edges(s["propositions"], s["edges"], s["initial"], s["accepting"])
        return BlockSetup(task, lambda: RenderedBlocksEnv(task), shape(truth, gamma), lambda info: info["truth"],
                          _top_prototypes_of_truth(env.task), actions, "ground truth")
    demos = demonstrations(task, seed=seed)
    if machine == "inferred":
        from symlearn.learners.reward_machines.rm_inference import RewardMachineInference

        learner = RewardMachineInference(gamma=gamma).fit(demos.front)
        labeling, rm, indices = learner.labeling_, learner.shaped_machine_, learner.prototype_indices_
        source = f"inferred from {len(demos.front)} demonstrations (seed {seed})"
    else:
        from symlearn.learners.reward_machines.labeling import PrototypeLabeling, check_machine_labeling
        from symlearn.logic.automata import RewardMachine

        path = Path(machine)
        rm = RewardMachine.load(path)
        labeling = PrototypeLabeling.load(path.with_name(path.with_suffix("").name + ".labeling.json"))
        check_machine_labeling(rm, labeling, source=str(path))
        if rm.potential is None:
            rm = shape(rm, gamma)
        frames = np.concatenate([t.states for t in demos.front])
        # the top-down prototype of a state: the demonstration frame its labeling is surest of
        distances = labeling.distances(frames)
        indices = [int(np.argmin(distances[:, k])) for k in range(rm.n_states)]
        source = str(path)
    tops = np.concatenate([t.states for t in demos.top])[indices]
    return BlockSetup(task, lambda: RenderedBlocksEnv(task), rm, lambda info: labeling.label(info["front"]), tops,
                      actions, source)


__all__ = ["BlockSetup", "block_setup"]
