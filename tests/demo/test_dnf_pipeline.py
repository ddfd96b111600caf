"""The ``dnf`` demo pipeline (the thesis' toy) in its quick setting: the report's numbers and files."""

from symlearn.demo.dnf_pipeline import PIPELINE, toy_lagrangian, toy_ppo_config
from symlearn.demo.registry import DemoContext, pipelines
from symlearn.logic.dnf import load


def test_dnf_pipeline_learns_trains_both_agents_and_prunes(tmp_path):
    assert "dnf" in [p.name for p in pipelines()]
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    fig = section.figures
    for name in section.files:
        assert (tmp_path / name).is_file(), name
    formula, pruned = load(tmp_path / "dnf" / "toy.dnf"), load(tmp_path / "dnf" / "toy.pruned.dnf")
    assert len(formula) == fig["rules"] >= 5 and fig["safe_boxes"] == 2
    assert set(pruned.conjunctions) <= set(formula.conjunctions) and len(pruned) == fig["rules_after_pruning"]
    assert fig["grid_agreement"] > 0.9
    assert fig["training_steps"] == fig["ppo_training_steps"] == 4096
    assert fig["ppo_lag_true_cost"] >= 0 and fig["multiplier"] > 0  # the start's exploration breaks limit 0
    assert isinstance(fig["solved"], bool) and "PPO-Lagrangian, learned DNF" in section.markdown
    assert (tmp_path / "dnf" / "toy_training.png").read_bytes()[:4] == b"\x89PNG"


def test_the_toy_settings_are_the_documented_ones():
    config, lagrangian = toy_ppo_config(3), toy_lagrangian()
    assert config.seed == 3 and config.normalize_observations and config.normalize_values
    assert config.log_std_init == -1.0 and config.learning_rate == 1e-3
    assert lagrangian.cost_limit == 0.0 and lagrangian.advantage_scale == "returns" and lagrangian.init == 1.0
    assert toy_ppo_config(0, normalize_values=False).normalize_values is False
