"""Reward machines: stepping, compilation from a DFA, potential-based shaping."""

import pytest
from automata_strategies import a_then_b_avoid_c

from symlearn.errors import ModelError
from symlearn.logic.automata import RewardMachine
from symlearn.logic.guards import Guard

a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")
T = Guard.true()


def test_step_and_implicit_self_loop():
    rm = RewardMachine({"a"}, 2, 0, {0: [(a, 1, 1.0)]}, terminal=[1], default_reward=-0.1)
    assert rm.step(0, {"a"}) == (1, 1.0)
    assert rm.step(0, set()) == (0, -0.1)
    assert rm.step(1, {"a"}) == (1, 0.0)  # terminal states stay put
    assert rm.run([set(), {"a"}, {"a"}]) == ([0, 0, 1], [-0.1, 1.0])


def test_from_dfa_rewards_on_reaching_acceptance():
    rm = RewardMachine.from_dfa(a_then_b_avoid_c())
    assert rm.n_states == 4  # minimal complete: 3 + rejecting sink
    states, rewards = rm.run([{"a"}, set(), {"b"}, {"b"}])
    assert rewards == [0.0, 0.0, 1.0, 0.0]
    assert rm.accepting == {states[3]}
    sink = rm.step(0, {"c"})[0]
    assert sink in rm.terminal and sink not in rm.accepting
    assert states[3] not in rm.terminal  # acceptance can be lost (c), so it is not absorbing
    assert RewardMachine.from_dfa(a_then_b_avoid_c(), terminal_on_acceptance=True).terminal >= rm.accepting


def test_shaping_is_potential_based():
    gamma = 0.9
    plain = RewardMachine.from_dfa(a_then_b_avoid_c())
    shaped = RewardMachine.from_dfa(a_then_b_avoid_c(), shaping=True, gamma=gamma)
    phi = shaped.potential
    assert shaped.gamma == gamma
    assert sorted(phi) == [0.0, 1.0, 2.0, 3.0]  # dead sink 0, then d_max + 1 - d for d = 2, 1, 0
    # waiting costs, progress pays, breaking the rule costs
    assert shaped.step(0, set())[1] < 0 < shaped.step(0, {"a"})[1]
    assert shaped.step(0, {"c"})[1] < shaped.step(0, set())[1]
    for (s, g, t, r), (_, _, _, r0) in zip(shaped.edges(), plain.edges()):
        assert r == pytest.approx(r0 + gamma * phi[t] - phi[s])
    # moving towards acceptance earns more than waiting
    assert shaped.step(0, {"a"})[1] > shaped.step(0, set())[1]
    # telescoping: the discounted shaping along a run is gamma^n phi(end) - phi(start)
    states, rewards = shaped.run([{"a"}, {"b"}])
    _, base = plain.run([{"a"}, {"b"}])
    extra = sum(gamma ** k * (r - r0) for k, (r, r0) in enumerate(zip(rewards, base)))
    assert extra == pytest.approx(gamma ** 2 * phi[states[-1]] - phi[states[0]])


def test_text_round_trip():
    rm = RewardMachine.from_dfa(a_then_b_avoid_c())
    back = RewardMachine.from_text(rm.to_text())
    assert back.n_states == rm.n_states and back.terminal == rm.terminal
    for word in ([{"a"}, {"b"}], [{"c"}], [{"a"}, set(), {"b", "a"}]):
        assert back.run(word) == rm.run(word)


@pytest.mark.parametrize("kwargs, message", [
    (dict(transitions={0: [(a, 1, 1.0), (a | b, 0, 0.0)]}), "not deterministic"),
    (dict(transitions={0: [(a, 1, float("nan"))]}), "finite number"),
    (dict(terminal=[4]), "terminal state 4"),
    (dict(potential=[0.0]), "1 potentials for 2 states"),
])
def test_bad_reward_machines(kwargs, message):
    args = dict(alphabet={"a", "b"}, n_states=2, initial=0, transitions={0: [(a, 1, 1.0)]})
    args.update(kwargs)
    with pytest.raises(ModelError, match=message):
        RewardMachine(**args)


def test_dot_marks_terminal_and_rewards():
    dot = RewardMachine.from_dfa(a_then_b_avoid_c()).to_dot()
    assert "fillcolor" in dot and "/ 1" in dot and "doublecircle" in dot
