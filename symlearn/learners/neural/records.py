"""The base of the neural learners' per-iteration history records."""

from __future__ import annotations

import math
from dataclasses import asdict
from typing import Any


class IterationRecord:
    """Mixin for a (frozen) dataclass of one iteration: ``as_dict()`` with NaN as null (JSON has no
    NaN, and a quantity not measured in an iteration is NaN in the record)."""

    def as_dict(self) -> dict[str, Any]:
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}


__all__ = ["IterationRecord"]
