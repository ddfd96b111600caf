"""Lagrange multipliers of PPO-Lagrangian: one per constraint, moved by the gap between an
estimate of the expected episode cost and its limit."""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

import numpy as np

from symlearn.errors import DataError
from symlearn.rl.ppo.config import LagrangianConfig


class Multipliers:
    """One multiplier per constraint, updated from the mean episode costs ``J_c`` of a rollout.

    * ``"gradient"``: ``lambda <- max(0, lambda + lr (J_c - d))``;
    * ``"adam"``: Adam on the loss ``-lambda (J_c - d)`` (its gradient is ``d - J_c``), then
      projected to ``>= 0``; steps of about ``lr`` whatever the size of the violation;
    * ``"pid"``: ``I <- max(0, I + ki (J_c - d))``, ``P`` = EMA of ``J_c - d``, ``D`` =
      ``max(0, C_t - C_{t-delay})`` for an EMA ``C`` of the cost;
      ``lambda = max(0, kp P + I + kd D)``.

    All three are capped at ``max_multiplier`` when set.

    With ``zero_limit_slack`` > 0 a limit of 0 is moved to ``zero_limit_slack x step_cost``
    (:func:`zero_limit_targets`), so that a rollout without cost can lower a multiplier; with 0 (the
    default) the limit is the exact 0, and a multiplier at that limit never comes down.

    >>> m = Multipliers(LagrangianConfig(cost_limit=1.0, update="gradient", lr=0.5, init=0.0), 1)
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

    def update(self, mean_costs: Sequence[float] | np.ndarray,
               step_cost: Sequence[float] | np.ndarray | None = None) -> np.ndarray:
        """One step from the estimates ``mean_costs`` of ``J_c``; ``step_cost``: per constraint, the
        cost of one violating step (training passes the largest step cost seen; None: limits of 0
        stay exact)."""
        costs = np.asarray(mean_costs, dtype=np.float64).reshape(-1)
        if costs.shape != self.limits.shape:
            raise DataError(f"got {costs.size} mean costs for {self.limits.size} constraints")
        c = self.config
        targets = zero_limit_targets(self.limits, c.zero_limit_slack, step_cost)
        error = costs - targets  # > 0: constraint violated, the multiplier should rise
        if c.update == "gradient":
            self.values = np.maximum(0.0, self.values + c.lr * error)
        elif c.update == "adam":  # torch.optim.Adam's: beta1 0.9, eps 1e-8; beta2 = adam_beta2
            grad = -error
            self._adam_t += 1
            self._adam_m = 0.9 * self._adam_m + 0.1 * grad
            self._adam_v = c.adam_beta2 * self._adam_v + (1 - c.adam_beta2) * grad**2
            m_hat = self._adam_m / (1 - 0.9**self._adam_t)
            v_hat = self._adam_v / (1 - c.adam_beta2**self._adam_t)
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


def zero_limit_targets(limits: np.ndarray, slack: float,
                       step_cost: Sequence[float] | np.ndarray | None) -> np.ndarray:
    """The limits the multipliers are moved against: each limit of 0 replaced by ``slack`` times
    ``step_cost`` -- ``slack`` violating steps per episode of the *training* (stochastic) policy.

    Why: at an exact 0 the error ``J_c - 0`` is never negative, so no rule ever lowers a multiplier,
    and Adam's step is scale-free, so each rollout with a single stochastic brush raises it about as
    much as one full of violations. An agent whose exploration raised it stays priced out of every
    route that risks a brush after it has become safe -- the speed cart that stops docking, the
    drone that hovers short of its detour (docs/BENCHMARKS.md, "Over-cautious agents at limit 0").
    With a slack, rollouts whose estimate is under ``slack`` steps an episode lower the multiplier
    and those over it raise it; the greedy policy the user gets is still asked for no cost (an
    evaluation episode pays a step only where the training policy's mode does). Positive limits
    are returned unchanged.

    >>> zero_limit_targets(np.array([0.0, 2.0]), 0.25, [1.0, 1.0]).tolist()
    [0.25, 2.0]
    """
    limits = np.asarray(limits, dtype=np.float64)
    if not slack or step_cost is None:
        return limits
    step_cost = np.broadcast_to(np.asarray(step_cost, dtype=np.float64), limits.shape)
    return np.where(limits == 0, slack * step_cost, limits)
