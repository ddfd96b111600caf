"""The one learner contract every symlearn learner follows.

* ``__init__`` takes hyper-parameters as keyword arguments and stores them under the same names,
  nothing else (no data, no computation) -- so :meth:`get_params` / :meth:`set_params` /
  ``repr`` work as in scikit-learn, whose ``clone`` and searches accept a learner
  (:class:`~symlearn.learners.parameters.Parametrised` implements that protocol without importing
  scikit-learn, which costs a command ~2 s).
* ``fit(demonstrations, world=None) -> self``, spelt so by every learner (a generic caller may
  pass either by keyword): ``demonstrations`` is what the method learns from (trajectories,
  labelled traces, frames, an ILP task, an LTL sample); ``world`` is what they are read against:
  the world they come from (a :class:`~symlearn.grounding.Domain`, a tabular MDP, an environment
  or a factory of one) or the names of their features or propositions, or None when the data
  carries everything. Old names of these arguments keep working for a while with a warning
  (:mod:`symlearn.learners.fit_arguments`).
* Results live in attributes ending in ``_``. Every learner sets ``result_``, a
  :class:`LearnerResult`: what was learned (``artefact``), its text form, metrics, timings and
  the per-iteration history as dataclasses with ``as_dict()``.
* Reading a result before ``fit`` raises :class:`NotFittedError` (a clear one-line error).
* ``save(path)`` writes the learned artefact in its editable text format (rules ``.lp``,
  formula ``.ltl``, constraint set JSON), atomically.

Hook callbacks (``callback=`` of a learner) receive records; a learner keeps no state between
its own hooks on ``self`` -- a fit builds a local object that carries what the steps share.
"""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass, field, is_dataclass
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import SymlearnError
from symlearn.learners.parameters import Parametrised


class NotFittedError(SymlearnError):
    """A learner's results were asked for before ``fit``."""


def record_dict(record: Any) -> dict[str, Any]:
    """A history record as a JSON-ready dict (its ``as_dict()`` when it has one)."""
    if hasattr(record, "as_dict"):
        return record.as_dict()
    if is_dataclass(record):
        return asdict(record)
    raise TypeError(f"{type(record).__name__} is not a history record")


@dataclass(frozen=True)
class LearnerResult:
    """What one ``fit`` produced, in a form every learner shares."""

    learner: str
    artefact: Any  # the learned object: Hypothesis, Formula, forbidden mask, ...
    text: str  # the artefact in its editable text format ("" when it has none)
    metrics: dict[str, Any] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)  # seconds per stage, "total" always
    history: tuple[Any, ...] = ()  # per-iteration dataclasses
    parameters: dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary (the artefact as its text)."""
        return {"learner": self.learner, "artefact": self.text, "metrics": dict(self.metrics),
                "timings": dict(self.timings), "history": [record_dict(h) for h in self.history],
                "parameters": {k: v for k, v in self.parameters.items() if _jsonable(v)}}


def _jsonable(value: Any) -> bool:
    return value is None or isinstance(value, (bool, int, float, str)) or (
        isinstance(value, (list, tuple)) and all(_jsonable(v) for v in value))


class Learner(Parametrised):
    """Base class of every learner (see the module docstring for the contract)."""

    #: suffix of the file :meth:`save` writes by default (documentation for users and the CLI)
    artefact_suffix = ".txt"

    def fit(self, demonstrations: Any, world: Any = None) -> Learner:  # pragma: no cover - abstract
        raise NotImplementedError

    # --- results --------------------------------------------------------------------------------
    def check_fitted(self) -> None:
        if "result_" not in self.__dict__:
            raise NotFittedError(f"this {type(self).__name__} is not fitted yet; call fit(...) first")

    def artefact_text(self) -> str:
        """The learned artefact as editable text (the format of :meth:`save`)."""
        self.check_fitted()
        return self.result_.text

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the learned artefact in its text format (atomically)."""
        text = self.artefact_text()
        if not text:
            raise SymlearnError(f"{type(self).__name__} learned nothing that can be written",
                                hint="look at result_.metrics for why")
        return write_text(path, text if text.endswith("\n") else text + "\n")

    def _set_result(self, artefact: Any, text: str, *, metrics: dict[str, Any] | None = None,
                    timings: dict[str, float] | None = None, history: Any = ()) -> LearnerResult:
        self.result_ = LearnerResult(type(self).__name__, artefact, text, dict(metrics or {}), dict(timings or {}),
                                     tuple(history), self.get_params(deep=False))
        return self.result_


__all__ = ["Learner", "LearnerResult", "NotFittedError", "record_dict"]
