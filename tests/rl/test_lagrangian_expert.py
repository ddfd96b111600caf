"""The PPO-Lagrangian expert for environments without a scripted one: cache names, cache use, warnings."""

from __future__ import annotations

import numpy as np
import pytest

from symlearn.envs.blocked_point import BlockedPoint
from symlearn.errors import DataError
from symlearn.rl.lagrangian_expert import (
    EXPERT_LAGRANGIAN,
    EXPERT_PPO,
    cache_name,
    default_cache_dir,
    lagrangian_expert,
)

SMALL = {"n_envs": 2, "n_steps": 128, "batch_size": 128, "n_epochs": 2}


def name(**changes):
    settings = {"key": {"env": "blocked-point", "kwargs": {}}, "steps": 1000, "seed": 0, "n_demos": 3,
                "ppo": EXPERT_PPO, "lagrangian": EXPERT_LAGRANGIAN, **changes}
    return cache_name(settings.pop("key"), **settings)


def test_every_setting_that_shapes_the_expert_changes_the_cache_name():
    base = name()
    assert base.startswith("blocked-point_s0_1000_") and base.endswith(".npz")
    others = [name(steps=2000), name(seed=1), name(n_demos=4), name(ppo={**EXPERT_PPO, "learning_rate": 1e-3}),
              name(lagrangian={**EXPERT_LAGRANGIAN, "init": 2.0}),
              name(key={"env": "blocked-point", "kwargs": {"wall": -2.0}})]
    assert len({base, *others}) == 1 + len(others)
    assert name() == base  # and nothing else (no time, no process id)


def test_cache_dir_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("SYMLEARN_CACHE_DIR", str(tmp_path))
    assert default_cache_dir() == tmp_path / "experts"
    monkeypatch.delenv("SYMLEARN_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "xdg" / "symlearn" / "experts"


def test_trained_once_then_read_from_the_cache(tmp_path):
    key = {"env": "blocked-point", "kwargs": {"max_steps": 40}}

    def env_fn():
        return BlockedPoint(max_steps=40)

    demos, report = lagrangian_expert(env_fn, 3, steps=1024, ppo=SMALL, key=key, cache_dir=tmp_path)
    assert len(demos) == 3 and report["cached"] and report["seconds"] > 0
    assert all(len(t.actions) == 40 for t in demos)
    files = list(tmp_path.iterdir())
    assert len(files) == 1 and files[0].suffix == ".npz"
    again, report2 = lagrangian_expert(env_fn, 3, steps=1024, ppo=SMALL, key=key, cache_dir=tmp_path)
    assert report2["cached"] == str(files[0]) and report2["seconds"] == 0.0
    for a, b in zip(demos, again):
        np.testing.assert_array_equal(a.states, b.states)
        np.testing.assert_array_equal(a.actions, b.actions)
    assert report2["violation_rate"] == pytest.approx(report["violation_rate"])


class AlwaysUnsafe(BlockedPoint):
    """Every step violates, whatever the agent does."""

    def step(self, action):
        obs, reward, terminated, truncated, info = super().step(action)
        return obs, reward, terminated, truncated, {**info, "cost": 1.0, "violation": True}


def test_an_expert_that_still_violates_is_reported():
    with pytest.warns(RuntimeWarning, match="expert violates the constraint on 100.0% of its steps"):
        _, report = lagrangian_expert(lambda: AlwaysUnsafe(max_steps=20), 2, steps=256, ppo=SMALL)
    assert report["violation_rate"] == 1.0 and report["cached"] is None


@pytest.mark.parametrize("kwargs, message", [({"n_demos": 0}, "at least one episode"),
                                             ({"steps": 0}, "positive integer")])
def test_bad_settings_are_refused(kwargs, message):
    with pytest.raises(DataError, match=message):
        lagrangian_expert(BlockedPoint, **{"n_demos": 2, "steps": 100, **kwargs})


def test_the_former_import_paths_name_the_same_objects():
    """The expert lived in ``learners/neural`` and the episode arrays beside it; users' imports still work."""
    import symlearn.learners.neural.episodes as old_episodes
    import symlearn.learners.neural.icrl_metrics as icrl_metrics
    import symlearn.learners.neural.lagrangian_expert as old_expert
    import symlearn.rl.episode_metrics as metrics
    import symlearn.rl.episodes as episodes
    import symlearn.rl.lagrangian_expert as expert

    for name in old_expert.__all__:
        assert getattr(old_expert, name) is getattr(expert, name)
    for name in old_episodes.__all__:
        assert getattr(old_episodes, name) is getattr(episodes, name)
    assert icrl_metrics.episode_metrics is metrics.episode_metrics
