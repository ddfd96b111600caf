"""The learners of symlearn, found by walking ``symlearn.learners`` (never listed by hand)."""

from __future__ import annotations

import importlib
import inspect
import pkgutil


def learner_classes() -> dict[str, type]:
    """Every public concrete ``Learner`` subclass defined under symlearn.learners, by qualified name."""
    import symlearn.learners as package
    from symlearn.learners.base import Learner

    found: dict[str, type] = {}
    for module_info in pkgutil.walk_packages(package.__path__, "symlearn.learners."):
        if any(part.startswith("_") for part in module_info.name.split(".")):
            continue
        module = importlib.import_module(module_info.name)
        for name, cls in inspect.getmembers(module, inspect.isclass):
            if issubclass(cls, Learner) and cls is not Learner and cls.__module__ == module.__name__ \
                    and not name.startswith("_") and not inspect.isabstract(cls):
                found[f"{cls.__module__}.{name}"] = cls
    return found
