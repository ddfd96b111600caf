"""The two constraints of the thesis' realistic traffic experiment (section 2.5.3), on our highway.

The thesis learns neural costs on Liu et al.'s highD scenarios in CommonRoad-RL, one with a
*minimum distance* between the ego and other vehicles and one with a *maximum velocity*. highD
needs a licence and CommonRoad-RL does not install here, so :class:`~symlearn.envs.driving.env.DrivingEnv`
re-creates both on highway-env's highway (``DrivingEnv(constraint="velocity" | "distance")``):

* ``velocity``: the ego's speed along the road ``v_x`` must not exceed ``bound`` m/s (default
  :data:`DEFAULT_BOUNDS` 20). The reward pays progress up to the 30 m/s speed limit and the
  traffic drives at about 23-28 m/s, so an agent that ignores the cap keeps up with it. (A cap of
  25 did not bind: measured, PPO without the constraint learns to drive at about 20 m/s on the
  crowded highway, where speeding up ends in rear-ending a slower car.) highway-env starts the
  ego at 25 m/s; this task starts it at the cap. With the start above the cap every episode paid
  the cost for its first second whatever the driver did, and PPO-Lagrangian on the true cost
  (limit 0) learned to end its episodes by crashing within three steps (return 1.6 against the
  demonstrator's 83; measured, ``benchmarks/results/icrl_driving_velocity20_start25.json``): a cost no
  policy can avoid makes an early end the cheapest policy.
* ``distance``: the bumper gap to the vehicle ahead in the ego's own lane (``lead_same``) must be
  at least ``bound`` metres (default 10). The thesis says neither value; these are our choice:
  a cap below the traffic's speed, and a gap IDM's own spacing (5 m standstill + 1.5 s
  headway) keeps at highway speeds but a car closing in on a slower one crosses.

With a constraint the environment's ``info["cost"]`` is that constraint (1 on a violating step),
not the collision / off-road cost of the DNF experiment; collisions and leaving the road still end
the episode and stay reported as ``info["collision"]`` / ``info["offroad"]``. The thesis notes that
its traffic constraints were sometimes violated in the very first state, so no agent reaches
zero cost; here a car cutting in ahead can break the distance rule for the demonstrator too.
"""

from __future__ import annotations

import numpy as np

from symlearn.envs.driving.features import FEATURE_NAMES
from symlearn.errors import DataError

#: the feature each constraint reads, and whether it bounds it from above
FEATURE = {"velocity": "v_x", "distance": "lead_same"}
UPPER = {"velocity": True, "distance": False}
DEFAULT_BOUNDS = {"velocity": 20.0, "distance": 10.0}


def check(constraint: str | None, bound: float | None) -> float | None:
    """The bound ``constraint`` uses (its default where ``bound`` is None); None without one."""
    if constraint is None:
        if bound is not None:
            raise DataError("a constraint bound needs a constraint", hint="constraint='velocity' or 'distance'")
        return None
    if constraint not in FEATURE:
        raise DataError(f"unknown traffic constraint {constraint!r}", hint="velocity or distance")
    value = DEFAULT_BOUNDS[constraint] if bound is None else float(bound)
    if not np.isfinite(value) or value <= 0:
        raise DataError(f"the {constraint} bound must be a positive number, got {bound!r}")
    return value


def violated(constraint: str, bound: float, features: np.ndarray) -> np.ndarray | bool:
    """Whether feature rows (physical units, :data:`FEATURE_NAMES` order) break the constraint."""
    value = np.asarray(features, dtype=np.float64)[..., FEATURE_NAMES.index(FEATURE[constraint])]
    return value > bound if UPPER[constraint] else value < bound


def violated_observations(constraint: str, bound: float, observations: np.ndarray,
                          scales: np.ndarray) -> np.ndarray | bool:
    """:func:`violated` of policy observations (the features divided by ``scales``)."""
    column = FEATURE_NAMES.index(FEATURE[constraint])
    value = np.asarray(observations, dtype=np.float64)[..., column] * scales[column]
    return value > bound if UPPER[constraint] else value < bound


__all__ = ["DEFAULT_BOUNDS", "FEATURE", "check", "violated", "violated_observations"]
