"""Numeric command-line values checked before anything is built.

Count flags are read by argparse as floats, so that ``--steps 1e20`` or ``--episodes 2.5`` reach
one clear message here instead of argparse's usage error (or an allocation sized from them)."""

from __future__ import annotations

import math


def whole(flag: str, value: float, low: int, high: int) -> int:
    """``value`` as an int, refused in one line unless it is a whole number in ``[low, high]``."""
    from symlearn.errors import SymlearnError

    if not math.isfinite(value) or value != int(value):
        raise SymlearnError(f"{flag} must be a whole number, got {value:g}")
    if not low <= value <= high:
        raise SymlearnError(f"{flag} must be between {low:,} and {high:,}, got {value:g}")
    return int(value)


__all__ = ["whole"]
