"""stable-baselines3 on our backends: counterfactual reward-machine experiences in a replay buffer.

Shields need no glue: :class:`~symlearn.backends.shield.Shield` has the ``action_masks()``
method that sb3-contrib's ``MaskablePPO`` asks every environment for. Reward machines need one
piece: :func:`counterfactual_callback` returns a stable-baselines3 callback that, after every
environment step, adds the counterfactual experiences a
:class:`~symlearn.backends.reward_machine.RewardMachineWrapper` (built with
``counterfactual=True``) reports in ``info["crm_experiences"]`` to the learner's replay buffer:
CRM for any off-policy learner (DQN, QR-DQN, SAC, TD3), not only our tabular one.

The experience of the machine state the agent was really in is the real transition, which the
learner stores itself; the callback adds the others. stable-baselines3 is imported only here and
only when asked for; without it, :class:`~symlearn.errors.MissingDependencyError` says how to
install it (``pip install 'symlearn[sb3]'``).

Example (not run here: it trains a network)::

    world = make_office_world()
    env = RewardMachineWrapper(world, task_machine("F a"), world.labeling,
                               observation="discrete", counterfactual=True)
    DQN("MlpPolicy", env).learn(20_000, callback=counterfactual_callback())
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np

from symlearn.errors import SymlearnError
from symlearn.optional import require

__all__ = ["counterfactual_callback"]


def counterfactual_callback(verbose: int = 0) -> Any:
    """A ``stable_baselines3`` ``BaseCallback`` adding counterfactual experiences to the replay
    buffer of an off-policy learner; its ``n_added`` counts them."""
    require("sb3", "adding counterfactual experiences to a stable-baselines3 learner")
    return _callback_class()(verbose=verbose)


@cache
def _callback_class() -> type:
    from gymnasium import spaces
    from stable_baselines3.common.buffers import DictReplayBuffer, ReplayBuffer
    from stable_baselines3.common.callbacks import BaseCallback

    class CounterfactualExperienceCallback(BaseCallback):
        """Replays every step for all the other machine states (see :mod:`symlearn.backends.sb3`)."""

        def __init__(self, verbose: int = 0) -> None:
            super().__init__(verbose)
            self.n_added = 0
            self._pending: list = []

        def _on_training_start(self) -> None:
            buffer = getattr(self.model, "replay_buffer", None)
            if buffer is None:
                raise SymlearnError(f"{type(self.model).__name__} has no replay buffer",
                                    hint="counterfactual experiences need an off-policy learner (DQN, SAC, TD3)")
            # Other buffers read meaning into where an entry sits (n-step returns, the next
            # observation stored in the following slot); inserted experiences would break it.
            if type(buffer) not in (ReplayBuffer, DictReplayBuffer) or buffer.optimize_memory_usage:
                raise SymlearnError(f"cannot add counterfactual experiences to a {type(buffer).__name__}"
                                    + (" with optimize_memory_usage" if buffer.optimize_memory_usage else ""),
                                    hint="use the default ReplayBuffer (n_steps=1, optimize_memory_usage=False)")

        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "crm_experiences" not in info:
                    raise SymlearnError("the environment reports no counterfactual experiences",
                                        hint="wrap it with RewardMachineWrapper(..., counterfactual=True)")
                real = info["rm_previous_state"]
                self._pending.extend(e for e in info["crm_experiences"] if e.machine_state != real)
            # The buffer takes one experience per environment slot at a time; the slot an
            # experience lands in does not matter to uniform replay.
            n_envs = self.model.replay_buffer.n_envs
            while len(self._pending) >= n_envs:
                batch, self._pending = self._pending[:n_envs], self._pending[n_envs:]
                self._add(batch)
            return True

        def _add(self, batch: list) -> None:
            buffer = self.model.replay_buffer
            actions = np.array([e.action for e in batch])
            if isinstance(self.model.action_space, spaces.Box):
                actions = self.model.policy.scale_action(actions)  # what the learner itself stores
            buffer.add(_stack([e.observation for e in batch]), _stack([e.next_observation for e in batch]),
                       actions, np.array([e.reward for e in batch], dtype=np.float32),
                       np.array([e.terminated for e in batch], dtype=np.float32), [{} for _ in batch])
            self.n_added += len(batch)

    return CounterfactualExperienceCallback


def _stack(observations: list) -> Any:
    """A batch of observations in the form a replay buffer takes (a dict of arrays for Dict)."""
    if isinstance(observations[0], dict):
        return {key: np.array([o[key] for o in observations]) for key in observations[0]}
    return np.array(observations)
