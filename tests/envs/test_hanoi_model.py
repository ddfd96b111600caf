import numpy as np
import pytest

from symlearn.envs.hanoi_model import HanoiModel, HanoiMove, HanoiState
from symlearn.errors import ModelError


@pytest.fixture(scope="module")
def model():
    return HanoiModel()


def test_state_and_pair_counts(model):
    # 3 labelled disks in ordered stacks on 3 pegs: 3! * C(5, 2) = 60 configurations
    assert len(model.states()) == 60
    assert len(set(model.states())) == 60
    assert len(model.ordered_states()) == 27  # each disk picks a peg, order forced
    # 18 one-peg states x 2 moves + 36 two-peg states x 4 + 6 three-peg states x 6
    assert len(list(model.state_actions())) == 216
    assert sum(model.is_allowed(s, a) for s, a in model.state_actions()) == 114


def test_slots_round_trip(model):
    for state in model.states():
        assert HanoiState.from_slots(state.slots) == state
    assert model.initial_state().slots == ((0, 0), (0, 1), (0, 2))


@pytest.mark.parametrize("slots, message", [
    ([(0, 0), (0, 0), (1, 0)], "share slot"),
    ([(0, 0), (0, 2), (1, 0)], "floats"),
    ([(0, 0), (3, 0), (1, 0)], "pegs are 0..2"),
])
def test_from_slots_rejects_impossible_configurations(slots, message):
    with pytest.raises(ModelError, match=message):
        HanoiState.from_slots(slots)


def test_moves_only_move_top_disks(model):
    state = HanoiState(((0, 1), (2,), ()))
    assert model.moves(state) == [HanoiMove(0, 1), HanoiMove(0, 2), HanoiMove(1, 0), HanoiMove(1, 2)]
    assert model.apply(state, HanoiMove(0, 2)) == HanoiState(((0,), (2,), (1,)))
    assert model.moved_disk(state, HanoiMove(0, 2)) == 1
    with pytest.raises(ModelError, match="peg 2 is empty"):
        model.apply(state, HanoiMove(2, 0))


def test_ground_truth_on_hand_checked_cases(model):
    state = HanoiState(((0, 1), (2,), ()))
    assert model.is_allowed(state, HanoiMove(0, 2))      # disk 1 onto the empty peg
    assert not model.is_allowed(state, HanoiMove(0, 1))  # disk 1 (larger) onto disk 2
    assert model.is_allowed(state, HanoiMove(1, 0))      # disk 2 onto disk 1
    # a disordered start: moving the misplaced disk away repairs it, anything else does not
    broken = HanoiState(((1, 0), (), ()))
    assert model.is_allowed(broken, HanoiMove(0, 1))
    assert not HanoiState(((0, 2, 1), (), ())).is_ordered()
    assert model.is_allowed(HanoiState(((0, 2, 1), (), ())), HanoiMove(0, 1))  # disk 1 leaves disk 2
    still_broken = HanoiState(((2, 0), (1,), ()))
    assert not model.is_allowed(still_broken, HanoiMove(1, 0))  # 1 on 0 is fine, 0 on 2 is not
    assert not model.is_allowed(still_broken, HanoiMove(0, 1))  # disk 0 onto the smaller disk 1
    assert model.is_allowed(still_broken, HanoiMove(0, 2))


def test_allowed_mask_and_transitions_agree(model):
    mask = model.allowed_mask()
    table = model.transition_matrix()
    assert mask.shape == table.shape[:2] == (60, 6)
    assert np.allclose(table.sum(axis=2), 1.0)
    for i, state in enumerate(model.states()):
        for a, move in enumerate(model.actions):
            if model.is_available(state, move):
                assert table[i, a, model.state_index(model.apply(state, move))] == 1.0
                assert mask[i, a] == model.apply(state, move).is_ordered()
            else:
                assert table[i, a, i] == 1.0 and not mask[i, a]


def test_expert_reaches_the_goal_without_breaking_the_rule(model):
    rng = np.random.default_rng(3)
    for _ in range(5):
        episode = model.expert_episode(rng)
        assert len(episode) == 7  # the optimal solution for 3 disks
        state = model.initial_state()
        for seen, move in episode:
            assert seen == state and model.is_allowed(state, move)
            state = model.apply(state, move)
        assert state == model.goal_state()


def test_expert_refuses_a_broken_start(model):
    with pytest.raises(ModelError, match="breaks the rules"):
        model.expert_episode(np.random.default_rng(0), start=HanoiState(((1, 0), (2,), ())))


def test_facts(model):
    state = HanoiState(((0,), (1, 2), ()))
    assert model.example_facts(state, HanoiMove(1, 2)) == ["at(0,0,0).", "at(1,1,0).", "at(2,1,1).", "move(2,2)."]
    assert model.state_index(state) == model.states().index(state)
    with pytest.raises(ModelError):
        model.state_index(HanoiState(((0,), (1,), ())))


def test_bad_sizes():
    with pytest.raises(ModelError):
        HanoiModel(0)
    with pytest.raises(ModelError):
        HanoiModel(3, 1)
    assert len(HanoiModel(2, 3).states()) == 12  # 2! * C(4, 2)
