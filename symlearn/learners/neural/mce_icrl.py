"""Neural maximum causal entropy inverse constrained RL (thesis chapter 2, Algorithm 2.1).

The tabular learner (:mod:`symlearn.learners.constraints.mce_icrl`) solves the dual of

    max_pi  E_pi[R(tau) + beta H(tau)]   s.t.   E_D[phi(tau)] - E_pi[phi(tau)] >= -alpha

exactly. Here every exact step has its sampled, neural counterpart:

1. a **nominal policy** is trained with PPO on the reward alone;
2. the **feature network** ``phi_zeta(s, a)`` (ReLU MLP, sigmoid output, ``n_features`` wide)
   is pre-trained as the encoder of an autoencoder on nominal and expert state(-action) pairs
   (:func:`~symlearn.learners.neural.feature_network.pretrain_autoencoder`);
3. then ``n_iterations`` times:

   * **dual step** on samples of the current policy (``n_policy_episodes`` whole episodes) and
     the demonstrations, with discounted feature sums ``F = E[sum_t gamma^t phi(s_t, a_t)]``:
     ``lambda <- max(0, lambda - lambda_lr * (F_D - F_pi - alpha))`` (eq. 2.12, projected on
     ``lambda >= 0``; the same sign convention as the tabular learner -- note that with it a
     budget ``alpha > 0`` raises ``lambda`` even when the sums match, i.e. it tightens the
     constraint; a slack would enter as ``+ alpha``. The default ``alpha = 0`` is unaffected),
     then ``zeta_steps``
     Adam steps on ``zeta`` down the gradient ``lambda . (w E_D[grad phi] - E_pi[grad phi])``
     (eq. 2.13 with ``w = expert_weight``: the features rise where the policy goes and the expert
     does not), with a learning rate ``zeta_lr * zeta_decay^(i-1)`` (the defaults: 100 steps a
     iteration at a constant ``3e-3``). ``expert_weight`` (default 2; 1 is eq. 2.13 as written):
     a state both the expert and the policies visit alike (the start, the common first steps)
     has no gradient under eq. 2.13, so the network charges it what its neighbours get -- on
     lava_grid the expert's start cell cost as much as the straight row through the lava, the
     expert's own episodes cost ~1.3 and ``train --cost``, held to that level, bought a shorter
     route through the lava with it. Weighing the expert's term more pushes every state the
     expert visits towards 0 (the expert's level ~0.001) and raises only what the policies do
     beyond it. The former 20 steps with a decay of 0.9 moved the network too little for the
     features to separate the expert's cells from the rest within 10 iterations (the cost
     stayed a soft half-plane through the expert's path; docs/BENCHMARKS.md, "Learned neural
     costs on detour tasks"). While every
     multiplier is 0 the steps weigh the features alike (``lambda`` replaced by ones: Adam's
     steps do not depend on the scale): with eq. 2.13 as written ``phi`` would never move from
     there, and where the expert's episodes are longer than the policy's (a detour round what
     the policy walks through) its sums of the positive features stay larger, every ``lambda``
     step is projected back to 0 and the cost stays 0 everywhere (lava_grid, docs/BENCHMARKS.md);
   * **policy step**: PPO continues the same policy (``train_ppo(policy=...)``) for
     ``policy_steps`` steps on the reward ``r - lambda . phi(s, a)`` with entropy coefficient
     ``beta`` (eq. 2.11), the learned reward computed in one forward pass per rollout
     (``reward_fn``).
     ``beta`` is 0.03 by default (0.01 before, and still for the other three learners): the
     cost can only charge what the loop's policies visit, and with 0.01 the continued policy on
     lava_grid stayed on the straight row or fell back to standing still, never tried the
     routes through the rest of the lava column, and ``train --cost`` then took one of those
     (docs/BENCHMARKS.md, "Learned neural costs on detour tasks"; 0.03 alone, with the cost
     step as before, did not help, nor did ``expert_weight`` and the stronger cost step alone).

   Both PPO phases learn from the reward minus ``bound_penalty * sum(max(|a| - bound, 0)^2)`` on
   the sampled (unclipped) Gaussian actions of a bounded Box action space. PPO samples actions
   from an unbounded Gaussian and the environment clips them, so every sample beyond a bound has
   the bound's effect; samples inside it move slower and earn less, and the mean drifts until
   almost no sample lands inside (measured on BlockedPoint: mean -2.7, standard deviation 0.8 for
   an action box of [-1, 1] after the nominal phase). Such a policy can hardly turn round when the
   cost starts to forbid that direction: only ~1 % of its samples carry a signal. The penalty,
   zero for every action the environment can tell apart, keeps the mean at the bound (-1.06,
   standard deviation 0.4 on the same run). ``bound_penalty=0`` turns it off.

   ``reset_actor`` (``"auto"``, the default, ``"never"``, ``"every"``, ``"last"``): which policy phases start from a
   freshly initialised actor (the critic, whose values carry over, and the observation statistics
   are kept). A policy continued from a nearly deterministic one does not leave a behaviour the
   cost now forbids when the way out needs many consecutive deviations from it (measured: the
   nominal HalfCheetah runs backward through the wall and, continued for 10 x 87.5k steps under a
   cost of ~27 per step behind it, kept doing so on 96 % of its steps; on the gridworld, 40k
   steps of PPO on the *true* cost did not move a continued policy off the forbidden shortest
   path, a fresh actor found the detour). ``"every"`` makes each phase a best response to the
   current cost: each must then be long enough to learn a policy from scratch, and while the
   multipliers are still small a fresh actor falls back into the forbidden behaviour (the
   history's violation rate rises again). ``"last"`` keeps the continued phases, during which the
   multipliers keep growing as long as the policy violates, and trains the returned policy
   afresh on the final cost -- the learned cost used as one would use it on a new agent.
   ``"auto"`` continues the policy until it stalls -- two phases in a row after which the current
   cost charges the new sample almost as much more than the expert (less than 10 % of that excess
   removed) as the sample before the phase, while it still keeps over half of the nominal policy's
   excess -- and then starts the next phase from a fresh actor
   (:class:`~symlearn.learners.neural.alternation.Stall`; the iterations in
   ``result_.metrics["actor_resets"]``). Measured (docs/BENCHMARKS.md): on BlockedPoint it never
   fires (the continued policy turns away from the wall by itself); on the blocked HalfCheetah it
   fires once the continued policy has kept its backward gait for two phases.

   The first dual step uses the nominal policy's samples (Algorithm 2.1 with its first PPO
   phase, which would run on ``lambda = 0`` and so repeat the nominal one, left out), so the
   cost returned is the one the returned policy was trained on last.

   ``cost_memory`` (``"all"``, the default, or ``"current"``): which samples the ``zeta`` steps
   of the feature network learn from. Algorithm 2.1 uses the current policy's (``"current"``).
   Once the policy obeys the cost it no longer visits what was forbidden, so nothing keeps the
   network's values there, and the later steps turn it to whatever the policy still does more
   than the expert: on BlockedPoint, going right faster than the scripted expert. Measured on 14
   runs at walls nobody tuned on (docs/BENCHMARKS.md), 2 ended with the cost *higher* on the
   allowed side than behind the wall (recovery AUC 0.0). With ``"all"`` the steps descend the
   gap between the expert's feature sums and the mean of every policy's since the first policy
   phase (the nominal policy's only while there is no other): the cost must keep telling the
   expert from every policy the loop has produced, violators included (14 of 14 runs at AUC 1.0,
   violation 0; its unsafe set reaches further into the allowed side -- IoU 0.24-0.65 against
   0.13-0.97 --, since early policies also lingered near the wall). The ``lambda`` step is the
   current policy's either way (eq. 2.12).

**Inputs of the cost** (all four neural learners alike). The candidates: ``obs_dims=None`` (the
default) the observation entries the environment declares its constraints to be about
(``feature_names``, where they name entries of ``observation_names``), else all; ``"all"`` every
entry; a list of indices those (:mod:`~symlearn.learners.neural.fit_setup` says why). Of the
candidates the network reads the fewest that tell the demonstrations' states from the nominal
policy's within ``select_inputs`` (0.01) of the held-out AUC of all of them
(:mod:`~symlearn.learners.neural.input_selection`; 0 = every candidate): on BlockedPoint ``x`` of
``(x, y)``, where reading ``y`` too let the cost follow the nominal policy's drift along ``y``.
``input_sparsity > 0`` adds a group-lasso penalty on the feature network's inputs to the cost
update instead (:mod:`~symlearn.learners.neural.input_sparsity`, :func:`dual_step`); off by
default: with Adam's per-weight steps it shrank every input's weights alike on BlockedPoint
rather than dropping any (docs/BENCHMARKS.md). The result's ``metrics["cost_inputs"]`` names the
entries read, the selection and each entry's share of the first layer's weight.

``fit(demonstrations, env)``: ``env`` is a function returning a fresh gymnasium environment,
a gymnasium id, or an environment (copied for PPO's parallel copies); the demonstrations'
states must be that environment's observations and they must carry the actions. The learner
reads the environment's reward; ``info["cost"]`` (the ground truth, when there is one) is only
*reported* in the history (violation rate), never learned from.

Results: ``cost_`` (:class:`~symlearn.learners.neural.NeuralCost`, callable, ``save``),
``policy_`` and ``nominal_policy_`` (:class:`~symlearn.rl.ppo.ActorCritic`), ``lambda_``,
``expert_features_``, ``pretrain_`` (:class:`PretrainRecord` or None), ``history_`` (one
:class:`ICRLIteration` per iteration), ``seconds_``, ``result_``. ``save(path)`` writes the cost
as ``path`` (``.safetensors``) and the JSON beside it.
"""

from __future__ import annotations

import copy
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch

from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.neural.feature_network import FeatureNetwork, pretrain_autoencoder
from symlearn.learners.neural.input_selection import choose_inputs, inputs_report
from symlearn.learners.neural.input_sparsity import input_penalty
from symlearn.learners.neural.alternation import Alternation, Round, seed_offset
from symlearn.learners.neural.fit_setup import check_common, environment_factory, fit_setup  # noqa: F401 (re-exported)
from symlearn.learners.neural.neural_cost import NeuralCost, spec_width
from symlearn.learners.neural.records import IterationRecord
from symlearn.rl.episode_metrics import episode_metrics

#: PPO settings of the policy phases unless ``ppo=`` overrides them (a shorter rollout and a
#: larger step than PPOConfig's defaults: the phases are short, and each continues the last)
PPO_DEFAULTS: dict[str, Any] = {"n_envs": 4, "n_steps": 256, "batch_size": 256, "n_epochs": 4,
                                "learning_rate": 1e-3, "anneal_lr": False, "normalize_values": True}
#: and, in the phases without a Lagrangian (every phase of MCE-ICRL and GACL, ME-/VME-ICRL's
#: nominal one), what PPOConfig resolved plain PPO to when the learners were measured: raw
#: observations, initial log standard deviation 0 (the recorded ICRL results stand on them)
PLAIN_PHASE_DEFAULTS: dict[str, Any] = {"normalize_observations": False, "log_std_init": 0.0}


@dataclass(frozen=True)
class ICRLIteration(IterationRecord):
    """One iteration: the multipliers after its dual step, the discounted feature sums it
    matched (expert, policy before the step), the reward and violation rate (ground truth,
    reported only) of the sampled episodes the dual step used -- those of the policy before this
    iteration's PPO phase --, and the seconds of its policy update, cost update and sampling."""

    iteration: int
    lambdas: tuple[float, ...]
    expert_features: tuple[float, ...]
    policy_features: tuple[float, ...]
    reward: float
    violation_rate: float
    zeta_lr: float
    policy_seconds: float
    cost_seconds: float
    sampling_seconds: float

    def bar_numbers(self) -> dict[str, float]:
        return {**super().bar_numbers(), "lambda": float(max(self.lambdas, default=0.0))}


class NeuralMCEICRL(Learner):
    """Neural MCE-ICRL: ``NeuralMCEICRL(...).fit(demonstrations, env)`` (module docstring).

    Parameters: ``beta`` (entropy coefficient of the policy phases, > 0), ``n_iterations``,
    ``nominal_steps`` / ``policy_steps`` (PPO steps of the nominal phase / of every iteration),
    ``features`` (``"state"`` or ``"state_action"``), ``obs_dims`` (observation entries ``phi``
    reads: indices, ``"all"``, or None = the environment's declared constraint features, else
    all: the candidates), ``select_inputs`` (the input selection's AUC tolerance, 0 = off; module
    docstring), ``n_features`` (width of ``phi``, one multiplier each),
    ``hidden_sizes``, ``pretrain`` (autoencoder pre-training on/off) and ``pretrain_epochs``,
    ``lambda_lr``, ``zeta_lr``, ``zeta_decay`` (per iteration), ``zeta_steps`` (Adam steps per
    iteration), ``expert_weight`` (the expert's term in those steps, >= 1; module docstring),
    ``alpha`` (the budget; 0 = hard constraints), ``discount`` (of the feature
    sums), ``n_policy_episodes`` (episodes sampled per dual step), ``bound_penalty`` (module
    docstring), ``lambda_init`` (every multiplier's start, >= 0; see ``fit``'s comment on why
    episodes that end at a goal need it > 0), ``reset_actor`` (module docstring), ``input_sparsity``
    (weight of the group lasso on ``phi``'s inputs, >= 0; 0 = off), ``ppo`` (a dict of
    :class:`~symlearn.rl.ppo.PPOConfig` fields over :data:`PPO_DEFAULTS`; ``ent_coef`` is
    ``beta``), ``random_state``.
    """

    artefact_suffix = ".safetensors"

    def __init__(self, *, beta: float = 0.03, n_iterations: int = 10, nominal_steps: int = 30_000,
                 policy_steps: int = 20_480, features: str = "state", obs_dims: Sequence[int] | None = None,
                 n_features: int = 4, hidden_sizes: Sequence[int] = (64, 64), pretrain: bool = True,
                 pretrain_epochs: int = 30, lambda_lr: float = 0.02, zeta_lr: float = 3e-3, zeta_decay: float = 1.0,
                 zeta_steps: int = 100, alpha: float = 0.0, discount: float = 0.99, n_policy_episodes: int = 16,
                 bound_penalty: float = 1.0, lambda_init: float = 0.0, reset_actor: str = "auto",
                 select_inputs: float = 0.01, input_sparsity: float = 0.0, ppo: dict[str, Any] | None = None,
                 cost_memory: str = "all", expert_weight: float = 2.0, random_state: int | None = 0) -> None:
        self.beta = beta
        self.n_iterations = n_iterations
        self.nominal_steps = nominal_steps
        self.policy_steps = policy_steps
        self.features = features
        self.obs_dims = obs_dims
        self.n_features = n_features
        self.hidden_sizes = hidden_sizes
        self.pretrain = pretrain
        self.pretrain_epochs = pretrain_epochs
        self.lambda_lr = lambda_lr
        self.zeta_lr = zeta_lr
        self.zeta_decay = zeta_decay
        self.zeta_steps = zeta_steps
        self.alpha = alpha
        self.discount = discount
        self.n_policy_episodes = n_policy_episodes
        self.bound_penalty = bound_penalty
        self.lambda_init = lambda_init
        self.reset_actor = reset_actor
        self.select_inputs = select_inputs
        self.input_sparsity = input_sparsity
        self.ppo = ppo
        self.cost_memory = cost_memory
        self.expert_weight = expert_weight
        self.random_state = random_state

    # --- settings ----------------------------------------------------------------------------------

    def _check_parameters(self) -> None:
        check_common(self, ("n_iterations", "nominal_steps", "policy_steps", "n_features", "zeta_steps",
                            "n_policy_episodes", "pretrain_epochs"), zero_allowed=("pretrain_epochs",),
                     beta_hint="beta weighs the policy's causal entropy; MCE-ICRL needs some (e.g. 0.01)")
        for name, ok in (("lambda_lr", self.lambda_lr > 0), ("zeta_lr", self.zeta_lr > 0),
                         ("zeta_decay", 0 < self.zeta_decay <= 1), ("alpha", self.alpha >= 0),
                         ("discount", 0 < self.discount <= 1), ("bound_penalty", self.bound_penalty >= 0),
                         ("input_sparsity", isinstance(self.input_sparsity, (int, float))
                          and math.isfinite(self.input_sparsity) and self.input_sparsity >= 0),
                         ("lambda_init", isinstance(self.lambda_init, (int, float)) and math.isfinite(self.lambda_init)
                          and self.lambda_init >= 0),
                         ("cost_memory", self.cost_memory in ("all", "current")),
                         ("expert_weight", isinstance(self.expert_weight, (int, float))
                          and math.isfinite(self.expert_weight) and self.expert_weight >= 1)):
            if not ok:
                raise SymlearnError(f"{name} out of range: {getattr(self, name)!r}")

    # --- fit -----------------------------------------------------------------------------------------

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> NeuralMCEICRL:
        """Learn a cost and a policy from ``demonstrations`` in the environment ``world`` (an
        environment, a factory or class of one, or a gymnasium id)."""
        from symlearn.rl.ppo import train_ppo

        self._check_parameters()
        started = time.perf_counter()
        setup = fit_setup(demonstrations, world, self.obs_dims, self.random_state)
        env_fn, probe, act_spec = setup.env_fn, setup.probe, setup.act_spec
        expert, expert_x, expert_a = setup.expert, setup.expert_x, setup.expert_a
        obs_dims, generator = setup.obs_dims, setup.generator
        seed = self.random_state
        previous_threads = torch.get_num_threads()
        torch.set_num_threads(1)
        try:
            timings: dict[str, float] = {}
            t0 = time.perf_counter()
            penalty = action_bound_penalty(act_spec, self.bound_penalty)
            nominal = train_ppo(env_fn, int(self.nominal_steps), policy_ppo_config(self.ppo, self.beta, seed),
                                reward_fn=penalised(None, penalty))
            timings["nominal"] = time.perf_counter() - t0
            policy = nominal.policy
            nominal_policy = copy.deepcopy(policy)
            loop = Alternation("MCE-ICRL", int(self.n_iterations), env_fn, int(self.n_policy_episodes), seed,
                               self.reset_actor, generator)
            batch = loop.sample(policy)
            selection = choose_inputs(setup, batch, self.select_inputs, seed)
            if selection is not None:
                obs_dims = list(selection.selected)

            action_dim = spec_width(act_spec) if self.features == "state_action" else 0
            phi = FeatureNetwork(obs_dims, action_dim, int(self.n_features), self.hidden_sizes, generator)
            cost = NeuralCost.for_env(probe, phi, provenance=setup.provenance(
                self, jsonable_params(self.get_params())))
            nominal_x, nominal_a = cost.tensors(*batch.pairs())
            all_x = np.concatenate([expert_x, nominal_x.numpy()])
            all_a = None if not action_dim else np.concatenate([expert_a, nominal_a.numpy()])
            phi.fit_standardisation(all_x, all_a)
            pretrain = None
            if self.pretrain and self.pretrain_epochs:
                pretrain = pretrain_autoencoder(phi, all_x, all_a, epochs=int(self.pretrain_epochs),
                                                generator=generator)
                timings["pretrain"] = pretrain.seconds

            expert_t = (torch.from_numpy(expert_x), None if not action_dim else torch.from_numpy(expert_a))
            expert_w = torch.from_numpy(expert.discount_weights(self.discount)[expert.mask]).float()
            optimizer = torch.optim.Adam(phi.parameters(), lr=self.zeta_lr)
            # Algorithm 2.1 initialises lambda; 0 suits fixed-length episodes (BlockedPoint). Where
            # episodes end at a goal, the expert's longer paths give larger sums of the (positive)
            # pre-trained features than the nominal policy's shorter ones, so from 0 every step on
            # lambda is projected back to 0 and phi, whose gradient is lambda-weighted, never moved
            # (measured on the gridworld: lambda 0 for all 5 iterations; on lava_grid, speed_cart
            # and boost_rover: a cost 0 everywhere). dual_step now moves phi with every feature
            # weighed alike while all multipliers are 0, so the gap turns and lambda rises from 0
            # too; lambda_init > 0 still starts the multipliers (and the cost) higher.
            lambdas = np.full(int(self.n_features), float(self.lambda_init))
            expert_features = np.zeros_like(lambdas)
            memory: list = []  # cost_memory="all": every iteration's policy samples, the nominal policy's first

            def cost_step(iteration: int, batch: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
                """The dual step on the current policy's samples; sets the cost's multipliers."""
                nonlocal lambdas, expert_features
                policy_t = cost.tensors(*batch.pairs())
                policy_w = torch.from_numpy(batch.discount_weights(self.discount)[batch.mask]).float()
                zeta_lr = self.zeta_lr * self.zeta_decay ** (iteration - 1)
                if self.cost_memory == "all":  # the first is the nominal policy's sample
                    memory.append((policy_t, policy_w))
                lambdas, expert_features, policy_features = dual_step(
                    phi, optimizer, lambdas, (expert_t, expert_w), (policy_t, policy_w), lambda_lr=self.lambda_lr,
                    alpha=self.alpha, zeta_lr=zeta_lr, zeta_steps=int(self.zeta_steps),
                    input_sparsity=float(self.input_sparsity),
                    remembered=(memory[1:] or memory) if self.cost_memory == "all" else None,
                    expert_weight=float(self.expert_weight))
                cost.set_lambdas(lambdas)
                return lambdas, expert_features, policy_features, zeta_lr

            def policy_step(iteration: int, policy: Any) -> Any:
                """PPO on r - lambda . phi, continuing ``policy``."""
                return train_ppo(env_fn, int(self.policy_steps),
                                 policy_ppo_config(self.ppo, self.beta, seed_offset(seed, iteration)),
                                 reward_fn=penalised(cost, penalty), policy=policy)

            def record(step: Round) -> ICRLIteration:
                step_lambdas, step_expert, policy_features, zeta_lr = step.cost
                return ICRLIteration(step.iteration, tuple(map(float, step_lambdas)),
                                     tuple(map(float, step_expert)), tuple(map(float, policy_features)),
                                     step.metrics.reward, step.metrics.violation_rate, zeta_lr, step.policy_seconds,
                                     step.cost_seconds, step.sampling_seconds)

            def priced(inputs: Any, weights: torch.Tensor) -> float:
                with torch.no_grad():
                    return float(np.dot(lambdas, (weights @ phi(*inputs)).double().numpy()))

            def price(samples: list[Any]) -> tuple[list[float], float]:
                """``lambda . F`` of each sample and of the expert under the current cost."""
                return ([priced(cost.tensors(*s.pairs()),
                                torch.from_numpy(s.discount_weights(self.discount)[s.mask]).float())
                         for s in samples], priced(expert_t, expert_w))

            resets: list[int] = []
            policy, batch, history = loop.run(policy, batch, cost_step=cost_step, policy_step=policy_step,
                                              record=record, price=price, resets=resets)
            final = episode_metrics(batch)
        finally:
            torch.set_num_threads(previous_threads)
            probe.close()
        phi.eval()
        self.cost_ = cost
        self.policy_ = policy
        self.policy_.eval()
        self.nominal_policy_ = nominal_policy
        self.lambda_ = lambdas
        self.expert_features_ = expert_features
        self.pretrain_ = pretrain
        self.history_ = history
        self.seconds_ = time.perf_counter() - started
        timings["policy"] = sum(h.policy_seconds for h in history)
        timings["cost"] = sum(h.cost_seconds for h in history)
        timings["total"] = self.seconds_
        expert_reward = float(np.where(expert.mask, expert.rewards, 0.0).sum(axis=1).mean())
        cost.record_expert_level(expert)  # the default budget of an agent trained on it
        self._set_result(cost, "", metrics={"lambda": [float(x) for x in lambdas], "expert_reward": expert_reward,
                                            "final_sample": final.as_dict(), "actor_resets": resets,
                                            "pretrain": None if pretrain is None else pretrain.as_dict(),
                                            "cost_inputs": inputs_report(cost, setup.inputs_from, selection)},
                         timings=timings, history=history)
        return self

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the learned cost: ``path`` (``.safetensors``) and its JSON configuration beside it."""
        self.check_fitted()
        return Path(self.cost_.save(path))


# --- helpers -------------------------------------------------------------------------------------


def policy_ppo_config(ppo: dict[str, Any] | None, beta: float, seed: int | None, *,
                      constrained: bool = False) -> Any:
    """The :class:`~symlearn.rl.ppo.PPOConfig` of a policy phase (all four neural learners):
    :data:`PPO_DEFAULTS` (and :data:`PLAIN_PHASE_DEFAULTS` unless the phase has a Lagrangian,
    ``constrained``) under the learner's ``ppo`` overrides, ``ent_coef = beta``, ``seed``; a field
    PPOConfig lacks is a :class:`SymlearnError` naming it."""
    from symlearn.rl.ppo import PPOConfig

    plain = {} if constrained else PLAIN_PHASE_DEFAULTS
    settings = {**PPO_DEFAULTS, **plain, **(ppo or {}), "ent_coef": float(beta), "seed": seed}
    try:
        return PPOConfig(**settings)
    except TypeError as exc:
        raise SymlearnError(f"ppo: {exc}", hint="ppo= takes PPOConfig fields") from None


def action_bound_penalty(action_spec: dict[str, Any], weight: float) -> Callable[[np.ndarray], np.ndarray] | None:
    """``actions [T, N, d] -> weight * sum_d max(|a| - bound, 0)^2`` for a Box action space with
    finite bounds (None for Discrete, unbounded or ``weight = 0``): see the module docstring."""
    if not weight or action_spec["kind"] != "box" or "low" not in action_spec:
        return None
    low = np.array([-np.inf if x is None else x for x in action_spec["low"]])
    high = np.array([np.inf if x is None else x for x in action_spec["high"]])

    def penalty(actions: np.ndarray) -> np.ndarray:
        a = np.asarray(actions, dtype=np.float64).reshape(*actions.shape[:2], -1)
        excess = np.maximum(a - high, 0.0) + np.maximum(low - a, 0.0)
        return weight * (excess ** 2).sum(-1)
    return penalty


def penalised(cost: NeuralCost | None, penalty: Callable[[np.ndarray], np.ndarray] | None) -> Any:
    """``train_ppo``'s ``reward_fn``: the environment's reward minus the learned cost (if any)
    and the action-bound penalty (if any); None when there is neither."""
    if cost is None and penalty is None:
        return None

    def reward(rollout: Any) -> np.ndarray:
        r = rollout.rewards if cost is None else rollout.rewards - cost.cost_of_rollout(rollout)
        return r if penalty is None else r - penalty(rollout.actions)
    return reward


def dual_step(phi: FeatureNetwork, optimizer: torch.optim.Optimizer, lambdas: np.ndarray,
              expert: tuple[tuple[torch.Tensor, torch.Tensor | None], torch.Tensor],
              policy: tuple[tuple[torch.Tensor, torch.Tensor | None], torch.Tensor], *, lambda_lr: float,
              alpha: float, zeta_lr: float, zeta_steps: int,
              input_sparsity: float = 0.0,
              remembered: list | None = None, expert_weight: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One step on the dual variables: ``lambda`` (eq. 2.12, projected on ``lambda >= 0``), then
    ``zeta_steps`` steps of ``optimizer`` (on ``phi``'s parameters, learning rate ``zeta_lr``)
    down ``lambda . (F_D - F_pi)`` (eq. 2.13). ``expert``/``policy``: ``((obs, actions), weights)``
    with the per-row weights of :meth:`EpisodeBatch.discount_weights`, so ``weights @ phi`` is a
    mean discounted feature sum. ``input_sparsity > 0`` adds the group lasso on ``phi``'s inputs
    (:func:`~symlearn.learners.neural.input_sparsity.input_penalty`) with that weight, against the
    gap divided by ``sum(lambda)`` and the expert's discounted episode length (a number in
    ``(-1, 1)``: the weight means the same whatever the multipliers' size and the episodes'
    length); at 0 the steps are as without it. ``remembered``: ``[((obs, actions), weights), ...]``
    samples of several policies, whose mean feature sum stands for ``F_pi`` in the ``zeta`` steps
    (``cost_memory="all"``; the ``lambda`` step keeps ``policy``). ``expert_weight``: the expert's
    sum in the ``zeta`` steps is multiplied by it (1: eq. 2.13 as written; > 1 pushes the states
    the expert shares with the policies towards 0, module docstring). Returns the new ``lambda`` and
    the feature sums ``F_D``, ``F_pi`` it was computed from."""
    (expert_in, expert_w), (policy_in, policy_w) = expert, policy
    with torch.no_grad():
        expert_features = (expert_w @ phi(*expert_in)).double().numpy()
        policy_features = (policy_w @ phi(*policy_in)).double().numpy()
    gradient = expert_features - policy_features - alpha  # eq. 2.12
    lambdas = np.maximum(0.0, np.asarray(lambdas, dtype=np.float64) - lambda_lr * gradient)
    for group in optimizer.param_groups:
        group["lr"] = zeta_lr
    # Every multiplier at 0 (the projection's fixed point when the expert's feature sums exceed
    # the policy's, e.g. the expert's episodes are longer): the lambda-weighted gradient of eq. 2.13
    # is 0, phi never moves and neither does lambda -- the cost stays 0 everywhere (measured on
    # lava_grid, docs/BENCHMARKS.md). The zeta steps then weigh every feature alike: Adam's steps
    # do not depend on the loss's scale, so this is the step any equal lambda > 0 would take, and
    # the features rise where the policy goes and the expert does not until the gap turns.
    lam = torch.from_numpy(lambdas if lambdas.any() else np.ones_like(lambdas)).float()
    # the gap per unit of lambda and per discounted expert step, so that input_sparsity weighs
    # the group lasso against a number in (-1, 1) whatever the multipliers' size and the
    # episodes' length (Adam's steps do not depend on the loss's scale: without the penalty
    # this division changes nothing)
    scale = float(lam.sum()) * float(expert_w.sum()) if input_sparsity else 1.0
    shown = remembered or [(policy_in, policy_w)]
    for _ in range(zeta_steps):
        policy_sum = sum(w @ phi(*inputs) for inputs, w in shown) / len(shown)
        loss = lam @ (expert_weight * (expert_w @ phi(*expert_in)) - policy_sum)
        if input_sparsity:
            loss = loss / scale + input_sparsity * input_penalty(phi)
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
    return lambdas, expert_features, policy_features


def jsonable_params(params: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in params.items():
        if isinstance(value, tuple):
            value = list(value)
        if value is None or isinstance(value, (bool, int, float, str, list, dict)):
            out[key] = value
    return out


__all__ = ["ICRLIteration", "NeuralMCEICRL", "PPO_DEFAULTS", "action_bound_penalty", "dual_step", "environment_factory",
           "jsonable_params", "penalised", "policy_ppo_config", "PLAIN_PHASE_DEFAULTS"]
