"""PPO and PPO-Lagrangian (symlearn.rl.ppo) and the safetensors model files.

Budgets were measured on 2 cores with one torch thread: CartPole 30k steps takes 2-5 s a seed and
reached a deterministic return of 300-500 on seeds 0-5 (random: about 22); the corridor runs
take about 2 s each.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

torch = pytest.importorskip("torch")
pytest.importorskip("safetensors")

from symlearn.errors import DataError, ModelError, SymlearnError  # noqa: E402
from symlearn.rl.model_files import load_torch_module, model_paths, save_torch_module  # noqa: E402
from symlearn.rl.ppo import (  # noqa: E402
    ActorCritic,
    LagrangianConfig,
    Multipliers,
    PPOConfig,
    _gae,
    evaluate,
    train_ppo,
)


class Corridor(gym.Env):
    """Cells 0..length, reward -1 a step, the episode ends at ``length``. Action 0 moves one cell;
    action 1 jumps two and costs 1 (``vector``: action 2 jumps three and costs ``[0, 1]``, action 1
    costs ``[1, 0]``). Plain PPO jumps every time (cost 5 per episode); within a cost limit of 1
    the best policy jumps once."""

    def __init__(self, length: int = 10, vector: bool = False, costs=None):
        self.length, self.vector, self.costs = length, vector, costs
        self.observation_space = spaces.Discrete(length + 1)
        self.action_space = spaces.Discrete(3 if vector else 2)
        self.steps = 0

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = 0
        return self.pos, {}

    def step(self, action):
        action = int(action)
        self.pos = min(self.length, self.pos + 1 + action)
        if self.costs is not None:  # a scripted sequence of info["cost"] values (None: no key)
            cost = self.costs[min(self.steps, len(self.costs) - 1)]
        elif self.vector:
            cost = [float(action == 1), float(action == 2)]
        else:
            cost = float(action == 1)
        self.steps += 1
        info = {} if cost is None else {"cost": cost}
        return self.pos, -1.0, self.pos == self.length, False, info


CORRIDOR = dict(n_envs=4, n_steps=64, batch_size=64, n_epochs=4, learning_rate=1e-3)


@pytest.fixture(scope="module")
def plain_corridor():
    return train_ppo(lambda: Corridor(), 12_000, PPOConfig(seed=0, **CORRIDOR))


# --- learning ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ppo_learns_cartpole(seed):
    result = train_ppo("CartPole-v1", 30_000, PPOConfig(seed=seed))
    # the last iteration in which an episode ended (a 500-step episode spans several rollouts)
    finished = [h.mean_return for h in result.history if not math.isnan(h.mean_return)]
    first, last = finished[0], finished[-1]
    final = evaluate(result.policy, gym.make("CartPole-v1"), 10, seed=100)
    assert final.returns.mean() >= 150  # a random policy: about 22
    assert last > 2 * first
    assert result.steps == 30_208 == result.history[-1].steps  # whole iterations of 4 x 128
    assert len(result.episodes) == len(result.episodes.costs) and result.episodes.costs.shape[1] == 0


def test_same_seed_same_run():
    config = PPOConfig(n_envs=2, n_steps=128, seed=7)
    a, b = (train_ppo("CartPole-v1", 1024, config) for _ in range(2))
    timing = {"steps_per_second", "seconds"}
    assert [{k: v for k, v in h.as_dict().items() if k not in timing} for h in a.history] == \
           [{k: v for k, v in h.as_dict().items() if k not in timing} for h in b.history]
    for (name, x), (_, y) in zip(a.policy.state_dict().items(), b.policy.state_dict().items()):
        assert torch.equal(x, y), name
    c = train_ppo("CartPole-v1", 1024, PPOConfig(n_envs=2, n_steps=128, seed=8))
    assert not torch.equal(c.policy.actor[0].weight, a.policy.actor[0].weight)


def test_threads_set_while_training_and_restored():
    before = torch.get_num_threads()
    seen = []
    train_ppo("CartPole-v1", 256, PPOConfig(n_envs=1, n_steps=128),
              callback=lambda record, policy: seen.append(torch.get_num_threads()))
    assert seen == [1, 1] and torch.get_num_threads() == before


def test_callback_can_stop_and_records_are_json():
    result = train_ppo("CartPole-v1", 10_000, PPOConfig(n_envs=1, n_steps=128),
                       callback=lambda record, policy: record.iteration < 3)
    assert len(result.history) == 3 and result.steps == 384
    record = json.loads(json.dumps(result.history[-1].as_dict(), allow_nan=False))
    assert {"mean_return", "mean_cost", "multipliers", "approx_kl", "policy_loss", "value_loss", "entropy",
            "steps_per_second", "epochs"} <= set(record)


def test_target_kl_stops_epochs_early():
    result = train_ppo("CartPole-v1", 2048, PPOConfig(n_envs=2, n_steps=256, n_epochs=30, learning_rate=3e-3,
                                                      anneal_lr=False, target_kl=0.001))
    assert any(h.stopped_early for h in result.history)
    assert all(h.epochs < 30 for h in result.history if h.stopped_early)


# --- continuous actions, files ------------------------------------------------------------------------


def test_continuous_actions_run_and_round_trip_exactly(tmp_path):
    result = train_ppo("Pendulum-v1", 1024, PPOConfig(n_envs=2, n_steps=256, seed=0))
    policy = result.policy
    assert len(result.history) == 2 and not policy.discrete and policy.log_std.shape == (1,)
    obs = np.array([1.0, 0.0, 0.5], dtype=np.float32)
    action = policy.act(obs, deterministic=True)
    assert action.shape == (1,) and -2.0 <= action[0] <= 2.0
    batch = policy.act(np.stack([obs, -obs]), rng=np.random.default_rng(0))
    assert len(batch) == 2 and all(a.shape == (1,) and abs(a[0]) <= 2.0 for a in batch)
    assert np.isfinite(result.history[-1].mean_return)  # Pendulum episodes end at 200 steps (truncated)

    path = result.save(tmp_path / "pendulum")
    weights, config_path = model_paths(path)
    assert weights.suffix == ".safetensors" and config_path.exists()
    document = json.loads(config_path.read_text())
    assert document["kind"] == "ppo-actor-critic" and document["config"]["action"]["low"] == [-2.0]
    assert document["config"]["training"]["ppo"]["n_steps"] == 256
    loaded = ActorCritic.load(weights)
    assert loaded.state_dict().keys() == policy.state_dict().keys()
    for name, tensor in policy.state_dict().items():
        assert torch.equal(tensor, loaded.state_dict()[name]), name
    observations = np.random.default_rng(1).normal(size=(16, 3)).astype(np.float32)
    np.testing.assert_array_equal(np.stack(loaded.act(observations, deterministic=True)),
                                  np.stack(policy.act(observations, deterministic=True)))
    env = gym.make("Pendulum-v1")
    assert evaluate(loaded, env, 2, seed=3).returns.tolist() == evaluate(policy, env, 2, seed=3).returns.tolist()


def test_discrete_policy_round_trips_with_cost_critics(tmp_path):
    result = train_ppo(lambda: Corridor(vector=True), 512, PPOConfig(n_envs=2, n_steps=128),
                       LagrangianConfig(cost_limit=[1.0, 1.0]))
    result.policy.save(tmp_path / "corridor.safetensors")
    loaded = ActorCritic.load(tmp_path / "corridor.safetensors")
    assert loaded.n_costs == 2 and loaded.observation_spec == {"kind": "discrete", "n": 11, "start": 0}
    for name, tensor in result.policy.state_dict().items():
        assert torch.equal(tensor, loaded.state_dict()[name]), name
    assert loaded.act(3, deterministic=True) == result.policy.act(3, deterministic=True)


def test_model_files_refuse_what_does_not_fit(tmp_path):
    policy = ActorCritic({"kind": "box", "shape": [4]}, {"kind": "discrete", "n": 2, "start": 0})
    path = policy.save(tmp_path / "agent")
    weights, config_path = model_paths(path)
    original = config_path.read_text()

    document = json.loads(original)
    document["config"]["hidden_sizes"] = [32, 32]
    config_path.write_text(json.dumps(document))
    fits = r"actor.0.weight \(64, 4\) torch.float32 in the file, \(32, 4\) torch.float32 in the model"
    with pytest.raises(ModelError, match=fits):
        ActorCritic.load(weights)

    document["config"]["hidden_sizes"], document["config"]["n_costs"] = [64, 64], 1
    config_path.write_text(json.dumps(document))
    with pytest.raises(ModelError, match="missing cost_critics.0.0.bias"):
        ActorCritic.load(weights)

    bigger = ActorCritic({"kind": "box", "shape": [4]}, {"kind": "discrete", "n": 2, "start": 0}, n_costs=1)
    bigger.save(tmp_path / "bigger")
    config_path.write_text(original)
    weights.write_bytes((tmp_path / "bigger.safetensors").read_bytes())
    with pytest.raises(ModelError, match="unknown cost_critics.0.0.bias"):
        ActorCritic.load(weights)

    import pickle  # a pickle where the weights should be: refused, never unpickled

    weights.write_bytes(pickle.dumps({"actor.0.weight": [1.0]}))
    with pytest.raises(ModelError, match="not a readable safetensors file"):
        ActorCritic.load(weights)

    config_path.unlink()
    with pytest.raises(ModelError, match="no model configuration"):
        ActorCritic.load(weights)


def test_generic_module_files(tmp_path):
    module = torch.nn.Linear(3, 2)
    save_torch_module(tmp_path / "lin.safetensors", module, {"n_in": 3, "n_out": 2}, kind="linear")
    loaded, config = load_torch_module(tmp_path / "lin.safetensors", lambda c: torch.nn.Linear(c["n_in"], c["n_out"]),
                                       kind="linear")
    assert config == {"n_in": 3, "n_out": 2} and torch.equal(loaded.weight, module.weight)
    with pytest.raises(ModelError, match="holds a 'linear' model, not a 'ppo-actor-critic' one"):
        ActorCritic.load(tmp_path / "lin.safetensors")
    with pytest.raises(ModelError, match="not plain JSON"):
        save_torch_module(tmp_path / "x", module, {"bad": float("nan")}, kind="linear")


# --- PPO-Lagrangian ------------------------------------------------------------------------------------


@pytest.mark.parametrize("update, options", [
    ("gradient", {"lr": 0.1}),
    ("adam", {"lr": 0.1}),
    ("pid", {"kp": 1.0, "ki": 0.1, "kd": 0.0}),
])
def test_lagrangian_keeps_cost_below_the_limit(plain_corridor, update, options):
    limit = 1.0
    result = train_ppo(lambda: Corridor(), 12_000, PPOConfig(seed=0, **CORRIDOR),
                       LagrangianConfig(cost_limit=limit, update=update, **options))
    plain_cost = plain_corridor.episodes.costs[-50:, 0].mean()
    lagrangian_cost = result.episodes.costs[-50:, 0].mean()
    assert plain_cost > 4  # the unconstrained agent jumps (nearly) every time
    assert lagrangian_cost < 2 and lagrangian_cost < plain_cost - 2
    greedy = evaluate(result.policy, Corridor(), 3, seed=0)
    assert greedy.costs.max() <= limit and greedy.returns.mean() < -5  # slower than jumping, within the limit
    lambdas = [h.multipliers[0] for h in result.history]
    assert result.history[0].mean_cost[0] > limit and lambdas[0] > 0  # a random start breaks the limit
    assert max(lambdas) > 1 and result.multipliers.shape == (1,)
    assert result.policy.n_costs == 1 and len(result.history[-1].cost_value_loss) == 1


def test_two_constraints_two_multipliers():
    # constraint 0 (jump two) can cost at most 5 < 10: its multiplier never leaves 0;
    # constraint 1 (jump three) is broken by the unconstrained policy: its multiplier rises
    result = train_ppo(lambda: Corridor(vector=True), 12_000, PPOConfig(seed=0, **CORRIDOR),
                       LagrangianConfig(cost_limit=[10.0, 1.0], update="gradient", lr=0.1, init=0.0))
    assert result.policy.n_costs == 2 and result.multipliers.shape == (2,)
    assert result.episodes.costs.shape == (len(result.episodes), 2)
    assert all(len(h.multipliers) == len(h.mean_cost) == len(h.cost_value_loss) == 2 for h in result.history)
    assert all(h.multipliers[0] == 0.0 for h in result.history)
    assert max(h.multipliers[1] for h in result.history) > 0.5
    assert result.episodes.costs[-50:, 1].mean() < 2


def test_scalar_limit_applies_to_every_constraint():
    result = train_ppo(lambda: Corridor(vector=True), 1024, PPOConfig(n_envs=2, n_steps=128),
                       LagrangianConfig(cost_limit=1.0, init=0.5))
    assert result.policy.n_costs == 2 and result.multipliers.shape == (2,)
    assert result.history[0].multipliers != (0.5, 0.5)  # updated from the first rollout's costs


@pytest.mark.parametrize("update, options", [
    ("gradient", {"lr": 0.1}),
    ("adam", {"lr": 0.1}),
    ("pid", {"kp": 0.1, "ki": 0.01, "kd": 0.01}),
])
def test_multiplier_rules_rise_above_and_fall_to_zero_below(update, options):
    multipliers = Multipliers(LagrangianConfig(cost_limit=[5.0, 1.0], update=update, **options), 2)
    rising = np.array([multipliers.update([8.0, 1.0]) for _ in range(30)])  # 0 broken, 1 exactly met
    assert rising[0, 0] > 0 and np.all(np.diff(rising[:, 0]) > 0)
    assert np.all(rising[:, 1] < rising[:, 0])  # met exactly (PID: only its derivative term moves)
    falling = np.array([multipliers.update([2.0, 0.0])[0] for _ in range(400)])  # both below their limits
    peak = int(falling.argmax())  # Adam's momentum and PID's averages carry on for a few updates
    assert peak < 15 and np.all(np.diff(falling[peak:]) <= 1e-12)
    assert falling[-1] == 0.0 and multipliers.values[1] == 0.0


def test_gradient_rule_by_hand_and_cap():
    m = Multipliers(LagrangianConfig(cost_limit=2.0, update="gradient", lr=0.5, init=1.0, max_multiplier=2.5), 1)
    assert [float(m.update([4.0])[0]) for _ in range(3)] == [2.0, 2.5, 2.5]
    assert float(m.update([0.0])[0]) == 1.5 and float(m.update([-100.0])[0]) == 0.0


def test_adam_rule_matches_torch_adam():
    """The numpy Adam step of the multipliers is torch's Adam on the loss -lambda (J_c - d), projected."""
    m = Multipliers(LagrangianConfig(cost_limit=1.0, update="adam", lr=0.05, init=0.0), 1)  # adam_beta2 0.99 by default
    lam = torch.zeros(1, requires_grad=True)
    optimizer = torch.optim.Adam([lam], lr=0.05, betas=(0.9, 0.99))
    for cost in [3.0, 2.5, 0.5, 4.0, 0.0, 0.0, 0.0]:
        optimizer.zero_grad()
        (-lam * (cost - 1.0)).sum().backward()
        optimizer.step()
        with torch.no_grad():
            lam.clamp_(min=0.0)
        np.testing.assert_allclose(m.update([cost]), lam.detach().numpy(), rtol=1e-5, atol=1e-7)


def test_gae_matches_a_direct_sum():
    rewards = np.array([[1.0], [2.0], [3.0], [4.0]])[:, :, None]  # T=4, one env, one signal
    dones = np.array([[0.0], [1.0], [0.0], [0.0]])
    values = np.zeros_like(rewards)
    _, returns = _gae(rewards, values, np.array([[10.0]]), dones, np.array([0.5]), 1.0)
    # lambda = 1, zero values: discounted sums, cut after step 1, bootstrapped with 10 at the end
    assert returns[:, 0, 0].tolist() == [1 + 0.5 * 2, 2, 3 + 0.5 * 4 + 0.25 * 10, 4 + 0.5 * 10]


# --- bad input ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("limit, where", [(-1.0, "got -1$"), ([1.0, -0.5], r"got -0.5 \(constraint 1\)")])
def test_negative_cost_limit_is_refused(limit, where):
    with pytest.raises(SymlearnError, match="cost_limit must be >= 0, " + where.rstrip("$")):
        LagrangianConfig(cost_limit=limit)


@pytest.mark.parametrize("kwargs, message", [
    ({"cost_limit": float("nan")}, "cost_limit must be finite"),
    ({"cost_limit": 1.0, "update": "newton"}, "update must be"),
    ({"cost_limit": [1.0, 2.0], "init": [0.0, 0.0, 0.0]}, "init has 3 entries but cost_limit has 2"),
    ({"cost_limit": 1.0, "init": -1.0}, "initial multipliers must be >= 0"),
    ({"cost_limit": 1.0, "advantage_scale": "std"}, "advantage_scale must be one of 'raw', 'returns'"),
])
def test_bad_lagrangian_settings(kwargs, message):
    with pytest.raises(SymlearnError, match=message):
        LagrangianConfig(**kwargs)


@pytest.mark.parametrize("kwargs, message", [
    ({"n_envs": 0}, "n_envs must be a positive integer"),
    ({"gamma": 1.5}, r"gamma must be in \[0, 1\]"),
    ({"activation": "gelu"}, "activation must be one of"),
    ({"target_kl": 0.0}, "target_kl must be > 0 or None"),
])
def test_bad_ppo_settings(kwargs, message):
    with pytest.raises(SymlearnError, match=message):
        PPOConfig(**kwargs)


@pytest.mark.parametrize("costs, lagrangian, message", [
    ([0.0, [1.0, 0.0]], None, "info\\['cost'\\] has 2 entries, earlier steps reported 1"),
    ([0.0, float("nan")], None, "info\\['cost'\\] is not finite"),
    ([[0.0, 1.0]], LagrangianConfig(cost_limit=[1.0, 1.0, 1.0]), "has 2 entries, the cost limits name 3"),
    ([None], LagrangianConfig(cost_limit=1.0), "PPO-Lagrangian got no info\\['cost'\\] in its first rollout"),
    (["high"], None, "must be a number or a vector of numbers"),
])
def test_bad_costs_are_refused(costs, lagrangian, message):
    with pytest.raises(DataError, match=message):
        train_ppo(lambda: Corridor(costs=costs), 256, PPOConfig(n_envs=1, n_steps=128), lagrangian)


def test_nan_reward_is_refused():
    class NanReward(Corridor):
        def step(self, action):
            obs, _, terminated, truncated, info = super().step(action)
            return obs, float("nan"), terminated, truncated, info

    with pytest.raises(DataError, match="the reward is not finite: nan"):
        train_ppo(NanReward, 128, PPOConfig(n_envs=1, n_steps=64))


def test_missing_costs_count_zero_for_plain_ppo():
    result = train_ppo(lambda: Corridor(costs=[None, None, 1.0, None]), 256, PPOConfig(n_envs=1, n_steps=128))
    assert result.episodes.costs.shape[1] == 1
    assert result.episodes.costs[0, 0] == 1.0 and result.episodes.costs[1:, 0].max() == 0.0


def test_unsupported_spaces_are_refused():
    class TupleEnv(Corridor):
        def __init__(self):
            super().__init__()
            self.action_space = spaces.MultiDiscrete([2, 2])

    with pytest.raises(SymlearnError, match="PPO supports Box and Discrete action spaces, got MultiDiscrete"):
        train_ppo(TupleEnv, 128, PPOConfig(n_envs=1, n_steps=64))


def test_importing_symlearn_rl_does_not_load_torch():
    code = ("import sys, symlearn.rl, symlearn.rl.tabular, symlearn.rl.q_learning, symlearn.rl.maxent, "
            "symlearn.rl.crm_q_learning; print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_hard_constraint_starts_at_one_and_a_budget_at_zero():
    """With return-unit advantages a multiplier of 1 weighs the cost as much as the reward: the
    default start of a limit of 0; a positive budget starts at 0, per constraint (init=0 gives the
    old start everywhere, and LEGACY_LAGRANGIAN keeps it)."""
    from symlearn.rl.ppo import LEGACY_LAGRANGIAN

    assert LagrangianConfig(cost_limit=0.0).init == 1.0 and LEGACY_LAGRANGIAN["init"] == 0.0
    assert LagrangianConfig(cost_limit=25.0).init == 0.0
    assert LagrangianConfig(cost_limit=[0.0, 3.0]).init == (1.0, 0.0)
    assert LagrangianConfig(cost_limit=0.0, init=0.0).init == 0.0
    assert Multipliers(LagrangianConfig(cost_limit=0.0), 2).values.tolist() == [1.0, 1.0]
