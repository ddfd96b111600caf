"""Truth values of LTLf formulas over a whole sample, as bit words, with every operator vectorised.

A *frame* fixes the sample: ``n`` traces, each padded to ``W`` 64-bit words, position ``t`` of
trace ``i`` being bit ``t % 64`` of word ``t // 64``. A candidate formula is represented by its
truth values at every (trace, position): a ``uint64`` array of shape ``(n, W)`` (or a batch
``(m, n, W)``). Bits past the end of a trace are always 0, so equal formulas have equal arrays
and the bytes can be hashed to keep semantically equal candidates once.

Temporal operators need a backward scan over time. With the time axis inside machine words,
``X`` is a shift, ``F`` a log-step "smear" towards earlier positions, and ``U`` a log-step
parallel-prefix (Kogge-Stone) combination of "generate" (``right`` holds) and "propagate"
(``left`` holds): after the steps of distance 1, 2, 4, ... the generate word says, for each
position, whether ``right`` holds at some later-or-equal position reached through ``left``.

Why not the core's :mod:`symlearn.logic.ltlf.vectorized`: the enumeration needs every
candidate's truth values at every position, for thousands of candidates per level. Packing 64
positions in a word and applying one operator to a whole batch is 18x faster than the core's
bool ``[trace, step]`` kernels batched the same way, and 26x faster than calling
:func:`~symlearn.logic.ltlf.vectorized.evaluate` per formula (which gives verdicts only), on the
2382 formulas of size <= 4 of a 200-trace benchmark sample; ``python
benchmarks/ltl_evaluators.py``, which also checks that all three agree (docs/BENCHMARKS.md).

>>> frame = Frame.from_traces([[{"a"}, set(), {"b"}]], ["a", "b"])
>>> a, b = frame.propositions["a"], frame.propositions["b"]
>>> bin(int(apply("U", frame, frame.negate(b), b)[0, 0]))   # !b U b holds at 0, 1 and 2
'0b111'
>>> bin(int(apply("X", frame, a)[0, 0]))                    # nothing follows a's step
'0b0'
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["Frame", "apply", "UNARY", "BINARY", "COMMUTATIVE", "TEMPORAL", "row_hashes", "first_bits"]

UNARY = ("F", "G", "X", "!", "N")  # F and G first: they matter most when a level is cut short
BINARY = ("&", "|", "->", "U", "R", "W", "T")
COMMUTATIVE = frozenset({"&", "|"})
TEMPORAL = frozenset({"X", "N", "F", "G", "U", "R", "W", "T"})

_WORD = 64


@dataclass(frozen=True)
class Frame:
    """Shape of a sample in words: valid-position mask, last-position bits, longest trace."""

    mask: np.ndarray  # (n, W) uint64, bit set at every position inside the trace
    last: np.ndarray  # (n, W) uint64, bit set at the last position of each trace
    length: int  # longest trace (number of positions the scans must cover)
    propositions: dict  # name -> (n, W) uint64 truth values

    @classmethod
    def from_traces(cls, traces: Sequence[Sequence[Iterable[str]]], propositions: Sequence[str]) -> Frame:
        """Encode traces (sequences of label sets) over ``propositions``."""
        lengths = np.array([len(t) for t in traces], dtype=np.int64)
        length = int(lengths.max())
        width = -(-length // _WORD)
        bits = {p: np.zeros((len(traces), width * _WORD), dtype=bool) for p in propositions}
        for i, trace in enumerate(traces):
            for t, label in enumerate(trace):
                for p in label:
                    bits[p][i, t] = True
        valid = np.arange(width * _WORD)[None, :] < lengths[:, None]
        last = np.arange(width * _WORD)[None, :] == (lengths[:, None] - 1)
        return cls(_pack(valid), _pack(last), length, {p: _pack(b) for p, b in bits.items()})

    @classmethod
    def from_columns(cls, n_positions: int) -> Frame:
        """A frame of one trace with ``n_positions`` positions and no propositions (for Boolean search)."""
        valid = np.ones((1, n_positions), dtype=bool)
        width = -(-n_positions // _WORD)
        padded = np.zeros((1, width * _WORD), dtype=bool)
        padded[:, :n_positions] = valid
        last = np.zeros_like(padded)
        last[0, n_positions - 1] = True
        return cls(_pack(padded), _pack(last), n_positions, {})

    @property
    def shape(self) -> tuple[int, int]:
        return self.mask.shape

    def negate(self, values: np.ndarray) -> np.ndarray:
        return self.mask & ~values


def _pack(bits: np.ndarray) -> np.ndarray:
    """(n, W*64) bools -> (n, W) uint64, position t at bit t % 64 of word t // 64."""
    n, total = bits.shape
    packed = np.packbits(bits.reshape(n, total // 8, 8), axis=-1, bitorder="little").reshape(n, total // 8)
    return packed.view("<u8").astype(np.uint64, copy=False).reshape(n, total // _WORD)


def unpack(values: np.ndarray, length: int) -> np.ndarray:
    """(..., W) uint64 -> (..., length) bools (inverse of the packing, for tests and display)."""
    as_bytes = np.ascontiguousarray(values.astype("<u8")).view(np.uint8)
    bits = np.unpackbits(as_bytes, axis=-1, bitorder="little")
    return bits[..., :length].astype(bool)


def _shift_down(values: np.ndarray, distance: int) -> np.ndarray:
    """Position t receives the value at position t + distance (zeros shifted in at the end)."""
    words, bits = divmod(distance, _WORD)
    width = values.shape[-1]
    if words:
        if words >= width:
            return np.zeros_like(values)
        values = np.concatenate([values[..., words:], np.zeros(values.shape[:-1] + (words,), np.uint64)], axis=-1)
    if bits:
        low = values >> np.uint64(bits)
        if width == 1:
            return low
        high = np.concatenate([values[..., 1:], np.zeros(values.shape[:-1] + (1,), np.uint64)], axis=-1)
        values = low | (high << np.uint64(_WORD - bits))
    return values


def _eventually(values: np.ndarray, length: int) -> np.ndarray:
    out = values.copy()
    distance = 1
    while distance < length:
        out |= _shift_down(out, distance)
        distance *= 2
    return out


def _until(left: np.ndarray, right: np.ndarray, length: int) -> np.ndarray:
    generate = right.copy()
    propagate = left.copy()
    distance = 1
    while distance < length:
        generate |= propagate & _shift_down(generate, distance)
        if distance * 2 < length:
            propagate &= _shift_down(propagate, distance)
        distance *= 2
    return generate


def apply(op: str, frame: Frame, left: np.ndarray, right: np.ndarray | None = None) -> np.ndarray:
    """Truth values of ``op`` applied to operand truth values (any leading batch shape)."""
    mask, length = frame.mask, frame.length
    if op == "!":
        return mask & ~left
    if op == "X":
        return _shift_down(left, 1)
    if op == "N":
        return _shift_down(left, 1) | frame.last
    if op == "F":
        return _eventually(left, length)
    if op == "G":
        return mask & ~_eventually(mask & ~left, length)
    if right is None:
        raise ValueError(f"unknown unary operator {op!r}")
    if op == "&":
        return left & right
    if op == "|":
        return left | right
    if op == "->":
        return mask & (~left | right)
    if op == "U":
        return _until(left, right, length)
    if op == "R":
        return mask & ~_until(mask & ~left, mask & ~right, length)
    if op == "W":
        return _until(left, right, length) | (mask & ~_eventually(mask & ~left, length))
    if op == "T":
        return _eventually(left & _shift_down(_eventually(right, length), 1), length)
    raise ValueError(f"unknown operator {op!r}")


_MIX1, _MIX2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)


def _mix(x: np.ndarray) -> np.ndarray:
    """The splitmix64 finaliser: a bijection on 64-bit words that spreads every input bit."""
    x = x ^ (x >> np.uint64(30))
    x = x * _MIX1
    x = x ^ (x >> np.uint64(27))
    x = x * _MIX2
    return x ^ (x >> np.uint64(31))


def row_hashes(values: np.ndarray) -> np.ndarray:
    """A 64-bit hash of each candidate of a batch ``(m, n, W)``.

    Each word is salted with its place and mixed before summing, so the hash depends on where
    every bit is. Two different candidates share a hash with probability about 2^-64 per pair;
    such a collision could only drop a candidate from the search, never make a wrong formula
    pass (solutions are checked on their own truth values).
    """
    flat = values.reshape(values.shape[0], -1)
    salts = _mix(np.arange(1, flat.shape[1] + 1, dtype=np.uint64) * np.uint64(0x9E3779B97F4A7C15))
    return _mix(flat ^ salts).sum(axis=1, dtype=np.uint64)


def first_bits(values: np.ndarray) -> np.ndarray:
    """``(m, n, W)`` -> ``(m, n)`` bools: the value of each candidate at position 0 of each trace."""
    return (values[..., 0] & np.uint64(1)).astype(bool)
