"""Specification learning in a gymnasium environment that comes without a tabular model.

:class:`~symlearn.learners.temporal.spec_from_demos.SpecLearner` needs three things from a world:
label words of nominal behaviour (random at first), a nominal policy trained on a candidate
formula, and label words of that policy. With a successor table those come from
:mod:`symlearn.rl.crm_q_learning`; here they come from the environment itself:

* the policy update is RL on the product of the environment and the formula's automaton:
  tabular CRM Q-learning over hashable observations
  (:func:`~symlearn.rl.product_q_learning.product_q_learning`) when actions are discrete and
  observations are discrete or integer arrays (MiniGrid, grid worlds, ``Discrete`` spaces), or
  when a ``state_key`` is given; PPO on :class:`~symlearn.rl.product_env.ProductEnv` otherwise
  (float observations, continuous actions; a ``Dict``/``Tuple`` of numeric parts is flattened for
  the policy, and the labeling sees it whole);
* every observation is labelled by the user's labeling, called ``labeling(observation, info)``
  (see :mod:`symlearn.grounding.labeling_function`);
* demonstrations contribute their stored labels; unlabelled ones are labelled from their stored
  states by a labeling of observations alone, and by replaying their actions from the seed
  ``symlearn.data.record`` kept for a labeling that reads ``info`` (or the environment); without
  a seed, stored states are labelled with an empty ``info``.

Traces are kept as sequences of *label ids*: every distinct set of propositions met gets a
number (:attr:`EnvWorld.symbols`), so the learner's template search, which reads a trace as
"states" with a table of which atom holds in which, runs unchanged with label ids as states.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, ModelError, SymlearnError

__all__ = ["EnvWorld", "policy_route"]

_PACKAGE = Path(__file__).resolve().parents[2]  # the symlearn package folder


@contextmanager
def _environment_errors(doing: str) -> Iterator[None]:
    """An error raised by the user's environment code (not by symlearn) as one located line."""
    try:
        yield
    except SymlearnError:
        raise
    except Exception as exc:  # the user's environment: any error it raises is reported, located
        tb, last = exc.__traceback__, None
        while tb is not None:
            last, tb = tb, tb.tb_next
        where = last.tb_frame.f_code.co_filename if last is not None else ""
        if not where or Path(where).resolve().is_relative_to(_PACKAGE):
            raise  # our own bug: keep the traceback
        raise DataError(f"{doing}: the environment raised {type(exc).__name__}: {exc}", file=where,
                        line=last.tb_lineno) from None


def _float_leaf(space: Any) -> bool:
    """Whether a (possibly nested) observation space holds real-valued numbers."""
    inner = getattr(space, "spaces", None)
    if isinstance(inner, dict):
        return any(_float_leaf(s) for s in inner.values())
    if isinstance(inner, (tuple, list)):
        return any(_float_leaf(s) for s in inner)
    dtype = getattr(space, "dtype", None)
    return dtype is not None and np.dtype(dtype).kind == "f" and getattr(space, "n", None) is None


def _flat_parts(space: Any) -> bool:
    """Whether ``space`` is a ``Dict``/``Tuple`` gymnasium can flatten to one vector (numeric parts
    only: no text), which :class:`~symlearn.rl.product_env.ProductEnv` hands PPO flattened."""
    from gymnasium import spaces

    return isinstance(space, (spaces.Dict, spaces.Tuple)) and bool(getattr(space, "is_np_flattenable", False))


def policy_route(env: Any, state_key: Callable | None = None) -> str:
    """``"tabular"`` (discrete actions, and discrete observations or a state key) or ``"ppo"``."""
    discrete_actions = getattr(env.action_space, "n", None) is not None
    if discrete_actions and (state_key is not None or not _float_leaf(env.observation_space)):
        return "tabular"
    return "ppo"


_RECORD_HINT = "label the demonstrations while recording: symlearn.data.record(env, policy, n, labeler=...)"


def _own_state_key(env: Any) -> Callable | None:
    """A ``state_key(observation)`` method of the environment or of any wrapper around it."""
    seen = 0
    while env is not None and seen < 64:
        found = getattr(type(env), "state_key", None)
        if callable(found):
            return env.state_key
        env, seen = getattr(env, "env", None), seen + 1
    return None


def _plain(state: Any) -> Any:
    """A stored state as the environment would give it: numpy scalars as Python numbers."""
    return state.item() if isinstance(state, np.generic) else state


def _same_or_refuse(i: int, t: int, stored: Any, observation: Any, seed: Any) -> None:
    """A replayed observation must be the stored one where the two can be compared."""
    try:
        now = np.asarray(observation)
        kept = np.asarray(stored)
    except (TypeError, ValueError):
        return
    if now.dtype.kind in "biuf" and kept.dtype.kind in "biuf" and now.shape == kept.shape \
            and not np.allclose(now, kept):
        raise DataError(f"demonstration {i}: replaying its actions from seed {seed} reaches another observation "
                        f"at step {t} than the one stored", hint=_RECORD_HINT)


def _fitting_action(i: int, t: int, stored: Any, space: Any, discrete: bool, index_of: Any = None) -> Any:
    """A demonstration's action as the environment takes it; one of another shape (demonstrations
    recorded in another environment) is refused, not handed to the environment. ``index_of``: an
    environment that acts in the combinations of a MultiDiscrete space as one Discrete
    (``recipes.action_spaces.JointDiscreteActions``) maps a recorded action to its id."""
    action = np.asarray(stored)
    if discrete and index_of is not None and action.ndim == 1:
        return index_of(action)
    shape = getattr(space, "shape", None)
    fits = (action.ndim == 0 and action.dtype.kind in "biuf") if discrete else \
        (shape is None or action.shape == tuple(shape))
    if not fits:
        raise DataError(f"demonstration {i}, step {t}: an action of shape {action.shape} does not fit the "
                        f"environment's action space {space}",
                        hint="were the demonstrations recorded in this environment?")
    return int(action) if discrete else action


class EnvWorld:
    """Rollouts, labels and policy updates in ``env`` (an environment or a factory of them).

    ``policy`` is ``"auto"`` (see :func:`policy_route`), ``"tabular"`` or ``"ppo"``;
    ``state_key(env, observation) -> hashable`` replaces the observation as the Q-table key
    (MiniGrid's partial view, say, is not the state; ``lambda env, obs: env.unwrapped.hash()``
    is); the environment (or a wrapper around it) may also offer it as a
    ``state_key(observation)`` method, which is used when none is given.
    """

    def __init__(self, env: Any, labeling: Any, *, horizon: int | None = None, policy: str = "auto",
                 q_steps: int | None = None, ppo_steps: int | None = None, discount: float = 0.99,
                 epsilon: float = 0.1, learning_rate: float = 1.0,
                 state_key: Callable[[Any, Any], Hashable] | None = None) -> None:
        from symlearn.grounding.labeling_function import as_observation_labeler

        if hasattr(env, "reset") and not isinstance(env, type):  # an instance (a class is a factory)
            self.env, self._factory = env, None
        else:
            self._factory = env
            with _environment_errors("building the environment"):
                self.env = env()
        if labeling is None:
            labeling = getattr(getattr(self.env, "unwrapped", self.env), "labeling", None)
        if labeling is None:
            raise DataError("specification learning in this environment needs a labeling of its observations",
                            hint="give --labeling FILE.json|FILE.py:function (or labeling= in Python)")
        self.labeling = labeling
        self._label = as_observation_labeler(labeling)
        unwrapped = getattr(self.env, "unwrapped", self.env)
        # rollouts are in self.env, so a labeling taking the environment gets that one
        self.labeler = lambda observation, info, where="": self._label(observation, info, where, env=unwrapped)
        own_key = _own_state_key(self.env)
        if state_key is None and own_key is not None:
            state_key = lambda env_, obs: own_key(obs)  # noqa: E731 - the environment's documented hook
        self.state_key = state_key
        self.route = policy_route(self.env, state_key) if policy == "auto" else policy
        if self.route not in ("tabular", "ppo"):
            raise ModelError(f"policy must be 'auto', 'tabular' or 'ppo', got {policy!r}")
        space = getattr(self.env, "observation_space", None)
        # a scalar Box (shape ()) is one entry, which ProductEnv hands PPO as a vector of one; it
        # was refused as "needs array observations (a Box)", though it is a Box
        scalar_box = getattr(space, "shape", None) == () and getattr(space, "n", None) is None \
            and getattr(space, "low", None) is not None
        if self.route == "ppo" and not getattr(space, "shape", None) and not scalar_box and not _flat_parts(space):
            raise ModelError(f"a PPO policy update needs array observations (a Box), not {space}",
                             hint="wrap the environment (gymnasium.wrappers.FlattenObservation) or use the "
                                  "tabular update (--policy tabular)")
        if self.route == "tabular" and getattr(self.env.action_space, "n", None) is None:
            raise ModelError(f"a tabular policy update needs a Discrete action space, not {self.env.action_space}",
                             hint="use the PPO update (--policy ppo)")
        spec = getattr(self.env, "spec", None)
        self.horizon = int(horizon or getattr(spec, "max_episode_steps", None)
                           or getattr(getattr(self.env, "unwrapped", self.env), "max_steps", None) or 200)
        self.q_steps, self.ppo_steps = q_steps, ppo_steps
        self.discount, self.epsilon, self.learning_rate = discount, epsilon, learning_rate
        self.symbols: list[frozenset[str]] = []
        self._ids: dict[frozenset[str], int] = {}
        self.last_entropy: float | None = None

    # --- label ids ----------------------------------------------------------------------------
    @property
    def n_states(self) -> int:
        return len(self.symbols)

    def _trace(self, word: Sequence[frozenset[str]]) -> np.ndarray:
        ids = []
        for label in word:
            label = frozenset(label)
            found = self._ids.get(label)
            if found is None:
                found = self._ids[label] = len(self.symbols)
                self.symbols.append(label)
            ids.append(found)
        return np.asarray(ids, dtype=np.int64)

    def label(self, symbol: int) -> frozenset[str]:
        return self.symbols[int(symbol)]

    def word(self, trace: np.ndarray) -> list[frozenset[str]]:
        return [self.symbols[int(s)] for s in trace]

    def propositions(self) -> list[str]:
        """The labeling's declared propositions, then any other name met, in order."""
        names = list(getattr(self.labeling, "propositions", ()))
        for label in self.symbols:
            names += sorted(p for p in label if p not in names)
        return names

    def atoms(self, names: Sequence[str]) -> np.ndarray:
        return np.array([[p in label for p in names] for label in self.symbols], dtype=bool).reshape(
            len(self.symbols), len(names))

    # --- traces -------------------------------------------------------------------------------
    def expert_traces(self, demonstrations) -> list[np.ndarray]:
        """Label-id traces of the demonstrations: their stored labels, or the labeling's."""
        items = list(demonstrations)
        if not items:
            raise DataError("no demonstrations to learn from")
        declared = set(getattr(self.labeling, "propositions", ()) or ())
        strict = bool(declared) and getattr(self.labeling, "declared", True)
        traces = []
        for i, trajectory in enumerate(items):
            labels = getattr(trajectory, "labels", None)
            if labels is not None:
                word = [frozenset(step) for step in labels]
                for t, step in enumerate(word):
                    odd = sorted(step - declared) if strict else []
                    if odd:
                        raise DataError(f"demonstration {i}, step {t}: label {odd[0]!r} is not a proposition of "
                                        f"the labeling", hint="known: " + ", ".join(sorted(declared)))
            else:
                word = None
                if getattr(self.labeling, "arity", 1) >= 2:
                    with _environment_errors(f"replaying demonstration {i}"):
                        word = self._replayed_word(i, trajectory)
                if word is None:
                    states = getattr(trajectory, "states", None)
                    if states is None:
                        raise DataError(f"demonstration {i} has neither labels nor states to label")
                    word = [self._label(_plain(state), {}, f"demonstration {i}, step {t}")
                            for t, state in enumerate(states)]
            traces.append(self._trace(word))
        return traces

    def _replayed_word(self, i: int, trajectory) -> list[frozenset[str]] | None:
        """Labels of an unlabelled demonstration for a labeling that reads ``info`` (or the
        environment): its actions replayed from the seed it was recorded with (``record`` keeps
        it in the trajectory's info); ``None`` when there is no seed or no actions. A replay that
        does not reproduce the stored observations is refused."""
        seed = (getattr(trajectory, "info", None) or {}).get("seed")
        actions, states = getattr(trajectory, "actions", None), getattr(trajectory, "states", None)
        if seed is None or actions is None or states is None:
            return None
        discrete = getattr(self.env.action_space, "n", None) is not None
        observation, info = self.env.reset(seed=int(seed))
        word = [self.labeler(observation, info, f"demonstration {i}, step 0")]
        for t in range(len(states) - 1):
            _same_or_refuse(i, t, states[t], observation, seed)
            action = _fitting_action(i, t, actions[t], self.env.action_space, discrete,
                                     getattr(self.env, "index_of", None))
            observation, _r, terminated, truncated, info = self.env.step(action)
            word.append(self.labeler(observation, info, f"demonstration {i}, step {t + 1}"))
            if (terminated or truncated) and t + 2 < len(states):
                raise DataError(f"demonstration {i}: replaying its actions from seed {seed} ended after {t + 1} "
                                f"steps, not {len(states) - 1}", hint=_RECORD_HINT)
        _same_or_refuse(i, len(states) - 1, states[-1], observation, seed)
        return word

    def random_traces(self, n: int, seed: int) -> list[np.ndarray]:
        from symlearn.rl.product_q_learning import rollout_words

        with _environment_errors("random rollouts"):
            words, _ = rollout_words(self.env, self.labeler, n, horizon=self.horizon, seed=seed)
        return [self._trace(w) for w in words]

    def policy_traces(self, policy, n: int, seed: int) -> list[np.ndarray]:
        with _environment_errors("rollouts of the nominal policy"):
            return self._policy_traces(policy, n, seed)

    def _policy_traces(self, policy, n: int, seed: int) -> list[np.ndarray]:
        if self.route == "tabular":
            from symlearn.rl.product_q_learning import rollout_words

            words, self.last_entropy = rollout_words(self.env, self.labeler, n, policy=policy,
                                                     horizon=self.horizon, seed=seed)
        else:
            words, self.last_entropy = self._ppo_words(policy, n, seed)
        return [self._trace(w) for w in words]

    # --- policy updates -----------------------------------------------------------------------
    def train(self, formula, seed: int):
        with _environment_errors(f"training the nominal policy for {formula}"):
            return self._train(formula, seed)

    def _train(self, formula, seed: int):
        from symlearn.logic.automata.reward_machine import RewardMachine

        machine = RewardMachine.from_formula(formula)
        if self.route == "tabular":
            from symlearn.rl.product_q_learning import product_q_learning

            steps = self.q_steps or 40_000 * (1 + machine.n_states // 8)
            return product_q_learning(self.env, self.labeler, machine, n_steps=steps, horizon=self.horizon,
                                      discount=self.discount, learning_rate=self.learning_rate,
                                      epsilon=self.epsilon, state_key=self.state_key, seed=seed)
        return self._train_ppo(machine, seed)

    def _train_ppo(self, machine, seed: int):
        from symlearn.rl.ppo import PPOConfig, train_ppo
        from symlearn.rl.product_env import ProductEnv

        make = self._factory or (lambda: self.env)  # one instance only: stepped by one PPO copy
        n_envs = 4 if self._factory is not None else 1
        result = train_ppo(lambda: ProductEnv(make(), self._label, machine), int(self.ppo_steps or 50_000),
                           PPOConfig(n_envs=n_envs, seed=seed, gamma=self.discount))
        return (result.policy, machine)

    def _ppo_words(self, policy, n: int, seed: int) -> tuple[list[list[frozenset[str]]], float | None]:
        from symlearn.rl.product_env import ProductEnv

        actor, machine = policy
        env = ProductEnv(self.env, self._label, machine)
        rng = np.random.default_rng(seed)
        words = []
        for _ in range(n):
            observation, _ = env.reset(seed=int(rng.integers(1 << 31)))
            for _t in range(self.horizon):
                observation, _r, terminated, truncated, _ = env.step(actor.act(observation, rng=rng))
                if terminated or truncated:
                    break
            words.append(list(env.word))
        return words, None
