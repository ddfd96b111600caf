"""Benchmark domains and environments, each with its ground-truth rules.

Light on purpose: importing ``symlearn.envs`` loads no gymnasium. The finite domain models
(:mod:`~symlearn.envs.hanoi_model`, :mod:`~symlearn.envs.traffic_model`) render state-action
pairs as ASP facts; :mod:`~symlearn.envs.logic_domains` ties them to their background
knowledge in ``background_kb/``; :mod:`~symlearn.envs.ilp_tasks` writes ILP task files.
"""
