"""The two SafeNav robots: planar kinematics and damped dynamics in plain Python floats.

Both re-create Safety-Gym's robots (``xmls/point.xml``, ``xmls/car.xml``) closely enough for
constraint learning, not MuJoCo-exactly: a step is ``dt = 0.02`` s (MuJoCo's 0.002 s times
Safety-Gym's 10 sub-steps), every action entry is clipped to ``[-1, 1]``, and motion is
integrated with semi-implicit Euler.

* :class:`Point` -- a disc on the plane with two actuators: a **forward force** along its
  heading (action 0) and a **rotation** velocity (action 1). Its velocity lives in the world
  frame and is only damped, so after a turn it keeps sliding sideways for a moment (as the
  Safety-Gym point does on its free x/y joints):
  ``v += dt * (force * a0 * heading - damping * v)``, ``omega = turn_rate * a1``,
  ``heading += dt * omega``.
* :class:`Car` -- **two independently driven parallel wheels** (action 0 = left, action 1 =
  right wheel) and a free rear wheel: a differential drive. The mean of the wheel commands
  drives forward, their difference turns; tyres kill sideways sliding:
  ``u += dt * (force * (aL + aR) / 2 - damping * u)``,
  ``omega += dt * (torque * (aR - aL) / 2 - turn_damping * omega)``,
  ``w += dt * (-lateral_damping * w)`` (``u``, ``w`` = forward / sideways body speed).
  Turning and driving therefore need the two wheels to cooperate.

Both reach about 1 m/s at full throttle and turn at about 3 rad/s. A step returns the
acceleration of the robot's own motion: the change of the world velocity over the step, in the
body frame at the new heading (so a turn at constant speed reads a centripetal ``a_y``); the
environment's accelerometer also counts what walls and the push box do to the velocity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from symlearn.errors import DataError

DT = 0.02
RADIUS = 0.1  # both robots collide with walls and the push box as a disc of this radius


@dataclass(slots=True)
class AgentState:
    """Pose and motion of a robot: world position, heading (rad), world velocity, yaw rate."""

    x: float = 0.0
    y: float = 0.0
    heading: float = 0.0
    vx: float = 0.0
    vy: float = 0.0
    yaw_rate: float = 0.0

    def body_velocity(self) -> tuple[float, float]:
        """Velocity in the robot frame: (forward, leftward) -- Safety-Gym's velocimeter."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        return c * self.vx + s * self.vy, -s * self.vx + c * self.vy


def _clip(value: float) -> float:
    return -1.0 if value < -1.0 else 1.0 if value > 1.0 else float(value)


class Point:
    """Rotation + forward force with damping (see the module docstring)."""

    name = "point"
    action_names = ("forward", "turn")

    def __init__(self, force: float = 5.0, damping: float = 5.0, turn_rate: float = 3.0, dt: float = DT) -> None:
        self.force, self.damping, self.turn_rate, self.dt = force, damping, turn_rate, dt

    def step(self, state: AgentState, action) -> tuple[float, float]:
        """Advance ``state`` in place by one step; returns the body-frame acceleration."""
        forward, turn = _clip(action[0]), _clip(action[1])
        dt = self.dt
        state.yaw_rate = self.turn_rate * turn
        state.heading = (state.heading + dt * state.yaw_rate) % (2 * math.pi)
        c, s = math.cos(state.heading), math.sin(state.heading)
        ax = self.force * forward * c - self.damping * state.vx
        ay = self.force * forward * s - self.damping * state.vy
        state.vx += dt * ax
        state.vy += dt * ay
        state.x += dt * state.vx
        state.y += dt * state.vy
        return c * ax + s * ay, -s * ax + c * ay


class Car:
    """Differential drive: two independently driven wheels (see the module docstring)."""

    name = "car"
    action_names = ("left_wheel", "right_wheel")

    def __init__(self, force: float = 4.0, damping: float = 4.0, torque: float = 12.0, turn_damping: float = 4.0,
                 lateral_damping: float = 20.0, dt: float = DT) -> None:
        self.force, self.damping, self.torque, self.turn_damping = force, damping, torque, turn_damping
        self.lateral_damping, self.dt = lateral_damping, dt

    def step(self, state: AgentState, action) -> tuple[float, float]:
        """Advance ``state`` in place by one step; returns the body-frame acceleration."""
        left, right = _clip(action[0]), _clip(action[1])
        dt = self.dt
        old_vx, old_vy = state.vx, state.vy
        u, w = state.body_velocity()
        u += dt * (self.force * 0.5 * (left + right) - self.damping * u)
        w -= dt * self.lateral_damping * w
        state.yaw_rate += dt * (self.torque * 0.5 * (right - left) - self.turn_damping * state.yaw_rate)
        state.heading = (state.heading + dt * state.yaw_rate) % (2 * math.pi)
        c, s = math.cos(state.heading), math.sin(state.heading)
        state.vx, state.vy = c * u - s * w, s * u + c * w  # the velocity turns with the car
        state.x += dt * state.vx
        state.y += dt * state.vy
        ax, ay = (state.vx - old_vx) / dt, (state.vy - old_vy) / dt
        return c * ax + s * ay, -s * ax + c * ay


AGENTS = {"point": Point, "car": Car}


def make_agent(name: str):
    """A fresh :class:`Point` or :class:`Car` by name."""
    try:
        return AGENTS[name]()
    except KeyError:
        raise DataError(f"unknown SafeNav agent {name!r}", hint="agents: " + ", ".join(AGENTS)) from None


__all__ = ["AGENTS", "DT", "RADIUS", "AgentState", "Car", "Point", "make_agent"]
