"""The names ``fit`` arguments had before the contract settled on ``fit(demonstrations, world=None)``.

Every learner's ``fit`` spells its arguments alike, so a generic caller (a pipeline, a sweep
cell, the contract test) can pass them by keyword to any learner. Some learners called them
otherwise (``domain=``, ``features=``, ``propositions=``, ``task=``, ``sample=``) and users may
have passed those keywords, so :func:`renamed_arguments` keeps the old keyword working with a
``FutureWarning`` (shown by default, unlike ``DeprecationWarning``) that names the new one.

>>> import warnings
>>> class Example:
...     @renamed_arguments(domain="world")
...     def fit(self, demonstrations, world=None):
...         return world
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     Example().fit([], domain="d")
'd'
>>> print(caught[0].message)
Example.fit(domain=...) is deprecated and will be removed: pass world=... (or the value by position)
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

#: ``stacklevel`` of a warning that ``fit`` itself raises, so that it names ``fit``'s caller: the
#: wrapper below is one more frame between them
FIT_CALLER = 3


def renamed_arguments(**old_to_new: str) -> Callable[[F], F]:
    """Decorate a ``fit`` so that each old keyword reaches the argument it was renamed to."""

    def decorate(fit: F) -> F:
        @functools.wraps(fit)
        def wrapper(self: Any, *args: Any, **kwargs: Any) -> Any:
            for old, new in old_to_new.items():
                if old not in kwargs:
                    continue
                if new in kwargs:
                    raise TypeError(f"{type(self).__name__}.fit() got both {old}= and {new}=; pass {new}= only")
                warnings.warn(f"{type(self).__name__}.fit({old}=...) is deprecated and will be removed: pass "
                              f"{new}=... (or the value by position)", FutureWarning, stacklevel=2)
                kwargs[new] = kwargs.pop(old)
            return fit(self, *args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate


__all__ = ["FIT_CALLER", "renamed_arguments"]
