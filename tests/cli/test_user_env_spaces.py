"""The CLI on users' environments with less common spaces (``tests/support/space_envs.py``)."""

from __future__ import annotations

import json

import gymnasium
import numpy as np
from cli_runner import run
from space_envs import OFFSET_WALK

from symlearn.data import record


def _walk(tmp_path, monkeypatch):
    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import offset_walk  # noqa: F401  (registers OffsetWalk-v0)

    # an expert that walks right but never onto the costly cell 5: ids from the spaces' own start
    record(gymnasium.make("OffsetWalk-v0"), lambda cell: 1 if cell < 4 else 0, 4, seed=0).save("walk.jsonl")


def test_learn_icrl_and_train_on_discrete_spaces_that_start_elsewhere(capsys, tmp_path, monkeypatch):
    """A rollout holds a Discrete observation one-hot and a Discrete action as its index; the cost
    reads the spaces' ids (from ``start``), as the demonstrations hold them."""
    _walk(tmp_path, monkeypatch)
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0",
                         "--demos", "walk.jsonl", "--steps", 2048, "--iterations", 1, "-o", "walk.safetensors")
    assert code == 0, err
    assert json.loads(out)["violation_rate"] is not None
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "offset_walk:OffsetWalk-v0",
                         "--cost", "walk.safetensors", "--steps", 1024, "--eval-episodes", 2)
    assert code == 0, err


def test_sampled_discrete_actions_are_the_spaces_ids(tmp_path, monkeypatch):
    """Sampled episodes keep a Discrete action as the environment took it (``start`` added)."""
    from symlearn.rl.episodes import sample_episodes
    from symlearn.rl.ppo import ActorCritic

    _walk(tmp_path, monkeypatch)
    env = gymnasium.make("OffsetWalk-v0")
    policy = ActorCritic.for_spaces(env.observation_space, env.action_space)
    batch = sample_episodes(policy, lambda: gymnasium.make("OffsetWalk-v0"), 3, seed=0)
    taken = batch.actions[batch.mask]
    assert set(np.unique(taken)) <= {-1, 0, 1} and taken.min() == -1
