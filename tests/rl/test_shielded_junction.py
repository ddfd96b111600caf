"""Logic-constrained Q-learning in the traffic junction: a shield from rules never violates."""

import numpy as np
import pytest

from symlearn.backends import Shield
from symlearn.backends.masks import env_mask
from symlearn.envs.junction_env import JunctionEnv, routes
from symlearn.envs.logic_mdp import logic_mdp
from symlearn.rl.q_learning import q_learning

SETTINGS = {"learning_rate": 0.9, "discount": 0.75, "epsilon": 0.05}

# What logic constraint inference induced in the priority junction from 100 expert drives
# (benchmarks/shielded_q_learning.py, demo seed 0) with start="demonstrations" (the thesis'
# objective, the default before the uniform share); rule text only, translated below.
PRIORITY_RULES = [":- go(west).", ":- not onRoad(V1) : dir(V1).", ":- onRoad(south), go(east).",
                  ":- go(south), not onRoad(north).", ":- go(north), not onRoad(south).",
                  ":- carOnTheRight, not go(zero)."]
# The same with the default start (a 0.1 uniform share) and with start="uniform": one more rule,
# the gap closed by the rules themselves.
PRIORITY_RULES_DEFAULT = PRIORITY_RULES[:2] + [":- onRoad(north), go(east)."] + PRIORITY_RULES[2:]


def junction_mask(lm, variant, forbidden, close=True):
    """A junction domain's mask over the observation ids of that junction's environment."""
    return env_mask(lm.mdp, forbidden, JunctionEnv(variant).state_names, unavailable=lm.unavailable, close=close)


def greedy_violations(env, q, episodes, seed):
    rng = np.random.default_rng(seed)
    count = 0
    for i in range(episodes):
        state, info = env.reset(seed=seed + i)
        while True:
            mask = np.asarray(info.get("action_mask", np.ones(5)), bool)
            values = np.where(mask, q[state], -np.inf)
            state, _, terminated, truncated, info = env.step(int(rng.choice(np.flatnonzero(values == values.max()))))
            count += info["violation"]
            if terminated or truncated:
                break
    return count


@pytest.mark.parametrize("variant, source", [("priority", "rules"), ("lights", "truth")])
def test_shielded_q_learning_never_violates_and_plain_q_learning_does(variant, source):
    lm = logic_mdp(f"junction-{variant}")
    forbidden = lm.rule_mask(PRIORITY_RULES) if source == "rules" else lm.truth_forbidden
    mask = junction_mask(lm, variant, forbidden)
    plain_violations = 0
    for i, (start, goal) in enumerate(routes(JunctionEnv(variant).model)[:3]):
        shielded = Shield(JunctionEnv(variant, start=start, goal=goal), mask, seed=i)
        result = q_learning(shielded, 200, seed=i, **SETTINGS)
        assert result.violations.sum() == 0
        assert greedy_violations(shielded, result.q_values, 10, seed=100 + i) == 0
        assert result.returns[-20:].mean() > -20  # it learned to drive to the goal
        plain = q_learning(JunctionEnv(variant, start=start, goal=goal), 200, seed=i, **SETTINGS)
        plain_violations += plain.violations.sum()
    assert plain_violations > 0


def test_rules_without_the_closure_let_the_priority_agent_off_the_road():
    """The priority rules induced with start="demonstrations" miss "no east turn from the north
    arm" (no demonstration shows it); the rules forbid everything off the road, so closing the mask
    covers the gap."""
    lm = logic_mdp("junction-priority")
    raw = junction_mask(lm, "priority", lm.rule_mask(PRIORITY_RULES), close=False)
    closed = junction_mask(lm, "priority", lm.rule_mask(PRIORITY_RULES))
    truth = junction_mask(lm, "priority", lm.truth_forbidden, close=False)
    missed = [str(JunctionEnv("priority").states[s]) for s, a in np.argwhere(truth & ~raw)]
    assert missed == ["(3,4)", "(3,5)"]
    np.testing.assert_array_equal(closed, truth)


def test_rules_learned_with_the_default_start_need_no_closure():
    lm = logic_mdp("junction-priority")
    np.testing.assert_array_equal(lm.rule_mask(PRIORITY_RULES_DEFAULT), lm.truth_forbidden)
    np.testing.assert_array_equal(
        junction_mask(lm, "priority", lm.rule_mask(PRIORITY_RULES_DEFAULT), close=False),
        junction_mask(lm, "priority", lm.truth_forbidden, close=False))
