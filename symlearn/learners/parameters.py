"""scikit-learn's estimator protocol (``get_params`` / ``set_params`` / ``repr``), without importing it.

Importing ``sklearn.base`` costs about two seconds of CPU on our machines (it pulls in scipy.stats
and pandas), and every ``symlearn`` command that touches a learner paid it, also those that never
fit a tree. scikit-learn's own tools (``sklearn.base.clone``, grid searches) work on any object
with these methods, so :class:`Parametrised` implements them the way ``BaseEstimator`` does:
the hyper-parameters are the keyword arguments of ``__init__``, stored under the same names;
``get_params(deep=True)`` also lists a nested estimator's parameters as ``outer__inner``; ``repr``
shows the parameters that differ from their defaults.
"""

from __future__ import annotations

import inspect
from typing import Any

__all__ = ["Parametrised"]


class Parametrised:
    """Hyper-parameters read from and written to the attributes named by ``__init__``."""

    @classmethod
    def _get_param_names(cls) -> list[str]:
        """The keyword parameters of ``__init__``, sorted (scikit-learn's order)."""
        init = cls.__init__
        if init is object.__init__:
            return []
        names = []
        for parameter in inspect.signature(init).parameters.values():
            if parameter.name == "self" or parameter.kind == parameter.VAR_KEYWORD:
                continue
            if parameter.kind == parameter.VAR_POSITIONAL:
                raise TypeError(f"{cls.__name__}.__init__ takes *{parameter.name}: a learner's "
                                "hyper-parameters are keyword arguments")
            names.append(parameter.name)
        return sorted(names)

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The hyper-parameters by name; with ``deep``, a nested estimator's as ``name__param``."""
        params: dict[str, Any] = {}
        for name in self._get_param_names():
            value = getattr(self, name)
            if deep and hasattr(value, "get_params") and not isinstance(value, type):
                params.update((f"{name}__{key}", inner) for key, inner in value.get_params().items())
            params[name] = value
        return params

    def set_params(self, **params: Any) -> Parametrised:
        """Set hyper-parameters (``name__param`` reaches into a nested estimator); returns ``self``."""
        if not params:
            return self
        valid = self.get_params(deep=True)
        nested: dict[str, dict[str, Any]] = {}
        for key, value in params.items():
            name, _, inner = key.partition("__")
            if name not in valid:
                raise ValueError(f"invalid parameter {name!r} for {type(self).__name__}; "
                                 f"valid parameters: {sorted(self._get_param_names())}")
            if inner:
                nested.setdefault(name, {})[inner] = value
            else:
                setattr(self, name, value)
                valid[name] = value
        for name, inner_params in nested.items():
            valid[name].set_params(**inner_params)
        return self

    def __repr__(self) -> str:
        defaults = {name: parameter.default for name, parameter in
                    inspect.signature(type(self).__init__).parameters.items()}
        shown = [f"{name}={value!r}" for name, value in self.get_params(deep=False).items()
                 if not _same(value, defaults.get(name, inspect.Parameter.empty))]
        return f"{type(self).__name__}({', '.join(shown)})"


def _same(value: Any, default: Any) -> bool:
    """Whether a parameter still has its default (arrays and odd ``__eq__`` compare by repr)."""
    if value is default:
        return True
    if type(value) is not type(default):
        return False
    try:
        equal = value == default
        if isinstance(equal, bool):
            return equal
    except Exception:  # an __eq__ that refuses the comparison: fall back to the repr
        pass
    return repr(value) == repr(default)
