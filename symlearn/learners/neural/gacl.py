"""GACL: generative adversarial constraint learning, the GAIL-style ICRL baseline of the thesis.

Section 2.5 (after Malik et al. 2021): a discriminator ``D(s, a)`` in ``(0, 1)`` learns to tell
expert state-action pairs (``D -> 1``) from the current policy's (``D -> 0``), and the policy is
trained on ``r + log D(s, a)``: pairs only the policy produces become very expensive (``log D ->
-inf``), so the agent is pushed toward what the expert does. After a nominal PPO phase, each
iteration takes ``disc_steps`` full-batch Adam steps on the binary cross-entropy of the
discriminator (policy episodes sampled from the current policy, the demonstrations), then
continues the policy with PPO for ``policy_steps`` steps.

The discriminator is a one-feature :class:`~symlearn.learners.neural.feature_network.FeatureNetwork`
whose sigmoid output is ``phi = 1 - D``; the learned cost is saved as a
:class:`~symlearn.learners.neural.NeuralCost` ``C = phi = 1 - D`` (``lambda = 1``), so the
file, the transfer checks and the recovery metrics (AUC depends only on the ordering, which
``1 - D`` and ``-log D`` share) are the same as for the other learners; the penalty the policy
learned from is ``-log(1 - C)`` (``log D`` is floored at ``log 1e-6``).
"""

from __future__ import annotations

import copy
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
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
from symlearn.learners.neural.mce_icrl import action_bound_penalty, jsonable_params, policy_ppo_config
from symlearn.learners.neural.neural_cost import NeuralCost, spec_width
from symlearn.learners.neural.records import IterationRecord
from symlearn.rl.episode_metrics import episode_metrics

LOG_FLOOR = 1e-6


@dataclass(frozen=True)
class GACLIteration(IterationRecord):
    """One iteration: the sampled policy's reward and violation rate (ground truth, reported
    only; the policy before this iteration's PPO phase), the discriminator's mean ``D`` on expert
    and policy pairs after its update, and the seconds of the policy and discriminator updates."""

    iteration: int
    reward: float
    violation_rate: float
    expert_d: float
    policy_d: float
    policy_seconds: float
    cost_seconds: float


class NeuralGACL(Learner):
    """GACL: ``NeuralGACL(...).fit(demonstrations, env)`` (module docstring). Parameters as
    :class:`~symlearn.learners.neural.NeuralMCEICRL` where they share a meaning, and
    ``learning_rate``, ``disc_steps`` (discriminator Adam steps per iteration)."""

    artefact_suffix = ".safetensors"

    def __init__(self, *, beta: float = 0.01, n_iterations: int = 10, nominal_steps: int = 30_000,
                 policy_steps: int = 20_480, features: str = "state", obs_dims: Sequence[int] | None = None,
                 hidden_sizes: Sequence[int] = (64, 64), learning_rate: float = 3e-3, disc_steps: int = 20,
                 n_policy_episodes: int = 16, bound_penalty: float = 1.0, reset_actor: str = "auto",
                 select_inputs: float = 0.01, ppo: dict[str, Any] | None = None,
                 random_state: int | None = 0) -> None:
        self.beta = beta
        self.n_iterations = n_iterations
        self.nominal_steps = nominal_steps
        self.policy_steps = policy_steps
        self.features = features
        self.obs_dims = obs_dims
        self.hidden_sizes = hidden_sizes
        self.learning_rate = learning_rate
        self.disc_steps = disc_steps
        self.n_policy_episodes = n_policy_episodes
        self.bound_penalty = bound_penalty
        self.reset_actor = reset_actor
        self.select_inputs = select_inputs
        self.ppo = ppo
        self.random_state = random_state

    def _check_parameters(self) -> None:
        check_common(self, ("n_iterations", "nominal_steps", "policy_steps", "disc_steps", "n_policy_episodes"))
        if not (self.learning_rate > 0 and self.bound_penalty >= 0):
            raise SymlearnError("learning_rate must be > 0 and bound_penalty >= 0")

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> NeuralGACL:
        from symlearn.rl.ppo import train_ppo

        self._check_parameters()
        started = time.perf_counter()
        setup = fit_setup(demonstrations, world, self.obs_dims, self.random_state)
        env_fn, probe, act_spec = setup.env_fn, setup.probe, setup.act_spec
        expert, expert_x, expert_a = setup.expert, setup.expert_x, setup.expert_a
        obs_dims, generator = setup.obs_dims, setup.generator
        seed = self.random_state
        penalty = action_bound_penalty(act_spec, self.bound_penalty)  # see mce_icrl's docstring

        def ppo_config(offset: int) -> Any:
            return policy_ppo_config(self.ppo, self.beta, seed_offset(seed, offset))

        def reward_fn(cost: NeuralCost | None) -> Any:
            def reward(rollout: Any) -> np.ndarray:
                r = rollout.rewards
                if cost is not None:  # r + log D, D = 1 - C
                    r = r + np.log(np.maximum(1.0 - cost.cost_of_rollout(rollout), LOG_FLOOR))
                return r if penalty is None else r - penalty(rollout.actions)
            return reward

        previous_threads = torch.get_num_threads()
        torch.set_num_threads(1)
        try:
            timings: dict[str, float] = {}
            t0 = time.perf_counter()
            policy = train_ppo(env_fn, int(self.nominal_steps), ppo_config(0), reward_fn=reward_fn(None)).policy
            timings["nominal"] = time.perf_counter() - t0
            nominal_policy = copy.deepcopy(policy)
            loop = Alternation("GACL", int(self.n_iterations), env_fn, int(self.n_policy_episodes), seed,
                               self.reset_actor, generator)
            batch = loop.sample(policy)
            selection = choose_inputs(setup, batch, self.select_inputs, seed)  # see mce_icrl's docstring
            if selection is not None:
                obs_dims = list(selection.selected)
            action_dim = spec_width(act_spec) if self.features == "state_action" else 0
            phi = FeatureNetwork(obs_dims, action_dim, 1, self.hidden_sizes, generator)  # phi = 1 - D
            cost = NeuralCost.for_env(probe, phi, provenance=setup.provenance(
                self, jsonable_params(self.get_params())))
            cost.set_lambdas([1.0])
            nominal_x, nominal_a = cost.tensors(*batch.pairs())
            phi.fit_standardisation(np.concatenate([expert_x, nominal_x.numpy()]),
                                    None if not action_dim else np.concatenate([expert_a, nominal_a.numpy()]))
            expert_in = (torch.from_numpy(expert_x), None if not action_dim else torch.from_numpy(expert_a))
            optimizer = torch.optim.Adam(phi.parameters(), lr=self.learning_rate)

            def cost_step(iteration: int, batch: Any) -> tuple[float, float]:
                """The discriminator step on the current policy's samples: mean ``D`` of expert and policy."""
                return discriminator_step(phi, optimizer, expert_in, cost.tensors(*batch.pairs()),
                                          steps=int(self.disc_steps))

            def policy_step(iteration: int, policy: Any) -> Any:
                """PPO on ``r + log D``, continuing ``policy``."""
                return train_ppo(env_fn, int(self.policy_steps), ppo_config(iteration), reward_fn=reward_fn(cost),
                                 policy=policy)

            def record(step: Round) -> GACLIteration:
                expert_d, policy_d = step.cost
                return GACLIteration(step.iteration, step.metrics.reward, step.metrics.violation_rate, expert_d,
                                     policy_d, step.policy_seconds, step.cost_seconds)

            def penalty_sum(sample: Any) -> float:
                """The mean episode sum of ``-log D`` (the reward's penalty) over ``sample``."""
                weights = sample.discount_weights(1.0)[sample.mask]
                return float(weights @ -np.log(np.maximum(1.0 - cost(*sample.pairs()), LOG_FLOOR)))

            def price(samples: list[Any]) -> tuple[list[float], float]:
                return [penalty_sum(s) for s in samples], penalty_sum(expert)

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
        self.history_ = history
        self.seconds_ = time.perf_counter() - started
        timings.update(policy=sum(h.policy_seconds for h in history), cost=sum(h.cost_seconds for h in history),
                       total=self.seconds_)
        expert_reward = float(np.where(expert.mask, expert.rewards, 0.0).sum(axis=1).mean())
        cost.record_expert_level(expert)  # the default budget of an agent trained on it
        self._set_result(cost, "", metrics={"expert_reward": expert_reward, "final_sample": final.as_dict(),
                                            "actor_resets": resets,
                                            "cost_inputs": inputs_report(cost, setup.inputs_from, selection)},
                         timings=timings, history=history)
        return self

    def save(self, path: Any) -> Path:
        """Write the learned cost ``1 - D``: ``path`` (``.safetensors``) and its JSON beside it."""
        self.check_fitted()
        return Path(self.cost_.save(path))


def discriminator_step(phi: FeatureNetwork, optimizer: torch.optim.Optimizer,
                       expert_in: tuple[torch.Tensor, torch.Tensor | None],
                       policy_in: tuple[torch.Tensor, torch.Tensor | None], *, steps: int) -> tuple[float, float]:
    """``steps`` full-batch Adam steps on the binary cross-entropy of ``D = 1 - phi`` (expert
    pairs labelled 1, policy pairs 0; each class weighted equally). Returns the mean ``D`` on
    expert and policy pairs afterwards."""
    bce = torch.nn.functional.binary_cross_entropy
    for _ in range(steps):
        expert_phi, policy_phi = phi(*expert_in), phi(*policy_in)
        loss = bce(expert_phi, torch.zeros_like(expert_phi)) + bce(policy_phi, torch.ones_like(policy_phi))
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
    with torch.no_grad():
        return float(1.0 - phi(*expert_in).mean()), float(1.0 - phi(*policy_in).mean())


__all__ = ["GACLIteration", "NeuralGACL", "discriminator_step"]
