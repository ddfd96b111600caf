"""The rendered block world: kinematics, cameras, tasks of Table 7.1 and the scripted demonstrator."""

import numpy as np
import pytest

from symlearn.envs.rendered_blocks.demonstrator import Cameras, demonstrations
from symlearn.envs.rendered_blocks.render import (
    NO_JITTER, Lighting, front_view, pixel_to_table, table_to_pixel, top_down_view,
)
from symlearn.envs.rendered_blocks.tasks import TASKS
from symlearn.envs.rendered_blocks.world import BLOCK, BlockWorld
from symlearn.errors import DataError


def test_pick_and_place_kinematics():
    world = BlockWorld((("red", 0.2, 0.2), ("green", 0.5, 0.5), ("blue", 0.62, 0.5)))
    assert not world.pick_place((0.9, 0.9), (0.3, 0.3))  # nothing to pick
    assert not world.pick_place((0.2, 0.2), (0.01, 0.5))  # off the table
    assert world.positions()[0].tolist() == [0.2, 0.2, 0.0]
    # between green and blue: resting on both (a pyramid's top)
    assert world.pick_place((0.21, 0.19), (0.56, 0.5))
    assert world.positions()[0].tolist() == pytest.approx([0.56, 0.5, 1.0])
    assert not world.free(1) and not world.free(2)
    assert world.block_at(0.56, 0.5) == 0  # the top block is what a pick there takes
    assert world.block_at(0.45, 0.5) is None  # green is under red: it cannot be picked
    # lowered near the centre of a single block: snapped onto it
    world2 = BlockWorld((("red", 0.2, 0.2), ("green", 0.5, 0.5)))
    assert world2.pick_place((0.2, 0.2), (0.53, 0.47))
    assert world2.positions()[0].tolist() == pytest.approx([0.5, 0.5, 1.0])


def test_cameras_show_positions_and_noise_is_seeded():
    names, positions = ("red",), np.array([[0.3, 0.7, 0.0]])
    top = top_down_view(names, positions, size=48)
    row, col = table_to_pixel(0.3, 0.7, 48)
    assert top[row, col, 0] > 120 and top[row, col, 1] < 60  # red under its own pixel
    assert pixel_to_table(row, col, 48) == pytest.approx((0.3, 0.7), abs=1 / 48)
    assert top[0, 0].tolist() != top[row, col].tolist()
    lit = Lighting(0.1, 0.05, 0.03)
    a = front_view(names, positions, lighting=lit, rng=np.random.default_rng(1))
    b = front_view(names, positions, lighting=lit, rng=np.random.default_rng(1))
    c = front_view(names, positions, lighting=lit, rng=np.random.default_rng(2))
    clean = front_view(names, positions, lighting=NO_JITTER)
    assert a.shape == (64, 64, 3) and a.dtype == np.uint8
    assert np.array_equal(a, b) and not np.array_equal(a, c) and not np.array_equal(a, clean)
    raised = front_view(names, positions, lift={0: 2 * BLOCK})
    assert not np.array_equal(raised, clean)  # a lifted block is drawn higher (with a shadow)


@pytest.mark.parametrize("task, orderings, configurations", [
    ("stack-2", 1, 2), ("place-2", 2, 4), ("pyramid-3", 2, 5), ("stack-3", 1, 3), ("place-3", 6, 8)])
def test_table_7_1_demonstration_counts(task, orderings, configurations):
    t = TASKS[task]
    assert len(t.orderings()) == orderings and len(t.configurations()) == configurations
    truth = t.truth_structure()
    assert len(truth["propositions"]) == configurations and truth["initial"] == 0
    # every configuration but the last has a way on; the goal has none
    sources = {u for u, _ in truth["edges"]}
    assert sources == set(range(configurations)) - set(truth["accepting"])


def test_truth_label_and_placement_error():
    task = TASKS["place-2"]
    start = task.layout(frozenset())
    assert task.truth_label(start) == {"at_start"}
    done = task.layout(frozenset({0, 1}))
    assert task.truth_label(done) == {"at_red_blue"} and task.placement_error(done) == 0
    halfway = start.copy()
    halfway[0, :2] = (start[0, :2] + done[0, :2]) / 2
    assert task.truth_label(halfway) == frozenset() and task.placement_error(halfway) > 0


def test_demonstrations_one_per_ordering_with_aligned_views_and_labels():
    demos = demonstrations("place-2", seed=3)
    assert len(demos.front) == len(demos.top) == 2
    assert demos.front.state_kind == "image" and demos.front[0].states.shape[1:] == (64, 64, 3)
    assert demos.top[0].states.shape[1:] == (48, 48, 3)
    assert [t.info["ordering"] for t in demos.front] == [[0, 1], [1, 0]]
    for front, top, config in zip(demos.front, demos.top, demos.configurations):
        assert len(front) == len(top) == len(config)
        assert front.labels == top.labels
        assert front.labels[0] == {"at_start"} and front.labels[-1] == {"at_red_blue"}
        assert (config < 0).sum() >= 2 * 6  # frames in the air between sub-goals
    again = demonstrations("place-2", seed=3)
    assert again.front == demos.front
    assert demonstrations("place-2", seed=4).front != demos.front


def test_demonstrations_round_trip_through_npz(tmp_path):
    demos = demonstrations("stack-2", seed=0, cameras=Cameras(front_size=32))
    path = tmp_path / "frames.npz"
    demos.front.save(path)
    from symlearn.data import load

    assert load(path) == demos.front


def test_unknown_task_is_a_clear_error():
    with pytest.raises(DataError, match="unknown block task 'stack-4'"):
        demonstrations("stack-4")
