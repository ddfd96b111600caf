"""Driving: highway-env's highway with a continuous action (thesis section 4.4.2, Figure 4.5).

One module per concept: :mod:`~.features` (the 10 features, thesis' highD feature space),
:mod:`~.scene` (highway-env set up for speed; its classes subclass highway-env's and are built
when the first environment is, so importing this package needs no highway-env), :mod:`~.env` (the gymnasium environment, ground-truth
collision / off-road events), :mod:`~.expert` (the IDM/MOBIL demonstrator and its
demonstrations). Needs the ``highway`` extra (``pip install 'symlearn[highway]'``); without it,
building the environment raises :class:`~symlearn.errors.MissingDependencyError`.

Registered as ``symlearn/driving-v0``.
"""

from symlearn.envs.driving.env import DrivingEnv, make_driving
from symlearn.envs.driving.features import FEATURE_NAMES

__all__ = ["FEATURE_NAMES", "DrivingEnv", "make_driving"]
