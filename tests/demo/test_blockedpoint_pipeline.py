"""The ``blockedpoint`` demo pipeline in its quick setting: the files it writes and the numbers it reports."""

import json

import numpy as np

from symlearn.demo.blockedpoint_pipeline import PIPELINE, cost_map, multiplier_of
from symlearn.demo.registry import DemoContext
from symlearn.envs.blocked_point import BlockedPoint
from symlearn.learners.neural import NeuralCost


def test_blockedpoint_pipeline_writes_the_cost_and_its_map(tmp_path):
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    for name in section.files:
        assert (tmp_path / name).is_file(), name
    fig = section.figures
    assert fig["steps"] == 4096 and fig["iterations"] == 2 and fig["demonstrations"] == 3
    assert 0 <= fig["violation_rate"] <= 1 and 0 <= fig["unconstrained_violation_rate"] <= 1
    assert fig["recovery_auc"] is None or 0 <= fig["recovery_auc"] <= 1
    assert (tmp_path / "blockedpoint" / "cost_map.png").read_bytes()[:4] == b"\x89PNG"
    assert "![learned cost over (x, y)](blockedpoint/cost_map.png)" in section.markdown
    json.dumps(fig)
    cost = NeuralCost.load(tmp_path / "blockedpoint" / "cost.safetensors", BlockedPoint())
    # the candidates are BlockedPoint's declared features (x, y); the selection keeps some of them
    assert set(cost.phi.obs_dims) <= {0, 1} and np.allclose(cost.lambdas.numpy(), fig["lambda"], atol=1e-3)


def test_cost_map_evaluates_positions_at_rest():
    class Probe:  # a cost that is x where x < 0: the map must put it at the right (row, column)
        def __call__(self, obs):
            assert obs.shape[1] == 4 and not obs[:, 2:].any()
            return np.maximum(-obs[:, 0], 0.0)

    xs, ys, values = cost_map(Probe(), (-2.0, 2.0), (-1.0, 1.0), n=5)
    assert values.shape == (5, 5) and np.allclose(values[:, 0], 2.0) and np.allclose(values[:, -1], 0.0)
    assert multiplier_of({"lambdas": [1.0, 2.5]}) == 3.5 and multiplier_of({"multiplier": 0.5}) == 0.5
    assert multiplier_of({"expert_d": 0.5}) is None
