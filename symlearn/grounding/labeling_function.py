"""Labelings a user brings for their own environment, and the ``(observation, info)`` contract.

A labeling of a gymnasium environment is asked, at every step, which propositions hold; it is
given the step's observation and its ``info`` dict (what ``reset``/``step`` returned), and
answers with a set of proposition names. Three forms are read from a file
(:func:`read_labeling`, the CLI's ``--labeling``):

* a saved :class:`~symlearn.grounding.labeling.Labeling` table (``"symlearn": "labeling"``
  JSON): looks the observation up (discrete observations);
* a *feature labeling*: a plain JSON object ``{"near_goal": "x > 0.8 & y > 0.8"}`` mapping each
  proposition to a condition over the observation's named features (the names come from the
  environment's ``feature_names``, ``info["features"]`` or ``--features``), or a saved
  :class:`~symlearn.grounding.feature_labeling.FeatureLabeling`;
* a Python function ``FILE.py:function`` called as ``function(observation, info)`` and
  returning an iterable of proposition names (:class:`FunctionLabeling`). A function with a
  third parameter also gets the (unwrapped) environment, for what neither the observation nor
  ``info`` shows (MiniGrid's partial view hides the cell the agent stands on); such a function
  cannot label stored states afterwards, so demonstrations must be labelled while recorded.

The function's *declared* propositions are, in this order of precedence, its ``propositions``
attribute or the module's ``PROPOSITIONS`` list; then any other name it returns is an error.
When it declares none, the propositions are discovered: every name it returns becomes one, in
the order first seen (a typo then silently becomes a proposition, which is why declaring is
recommended). Loading the file runs it: that is what the user asked for by naming it.

Every mistake is one :class:`~symlearn.errors.DataError` line: file missing, the module raising
on import (its own error named), the function missing or not callable, the function raising
(the step named by the caller), returning something that is not a collection of strings, or a
name it did not declare.

>>> lab = FunctionLabeling(lambda obs, info: {"high"} if obs > 2 else (), ["high"])
>>> sorted(lab(3, {})), sorted(lab(1, {}))
(['high'], [])
"""

from __future__ import annotations

import importlib.util
import inspect
import itertools
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from symlearn.errors import DataError, ParseError, UnknownNameError
from symlearn.grounding.labeling import LabelingBase

__all__ = ["FunctionLabeling", "as_observation_labeler", "load_labeling_function", "read_labeling"]


class FunctionLabeling(LabelingBase):
    """``function(observation, info) -> names`` with declared (or discovered) propositions.

    ``propositions=None`` discovers them from what the function returns (see module docstring).
    ``name`` (e.g. ``labels.py:label``) is how errors refer to the function.
    """

    def __init__(self, function: Callable[[Any, Mapping[str, Any]], Iterable[str]],
                 propositions: Iterable[str] | None = None, *, meanings: Mapping[str, str] | None = None,
                 name: str | None = None, path: str | None = None) -> None:
        if not callable(function):
            raise DataError(f"{name or function!r} is not callable")
        from symlearn.data.recording import labeler_arity

        self.function = function
        self.arity = labeler_arity(function)
        self.name = name or getattr(function, "__name__", "labeling function")
        self.path = path  # the file it came from: errors name it (and the line that raised)
        self.declared = propositions is not None
        props = [] if propositions is None else list(propositions)
        for p in props:
            if not isinstance(p, str) or not p:
                raise DataError(f"{self.name}: declared proposition {p!r} is not a non-empty string")
        self._props = list(dict.fromkeys(props))
        self._given_meanings = dict(meanings or {})

    @property
    def propositions(self) -> tuple[str, ...]:
        return tuple(self._props)

    @property
    def meanings(self) -> dict[str, str]:
        return {p: self._given_meanings.get(p, "") for p in self._props}

    def label(self, state: Any, info: Mapping[str, Any] | None = None, where: str = "", env: Any = None
              ) -> frozenset[str]:
        """The propositions true at ``state``; ``where`` ("episode 3, step 7") locates errors;
        ``env`` is passed to a function taking a third parameter."""
        at = f" ({where})" if where else ""
        if self.arity == 3 and env is None:
            raise DataError(f"labeling function {self.name} needs the environment (its third parameter), which "
                            f"is not at hand{at}", hint="label the demonstrations while recording them: "
                                                        "symlearn.data.record(env, policy, n, labeler=...)")
        arguments = (state, {} if info is None else info, env)[:self.arity]
        try:
            found = self.function(*arguments)
        except Exception as exc:  # the user's code: any error it raises is reported, named
            raise DataError(f"labeling function {self.name} raised {type(exc).__name__}: {exc}{at}", file=self.path,
                            line=_line_in(exc, self.path)) from None
        if isinstance(found, (str, bytes)) or not isinstance(found, Iterable):
            raise DataError(f"labeling function {self.name} returned {type(found).__name__} {found!r}{at}; "
                            f"it must return a list or set of proposition names", file=self.path)
        names = list(itertools.islice(found, MAX_NAMES + 1))  # a generator may never end
        if len(names) > MAX_NAMES:
            raise DataError(f"labeling function {self.name} returned more than {MAX_NAMES:,} names{at}",
                            file=self.path, hint="return the propositions true in this state (a list or set)")
        odd = [n for n in names if not isinstance(n, str) or not n]
        if odd:
            raise DataError(f"labeling function {self.name} returned {type(odd[0]).__name__} {odd[0]!r}{at}, which "
                            f"is not a proposition name (a non-empty string)", file=self.path)
        if self.declared:
            unknown = [n for n in names if n not in self._props]
            if unknown:
                raise DataError(f"labeling function {self.name} returned unknown proposition {unknown[0]!r}{at}",
                                file=self.path,
                                hint="declared: " + (", ".join(self._props) or "none") +
                                     " (PROPOSITIONS in the module or the function's propositions attribute)")
        else:
            known = self._known = getattr(self, "_known", None) or set(self._props)  # a list scan per name was quadratic
            for n in names:
                if n not in known:
                    if len(known) >= MAX_NAMES:
                        raise DataError(f"labeling function {self.name} returned more than {MAX_NAMES:,} different "
                                        f"names{at}", file=self.path,
                                        hint="declare the propositions (PROPOSITIONS) and return only those")
                    known.add(n)
                    self._props.append(n)
        return frozenset(names)

    def __call__(self, state: Any, info: Mapping[str, Any] | None = None, env: Any = None) -> frozenset[str]:
        return self.label(state, info, env=env)

    def __repr__(self) -> str:
        return f"FunctionLabeling({self.name}: {', '.join(self._props) or 'propositions discovered'})"


#: names one call of a labeling function may return, and propositions it may discover in all: a
#: generator that never ends, or a million names a step (discovered one by one), would otherwise
#: exhaust the memory or the time before any learning starts
MAX_NAMES = 10_000


def load_labeling_function(spec: str) -> FunctionLabeling:
    """``"path/to/file.py:function"`` -> :class:`FunctionLabeling` (imports the file)."""
    path_text, sep, attr = spec.rpartition(":")
    if not sep or not path_text.endswith(".py") or not attr:
        raise DataError(f"{spec!r} is not FILE.py:function", hint="e.g. --labeling labels.py:label")
    path = Path(path_text)
    if not path.is_file():
        raise DataError(f"labeling module {path_text} does not exist" if not path.exists()
                        else f"labeling module {path_text} is not a file")
    module_name = "symlearn_user_labeling_" + "".join(c if c.isalnum() else "_" for c in str(path.resolve()))
    module_spec = importlib.util.spec_from_file_location(module_name, path)
    if module_spec is None or module_spec.loader is None:
        raise DataError(f"{path_text} cannot be imported as a Python module")
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[module_name] = module  # dataclasses and pickling-free helpers look themselves up here
    try:
        module_spec.loader.exec_module(module)
    except SyntaxError as exc:
        sys.modules.pop(module_name, None)
        raise DataError(f"labeling module has a syntax error: {exc.msg}", file=path_text, line=exc.lineno,
                        column=exc.offset) from None
    except Exception as exc:  # the user's module: whatever it raises on import is reported, named
        sys.modules.pop(module_name, None)
        raise DataError(f"importing labeling module {path_text} raised {type(exc).__name__}: {exc}") from None
    function = getattr(module, attr, None)
    if function is None:
        defined = sorted(n for n, v in vars(module).items() if inspect.isfunction(v) and not n.startswith("_")
                         and getattr(v, "__module__", None) == module_name)
        raise UnknownNameError(f"{path_text} defines no function {attr!r}",
                               hint="functions there: " + (", ".join(defined) or "none"))
    if not callable(function):
        raise DataError(f"{path_text}:{attr} is a {type(function).__name__}, not a function")
    declared = getattr(function, "propositions", None)
    if declared is None:
        declared = getattr(module, "PROPOSITIONS", None)
    if declared is not None and (isinstance(declared, (str, bytes)) or not isinstance(declared, Iterable)):
        raise DataError(f"the declared propositions must be a list of names, got {declared!r}", file=path_text)
    meanings = getattr(module, "MEANINGS", None)
    return FunctionLabeling(function, None if declared is None else list(declared),
                            meanings=meanings if isinstance(meanings, Mapping) else None, name=attr, path=path_text)


def _line_in(exc: BaseException, path: str | None) -> int | None:
    """The line of ``path`` where ``exc`` was raised (the innermost frame in that file)."""
    if path is None:
        return None
    target, line = str(Path(path).resolve()), None
    tb = exc.__traceback__
    while tb is not None:
        if str(Path(tb.tb_frame.f_code.co_filename).resolve()) == target:
            line = tb.tb_lineno
        tb = tb.tb_next
    return line


def read_labeling(spec: str, *, feature_names: Sequence[str] | None = None,
                  names_hint: str = "give --features a,b,... or an environment with a feature_names attribute"):
    """A labeling from ``--labeling``: ``FILE.py:function``, a saved labeling JSON (table or
    features), or a plain JSON object ``{proposition: condition}`` over ``feature_names`` (in a
    file, or the object itself as the argument); ``names_hint`` says where names come from when
    there are none."""
    if ".py:" in spec or spec.endswith(".py"):
        return load_labeling_function(spec)
    from symlearn.grounding.labeling import load_labeling_text
    from symlearn.input_limits import load_json, read_input_text

    path = Path(spec)
    if spec.lstrip().startswith("{") and not path.exists():
        # the JSON object itself: --labeling '{"near_goal": "x > 0.8 & y > 0.8"}' (README)
        from symlearn.json_document import load_option_json

        text, spec = spec, "--labeling"
        doc = load_option_json(text, spec)
    else:
        try:
            text = read_input_text(path, what="labeling file")
        except OSError as exc:
            raise DataError(f"cannot read the labeling: {exc.strerror}", file=spec) from None
        # syntax, nesting, duplicate keys, huge integers and lone surrogates refused with their place
        doc = load_json(text, source=spec, error=DataError, syntax="the labeling is not JSON")
    if isinstance(doc, dict) and "symlearn" in doc:
        return load_labeling_text(text, source=spec)
    if not isinstance(doc, dict) or not doc or not all(isinstance(v, str) for v in doc.values()):
        raise DataError("a labeling file is a saved labeling or a JSON object {proposition: condition}", file=spec,
                        hint='e.g. {"near_goal": "x > 0.8 & y > 0.8"}')
    if not feature_names:
        raise DataError("this feature labeling needs the observation's feature names", file=spec, hint=names_hint)
    from symlearn.grounding.feature_labeling import FeatureLabeling

    try:
        return FeatureLabeling(list(feature_names), doc)
    except (DataError, ParseError) as exc:   # the column, where there is one, is the condition's (in the message)
        raise type(exc)(exc.message, file=spec, hint=exc.hint) from None


def as_observation_labeler(labeling: Any) -> Callable[..., frozenset[str]]:
    """Any labeling as ``f(observation, info, where="", env=None) -> frozenset``: a
    :class:`FunctionLabeling` gets what its function takes; a table or feature labeling reads
    the observation only."""
    if isinstance(labeling, FunctionLabeling):
        return labeling.label
    if isinstance(labeling, LabelingBase):
        def label(observation: Any, info: Mapping[str, Any] | None = None, where: str = "", env: Any = None
                  ) -> frozenset[str]:
            try:
                return labeling.label(observation)
            except DataError as exc:
                at = f" ({where})" if where else ""
                raise type(exc)(exc.message + at, file=exc.file, hint=exc.hint) from None
        return label
    if callable(labeling):
        return FunctionLabeling(labeling, None, name=getattr(labeling, "__name__", None)).label
    raise DataError(f"{labeling!r} is not a labeling", hint="a Labeling, FeatureLabeling or function(observation, info)")
