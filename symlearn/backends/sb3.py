"""stable-baselines3 on our backends: counterfactual reward-machine experiences in a replay buffer,
a Lagrangian multiplier as a callback, and policy files without pickles.

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

A Lagrangian on any SB3 learner: the environments carry
:class:`~symlearn.backends.lagrangian.LagrangianReward` (reward ``r - lambda . c``) over a shared
:class:`~symlearn.backends.lagrangian.SharedMultipliers`, and :func:`lagrangian_callback` moves
``lambda`` from the costs the steps report. :func:`save_policy` / :func:`load_policy` keep a
model's policy as safetensors + JSON (``docs/FORMATS.md``); SB3's ``.zip`` unpickles on load, so
it is never written or read. :func:`check_action_space` refuses, in one line, an algorithm that
cannot act in an environment's action space (``docs/SB3.md`` walks the routes).

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
from symlearn.rl.episode_stats import NoCostReported, summed_cost

__all__ = ["ALGORITHMS", "check_action_space", "counterfactual_callback", "lagrangian_callback", "load_policy",
           "monitor_callback", "save_policy"]


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


# --------------------------------------------------------------------------------------------------
# algorithms, the Lagrangian multiplier as a callback, and policy files

# our name -> (stable-baselines3 class, the action spaces it takes)
ALGORITHMS: dict[str, tuple[str, tuple[str, ...]]] = {
    "ppo": ("PPO", ("Box", "Discrete", "MultiDiscrete", "MultiBinary")),
    "sac": ("SAC", ("Box",)),
    "dqn": ("DQN", ("Discrete",)),
}

POLICY_KIND = "sb3-policy"
_ACTIVATIONS = ("Tanh", "ReLU", "ELU", "LeakyReLU")


def check_action_space(algo: str, space: Any) -> None:
    """Refuse, in one line, an algorithm that cannot act in ``space``."""
    if algo not in ALGORITHMS:
        raise SymlearnError(f"unknown stable-baselines3 algorithm {algo!r}", hint="use " + ", ".join(ALGORITHMS))
    name, accepted = ALGORITHMS[algo]
    if type(space).__name__ not in accepted:
        others = [a for a, (_, spaces) in ALGORITHMS.items() if type(space).__name__ in spaces]
        raise SymlearnError(f"stable-baselines3 {name} acts only in {' or '.join(accepted)} action spaces, "
                            f"the environment's is {space}",
                            hint=("use sb3-" + " or sb3-".join(others)) if others else None)


def algorithm_class(algo: str) -> Any:
    require("sb3", f"training with stable-baselines3 {algo.upper()}")
    import stable_baselines3

    return getattr(stable_baselines3, ALGORITHMS[algo][0])


def quiet_logger() -> Any:
    """A logger with no outputs and no folder.

    SB3's own default (``configure``) creates ``SB3-<date>`` in the temporary directory on every
    ``learn`` even when it writes nothing there: hundreds of empty folders after a sweep. Our
    monitor callback reports progress and writes the CSV/TensorBoard logs itself.
    """
    from stable_baselines3.common.logger import Logger

    return Logger(folder=None, output_formats=[])


def lagrangian_callback(multipliers: Any, *, cost_key: str = "cost", update_every: int | None = None) -> Any:
    """A ``BaseCallback`` updating a :class:`~symlearn.backends.lagrangian.SharedMultipliers` from
    the ``info[cost_key]`` of the steps the learner takes.

    Every ``update_every`` environment steps (default: one rollout of an on-policy learner, 1000
    steps of an off-policy one) the multipliers take one step of their rule from the estimated
    cost per episode: the mean cost of the episodes that ended since the last update, or, when none
    did, the mean cost per step times the mean episode length seen so far (an update from every
    window of steps, not only from windows in which an episode ends). The environments must
    carry :class:`~symlearn.backends.lagrangian.LagrangianReward` with the same ``multipliers``.
    """
    require("sb3", "a PPO-/SAC-Lagrangian on stable-baselines3")
    return _lagrangian_class()(multipliers, cost_key, update_every)


@cache
def _lagrangian_class() -> type:
    from stable_baselines3.common.callbacks import BaseCallback

    class LagrangianCallback(BaseCallback):
        """The multiplier update of a Lagrangian on stable-baselines3 (:func:`lagrangian_callback`)."""

        def __init__(self, multipliers: Any, cost_key: str, update_every: int | None) -> None:
            super().__init__(0)
            self.multipliers, self.cost_key, self.update_every = multipliers, cost_key, update_every
            if update_every is not None and update_every < 1:
                raise SymlearnError(f"update_every must be >= 1, got {update_every}")

        def _on_training_start(self) -> None:
            n_envs = self.training_env.num_envs
            k = len(self.multipliers.values)
            if self.update_every is None:
                on_policy = getattr(self.model, "replay_buffer", None) is None
                self.update_every = int(self.model.n_steps) * n_envs if on_policy else 1000
            self._running = np.zeros((n_envs, k))             # cost of each copy's episode so far
            self._window_cost, self._window_steps = np.zeros(k), 0
            self._ended: list[np.ndarray] = []
            self._lengths: list[int] = []
            self._length = np.zeros(n_envs, dtype=np.int64)
            self._since = 0
            self._seen = False   # some step has reported info[cost_key]
            self.updates = 0     # multiplier steps taken (0: a run shorter than one window)

        def _on_step(self) -> bool:
            for i, (info, done) in enumerate(zip(self.locals["infos"], self.locals["dones"], strict=True)):
                raw = info.get(self.cost_key)
                if raw is None:   # a step without a cost costs 0 (one reported only where it is paid)
                    cost = np.zeros(self._running.shape[1])
                else:
                    cost = np.asarray(raw, dtype=np.float64).reshape(-1)
                    self._seen = True
                self._running[i] += cost
                self._window_cost += cost
                self._length[i] += 1
                if done:
                    self._ended.append(self._running[i].copy())
                    self._lengths.append(int(self._length[i]))
                    self._running[i], self._length[i] = 0.0, 0
            self._window_steps += len(self.locals["infos"])
            self._since += len(self.locals["infos"])
            if self._since >= self.update_every:
                self._check_seen()   # decided from the steps of the first rollout, not from the first step
                self._update()
            return True

        def _on_training_end(self) -> None:
            # a run shorter than one update window (SAC's 1,000 steps) never reached the check
            # above, and trained a Lagrangian with nothing to constrain in silence
            if self._since:
                self._check_seen()

        def _check_seen(self) -> None:
            if not self._seen:
                raise NoCostReported(f"the environment reported no info[{self.cost_key!r}] in the first "
                                     f"{self._since} steps", steps=self._since,
                                     hint="report it on the steps that pay it (a step without it costs 0), "
                                          "or wrap the environment with LagrangianReward over a cost")

        def _update(self) -> None:
            self.updates += 1
            if self._ended:
                estimate = np.mean(self._ended, axis=0)
            else:  # no episode ended in this window: its cost rate over a typical episode's length
                length = np.mean(self._lengths) if self._lengths else max(float(self._length.mean()), 1.0)
                estimate = self._window_cost / max(self._window_steps, 1) * length
            self.multipliers.update(estimate, self.num_timesteps)
            self.logger.record("lagrangian/cost", float(np.sum(estimate)))
            self.logger.record("lagrangian/multiplier", float(np.sum(self.multipliers.values)))
            self._ended, self._window_cost, self._window_steps, self._since = [], 0.0 * self._window_cost, 0, 0

    return LagrangianCallback


def monitor_callback(total_steps: int, *, log: Any = None, multipliers: Any = None, learned_cost: bool = False,
                     window: int | None = None, desc: str | None = None) -> Any:
    """A ``BaseCallback`` that shows a stable-baselines3 run as our PPO's is shown: a progress bar
    with the latest return and cost on a terminal, and, with ``log`` (a
    :class:`~symlearn.rl.training_log.TrainingLog`), one row per window of ``window`` environment
    steps (default: one rollout of an on-policy learner, 1000 steps of an off-policy one).

    A row has the columns our PPO's ``--log`` has, measured over the episodes that *ended* in the
    window (empty when none did): ``steps``, ``episodes``, ``mean_return`` (the environment's own
    reward, ``info["env_reward"]`` where a Lagrangian wrapper changed what the learner sees),
    ``mean_length``, ``learned_cost_i`` (with ``learned_cost``), ``true_cost`` (the environment's
    ``info["cost"]`` per episode; empty until a step has reported one), ``multipliers_i``,
    ``steps_per_second`` and ``seconds``.
    """
    require("sb3", "monitoring a stable-baselines3 run")
    return _monitor_class()(total_steps, log, multipliers, learned_cost, window, desc)


@cache
def _monitor_class() -> type:
    import time

    from stable_baselines3.common.callbacks import BaseCallback

    from symlearn.progress import ProgressBar

    class MonitorCallback(BaseCallback):
        """Progress bar and per-window log rows of a stable-baselines3 run (:func:`monitor_callback`)."""

        def __init__(self, total_steps: int, log: Any, multipliers: Any, learned_cost: bool,
                     window: int | None, desc: str | None) -> None:
            super().__init__(0)
            self.total_steps, self.log, self.multipliers = int(total_steps), log, multipliers
            self.learned_cost, self.window, self.desc = learned_cost, window, desc
            self.rows: list[dict[str, Any]] = []

        def _on_training_start(self) -> None:
            n_envs = self.training_env.num_envs
            if self.window is None:
                on_policy = getattr(self.model, "replay_buffer", None) is None
                self.window = int(self.model.n_steps) * n_envs if on_policy else 1000
            # per copy: the running episode's return, true cost, learned cost and length
            self._return, self._true = np.zeros(n_envs), np.zeros(n_envs)
            self._learned: np.ndarray | None = None
            self._length = np.zeros(n_envs, dtype=np.int64)
            self._ended: list[tuple[float, float, np.ndarray | None, int]] = []
            self._true_seen = False
            self._since, self._started = 0, time.perf_counter()
            self._window_started = self._started
            self._bar = ProgressBar(self.total_steps, desc=self.desc, unit="step")

        def _on_step(self) -> bool:
            rewards = np.asarray(self.locals["rewards"], dtype=np.float64).reshape(-1)
            for i, (info, done) in enumerate(zip(self.locals["infos"], self.locals["dones"], strict=True)):
                self._return[i] += float(info.get("env_reward", rewards[i]))
                cost = summed_cost(info, where=lambda: f"step {int(self._length[i])} of an episode of environment copy {i}")
                if cost is not None:
                    self._true[i] += cost
                    self._true_seen = True
                if self.learned_cost and info.get("learned_cost") is not None:
                    cost = np.asarray(info["learned_cost"], dtype=np.float64).reshape(-1)
                    if self._learned is None:
                        self._learned = np.zeros((len(rewards), cost.size))
                    self._learned[i] += cost
                self._length[i] += 1
                if done:
                    learned = None if self._learned is None else self._learned[i].copy()
                    self._ended.append((self._return[i], self._true[i], learned, int(self._length[i])))
                    self._return[i] = self._true[i] = 0.0
                    self._length[i] = 0
                    if self._learned is not None:
                        self._learned[i] = 0.0
            self._since += len(rewards)
            if self._since >= self.window:
                self._row()
            return True

        def _on_training_end(self) -> None:
            if self._since:
                self._row()
            self._bar.close()

        def _row(self) -> None:
            now = time.perf_counter()
            ended = self._ended

            def mean(values: list) -> float:
                return float(np.mean(values)) if len(values) else float("nan")

            row: dict[str, Any] = {"steps": int(self.num_timesteps), "episodes": len(ended),
                                   "mean_return": mean([e[0] for e in ended]),
                                   "mean_length": mean([e[3] for e in ended])}
            if self.learned_cost:
                learned = [e[2] for e in ended if e[2] is not None]
                row["learned_cost"] = (tuple(np.mean(learned, axis=0).tolist()) if learned
                                       else (float("nan"),) * (1 if self._learned is None else self._learned.shape[1]))
            row["true_cost"] = mean([e[1] for e in ended]) if self._true_seen else float("nan")
            if self.multipliers is not None:
                row["multipliers"] = tuple(float(m) for m in self.multipliers.values)
            row["steps_per_second"] = self._since / max(now - self._window_started, 1e-9)
            row["seconds"] = now - self._started
            self.rows.append(row)
            if self.log is not None:
                self.log.write(row)
            shown = {"return": row["mean_return"]}
            if self.learned_cost:
                shown["cost"] = float(np.sum(row["learned_cost"]))
            elif self._true_seen:
                shown["cost"] = row["true_cost"]
            if self.multipliers is not None:
                shown["lambda"] = float(np.max(self.multipliers.values))
            self._bar.update(self._since, **shown)
            self._ended, self._since, self._window_started = [], 0, now

    return MonitorCallback


def _space(space: Any) -> dict[str, Any]:
    """A JSON description of a gymnasium space, enough to tell two apart."""
    description: dict[str, Any] = {"kind": type(space).__name__, "shape": list(space.shape or ())}
    if hasattr(space, "n"):
        description["n"] = np.asarray(space.n).tolist()
    return description


def _descriptions(space: Any) -> list[dict[str, Any]]:
    """What :func:`save_policy` may have recorded for a model trained on ``space``: its own
    description, and for a channels-last picture the channels-first one stable-baselines3 trains
    on (it wraps such an environment in ``VecTransposeImage`` and the model keeps that space; a
    loaded model wraps the environment the same way, so the policy acts on it as trained)."""
    found = [_space(space)]
    from stable_baselines3.common.preprocessing import is_image_space, is_image_space_channels_first
    from stable_baselines3.common.vec_env import VecTransposeImage

    if is_image_space(space) and not is_image_space_channels_first(space):
        found.append(_space(VecTransposeImage.transpose_space(space)))
    return found


def save_policy(model: Any, path: Any, extra: dict[str, Any] | None = None) -> Any:
    """Write a stable-baselines3 model's policy as ``NAME.safetensors`` + ``NAME.json`` (weights and
    the settings to build it again; never SB3's pickled ``.zip``). Returns the weights path."""
    from symlearn.rl.model_files import save_torch_module

    policy = model.policy
    activation = getattr(policy, "activation_fn", None)
    config = {"algorithm": type(model).__name__, "policy": _policy_name(model),
              "net_arch": _plain(getattr(policy, "net_arch", None)),
              "activation": None if activation is None else activation.__name__,
              "observation": _space(model.observation_space), "action": _space(model.action_space),
              **(extra or {})}
    return save_torch_module(path, policy, config, kind=POLICY_KIND)


def load_policy(path: Any, env: Any) -> Any:
    """A stable-baselines3 model for ``env`` with the policy saved by :func:`save_policy` (the
    JSON names the algorithm and network; the weights are read from safetensors, nothing is
    unpickled). Refused when the file was written for other spaces."""
    import torch

    from symlearn.errors import ModelError
    from symlearn.rl.model_files import load_torch_module, read_model_config

    require("sb3", "loading a stable-baselines3 policy")
    import stable_baselines3

    config = read_model_config(path, kind=POLICY_KIND)
    classes = {name for name, _ in ALGORITHMS.values()}
    if config.get("algorithm") not in classes or config.get("policy") not in ("MlpPolicy", "MultiInputPolicy"):
        raise ModelError(f"not a policy this symlearn builds: {config.get('algorithm')!r} {config.get('policy')!r}",
                         file=str(path))
    for side, space in (("observation", env.observation_space), ("action", env.action_space)):
        if config.get(side) not in _descriptions(space):
            raise ModelError(f"the policy was trained for {side}s {config.get(side)}, the environment's are "
                             f"{_space(space)}", file=str(path))
    kwargs: dict[str, Any] = {}
    if config.get("net_arch") is not None:
        _check_net_arch(config["net_arch"], path)
        kwargs["net_arch"] = config["net_arch"]
    if config.get("activation") is not None:
        if config["activation"] not in _ACTIVATIONS:
            raise ModelError(f"unknown activation {config['activation']!r}", file=str(path))
        kwargs["activation_fn"] = getattr(torch.nn, config["activation"])
    algorithm = getattr(stable_baselines3, config["algorithm"])
    built: dict[str, Any] = {}

    def build(_: dict[str, Any]) -> Any:
        built["model"] = algorithm(config["policy"], env, policy_kwargs=kwargs, device="cpu")
        return built["model"].policy

    # SB3 moves its networks to a device as it builds them, which the meta-device preflight cannot
    # follow; the layer sizes were bounded above instead
    load_torch_module(path, build, kind=POLICY_KIND, meta_check=False)
    return built["model"]


#: the widest layer and the most layers a policy file may ask for (its sizes come from a file)
MAX_LAYER_WIDTH = 4096
MAX_LAYERS = 16


def _check_net_arch(net_arch: Any, path: Any) -> None:
    from symlearn.errors import ModelError

    def widths(value: Any) -> list[Any]:
        if isinstance(value, dict):
            return [w for v in value.values() for w in widths(v)]
        if isinstance(value, list):
            return [w for v in value for w in widths(v)] if any(isinstance(v, (list, dict)) for v in value) else value
        return [value]

    found = widths(net_arch)
    if (len(found) > 2 * MAX_LAYERS or
            not all(isinstance(w, int) and not isinstance(w, bool) and 1 <= w <= MAX_LAYER_WIDTH for w in found)):
        raise ModelError(f"the policy's net_arch {str(net_arch)[:80]} is not a list of at most {MAX_LAYERS} layer "
                         f"widths from 1 to {MAX_LAYER_WIDTH}", file=str(path))


def _policy_name(model: Any) -> str:
    from gymnasium import spaces

    return "MultiInputPolicy" if isinstance(model.observation_space, spaces.Dict) else "MlpPolicy"


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value
