"""The ``safenav`` demo pipeline in its quick setting: a DNF from expert demonstrations, plain PPO
and PPO-Lagrangian on it in the same run, a plot."""

import math

from symlearn.demo.registry import DemoContext, pipelines
from symlearn.demo.safenav_pipeline import PIPELINE
from symlearn.envs.safenav.observation import FEATURE_NAMES
from symlearn.logic.dnf import load


def test_safenav_pipeline_learns_a_formula_and_trains_both_agents(tmp_path):
    names = [p.name for p in pipelines()]
    assert names.index("safenav") == names.index("dnf") + 1
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    fig = section.figures
    for name in section.files:
        assert (tmp_path / name).is_file(), name
    formula = load(tmp_path / "safenav" / "point_goal.dnf")
    assert len(formula) == fig["rules"] > 0 and set(formula.features) <= set(FEATURE_NAMES)
    assert fig["expert_true_cost"] == 0  # the scripted expert stays out of the hazards
    for agent in ("ppo", "ppo_lag"):
        assert math.isfinite(fig[f"{agent}_return"]) and fig[f"{agent}_true_cost"] >= 0
        assert 0 <= fig[f"{agent}_learned_cost"] <= fig["episode_steps"]
    assert fig["multiplier"] >= 0 and fig["training_steps"] == 4096
    assert "| PPO |" in section.markdown and "| PPO-Lagrangian, learned DNF |" in section.markdown
    assert (tmp_path / "safenav" / "training.png").read_bytes()[:4] == b"\x89PNG"
