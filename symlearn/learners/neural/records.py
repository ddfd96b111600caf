"""The base of the neural learners' per-iteration history records."""

from __future__ import annotations

import math
from dataclasses import asdict
from typing import Any


class IterationRecord:
    """Mixin for a (frozen) dataclass of one iteration: ``as_dict()`` with NaN as null (JSON has no
    NaN, and a quantity not measured in an iteration is NaN in the record), and ``bar_numbers()``,
    what the learner's progress bar shows of the iteration."""

    def as_dict(self) -> dict[str, Any]:
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}

    def bar_numbers(self) -> dict[str, float]:
        """The sampled policy's return and true violation rate (every neural learner's record has
        ``reward`` and ``violation_rate``); a record with a multiplier adds it as ``lambda``."""
        return {"return": getattr(self, "reward"), "violation": getattr(self, "violation_rate")}


__all__ = ["IterationRecord"]
