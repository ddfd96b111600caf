"""VME-ICRL (Liu et al., 2023): variational ICRL with a Beta-distributed feasibility.

ME-ICRL (:mod:`symlearn.learners.neural.me_icrl`) learns one feasibility value ``zeta(s, a)``
per pair. Liu et al.'s variational ICRL treats the feasibility as uncertain: the network gives a
distribution ``q(zeta | s, a) = Beta(a(s, a), b(s, a))`` and the backward step maximises an
evidence lower bound -- the demonstrations' expected log-feasibility under ``q`` minus the
policy's (importance weighted, as in ME-ICRL), minus ``kl_weight`` times the KL divergence of
``q`` from a prior ``Beta(prior)`` on every expert and policy pair. The KL term replaces
ME-ICRL's ad-hoc ``E[1 - zeta]`` regulariser: it pulls pairs the data say little about toward
the prior (by default ``Beta(1, 0.1)``, mean 0.91: most of a state space is feasible, with a
weak concentration of 1.1, so the data decide wherever they speak -- our choice, the paper
leaves the prior to the task) and it keeps the network from becoming certain on few samples.

Parameterisation (so that the learned cost is an ordinary :class:`NeuralCost`): the network
is a two-feature :class:`~symlearn.learners.neural.feature_network.FeatureNetwork` with
sigmoid outputs ``phi_1, phi_2``; the Beta's mean is ``m = 1 - phi_1`` and its concentration
``kappa = min_c + (max_c - min_c) * phi_2`` (``concentration=(min_c, max_c)``), i.e.
``a = m kappa``, ``b = (1 - m) kappa``. The cost ``C = 1 - E_q[zeta] = phi_1`` is then the
network's first feature with ``lambda = (1, 0)``: files, transfer checks and recovery metrics
are those of the other learners, and the second feature (the certainty) travels with the file.

``E_q[log zeta] = digamma(a) - digamma(a + b)`` is used in closed form (no sampling of
``zeta``: the same expectation with no Monte Carlo noise), floored at ``log 1e-6`` as ME-ICRL
floors ``log zeta``. The forward step, the importance weights (on the mean feasibility ``m``)
and the KL early stopping are ME-ICRL's: PPO-Lagrangian on ``C`` with cost limit 0, its
multiplier stepped once per iteration by ``lambda_lr`` times the sampled episodes' discounted cost
(MCE-ICRL's rule; ``lambda_lr=None``: the PPO-Lagrangian's per-rollout rule).

Results as :class:`~symlearn.learners.neural.NeuralMEICRL`, with :class:`VMEIteration` records
(also the mean KL from the prior and the mean concentration after each backward step).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import torch
from torch.distributions import Beta, kl_divergence

from symlearn.errors import SymlearnError
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.me_icrl import LOG_FLOOR, ImportanceWeights, MEIteration, NeuralMEICRL, log_feasibility
from symlearn.learners.neural.neural_cost import NeuralCost
from symlearn.rl.episodes import EpisodeBatch

SHAPE_FLOOR = 1e-4  # Beta parameters stay above this (a sigmoid output of exactly 0 or 1)


@dataclass(frozen=True)
class VMEIteration(MEIteration):
    """:class:`MEIteration` plus the mean KL divergence of ``q(zeta | s, a)`` from the prior and
    the mean concentration ``a + b`` over expert and policy pairs after the backward step."""

    prior_kl: float
    concentration: float


class NeuralVMEICRL(NeuralMEICRL):
    """VME-ICRL: ``NeuralVMEICRL(...).fit(demonstrations, env)`` (module docstring). Parameters
    as :class:`~symlearn.learners.neural.NeuralMEICRL`, and ``kl_weight`` (weight of the KL
    from the prior), ``prior`` (the prior Beta's ``(a0, b0)``), ``concentration`` (the range
    ``(min, max)`` of ``a + b``)."""

    _n_outputs = 2
    _record_type = VMEIteration
    _label = "VME-ICRL"
    regularizer = 0.0  # read by NeuralMEICRL's parameter checks; unused here

    def __init__(self, *, beta: float = 0.01, n_iterations: int = 10, nominal_steps: int = 30_000,
                 policy_steps: int = 20_480, features: str = "state", obs_dims: Sequence[int] | None = None,
                 hidden_sizes: Sequence[int] = (64, 64), learning_rate: float = 3e-3, backward_epochs: int = 20,
                 kl_weight: float = 0.1, prior: Sequence[float] = (1.0, 0.1),
                 concentration: Sequence[float] = (1.0, 100.0), target_kl: float = 10.0,
                 n_policy_episodes: int = 16, bound_penalty: float = 1.0, reset_actor: str = "auto",
                 ppo: dict[str, Any] | None = None, lagrangian: dict[str, Any] | None = None,
                 lambda_lr: float | None = 0.02, discount: float = 0.99, select_inputs: float = 0.01,
                 random_state: int | None = 0) -> None:
        # set here rather than through NeuralMEICRL.__init__: ``regularizer`` is no parameter of
        # this learner (the KL from the prior takes its place), and the parameters are __init__'s
        self.beta = beta
        self.n_iterations = n_iterations
        self.nominal_steps = nominal_steps
        self.policy_steps = policy_steps
        self.features = features
        self.obs_dims = obs_dims
        self.hidden_sizes = hidden_sizes
        self.learning_rate = learning_rate
        self.backward_epochs = backward_epochs
        self.kl_weight = kl_weight
        self.prior = prior
        self.concentration = concentration
        self.target_kl = target_kl
        self.n_policy_episodes = n_policy_episodes
        self.bound_penalty = bound_penalty
        self.reset_actor = reset_actor
        self.ppo = ppo
        self.lagrangian = lagrangian
        self.lambda_lr = lambda_lr
        self.discount = discount
        self.select_inputs = select_inputs
        self.random_state = random_state

    def _check_parameters(self) -> None:
        super()._check_parameters()
        if not (isinstance(self.kl_weight, (int, float)) and math.isfinite(self.kl_weight) and self.kl_weight >= 0):
            raise SymlearnError(f"kl_weight must be a number >= 0, got {self.kl_weight!r}")
        for name in ("prior", "concentration"):
            value = getattr(self, name)
            try:
                pair = [float(x) for x in value]
            except (TypeError, ValueError):
                pair = []
            if len(pair) != 2 or not all(math.isfinite(x) and x > 0 for x in pair):
                raise SymlearnError(f"{name} must be two positive numbers, got {value!r}")
        low, high = (float(x) for x in self.concentration)
        if not low < high:
            raise SymlearnError(f"concentration must be (min, max) with min < max, got {self.concentration!r}")

    def _backward(self, phi: FeatureNetwork, optimizer: torch.optim.Optimizer,
                  expert_in: tuple[torch.Tensor, torch.Tensor | None], batch: EpisodeBatch,
                  cost: NeuralCost) -> tuple[Any, ...]:
        return variational_backward_step(phi, optimizer, expert_in, batch, cost, epochs=int(self.backward_epochs),
                                         kl_weight=float(self.kl_weight), prior=tuple(map(float, self.prior)),
                                         concentration=tuple(map(float, self.concentration)),
                                         target_kl=self.target_kl)


def beta_parameters(outputs: torch.Tensor, concentration: tuple[float, float]) -> tuple[torch.Tensor, torch.Tensor]:
    """The Beta's ``(a, b)`` of network outputs ``(B, 2)``: mean ``1 - phi_1``, concentration
    ``min + (max - min) * phi_2`` (module docstring)."""
    low, high = concentration
    mean = 1.0 - outputs[:, 0]
    kappa = low + (high - low) * outputs[:, 1]
    return (mean * kappa).clamp_min(SHAPE_FLOOR), ((1.0 - mean) * kappa).clamp_min(SHAPE_FLOOR)


def expected_log_feasibility(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """``E[log zeta]`` for ``zeta ~ Beta(a, b)``, floored at ``log LOG_FLOOR``."""
    return (torch.digamma(a) - torch.digamma(a + b)).clamp_min(math.log(LOG_FLOOR))


def variational_backward_step(phi: FeatureNetwork, optimizer: torch.optim.Optimizer,
                              expert_in: tuple[torch.Tensor, torch.Tensor | None], batch: EpisodeBatch,
                              cost: NeuralCost, *, epochs: int, kl_weight: float, prior: tuple[float, float],
                              concentration: tuple[float, float],
                              target_kl: float) -> tuple[float, float, int, float, float, float, float]:
    """VME-ICRL's backward step (module docstring): up to ``epochs`` Adam steps on
    ``-E_D[E_q log zeta] + E_pi[w E_q log zeta] + kl_weight * E[KL(q || prior)]``, with ME-ICRL's
    per-episode importance weights on the mean feasibility and its KL early stopping. Returns
    the mean feasibility ``E_q[zeta]`` of expert and policy pairs afterwards, the epochs run, the
    last importance-weight KL estimates, the mean KL from the prior and the mean concentration."""
    policy_in = cost.tensors(*batch.pairs())
    prior_dist = Beta(torch.tensor(prior[0]), torch.tensor(prior[1]))
    # the weights are taken on the mean feasibility, phi's first output, as in ME-ICRL
    importance = ImportanceWeights(batch, lambda: log_feasibility(phi, policy_in))
    epochs_run, kl_old_new, kl_new_old = 0, 0.0, 0.0
    for _ in range(epochs):
        step_weights, kl_old_new, kl_new_old = importance.update()
        if kl_old_new > target_kl or kl_new_old > target_kl:
            break
        a_e, b_e = beta_parameters(phi(*expert_in), concentration)
        a_p, b_p = beta_parameters(phi(*policy_in), concentration)
        loss = (-expected_log_feasibility(a_e, b_e).mean()
                + (step_weights * expected_log_feasibility(a_p, b_p)).mean())
        if kl_weight:
            loss = loss + kl_weight * 0.5 * (kl_divergence(Beta(a_e, b_e), prior_dist).mean()
                                             + kl_divergence(Beta(a_p, b_p), prior_dist).mean())
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
        epochs_run += 1
    with torch.no_grad():
        a_e, b_e = beta_parameters(phi(*expert_in), concentration)
        a_p, b_p = beta_parameters(phi(*policy_in), concentration)
        prior_kl = 0.5 * float(kl_divergence(Beta(a_e, b_e), prior_dist).mean()
                               + kl_divergence(Beta(a_p, b_p), prior_dist).mean())
        kappa = 0.5 * float((a_e + b_e).mean() + (a_p + b_p).mean())
        expert_feasibility = float((a_e / (a_e + b_e)).mean())
        policy_feasibility = float((a_p / (a_p + b_p)).mean())
    return expert_feasibility, policy_feasibility, epochs_run, kl_old_new, kl_new_old, prior_kl, kappa


__all__ = ["NeuralVMEICRL", "VMEIteration", "beta_parameters", "expected_log_feasibility",
           "variational_backward_step"]
