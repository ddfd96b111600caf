import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from symlearn.backends.masks import env_mask
from symlearn.envs.junction_env import JunctionEnv, routes
from symlearn.envs.logic_mdp import logic_mdp
from symlearn.envs.traffic_model import JunctionState, TrafficJunction
from symlearn.errors import ModelError

ACT = {name: i for i, name in enumerate(TrafficJunction().actions)}


def junction_mask(lm, variant, forbidden, close=True):
    """A junction domain's mask over the observation ids of that junction's environment."""
    return env_mask(lm.mdp, forbidden, JunctionEnv(variant).state_names, unavailable=lm.unavailable, close=close)


@pytest.mark.parametrize("variant", ["lights", "priority", "combined"])
def test_check_env_and_spaces(variant):
    env = JunctionEnv(variant)
    check_env(env, skip_render_check=True)
    assert env.observation_space.n == len(env.model.states())
    assert env.action_space.n == 5 and env.actions == ("zero", "north", "east", "south", "west")


def test_routes():
    assert len(routes(TrafficJunction("lights"))) == 12  # 4 entries x 3 other arms
    assert routes(TrafficJunction("priority")) == [((3, 5), (5, 3)), ((3, 1), (5, 3)), ((1, 3), (5, 3))]
    assert all(goal == (7, 4) for _, goal in routes(TrafficJunction("combined")))
    with pytest.raises(ModelError):
        JunctionEnv("lights", start=(1, 1))


def test_rewards_and_violations_follow_the_model():
    env = JunctionEnv("lights", start=(3, 1), goal=(5, 3))
    state, info = env.reset(seed=1)
    assert info["cell"] == (3, 1) and env.states[state].cell == (3, 1)
    assert info["state_facts"] == env.model.state_facts(env.states[state])
    before = env.states[state]
    state, reward, terminated, truncated, info = env.step(ACT["north"])
    assert info["cell"] == (3, 2) and not info["violation"] and reward == -3.0  # |5-3| + |3-2|
    assert info["facts"] == env.model.example_facts(before, "north")
    # drive north from (3, 2) until the light is red for the south approach (tls0): a violation
    for _ in range(100):
        if env.states[state].light == 0:
            break
        state, *_ = env.step(ACT["zero"])
    assert env.states[state].light == 0
    _, reward, _, _, info = env.step(ACT["north"])
    assert info["violations"] == ["red_light"] and info["violation"] and reward == -(2 + 0) - 10.0
    # on to the goal: east twice, terminated there with reward 0
    env.step(ACT["east"])
    _, reward, terminated, _, info = env.step(ACT["east"])
    assert terminated and reward == 0.0 and info["distance"] == 0


def test_edge_keeps_the_car_and_truncation():
    env = JunctionEnv("lights", start=(3, 1), goal=(3, 5), max_steps=3)
    env.reset(seed=0)
    _, reward, terminated, truncated, info = env.step(ACT["south"])  # past the edge: stays, allowed
    assert info["cell"] == (3, 1) and not info["violation"] and reward == -4.0
    env.step(ACT["zero"])
    *_, terminated, truncated, _ = env.step(ACT["zero"])
    assert truncated and not terminated


def test_observations_redrawn_with_the_model_probabilities():
    env = JunctionEnv("priority", start=(1, 3), goal=(5, 3), max_steps=10_000)
    env.reset(seed=0)
    cars = [env.states[env.step(ACT["zero"])[0]].car_on_right for _ in range(4000)]
    assert abs(np.mean(cars) - 0.3) < 0.03


def test_seeding_is_reproducible():
    def run(seed):
        env = JunctionEnv("combined")
        obs = [env.reset(seed=seed)[0]]
        rng = np.random.default_rng(0)
        for _ in range(30):
            o, r, term, trunc, _ = env.step(int(rng.integers(5)))
            obs.append((o, r))
            if term or trunc:
                break
        return obs
    assert run(3) == run(3)
    assert run(3) != run(4)


@pytest.mark.parametrize("variant", ["lights", "priority", "combined"])
def test_env_mask_matches_the_logic_mdp_ids(variant):
    env = JunctionEnv(variant)
    lm = logic_mdp(f"junction-{variant}")
    assert tuple(lm.states[:env.observation_space.n]) == env.states
    truth = junction_mask(lm, variant, lm.truth_forbidden, close=False)
    np.testing.assert_array_equal(truth, env.violation_mask())
    # the truth is closed already
    np.testing.assert_array_equal(junction_mask(lm, variant, lm.truth_forbidden), truth)
    with pytest.raises(ModelError):
        junction_mask(lm, variant, truth)  # wrong shape: the LogicMDP has four exit states more
    with pytest.raises(ModelError):  # the ids of another variant are in another order
        other = "priority" if variant != "priority" else "lights"
        env_mask(lm.mdp, lm.truth_forbidden, JunctionEnv(other).state_names, unavailable=lm.unavailable)


def test_closure_forbids_entering_states_where_everything_is_forbidden():
    lm = logic_mdp("junction-priority")
    rules = [":- not onRoad(V) : dir(V).", ":- carOnTheRight, not go(zero)."]
    raw = junction_mask(lm, "priority", lm.rule_mask(rules), close=False)
    closed = junction_mask(lm, "priority", lm.rule_mask(rules))
    env = JunctionEnv("priority")
    north_arm = env.model.state_index(JunctionState(3, 4))
    assert not raw[north_arm, ACT["east"]] and closed[north_arm, ACT["east"]]  # (4, 4) is off the road
    assert not closed[north_arm, ACT["south"]]
