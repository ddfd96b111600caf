"""Benchmark domains and environments, each with its ground-truth rules.

Light on purpose: importing ``symlearn.envs`` loads no gymnasium. The finite domain models
(:mod:`~symlearn.envs.hanoi_model`, :mod:`~symlearn.envs.traffic_model`) render state-action
pairs as ASP facts; :mod:`~symlearn.envs.logic_domains` ties them to their background
knowledge in ``background_kb/``; :mod:`~symlearn.envs.ilp_tasks` writes ILP task files.

:mod:`~symlearn.envs.registry` lists every bundled environment, domain and task once. Importing
this package registers the gymnasium environments among them as ``symlearn/<name>-v0`` (now if
gymnasium is loaded, else as soon as it is; see :mod:`~symlearn.envs.gym_registration`).
"""

from symlearn.envs.gym_registration import register_when_gymnasium_loads as _register

_register()
