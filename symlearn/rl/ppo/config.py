"""The hyper-parameters of PPO (:class:`PPOConfig`) and of its Lagrangian (:class:`LagrangianConfig`),
checked when made, with the named settings they accept."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from torch import nn

from symlearn.errors import SymlearnError

ACTIVATIONS = {"tanh": nn.Tanh, "relu": nn.ReLU}  # PPOConfig.activation
ENTROPY_MODES = ("bonus", "reward")  # PPOConfig.entropy_mode
ADVANTAGE_SCALES = ("raw", "returns")  # LagrangianConfig.advantage_scale
COST_ESTIMATES = ("rollout", "episodes")  # LagrangianConfig.cost_estimate
RESET_ACTOR_RULES = ("never", "auto")  # LagrangianConfig.reset_actor (symlearn.rl.ppo.stall)
# LagrangianConfig's defaults before they became those of `symlearn train` (with PPOConfig
# normalize_observations=False, normalize_values=False): what the recorded benchmark tables used
LEGACY_LAGRANGIAN = {"update": "adam", "lr": 0.035, "advantage_scale": "raw", "cost_estimate": "episodes",
                     "adam_beta2": 0.999, "init": 0.0}
# what PPOConfig's None settings resolve to (PPOConfig.resolved), with a Lagrangian or without
RESOLVED_DEFAULTS = {"normalize_observations": True, "normalize_values": True, "learning_rate": 1e-3,
                     "log_std_init": -1.0}
# plain PPO's settings before they became RESOLVED_DEFAULTS (CleanRL's): pass them to reproduce a
# plain-PPO row recorded before (docs/BENCHMARKS.md, "One default configuration for plain PPO")
CLEANRL_PLAIN = {"normalize_observations": False, "normalize_values": False, "learning_rate": 2.5e-4,
                 "log_std_init": 0.0}


@dataclass(frozen=True)
class PPOConfig:
    """Hyper-parameters (defaults after CleanRL's ``ppo.py``; value loss = plain MSE as in SB3)."""

    n_envs: int = 4  # environment copies stepped side by side
    n_steps: int = 128  # steps per environment per iteration (rollout = n_envs * n_steps)
    batch_size: int = 128  # minibatch size (the last minibatch of an epoch may be smaller)
    n_epochs: int = 4  # passes over the rollout per iteration
    # None (default): 1e-3 (resolved(); CLEANRL_PLAIN has CleanRL's 2.5e-4)
    learning_rate: float | None = None
    anneal_lr: bool = True  # linearly to 0 over training
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip_range: float = 0.2
    normalize_advantage: bool = True  # per minibatch (PPO-Lagrangian: the mixed advantage)
    ent_coef: float = 0.01
    # "bonus": ent_coef x the policy's entropy in the loss (CleanRL/SB3); "reward": the maximum
    # (causal) entropy objective, -ent_coef x log pi(a|s) added to every step's reward before GAE,
    # so ent_coef is a temperature in reward units (its fixed point is pi ~ exp(Q / ent_coef))
    entropy_mode: str = "bonus"
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    target_kl: float | None = None  # stop the epochs once a minibatch's approx. KL exceeds 1.5 x this
    hidden_sizes: tuple[int, ...] = (64, 64)
    activation: str = "tanh"  # "tanh" | "relu"
    log_std_init: float | None = None  # Box actions; None: -1 (resolved())
    # None (default): on (resolved(); measured, docs/BENCHMARKS.md)
    normalize_observations: bool | None = None  # standardise inputs by running mean/std (saved with the model)
    normalize_values: bool | None = None  # critics learn returns / their running std (outputs kept, PopArt-style)
    seed: int | None = 0
    device: str = "cpu"
    torch_threads: int | None = 1  # None: leave torch's setting alone

    def __post_init__(self) -> None:
        object.__setattr__(self, "hidden_sizes", tuple(int(h) for h in self.hidden_sizes))
        for name in ("n_envs", "n_steps", "batch_size", "n_epochs"):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or value < 1:
                raise SymlearnError(f"PPOConfig.{name} must be a positive integer, got {value!r}")
        for name in ("learning_rate", "log_std_init"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float, np.number))
                                      or not np.isfinite(value)):
                raise SymlearnError(f"PPOConfig.{name} must be a finite number or None, got {value!r}")
        checks = [
            ("learning_rate", self.learning_rate is None or self.learning_rate > 0, "> 0 or None"),
            ("gamma", 0 <= self.gamma <= 1, "in [0, 1]"),
            ("gae_lambda", 0 <= self.gae_lambda <= 1, "in [0, 1]"),
            ("clip_range", self.clip_range > 0, "> 0"),
            ("ent_coef", self.ent_coef >= 0, ">= 0"),
            ("vf_coef", self.vf_coef > 0, "> 0"),
            ("max_grad_norm", self.max_grad_norm > 0, "> 0"),
            ("target_kl", self.target_kl is None or self.target_kl > 0, "> 0 or None"),
            ("hidden_sizes", all(h >= 1 for h in self.hidden_sizes), "positive layer widths"),
            ("torch_threads", self.torch_threads is None or self.torch_threads >= 1, ">= 1 or None"),
        ]
        for name, ok, need in checks:
            if not ok:
                raise SymlearnError(f"PPOConfig.{name} must be {need}, got {getattr(self, name)!r}")
        if self.entropy_mode not in ENTROPY_MODES:
            raise SymlearnError(f"PPOConfig.entropy_mode must be one of {list(ENTROPY_MODES)}, got {self.entropy_mode!r}")
        if self.activation not in ACTIVATIONS:
            raise SymlearnError(f"PPOConfig.activation must be one of {sorted(ACTIVATIONS)}, got {self.activation!r}")
        for name in ("normalize_observations", "normalize_values"):
            if getattr(self, name) not in (None, True, False):
                raise SymlearnError(f"PPOConfig.{name} must be True, False or None, got {getattr(self, name)!r}")

    def resolved(self) -> PPOConfig:
        """This configuration with its ``None`` settings decided, with a Lagrangian or without:
        normalised observations and values, learning rate 1e-3, initial log standard deviation -1
        (:data:`RESOLVED_DEFAULTS`). Under a cost, an agent that keeps the initial noise (std 1 on a
        [-1, 1] action box) cannot follow a safe route narrower than its own jitter, and at 2.5e-4
        the log standard deviation moves by at most ~0.004 an iteration -- in 50k steps the noise
        barely shrinks, and the safe agent freezes where it started (docs/BENCHMARKS.md,
        "PPO-Lagrangian defaults of `train`"). Plain PPO had CleanRL's settings
        (:data:`CLEANRL_PLAIN`) until the same four earned more on 11 of 15 tasks at 50k steps, as
        much on 3 and less on 2 (docs/BENCHMARKS.md, "One default configuration for plain PPO"):
        they are one configuration now, and ``CLEANRL_PLAIN`` gives back the old one."""
        choices = RESOLVED_DEFAULTS
        return replace(self, **{name: value for name, value in choices.items() if getattr(self, name) is None})


@dataclass(frozen=True)
class LagrangianConfig:
    """Constraints ``J_ci <= cost_limit_i`` on the expected episode cost, one multiplier each.

    ``cost_limit`` is one number (the same limit for every constraint; the number of constraints is
    then the length of the first ``info["cost"]`` seen) or one limit per constraint. ``init`` is
    the starting multiplier (one number or one per constraint). ``update`` picks the rule of
    :class:`~symlearn.rl.ppo.multipliers.Multipliers`: ``"gradient"`` and ``"adam"`` take steps of
    ``lr``; ``"pid"`` uses ``kp``, ``ki``, ``kd`` with exponential averages ``p_ema``/``d_ema`` of
    the error and the cost and a derivative over ``d_delay`` updates (the defaults are OmniSafe's
    CPPOPID ones). ``max_multiplier`` caps every multiplier (``None``: no cap). ``cost_gamma`` discounts costs for
    the cost critics (``None``: the reward's ``gamma``). ``advantage_scale``: ``"raw"`` mixes the
    advantages in their own units (``lambda`` = the price of a unit of cost in reward); ``"returns"``
    (the default) first divides each by the running standard deviation of its signal's returns,
    which makes the multiplier's range independent of the units of reward and cost (the
    docstring of :mod:`symlearn.rl.ppo`). ``cost_estimate``: what the multipliers are updated
    from, every iteration: ``"rollout"`` (the default) the rollout's cost per step times the mean
    length of the last :data:`~symlearn.rl.ppo.rollouts.LENGTH_MEMORY` finished episodes (a ratio
    estimate of ``J_c`` from every step, finished episode or not); ``"episodes"`` the mean cost of
    the episodes that ended in the rollout, and no update in a rollout where none ended (the
    behaviour before; with 1000-step episodes and 4 x 128-step rollouts that is one update in
    eight iterations).

    The defaults (``"adam"``, ``lr=0.1``, ``adam_beta2=0.99``, ``"returns"``, ``"rollout"``, ``init``
    1 for a limit of 0 and 0 for a positive one, with
    :class:`PPOConfig`'s Lagrangian settings: normalisation, learning rate 1e-3, log std -1) are the ones ``symlearn
    train --algo ppo-lag`` uses; they were chosen by measurement on four tasks x 3 seeds
    (docs/BENCHMARKS.md, "PPO-Lagrangian defaults of `train`"): Adam moves ``lambda`` by about
    ``lr`` an iteration whatever the size of the violation, where the gradient rule's first steps
    (``0.05 x`` an exploring agent's 100 cost steps) priced every cost out of reach of the reward and
    froze the agent at its start. The start (``0`` everywhere until 2026-12-07) was measured on eleven
    tasks x 3-10 seeds and SafeNav with a budget of 25 (docs/BENCHMARKS.md, "Where the multiplier
    starts"): from 1, BlockedPoint's learned wall was safe on 10 of 10 seeds instead of 9 and the
    toy on its true cost on 9 of 10 instead of 8; under the budget, SafeNav CarGoal earned 3.04
    instead of 6.24 (10 seeds). Before, the library's were ``"adam"``, ``lr=0.035``, ``"raw"``,
    ``"episodes"``, no normalisation, ``init=0`` (``LEGACY_LAGRANGIAN``, with torch's ``adam_beta2=0.999``); the
    CLI's, ``"gradient"``, ``lr=0.05``.
    """

    cost_limit: float | Sequence[float]
    update: str = "adam"
    lr: float = 0.1
    # None: 1 for a hard constraint (limit 0), 0 for a budget (limit > 0). With return-unit
    # advantages 1 weighs the cost as much as the reward from the first iteration; from 0 a policy
    # learns from the reward alone for ~10 iterations, long enough to commit to a forbidden short
    # cut it never leaves. Under a budget the policy may spend, starting at 1 cost SafeNav CarGoal
    # half its return (docs/BENCHMARKS.md, "Where the multiplier starts")
    init: float | Sequence[float] | None = None
    kp: float = 0.1
    ki: float = 0.01
    kd: float = 0.01
    d_delay: int = 10
    p_ema: float = 0.95
    d_ema: float = 0.95
    # Adam's second-moment memory for the multipliers: 0.99, about 100 updates (torch's 0.999
    # remembers ~1000: an exploring agent's early violations, 10-20x the late ones, then kept the
    # late steps ~10x smaller than lr and the toy's agent on its diagonal shortcut; BENCHMARKS)
    adam_beta2: float = 0.99
    max_multiplier: float | None = None
    cost_gamma: float | None = None
    advantage_scale: str = "returns"
    # in the mix (advantage_scale="returns"), the reward's return scale never drops below this share
    # of the largest it had (each cost's: RETURN_SCALE_FLOOR; the critics' unit is not affected).
    # Once every episode earns about the same -- a pole balanced to the time limit -- the spread of
    # the reward's returns collapses, and in its units the small differences left between
    # near-equal episodes outweigh any constraint. 1 fixes CartPole held left of a line (5 of 5
    # seeds safe, 3 of 5 at 0.01) but costs SafeNav and BlockedPoint's learned wall; 0.1 changed
    # nothing within 50k steps (docs/BENCHMARKS.md, "A reward that stops varying"): the default
    # stays, and limit_warnings names this setting when a run shows the collapse
    reward_scale_floor: float = 0.01
    # the same for each cost's return scale in the mix: as the agent stops paying a cost its scale
    # shrinks, and every remaining violation gets dearer in its units (up to 1 / 0.01 = 100x)
    cost_scale_floor: float = 0.01
    cost_estimate: str = "rollout"
    # a limit of 0 as the multipliers see it: this many violating steps per episode of the training
    # policy (times the largest step cost seen; symlearn.rl.ppo.multipliers.zero_limit_targets). At
    # an exact 0 a rollout without cost is no error, so no rule ever lowers a multiplier: once an
    # exploring agent's brushes have raised it, the agent is held at that price after it has become
    # over-cautious. 0 (the default): the exact limit, as before (opt-in: measured in
    # docs/BENCHMARKS.md, "Over-cautious agents at limit 0")
    zero_limit_slack: float = 0.0
    # "auto": a fresh actor, on trial, when the policy is stuck over its limit while the multiplier
    # keeps rising (symlearn.rl.ppo.stall); "never" (the default: measured, it helps some tasks and
    # costs others, docs/BENCHMARKS.md): the policy is only ever continued
    reset_actor: str = "never"

    def __post_init__(self) -> None:
        limits = _numbers(self.cost_limit, "cost_limit")
        for i, limit in enumerate(limits):
            if limit < 0:
                where = "" if np.ndim(self.cost_limit) == 0 else f" (constraint {i})"
                raise SymlearnError(f"cost_limit must be >= 0, got {limit:g}{where}",
                                    hint="a cost limit bounds an expected sum of non-negative costs")
        if self.init is None:   # per constraint: hard (limit 0) from 1, a budget from 0
            starts = tuple(1.0 if limit == 0 else 0.0 for limit in limits)
            object.__setattr__(self, "init", starts[0] if np.ndim(self.cost_limit) == 0 else starts)
        inits = _numbers(self.init, "init")
        if any(x < 0 for x in inits):
            raise SymlearnError(f"the initial multipliers must be >= 0, got {list(inits)}")
        if np.ndim(self.cost_limit) and np.ndim(self.init) and len(inits) != len(limits):
            raise SymlearnError(f"init has {len(inits)} entries but cost_limit has {len(limits)}")
        object.__setattr__(self, "cost_limit", float(limits[0]) if np.ndim(self.cost_limit) == 0 else limits)
        object.__setattr__(self, "init", float(inits[0]) if np.ndim(self.init) == 0 else inits)
        if self.update not in ("gradient", "adam", "pid"):
            raise SymlearnError(f"update must be 'gradient', 'adam' or 'pid', got {self.update!r}")
        if not self.lr > 0 or min(self.kp, self.ki, self.kd) < 0 or self.d_delay < 1:
            raise SymlearnError("need lr > 0, kp, ki, kd >= 0 and d_delay >= 1")
        if not (0 <= self.p_ema < 1 and 0 <= self.d_ema < 1):
            raise SymlearnError("p_ema and d_ema must be in [0, 1)")
        if not 0 < self.adam_beta2 < 1:
            raise SymlearnError(f"adam_beta2 must be in (0, 1), got {self.adam_beta2!r}")
        if self.max_multiplier is not None and not self.max_multiplier > 0:
            raise SymlearnError(f"max_multiplier must be > 0 or None, got {self.max_multiplier!r}")
        if self.cost_gamma is not None and not 0 <= self.cost_gamma <= 1:
            raise SymlearnError(f"cost_gamma must be in [0, 1], got {self.cost_gamma!r}")
        if self.advantage_scale not in ADVANTAGE_SCALES:
            raise SymlearnError(f"advantage_scale must be one of {', '.join(map(repr, ADVANTAGE_SCALES))}, "
                                f"got {self.advantage_scale!r}")
        if isinstance(self.reward_scale_floor, bool) or not isinstance(self.reward_scale_floor, (int, float)) \
                or not 0 < self.reward_scale_floor <= 1:
            raise SymlearnError(f"reward_scale_floor must be a number in (0, 1], got {self.reward_scale_floor!r}")
        if isinstance(self.cost_scale_floor, bool) or not isinstance(self.cost_scale_floor, (int, float)) \
                or not 0 < self.cost_scale_floor <= 1:
            raise SymlearnError(f"cost_scale_floor must be a number in (0, 1], got {self.cost_scale_floor!r}")
        if isinstance(self.zero_limit_slack, bool) or not isinstance(self.zero_limit_slack, (int, float)) \
                or not 0 <= self.zero_limit_slack <= 1:
            raise SymlearnError(f"zero_limit_slack must be a number in [0, 1], got {self.zero_limit_slack!r}")
        if self.reset_actor not in RESET_ACTOR_RULES:
            raise SymlearnError(f"reset_actor must be one of {', '.join(map(repr, RESET_ACTOR_RULES))}, "
                                f"got {self.reset_actor!r}")
        if self.cost_estimate not in COST_ESTIMATES:
            raise SymlearnError(f"cost_estimate must be one of {', '.join(map(repr, COST_ESTIMATES))}, "
                                f"got {self.cost_estimate!r}")

    @property
    def n_constraints(self) -> int | None:
        """The number of constraints if the limits or initial values name it, else ``None``."""
        for value in (self.cost_limit, self.init):
            if isinstance(value, tuple):
                return len(value)
        return None

    def limits(self, n: int) -> np.ndarray:
        return np.broadcast_to(np.asarray(self.cost_limit, dtype=np.float64), (n,)).copy()


def _numbers(value: Any, name: str) -> tuple[float, ...]:
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise SymlearnError(f"{name} must be a number or a list of numbers, got {value!r}") from None
    if array.ndim > 1 or array.size == 0:
        raise SymlearnError(f"{name} must be a number or a non-empty list of numbers, got {value!r}")
    if not np.all(np.isfinite(array)):
        raise SymlearnError(f"{name} must be finite, got {value!r}")
    return tuple(float(x) for x in array.reshape(-1))

