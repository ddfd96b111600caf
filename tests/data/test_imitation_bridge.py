"""imitation's trajectories to and from symlearn's demonstrations.

imitation itself is not installed in the test environment: ``pip install imitation`` (1.0.1)
would downgrade gymnasium to 0.29 and stable-baselines3 to 2.2. The stand-ins below have the
fields and the checks of ``imitation.data.types.Trajectory``/``TrajectoryWithRew`` and of
``DictObs`` (a dict of arrays kept in ``_d``).
"""

from __future__ import annotations

import dataclasses
import importlib.util

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory, from_imitation, record, to_imitation
from symlearn.data.imitation_bridge import PlainTrajectory, PlainTrajectoryWithRew
from symlearn.errors import DataError


@dataclasses.dataclass(frozen=True, eq=False)
class ImitationTrajectory:
    obs: np.ndarray
    acts: np.ndarray
    infos: np.ndarray | None
    terminal: bool

    def __len__(self):
        return len(self.acts)

    def __post_init__(self):
        if len(self.obs) != len(self.acts) + 1:
            raise ValueError("expected one more observations than actions")
        if self.infos is not None and len(self.infos) != len(self.acts):
            raise ValueError("infos when present must be present for each action")
        if len(self.acts) == 0:
            raise ValueError("Degenerate trajectory: must have at least one action.")


@dataclasses.dataclass(frozen=True, eq=False)
class ImitationTrajectoryWithRew(ImitationTrajectory):
    rews: np.ndarray

    def __post_init__(self):
        super().__post_init__()
        if self.rews.shape != (len(self.acts),) or self.rews.dtype.kind != "f":
            raise ValueError("rewards must be 1D float array, one entry for each action")


class DictObs:
    def __init__(self, d):
        self._d = d

    def __len__(self):
        return len(next(iter(self._d.values())))


CLASSES = (ImitationTrajectory, ImitationTrajectoryWithRew)


def test_recorded_demonstrations_round_trip_through_imitation():
    import gymnasium as gym

    demos = record(gym.make("CartPole-v1", max_episode_steps=20), "random", 3, seed=4)
    trajs = to_imitation(demos, classes=CLASSES)
    assert all(isinstance(t, ImitationTrajectoryWithRew) for t in trajs)
    assert [len(t) for t in trajs] == [t.n_actions for t in demos]
    assert [t.terminal for t in trajs] == [t.info["terminated"] for t in demos]
    back = from_imitation(trajs)
    for ours, original in zip(back, demos):
        # everything but the reset seed, which imitation does not keep
        expected = {k: v for k, v in original.info.items() if k != "seed"}
        assert ours == Trajectory(original.states, original.actions, original.rewards, None, expected)
    assert back.metadata == {"source_format": "imitation"}


def test_without_rewards_plain_trajectories():
    demos = Demonstrations([Trajectory(np.eye(3, dtype=np.float32), [0, 1], info={"terminated": False})])
    (traj,) = to_imitation(demos, classes=CLASSES)
    assert type(traj) is ImitationTrajectory and traj.terminal is False
    again = from_imitation([traj])
    assert again[0].info == {"terminated": False, "truncated": True} and again[0].rewards is None
    np.testing.assert_array_equal(again[0].states, demos[0].states)


@pytest.mark.skipif(importlib.util.find_spec("imitation") is not None, reason="imitation's own classes are used")
def test_without_imitation_look_alike_dataclasses_are_built():
    (plain,) = to_imitation(Demonstrations([Trajectory([0, 1], [1])]))
    (rewarded,) = to_imitation(Demonstrations([Trajectory([0, 1], [1], [2.0])]))
    assert type(plain) is PlainTrajectory and type(rewarded) is PlainTrajectoryWithRew
    assert len(rewarded) == 1 and rewarded.rews.tolist() == [2.0] and rewarded.terminal is True
    assert from_imitation([rewarded])[0] == Trajectory([0, 1], [1], [2.0], info={"terminated": True, "truncated": False})


def test_dict_observations_are_flattened_with_names():
    obs = DictObs({"pos": np.arange(6.0).reshape(3, 2), "door": np.array([0, 0, 1])})
    traj = ImitationTrajectoryWithRew(obs=obs, acts=np.array([1, 2]), infos=None, terminal=True,
                                      rews=np.array([0.0, 1.0]))
    demos = from_imitation([traj, traj], metadata={"env": "room"})
    assert demos.metadata == {"source_format": "imitation", "feature_names": ["door", "pos[0]", "pos[1]"],
                              "env": "room"}
    np.testing.assert_array_equal(demos[0].states, [[0, 0, 1], [0, 2, 3], [1, 4, 5]])
    nested = from_imitation([ImitationTrajectory(obs=DictObs({"a": DictObs({"x": np.zeros(2)}), "b": np.ones((2, 1))}),
                                                 acts=np.zeros(1), infos=None, terminal=True)])
    assert nested.metadata["feature_names"] == ["a.x", "b[0]"]


def test_what_does_not_fit_is_refused_with_the_trajectory_named():
    with pytest.raises(DataError, match="trajectory 0 .* not an imitation trajectory"):
        from_imitation([object()])
    bad = dataclasses.make_dataclass("Bad", ["obs", "acts"])(np.zeros((3, 2)), np.zeros(3))
    with pytest.raises(DataError, match="trajectory 0: 3 observations for 3 actions"):
        from_imitation([bad])
    image = DictObs({"cam": np.zeros((2, 4, 4)), "pos": np.zeros((2, 2))})
    with pytest.raises(DataError, match="entry 'cam' has shape \\(4, 4\\) per step"):
        from_imitation([ImitationTrajectory(obs=image, acts=np.zeros(1), infos=None, terminal=True)])
    one = ImitationTrajectory(obs=np.zeros((2, 1)), acts=np.zeros(1), infos=None, terminal=True)
    other = ImitationTrajectory(obs=DictObs({"a": np.zeros(2)}), acts=np.zeros(1), infos=None, terminal=True)
    with pytest.raises(DataError, match="trajectory 1: observation entries"):
        from_imitation([one, other])
    with pytest.raises(DataError, match="needs the final state"):
        to_imitation(Demonstrations([Trajectory([0, 1], [0, 1])]), classes=CLASSES)
    with pytest.raises(DataError, match="array observations"):
        to_imitation(Demonstrations([Trajectory(["a", "b"], [0])]), classes=CLASSES)
    with pytest.raises(DataError, match="no actions"):
        to_imitation(Demonstrations([Trajectory([0, 1])]), classes=CLASSES)


def test_tuple_entries_are_taken_in_index_order():
    obs = DictObs({f"_index_{i}": np.full((2, 1), float(i)) for i in (10, 2, 0)})
    demos = from_imitation([ImitationTrajectory(obs=obs, acts=np.zeros(1), infos=None, terminal=True)])
    assert demos.metadata["feature_names"] == ["0[0]", "2[0]", "10[0]"]
    np.testing.assert_array_equal(demos[0].states[0], [0.0, 2.0, 10.0])
