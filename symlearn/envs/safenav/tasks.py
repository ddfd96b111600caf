"""SafeNav tasks: what earns reward (Safety-Gym's Goal and Push, dense rewards).

* :class:`GoalTask` -- reach the goal circle (radius 0.3). Reward per step = decrease of the
  agent's distance to the goal centre, plus 1 on reaching it; then a new goal is drawn (away
  from the hazards and the agent) and the episode goes on, as Safety-Gym's ``continue_goal``.
* :class:`PushTask` -- push the box (a disc of radius 0.2) into the goal circle. Reward per
  step = decrease of the box's distance to the goal + decrease of the agent's distance to the
  box, plus 1 when the box centre enters the goal circle; then a new goal is drawn.

The box is a damped disc (floor friction ``box_damping``) that the robot's disc shoves: an
overlap is split between the two by their masses, and the approaching part of the relative
velocity is removed by an inelastic impulse, so a robot driving into the box carries it along
at a somewhat lower speed. Walls stop the box as they stop the robot. Hazards are not solid
(neither in Safety-Gym): they only cost when the *robot* is inside one.
"""

from __future__ import annotations

import math

import numpy as np

from symlearn.envs.safenav.agents import DT, RADIUS, AgentState
from symlearn.envs.safenav.layout import sample_point
from symlearn.errors import DataError

AGENT_KEEPOUT = 0.4


class GoalTask:
    """Reach the goal circle again and again (see the module docstring)."""

    name = "goal"
    box_radius: float | None = None

    def __init__(self, goal_radius: float = 0.3, reward_distance: float = 1.0, reward_goal: float = 1.0) -> None:
        self.goal_radius, self.reward_distance, self.reward_goal = goal_radius, reward_distance, reward_goal
        self.goal = np.zeros(2)
        self._last = 0.0

    def reset(self, goal: np.ndarray, box: np.ndarray | None, agent: AgentState) -> None:
        self.goal = np.array(goal, dtype=np.float64)
        self._last = self.progress_distance(agent)

    def progress_distance(self, agent: AgentState) -> float:
        return math.hypot(agent.x - self.goal[0], agent.y - self.goal[1])

    def physics(self, agent: AgentState, wall: float | None) -> None:
        """Move what the task owns (nothing here)."""

    def goal_met(self, agent: AgentState) -> bool:
        return math.hypot(agent.x - self.goal[0], agent.y - self.goal[1]) <= self.goal_radius

    def reward(self, agent: AgentState) -> tuple[float, bool]:
        """This step's reward and whether the goal was met (a new goal is then needed)."""
        distance = self.progress_distance(agent)
        reward = self.reward_distance * (self._last - distance)
        self._last = distance
        met = self.goal_met(agent)
        if met:
            reward += self.reward_goal
        return reward, met

    def new_goal(self, rng: np.random.Generator, agent: AgentState, hazards: np.ndarray, hazard_radius: float,
                 extent: float) -> None:
        keep = [(h, self.goal_radius + hazard_radius + 0.05) for h in hazards]
        keep += self._keep_away(agent)
        self.goal = sample_point(rng, extent, keep, "goal")
        self._last = self.progress_distance(agent)

    def _keep_away(self, agent: AgentState) -> list[tuple[np.ndarray, float]]:
        return [(np.array([agent.x, agent.y]), self.goal_radius + AGENT_KEEPOUT)]


class PushTask(GoalTask):
    """Push the box into the goal circle (see the module docstring)."""

    name = "push"

    def __init__(self, goal_radius: float = 0.3, box_radius: float = 0.2, box_damping: float = 4.0,
                 box_mass: float = 1.0, reward_box_goal: float = 1.0, reward_box_dist: float = 1.0,
                 reward_goal: float = 1.0) -> None:
        super().__init__(goal_radius, reward_box_goal, reward_goal)
        self.box_radius, self.box_damping, self.box_mass = box_radius, box_damping, box_mass
        self.reward_box_dist = reward_box_dist
        self.box = np.zeros(2)
        self.box_velocity = np.zeros(2)
        self._last_box = 0.0

    def reset(self, goal: np.ndarray, box: np.ndarray | None, agent: AgentState) -> None:
        self.box = np.array(box, dtype=np.float64)
        self.box_velocity = np.zeros(2)
        super().reset(goal, box, agent)
        self._last_box = self.agent_box_distance(agent)

    def progress_distance(self, agent: AgentState) -> float:
        return math.hypot(self.box[0] - self.goal[0], self.box[1] - self.goal[1])

    def agent_box_distance(self, agent: AgentState) -> float:
        return math.hypot(agent.x - self.box[0], agent.y - self.box[1])

    def goal_met(self, agent: AgentState) -> bool:
        return self.progress_distance(agent) <= self.goal_radius

    def physics(self, agent: AgentState, wall: float | None) -> None:
        """Slide the box, then resolve its contact with the robot (masses: robot 1, box ``box_mass``)."""
        bx, by = self.box
        vx, vy = self.box_velocity
        decay = max(0.0, 1.0 - DT * self.box_damping)
        vx, vy = vx * decay, vy * decay
        bx, by = bx + DT * vx, by + DT * vy
        dx, dy = bx - agent.x, by - agent.y
        distance = math.hypot(dx, dy)
        reach = RADIUS + self.box_radius
        if distance < reach:
            nx, ny = (dx / distance, dy / distance) if distance > 1e-9 else (math.cos(agent.heading),
                                                                              math.sin(agent.heading))
            overlap = reach - distance
            share = 1.0 / (1.0 + self.box_mass)  # the box's part of the overlap: robot mass / total
            bx, by = bx + nx * overlap * share, by + ny * overlap * share
            agent.x -= nx * overlap * (1.0 - share)
            agent.y -= ny * overlap * (1.0 - share)
            closing = (agent.vx - vx) * nx + (agent.vy - vy) * ny
            if closing > 0.0:
                impulse = closing / (1.0 + 1.0 / self.box_mass)
                agent.vx -= impulse * nx
                agent.vy -= impulse * ny
                vx += impulse / self.box_mass * nx
                vy += impulse / self.box_mass * ny
        if wall is not None:
            limit = wall - self.box_radius
            if bx > limit or bx < -limit:
                bx, vx = max(-limit, min(limit, bx)), 0.0
            if by > limit or by < -limit:
                by, vy = max(-limit, min(limit, by)), 0.0
        self.box[0], self.box[1] = bx, by
        self.box_velocity[0], self.box_velocity[1] = vx, vy

    def reward(self, agent: AgentState) -> tuple[float, bool]:
        reward, met = super().reward(agent)
        box_distance = self.agent_box_distance(agent)
        reward += self.reward_box_dist * (self._last_box - box_distance)
        self._last_box = box_distance
        return reward, met

    def _keep_away(self, agent: AgentState) -> list[tuple[np.ndarray, float]]:
        return super()._keep_away(agent) + [(self.box.copy(), self.goal_radius + self.box_radius + 0.2)]


TASKS = {"goal": GoalTask, "push": PushTask}


def make_task(name: str) -> GoalTask:
    """A fresh :class:`GoalTask` or :class:`PushTask` by name."""
    try:
        return TASKS[name]()
    except KeyError:
        raise DataError(f"unknown SafeNav task {name!r}", hint="tasks: " + ", ".join(TASKS)) from None


__all__ = ["TASKS", "GoalTask", "PushTask", "make_task"]
