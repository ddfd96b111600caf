"""The alternating loop the four neural ICRL learners share (MCE-ICRL, ME-ICRL, VME-ICRL, GACL).

After their nominal PPO phase all four repeat, ``n_iterations`` times and without stopping early:

1. a **cost step** on the current sample of the policy and the demonstrations (MCE-ICRL's dual
   step, ME-/VME-ICRL's backward step and multiplier step, GACL's discriminator step), timed;
2. the **metrics** of that sample (reward and true violation rate: reported, never learned from);
3. a **policy step**: PPO continues the policy on the new cost (from a fresh actor where
   ``reset_actor`` says so, :func:`~symlearn.learners.neural.fit_setup.resets_actor`), timed;
4. a new **sample** of the policy, timed, whose seed depends on the iteration only
   (:meth:`Alternation.sample`), so a run is reproducible and the samples of two runs with one
   seed match iteration by iteration;
5. one step of the learner's **progress bar** (the numbers its record shows, ``bar_numbers()``)
   and one **history record**, built by the learner from the iteration's :class:`Round`.

They differ only in the two steps and in the record, which the learner passes as functions;
the loop, its order and its seeds live here once, so a change to one (a timing, a seed, what
the bar shows) reaches all four.

Seeds: the nominal phase runs PPO with ``seed``, the policy phase of iteration ``i`` with
``seed_offset(seed, i)`` (the learners' own PPO configurations) and the sample after it with
``seed_offset(seed, 10_000 + 100 * i)`` (``i = 0``: the nominal policy's sample).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import torch

from symlearn.learners.neural.fit_setup import resets_actor
from symlearn.progress import ProgressBar
from symlearn.rl.episode_metrics import EpisodeMetrics, episode_metrics
from symlearn.rl.episodes import EpisodeBatch, sample_episodes

SAMPLE_SEEDS = 10_000  # sample seeds start here, PPO's (seed + iteration) below; 100 apart per iteration


def seed_offset(seed: int | None, k: int) -> int | None:
    """``seed + k`` (None stays None: an unseeded run)."""
    return None if seed is None else int(seed) + k


@dataclass(frozen=True)
class Round:
    """What one iteration's history record is built from: the iteration (from 1), the metrics of
    the sample the cost step read (the policy before this iteration's PPO phase), what the cost
    step returned, the policy step's :class:`~symlearn.rl.ppo.PPOResult`, and the seconds of the
    two steps and of the new sample."""

    iteration: int
    metrics: EpisodeMetrics
    cost: Any
    trained: Any
    policy_seconds: float
    cost_seconds: float
    sampling_seconds: float


@dataclass(frozen=True)
class Alternation:
    """The loop's fixed settings: the bar's label, the number of iterations, the environment
    factory and episodes per sample, the seed, ``reset_actor`` and the generator a fresh actor is
    drawn from."""

    label: str
    n_iterations: int
    env_fn: Callable[[], Any]
    n_episodes: int
    seed: int | None
    reset_actor: str
    generator: torch.Generator

    def sample(self, policy: Any, iteration: int = 0) -> EpisodeBatch:
        """The episodes of ``policy`` sampled after ``iteration`` (0: the nominal policy)."""
        return sample_episodes(policy, self.env_fn, int(self.n_episodes),
                               seed=seed_offset(self.seed, SAMPLE_SEEDS + 100 * iteration))

    def run(self, policy: Any, batch: EpisodeBatch, *, cost_step: Callable[[int, EpisodeBatch], Any],
            policy_step: Callable[[int, Any], Any],
            record: Callable[[Round], Any],
            price: Callable[[list[EpisodeBatch]], tuple[list[float], float]] | None = None,
            resets: list[int] | None = None) -> tuple[Any, EpisodeBatch, list[Any]]:
        """Alternate from ``policy`` and its sample ``batch`` (module docstring):
        ``cost_step(iteration, batch)`` learns the cost and returns what the record needs of it,
        ``policy_step(iteration, policy)`` continues the policy and returns ``train_ppo``'s result,
        ``record(round)`` builds the history record (whose ``bar_numbers()`` the bar shows).
        ``price(samples)``: what the *current* learned cost charges each sample and the expert
        (mean discounted episode sums, all >= 0), which ``reset_actor="auto"`` reads (:class:`Stall`);
        the iterations whose phase started from a fresh actor are appended to ``resets``.
        Returns the last policy, its sample and the history."""
        n = int(self.n_iterations)
        history: list[Any] = []
        stall = Stall() if self.reset_actor == "auto" and price is not None else None
        previous: EpisodeBatch | None = None  # the sample before the last policy phase
        nominal = batch                       # the nominal policy's: what "still forbidden" is measured by
        with ProgressBar(n, desc=self.label, unit="iter") as bar:
            for iteration in range(1, n + 1):
                t0 = time.perf_counter()
                cost = cost_step(iteration, batch)
                cost_seconds = time.perf_counter() - t0
                metrics = episode_metrics(batch)
                t0 = time.perf_counter()
                fresh = resets_actor(self.reset_actor, iteration, n)
                if stall is not None and previous is not None:
                    (before, after, first), expert = price([previous, batch, nominal])
                    fresh = stall.update(before - expert, after - expert, first - expert, after)
                if fresh:
                    policy.reset_actor(self.generator)
                    if resets is not None:
                        resets.append(iteration)
                previous = batch
                trained = policy_step(iteration, policy)
                policy = trained.policy
                policy_seconds = time.perf_counter() - t0
                t0 = time.perf_counter()
                batch = self.sample(policy, iteration)
                sampling_seconds = time.perf_counter() - t0
                entry = record(Round(iteration, metrics, cost, trained, policy_seconds, cost_seconds,
                                     sampling_seconds))
                bar.update(1, **entry.bar_numbers())
                history.append(entry)
        return policy, batch, history


class Stall:
    """``reset_actor="auto"``: a fresh actor once the policy has stopped moving away from what
    the learned cost forbids. After each policy phase the *current* cost prices the samples before
    and after it, the nominal policy's and the expert's; the *excess* of a sample is what it costs
    beyond the expert. A phase is a stall when the policy's excess after it is material (more than
    :attr:`MATERIAL` of what the policy costs), it removed less than :attr:`PROGRESS` of the excess,
    and the policy keeps more than :attr:`STILL_NOMINAL` of the nominal policy's excess. A policy
    whose cost is the expert's up to a wobble is not stuck, nor one that has left the nominal
    behaviour. :attr:`STALLS` stalls in a row reset the actor (and the count).

    Why: a policy continued from a nearly deterministic one may never leave a behaviour the cost
    now forbids when the way out needs many consecutive deviations (the nominal HalfCheetah kept
    running backward through the wall under any multiplier), while a fresh actor each phase needs
    phases long enough to learn from scratch (BlockedPoint's 21k-step phases then earn 15-52
    instead of 59). Pricing all samples by one cost keeps the test free of the cost's own drift
    between iterations."""

    MATERIAL = 0.1
    PROGRESS = 0.1
    STILL_NOMINAL = 0.5
    STALLS = 2

    def __init__(self) -> None:
        self.count = 0

    def update(self, before: float, after: float, nominal: float, cost: float) -> bool:
        """Record one phase -- the excess of the samples before and after it and of the nominal
        policy's, and what the sample after it costs, all under the current cost; whether to reset."""
        stalled = (after > self.MATERIAL * cost and after > (1.0 - self.PROGRESS) * before
                   and after > self.STILL_NOMINAL * nominal)
        self.count = self.count + 1 if stalled else 0
        if self.count >= self.STALLS:
            self.count = 0
            return True
        return False


__all__ = ["Alternation", "Round", "SAMPLE_SEEDS", "Stall", "seed_offset"]
