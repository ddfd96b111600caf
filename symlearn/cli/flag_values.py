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


#: the most demonstrations a learn command records with --n-demos (as data record's --episodes):
#: each is an expert episode kept in memory, and 10^9 ran on, unrefused, past a minute and 1 GB
MAX_DEMOS = 100_000


def demo_count(text: str) -> int:
    """argparse ``type`` of ``--n-demos``: a whole number from 1 to :data:`MAX_DEMOS` (a usage
    error, one line, before anything is recorded)."""
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid int value: {text!r}") from None
    if not 1 <= value <= MAX_DEMOS:
        raise argparse.ArgumentTypeError(f"must be between 1 and {MAX_DEMOS:,}, got {value:,}"
                                         if abs(value) < 10**30 else f"must be between 1 and {MAX_DEMOS:,}")
    return value


__all__ = ["MAX_DEMOS", "demo_count", "whole"]
