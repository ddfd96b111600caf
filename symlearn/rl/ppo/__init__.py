"""PPO and PPO-Lagrangian, one concept per module, each readable top to bottom (in the spirit of CleanRL).

``train_ppo(env_fn, total_steps, config, lagrangian=None)`` trains an actor and a critic (two
separate MLPs, 64 x 64 tanh by default) with the clipped surrogate objective of Schulman et al.
(2017) on ``n_envs`` copies of an environment, ``n_steps`` steps each per iteration, then
``n_epochs`` passes of minibatches of ``batch_size``. Discrete actions use a categorical policy;
``Box`` actions a Gaussian with a state-independent log standard deviation (the sampled action is
learned from, the action sent to the environment is clipped to the bounds). ``Box`` observations
are flattened, ``Discrete`` ones one-hot encoded (:mod:`symlearn.rl.spaces`).

**Modules.** :mod:`~symlearn.rl.ppo.config` (:class:`PPOConfig`, :class:`LagrangianConfig`,
:data:`LEGACY_LAGRANGIAN`), :mod:`~symlearn.rl.ppo.multipliers` (:class:`Multipliers`),
:mod:`~symlearn.rl.ppo.networks` (:class:`ActorCritic`, :class:`NumpyActor`),
:mod:`~symlearn.rl.ppo.records` (:class:`PPOIteration`, :class:`PPOResult`),
:mod:`~symlearn.rl.ppo.rollouts` (:class:`Rollout`, the rollout collector and its typed
:class:`RolloutBatch`), :mod:`~symlearn.rl.ppo.update` (GAE, return scales, the clipped-surrogate
epochs), :mod:`~symlearn.rl.ppo.stall` (:class:`LagrangianStall`: a fresh actor for a policy stuck
over its limit while the multiplier rises, ``LagrangianConfig.reset_actor="auto"``),
:mod:`~symlearn.rl.ppo.training` (:func:`train_ppo`) and
:mod:`~symlearn.rl.ppo.evaluation` (:func:`evaluate`), :mod:`~symlearn.rl.ppo.limit_check`
(:func:`limit_warnings`: a limit the run never got within while its multiplier rose). Every name is importable from
``symlearn.rl.ppo``; each module imports only those before it in this list, and two modules of
``rl`` that are not PPO's own: :mod:`symlearn.rl.episode_stats` (the cost reader and the accounting
of finished episodes, :class:`EpisodeStats`, :class:`FinishedEpisode`) and
:mod:`symlearn.rl.evaluation` (the one evaluation loop, which any policy can be run with).

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
is divided by the running standard deviation of its own returns
(:class:`~symlearn.rl.ppo.update._ReturnScales`: an average over about ten iterations, floored at
1 % of its largest value), so ``lambda`` weighs standard
deviations of cost-to-go against those of reward-to-go: while the exploring agent's costs are large
and spread, one unit of cost is cheap; as the agent becomes safe the cost's scale shrinks and the
remaining violations get dearer. The constrained problem is unchanged (a positive rescaling of
objective and constraint moves only the value of the multiplier at the saddle point);
``PPOIteration.return_scales`` records the scales, so ``lambda_i * scale_r / scale_ci`` is the
price in raw units. In these units ``lambda = 1`` weighs a cost as much as the reward, which is
where the multiplier of a hard constraint (limit 0) starts by default (``LagrangianConfig.init``):
from 0 the first iterations learn from the reward alone, long enough for a policy to settle on a
forbidden short cut before it is priced; a positive budget starts at 0 (docs/BENCHMARKS.md,
"Where the multiplier starts").

**Normalisation** (both on by default, with a Lagrangian or without; ``PPOConfig``'s ``None``
decides it when training starts, ``CLEANRL_PLAIN`` turns it off with CleanRL's step sizes). ``normalize_observations``: the networks see the features
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

import numpy as np  # noqa: F401  (the doctest above uses it)

from symlearn.rl.episode_stats import EpisodeStats, FinishedEpisode
from symlearn.rl.ppo.config import (
    ACTIVATIONS,
    ADVANTAGE_SCALES,
    CLEANRL_PLAIN,
    COST_ESTIMATES,
    ENTROPY_MODES,
    LEGACY_LAGRANGIAN,
    RESET_ACTOR_RULES,
    RESOLVED_DEFAULTS,
    LagrangianConfig,
    PPOConfig,
)
from symlearn.rl.ppo.evaluation import evaluate
from symlearn.rl.ppo.limit_check import limit_warnings
from symlearn.rl.ppo.multipliers import Multipliers
from symlearn.rl.ppo.networks import MODEL_KIND, OBS_CLIP, OBS_EPSILON, ActorCritic, NumpyActor
from symlearn.rl.ppo.records import PPOIteration, PPOResult
from symlearn.rl.ppo.rollouts import LENGTH_MEMORY, Rollout, RolloutBatch
from symlearn.rl.ppo.stall import LagrangianStall
from symlearn.rl.ppo.training import train_ppo
from symlearn.rl.ppo.update import RETURN_SCALE_FLOOR, RETURN_SCALE_MEMORY

# private helpers that tests import from here, as they did from the single-file module
from symlearn.rl.ppo.networks import _space_spec  # noqa: E402, F401  isort: skip
from symlearn.rl.ppo.update import _gae, _rescale_critics  # noqa: E402, F401  isort: skip

__all__ = [
    "ACTIVATIONS",
    "ADVANTAGE_SCALES",
    "CLEANRL_PLAIN",
    "COST_ESTIMATES",
    "ENTROPY_MODES",
    "LEGACY_LAGRANGIAN",
    "LENGTH_MEMORY",
    "MODEL_KIND",
    "OBS_CLIP",
    "OBS_EPSILON",
    "RESET_ACTOR_RULES",
    "RESOLVED_DEFAULTS",
    "RETURN_SCALE_FLOOR",
    "RETURN_SCALE_MEMORY",
    "ActorCritic",
    "EpisodeStats",
    "FinishedEpisode",
    "LagrangianConfig",
    "LagrangianStall",
    "Multipliers",
    "NumpyActor",
    "PPOConfig",
    "PPOIteration",
    "PPOResult",
    "Rollout",
    "RolloutBatch",
    "evaluate",
    "limit_warnings",
    "train_ppo",
]
