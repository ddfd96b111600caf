"""``reset_actor``: every ICRL learner starts each policy phase from a fresh actor when asked to."""

from __future__ import annotations

import pytest

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.learners import neural
from symlearn.rl.ppo import ActorCritic


@pytest.mark.parametrize("name", ["NeuralMCEICRL", "NeuralMEICRL", "NeuralVMEICRL", "NeuralGACL"])
@pytest.mark.parametrize("reset, expected", [("never", 0), ("every", 2), ("last", 1), ("auto", 0)])
def test_reset_actor_before_the_chosen_policy_phases(name, reset, expected, monkeypatch):
    calls = []
    original = ActorCritic.reset_actor

    def counted(self, generator=None):
        calls.append(self)
        return original(self, generator)

    monkeypatch.setattr(ActorCritic, "reset_actor", counted)
    learner = getattr(neural, name)(n_iterations=2, nominal_steps=512, policy_steps=512, n_policy_episodes=2,
                                    obs_dims=[0, 1], hidden_sizes=(8,), reset_actor=reset)
    learner.fit(expert_demonstrations(2, seed=0), lambda: BlockedPoint(max_steps=30))
    assert len(calls) == expected
    assert all(policy is calls[0] for policy in calls)  # the one policy that is returned, reset in place
    if expected:
        assert calls[0] is learner.policy_ and learner.policy_ is not learner.nominal_policy_


def test_unknown_reset_actor_is_refused():
    from symlearn.errors import SymlearnError

    with pytest.raises(SymlearnError, match="reset_actor must be one of"):
        neural.NeuralMCEICRL(reset_actor=True).fit(expert_demonstrations(2, seed=0), BlockedPoint)
