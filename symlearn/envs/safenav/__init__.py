"""SafeNav: Safety-Gym's Point and Car robots x Goal and Push tasks, re-created in numpy.

One module per concept: :mod:`~.agents` (robot dynamics), :mod:`~.tasks` (reward, goal, push
box), :mod:`~.layout` (random hazards), :mod:`~.lidar` (Safety-Gym's pseudo-lidar),
:mod:`~.observation` (observation layout, the thesis' 20 features), :mod:`~.render` (numpy
picture) and :mod:`~.env` (the gymnasium environment). The scripted expert lives in
:mod:`symlearn.envs.safenav_expert`.

Registered as ``symlearn/safenav-{point,car}-{goal,push}-v0``.
"""

from symlearn.envs.safenav.env import DEFAULT_MAX_STEPS, FEATURE_NAMES, SafeNavEnv, make_safenav

__all__ = ["DEFAULT_MAX_STEPS", "FEATURE_NAMES", "SafeNavEnv", "make_safenav"]
