"""DQRM and its DQN baselines on the rendered block world (thesis section 7.5)."""

import numpy as np
import pytest

from symlearn.recipes.block_rewards import block_setup
from symlearn.errors import DataError
from symlearn.rl.dqrm import DQRMConfig, pixel_network, train_dqrm


@pytest.fixture(scope="module")
def stack2_truth():
    return block_setup("stack-2", "truth")


def test_fully_convolutional_maps_keep_the_image_size():
    import torch

    for coordinates, inputs in ((False, 6), (True, 8)):
        net = pixel_network(6, 8, coordinates)
        for size in (32, 48):
            assert net(torch.zeros(2, inputs, size, size)).shape == (2, 1, size, size)


@pytest.mark.parametrize("method", ["dqrm", "dqn-shaped", "dqn-sparse"])
def test_short_runs_record_greedy_evaluations_and_save(tmp_path, stack2_truth, method):
    s = stack2_truth
    result = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, method=method, demonstrations=s.demonstrations,
                        config=DQRMConfig(episodes=4, eval_every=2, updates_per_episode=1), seed=0)
    assert [h.episode for h in result.history] == [2, 4] and len(result.episode_returns) == 4
    assert all(0 <= h.success <= 1 and h.placement_error >= 0 for h in result.history)
    expected = 2 * (s.machine.n_states if method == "dqrm" else 1)
    assert len(result.networks) == expected
    path = result.save(tmp_path / "agent.safetensors", {"task": "stack-2"})
    from symlearn.rl.model_files import read_model_config

    saved = read_model_config(path, kind="symlearn-dqrm")
    assert saved["method"] == method and saved["coordinates"] is False and saved["channels"] == 16


def test_bad_method_and_prototypes_are_refused(stack2_truth):
    s = stack2_truth
    with pytest.raises(DataError, match="unknown method"):
        train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, method="ppo")
    with pytest.raises(DataError, match="one top-down image per state"):
        train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes[:1])


@pytest.mark.slow
def test_dqrm_on_the_inferred_machine_solves_place2_where_sparse_dqn_does_not():
    # Place-2, not Stack-2: Stack-2 is one demonstrated move paying 1, which every agent learns from the
    # demonstration in its buffer, sparse DQN included (docs/BENCHMARKS.md, DQRM and DQN)
    s = block_setup("place-2", "inferred")
    config = DQRMConfig(episodes=60, learning_rate=1e-3, updates_per_episode=8)
    dqrm = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, demonstrations=s.demonstrations, config=config)
    sparse = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, method="dqn-sparse",
                        demonstrations=s.demonstrations, config=config)
    assert np.mean([h.machine_return >= 0.9 for h in dqrm.history[-4:]]) >= 0.5
    assert max(h.success for h in sparse.history) == 0.0


def test_a_seed_fixes_the_run(stack2_truth):
    s = stack2_truth
    config = DQRMConfig(episodes=3, eval_every=3, updates_per_episode=1)
    runs = [train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, demonstrations=s.demonstrations,
                       config=config, seed=5) for _ in range(2)]
    assert runs[0].episode_returns == runs[1].episode_returns
    first, second = (dict(r.networks.state_dict()) for r in runs)
    assert all(bool((first[k] == second[k]).all()) for k in first)


def test_double_q_values_the_online_choice_with_the_target_maps():
    import torch

    from symlearn.rl.dqrm import _bootstrap_values

    # one row, two transitions, 2 x 2 pixels; the online maps prefer transition 1, pick pixel 3 and
    # place pixel 0; the target maps' own best (transition 0, value 5) must not be used
    online_pick = torch.tensor([[[[0.0, 0.0], [0.0, 0.0]], [[0.0, 0.0], [0.0, 2.0]]]])
    online_place = torch.tensor([[[[0.0, 0.0], [0.0, 0.0]], [[2.0, 0.0], [0.0, 0.0]]]])
    target_pick = torch.tensor([[[[5.0, 5.0], [5.0, 5.0]], [[9.0, 9.0], [9.0, 0.4]]]])
    target_place = torch.tensor([[[[5.0, 5.0], [5.0, 5.0]], [[0.2, 9.0], [9.0, 9.0]]]])
    double = _bootstrap_values((online_pick, online_place), (target_pick, target_place), True)
    assert double.tolist() == pytest.approx([0.3])
    single = _bootstrap_values((online_pick, online_place), (target_pick, target_place), False)
    assert single.tolist() == pytest.approx([9.0])  # the target's own max: transition 1, 0.5 * (9 + 9)


def test_target_networks_synced_every_update_are_the_online_ones(stack2_truth):
    s = stack2_truth

    def run(sync: int):
        config = DQRMConfig(episodes=2, eval_every=2, updates_per_episode=2, target_sync=sync, double_q=False)
        result = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, demonstrations=s.demonstrations,
                            config=config, seed=3)
        return dict(result.networks.state_dict())

    without, every_update, once = run(0), run(1), run(1000)
    assert all(bool((without[k] == every_update[k]).all()) for k in without)
    # copied once before the first update and then frozen: later targets differ, so do the weights
    assert any(not bool((without[k] == once[k]).all()) for k in without)


def test_without_coordinates_every_empty_pixel_gets_the_same_value():
    # the reason coordinate channels are off by default: on a uniform (empty) table, a map without
    # them cannot single out one pixel away from the border; with them it can
    import torch

    from symlearn.rl.dqrm import _tensor

    torch.manual_seed(0)
    table = torch.full((1, 6, 40, 40), 0.5)
    coords = _tensor(np.full((1, 40, 40, 3), 128, np.uint8))
    with torch.no_grad():
        plain = pixel_network(6, 8, coordinates=False)(table)[0, 0, 16:24, 16:24]
        with_coordinates = pixel_network(6, 8, coordinates=True)(torch.cat([table, coords[:, 3:]], 1))[0, 0, 16:24, 16:24]
    assert float(plain.max() - plain.min()) < 1e-6
    assert float(with_coordinates.max() - with_coordinates.min()) > 1e-4


def test_the_default_networks_read_colours_only(stack2_truth):
    s = stack2_truth
    for coordinates, channels in ((False, 6), (True, 8)):
        config = DQRMConfig(episodes=1, eval_every=1, updates_per_episode=1, coordinates=coordinates)
        result = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, demonstrations=s.demonstrations,
                            config=config, seed=0)
        assert result.networks["pick0"][0].in_channels == channels and len(result.history) == 1
    assert DQRMConfig().coordinates is False
