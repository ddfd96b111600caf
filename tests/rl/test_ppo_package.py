"""The shape of symlearn.rl.ppo: its modules import each other in one order, the names imported
from the single-file module still resolve, a rollout comes back as a typed frozen batch, and PPO
and the learned neural cost share one space encoding (symlearn.rl.spaces)."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

pytest.importorskip("torch")

import symlearn.rl.ppo as ppo  # noqa: E402
from symlearn.errors import DataError, SymlearnError  # noqa: E402
from symlearn.rl import spaces as encoding  # noqa: E402
from symlearn.rl.episode_stats import CostReader  # noqa: E402
from symlearn.rl.ppo.rollouts import RolloutBatch, _Rollouts  # noqa: E402

PACKAGE = Path(ppo.__file__).parent
# the order of the package docstring's module list: each imports only modules before it
ORDER = ["config", "multipliers", "networks", "records", "rollouts", "update", "stall", "training", "evaluation",
         "limit_check"]


def _package_imports(path: Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("symlearn.rl.ppo."):
            found.add(node.module.rsplit(".", 1)[1])
    return found


def test_modules_import_only_earlier_ones():
    assert sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__") == sorted(ORDER)
    for i, name in enumerate(ORDER):
        later = _package_imports(PACKAGE / f"{name}.py") - set(ORDER[:i])
        assert not later, f"{name}.py imports {sorted(later)}, which come after it"


def test_the_old_import_paths_resolve():
    from symlearn.rl.ppo import (  # noqa: F401
        LEGACY_LAGRANGIAN, OBS_CLIP, ActorCritic, LagrangianConfig, Multipliers, PPOConfig, Rollout, _gae,
        _rescale_critics, _space_spec, evaluate, train_ppo)

    for name in ppo.__all__:
        assert getattr(ppo, name) is not None
    assert ppo.train_ppo.__module__ == "symlearn.rl.ppo.training"
    assert LEGACY_LAGRANGIAN["cost_estimate"] == "episodes"


class Walk(gym.Env):
    """Cells 0..4, action 1 steps right (cost 1 on cell 4), the episode ends on cell 4 or after 6 steps."""

    observation_space = spaces.Discrete(5)
    action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0, 0
        return self.x, {}

    def step(self, action):
        self.x, self.t = min(self.x + int(action), 4), self.t + 1
        return self.x, 1.0, self.x == 4, self.t >= 6, {"cost": float(self.x == 4)}


def test_collect_returns_a_frozen_batch_consistent_with_its_episodes():
    agent = ppo.ActorCritic.for_spaces(Walk.observation_space, Walk.action_space)
    rollouts = _Rollouts([Walk(), Walk()], agent, CostReader(None), seed=0)
    batch = rollouts.collect(16, agent.numpy_actor(), np.random.default_rng(0))
    assert isinstance(batch, RolloutBatch)
    with pytest.raises(dataclasses.FrozenInstanceError):
        batch.rewards = np.zeros(1)
    assert batch.obs.shape == (16, 2, 5) and batch.actions.shape == batch.rewards.shape == (16, 2)
    assert batch.costs.shape == (16, 2, 1) and batch.last_obs.shape == (2, 5)
    assert np.array_equal(batch.true_costs, batch.costs.sum(axis=2))
    assert batch.dones.sum() == len(batch.episodes) > 0
    # every finished episode: reward 1 a step, cost 1 exactly when it ended on cell 4 (not truncated)
    truncated = {(t, i) for t, i, _ in batch.truncated}
    ends = sorted(zip(*np.nonzero(batch.dones)))
    for episode, (t, i) in zip(batch.episodes, ends):
        assert episode.episode_return == episode.length <= 6
        assert episode.costs.tolist() == [0.0 if (t, i) in truncated else 1.0]
    stats = rollouts.episode_stats(1)
    assert stats.costs.shape == (len(batch.episodes), 1) and list(stats.lengths) == [e.length for e in batch.episodes]


HALF_OPEN = spaces.Box(np.array([0.0, -np.inf], np.float32), np.array([1.0, np.inf], np.float32))


@pytest.mark.parametrize("space", [spaces.Discrete(4, start=2), spaces.Box(-1.0, 1.0, (3,)), HALF_OPEN])
def test_ppo_and_the_neural_cost_share_one_space_encoding(space):
    from symlearn.learners.neural.neural_cost import encode, space_spec, spec_width

    assert encode is encoding.encode and spec_width is encoding.spec_width
    for role in ("observation", "action"):
        bounds = role == "action"
        assert ppo._space_spec(space, role) == space_spec(space, bounds) == encoding.space_spec(space, bounds)
    agent = ppo.ActorCritic.for_spaces(space, spaces.Discrete(2))
    values = np.stack([space.sample() for _ in range(5)])
    assert agent.obs_dim == spec_width(space_spec(space))
    assert np.array_equal(agent.features(values), encode(values, space_spec(space), "observations"))


def test_other_spaces_are_refused_with_their_users_message():
    from symlearn.learners.neural.neural_cost import space_spec

    other = spaces.MultiDiscrete([2, 2])
    with pytest.raises(SymlearnError, match="PPO supports Box and Discrete observation spaces"):
        ppo._space_spec(other, "observation")
    with pytest.raises(DataError, match="a learned cost needs Box or Discrete spaces, got MultiDiscrete"):
        space_spec(other)
    with pytest.raises(DataError, match="only Box and Discrete"):
        encoding.space_spec(other)
    with pytest.raises(SymlearnError, match="1-D Box action space"):
        ppo._space_spec(spaces.Box(0.0, 1.0, (2, 2)), "action")
