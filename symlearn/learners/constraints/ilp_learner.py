"""Inductive logic programming under the learner contract: an ILP task in, ASP rules out.

``ILPLearner(timeout=30).fit(task)`` runs :func:`symlearn.logic.ilp.learn` (the search itself
lives in the symbolic core, where a task file is all it needs) and keeps the result the way
every learner does: ``hypothesis_``, ``rules_``, ``optimal_``, ``diagnostics_``, ``result_``,
``save(path)`` for the editable ``.lp`` file.

>>> from symlearn.logic.ilp import parse_task
>>> task = parse_task('''
... dir(n; s).
... #modeb(1, go(var(dir))). #modeb(1, blocked(var(dir))).
... #pos(p1, {}, {}, { go(n). blocked(s). }).
... #neg(n1, {}, {}, { go(s). blocked(s). }).
... ''')
>>> ILPLearner(timeout=10).fit(task).rules_
[':- go(V1), blocked(V1).']
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments


class ILPLearner(Learner):
    """``ILPLearner(timeout=30.0, noise=False, method="auto", max_body=None).fit(task)``.

    ``task``: an :class:`~symlearn.logic.ilp.task.ILPTask` or the path of an ILASP-style task
    file. ``noise``: examples with a penalty may stay uncovered at that cost. ``method``: ``auto``,
    ``single`` (one grounding; integrity constraints over single-answer-set contexts) or
    ``general``. On timeout the best hypothesis so far is kept with ``optimal_ = False``.
    """

    artefact_suffix = ".lp"

    def __init__(self, *, timeout: float = 30.0, noise: bool = False, method: str = "auto",
                 max_body: int | None = None) -> None:
        self.timeout = timeout
        self.noise = noise
        self.method = method
        self.max_body = max_body

    @renamed_arguments(task="demonstrations", domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> ILPLearner:
        """Learn from ``demonstrations``, an ILP task (its examples are the data) or the path of a
        ``.las`` file; ``world`` is not used: the task carries its background and bias."""
        from symlearn.logic.ilp import learn, load_task

        task = demonstrations
        if isinstance(task, (str, os.PathLike)):
            task = load_task(Path(task))
        found = learn(task, timeout=self.timeout, noise=self.noise, method=self.method, max_body=self.max_body)
        self.learning_ = found
        self.hypothesis_ = found.hypothesis
        self.rules_ = list(found.hypothesis.rules) if found.hypothesis is not None else []
        self.optimal_ = found.optimal
        self.diagnostics_ = found.diagnostics
        text = ""
        if found.hypothesis is not None:
            text = found.hypothesis.lp_text(f"Rules learned by ILPLearner from {task.source} "
                                            f"(score {found.score}, {'optimal' if found.optimal else 'not proven optimal'}).")
        self._set_result(found.hypothesis, text,
                         metrics={"score": found.score, "optimal": found.optimal, "space_size": found.space_size,
                                  "method": found.method},
                         timings={"total": found.seconds})
        return self


__all__ = ["ILPLearner"]
