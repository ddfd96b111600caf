"""The alternating loop the neural ICRL learners share: its order, seeds, actor resets, bar and
records on stand-in steps, and the bar of the learners whose record carries a multiplier."""

from dataclasses import dataclass

import numpy as np
import pytest
import torch

import symlearn.learners.neural.alternation as alternation
from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.learners.neural import NeuralMCEICRL, NeuralMEICRL, NeuralVMEICRL
from symlearn.learners.neural.alternation import Alternation, Round, seed_offset
from symlearn.learners.neural.records import IterationRecord
from progress_recording import recording_bar
from symlearn.rl.episodes import EpisodeBatch


def batch_of(reward: float) -> EpisodeBatch:
    """Two one-step episodes with this reward, the second violating."""
    return EpisodeBatch(np.zeros((2, 1, 1)), np.zeros((2, 1, 1)), np.full((2, 1), reward),
                        np.array([[0.0], [1.0]]), np.ones((2, 1), bool))


class Policy:
    def __init__(self, name: str, log: list) -> None:
        self.name, self.log = name, log

    def reset_actor(self, generator: torch.Generator) -> None:
        self.log.append(("reset", self.name))


@dataclass(frozen=True)
class Trained:
    policy: Policy


@dataclass(frozen=True)
class Record(IterationRecord):
    iteration: int
    reward: float
    violation_rate: float
    cost: str


def test_one_loop_in_order_with_its_seeds(monkeypatch):
    log, seeds = [], []

    def sample(policy, env_fn, n_episodes, *, seed):
        seeds.append(seed)
        log.append(("sample", policy.name))
        return batch_of(float(len(seeds)))

    monkeypatch.setattr(alternation, "sample_episodes", sample)
    shown = recording_bar(monkeypatch, alternation)
    loop = Alternation("test", 3, env_fn=lambda: None, n_episodes=2, seed=5, reset_actor="last",
                       generator=torch.Generator())
    first = loop.sample(Policy("nominal", log))

    def cost_step(iteration, batch):
        log.append(("cost", iteration))
        return f"cost {iteration} on reward {batch.rewards[0, 0]}"

    def policy_step(iteration, policy):
        log.append(("policy", iteration, policy.name))
        return Trained(Policy(f"p{iteration}", log))

    rounds = []

    def record(step: Round) -> Record:
        rounds.append(step)
        return Record(step.iteration, step.metrics.reward, step.metrics.violation_rate, step.cost)

    policy, batch, history = loop.run(Policy("nominal", log), first, cost_step=cost_step, policy_step=policy_step,
                                      record=record)
    # sample seeds: 10_000 + 100 * iteration after the seed, the nominal policy's first
    assert seeds == [10_005, 10_105, 10_205, 10_305]
    assert log[1:] == [("cost", 1), ("policy", 1, "nominal"), ("sample", "p1"),
                       ("cost", 2), ("policy", 2, "p1"), ("sample", "p2"),
                       ("cost", 3), ("reset", "p2"), ("policy", 3, "p2"), ("sample", "p3")]
    assert policy.name == "p3" and batch.rewards[0, 0] == 4.0
    # each record reads the sample its cost step learned from: the policy before the PPO phase
    assert [h.cost for h in history] == ["cost 1 on reward 1.0", "cost 2 on reward 2.0", "cost 3 on reward 3.0"]
    assert [h.reward for h in history] == [1.0, 2.0, 3.0] and {h.violation_rate for h in history} == {0.5}
    assert all(r.policy_seconds >= 0 and r.cost_seconds >= 0 and r.sampling_seconds >= 0 for r in rounds)
    assert shown == [{"return": r, "violation": 0.5} for r in (1.0, 2.0, 3.0)]
    assert seed_offset(None, 7) is None


@pytest.mark.parametrize("learner, multiplier", [
    (NeuralMCEICRL(n_features=2, pretrain=False), lambda h: max(h.lambdas)),
    (NeuralMEICRL(backward_epochs=1), lambda h: h.multiplier),
    (NeuralVMEICRL(backward_epochs=1), lambda h: h.multiplier),
])
def test_bar_shows_the_multiplier(monkeypatch, learner, multiplier):
    shown = recording_bar(monkeypatch, alternation)
    learner.set_params(n_iterations=2, nominal_steps=512, policy_steps=512, n_policy_episodes=2, obs_dims=[0, 1],
                       hidden_sizes=(8,))
    learner.fit(expert_demonstrations(2, seed=0), BlockedPoint)
    assert shown == [{"return": h.reward, "violation": h.violation_rate, "lambda": multiplier(h)}
                     for h in learner.history_]


def test_stall_resets_after_two_phases_without_progress():
    from symlearn.learners.neural.alternation import Stall

    stall = Stall()  # excess before, after, nominal's excess, the policy's cost after the phase
    phases = [(10, 9.5), (9.5, 9.4), (9.4, 9.3), (9.3, 6.0), (6.0, 5.9), (5.9, 5.8)]
    assert [stall.update(b, a, 10.0, a + 1.0) for b, a in phases] == [False, True, False, False, False, True]
    stall = Stall()  # a policy that matches the expert (no excess) never stalls
    assert not any(stall.update(0.0, 0.0, 10.0, 5.0) for _ in range(5))
    stall = Stall()  # nor one that has left most of the nominal policy's excess behind, however it wobbles
    assert not any(stall.update(0.3, 0.31, 10.0, 5.0) for _ in range(5))
    stall = Stall()  # nor one whose excess is a sliver of what it costs (the cost no longer separates)
    assert not any(stall.update(0.3, 0.31, 0.4, 159.0) for _ in range(5))


def test_auto_reset_reads_the_excess_of_the_samples_before_and_after_each_phase(monkeypatch):
    """``reset_actor="auto"``: the loop compares, under the cost of the iteration, the sample
    before the last phase with the one after it; two stalls in a row reset the actor."""
    log = []
    monkeypatch.setattr(alternation, "sample_episodes",
                        lambda policy, env_fn, n, *, seed: batch_of(float(seed - 10_000) / 100))
    loop = Alternation("test", 5, env_fn=lambda: None, n_episodes=2, seed=0, reset_actor="auto",
                       generator=torch.Generator())
    first = loop.sample(Policy("nominal", log))
    # the excess of a sample is set by the iteration it was drawn after: it never shrinks
    price = lambda batches: ([11.0 - 0.01 * b.rewards[0, 0] for b in batches], 1.0)
    resets = []
    loop.run(Policy("nominal", log), first, cost_step=lambda i, b: None,
             policy_step=lambda i, p: Trained(Policy(f"p{i}", log)),
             record=lambda step: Record(step.iteration, 0.0, 0.0, ""), price=price, resets=resets)
    # iteration 2 compares samples 0 and 1 (stall 1), iteration 3 samples 1 and 2 (stall 2: reset),
    # then the count starts again: 4 (stall 1), 5 (stall 2: reset)
    assert resets == [3, 5] and [e for e in log if e[0] == "reset"] == [("reset", "p2"), ("reset", "p4")]


def test_mce_icrl_accepts_auto_and_reports_its_resets():
    learner = NeuralMCEICRL(n_iterations=3, nominal_steps=512, policy_steps=512, n_policy_episodes=2,
                            obs_dims=[0, 1], hidden_sizes=(8,), reset_actor="auto")
    learner.fit(expert_demonstrations(2, seed=0), lambda: BlockedPoint(max_steps=30))
    resets = learner.result_.metrics["actor_resets"]
    assert isinstance(resets, list) and all(i in (3,) for i in resets)
