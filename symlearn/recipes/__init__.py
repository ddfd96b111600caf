"""The glue the entry points share (``cli``, ``demo``, ``benchmarks``): resolve an environment
(a bundled name, a gymnasium id or ``module:EnvId``) with its kwargs, expert and features, and
join it to a learner and a backend.

This floor sits between the entry points and ``learners`` / ``envs`` / ``backends``: it may
import all three (which none of them may do with each other), and nothing below imports it.
Modules are imported by their full names (``symlearn.recipes.environments``); this package
imports nothing itself, so ``import symlearn.recipes`` stays free.
"""
