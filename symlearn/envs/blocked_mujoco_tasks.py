"""The blocked MuJoCo tasks, one row each: robot, wall, reward and episode length.

The rows follow the ICRL benchmark of Liu et al. (2023; its tasks extend Malik et al. 2021's),
which the thesis uses in section 2.5.2, rebuilt on gymnasium's v5 robots. The thesis says which
side each wall blocks and how each robot is paid; the numbers the thesis leaves out (wall
positions, episode lengths, the pendulum's reward) are the benchmark's.

=====================  ==============  ================  ==========================================  =====
task                   robot           forbidden         reward per step                             steps
=====================  ==============  ================  ==========================================  =====
half-cheetah           HalfCheetah-v5  ``x < -3``        v5's with the forward term made ``|.|``     1000
ant                    Ant-v5          ``x < -3``        distance of the torso from the origin +      500
                                                         v5's healthy bonus - control - contact cost
walker2d               Walker2d-v5     ``x < -3``        v5's with the forward term made ``|.|``      500
swimmer                Swimmer-v5      ``x > 0.5``       v5's with the forward term made ``|.|``      500
inverted-pendulum      InvertedPend.   ``x < -0.015``    ``0.1 + 0.9 * clip(-x / 0.01, 0, 1)`` while   100
                       -v5                               upright (1 at ``x <= -0.01``, 0.1 at ``x >= 0``)
=====================  ==============  ================  ==========================================  =====

"Made ``|.|``" keeps every other term of v5's reward (control cost, the walker's healthy
bonus) and pays the speed along ``x`` in either direction, so an agent that ignores the wall
runs through it: each robot's easier direction is the forbidden one (thesis, section 2.5.2).
The ant is paid for its distance from the origin, whichever way it goes (Malik et al.'s
``AntWall``); it does not end its episode when it flips (``terminate_when_unhealthy=False``, as
there), but v5 pays the healthy bonus only while it is healthy. The walker and the pendulum keep
v5's termination (the walker falls, the pole leaves +-0.2 rad); the pendulum's reward is 0 on the
step it falls (v5 pays nothing for that step either).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: the reward of a step from v5's reward, its info and the observation reached
Reward = Callable[[float, Mapping[str, Any], np.ndarray], float]


def speed_either_way(reward: float, info: Mapping[str, Any], obs: np.ndarray) -> float:
    """v5's reward with its forward term ``w * x_velocity`` replaced by ``|w * x_velocity|``."""
    forward = float(info["reward_forward"])
    return float(reward) - forward + abs(forward)


def distance_from_origin(reward: float, info: Mapping[str, Any], obs: np.ndarray) -> float:
    """v5's Ant reward with its forward term replaced by the torso's distance from the origin."""
    return float(reward) - float(info["reward_forward"]) + float(info["distance_from_origin"])


def left_of_start(reward: float, info: Mapping[str, Any], obs: np.ndarray) -> float:
    """The benchmark's biased pendulum: 1 at ``x <= -0.01``, 0.1 at ``x >= 0``, linear between;
    times v5's reward (1 while the pole is upright, 0 on the step it falls)."""
    return float(reward) * (0.1 + 0.9 * min(max(-float(obs[0]) / 0.01, 0.0), 1.0))


@dataclass(frozen=True)
class BlockedTask:
    """One row: ``gym_id`` built with ``robot_kwargs``, forbidden beyond ``wall`` on ``side``
    (``"below"``: ``x < wall``; ``"above"``: ``x > wall``), paid by ``reward``."""

    name: str
    gym_id: str
    wall: float
    side: str
    reward: Reward
    max_episode_steps: int
    robot_kwargs: Mapping[str, Any] = field(default_factory=dict, hash=False)

    def __post_init__(self) -> None:
        if self.side not in ("below", "above"):
            raise ValueError(f"task {self.name!r}: side must be 'below' or 'above', got {self.side!r}")


# Every robot but the pendulum (whose observation is its full state already) keeps its root's
# position in the observation: the constraint is about x, so a learned cost must see it.
_WITH_X = {"exclude_current_positions_from_observation": False}

TASKS: dict[str, BlockedTask] = {t.name: t for t in (
    BlockedTask("half-cheetah", "HalfCheetah-v5", -3.0, "below", speed_either_way, 1000, _WITH_X),
    BlockedTask("ant", "Ant-v5", -3.0, "below", distance_from_origin, 500,
                {**_WITH_X, "terminate_when_unhealthy": False}),
    BlockedTask("walker2d", "Walker2d-v5", -3.0, "below", speed_either_way, 500, _WITH_X),
    BlockedTask("swimmer", "Swimmer-v5", 0.5, "above", speed_either_way, 500, _WITH_X),
    BlockedTask("inverted-pendulum", "InvertedPendulum-v5", -0.015, "below", left_of_start, 100),
)}

#: Malik et al.'s broken ant (``AntWallBroken``) zeroes actions 4-7: in the ant's model these
#: drive hip_2/ankle_2 (front right leg) and hip_3/ankle_3 (back leg): two legs of four.
BROKEN_ANT_ACTUATORS = (4, 5, 6, 7)


__all__ = ["BROKEN_ANT_ACTUATORS", "TASKS", "BlockedTask", "distance_from_origin", "left_of_start",
           "speed_either_way"]
