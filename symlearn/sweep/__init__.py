"""Experiments at scale: a sweep file (TOML) names a function or a command, a grid of parameters
and seeds; :mod:`~symlearn.sweep.runner` runs every cell once (on Ray, or a local process pool),
retrying crashes and timeouts, and appends one record per finished cell to a results store that
a re-run resumes from; :mod:`~symlearn.sweep.report` aggregates over seeds into tables and plots.

The package sits above the learners (a cell may call anything) and below the CLI; no lower
layer imports it. Importing it loads nothing heavy: Ray, numpy and matplotlib are imported by the
functions that need them.

Modules: ``spec`` (reading a sweep file, the cells), ``cell`` (running one cell, in a worker),
``store`` (the append-only results file and the folder's identity), ``local_pool`` / ``ray_pool``
(the two executors), ``runner`` (scheduling, retries, progress), ``statistics`` (mean, standard
error, bootstrap interval), ``report`` and ``plots``.
"""
