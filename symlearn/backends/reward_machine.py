"""A reward machine on any gymnasium environment: the task becomes part of the state and the reward.

:class:`RewardMachineWrapper` runs a :class:`~symlearn.logic.automata.reward_machine.RewardMachine`
beside an environment. After every step a *labeling* (``observation -> set of propositions``; a
:class:`~symlearn.grounding.labeling.Labeling` or any such callable) reads the new observation,
the machine steps on that label from its state ``u`` to ``u'`` and pays ``r_u``:

* **observation**: the environment's observation joined with ``u'``, in one of four forms
  (``observation=``): ``"dict"`` -- ``{"env": obs, "rm": u}`` (stable-baselines3's
  ``MultiInputPolicy`` reads it); ``"tuple"`` -- ``(obs, u)``; ``"discrete"`` -- for a
  ``Discrete(n)`` environment, the product id ``obs * U + u`` of ``Discrete(n * U)`` (what a
  tabular learner or an ``MlpPolicy`` wants); ``"flat"`` -- a ``float32`` vector, the flattened
  observation (one-hot for ``Discrete``) followed by the one-hot ``u``.
* **reward**: ``reward="replace"`` (default) returns the machine's reward, ``"add"`` adds it to
  the environment's. ``shaping=gamma`` adds the potential-based term
  ``gamma * phi(u') - phi(u)`` with ``phi`` of
  :func:`~symlearn.logic.automata.reward_machine.task_potential` (or ``potential=``); a machine
  compiled with shaping already carries it and refuses a second dose.
* **termination**: the episode also ends when the machine reaches a terminal state (the task is
  done for good, or can no longer be done) and, with ``terminate_on_accept=True`` (default),
  when it reaches an accepting state: the finite trace so far satisfies the task.
* **info**: ``rm_state`` (``u'``; after ``reset`` the start state), ``rm_previous_state``
  (``u``), ``rm_reward``, ``env_reward`` and ``rm_label`` (the sorted propositions read).

The first observation is the first letter of the trace (as for LTLf and
:func:`~symlearn.rl.crm_q_learning.crm_q_learning`): ``reset`` steps the machine on its label
and drops that step's reward, which an episode has no place for.

**Counterfactual experiences** (CRM, Toro Icarte et al.): a real transition ``obs -a-> obs'``
says what would have happened in *every* machine state, because the labeling does not depend
on ``u``. :meth:`RewardMachineWrapper.counterfactual_experiences` lists those transitions
``(obs + u, a, r_u, obs' + u', done_u)``, one per machine state the agent can act in; with
``counterfactual=True`` every step reports them in ``info["crm_experiences"]`` for an
off-policy learner to replay (:func:`symlearn.backends.sb3.counterfactual_callback` does that
for stable-baselines3).

>>> from symlearn.envs.labelled_grid import LabelledGridEnv
>>> grid = LabelledGridEnv(3, 1, {(2, 0): {"a"}}, start=(0, 0))       # three cells, "a" on the right
>>> env = RewardMachineWrapper(grid, task_machine("F a"), grid.labeling, observation="tuple")
>>> env.reset(seed=0)[0]
(0, 0)
>>> [env.step(1)[:3] for _ in range(2)]   # right, right: the task is done
[((1, 0), 0.0, False), ((2, 1), 1.0, True)]
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any, Literal, NamedTuple

import gymnasium as gym
import numpy as np

from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.logic.automata.reward_machine import RewardMachine, task_potential

__all__ = ["Experience", "RewardMachineWrapper", "task_machine"]

RewardMode = Literal["replace", "add"]
ObservationMode = Literal["dict", "tuple", "discrete", "flat"]
_OBSERVATION_MODES = ("dict", "tuple", "discrete", "flat")


def task_machine(formula: Any, **options: Any) -> RewardMachine:
    """The reward machine of an LTLf task (text or a parsed formula): reward 1 on entering
    acceptance; ``options`` are those of
    :meth:`~symlearn.logic.automata.reward_machine.RewardMachine.from_dfa` (``reward``,
    ``shaping``, ``gamma``, ...).

    >>> task_machine("F a").run([set(), {"a"}])
    ([0, 0, 1], [0.0, 1.0])
    """
    return RewardMachine.from_formula(formula, **options)


class Experience(NamedTuple):
    """One transition as the wrapped environment would have reported it from machine state
    ``machine_state``; observations are in the wrapper's observation format."""

    observation: Any
    action: Any
    reward: float
    next_observation: Any
    terminated: bool
    machine_state: int
    next_machine_state: int


class RewardMachineWrapper(gym.Wrapper):
    """``RewardMachineWrapper(env, machine, labeling, *, reward="replace", shaping=None,
    potential=None, terminate_on_accept=True, observation="dict", counterfactual=False)``.

    See the module docstring for what each option does. ``labeling`` maps an observation of
    ``env`` to the propositions true in it; when it declares its propositions (a ``Labeling``),
    every proposition of the machine must be among them.
    """

    def __init__(
        self,
        env: gym.Env,
        machine: RewardMachine,
        labeling: Callable[[Any], Iterable[str]],
        *,
        reward: RewardMode = "replace",
        shaping: float | None = None,
        potential: Sequence[float] | None = None,
        terminate_on_accept: bool = True,
        observation: ObservationMode = "dict",
        counterfactual: bool = False,
    ) -> None:
        super().__init__(env)
        if not isinstance(machine, RewardMachine):
            raise ModelError(f"expected a RewardMachine, got {type(machine).__name__}",
                             hint="build one from a task with task_machine(formula)")
        if reward not in ("replace", "add"):
            raise SymlearnError(f"unknown reward mode {reward!r}", hint="use 'replace' or 'add'")
        if observation not in _OBSERVATION_MODES:
            raise SymlearnError(f"unknown observation mode {observation!r}",
                                hint="use " + ", ".join(repr(m) for m in _OBSERVATION_MODES))
        self.machine = machine
        self.labeling = labeling
        self._label_of = _label_function(labeling, machine)
        self.reward_mode = reward
        self.observation_mode = observation
        self.terminate_on_accept = bool(terminate_on_accept)
        self.counterfactual = bool(counterfactual)
        self.n_machine_states = machine.n_states
        self.shaping, self.potential = _shaping(machine, shaping, potential)
        self.observation_space = self._joint_space(env.observation_space)
        # The machine is immutable and labels repeat, so each (u, label) is decided once.
        self._steps: dict[tuple[int, frozenset[str]], tuple[int, float]] = {}
        self._observation: Any = None
        self._u = machine.initial

    # --- the machine ---------------------------------------------------------------------------
    @property
    def machine_state(self) -> int:
        """The machine state the agent is in now."""
        return self._u

    @property
    def acting_states(self) -> list[int]:
        """Machine states an episode can go on from: not terminal, and not accepting when
        reaching acceptance ends the episode."""
        return [u for u in self.machine.states if not self._ends(u)]

    def _ends(self, u: int) -> bool:
        return u in self.machine.terminal or (self.terminate_on_accept and u in self.machine.accepting)

    def machine_step(self, u: int, label: frozenset[str]) -> tuple[int, float]:
        """``(u', r)``: the machine's step with the shaping term included."""
        key = (u, label)
        if key not in self._steps:
            target, reward = self.machine.step(u, label)
            if self.potential is not None:
                reward += self.shaping * self.potential[target] - self.potential[u]
            self._steps[key] = (target, float(reward))
        return self._steps[key]

    def label(self, observation: Any) -> frozenset[str]:
        """The propositions the labeling says are true in ``observation``."""
        return self._label_of(observation)

    # --- observations ---------------------------------------------------------------------------
    def _joint_space(self, space: gym.Space) -> gym.Space:
        machine_space = gym.spaces.Discrete(self.n_machine_states)
        if self.observation_mode == "dict":
            return gym.spaces.Dict({"env": space, "rm": machine_space})
        if self.observation_mode == "tuple":
            return gym.spaces.Tuple((space, machine_space))
        if self.observation_mode == "discrete":
            if not isinstance(space, gym.spaces.Discrete):
                raise SymlearnError(f"observation='discrete' needs a Discrete observation space, got {space}",
                                    hint="use observation='dict' or 'flat'")
            return gym.spaces.Discrete(int(space.n) * self.n_machine_states)
        try:
            flat = gym.spaces.flatten_space(space)
        except NotImplementedError:
            raise SymlearnError(f"observation='flat' cannot flatten {space}",
                                hint="use observation='dict' or 'tuple'") from None
        low = np.concatenate([np.asarray(flat.low, np.float32).ravel(), np.zeros(self.n_machine_states, np.float32)])
        high = np.concatenate([np.asarray(flat.high, np.float32).ravel(), np.ones(self.n_machine_states, np.float32)])
        return gym.spaces.Box(low, high, dtype=np.float32)

    def augment(self, observation: Any, u: int) -> Any:
        """The wrapper's observation of environment observation ``observation`` in machine state ``u``."""
        if self.observation_mode == "dict":
            return {"env": observation, "rm": int(u)}
        if self.observation_mode == "tuple":
            return (observation, int(u))
        space = self.env.observation_space
        if self.observation_mode == "discrete":
            return (int(observation) - int(space.start)) * self.n_machine_states + int(u)
        one_hot = np.zeros(self.n_machine_states, np.float32)
        one_hot[int(u)] = 1.0
        return np.concatenate([np.asarray(gym.spaces.flatten(space, observation), np.float32).ravel(), one_hot])

    # --- gymnasium API -----------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        observation, info = self.env.reset(seed=seed, options=options)
        label = self.label(observation)
        # The first observation is the trace's first letter; its reward has nowhere to go.
        self._u, _ = self.machine_step(self.machine.initial, label)
        self._observation = observation
        info = dict(info)
        info.update(rm_state=self._u, rm_label=sorted(label))
        return self.augment(observation, self._u), info

    def step(self, action: Any):
        previous, u = self._observation, self._u
        observation, env_reward, terminated, truncated, info = self.env.step(action)
        label = self.label(observation)
        u2, machine_reward = self.machine_step(u, label)
        info = dict(info)
        info.update(rm_state=u2, rm_previous_state=u, rm_reward=machine_reward, env_reward=float(env_reward),
                    rm_label=sorted(label))
        if self.counterfactual:
            info["crm_experiences"] = self._experiences(previous, action, observation, float(env_reward),
                                                        bool(terminated), label)
        self._observation, self._u = observation, u2
        return (self.augment(observation, u2), self._reward(float(env_reward), machine_reward),
                bool(terminated) or self._ends(u2), truncated, info)

    def _reward(self, env_reward: float, machine_reward: float) -> float:
        return machine_reward if self.reward_mode == "replace" else env_reward + machine_reward

    # --- counterfactual experiences ------------------------------------------------------------------
    def counterfactual_experiences(self, observation: Any, action: Any, next_observation: Any,
                                   env_reward: float = 0.0, terminated: bool = False) -> list[Experience]:
        """Every machine state's version of the environment transition
        ``observation -action-> next_observation`` (``env_reward``; ``terminated`` by the
        environment itself), one :class:`Experience` per state of :attr:`acting_states`."""
        return self._experiences(observation, action, next_observation, float(env_reward), bool(terminated),
                                 self.label(next_observation))

    def _experiences(self, observation, action, next_observation, env_reward, terminated, label):
        experiences = []
        for u in self.acting_states:
            u2, machine_reward = self.machine_step(u, label)
            experiences.append(Experience(self.augment(observation, u), action,
                                          self._reward(env_reward, machine_reward),
                                          self.augment(next_observation, u2), terminated or self._ends(u2), u, u2))
        return experiences


def _label_function(labeling: Any, machine: RewardMachine) -> Callable[[Any], frozenset[str]]:
    """``observation -> frozenset`` from a Labeling or a callable, checked against the machine."""
    function = labeling.label if callable(getattr(labeling, "label", None)) else labeling
    if not callable(function):
        raise SymlearnError(f"a labeling must be callable (observation -> propositions), got {type(labeling).__name__}")
    declared = getattr(labeling, "propositions", None)
    if declared is not None:
        unknown = sorted(set(machine.alphabet) - set(declared))
        if unknown:
            raise DataError(f"the machine reads proposition {unknown[0]!r}, which the labeling does not know",
                            hint="known: " + ", ".join(declared))

    def label(observation: Any) -> frozenset[str]:
        props = function(observation)
        # A bare string would silently become a set of characters.
        if isinstance(props, str) or not isinstance(props, Iterable):
            raise DataError(f"a labeling must return a set of proposition names, got {props!r}")
        return frozenset(props)

    return label


def _shaping(machine: RewardMachine, shaping: Any, potential: Sequence[float] | None):
    """``(gamma, potential)`` of run-time shaping, or ``(None, None)`` without it."""
    if shaping is None or shaping is False:
        if potential is not None:
            raise SymlearnError("a potential without shaping has no effect", hint="pass shaping=<discount>")
        return None, None
    if isinstance(shaping, bool) or not isinstance(shaping, (int, float)) or not 0 < shaping <= 1:
        raise SymlearnError(f"shaping must be the agent's discount in (0, 1], got {shaping!r}")
    if machine.potential is not None:
        raise ModelError("this reward machine is shaped already (its rewards include the potential)",
                         hint="compile it without shaping or wrap it with shaping=None")
    values = task_potential(machine) if potential is None else [float(v) for v in potential]
    if len(values) != machine.n_states or not all(np.isfinite(values)):
        raise ModelError(f"the potential needs one finite number per machine state ({machine.n_states})")
    return float(shaping), tuple(values)
