"""Specification learning with a PPO policy update: float observations, a feature labeling."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch
from gymnasium import spaces

from symlearn.data import record
from symlearn.grounding import FeatureLabeling
from symlearn.learners.temporal.spec_from_demos import SpecLearner
from symlearn.logic.ltlf import holds


class Line(gym.Env):
    """A point on [0, 1] starting at 0.5, stepping 0.1 left or right; either end ends the episode."""

    feature_names = ("x",)

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.5, 0
        return np.array([self.x], np.float32), {}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.1 if action == 1 else -0.1), 0.0, 1.0))
        self.t += 1
        end = self.x < 0.05 or self.x > 0.95
        return np.array([self.x], np.float32), 0.0, end, self.t >= 30, {}


def test_ppo_policy_update_on_float_observations():
    torch.set_num_threads(1)
    labeling = FeatureLabeling(["x"], {"right_end": "x > 0.85", "left_end": "x < 0.15"})
    env = Line()
    demos = record(env, lambda obs: 1, 8, seed=0, labeler=labeling)
    learner = SpecLearner(labeling=labeling, ppo_steps=6_000, n_eval=20, random_state=0).fit(demos, Line)
    assert learner.world_.route == "ppo"
    words = [[frozenset(s) for s in t.labels] for t in demos]
    assert all(holds(learner.formula_, w) for w in words)
    assert "right_end" in str(learner.formula_) or "left_end" in str(learner.formula_)
    assert learner.success_rate(learner.formula_) >= 0.8  # the product-trained PPO policy meets it
    assert learner.history_[0].nominal_rate < 0.8  # random walks did not
