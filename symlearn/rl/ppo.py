"""PPO and PPO-Lagrangian in one file, readable top to bottom (in the spirit of CleanRL).

``train_ppo(env_fn, total_steps, config, lagrangian=None)`` trains an actor and a critic (two
separate MLPs, 64 x 64 tanh by default) with the clipped surrogate objective of Schulman et al.
(2017) on ``n_envs`` copies of an environment, ``n_steps`` steps each per iteration, then
``n_epochs`` passes of minibatches of ``batch_size``. Discrete actions use a categorical policy;
``Box`` actions a Gaussian with a state-independent log standard deviation (the sampled action is
learned from, the action sent to the environment is clipped to the bounds). ``Box`` observations
are flattened, ``Discrete`` ones one-hot encoded.

**Costs.** Every step's ``info["cost"]`` is read: a number or a vector of fixed length (one entry
per constraint; a step without the key costs 0; NaN/inf, or a vector whose length changes, is a
:class:`~symlearn.errors.DataError`). Episode cost sums are reported for plain PPO too.

**PPO-Lagrangian** (``lagrangian=LagrangianConfig(cost_limit=...)``) solves
``max_pi J_r(pi)  s.t.  J_ci(pi) <= d_i`` for every constraint ``i`` with one cost critic (GAE on
its own) and one multiplier ``lambda_i >= 0`` per constraint. Each iteration first updates the
multipliers from an estimate of the expected episode cost ``J_c`` -- by default the rollout's cost
per step times the mean episode length, so every rollout counts, also one in which no episode
ended (``LagrangianConfig.cost_estimate``) --, by one of three rules (:class:`Multipliers`): ``"gradient"`` (projected dual ascent),
``"adam"`` (Adam on ``-lambda (J_c - d)``, then projected; OmniSafe's default) or ``"pid"``
(Stooke et al., 2020). The policy then ascends the advantage of the Lagrangian
``J_r - sum_i lambda_i (J_ci - d_i)``:

    A = (A_r - sum_i lambda_i A_ci) / (1 + sum_i lambda_i)

with the raw GAE advantages (reward and cost in their own units), normalised per minibatch like
plain PPO's (``normalize_advantage``). So ``lambda_i`` keeps its meaning, the price of one unit of
cost ``i`` in reward, and ``lambda = 0`` is exactly plain PPO. The division by ``1 + sum lambda``
(as in safety-starter-agents and OmniSafe) keeps the advantage's size bounded when the multipliers
grow; after the per-minibatch normalisation it changes nothing, so it matters only with
``normalize_advantage=False``. We do not standardise ``A_r`` alone before mixing, as those two
libraries do: that measures reward in standard deviations of ``A_r``, which shrink as the policy
becomes deterministic, so the multiplier needed to move the policy keeps growing. Measured on the
corridor with two constraints of ``tests/rl/test_ppo.py`` (12k steps, ``"gradient"``, seeds 0-2):
that version stayed at cost 2 per episode (limit 1) while the multiplier climbed past 4; the mix
above brought the greedy policy to cost 0 on all three seeds, with multipliers near 1.

**Scale-free multipliers** (``LagrangianConfig(advantage_scale="returns")``, the default;
``"raw"`` is the mix above). Raw units make the multiplier's useful range depend on the ratio of the reward's
scale to the cost's, which no step size fits: on the thesis' toy an episode earns about 2 and an
exploring agent collects 100-200 cost steps, so the price that already makes the safe route pay is
about 0.01 while Adam moves ``lambda`` by about ``lr`` = 0.035 per iteration; from the second
iteration on the cost swamped the reward, and with a cost limit of 0 (no slack: ``lambda`` can only
grow) the agent learned to stand still near the start. With ``"returns"`` each signal's advantage
is divided by the running standard deviation of its own returns (:class:`_ReturnScales`: an average
over about ten iterations, floored at 1 % of its largest value), so ``lambda`` weighs standard
deviations of cost-to-go against those of reward-to-go: while the exploring agent's costs are large
and spread, one unit of cost is cheap; as the agent becomes safe the cost's scale shrinks and the
remaining violations get dearer. The constrained problem is unchanged (a positive rescaling of
objective and constraint moves only the value of the multiplier at the saddle point);
``PPOIteration.return_scales`` records the scales, so ``lambda_i * scale_r / scale_ci`` is the
price in raw units.

**Normalisation** (both on by default with a Lagrangian, off for plain PPO; ``PPOConfig``'s
``None`` decides it when training starts). ``normalize_observations``: the networks see the features
standardised by their running mean and variance (every rollout joins the statistics before it is
learned from; clipped to +-10; saved with the weights, applied by ``act``/``encode``). Without it,
inputs that all lie on one side of zero (positions in ``[0, 1]^2``) meet a first layer whose zero
biases put every hyperplane through the origin: a policy that must turn at ``x = 0.7`` is hard to
represent and PPO stalled there. ``normalize_values``: the critics learn each signal's returns
divided by the same running scale, the output layers being rescaled whenever the scale changes so
that their values stay put (PopArt's trick, Hessel et al. 2019); after training they output returns
again. Cost-to-go values of 50-100 are otherwise out of reach of an output layer moved by Adam at
``2.5e-4`` a step, and the cost critic stayed flat.

**Speed.** Actions are sampled during rollouts by a numpy copy of the actor (a forward pass for a
few rows costs a few microseconds in numpy and tens in torch); everything learning needs (old
log-probabilities, values, cost values) is computed afterwards in torch, over the whole rollout at
once, from the same weights, so nothing a gradient sees comes from numpy. ``torch.set_num_threads``
is set to ``config.torch_threads`` (1) during training and restored afterwards: the networks are
small and on 2 cores a second thread slows PPO down several times. Environments are a plain list
(stepped one after the other, reset on the spot) rather than ``gymnasium.vector.SyncVectorEnv``: a
little faster, and every step's own ``info`` dict is at hand. Truncated episodes (time limits) are
bootstrapped with the value of their last observation, as SB3 does.

Models are saved as ``safetensors`` + JSON (:mod:`symlearn.rl.model_files`); loading never runs code.

>>> result = train_ppo("CartPole-v1", 2_048, PPOConfig(n_envs=2, n_steps=256, seed=0))
>>> len(result.history), result.steps
(4, 2048)
>>> action = result.policy.act(np.zeros(4, dtype=np.float32), deterministic=True)
>>> action in (0, 1)
True
"""

from __future__ import annotations

import math
import os
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.progress import ProgressBar
from symlearn.rl.model_files import load_torch_module, save_torch_module

MODEL_KIND = "ppo-actor-critic"
ACTIVATIONS = {"tanh": nn.Tanh, "relu": nn.ReLU}
OBS_CLIP = 10.0  # normalised observations are clipped to +-OBS_CLIP (as SB3's VecNormalize)
OBS_EPSILON = 1e-8  # added to the running variance before the square root
ADVANTAGE_SCALES = ("raw", "returns")  # LagrangianConfig.advantage_scale
COST_ESTIMATES = ("rollout", "episodes")  # LagrangianConfig.cost_estimate
# LagrangianConfig's defaults before they became those of `symlearn train` (with PPOConfig
# normalize_observations=False, normalize_values=False): what the recorded benchmark tables used
LEGACY_LAGRANGIAN = {"update": "adam", "lr": 0.035, "advantage_scale": "raw", "cost_estimate": "episodes"}
LENGTH_MEMORY = 100  # finished episodes whose mean length turns a rollout's cost rate into J_c
ENTROPY_MODES = ("bonus", "reward")  # PPOConfig.entropy_mode
RETURN_SCALE_MEMORY = 0.9  # per iteration, for the running standard deviation of each signal's returns
RETURN_SCALE_FLOOR = 1e-2  # a signal's scale never drops below this share of the largest it had


# --------------------------------------------------------------------------------------------------
# configuration


@dataclass(frozen=True)
class PPOConfig:
    """Hyper-parameters (defaults after CleanRL's ``ppo.py``; value loss = plain MSE as in SB3)."""

    n_envs: int = 4  # environment copies stepped side by side
    n_steps: int = 128  # steps per environment per iteration (rollout = n_envs * n_steps)
    batch_size: int = 128  # minibatch size (the last minibatch of an epoch may be smaller)
    n_epochs: int = 4  # passes over the rollout per iteration
    learning_rate: float = 2.5e-4
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
    log_std_init: float = 0.0  # Box actions
    # None (default): on with a Lagrangian, off for plain PPO (measured; LagrangianConfig's docstring)
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
        checks = [
            ("learning_rate", self.learning_rate > 0, "> 0"),
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

    def resolved(self, constrained: bool) -> PPOConfig:
        """This configuration with ``None`` normalisation settings decided: on with a Lagrangian
        (``constrained``), off without one."""
        return replace(self, **{name: constrained for name in ("normalize_observations", "normalize_values")
                                if getattr(self, name) is None})


@dataclass(frozen=True)
class LagrangianConfig:
    """Constraints ``J_ci <= cost_limit_i`` on the expected episode cost, one multiplier each.

    ``cost_limit`` is one number (the same limit for every constraint; the number of constraints is
    then the length of the first ``info["cost"]`` seen) or one limit per constraint. ``init`` is
    the starting multiplier (one number or one per constraint). ``update`` picks the rule of
    :class:`Multipliers`: ``"gradient"`` and ``"adam"`` take steps of ``lr``; ``"pid"`` uses
    ``kp``, ``ki``, ``kd`` with exponential averages ``p_ema``/``d_ema`` of the error and the cost
    and a derivative over ``d_delay`` updates (the defaults are OmniSafe's CPPOPID ones).
    ``max_multiplier`` caps every multiplier (``None``: no cap). ``cost_gamma`` discounts costs for
    the cost critics (``None``: the reward's ``gamma``). ``advantage_scale``: ``"raw"`` mixes the
    advantages in their own units (``lambda`` = the price of a unit of cost in reward); ``"returns"``
    (the default) first divides each by the running standard deviation of its signal's returns,
    which makes the multiplier's range independent of the units of reward and cost (module
    docstring). ``cost_estimate``: what the multipliers are updated from, every iteration:
    ``"rollout"`` (the default) the rollout's cost per step times the mean length of the last
    ``LENGTH_MEMORY`` finished episodes (a ratio estimate of ``J_c`` from every step, finished
    episode or not); ``"episodes"`` the mean cost of the episodes that ended in the rollout, and no
    update in a rollout where none ended (the behaviour before; with 1000-step episodes and
    4 x 128-step rollouts that is one update in eight iterations).

    The defaults (``"gradient"``, ``lr=0.05``, ``"returns"``, ``"rollout"``, with
    :class:`PPOConfig`'s normalisation, which turns on with a Lagrangian) are the ones ``symlearn
    train --algo ppo-lag`` uses; they were chosen by measurement (docs/BENCHMARKS.md, "PPO-Lagrangian
    defaults of `train`"). Before, the library's were ``"adam"``, ``lr=0.035``, ``"raw"``,
    ``"episodes"`` and no normalisation.
    """

    cost_limit: float | Sequence[float]
    update: str = "gradient"
    lr: float = 0.05
    init: float | Sequence[float] = 0.0
    kp: float = 0.1
    ki: float = 0.01
    kd: float = 0.01
    d_delay: int = 10
    p_ema: float = 0.95
    d_ema: float = 0.95
    max_multiplier: float | None = None
    cost_gamma: float | None = None
    advantage_scale: str = "returns"
    cost_estimate: str = "rollout"

    def __post_init__(self) -> None:
        limits = _numbers(self.cost_limit, "cost_limit")
        for i, limit in enumerate(limits):
            if limit < 0:
                where = "" if np.ndim(self.cost_limit) == 0 else f" (constraint {i})"
                raise SymlearnError(f"cost_limit must be >= 0, got {limit:g}{where}",
                                    hint="a cost limit bounds an expected sum of non-negative costs")
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
        if self.max_multiplier is not None and not self.max_multiplier > 0:
            raise SymlearnError(f"max_multiplier must be > 0 or None, got {self.max_multiplier!r}")
        if self.cost_gamma is not None and not 0 <= self.cost_gamma <= 1:
            raise SymlearnError(f"cost_gamma must be in [0, 1], got {self.cost_gamma!r}")
        if self.advantage_scale not in ADVANTAGE_SCALES:
            raise SymlearnError(f"advantage_scale must be one of {', '.join(map(repr, ADVANTAGE_SCALES))}, "
                                f"got {self.advantage_scale!r}")
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


# --------------------------------------------------------------------------------------------------
# Lagrange multipliers


class Multipliers:
    """One multiplier per constraint, updated from the mean episode costs ``J_c`` of a rollout.

    * ``"gradient"``: ``lambda <- max(0, lambda + lr (J_c - d))``;
    * ``"adam"``: Adam on the loss ``-lambda (J_c - d)`` (its gradient is ``d - J_c``), then
      projected to ``>= 0``; steps of about ``lr`` whatever the size of the violation;
    * ``"pid"``: ``I <- max(0, I + ki (J_c - d))``, ``P`` = EMA of ``J_c - d``, ``D`` =
      ``max(0, C_t - C_{t-delay})`` for an EMA ``C`` of the cost;
      ``lambda = max(0, kp P + I + kd D)``.

    All three are capped at ``max_multiplier`` when set.

    >>> m = Multipliers(LagrangianConfig(cost_limit=1.0, update="gradient", lr=0.5), 1)
    >>> [float(m.update([3.0])[0]) for _ in range(2)], float(m.update([0.0])[0])
    ([1.0, 2.0], 1.5)
    """

    def __init__(self, config: LagrangianConfig, n_constraints: int) -> None:
        self.config = config
        self.limits = config.limits(n_constraints)
        self.values = np.broadcast_to(np.asarray(config.init, dtype=np.float64), (n_constraints,)).copy()
        self._adam_m = np.zeros(n_constraints)
        self._adam_v = np.zeros(n_constraints)
        self._adam_t = 0
        self._pid_i = self.values.copy()  # the integral starts at init, so lambda starts near it
        self._pid_p = np.zeros(n_constraints)
        self._pid_cost = np.zeros(n_constraints)
        self._pid_costs: deque[np.ndarray] = deque([np.zeros(n_constraints)], maxlen=config.d_delay)

    def update(self, mean_costs: Sequence[float] | np.ndarray) -> np.ndarray:
        costs = np.asarray(mean_costs, dtype=np.float64).reshape(-1)
        if costs.shape != self.limits.shape:
            raise DataError(f"got {costs.size} mean costs for {self.limits.size} constraints")
        c = self.config
        error = costs - self.limits  # > 0: constraint violated, the multiplier should rise
        if c.update == "gradient":
            self.values = np.maximum(0.0, self.values + c.lr * error)
        elif c.update == "adam":  # torch.optim.Adam's defaults: betas (0.9, 0.999), eps 1e-8
            grad = -error
            self._adam_t += 1
            self._adam_m = 0.9 * self._adam_m + 0.1 * grad
            self._adam_v = 0.999 * self._adam_v + 0.001 * grad**2
            m_hat = self._adam_m / (1 - 0.9**self._adam_t)
            v_hat = self._adam_v / (1 - 0.999**self._adam_t)
            self.values = np.maximum(0.0, self.values - c.lr * m_hat / (np.sqrt(v_hat) + 1e-8))
        else:  # pid
            self._pid_i = np.maximum(0.0, self._pid_i + c.ki * error)
            self._pid_p = c.p_ema * self._pid_p + (1 - c.p_ema) * error
            self._pid_cost = c.d_ema * self._pid_cost + (1 - c.d_ema) * costs
            derivative = np.maximum(0.0, self._pid_cost - self._pid_costs[0])
            self._pid_costs.append(self._pid_cost.copy())
            self.values = np.maximum(0.0, c.kp * self._pid_p + self._pid_i + c.kd * derivative)
        if c.max_multiplier is not None:
            self.values = np.minimum(self.values, c.max_multiplier)
        return self.values.copy()


# --------------------------------------------------------------------------------------------------
# the networks


def _space_spec(space: Any, role: str) -> dict[str, Any]:
    """A JSON description of a Box or Discrete space (what the networks need to know)."""
    kind = type(space).__name__
    if kind == "Discrete":
        return {"kind": "discrete", "n": int(space.n), "start": int(getattr(space, "start", 0))}
    if kind == "Box":
        spec: dict[str, Any] = {"kind": "box", "shape": [int(n) for n in space.shape]}
        if role == "action":
            if len(space.shape) != 1:
                raise SymlearnError(f"PPO needs a 1-D Box action space, got shape {space.shape}")
            # JSON has no infinity: an unbounded side is stored as null
            spec["low"] = [float(x) if np.isfinite(x) else None for x in np.asarray(space.low, np.float64)]
            spec["high"] = [float(x) if np.isfinite(x) else None for x in np.asarray(space.high, np.float64)]
        return spec
    raise SymlearnError(f"PPO supports Box and Discrete {role} spaces, got {kind}",
                        hint="flatten dict/tuple spaces with a gymnasium wrapper (e.g. FlattenObservation)")


def _mlp(sizes: Sequence[int], activation: str, out_gain: float, generator: torch.Generator | None) -> nn.Sequential:
    """Linear layers with ``activation`` between them, orthogonal initialisation (gain sqrt(2),
    the last layer ``out_gain``), zero biases: the initialisation of CleanRL and SB3."""
    layers: list[nn.Module] = []
    for i, (n_in, n_out) in enumerate(zip(sizes[:-1], sizes[1:])):
        last = i == len(sizes) - 2
        layer = nn.Linear(n_in, n_out)
        nn.init.orthogonal_(layer.weight, out_gain if last else math.sqrt(2), generator=generator)
        nn.init.zeros_(layer.bias)
        layers.append(layer)
        if not last:
            layers.append(ACTIVATIONS[activation]())
    return nn.Sequential(*layers)


def _actor(obs_dim: int, hidden_sizes: Sequence[int], n_out: int, activation: str,
           generator: torch.Generator | None) -> nn.Sequential:
    """The policy network as a new model has it (last layer's gain 0.01: actions start near-uniform
    / near the mean 0); shared by the constructor and :meth:`ActorCritic.reset_actor`."""
    return _mlp([obs_dim, *hidden_sizes, n_out], activation, 0.01, generator)


class ActorCritic(nn.Module):
    """The policy (``actor``), the reward critic and one cost critic per constraint.

    ``act(observation)`` is the numpy interface for using a trained policy; ``save``/``load``
    write and read ``NAME.safetensors`` + ``NAME.json``.
    """

    def __init__(self, observation: dict[str, Any], action: dict[str, Any], hidden_sizes: Sequence[int] = (64, 64),
                 activation: str = "tanh", n_costs: int = 0, log_std_init: float = 0.0,
                 generator: torch.Generator | None = None, *, obs_normalization: bool = False) -> None:
        super().__init__()
        self.observation_spec, self.action_spec = observation, action
        self.hidden_sizes, self.activation, self.log_std_init = tuple(hidden_sizes), activation, float(log_std_init)
        self.discrete = action["kind"] == "discrete"
        self.obs_dim = observation["n"] if observation["kind"] == "discrete" else int(np.prod(observation["shape"]))
        n_out = action["n"] if self.discrete else action["shape"][0]
        sizes = [self.obs_dim, *self.hidden_sizes]
        self.actor = _actor(self.obs_dim, self.hidden_sizes, n_out, activation, generator)
        self.critic = _mlp([*sizes, 1], activation, 1.0, generator)
        self.cost_critics = nn.ModuleList()
        self.add_cost_critics(n_costs, generator)
        if not self.discrete:
            self.log_std = nn.Parameter(torch.full((n_out,), float(log_std_init)))
            low = [-np.inf if x is None else x for x in action["low"]]
            high = [np.inf if x is None else x for x in action["high"]]
            self._low, self._high = np.asarray(low, np.float32), np.asarray(high, np.float32)
        # running mean and variance of the observation features (saved with the weights)
        self.obs_normalization = bool(obs_normalization)
        if self.obs_normalization:
            self.register_buffer("obs_mean", torch.zeros(self.obs_dim, dtype=torch.float64))
            self.register_buffer("obs_var", torch.ones(self.obs_dim, dtype=torch.float64))
            self.register_buffer("obs_count", torch.zeros(1, dtype=torch.float64))
        self._normalizer: tuple[np.ndarray, np.ndarray] | None = None  # numpy (mean, 1 / std), rebuilt on change

    @classmethod
    def for_spaces(cls, observation_space: Any, action_space: Any, **kwargs: Any) -> ActorCritic:
        return cls(_space_spec(observation_space, "observation"), _space_spec(action_space, "action"), **kwargs)

    def add_cost_critics(self, n: int, generator: torch.Generator | None = None) -> list[nn.Parameter]:
        """Append ``n`` cost critics (same shape as the reward critic); returns their parameters."""
        new = [_mlp([self.obs_dim, *self.hidden_sizes, 1], self.activation, 1.0, generator) for _ in range(n)]
        self.cost_critics.extend(new)
        return [p for critic in new for p in critic.parameters()]

    @property
    def n_costs(self) -> int:
        return len(self.cost_critics)

    def reset_actor(self, generator: torch.Generator | None = None) -> None:
        """Give the policy a new model's initial weights (and, for Box actions, ``log_std_init``),
        keeping the critics and the observation statistics.

        Continuing a policy that has become nearly deterministic under one reward does not find a
        behaviour several consecutive deviations away when the reward changes: every single
        deviation scores worse, and its entropy only falls further (measured on the gridworld of
        thesis Fig. 2.1: 40k PPO steps on the true cost left a continued policy on the forbidden
        shortest path, a policy with a fresh actor and the old critic took the detour). The
        critics keep their values, which speeds the new actor's first updates."""
        fresh = _actor(self.obs_dim, self.hidden_sizes, self.actor[-1].out_features, self.activation,
                       generator).to(self.actor[-1].weight.device)
        with torch.no_grad():
            self.actor.load_state_dict(fresh.state_dict())
            if not self.discrete:
                self.log_std.fill_(self.log_std_init)

    # --- observations and actions as arrays --------------------------------------------------------

    def encode(self, observations: Any) -> np.ndarray:
        """A batch of raw observations -> the networks' float32 input ``(B, obs_dim)``: the
        :meth:`features`, standardised when the model normalises observations."""
        return self.normalize(self.features(observations))

    def normalize(self, features: np.ndarray) -> np.ndarray:
        """``(features - mean) / std`` by the running statistics, clipped to +-:data:`OBS_CLIP`
        (the features themselves when the model does not normalise observations)."""
        if not self.obs_normalization:
            return features
        if self._normalizer is None:
            mean = self.obs_mean.detach().cpu().numpy()
            scale = 1.0 / np.sqrt(self.obs_var.detach().cpu().numpy() + OBS_EPSILON)
            self._normalizer = (mean.astype(np.float32), scale.astype(np.float32))
        mean, scale = self._normalizer
        return np.clip((features - mean) * scale, -OBS_CLIP, OBS_CLIP).astype(np.float32, copy=False)

    def update_observation_stats(self, features: np.ndarray) -> None:
        """Fold a batch of :meth:`features` ``(B, obs_dim)`` into the running mean and variance
        (the parallel update of Chan et al., in float64)."""
        x = np.asarray(features, dtype=np.float64).reshape(-1, self.obs_dim)
        if not self.obs_normalization or not len(x):
            return
        count, mean, var = float(self.obs_count[0]), self.obs_mean.cpu().numpy(), self.obs_var.cpu().numpy()
        batch_mean, batch_var, n = x.mean(axis=0), x.var(axis=0), len(x)
        total = count + n
        delta = batch_mean - mean
        new_mean = mean + delta * (n / total)
        new_var = (var * count + batch_var * n + delta**2 * (count * n / total)) / total
        with torch.no_grad():
            self.obs_mean.copy_(torch.from_numpy(new_mean))
            self.obs_var.copy_(torch.from_numpy(new_var))
            self.obs_count.fill_(total)
        self._normalizer = None

    def load_state_dict(self, state_dict: Any, strict: bool = True, assign: bool = False) -> Any:
        self._normalizer = None  # the statistics may change
        return super().load_state_dict(state_dict, strict=strict, assign=assign)

    def features(self, observations: Any) -> np.ndarray:
        """A batch of raw observations -> float32 ``(B, obs_dim)`` (Box: flattened; Discrete: one-hot)."""
        if self.observation_spec["kind"] == "discrete":
            ids = np.asarray(observations, dtype=np.int64).reshape(-1) - self.observation_spec["start"]
            if ids.size and (ids.min() < 0 or ids.max() >= self.obs_dim):
                raise DataError(f"observation ids {ids.tolist()} outside the space of {self.obs_dim}")
            one_hot = np.zeros((ids.size, self.obs_dim), dtype=np.float32)
            one_hot[np.arange(ids.size), ids] = 1.0
            return one_hot
        return np.asarray(observations, dtype=np.float32).reshape(-1, self.obs_dim)

    def env_action(self, action: np.ndarray) -> Any:
        """One sampled action as the environment takes it (Discrete: an int; Box: clipped)."""
        if self.discrete:
            return int(action) + self.action_spec["start"]
        return np.clip(action, self._low, self._high)

    # --- the torch side ------------------------------------------------------------------------------

    def value(self, obs: torch.Tensor) -> torch.Tensor:
        return self.critic(obs).squeeze(-1)

    def cost_values(self, obs: torch.Tensor) -> torch.Tensor:
        """``(B, n_costs)``."""
        if not self.n_costs:
            return obs.new_zeros((obs.shape[0], 0))
        return torch.cat([critic(obs) for critic in self.cost_critics], dim=-1)

    def log_prob_entropy(self, obs: torch.Tensor, actions: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Log-probability of ``actions`` and the policy's entropy, per row (written out instead of
        ``torch.distributions``, whose argument checks cost more than the arithmetic here)."""
        out = self.actor(obs)
        if self.discrete:
            log_p = torch.log_softmax(out, dim=-1)
            return log_p.gather(-1, actions.long().unsqueeze(-1)).squeeze(-1), -(log_p.exp() * log_p).sum(-1)
        log_std = self.log_std.expand_as(out)
        z = (actions - out) * torch.exp(-log_std)
        log_p = (-0.5 * z.pow(2) - log_std - 0.5 * math.log(2 * math.pi)).sum(-1)
        entropy = (0.5 + 0.5 * math.log(2 * math.pi) + log_std).sum(-1)
        return log_p, entropy

    def numpy_actor(self) -> NumpyActor:
        return NumpyActor(self)

    def act(self, observation: Any, deterministic: bool = False, rng: np.random.Generator | None = None) -> Any:
        """The environment action for one observation, or a list of them for a batch (sampled, or
        the most likely / mean action when ``deterministic``), from the current weights."""
        single = np.shape(observation) == tuple(self.observation_spec.get("shape", ()))
        x = self.encode(observation)
        actor = self.numpy_actor()
        rows = actor.mode(x) if deterministic else actor.sample(x, rng or np.random.default_rng())
        actions = [self.env_action(row) for row in rows]
        return actions[0] if single else actions

    # --- files ---------------------------------------------------------------------------------------

    def model_config(self) -> dict[str, Any]:
        return {"observation": self.observation_spec, "action": self.action_spec,
                "hidden_sizes": list(self.hidden_sizes), "activation": self.activation, "n_costs": self.n_costs,
                "log_std_init": self.log_std_init, "obs_normalization": self.obs_normalization}

    @classmethod
    def from_config(cls, config: dict[str, Any]) -> ActorCritic:
        try:
            return cls(config["observation"], config["action"], config["hidden_sizes"], config["activation"],
                       config["n_costs"], config.get("log_std_init", 0.0),
                       obs_normalization=bool(config.get("obs_normalization", False)))
        except (KeyError, TypeError, IndexError) as exc:
            raise ModelError(f"not a PPO actor-critic configuration ({type(exc).__name__}: {exc})") from None

    def save(self, path: str | os.PathLike[str], extra: dict[str, Any] | None = None) -> os.PathLike[str]:
        """Write ``path`` (``.safetensors``) and the JSON beside it; ``extra`` goes into the JSON."""
        return save_torch_module(path, self, {**self.model_config(), **(extra or {})}, kind=MODEL_KIND)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> ActorCritic:
        module, _ = load_torch_module(path, cls.from_config, kind=MODEL_KIND)
        return module


class NumpyActor:
    """The actor's forward pass in numpy, for sampling actions during rollouts (a snapshot of the
    weights: take a new one after every update)."""

    def __init__(self, agent: ActorCritic) -> None:
        linears = [m for m in agent.actor if isinstance(m, nn.Linear)]
        self.layers = [(m.weight.detach().cpu().numpy().T.copy(), m.bias.detach().cpu().numpy().copy())
                       for m in linears]
        self.activation = np.tanh if agent.activation == "tanh" else (lambda h: np.maximum(h, 0.0))
        self.std = None if agent.discrete else np.exp(agent.log_std.detach().cpu().numpy())

    def forward(self, x: np.ndarray) -> np.ndarray:
        for weight, bias in self.layers[:-1]:
            x = self.activation(x @ weight + bias)
        weight, bias = self.layers[-1]
        return x @ weight + bias

    def sample(self, x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        out = self.forward(x)
        if self.std is None:  # Gumbel-max: argmax(logits + Gumbel noise) is a categorical sample
            return (out - np.log(-np.log(rng.random(out.shape)))).argmax(axis=1)
        return (out + self.std * rng.standard_normal(out.shape)).astype(np.float32)

    def mode(self, x: np.ndarray) -> np.ndarray:
        out = self.forward(x)
        return out.argmax(axis=1) if self.std is None else out.astype(np.float32)


# --------------------------------------------------------------------------------------------------
# records


def _plain(value: Any) -> Any:
    """JSON-able: tuples -> lists, NaN -> None, numpy scalars -> Python."""
    if isinstance(value, dict):
        return {key: _plain(v) for key, v in value.items()}
    if isinstance(value, (tuple, list, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return None if not math.isfinite(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


@dataclass(frozen=True)
class PPOIteration:
    """One iteration: rollout statistics (episodes that *ended* in it; NaN when none did), the
    multipliers used for its update, and the update's diagnostics (means over its minibatches)."""

    iteration: int
    steps: int  # environment steps so far (over all copies)
    episodes: int
    mean_return: float
    mean_length: float
    mean_cost: tuple[float, ...]  # per constraint
    multipliers: tuple[float, ...]
    policy_loss: float
    value_loss: float
    cost_value_loss: tuple[float, ...]
    entropy: float
    approx_kl: float
    clip_fraction: float
    explained_variance: float
    epochs: float  # passes actually made (fractional when stopped by target_kl)
    stopped_early: bool
    learning_rate: float
    steps_per_second: float
    seconds: float
    # running standard deviation of the returns of the reward, then of each cost (PPO-Lagrangian;
    # the divisors of the advantages under ``advantage_scale="returns"``)
    return_scales: tuple[float, ...] = ()
    # J_c per constraint the multipliers were updated from in this iteration (empty: no update)
    cost_estimate: tuple[float, ...] = ()
    # the environment's own info["cost"] per episode, summed over constraints (rollout cost per step
    # x mean episode length), also when a learned cost drives training; NaN when it reports none
    true_cost: float = math.nan

    def as_dict(self) -> dict[str, Any]:
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}


@dataclass(frozen=True)
class EpisodeStats:
    """Finished episodes: return, length, cost sum per constraint ``(E, k)``, and the environment
    step count (over all copies, at the end of the round of steps in which it ended) of its end."""

    returns: np.ndarray
    lengths: np.ndarray
    costs: np.ndarray
    end_steps: np.ndarray

    def __len__(self) -> int:
        return len(self.returns)

    def as_dict(self) -> dict[str, Any]:
        return {"returns": _plain(self.returns), "lengths": _plain(self.lengths), "costs": _plain(self.costs),
                "end_steps": _plain(self.end_steps)}


@dataclass
class PPOResult:
    """What :func:`train_ppo` returns; ``save(path)`` writes the policy with this run's settings."""

    policy: ActorCritic
    config: PPOConfig
    lagrangian: LagrangianConfig | None
    history: list[PPOIteration]
    episodes: EpisodeStats
    multipliers: np.ndarray  # final values, (n_constraints,) (empty for plain PPO)
    steps: int
    seconds: float
    provenance: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | os.PathLike[str]) -> os.PathLike[str]:
        lagrangian = None if self.lagrangian is None else asdict(self.lagrangian)
        training = {"ppo": asdict(self.config), "lagrangian": lagrangian,
                    "steps": self.steps, "seconds": self.seconds, "multipliers": _plain(self.multipliers),
                    **self.provenance}
        return self.policy.save(path, {"training": _plain(training)})


# --------------------------------------------------------------------------------------------------
# rollouts


class _CostReader:
    """Reads ``info["cost"]``: a number or a vector whose length, once seen, stays fixed."""

    def __init__(self, n: int | None) -> None:
        self.n = n  # None until the first cost arrives (or the Lagrangian limits fix it)
        self.seen = False

    def read(self, info: dict[str, Any], env_index: int, step: int) -> np.ndarray | None:
        raw = info.get("cost")
        if raw is None:
            return None
        try:
            cost = np.asarray(raw, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise DataError(f"info['cost'] must be a number or a vector of numbers, got {raw!r} "
                            f"(environment {env_index}, step {step})") from None
        if cost.size == 0:
            raise DataError(f"info['cost'] is empty (environment {env_index}, step {step})")
        if not np.all(np.isfinite(cost)):
            raise DataError(f"info['cost'] is not finite: {cost.tolist()} (environment {env_index}, step {step})",
                            hint="an environment must report a finite cost on every step")
        if self.n is None:
            self.n = cost.size
        elif cost.size != self.n:
            before = "the cost limits name" if not self.seen else "earlier steps reported"
            raise DataError(f"info['cost'] has {cost.size} entries, {before} {self.n} "
                            f"(environment {env_index}, step {step})",
                            hint="report one cost per constraint on every step, always in the same order")
        self.seen = True
        return cost

    def accept(self, k: int) -> None:
        """A whole rollout's costs arrived at once (``cost_fn``): ``k`` per step, fixed once seen."""
        if self.n is None:
            self.n = k
        elif k != self.n:
            before = "the cost limits name" if not self.seen else "earlier rollouts had"
            raise DataError(f"cost_fn returned {k} cost(s) per step, {before} {self.n}",
                            hint="return one cost per constraint, always in the same order")
        self.seen = True


class _ReturnScales:
    """The running standard deviation of each signal's returns (reward, then every cost): an
    exponential average over iterations (memory :data:`RETURN_SCALE_MEMORY`), never below
    :data:`RETURN_SCALE_FLOOR` times the largest value it reached, so a constraint the agent stopped
    breaking keeps a finite scale; a signal whose returns never varied has scale 1."""

    def __init__(self) -> None:
        self.values: np.ndarray | None = None
        self.peak: np.ndarray | None = None

    def update(self, returns: np.ndarray) -> np.ndarray:
        now = np.asarray(returns, dtype=np.float64).std(axis=0)
        if self.values is None or self.values.shape != now.shape:
            self.values, self.peak = now.copy(), now.copy()
        else:
            self.values = RETURN_SCALE_MEMORY * self.values + (1 - RETURN_SCALE_MEMORY) * now
            self.peak = np.maximum(self.peak, self.values)
        return self.scales()

    def scales(self) -> np.ndarray:
        if self.values is None:
            return np.zeros(0)
        return np.where(self.peak > 0, np.maximum(self.values, RETURN_SCALE_FLOOR * self.peak), 1.0)


@dataclass(frozen=True)
class Rollout:
    """One iteration's steps, as :func:`train_ppo` hands them to ``reward_fn`` / ``cost_fn``.

    Arrays are ``[T, N, ...]`` (``T`` = ``n_steps`` rounds over ``N`` = ``n_envs`` copies):
    ``obs`` the raw observation features of the state each step started in (not normalised),
    ``actions`` the actions learned from (continuous ones before clipping to the bounds),
    ``next_obs`` the state each step reached (the episode's last observation where it ended, not
    the next episode's first), ``rewards`` the environment's, ``dones`` 1 where an episode ended,
    ``info`` one array per key named in the callable's ``info_keys`` attribute.
    """

    obs: np.ndarray
    actions: np.ndarray
    next_obs: np.ndarray
    rewards: np.ndarray
    dones: np.ndarray
    info: dict[str, np.ndarray]


def _info_keys(*fns: Any) -> tuple[str, ...]:
    keys: list[str] = []
    for fn in fns:
        for key in getattr(fn, "info_keys", ()) if fn is not None else ():
            if not isinstance(key, str):
                raise SymlearnError(f"info_keys must be strings, got {key!r}")
            if key not in keys:
                keys.append(key)
    return tuple(keys)


def _signal(value: Any, what: str, shape: tuple[int, int]) -> np.ndarray:
    """``reward_fn``/``cost_fn`` output checked: ``[T, N]`` or ``[T, N, k]``, finite, as float64."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{what} must return an array of numbers, got {type(value).__name__}") from None
    if array.shape[:2] != shape or array.ndim not in (2, 3):
        raise DataError(f"{what} returned shape {array.shape}; expected {shape} or {shape + ('k',)}")
    if not np.isfinite(array).all():
        raise DataError(f"{what} returned NaN or inf")
    return array


def _reported_cost(value: Any) -> float:
    """An ``info["cost"]`` that only gets reported (a learned cost drives training): its sum, NaN
    when it is not numbers -- never an error, since training does not depend on it."""
    try:
        total = float(np.sum(np.asarray(value, dtype=np.float64)))
    except (TypeError, ValueError):
        return math.nan
    return total if math.isfinite(total) else math.nan


class _Rollouts:
    """``n_envs`` environments stepped in turn, each reset as soon as its episode ends."""

    def __init__(self, envs: list[Any], agent: ActorCritic, costs: _CostReader, seed: int | None,
                 info_keys: tuple[str, ...] = (), read_costs: bool = True) -> None:
        self.envs, self.agent, self.costs = envs, agent, costs
        self.info_keys, self.read_costs = info_keys, read_costs
        self._shapes: dict[str, tuple[int, ...]] = {}   # per recorded info key, once seen
        first = [env.reset(seed=None if seed is None else seed + i)[0] for i, env in enumerate(envs)]
        self.obs = agent.features(np.stack([np.asarray(o) for o in first]))  # raw features, not normalised
        n = len(envs)
        self.ep_return, self.ep_length = np.zeros(n), np.zeros(n, dtype=np.int64)
        self.ep_cost = np.zeros((n, costs.n or 0))
        self.steps = 0
        self.finished: list[tuple[float, int, np.ndarray, int]] = []  # return, length, costs, end step
        self.recent_lengths: deque[int] = deque(maxlen=LENGTH_MEMORY)
        spec = getattr(envs[0], "spec", None)
        self.time_limit = getattr(spec, "max_episode_steps", None)  # gymnasium's TimeLimit, when known

    def collect(self, n_steps: int, actor: NumpyActor, rng: np.random.Generator,
                cost_fn: Callable[[Rollout], Any] | None = None) -> dict[str, Any]:
        """``n_steps`` rounds of steps. Observations come back as raw :meth:`ActorCritic.features`
        (``obs``, ``next_obs``, ``last_obs`` and the truncated ones); actions are sampled from the
        normalised ones. The costs are every step's ``info["cost"]``, or ``cost_fn``'s verdict on
        the whole rollout at once (one vectorised call instead of one per step)."""
        n_envs, agent = len(self.envs), self.agent
        obs = np.zeros((n_steps, n_envs, agent.obs_dim), dtype=np.float32)
        act_shape = () if agent.discrete else (agent.action_spec["shape"][0],)
        actions = np.zeros((n_steps, n_envs, *act_shape), dtype=np.int64 if agent.discrete else np.float32)
        rewards = np.zeros((n_steps, n_envs))
        dones = np.zeros((n_steps, n_envs))
        reached = np.zeros((n_steps, n_envs, agent.obs_dim), dtype=np.float32)
        costs = np.zeros((n_steps, n_envs, self.costs.n or 0))
        info_arrays: dict[str, np.ndarray] = {}
        self._shapes = {}                 # the arrays are new: their first step takes the slow path
        truncated: list[tuple[int, int, np.ndarray]] = []  # (t, env, last observation) to bootstrap
        ends: list[tuple[int, int]] = []  # (t, env) where an episode ended
        read_costs = self.read_costs
        # with cost_fn, the environment's own info["cost"] (summed) is kept beside it, for reports only
        reported = None if read_costs else np.full((n_steps, n_envs), np.nan)
        for t in range(n_steps):
            obs[t] = self.obs
            actions[t] = actor.sample(agent.normalize(self.obs), rng)
            next_obs = np.empty_like(self.obs)
            for i, env in enumerate(self.envs):
                o, r, term, trunc, info = env.step(agent.env_action(actions[t, i]))
                if not math.isfinite(r):
                    raise DataError(f"the reward is not finite: {r} "
                                    f"(environment {i}, step {self.steps + t * n_envs + i})")
                rewards[t, i] = r
                if read_costs:
                    cost = self.costs.read(info, i, self.steps + t * n_envs + i)
                    if cost is not None:
                        if costs.shape[2] != cost.size:  # the first cost ever: widen the zero-width buffer
                            costs = np.zeros((n_steps, n_envs, cost.size))
                        costs[t, i] = cost
                elif reported is not None and "cost" in info:
                    reported[t, i] = _reported_cost(info["cost"])
                for key in self.info_keys:
                    self._record(info_arrays, key, info, t, i, n_steps, n_envs)
                reached[t, i] = agent.features(np.asarray(o)[None])[0]
                next_obs[i] = reached[t, i]
                if term or trunc:
                    dones[t, i] = 1.0
                    ends.append((t, i))
                    if trunc and not term:
                        truncated.append((t, i, reached[t, i].copy()))
                    o, _ = env.reset()
                    next_obs[i] = agent.features(np.asarray(o)[None])[0]
            self.obs = next_obs
        rollout = Rollout(obs, actions, reached, rewards, dones, info_arrays)
        if cost_fn is not None:
            costs = _signal(cost_fn(rollout), "cost_fn", (n_steps, n_envs))
            if costs.ndim == 2:
                costs = costs[..., None]
            self.costs.accept(costs.shape[2])
        self._account(rewards, costs, ends, n_steps)
        self.steps += n_steps * n_envs
        return {"obs": obs, "actions": actions, "rewards": rewards, "dones": dones, "costs": costs,
                "true_costs": reported if reported is not None else costs.sum(axis=2) if self.costs.seen
                else np.full((n_steps, n_envs), np.nan),
                "truncated": truncated, "last_obs": self.obs.copy(), "rollout": rollout,
                "episodes": self.finished[len(self.finished) - len(ends):]}

    def true_cost_estimate(self, true_costs: np.ndarray) -> float:
        """The environment's cost per episode (summed over constraints) from a rollout's ``[T, N]``
        step costs, estimated as :meth:`cost_estimate` does; NaN where it reported none."""
        length = self.episode_length()
        finite = true_costs[np.isfinite(true_costs)]
        return float(finite.mean() * length) if finite.size and length is not None else math.nan

    def _record(self, arrays: dict[str, np.ndarray], key: str, info: dict[str, Any], t: int, i: int,
                n_steps: int, n_envs: int) -> None:
        if key not in info:
            raise DataError(f"the environment reports no info[{key!r}] (environment {i}, "
                            f"step {self.steps + t * n_envs + i})",
                            hint="reward_fn/cost_fn name it in info_keys")
        value = np.asarray(info[key])
        if value.shape == self._shapes.get(key):   # every step after the first
            arrays[key][t, i] = value
            return
        if key not in arrays:
            arrays[key] = np.zeros((n_steps, n_envs, *value.shape),
                                   dtype=np.float64 if value.dtype.kind in "fiub" else value.dtype)
        if value.shape != arrays[key].shape[2:]:
            raise DataError(f"info[{key!r}] has shape {value.shape}, earlier steps {arrays[key].shape[2:]} "
                            f"(environment {i}, step {self.steps + t * n_envs + i})")
        arrays[key][t, i] = value
        self._shapes[key] = value.shape

    def _account(self, rewards: np.ndarray, costs: np.ndarray, ends: list[tuple[int, int]], n_steps: int) -> None:
        """Episode returns, lengths and cost sums, per environment in one pass over its segments
        between episode ends (episodes carry over from one rollout to the next)."""
        if self.ep_cost.shape[1] != costs.shape[2]:  # the first costs ever arrived in this rollout
            self.ep_cost = np.zeros((len(self.envs), costs.shape[2]))
        by_env: list[list[int]] = [[] for _ in self.envs]
        for t, i in ends:
            by_env[i].append(t)
        finished: list[tuple[int, int, tuple[float, int, np.ndarray, int]]] = []
        for i, times in enumerate(by_env):
            starts = [0] + [t + 1 for t in times]
            segments = starts if starts[-1] < n_steps else starts[:-1]
            reward_sums = np.add.reduceat(rewards[:, i], segments)
            cost_sums = np.add.reduceat(costs[:, i], segments, axis=0) if costs.shape[2] else \
                np.zeros((len(segments), 0))
            for j, t in enumerate(times):
                ret = self.ep_return[i] + reward_sums[j]
                length = self.ep_length[i] + (t + 1 - starts[j])
                cost = self.ep_cost[i] + cost_sums[j]
                finished.append((t, i, (float(ret), int(length), cost, self.steps + (t + 1) * len(self.envs))))
                self.ep_return[i], self.ep_length[i], self.ep_cost[i] = 0.0, 0, 0.0
            if starts[-1] < n_steps:  # the unfinished episode carries over
                self.ep_return[i] += reward_sums[-1]
                self.ep_length[i] += n_steps - starts[-1]
                self.ep_cost[i] += cost_sums[-1]
        finished.sort(key=lambda row: (row[0], row[1]))  # in the order the steps happened
        self.finished.extend(row for _, _, row in finished)
        self.recent_lengths.extend(row[1] for _, _, row in finished)

    def episode_length(self) -> float | None:
        """The expected episode length: the mean of the last finished ones; before any ended, the
        time limit when the environment declares one, else the longest episode still running (a
        lower bound); ``None`` before a single step."""
        if self.recent_lengths:
            return float(np.mean(self.recent_lengths))
        if self.time_limit:
            return float(self.time_limit)
        longest = int(self.ep_length.max()) if self.ep_length.size else 0
        return float(longest) if longest > 0 else None

    def cost_estimate(self, costs: np.ndarray) -> np.ndarray | None:
        """``J_c`` per constraint from a whole rollout's ``[T, N, k]`` step costs: the cost per step
        times :meth:`episode_length` -- over the episodes that finished, exactly their mean cost
        (a ratio estimate), and defined in every rollout, also one in which no episode ended."""
        length = self.episode_length()
        if length is None or costs.shape[0] * costs.shape[1] == 0:
            return None
        return costs.reshape(-1, costs.shape[2]).mean(axis=0) * length

    def episode_stats(self, n_costs: int) -> EpisodeStats:
        rows = self.finished
        costs = np.zeros((len(rows), n_costs))
        for j, (_, _, c, _) in enumerate(rows):
            costs[j, : c.size] = c  # episodes that ended before the first cost arrived cost 0
        return EpisodeStats(np.array([r[0] for r in rows]), np.array([r[1] for r in rows], dtype=np.int64),
                            costs, np.array([r[3] for r in rows], dtype=np.int64))


def _gae(rewards: np.ndarray, values: np.ndarray, last_values: np.ndarray, dones: np.ndarray,
         gamma: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray]:
    """Generalised advantage estimation for ``C`` signals at once (reward and costs):
    ``rewards``/``values`` ``(T, N, C)``, ``last_values`` ``(N, C)``, ``dones`` ``(T, N)`` (the
    episode ended at step t), ``gamma`` ``(C,)``. Returns advantages and returns ``(T, N, C)``."""
    advantages = np.zeros_like(rewards)
    running = np.zeros_like(last_values)
    for t in reversed(range(len(rewards))):
        next_values = last_values if t == len(rewards) - 1 else values[t + 1]
        alive = (1.0 - dones[t])[:, None]
        delta = rewards[t] + gamma * next_values * alive - values[t]
        running = delta + gamma * lam * alive * running
        advantages[t] = running
    return advantages, advantages + values


def _make_envs(env_fn: Callable[[], Any] | str, n: int) -> list[Any]:
    if isinstance(env_fn, str):
        import gymnasium

        env_id = env_fn
        env_fn = lambda: gymnasium.make(env_id)  # noqa: E731
    if not callable(env_fn):
        raise SymlearnError(f"env_fn must be a gymnasium id or a function returning an environment, got {env_fn!r}")
    return [env_fn() for _ in range(n)]


# --------------------------------------------------------------------------------------------------
# training


def train_ppo(
    env_fn: Callable[[], Any] | str,
    total_steps: int,
    config: PPOConfig | None = None,
    lagrangian: LagrangianConfig | None = None,
    callback: Callable[[PPOIteration, ActorCritic], bool | None] | None = None,
    *,
    reward_fn: Callable[[Rollout], Any] | None = None,
    cost_fn: Callable[[Rollout], Any] | None = None,
    policy: ActorCritic | None = None,
) -> PPOResult:
    """Train PPO (or PPO-Lagrangian) for at least ``total_steps`` environment steps.

    ``env_fn`` returns a fresh environment (it is called ``n_envs`` times) or is a gymnasium id.
    ``callback(record, policy)`` runs after every iteration; returning ``False`` stops training.

    ``reward_fn(rollout)`` and ``cost_fn(rollout)`` see each iteration's :class:`Rollout` once,
    after it was collected, and return the rewards to learn from (``[T, N]``; the episode returns
    reported stay the environment's) and the costs (``[T, N]`` or ``[T, N, k]``, instead of
    ``info["cost"]``): a learned reward or cost is then one vectorised evaluation per rollout,
    not a call per step. Info keys they need are named in their ``info_keys`` attribute.
    ``policy`` continues training an existing :class:`ActorCritic` (same spaces) in place.
    """
    config = config or PPOConfig()
    if isinstance(policy, ActorCritic) and config.normalize_observations is None:
        # a continued policy keeps its own inputs (a nominal PPO phase, then a Lagrangian one)
        config = replace(config, normalize_observations=policy.obs_normalization)
    config = config.resolved(constrained=lagrangian is not None)
    if not isinstance(total_steps, (int, np.integer)) or total_steps < 1:
        raise SymlearnError(f"total_steps must be a positive integer, got {total_steps!r}")
    for name, fn in (("reward_fn", reward_fn), ("cost_fn", cost_fn)):
        if fn is not None and not callable(fn):
            raise SymlearnError(f"{name} must be callable, got {fn!r}")
    if policy is not None and not isinstance(policy, ActorCritic):
        raise SymlearnError(f"policy must be an ActorCritic, got {type(policy).__name__}")
    envs = _make_envs(env_fn, config.n_envs)
    previous_threads = torch.get_num_threads()
    try:
        if config.torch_threads is not None:
            torch.set_num_threads(config.torch_threads)
        return _train(envs, int(total_steps), config, lagrangian, callback, reward_fn, cost_fn, policy)
    finally:
        torch.set_num_threads(previous_threads)
        for env in envs:
            env.close()


def _train(envs: list[Any], total_steps: int, config: PPOConfig, lagrangian: LagrangianConfig | None,
           callback: Callable[[PPOIteration, ActorCritic], bool | None] | None,
           reward_fn: Callable[[Rollout], Any] | None = None, cost_fn: Callable[[Rollout], Any] | None = None,
           policy: ActorCritic | None = None) -> PPOResult:
    started = time.perf_counter()
    seed = config.seed
    rng = np.random.default_rng(seed)
    generator = torch.Generator().manual_seed(seed if seed is not None else int(rng.integers(2**62)))
    device = torch.device(config.device)
    if policy is None:
        agent = ActorCritic.for_spaces(envs[0].observation_space, envs[0].action_space,
                                       hidden_sizes=config.hidden_sizes, activation=config.activation,
                                       log_std_init=config.log_std_init, generator=generator,
                                       obs_normalization=config.normalize_observations)
    else:
        agent = _continued(policy, envs[0], config)
    costs = _CostReader(None if lagrangian is None else lagrangian.n_constraints)
    if policy is not None and lagrangian is not None and agent.n_costs:
        if costs.n is not None and costs.n != agent.n_costs:
            raise SymlearnError(f"the policy has {agent.n_costs} cost critic(s) but the cost limits name {costs.n}")
        costs.n = agent.n_costs
    elif lagrangian is not None and costs.n is not None:
        agent.add_cost_critics(costs.n, generator)
    agent.to(device)
    main_params = [p for name, p in agent.named_parameters() if not name.startswith("cost_critics.")]
    # foreach=True: one pass over all parameter tensors per Adam step (torch picks the per-tensor loop
    # on CPU by default); about 20 % faster for networks this small
    optimizer = torch.optim.Adam(main_params, lr=config.learning_rate, eps=1e-5, foreach=True)
    cost_optimizer = None if not agent.n_costs else \
        torch.optim.Adam(agent.cost_critics.parameters(), lr=config.learning_rate, eps=1e-5, foreach=True)
    multipliers = None
    return_scales = _ReturnScales()
    rollouts = _Rollouts(envs, agent, costs, seed, _info_keys(reward_fn, cost_fn), read_costs=cost_fn is None)
    fresh_critics = policy is not None  # their outputs are in returns, not yet in the running scales
    batch = config.n_envs * config.n_steps
    n_iterations = -(-total_steps // batch)
    history: list[PPOIteration] = []
    desc = "PPO-Lagrangian" if lagrangian is not None else "PPO"
    bar = ProgressBar(n_iterations, desc=desc, unit="iter")
    with bar:
        for iteration in range(1, n_iterations + 1):
            iteration_start = time.perf_counter()
            lr = config.learning_rate * (1.0 - (iteration - 1) / n_iterations if config.anneal_lr else 1.0)
            for opt in (optimizer, cost_optimizer):
                for group in (opt.param_groups if opt is not None else ()):
                    group["lr"] = lr

            data = rollouts.collect(config.n_steps, agent.numpy_actor(), rng, cost_fn)
            if reward_fn is not None:  # the agent learns from these; the episode returns stay the environment's
                learned = _signal(reward_fn(data["rollout"]), "reward_fn", data["rewards"].shape)
                if learned.ndim != 2:
                    raise DataError(f"reward_fn returned shape {learned.shape}; expected {data['rewards'].shape}")
                data = {**data, "rewards": learned}
            if agent.obs_normalization:  # this rollout joins the statistics, then is learned from with them
                agent.update_observation_stats(data["obs"].reshape(-1, agent.obs_dim))
                data = {**data, "obs": agent.normalize(data["obs"]), "last_obs": agent.normalize(data["last_obs"]),
                        "truncated": [(t, i, agent.normalize(x)) for t, i, x in data["truncated"]]}
            n_costs = costs.n or 0
            if lagrangian is not None:
                if not costs.seen:
                    raise DataError("PPO-Lagrangian got no info['cost'] in a whole rollout "
                                    f"({batch} steps)", hint="wrap the environment so that every step reports "
                                    "info['cost'] (0 when nothing is violated), e.g. with symlearn.backends.cost")
                if agent.n_costs == 0:  # a scalar limit: the first rollout told how many constraints there are
                    new_params = agent.add_cost_critics(n_costs, generator)
                    cost_optimizer = torch.optim.Adam(new_params, lr=lr, eps=1e-5, foreach=True)
                    agent.cost_critics.to(device)
                if multipliers is None:
                    multipliers = Multipliers(lagrangian, n_costs)
            episodes = data["episodes"]
            ep_costs = np.zeros((len(episodes), n_costs))
            for j, (_, _, c, _) in enumerate(episodes):
                ep_costs[j, : c.size] = c  # an episode that ended before the first cost arrived cost 0
            mean_cost = ep_costs.mean(axis=0) if episodes else np.full(n_costs, np.nan)
            estimate = None
            if multipliers is not None:
                if lagrangian.cost_estimate == "rollout":
                    estimate = rollouts.cost_estimate(data["costs"])
                elif episodes:
                    estimate = mean_cost
                if estimate is not None:
                    multipliers.update(estimate)
            lambdas = multipliers.values.copy() if multipliers is not None else np.zeros(0)

            stats = _update(agent, optimizer, cost_optimizer, data, config, lagrangian, lambdas, rng, device,
                            return_scales, fresh_critics)
            fresh_critics = False
            seconds = time.perf_counter() - iteration_start
            record = PPOIteration(
                iteration=iteration, steps=rollouts.steps, episodes=len(episodes),
                mean_return=float(np.mean([e[0] for e in episodes])) if episodes else math.nan,
                mean_length=float(np.mean([e[1] for e in episodes])) if episodes else math.nan,
                mean_cost=tuple(float(c) for c in mean_cost), multipliers=tuple(float(x) for x in lambdas),
                cost_estimate=() if estimate is None else tuple(float(c) for c in estimate),
                true_cost=rollouts.true_cost_estimate(data["true_costs"]),
                learning_rate=lr, steps_per_second=batch / seconds, seconds=seconds, **stats)
            history.append(record)
            bar.update(1, **{"return": record.mean_return, "cost": float(np.sum(record.mean_cost))
                             if record.mean_cost else None, "lambda": float(np.max(lambdas)) if lambdas.size else None})
            if callback is not None and callback(record, agent) is False:
                break
    agent.eval()
    n_costs = costs.n or 0
    if config.normalize_values and return_scales.values is not None:  # the critics output returns again
        _rescale_critics(agent, n_costs if lagrangian is not None else 0, return_scales.scales())
    return PPOResult(policy=agent, config=config, lagrangian=lagrangian, history=history,
                     episodes=rollouts.episode_stats(n_costs),
                     multipliers=np.zeros(0) if multipliers is None else multipliers.values.copy(),
                     steps=rollouts.steps, seconds=time.perf_counter() - started,
                     provenance={"environment": _env_name(envs[0]), "torch": torch.__version__})


def _continued(policy: ActorCritic, env: Any, config: PPOConfig) -> ActorCritic:
    """``policy`` checked against the environment's spaces before training goes on with it."""
    want_obs = _space_spec(env.observation_space, "observation")
    want_act = _space_spec(env.action_space, "action")
    if policy.observation_spec != want_obs or policy.action_spec != want_act:
        raise SymlearnError("the policy was made for other spaces than this environment's",
                            hint=f"policy: observation {policy.observation_spec}, action {policy.action_spec}; "
                                 f"environment: observation {want_obs}, action {want_act}")
    if policy.obs_normalization != config.normalize_observations:
        raise SymlearnError(f"the policy {'has' if policy.obs_normalization else 'has no'} observation "
                            f"normalisation but PPOConfig.normalize_observations={config.normalize_observations}")
    policy.train()
    return policy


def _env_name(env: Any) -> str:
    spec = getattr(env, "spec", None)
    return getattr(spec, "id", None) or type(getattr(env, "unwrapped", env)).__name__


def _update(agent: ActorCritic, optimizer: torch.optim.Optimizer, cost_optimizer: torch.optim.Optimizer | None,
            data: dict[str, Any], config: PPOConfig, lagrangian: LagrangianConfig | None, lambdas: np.ndarray,
            rng: np.random.Generator, device: torch.device, return_scales: _ReturnScales | None = None,
            critics_in_returns: bool = False) -> dict[str, Any]:
    """Advantages for the rollout, then the clipped-surrogate epochs. Returns the diagnostics."""
    T, N = data["rewards"].shape
    n_costs = agent.n_costs if lagrangian is not None else 0
    as_tensor = lambda x: torch.as_tensor(x, device=device)  # noqa: E731
    obs = as_tensor(data["obs"].reshape(T * N, -1))
    actions = as_tensor(data["actions"].reshape(T * N, *data["actions"].shape[2:]))

    signals = np.concatenate([data["rewards"][..., None], data["costs"][..., :n_costs]], axis=2)
    cost_gamma = config.gamma if lagrangian is None or lagrangian.cost_gamma is None else lagrangian.cost_gamma
    gamma = np.array([config.gamma] + [cost_gamma] * n_costs)
    # the critics' output unit (normalize_values: the running scale of each signal's returns, else 1)
    n_signals = 1 + n_costs
    old_scales = np.ones(n_signals)
    if config.normalize_values and return_scales is not None:
        if return_scales.scales().shape != (n_signals,):  # first update: scales of the returns without critics
            zeros = np.zeros_like(signals)
            return_scales.update(_gae(signals, zeros, zeros[0], data["dones"], gamma, 1.0)[1].reshape(T * N, -1))
        old_scales = return_scales.scales()
        if critics_in_returns:  # a continued policy's critics output returns: put them in the new unit
            _rescale_critics(agent, n_costs, 1.0 / old_scales)
    unit = as_tensor(old_scales.astype(np.float32))

    # values, cost values and old log-probabilities of the whole rollout in one pass each
    with torch.no_grad():
        def signal_values(x: torch.Tensor) -> torch.Tensor:
            return torch.cat([agent.value(x)[:, None], agent.cost_values(x)[:, :n_costs]], 1) * unit

        values = signal_values(obs).double().cpu().numpy().reshape(T, N, 1 + n_costs)
        last_values = signal_values(as_tensor(data["last_obs"])).double().cpu().numpy()
        old_log_prob, _ = agent.log_prob_entropy(obs, actions)
        if config.entropy_mode == "reward":  # soft return: the entropy of every later step counts too
            signals[..., 0] -= config.ent_coef * old_log_prob.double().cpu().numpy().reshape(T, N)
        if data["truncated"]:  # a time limit is not a terminal state: bootstrap with its value
            ts, envs, last = zip(*data["truncated"])
            final = signal_values(as_tensor(np.stack(last))).double().cpu().numpy()
            signals[list(ts), list(envs)] += gamma * final
    advantages, returns = _gae(signals, values, last_values, data["dones"], gamma, config.gae_lambda)
    advantages, returns = advantages.reshape(T * N, -1), returns.reshape(T * N, -1)

    scales = np.zeros(0)
    if return_scales is not None and (lagrangian is not None or config.normalize_values):
        scales = return_scales.update(returns)
    targets = returns
    if config.normalize_values:  # new unit: rescale the critics' last layers so their values stay put
        _rescale_critics(agent, n_costs, old_scales / scales)
        targets = returns / scales
    # the Lagrangian's advantage (see the module docstring); lambda = 0 is plain PPO
    mixed = advantages
    if lagrangian is not None and lagrangian.advantage_scale == "returns":  # in standard deviations of returns
        mixed = advantages / scales
    policy_adv = (mixed[:, 0] - mixed[:, 1:1 + len(lambdas)] @ lambdas) / (1.0 + lambdas.sum())
    policy_adv_t = as_tensor(policy_adv.astype(np.float32))
    returns_t = as_tensor(targets.astype(np.float32))

    main_params = [p for group in optimizer.param_groups for p in group["params"]]
    sums = {"policy_loss": 0.0, "value_loss": 0.0, "entropy": 0.0, "approx_kl": 0.0, "clip_fraction": 0.0}
    cost_loss_sum = np.zeros(n_costs)
    n_updates, stopped_early, minibatches_per_epoch = 0, False, -(-(T * N) // config.batch_size)
    bonus = config.ent_coef if config.entropy_mode == "bonus" else 0.0  # "reward": in the returns already
    for _epoch in range(config.n_epochs):
        order = torch.as_tensor(rng.permutation(T * N), device=device)
        for start in range(0, T * N, config.batch_size):
            idx = order[start:start + config.batch_size]
            log_prob, entropy = agent.log_prob_entropy(obs[idx], actions[idx])
            log_ratio = log_prob - old_log_prob[idx]
            ratio = log_ratio.exp()
            with torch.no_grad():
                approx_kl = float(((ratio - 1) - log_ratio).mean())  # the k3 estimator (Schulman's blog)
            if config.target_kl is not None and approx_kl > 1.5 * config.target_kl:
                stopped_early = True
                break
            adv = policy_adv_t[idx]
            if config.normalize_advantage and len(idx) > 1:
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
            clipped = ratio.clamp(1 - config.clip_range, 1 + config.clip_range)
            policy_loss = -torch.min(adv * ratio, adv * clipped).mean()
            value_loss = (agent.value(obs[idx]) - returns_t[idx, 0]).pow(2).mean()
            entropy_mean = entropy.mean()
            loss = policy_loss - bonus * entropy_mean + config.vf_coef * value_loss
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            nn.utils.clip_grad_norm_(main_params, config.max_grad_norm)
            optimizer.step()
            if n_costs:
                cost_losses = (agent.cost_values(obs[idx]) - returns_t[idx, 1:]).pow(2).mean(0)
                cost_optimizer.zero_grad(set_to_none=True)
                cost_losses.sum().backward()
                nn.utils.clip_grad_norm_(agent.cost_critics.parameters(), config.max_grad_norm)
                cost_optimizer.step()
                cost_loss_sum += cost_losses.detach().cpu().numpy()
            n_updates += 1
            sums["policy_loss"] += policy_loss.item()
            sums["value_loss"] += value_loss.item()
            sums["entropy"] += entropy_mean.item()
            sums["approx_kl"] += approx_kl
            sums["clip_fraction"] += float(((ratio - 1).abs() > config.clip_range).float().mean())
        if stopped_early:
            break
    means = {k: v / n_updates if n_updates else math.nan for k, v in sums.items()}
    variance = np.var(returns[:, 0])
    residual = returns[:, 0] - values.reshape(T * N, -1)[:, 0]
    explained = math.nan if variance == 0 else float(1 - np.var(residual) / variance)
    return {**means, "cost_value_loss": tuple(float(x) for x in cost_loss_sum / max(n_updates, 1)),
            "return_scales": tuple(float(x) for x in scales),
            "explained_variance": explained, "epochs": n_updates / minibatches_per_epoch,
            "stopped_early": stopped_early}


def _rescale_critics(agent: ActorCritic, n_costs: int, factors: np.ndarray) -> None:
    """Multiply the output layer of the reward critic (``factors[0]``) and of each cost critic by a
    factor: the outputs scale by it (how PopArt keeps a critic's values when their unit changes)."""
    critics = [agent.critic, *list(agent.cost_critics)[:n_costs]]
    with torch.no_grad():
        for critic, factor in zip(critics, factors):
            if factor != 1.0:
                last = critic[-1]
                last.weight.mul_(float(factor))
                last.bias.mul_(float(factor))


# --------------------------------------------------------------------------------------------------
# evaluation


def evaluate(policy: ActorCritic, env: Any, n_episodes: int = 10, *, seed: int | None = None,
             deterministic: bool = True, max_steps: int = 100_000) -> EpisodeStats:
    """Run ``n_episodes`` with ``policy`` (the mean/most likely action when ``deterministic``);
    episode ``i`` is reset with ``seed + i``. Costs are read from ``info["cost"]`` as in training."""
    rng = np.random.default_rng(seed)
    reader = _CostReader(None)
    rows, step = [], 0
    actor = policy.numpy_actor()
    for episode in range(n_episodes):
        o, _ = env.reset(seed=None if seed is None else seed + episode)
        total, length, cost_sum = 0.0, 0, np.zeros(0)
        for _ in range(max_steps):
            x = policy.encode(np.asarray(o)[None])
            row = actor.mode(x)[0] if deterministic else actor.sample(x, rng)[0]
            o, r, term, trunc, info = env.step(policy.env_action(row))
            total, length, step = total + float(r), length + 1, step + 1
            cost = reader.read(info, 0, step)
            if cost is not None:
                cost_sum = cost if cost_sum.size == 0 else cost_sum + cost
            if term or trunc:
                break
        rows.append((total, length, cost_sum, step))
    n = reader.n or 0
    costs = np.array([c if c.size == n else np.zeros(n) for _, _, c, _ in rows]).reshape(len(rows), n)
    return EpisodeStats(np.array([r[0] for r in rows]), np.array([r[1] for r in rows], dtype=np.int64), costs,
                        np.array([r[3] for r in rows], dtype=np.int64))
