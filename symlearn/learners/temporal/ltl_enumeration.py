"""Bottom-up enumeration of formulas by size, one candidate per distinct truth-value matrix.

Level ``s`` holds the candidates of size ``s`` (number of syntax-tree nodes): the atoms of that
size, then every unary operator over level ``s-1``, then every binary operator over levels
``s1`` and ``s2`` with ``s1 + s2 = s - 1``. A candidate is computed from its children's bit
words (:mod:`symlearn.learners.temporal.ltl_bitsets`) in vectorised batches and kept only if no candidate
of the same or a smaller size already has the same truth values everywhere. Since two
candidates with equal truth values can replace each other inside any larger formula, keeping
the first (smallest) one loses no solution: the first level holding a solution holds a
smallest one, for the operators searched.

The enumeration is deterministic: the order of atoms, operators and pairs is fixed, and the
limits that cut a level short (stored candidates, evaluated words) count work, not time. The
wall-clock deadline is only a safety net.

>>> from symlearn.learners.temporal.ltl_bitsets import Frame
>>> frame = Frame.from_traces([[{"a"}], [set(), {"a"}], [set()]], ["a"])
>>> goal = lambda v: (v[..., 0] & 1).astype(bool) @ [1, 2, -4] == 3   # true on traces 0, 1 only
>>> search = Enumerator(frame, [("a", frame.propositions["a"], 1)], ("!", "F"), goal)
>>> search.run(max_size=4).solution_size
2
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from symlearn.learners.temporal.ltl_bitsets import BINARY, COMMUTATIVE, UNARY, Frame, apply, first_bits, row_hashes

__all__ = ["Enumerator", "EnumerationOutcome"]

ATOM = -1
_BLOCK_WORDS = 1 << 21  # words computed per numpy batch (16 MiB per operand)
_BLOCK_ROWS = 1 << 16  # candidates per batch, so limits are checked often on tiny frames


@dataclass
class _Level:
    values: list = field(default_factory=list)  # batches of (k, n, W) uint64
    ops: list = field(default_factory=list)  # batches of int8 operator codes (ATOM for atoms)
    left: list = field(default_factory=list)  # batches of child ids (atom index for atoms)
    right: list = field(default_factory=list)
    count: int = 0

    def freeze(self, shape: tuple[int, int]) -> None:
        def join(parts, dtype, tail=()):
            return np.concatenate(parts) if parts else np.zeros((0, *tail), dtype=dtype)

        self.values = [join(self.values, np.uint64, shape)]
        self.ops = [join(self.ops, np.int8)]
        self.left = [join(self.left, np.int64)]
        self.right = [join(self.right, np.int64)]


@dataclass
class EnumerationOutcome:
    """Where the search stopped: the first solution (smallest found) and how far it got."""

    solution: int | None  # candidate id of the first solution, or None
    solution_size: int | None
    complete_up_to: int  # every candidate up to this size was generated (modulo semantic duplicates)
    stopped_by: str  # "solution", "max_size", "candidate limit", "work limit", "deadline"
    candidates: int  # distinct candidates stored
    evaluated: int  # candidates computed (before removing duplicates)


class Enumerator:
    """Size-ordered search over formulas built from ``atoms`` with ``operators``.

    ``atoms`` are ``(payload, values, size)``; ``is_solution(batch) -> bool mask`` says which
    candidates of a ``(m, n, W)`` batch solve the problem. ``max_candidates`` bounds memory and
    ``max_work`` the number of words evaluated (both deterministic); ``deadline`` is a
    ``time.monotonic()`` value after which the search stops where it is.
    """

    def __init__(self, frame: Frame, atoms: Sequence[tuple[Any, np.ndarray, int]], operators: Sequence[str],
                 is_solution: Callable[[np.ndarray], np.ndarray], *, max_candidates: int = 2_000_000,
                 max_work: float = float("inf"), deadline: float | None = None) -> None:
        unknown = [op for op in operators if op not in UNARY and op not in BINARY]
        if unknown:
            raise ValueError(f"unknown operator {unknown[0]!r}")
        self.frame = frame
        self.atoms = list(atoms)
        self.unary = [op for op in UNARY if op in operators]
        self.binary = [op for op in BINARY if op in operators]
        self.codes = {op: i for i, op in enumerate(UNARY + BINARY)}
        self.is_solution = is_solution
        self.max_candidates = max_candidates
        self.max_work = max_work
        self.deadline = deadline
        self.levels: dict[int, _Level] = {}
        self.offsets: dict[int, int] = {}
        self.seen: set[int] = set()
        self.stored = 0
        self.evaluated = 0
        self.work = 0.0
        self._words = int(np.prod(frame.shape))
        self._stop: str | None = None
        self._solution: int | None = None

    # -- public -----------------------------------------------------------------------------

    def run(self, max_size: int) -> EnumerationOutcome:
        """Generate levels 1, 2, ... up to ``max_size``; stop at the first solution or a limit."""
        complete = 0
        size = 0
        for size in range(1, max_size + 1):
            self._generate(size)
            if self._solution is not None:
                return self._outcome("solution", complete)
            if self._stop:
                return self._outcome(self._stop, complete)
            complete = size
        return self._outcome("max_size", complete)

    def size_of(self, cid: int) -> int:
        for size in sorted(self.offsets, reverse=True):
            if cid >= self.offsets[size]:
                return size
        raise IndexError(cid)

    def recipe(self, cid: int) -> tuple[str | None, int, int]:
        """``(operator, left, right)`` of a candidate; for an atom ``(None, atom index, -1)``."""
        size = self.size_of(cid)
        local = cid - self.offsets[size]
        level = self.levels[size]
        code = int(level.ops[0][local])
        left, right = int(level.left[0][local]), int(level.right[0][local])
        if code == ATOM:
            return None, left, right
        return (UNARY + BINARY)[code], left, right

    def values_of(self, cid: int) -> np.ndarray:
        size = self.size_of(cid)
        return self.levels[size].values[0][cid - self.offsets[size]]

    def build(self, cid: int, make_atom: Callable[[Any], Any], make_node: Callable[..., Any]) -> Any:
        """Rebuild candidate ``cid`` bottom-up: ``make_atom(payload)``, ``make_node(op, *children)``."""
        built: dict[int, Any] = {}
        stack = [cid]
        while stack:
            node = stack[-1]
            if node in built:
                stack.pop()
                continue
            op, left, right = self.recipe(node)
            if op is None:
                built[node] = make_atom(self.atoms[left][0])
                stack.pop()
                continue
            children = [left] if op in UNARY else [left, right]
            missing = [c for c in children if c not in built]
            if missing:
                stack.extend(missing)
                continue
            built[node] = make_node(op, *(built[c] for c in children))
            stack.pop()
        return built[cid]

    def all_candidates(self, first_only: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every stored candidate: ``(ids, sizes, values)`` in size order (values at position 0 only:
        ``(k, n)`` bools, with ``first_only``)."""
        ids, sizes, values = [], [], []
        for size in sorted(self.levels):
            level = self.levels[size]
            k = level.count
            ids.append(self.offsets[size] + np.arange(k))
            sizes.append(np.full(k, size))
            values.append(first_bits(level.values[0]) if first_only else level.values[0])
        if not ids:
            shape = self.frame.shape
            empty = np.zeros((0, shape[0]), bool) if first_only else np.zeros((0, *shape), np.uint64)
            return np.zeros(0, np.int64), np.zeros(0, np.int64), empty
        return np.concatenate(ids), np.concatenate(sizes), np.concatenate(values)

    # -- generation -------------------------------------------------------------------------

    def _outcome(self, stopped_by: str, complete: int) -> EnumerationOutcome:
        size = None if self._solution is None else self.size_of(self._solution)
        return EnumerationOutcome(self._solution, size, complete, stopped_by, self.stored, self.evaluated)

    def _generate(self, size: int) -> None:
        level = _Level()
        self.levels[size] = level
        self.offsets[size] = self.stored
        try:
            atoms = [(i, a) for i, a in enumerate(self.atoms) if a[2] == size]
            if atoms:
                values = np.stack([a[1] for _, a in atoms]).astype(np.uint64)
                idx = np.array([i for i, _ in atoms], dtype=np.int64)
                self._add(level, values, np.full(len(atoms), ATOM, np.int8), idx, np.full(len(atoms), -1, np.int64))
            for op in self.unary:
                source = self.levels.get(size - 1)
                if source is None or not source.count:
                    continue
                src = source.values[0]
                step = max(1, min(_BLOCK_ROWS, _BLOCK_WORDS // self._words))
                for start in range(0, source.count, step):
                    if self._halted():
                        return
                    chunk = src[start:start + step]
                    ids = self.offsets[size - 1] + np.arange(start, start + len(chunk))
                    self._add(level, apply(op, self.frame, chunk), np.full(len(chunk), self.codes[op], np.int8),
                              ids, np.full(len(chunk), -1, np.int64))
            for op in self.binary:
                for s1 in range(1, size - 1):
                    s2 = size - 1 - s1
                    if op in COMMUTATIVE and s1 > s2:
                        continue
                    self._binary(level, op, s1, s2)
                    if self._halted():
                        return
        finally:
            level.freeze(self.frame.shape)

    def _binary(self, level: _Level, op: str, s1: int, s2: int) -> None:
        a_level, b_level = self.levels.get(s1), self.levels.get(s2)
        if a_level is None or b_level is None or not a_level.count or not b_level.count:
            return
        a_vals, b_vals = a_level.values[0], b_level.values[0]
        ka, kb = a_level.count, b_level.count
        triangle = s1 == s2 and op in COMMUTATIVE
        pairs_per_block = max(1, min(_BLOCK_ROWS, _BLOCK_WORDS // self._words))
        b_step = min(kb, pairs_per_block)
        a_step = max(1, pairs_per_block // b_step)
        for a0 in range(0, ka, a_step):
            for b0 in range(0, kb, b_step):
                if self._halted():
                    return
                ia = np.arange(a0, min(ka, a0 + a_step))
                ib = np.arange(b0, min(kb, b0 + b_step))
                if triangle and ib[-1] <= ia[0]:
                    continue
                ii = np.repeat(ia, len(ib))
                jj = np.tile(ib, len(ia))
                keep = ii < jj if triangle else (ii != jj if s1 == s2 and op != "T" else None)
                if keep is not None:
                    ii, jj = ii[keep], jj[keep]
                if not len(ii):
                    continue
                values = apply(op, self.frame, a_vals[ii], b_vals[jj])
                self._add(level, values, np.full(len(ii), self.codes[op], np.int8),
                          self.offsets[s1] + ii, self.offsets[s2] + jj)
                if self._solution is not None:
                    return

    def _halted(self) -> bool:
        if self._solution is not None or self._stop:
            return True
        if self.stored >= self.max_candidates:
            self._stop = "candidate limit"
        elif self.work >= self.max_work:
            self._stop = "work limit"
        elif self.deadline is not None and time.monotonic() > self.deadline:
            self._stop = "deadline"
        return self._stop is not None

    def _add(self, level: _Level, values: np.ndarray, ops, left, right) -> None:
        m = len(values)
        self.evaluated += m
        self.work += m * (self._words + 16)  # per-candidate bookkeeping costs about 16 words
        hashes = row_hashes(values)
        _, first = np.unique(hashes, return_index=True)
        first.sort()
        seen = self.seen
        fresh = [i for i, h in zip(first.tolist(), hashes[first].tolist()) if h not in seen]
        if not fresh:
            return
        room = self.max_candidates - self.stored
        if len(fresh) > room:
            fresh = fresh[:room]
        fresh_idx = np.array(fresh, dtype=np.int64)
        seen.update(hashes[fresh_idx].tolist())
        values = values[fresh_idx]
        solved = np.flatnonzero(self.is_solution(values))
        if len(solved):  # keep the candidates up to the first solution only, so ids stay ordered
            cut = int(solved[0]) + 1
            fresh_idx, values = fresh_idx[:cut], values[:cut]
            self._solution = self.stored + cut - 1
        level.values.append(values)
        level.ops.append(ops[fresh_idx])
        level.left.append(left[fresh_idx])
        level.right.append(right[fresh_idx])
        level.count += len(fresh_idx)
        self.stored += len(fresh_idx)
