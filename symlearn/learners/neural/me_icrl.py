"""ME-ICRL (Malik et al., 2021): maximum (trajectory) entropy ICRL with a feasibility network.

The baseline the thesis compares MCE-ICRL with (section 2.5). A feasibility network
``zeta(s, a)`` in ``(0, 1)`` defines the cost ``1 - zeta(s, a)``; the expert's trajectories are
modelled as ``P(tau) ~ exp(R(tau)) * prod_t zeta(s_t, a_t)`` (a trajectory-level maximum entropy
model in which infeasible steps have probability 0). After a nominal PPO phase, each iteration

1. **forward**: PPO-Lagrangian continues the policy with the cost ``1 - zeta`` and a cost limit
   of 0 (hard constraints). Its multiplier follows MCE-ICRL's rule (so the two are compared with
   the same multiplier control): once per iteration, from the same sampled episodes as the
   backward step, ``lambda <- max(0, lambda + lambda_lr * J)`` with ``J`` the episodes' mean
   discounted sum (``discount``) of the learned cost after the backward step -- the constraint
   gap, as MCE-ICRL's ``F_pi - F_D`` is its own --, and held fixed during the PPO phase (the
   PPO-Lagrangian capped at its starting value, so its per-rollout rule cannot move it). With
   ``lambda_lr=None`` the PPO-Lagrangian's own per-rollout rule moves it instead (``lagrangian``'s
   fields over ``{"update": "adam", "lr": 0.035}``, the behaviour before: a step of about 0.035
   per rollout whatever the size of the violation, measured too slow on BlockedPoint, where the
   policy still violated after 10 iterations on one seed in three). Either way the advantages mix
   in raw units (``advantage_scale="raw"``, passed explicitly): ``lambda`` is a price in reward per
   unit of cost, as MCE-ICRL's;
2. **backward**: ``backward_epochs`` Adam steps on the network's weights maximising the
   demonstrations' log-likelihood under the model, whose gradient is
   ``E_D[sum_t grad log zeta] - E_pi[w(tau) sum_t grad log zeta]`` with the policy's sampled
   episodes reweighted by importance weights ``w(tau) ~ prod_t zeta_new / zeta_old`` (normalised
   to mean 1; the samples came from the policy of the weights at the start of the step), plus a
   regulariser ``regularizer * E[1 - zeta]`` on expert and policy steps that keeps the network
   from calling everything infeasible. The epochs stop early once the importance weights drift
   too far from uniform: ``KL(old || new) = -mean log w`` or ``KL(new || old) = mean w log w``
   above ``target_kl`` (the samples no longer describe the reweighted policy).

The learned cost is a :class:`~symlearn.learners.neural.NeuralCost` with one feature
``phi = 1 - zeta`` (the network's sigmoid output read as the cost) and ``lambda = 1``, so files,
transfer checks and recovery metrics are the same as MCE-ICRL's. Results: ``cost_``, ``policy_``,
``nominal_policy_``, ``multiplier_`` (PPO-Lagrangian's), ``history_`` (:class:`MEIteration`),
``result_``.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.input_selection import choose_inputs, inputs_report
from symlearn.learners.neural.alternation import Alternation, Round, seed_offset
from symlearn.learners.neural.fit_setup import check_common, fit_setup
from symlearn.learners.neural.mce_icrl import action_bound_penalty, jsonable_params, penalised, policy_ppo_config
from symlearn.learners.neural.neural_cost import NeuralCost, spec_width
from symlearn.learners.neural.records import IterationRecord
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.rl.episodes import EpisodeBatch

LOG_FLOOR = 1e-6  # log(zeta) is taken of max(zeta, LOG_FLOOR): a step called infeasible costs log(1e-6), not -inf


@dataclass(frozen=True)
class MEIteration(IterationRecord):
    """One iteration: the sampled policy's reward and violation rate (ground truth, reported
    only), the mean feasibility of expert and policy steps after the backward step, the backward
    epochs run (fewer than asked when stopped by the KL test), the final KL estimates, the
    PPO-Lagrangian multiplier, and the seconds of forward (policy) and backward (cost) updates."""

    iteration: int
    reward: float
    violation_rate: float
    expert_feasibility: float
    policy_feasibility: float
    epochs: int
    kl_old_new: float
    kl_new_old: float
    multiplier: float
    policy_seconds: float
    cost_seconds: float

    def bar_numbers(self) -> dict[str, float]:
        return {**super().bar_numbers(), "lambda": float(self.multiplier)}


class NeuralMEICRL(Learner):
    """ME-ICRL: ``NeuralMEICRL(...).fit(demonstrations, env)`` (module docstring).

    Parameters as :class:`~symlearn.learners.neural.NeuralMCEICRL` where they share a meaning
    (``beta`` is PPO's entropy coefficient; ``bound_penalty``, ``reset_actor``, ``obs_dims`` and
    ``select_inputs`` as there), and ``learning_rate`` (Adam, backward step), ``backward_epochs``,
    ``regularizer``, ``target_kl``,
    ``lambda_lr`` (the multiplier's step per iteration, MCE-ICRL's rule and default; None: the
    PPO-Lagrangian's per-rollout rule, module docstring), ``discount`` (of the cost sums that
    step reads), ``lagrangian`` (a dict of :class:`~symlearn.rl.ppo.LagrangianConfig` fields; the
    cost limit is 0; ``init`` is the multiplier's start).
    """

    artefact_suffix = ".safetensors"
    #: outputs of the network (the first is the cost ``1 - zeta``); the history's record type
    _n_outputs = 1
    _record_type: type = MEIteration
    _label = "ME-ICRL"

    def __init__(self, *, beta: float = 0.01, n_iterations: int = 10, nominal_steps: int = 30_000,
                 policy_steps: int = 20_480, features: str = "state", obs_dims: Sequence[int] | None = None,
                 hidden_sizes: Sequence[int] = (64, 64), learning_rate: float = 3e-3, backward_epochs: int = 20,
                 regularizer: float = 0.1, target_kl: float = 10.0, n_policy_episodes: int = 16,
                 bound_penalty: float = 1.0, reset_actor: str = "auto", ppo: dict[str, Any] | None = None,
                 lagrangian: dict[str, Any] | None = None, lambda_lr: float | None = 0.02, discount: float = 0.99,
                 select_inputs: float = 0.01, random_state: int | None = 0) -> None:
        self.beta = beta
        self.n_iterations = n_iterations
        self.nominal_steps = nominal_steps
        self.policy_steps = policy_steps
        self.features = features
        self.obs_dims = obs_dims
        self.hidden_sizes = hidden_sizes
        self.learning_rate = learning_rate
        self.backward_epochs = backward_epochs
        self.regularizer = regularizer
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
        check_common(self, ("n_iterations", "nominal_steps", "policy_steps", "backward_epochs", "n_policy_episodes"))
        if not (self.learning_rate > 0 and self.regularizer >= 0 and self.target_kl > 0 and self.bound_penalty >= 0):
            raise SymlearnError("learning_rate and target_kl must be > 0, regularizer and bound_penalty >= 0")
        rate = self.lambda_lr
        if rate is not None and not (isinstance(rate, (int, float)) and math.isfinite(rate) and rate > 0):
            raise SymlearnError(f"lambda_lr must be a number > 0 or None, got {self.lambda_lr!r}")
        if not 0 < self.discount <= 1:
            raise SymlearnError(f"discount out of range: {self.discount!r}")

    def _backward(self, phi: FeatureNetwork, optimizer: torch.optim.Optimizer,
                  expert_in: tuple[torch.Tensor, torch.Tensor | None], batch: EpisodeBatch,
                  cost: NeuralCost) -> tuple[Any, ...]:
        """The backward step of one iteration; its first five values fill :class:`MEIteration`'s
        fields after the violation rate, any further ones a subclass record's extra fields."""
        return backward_step(phi, optimizer, expert_in, batch, cost, epochs=int(self.backward_epochs),
                             regularizer=self.regularizer, target_kl=self.target_kl)

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> NeuralMEICRL:
        from symlearn.rl.ppo import LagrangianConfig, train_ppo

        self._check_parameters()
        started = time.perf_counter()
        setup = fit_setup(demonstrations, world, self.obs_dims, self.random_state)
        env_fn, probe, act_spec = setup.env_fn, setup.probe, setup.act_spec
        expert, expert_x, expert_a = setup.expert, setup.expert_x, setup.expert_a
        obs_dims, generator = setup.obs_dims, setup.generator
        seed = self.random_state

        def ppo_config(offset: int, constrained: bool = False) -> Any:
            return policy_ppo_config(self.ppo, self.beta, seed_offset(seed, offset), constrained=constrained)

        previous_threads = torch.get_num_threads()
        torch.set_num_threads(1)
        try:
            timings: dict[str, float] = {}
            t0 = time.perf_counter()
            penalty = action_bound_penalty(act_spec, self.bound_penalty)  # see mce_icrl's docstring
            policy = train_ppo(env_fn, int(self.nominal_steps), ppo_config(0),
                               reward_fn=penalised(None, penalty)).policy
            timings["nominal"] = time.perf_counter() - t0
            nominal_policy = copy.deepcopy(policy)
            loop = Alternation(self._label, int(self.n_iterations), env_fn, int(self.n_policy_episodes), seed,
                               self.reset_actor, generator)
            batch = loop.sample(policy)
            selection = choose_inputs(setup, batch, self.select_inputs, seed)  # see mce_icrl's docstring
            if selection is not None:
                obs_dims = list(selection.selected)
            action_dim = spec_width(act_spec) if self.features == "state_action" else 0
            # phi = 1 - zeta: the network's sigmoid output is the cost; zeta = 1 - phi
            phi = FeatureNetwork(obs_dims, action_dim, self._n_outputs, self.hidden_sizes, generator)
            cost = NeuralCost.for_env(probe, phi, provenance=setup.provenance(
                self, jsonable_params(self.get_params())))
            cost.set_lambdas([1.0] + [0.0] * (self._n_outputs - 1))  # the cost is the first output
            nominal_x, nominal_a = cost.tensors(*batch.pairs())
            phi.fit_standardisation(np.concatenate([expert_x, nominal_x.numpy()]),
                                    None if not action_dim else np.concatenate([expert_a, nominal_a.numpy()]))
            expert_in = (torch.from_numpy(expert_x), None if not action_dim else torch.from_numpy(expert_a))
            optimizer = torch.optim.Adam(phi.parameters(), lr=self.learning_rate)
            multiplier = float((self.lagrangian or {}).get("init", 0.0))

            def cost_step(iteration: int, batch: EpisodeBatch) -> tuple[Any, ...]:
                """The backward step, then (with ``lambda_lr``) MCE-ICRL's multiplier rule on the
                constraint gap (module docstring)."""
                nonlocal multiplier
                backward = self._backward(phi, optimizer, expert_in, batch, cost)
                if self.lambda_lr is not None:
                    gap = discounted_cost(cost, batch, self.discount)
                    multiplier = max(0.0, multiplier + float(self.lambda_lr) * gap)
                return backward

            def policy_step(iteration: int, policy: Any) -> Any:
                """PPO-Lagrangian on the cost ``1 - zeta``, continuing ``policy`` from ``multiplier``."""
                nonlocal multiplier
                lagrangian = LagrangianConfig(**forward_lagrangian(self.lagrangian, multiplier, self.lambda_lr is None))
                trained = train_ppo(env_fn, int(self.policy_steps), ppo_config(iteration, constrained=True), lagrangian,
                                    cost_fn=cost.cost_fn(), reward_fn=penalised(None, penalty), policy=policy)
                multiplier = float(trained.multipliers[0])
                return trained

            def record(step: Round) -> MEIteration:
                backward = step.cost
                return self._record_type(step.iteration, step.metrics.reward, step.metrics.violation_rate,
                                         *backward[:5], float(step.trained.multipliers[0]), step.policy_seconds,
                                         step.cost_seconds, *backward[5:])

            def price(samples: list[EpisodeBatch]) -> tuple[list[float], float]:
                """The learned cost's discounted sums over each sample and over the expert's episodes."""
                with torch.no_grad():
                    return ([discounted_cost(cost, s, self.discount) for s in samples],
                            discounted_cost(cost, expert, self.discount))

            resets: list[int] = []
            policy, batch, history = loop.run(policy, batch, cost_step=cost_step, policy_step=policy_step,
                                              record=record, price=price, resets=resets)
            final = episode_metrics(batch)
        finally:
            torch.set_num_threads(previous_threads)
            probe.close()
        phi.eval()
        policy.eval()
        self.cost_, self.policy_, self.nominal_policy_ = cost, policy, nominal_policy
        self.multiplier_ = multiplier
        self.history_ = history
        self.seconds_ = time.perf_counter() - started
        timings.update(policy=sum(h.policy_seconds for h in history), cost=sum(h.cost_seconds for h in history),
                       total=self.seconds_)
        expert_reward = float(np.where(expert.mask, expert.rewards, 0.0).sum(axis=1).mean())
        cost.record_expert_level(expert)  # the default budget of an agent trained on it
        self._set_result(cost, "", metrics={"multiplier": multiplier, "expert_reward": expert_reward,
                                            "final_sample": final.as_dict(), "actor_resets": resets,
                                            "cost_inputs": inputs_report(cost, setup.inputs_from, selection)},
                         timings=timings, history=history)
        return self

    def save(self, path: Any) -> Any:
        """Write the learned cost: ``path`` (``.safetensors``) and its JSON configuration beside it."""
        from pathlib import Path

        self.check_fitted()
        return Path(self.cost_.save(path))


#: the PPO-Lagrangian's own rule when ``lambda_lr=None`` (the defaults of LagrangianConfig before
#: they changed: passed explicitly so that this baseline does not move with them)
PER_ROLLOUT_RULE: dict[str, Any] = {"update": "adam", "lr": 0.035, "adam_beta2": 0.999}


def forward_lagrangian(settings: dict[str, Any] | None, multiplier: float, per_rollout: bool) -> dict[str, Any]:
    """The :class:`~symlearn.rl.ppo.LagrangianConfig` fields of a forward step starting at
    ``multiplier``: raw advantage units, cost limit 0, and either the per-rollout rule
    (:data:`PER_ROLLOUT_RULE` under ``settings``) or the multiplier held fixed (capped at its
    start: with a limit of 0 and costs >= 0 every rule only raises it)."""
    fields: dict[str, Any] = {**PER_ROLLOUT_RULE, "advantage_scale": "raw", **(settings or {}),
                              "cost_limit": 0.0, "init": float(multiplier)}
    if not per_rollout:
        fields["max_multiplier"] = max(float(multiplier), 1e-12)  # LagrangianConfig needs a cap > 0
    return fields


def discounted_cost(cost: NeuralCost, batch: EpisodeBatch, discount: float) -> float:
    """The mean discounted episode sum of the learned cost over ``batch``'s episodes."""
    weights = batch.discount_weights(discount)[batch.mask]
    return float(weights @ cost(*batch.pairs()))


def log_feasibility(phi: FeatureNetwork, inputs: tuple[torch.Tensor, torch.Tensor | None]) -> torch.Tensor:
    """``log zeta`` of pairs with ``zeta = 1 - phi_0`` (floored at :data:`LOG_FLOOR`)."""
    return torch.log((1.0 - phi(*inputs)[:, 0]).clamp_min(LOG_FLOOR))


class ImportanceWeights:
    """Per-episode importance weights of a batch of sampled episodes while a backward step moves
    ``zeta`` away from the one they were sampled under: ``w_e ~ prod_t zeta_new / zeta_old``,
    normalised to mean 1, and the two KL estimates (``KL(old||new) = -mean log w``,
    ``KL(new||old) = mean w log w``) that stop the epochs (ME-ICRL and VME-ICRL alike)."""

    def __init__(self, batch: EpisodeBatch, log_zeta: Callable[[], torch.Tensor]) -> None:
        """``log_zeta()``: ``log zeta`` of the batch's flattened steps under the current ``zeta``
        (evaluated here without gradients, now and at every :meth:`update`)."""
        self.n, self.log_zeta = batch.n_episodes, log_zeta
        # the episode of every flattened step
        self.episode_t = torch.from_numpy(np.repeat(np.arange(self.n), batch.lengths))
        with torch.no_grad():
            self.old = self._sums(log_zeta())

    def _sums(self, values: torch.Tensor) -> torch.Tensor:
        return torch.zeros(self.n, dtype=values.dtype).index_add_(0, self.episode_t, values)

    def update(self) -> tuple[torch.Tensor, float, float]:
        """Per-step weights (each step gets its episode's) and the two KL estimates."""
        with torch.no_grad():
            log_w = self._sums(self.log_zeta()) - self.old
            log_w = log_w - torch.logsumexp(log_w, 0) + math.log(self.n)  # mean weight 1
            weights = log_w.exp()
            return weights[self.episode_t], float(-log_w.mean()), float((weights * log_w).mean())


def backward_step(phi: FeatureNetwork, optimizer: torch.optim.Optimizer,
                  expert_in: tuple[torch.Tensor, torch.Tensor | None], batch: EpisodeBatch, cost: NeuralCost, *,
                  epochs: int, regularizer: float, target_kl: float) -> tuple[float, float, int, float, float]:
    """ME-ICRL's backward step on ``phi = 1 - zeta`` (module docstring). Returns the mean
    feasibility of expert and policy steps afterwards, the epochs run and the last KL estimates."""
    policy_in = cost.tensors(*batch.pairs())
    importance = ImportanceWeights(batch, lambda: log_feasibility(phi, policy_in))
    epochs_run, kl_old_new, kl_new_old = 0, 0.0, 0.0
    for _ in range(epochs):
        step_weights, kl_old_new, kl_new_old = importance.update()
        if kl_old_new > target_kl or kl_new_old > target_kl:
            break
        loss = -log_feasibility(phi, expert_in).mean() + (step_weights * log_feasibility(phi, policy_in)).mean()
        if regularizer:
            loss = loss + regularizer * (phi(*expert_in).mean() + phi(*policy_in).mean())
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
        epochs_run += 1
    with torch.no_grad():
        expert_feasibility = float(1.0 - phi(*expert_in).mean())
        policy_feasibility = float(1.0 - phi(*policy_in).mean())
    return expert_feasibility, policy_feasibility, epochs_run, kl_old_new, kl_new_old


__all__ = ["PER_ROLLOUT_RULE", "ImportanceWeights", "MEIteration", "NeuralMEICRL", "backward_step", "discounted_cost",
           "forward_lagrangian", "log_feasibility"]
