"""DNF constraints: disjunctions of conjunctions of inequalities ``feature op number``.

A one-class decision tree describes where the expert never goes as a union of boxes; each box
is a conjunction of bounds on named features, the union is a formula in disjunctive normal
form (thesis, chapter 4). The text format has one conjunction per line:

>>> f = parse('''
... # unsafe when too fast, or in the corner
... v > 1.46
... x0 > 0.1 & x0 < 0.7 & x1 > 0.3
... ''')
>>> print(f)
v > 1.46
x0 > 0.1 & x0 < 0.7 & x1 > 0.3
>>> f.features
('v', 'x0', 'x1')
>>> parse(str(f)) == f
True
>>> import numpy as np
>>> X = np.array([[0.0, 0.5, 0.5], [2.0, 0.0, 0.0], [0.0, 0.9, 0.5]])
>>> f.evaluate(X, ["v", "x0", "x1"]).tolist()
[True, True, False]
>>> f.evaluate(X, ["v", "x0", "x1"], per_conjunction=True).tolist()
[[False, True], [True, False], [False, False]]

Text format (``grammars/dnf.lark``)
-----------------------------------

* one conjunction per line, atoms ``feature op number`` joined by ``&`` (also ``&&``, ``∧``);
  ``op`` is one of ``< <= > >=`` (also ``≤ ≥``); ``x == 3`` is read as ``x >= 3 & x <= 3``
  and ``x != 3`` (also ``≠``) as two conjunctions, one with ``x < 3`` and one with ``x > 3``
  (at most 10 ``!=`` in one conjunction); ``#`` starts a comment; blank lines are ignored. Several conjunctions may share a line joined by ``|`` (also ``||``, ``∨``), the
  one-line form of feature labelings.
* ``true`` (``⊤``) is the empty conjunction (always holds); a ``false`` (``⊥``) line adds
  nothing; a file without conjunctions is the empty disjunction, false (printed ``false``).
* feature names are identifiers ``[A-Za-z_][A-Za-z0-9_]*`` or double-quoted names with
  ``\\"`` and ``\\\\`` escapes (``"door open" < 1``); ``true``/``false`` must be quoted.
* numbers are decimal with an optional exponent and are read with Python's ``float``; they print
  as the shortest text that reads back to the same double (integers without ``.0``), so
  ``parse(str(f)) == f`` exactly. ``inf`` and ``nan`` are refused with their column.

Values are immutable and compare structurally (order of atoms and conjunctions included, as it
prints); :meth:`DNF.simplify` gives the canonical, smaller form and :meth:`DNF.equivalent`
compares the sets of points. Set operations are exact box algebra:

>>> g = parse("x0 > 0.1 & x0 < 0.4 & x1 > 0.3\\nx0 >= 0.4 & x0 < 0.7 & x1 > 0.3\\nv > 2")
>>> print(g.simplify())
x0 > 0.1 & x0 < 0.7 & x1 > 0.3
v > 2
>>> g.implies(f), f.implies(g), g.simplify().equivalent(g)
(True, False, True)
>>> f.volume({"v": (0, 2), "x0": (0, 1), "x1": (0, 1)})
1.1532
>>> print(parse("x < 1 | x >= 1").simplify())
true
>>> print(f.to_string("unicode", one_line=True))
v > 1.46 ∨ x0 > 0.1 ∧ x0 < 0.7 ∧ x1 > 0.3
>>> print(f.to_string("latex"))
v > 1.46 \\lor \\left(x_{0} > 0.1 \\land x_{0} < 0.7 \\land x_{1} > 0.3\\right)

``|`` (union), ``&`` (intersection), ``-`` (difference) and ``~`` (complement) build new
formulas; :meth:`DNF.implies`, :meth:`DNF.contains` and :meth:`DNF.equivalent` decide set
containment exactly by splitting boxes along the faces of the boxes that overlap them (bounded
by ``limit=``, beyond which :class:`~symlearn.errors.LimitExceededError` is raised).

Evaluation
----------

:meth:`DNF.evaluate` compiles the formula once (cached on the value; :mod:`symlearn.logic.dnf_eval`,
run by numba): per feature, the sorted thresholds cut the line into cells (below, on and between
thresholds), so every conjunction is a box of cell intervals. A point finds its cell per feature
through a uniform grid over the thresholds and one exact comparison, then either ANDs per-cell
bitmasks of the conjunctions (few features) or tests the boxes on many points at once (many
features). NaN in a used column is an error (it would compare false with every bound).
:meth:`DNF.evaluator` binds the formula to one column order for cheap repeated calls.
"""

from __future__ import annotations

import gc
import itertools
import json
import math
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache, cached_property
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, LimitExceededError, ParseError

__all__ = [
    "OPS", "Interval", "Atom", "Conjunction", "DNF", "TRUE", "FALSE", "parse", "load", "from_json", "to_sympy",
    "format_number", "format_feature", "MAGIC", "FORMAT_VERSION",
]

MAGIC = "dnf"
FORMAT_VERSION = 1
OPS = ("<", "<=", ">", ">=")
STYLES = ("ascii", "unicode", "latex")
_UNICODE_OPS = {"\u2264": "<=", "\u2265": ">="}
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_KEYWORDS = frozenset({"true", "false"})
_INF = math.inf
#: box splits a containment check, difference or volume may make before giving up
FRAGMENT_LIMIT = 200_000


def format_number(value: float) -> str:
    """The shortest text that reads back to exactly ``value``: integers without ``.0``.

    >>> format_number(3.0), format_number(0.1), format_number(1e-7), format_number(2.0**60)
    ('3', '0.1', '1e-07', '1.152921504606847e+18')
    """
    if value.is_integer() and abs(value) < 1e16:
        return str(int(value))
    return repr(value)


def format_feature(name: str) -> str:
    """``name`` as written in the text format: bare when an identifier, else double-quoted."""
    if _IDENTIFIER.match(name) and name not in _KEYWORDS:
        return name
    return '"' + name.replace("\\", "\\\\").replace('"', '\\"') + '"'


# -- intervals -----------------------------------------------------------------------------

@dataclass(frozen=True)
class Interval:
    """A set of reals between ``lo`` and ``hi``, each end open or closed; infinite ends are open.

    >>> Interval(0, 1, True, False).intersect(Interval(0.5, 2))
    Interval(lo=0.5, hi=1.0, lo_closed=False, hi_closed=False)
    >>> Interval(0, 1, hi_closed=True).union(Interval(1, 2))
    Interval(lo=0.0, hi=2.0, lo_closed=False, hi_closed=False)
    >>> Interval(0, 1).union(Interval(1, 2)) is None     # the point 1 is missing
    True
    """

    lo: float = -_INF
    hi: float = _INF
    lo_closed: bool = False
    hi_closed: bool = False

    def __post_init__(self) -> None:
        lo, hi = float(self.lo) + 0.0, float(self.hi) + 0.0
        if math.isnan(lo) or math.isnan(hi):
            raise DataError("interval ends must not be NaN")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "lo_closed", bool(self.lo_closed) and math.isfinite(lo))
        object.__setattr__(self, "hi_closed", bool(self.hi_closed) and math.isfinite(hi))

    @property
    def is_empty(self) -> bool:
        return self.lo > self.hi or (self.lo == self.hi and not (self.lo_closed and self.hi_closed))

    @property
    def is_full(self) -> bool:
        return self.lo == -_INF and self.hi == _INF

    @property
    def holds_whole_number(self) -> bool:
        """Whether some integer lies in the interval (``(1, 2)`` holds none, ``[1, 2)`` holds 1):
        where a feature takes whole-number values only, an interval without one is empty."""
        least = self.lo if self.lo == -_INF else math.ceil(self.lo) if self.lo_closed else math.floor(self.lo) + 1
        most = self.hi if self.hi == _INF else math.floor(self.hi) if self.hi_closed else math.ceil(self.hi) - 1
        return least <= most

    @property
    def length(self) -> float:
        return 0.0 if self.is_empty else self.hi - self.lo

    def __contains__(self, x: float) -> bool:
        return (self.lo < x or (self.lo_closed and x == self.lo)) and (x < self.hi or (self.hi_closed and x == self.hi))

    def intersect(self, other: Interval) -> Interval:
        lo, lc = _tighter_lo(self, other)
        hi, hc = _tighter_hi(self, other)
        return Interval(lo, hi, lc, hc)

    def contains(self, other: Interval) -> bool:
        """``other ⊆ self``."""
        if other.is_empty:
            return True
        if self.is_empty:
            return False
        lo_ok = self.lo < other.lo or (self.lo == other.lo and (self.lo_closed or not other.lo_closed))
        hi_ok = self.hi > other.hi or (self.hi == other.hi and (self.hi_closed or not other.hi_closed))
        return lo_ok and hi_ok

    def union(self, other: Interval) -> Interval | None:
        """The union when it is one interval (the two overlap or touch), else ``None``."""
        if other.is_empty:
            return self
        if self.is_empty:
            return other
        first, second = sorted((self, other), key=lambda i: (i.lo, not i.lo_closed))
        if first.hi < second.lo or (first.hi == second.lo and not (first.hi_closed or second.lo_closed)):
            return None
        if first.hi > second.hi or (first.hi == second.hi and first.hi_closed):
            hi, hc = first.hi, first.hi_closed
        else:
            hi, hc = second.hi, second.hi_closed
        lc = first.lo_closed or (second.lo == first.lo and second.lo_closed)
        return Interval(first.lo, hi, lc, hc)

    def minus(self, other: Interval) -> list[Interval]:
        """``self \\ other`` as at most two disjoint intervals (none empty)."""
        if self.is_empty:
            return []
        if other.is_empty or self.intersect(other).is_empty:
            return [self]
        parts = [self.intersect(Interval(-_INF, other.lo, False, not other.lo_closed)),
                 self.intersect(Interval(other.hi, _INF, not other.hi_closed, False))]
        return [p for p in parts if not p.is_empty]

    def atoms(self, feature: str) -> list[Atom]:
        """The atoms that bound ``feature`` to this interval (none when it is unbounded)."""
        out = []
        if self.lo > -_INF:
            out.append(Atom(feature, ">=" if self.lo_closed else ">", self.lo))
        if self.hi < _INF:
            out.append(Atom(feature, "<=" if self.hi_closed else "<", self.hi))
        return out


FULL = Interval()


def _tighter_lo(a: Interval, b: Interval) -> tuple[float, bool]:
    if a.lo != b.lo:
        return (a.lo, a.lo_closed) if a.lo > b.lo else (b.lo, b.lo_closed)
    return a.lo, a.lo_closed and b.lo_closed


def _tighter_hi(a: Interval, b: Interval) -> tuple[float, bool]:
    if a.hi != b.hi:
        return (a.hi, a.hi_closed) if a.hi < b.hi else (b.hi, b.hi_closed)
    return a.hi, a.hi_closed and b.hi_closed


# -- the formula values --------------------------------------------------------------------

@dataclass(frozen=True)
class Atom:
    """``feature op value`` with ``op`` one of ``< <= > >=`` and a finite ``value``."""

    feature: str
    op: str
    value: float

    def __post_init__(self) -> None:
        if not isinstance(self.feature, str) or not self.feature or "\n" in self.feature or "\r" in self.feature:
            raise DataError(f"a feature name must be a non-empty single-line string, not {self.feature!r}")
        op = _UNICODE_OPS.get(self.op, self.op)
        if op not in OPS:
            raise DataError(f"unknown comparison {self.op!r}", hint="use one of: " + " ".join(OPS))
        number = (int, float, np.integer, np.floating)
        if isinstance(self.value, (bool, np.bool_)) or not isinstance(self.value, number):
            raise DataError(f"the bound of {self.feature} {op} ... must be a number, not {self.value!r}")
        try:
            value = float(self.value)
        except OverflowError:  # an integer beyond float64 (a JSON file may hold 10**400)
            raise DataError(f"the bound of {self.feature} {op} ... is too large for a float") from None
        if not math.isfinite(value):
            raise DataError(f"the bound of {self.feature} {op} ... must be finite, not {value!r}")
        object.__setattr__(self, "op", op)
        object.__setattr__(self, "value", value + 0.0)  # -0.0 -> 0.0

    @property
    def is_upper(self) -> bool:
        """``True`` for ``<``/``<=`` (an upper bound on the feature)."""
        return self.op[0] == "<"

    @property
    def strict(self) -> bool:
        return len(self.op) == 1

    @property
    def interval(self) -> Interval:
        """The values of the feature for which the atom holds."""
        if self.is_upper:
            return Interval(-_INF, self.value, False, not self.strict)
        return Interval(self.value, _INF, not self.strict, False)

    def holds(self, x: float) -> bool:
        """Truth for one value of the feature."""
        v = self.value
        if self.op == "<":
            return x < v
        if self.op == "<=":
            return x <= v
        if self.op == ">":
            return x > v
        return x >= v

    def negate(self) -> Atom:
        return Atom(self.feature, {"<": ">=", "<=": ">", ">": "<=", ">=": "<"}[self.op], self.value)

    def to_string(self, style: str = "ascii") -> str:
        _check_style(style)
        if style == "latex":
            return f"{_latex_name(self.feature)} {_LATEX_OPS[self.op]} {_latex_number(self.value)}"
        op = _PRETTY_OPS.get(self.op, self.op) if style == "unicode" else self.op
        return f"{format_feature(self.feature)} {op} {format_number(self.value)}"

    def __str__(self) -> str:
        return self.to_string()


@dataclass(frozen=True)
class Conjunction:
    """A conjunction of atoms; the empty conjunction is true. Atom order is kept (it prints)."""

    atoms: tuple[Atom, ...] = ()

    def __post_init__(self) -> None:
        atoms = tuple(self.atoms)
        for a in atoms:
            if not isinstance(a, Atom):
                raise DataError(f"a conjunction holds atoms, not {type(a).__name__}")
        object.__setattr__(self, "atoms", atoms)

    @classmethod
    def from_box(cls, box: Mapping[str, Interval], order: Sequence[str] | None = None) -> Conjunction:
        """The conjunction of the bounds of ``box`` (features in ``order``, then sorted)."""
        first = [f for f in dict.fromkeys(order or ()) if f in box]
        names = first + sorted(set(box) - set(first))
        return cls(tuple(a for f in names for a in box[f].atoms(f)))

    @property
    def features(self) -> tuple[str, ...]:
        return tuple(sorted({a.feature for a in self.atoms}))

    def box(self) -> dict[str, Interval]:
        """Feature -> the interval its atoms allow (intersected); unconstrained features are absent."""
        box: dict[str, Interval] = {}
        for a in self.atoms:
            box[a.feature] = box.get(a.feature, FULL).intersect(a.interval)
        return box

    @property
    def is_satisfiable(self) -> bool:
        return not any(i.is_empty for i in self.box().values())

    def simplify(self) -> Conjunction:
        """One lower and one upper bound per feature at most (features in order of appearance)."""
        return Conjunction.from_box(self.box(), [a.feature for a in self.atoms])

    def holds(self, values: Any) -> bool:
        """Truth for one point given as a mapping ``feature -> value``."""
        return all(a.holds(float(values[a.feature])) for a in self.atoms)

    def __len__(self) -> int:
        return len(self.atoms)

    def __iter__(self):
        return iter(self.atoms)

    def to_string(self, style: str = "ascii") -> str:
        _check_style(style)
        if not self.atoms:
            return _TRUE_TEXT[style]
        return _AND_TEXT[style].join(a.to_string(style) for a in self.atoms)

    def __str__(self) -> str:
        return self.to_string()


@dataclass(frozen=True)
class DNF:
    """A disjunction of conjunctions; the empty disjunction is false. Order is kept (it prints)."""

    conjunctions: tuple[Conjunction, ...] = ()

    def __post_init__(self) -> None:
        conjunctions = tuple(c if isinstance(c, Conjunction) else Conjunction(tuple(c)) for c in self.conjunctions)
        object.__setattr__(self, "conjunctions", conjunctions)

    @classmethod
    def of(cls, *conjunctions: Iterable[tuple[str, str, float] | Atom]) -> DNF:
        """Build from plain tuples: ``DNF.of([("x", "<", 1)], [("y", ">=", 0), ("x", ">", 2)])``."""
        return cls(tuple(Conjunction(tuple(a if isinstance(a, Atom) else Atom(*a) for a in c)) for c in conjunctions))

    @classmethod
    def from_boxes(cls, boxes: Iterable[Mapping[str, Interval]], order: Sequence[str] | None = None) -> DNF:
        """One conjunction per box (empty boxes are dropped)."""
        return cls(tuple(Conjunction.from_box(b, order) for b in boxes
                         if not any(i.is_empty for i in b.values())))

    @property
    def features(self) -> tuple[str, ...]:
        """The sorted names of the features the formula uses."""
        return tuple(sorted({a.feature for c in self.conjunctions for a in c.atoms}))

    def __len__(self) -> int:
        return len(self.conjunctions)

    def __iter__(self):
        return iter(self.conjunctions)

    def __str__(self) -> str:
        return self.to_string()

    # -- truth ---------------------------------------------------------------------------
    def holds(self, values: Any) -> bool:
        """Truth for one point given as a mapping ``feature -> value``."""
        return any(c.holds(values) for c in self.conjunctions)

    def evaluate(self, X: Any, features: Any = None, per_conjunction: bool = False) -> np.ndarray:
        """Truth on every row of ``X`` (``[N, k]``, columns named by ``features``).

        ``features`` is a sequence of names, a comma-separated string or any object with a
        ``names`` attribute (a ``FeatureMap``). ``X`` may also be a mapping ``name -> [N]``
        array (then ``features`` is not needed). Returns a boolean array ``[N]``, or ``[N, m]``
        (one column per conjunction, in order) with ``per_conjunction=True``. Unknown features
        and NaN in a used column raise :class:`~symlearn.errors.DataError`; integer columns are
        compared as float64. The formula is compiled once (module docstring, "Evaluation").
        """
        from symlearn.logic.dnf_eval import points

        X, cols = points(self._plan, X, features)
        return self._plan.run(X, cols, per_conjunction)

    def evaluator(self, features: Any):
        """The formula bound to one column order: ``ev = f.evaluator(names)``, then ``ev(X)`` or
        ``ev(X, per_conjunction=True)`` for ``[N, k]`` (or ``[k]``) points in that order, as
        :meth:`evaluate` but without resolving the names on every call (one point costs a few
        microseconds: the cost wrapper calls it every environment step)."""
        from symlearn.logic.dnf_eval import Evaluator, feature_names

        return Evaluator(self._plan, feature_names(features))

    @cached_property
    def _plan(self):
        from symlearn.logic.dnf_eval import compile_plan

        return compile_plan(self)

    # -- box algebra ---------------------------------------------------------------------
    def boxes(self) -> list[dict[str, Interval]]:
        """The satisfiable conjunctions as boxes (see :meth:`Conjunction.box`)."""
        return [b for b in (c.box() for c in self.conjunctions) if not any(i.is_empty for i in b.values())]

    def _order(self) -> list[str]:
        return list(dict.fromkeys(a.feature for c in self.conjunctions for a in c.atoms))

    def simplify(self) -> DNF:
        """An equivalent, smaller formula in a canonical spelling.

        Inside each conjunction the atoms on one feature are intersected to at most one lower
        and one upper bound; unsatisfiable conjunctions are dropped, so are conjunctions
        contained in another one; two boxes that agree on every feature but one and whose
        intervals there overlap or touch are merged, until nothing changes. Features print in
        their order of first appearance. The set of points is unchanged (exactly).
        """
        order = self._order()
        boxes = _drop_contained(self.boxes())
        while True:
            before = len(boxes)
            for name in sorted({n for b in boxes for n in b}):
                boxes = _merge_along(boxes, name)
            boxes = _drop_contained(boxes)
            if len(boxes) == before:
                return DNF.from_boxes(boxes, order)

    def is_empty(self) -> bool:
        """``True`` when no point satisfies the formula."""
        return not self.boxes()

    def is_valid(self) -> bool:
        """``True`` when every point satisfies the formula."""
        return TRUE.implies(self)

    def union(self, other: DNF) -> DNF:
        """The conjunctions of both (``f | g``), not simplified."""
        return DNF(self.conjunctions + other.conjunctions)

    def intersection(self, other: DNF) -> DNF:
        """Pairwise intersections of the boxes (unsatisfiable pairs dropped)."""
        order = list(dict.fromkeys(self._order() + other._order()))
        boxes = [_box_intersect(a, b) for a in self.boxes() for b in other.boxes()]
        return DNF.from_boxes([b for b in boxes if b is not None], order)

    def difference(self, other: DNF, *, limit: int = FRAGMENT_LIMIT) -> DNF:
        """The points of ``self`` outside ``other``, as disjoint boxes (then simplified)."""
        order = list(dict.fromkeys(self._order() + other._order()))
        pieces = [p for box in self.boxes() for p in _subtract(box, other.boxes(), limit)]
        return DNF.from_boxes(pieces, order).simplify()

    def complement(self, *, limit: int = FRAGMENT_LIMIT) -> DNF:
        """The points that do not satisfy the formula."""
        return TRUE.difference(self, limit=limit)

    __or__ = union
    __and__ = intersection
    __sub__ = difference

    def __invert__(self) -> DNF:
        return self.complement()

    def implies(self, other: DNF, *, limit: int = FRAGMENT_LIMIT) -> bool:
        """``True`` when every point of ``self`` satisfies ``other`` (set containment, exact).

        Raises :class:`~symlearn.errors.LimitExceededError` when the check would split boxes
        more than ``limit`` times.
        """
        theirs = other.boxes()
        return all(not _subtract(box, theirs, limit, stop_at_first=True) for box in self.boxes())

    def contains(self, other: DNF, *, limit: int = FRAGMENT_LIMIT) -> bool:
        """``True`` when every point of ``other`` satisfies ``self``."""
        return other.implies(self, limit=limit)

    def equivalent(self, other: DNF, *, limit: int = FRAGMENT_LIMIT) -> bool:
        """``True`` when both formulas hold on exactly the same points."""
        return self.implies(other, limit=limit) and other.implies(self, limit=limit)

    def volume(self, bounds: Mapping[str, tuple[float, float]], *, limit: int = FRAGMENT_LIMIT) -> float:
        """The volume of the formula's points inside the box ``bounds`` (``feature -> (lo, hi)``).

        Every feature of the formula must be bounded; features of ``bounds`` the formula does
        not use count with their full width, so ``volume / prod(hi - lo)`` is the fraction of
        the bounding box the formula covers. Open and closed ends do not matter (measure).
        """
        clip: dict[str, Interval] = {}
        for name, pair in bounds.items():
            try:
                lo, hi = (float(v) for v in pair)
            except (TypeError, ValueError):
                raise DataError(f"bounds of {name} must be a pair (lo, hi), not {pair!r}") from None
            if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
                raise DataError(f"bounds of {name} must be finite with lo <= hi, not {pair!r}")
            clip[name] = Interval(lo, hi, True, True)
        missing = [f for f in self.features if f not in clip]
        if missing:
            raise DataError(f"no bounds for feature{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
        boxes = [b for b in (_box_intersect(box, clip) for box in self.boxes()) if b is not None]
        disjoint: list[dict[str, Interval]] = []
        for box in boxes:
            disjoint += _subtract(box, disjoint, limit)
        total = 0.0
        for box in disjoint:
            part = 1.0
            for name, interval in clip.items():
                part *= box.get(name, interval).length
            total += part
        return total

    # -- printing and files --------------------------------------------------------------
    def to_string(self, style: str = "ascii", *, one_line: bool = False) -> str:
        """``ascii`` (the text format), ``unicode`` (``≤ ≥ ∧``, also readable by :func:`parse`)
        or ``latex`` (one math-mode expression). Conjunctions go one per line, or joined by
        ``|``/``∨`` with ``one_line``.
        """
        _check_style(style)
        if not self.conjunctions:
            return _FALSE_TEXT[style]
        parts = [c.to_string(style) for c in self.conjunctions]
        if style == "latex":
            if len(parts) > 1:
                parts = [rf"\left({p}\right)" if len(c.atoms) > 1 else p for p, c in zip(parts, self.conjunctions)]
            return r" \lor ".join(parts)
        return (" \u2228 " if style == "unicode" else " | ").join(parts) if one_line else "\n".join(parts)

    def to_latex(self) -> str:
        return self.to_string("latex")

    def to_dict(self) -> dict[str, Any]:
        return {"symlearn": MAGIC, "format_version": FORMAT_VERSION,
                "conjunctions": [[[a.feature, a.op, a.value] for a in c.atoms] for c in self.conjunctions]}

    def to_json(self) -> str:
        """``{"symlearn": "dnf", "format_version": 1, "conjunctions": [[[feature, op, value], ...], ...]}``."""
        return json.dumps(self.to_dict())

    @classmethod
    def from_json(cls, text: str | Mapping, *, source: str | None = None) -> DNF:
        return from_json(text, source=source)

    def save(self, path: str | os.PathLike[str], *, header: str | None = None) -> Path:
        """Write the text format (JSON when ``path`` ends in ``.json``) atomically.

        ``header`` (any text) is written first as ``#`` comment lines in the text format.
        """
        from symlearn.atomic import write_text

        if str(path).endswith(".json"):
            return write_text(path, self.to_json() + "\n")
        lines = [("# " + line).rstrip() for line in header.splitlines()] if header else []
        return write_text(path, "\n".join(lines + [str(self)]) + "\n")

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> DNF:
        return load(path)

    def to_sympy(self, *, rational: bool = False):
        return to_sympy(self, rational=rational)


TRUE = DNF((Conjunction(()),))
FALSE = DNF(())

_PRETTY_OPS = {"<=": "\u2264", ">=": "\u2265"}
_LATEX_OPS = {"<": "<", "<=": r"\leq", ">": ">", ">=": r"\geq"}
_AND_TEXT = {"ascii": " & ", "unicode": " \u2227 ", "latex": r" \land "}
_TRUE_TEXT = {"ascii": "true", "unicode": "\u22a4", "latex": r"\top"}
_FALSE_TEXT = {"ascii": "false", "unicode": "\u22a5", "latex": r"\bot"}


def _check_style(style: str) -> None:
    if style not in STYLES:
        raise DataError(f"unknown style {style!r}", hint="choose one of: " + ", ".join(STYLES))


_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "_": r"\_", "^": r"\^{}", "#": r"\#",
                  "$": r"\$", "%": r"\%", "&": r"\&", "~": r"\~{}"}


def _latex_escape(text: str) -> str:
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in text)


def _latex_name(name: str) -> str:
    """``x0`` -> ``x_{0}``, ``d_13`` -> ``d_{13}``, ``speed`` -> ``\\mathit{speed}``, else ``\\text{...}``."""
    if not _IDENTIFIER.match(name):
        return r"\text{" + _latex_escape(name) + "}"
    m = re.fullmatch(r"([A-Za-z]+)(\d+)", name) or re.fullmatch(r"([A-Za-z]+)_([A-Za-z0-9]+)", name)
    if m:
        head = m.group(1) if len(m.group(1)) == 1 else r"\mathit{" + m.group(1) + "}"
        return f"{head}_{{{m.group(2)}}}"
    return name if len(name) == 1 else r"\mathit{" + _latex_escape(name) + "}"


def _latex_number(value: float) -> str:
    text = format_number(value)
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return rf"{mantissa} \times 10^{{{int(exponent)}}}"


# -- box algebra helpers -------------------------------------------------------------------

Box = dict[str, Interval]


def _box_intersect(a: Mapping[str, Interval], b: Mapping[str, Interval]) -> Box | None:
    out = dict(a)
    for name, interval in b.items():
        out[name] = out[name].intersect(interval) if name in out else interval
        if out[name].is_empty:
            return None
    return out


def _box_contains(outer: Mapping[str, Interval], inner: Mapping[str, Interval]) -> bool:
    return all(interval.contains(inner.get(name, FULL)) for name, interval in outer.items())


def _subtract(box: Box, others: Sequence[Mapping[str, Interval]], limit: int, stop_at_first: bool = False) -> list[Box]:
    """``box`` minus the union of ``others``, as disjoint boxes (only the first with ``stop_at_first``).

    Splits ``box`` along the faces of the boxes that overlap it, keeping for each piece only the
    boxes that still overlap it: a piece inside one of them is covered, a piece none of them
    overlaps is uncovered. ``limit`` bounds the number of splits.
    """
    out: list[Box] = []
    stack = [(box, [o for o in others if _box_intersect(box, o) is not None])]
    splits = 0
    while stack:
        piece, near = stack.pop()
        near = [o for o in near if _box_intersect(piece, o) is not None]
        if not near:
            out.append(piece)
            if stop_at_first:
                return out
            continue
        if any(_box_contains(o, piece) for o in near):
            continue
        other = near[0]
        name = next(n for n in sorted(other) if not other[n].contains(piece.get(n, FULL)))
        here = piece.get(name, FULL)
        for part in here.minus(other[name]) + [here.intersect(other[name])]:
            split = dict(piece)
            if part.is_full:
                split.pop(name, None)
            else:
                split[name] = part
            stack.append((split, near))
        splits += 1
        if splits > limit:
            raise LimitExceededError(f"box algebra would need more than {limit} splits",
                                     hint="simplify the formulas first, or raise limit=")
    return out


def _drop_contained(boxes: list[Box]) -> list[Box]:
    """Drop boxes contained in another (of equal boxes the first stays); vectorised over pairs."""
    m = len(boxes)
    if m < 2:
        return list(boxes)
    names = sorted({n for b in boxes for n in b})
    k = len(names)
    lo = np.array([[b.get(n, FULL).lo for n in names] for b in boxes], dtype=float).reshape(m, k)
    hi = np.array([[b.get(n, FULL).hi for n in names] for b in boxes], dtype=float).reshape(m, k)
    lc = np.array([[b.get(n, FULL).lo_closed for n in names] for b in boxes], dtype=bool).reshape(m, k)
    hc = np.array([[b.get(n, FULL).hi_closed for n in names] for b in boxes], dtype=bool).reshape(m, k)
    dropped = np.zeros(m, dtype=bool)
    step = max(1, 2_000_000 // max(1, m * k))
    index = np.arange(m)
    for start in range(0, m, step):
        i = slice(start, min(m, start + step))
        # outer[a, j]: box start + a contains box j; inner[a, j]: box j contains box start + a
        outer = _contains(lo[i, None], hi[i, None], lc[i, None], hc[i, None], lo[None], hi[None], lc[None], hc[None])
        inner = _contains(lo[None], hi[None], lc[None], hc[None], lo[i, None], hi[i, None], lc[i, None], hc[i, None])
        rows = index[i, None]
        dropped |= (outer & (rows != index[None]) & ((rows < index[None]) | ~inner)).any(axis=0)
    return [b for b, d in zip(boxes, dropped) if not d]


def _contains(lo_a, hi_a, lc_a, hc_a, lo_b, hi_b, lc_b, hc_b) -> np.ndarray:
    """Box a contains box b (arrays broadcast over boxes, last axis features)."""
    lo_ok = (lo_a < lo_b) | ((lo_a == lo_b) & (lc_a | ~lc_b))
    hi_ok = (hi_a > hi_b) | ((hi_a == hi_b) & (hc_a | ~hc_b))
    return (lo_ok & hi_ok).all(axis=-1)


def _merge_along(boxes: list[Box], name: str) -> list[Box]:
    """Merge the boxes that agree on every feature but ``name`` and whose intervals on ``name``
    overlap or touch; a merged box takes the place of the first of its parts."""
    groups: dict[frozenset, list[int]] = {}
    for position, box in enumerate(boxes):
        key = frozenset((n, i) for n, i in box.items() if n != name)
        groups.setdefault(key, []).append(position)
    placed: dict[int, Box] = {}
    for key, positions in groups.items():
        if len(positions) == 1:
            placed[positions[0]] = boxes[positions[0]]
            continue
        ordered = sorted(positions, key=lambda p: (boxes[p].get(name, FULL).lo, not boxes[p].get(name, FULL).lo_closed))
        runs: list[tuple[int, Interval]] = []
        for p in ordered:
            interval = boxes[p].get(name, FULL)
            union = runs[-1][1].union(interval) if runs else None
            if union is None:
                runs.append((p, interval))
            else:
                runs[-1] = (min(runs[-1][0], p), union)
        for p, interval in runs:
            box = dict(key)
            if not interval.is_full:
                box[name] = interval
            placed[p] = box
    return [placed[p] for p in sorted(placed)]


# -- JSON, files, sympy --------------------------------------------------------------------

def from_json(text: str | Mapping, *, source: str | None = None) -> DNF:
    """Read the JSON form (see :meth:`DNF.to_json`); mistakes name the member."""
    from symlearn.json_document import read_document

    from symlearn.json_position import locate

    doc = read_document(text, MAGIC, FORMAT_VERSION, source=source)

    def at(*path) -> dict:
        """The line and column of ``path`` in the file's text, so a member's mistake reads FILE:LINE:COL."""
        found = locate(text, path) if isinstance(text, str) else None
        return {"file": source, "line": found[0], "column": found[1]} if found else {"file": source}

    conjunctions = doc.get("conjunctions")
    if not isinstance(conjunctions, list):
        raise DataError('"conjunctions" must be a list of lists of [feature, op, value]', **at("conjunctions"))
    out = []
    for i, conj in enumerate(conjunctions):
        if not isinstance(conj, list):
            raise DataError(f"conjunctions[{i}] must be a list of [feature, op, value]", **at("conjunctions", i))
        atoms = []
        for j, atom in enumerate(conj):
            where = f"conjunctions[{i}][{j}]"
            if not isinstance(atom, list) or len(atom) != 3:
                raise DataError(f"{where} must be [feature, op, value], not {atom!r}", **at("conjunctions", i, j))
            if not isinstance(atom[0], str) or not isinstance(atom[1], str):
                raise DataError(f"{where}: feature and op must be strings", **at("conjunctions", i, j))
            try:
                atoms.append(Atom(*atom))
            except DataError as exc:
                raise DataError(f"{where}: {exc.message}", hint=exc.hint, **at("conjunctions", i, j)) from None
        out.append(Conjunction(tuple(atoms)))
    return DNF(tuple(out))


def load(path: str | os.PathLike[str]) -> DNF:
    """Read a ``.dnf`` text file (or ``.json``); errors name the file, line and column."""
    from symlearn.input_limits import read_input_text

    path = Path(path)
    try:  # size-capped, a bad byte located at its line:col
        text = read_input_text(path, what="rule file")
    except OSError as exc:
        raise DataError(f"cannot read {path}: {exc.strerror}", file=str(path)) from None
    if path.suffix == ".json":
        return from_json(text, source=str(path))
    return parse(text, source=str(path))


def to_sympy(formula: DNF, *, rational: bool = False):
    """The formula as a sympy ``Or`` of ``And`` of relationals over real symbols.

    Bounds become ``sympy.Float`` with the double's exact value, or with ``rational=True`` the
    rational number the text format prints (``0.1`` -> ``1/10``). sympy is imported here only.
    """
    import sympy

    symbols: dict[str, Any] = {}
    relation = {"<": sympy.Lt, "<=": sympy.Le, ">": sympy.Gt, ">=": sympy.Ge}

    def number(v: float):
        if rational:
            return sympy.Rational(format_number(v))
        return sympy.Integer(int(v)) if v.is_integer() else sympy.Float(v)

    def atom(a: Atom):
        symbol = symbols.setdefault(a.feature, sympy.Symbol(a.feature, real=True))
        return relation[a.op](symbol, number(a.value))

    return sympy.Or(*[sympy.And(*[atom(a) for a in c.atoms]) for c in formula.conjunctions])


# -- parsing -------------------------------------------------------------------------------

@cache
def _parser():
    from lark import Lark

    from symlearn.resources import grammar_text

    return Lark(grammar_text("dnf"), parser="lalr", maybe_placeholders=False)


def parse(text: str, *, source: str | None = None) -> DNF:
    """Read the text format (module docstring); ``source`` names the file in error messages.

    Well-formed lines are read by a hand-written scanner (a few regular-expression matches per
    atom, linear in the text: 10^6 lines in seconds); a line it does not accept is handed to the
    lark grammar, alone, which either reads it (a rarer spelling) or reports the error with the
    line, column and expected tokens."""
    if not isinstance(text, str):
        raise ParseError(f"a DNF formula must be text, not {type(text).__name__}", file=source)
    lines = text.split("\n")
    # Millions of new, long-lived objects make the cyclic collector rescan the old ones again and
    # again (a fifth of the time at 10^6 lines); they form no cycles, so it can rest meanwhile.
    collecting = gc.isenabled() and len(lines) > 10_000
    if collecting:
        gc.disable()
    try:
        return _parse_lines(lines, source)
    finally:
        if collecting:
            gc.enable()


def _parse_lines(lines: list[str], source: str | None) -> DNF:
    conjunctions: list[Conjunction] = []
    pending: ParseError | None = None  # a bad number; a syntax error on a later line comes first
    atoms_seen: dict = {}
    never: list[tuple[int, Conjunction]] = []   # (line, conjunction) that no point satisfies
    for number, line in enumerate(lines, 1):
        found = _scan_line(line, atoms_seen)
        if found is None:
            try:
                found = _parse_line_with_grammar(line, number, number == len(lines), source)
            except _BadNumber as exc:
                pending = pending or exc.error
                continue
        for conjunction in found:
            # only a feature bounded twice can empty a conjunction: the cheap test first
            atoms = conjunction.atoms
            if len(atoms) > 1 and len({a.feature for a in atoms}) < len(atoms) and not conjunction.is_satisfiable:
                never.append((number, conjunction))
        conjunctions.extend(found)
    if pending is not None:
        raise pending
    if never:
        _warn_never_holding(never, source)
    return DNF(tuple(conjunctions))


def _warn_never_holding(never: list[tuple[int, Conjunction]], source: str | None) -> None:
    """One warning for the conjunctions no point satisfies (``x < 1 & x > 2``): a learner never
    writes one, so in a file it is an edit gone wrong -- a reversed comparison, a misplaced bound --
    and the rule it meant forbids nothing now."""
    import warnings

    lines = sorted({number for number, _ in never})
    number, first = never[0]
    empty = next(f for f, i in first.box().items() if i.is_empty)
    bounds = " & ".join(a.to_string() for a in first.atoms if a.feature == empty)
    where = f"{source}: " if source else ""
    shown = ", ".join(map(str, lines[:10])) + (f", ... ({len(lines) - 10} more)" if len(lines) > 10 else "")
    warnings.warn(f"{where}{len(never)} conjunction{'s' if len(never) > 1 else ''} can never hold, so "
                  f"{'they forbid' if len(never) > 1 else 'it forbids'} nothing (line{'s' if len(lines) > 1 else ''} "
                  f"{shown}; line {number}: {bounds} leaves no value of {empty}): a comparison the wrong way "
                  "round?", UserWarning, stacklevel=4)


_WS = r"[ \t\f\r]*"
_ATOM_TOKEN = re.compile(
    _WS + r'(?:(?P<name>[A-Za-z_][A-Za-z0-9_]*)|"(?P<quoted>(?:[^"\\\n]|\\.)+)")' + _WS
    + r"(?P<op><=|>=|<|>|\u2264|\u2265)" + _WS
    + r"(?P<number>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)" + _WS
    + r"(?P<sep>&&|&|\u2227|\|\||\||\u2228|#.*|\Z)")
_CONSTANT_TOKEN = re.compile(_WS + r"(?P<constant>true|false|\u22a4|\u22a5)" + _WS + r"(?P<sep>\|\||\||\u2228|#.*|\Z)")
_BLANK_LINE = re.compile(_WS + r"(?:#.*)?\Z")
_AND_SEPARATORS = ("&", "&&", "\u2227")
_ESCAPE = re.compile(r"\\(.)")
_TRUE_CONJUNCTION = Conjunction(())


class _BadNumber(Exception):
    """A line that follows the grammar but holds a number that is no finite float."""

    def __init__(self, error: ParseError) -> None:
        super().__init__(str(error))
        self.error = error


def _scan_line(line: str, atoms_seen: dict) -> list[Conjunction] | None:
    """The conjunctions of one well-formed line, or None for the grammar to read (or refuse).
    ``atoms_seen``: atoms already made, shared (a rule file repeats its thresholds)."""
    if _BLANK_LINE.match(line):
        return []
    out: list[Conjunction] = []
    atoms: list[Atom] = []
    position, after_and = 0, False
    while True:
        match = _ATOM_TOKEN.match(line, position)
        if match is None:
            if after_and:
                return None
            match = _CONSTANT_TOKEN.match(line, position)
            if match is None:
                return None
            constant, separator = match.groups()
            if constant in ("true", "\u22a4"):
                out.append(_TRUE_CONJUNCTION)
        else:
            name, quoted, op, literal, separator = match.groups()
            key = (name, quoted, op, literal)
            atom = atoms_seen.get(key)
            if atom is None:
                if name is None:
                    name = _ESCAPE.sub(r"\1", quoted)
                elif name in _KEYWORDS:  # 'true < 1': the grammar says what is wrong
                    return None
                value = float(literal)
                if not math.isfinite(value):  # the grammar's reader reports it, after the line's syntax
                    return None
                atom = atoms_seen[key] = _checked_atom(name, _UNICODE_OPS.get(op, op), value + 0.0)
            atoms.append(atom)
        position = match.end()
        after_and = separator in _AND_SEPARATORS
        if after_and:
            continue
        if atoms:
            out.append(_checked_conjunction(tuple(atoms)))
            atoms = []
        if not separator or separator[0] == "#":  # end of the line
            return out


def _checked_atom(feature: str, op: str, value: float) -> Atom:
    """An :class:`Atom` whose fields the scanner has already checked (a name, one of :data:`OPS`,
    a finite float), made without ``__post_init__``'s checks again."""
    atom = object.__new__(Atom)
    object.__setattr__(atom, "feature", feature)
    object.__setattr__(atom, "op", op)
    object.__setattr__(atom, "value", value)
    return atom


def _checked_conjunction(atoms: tuple[Atom, ...]) -> Conjunction:
    conjunction = object.__new__(Conjunction)
    object.__setattr__(conjunction, "atoms", atoms)
    return conjunction


def _parse_line_with_grammar(line: str, number: int, last: bool, source: str | None) -> list[Conjunction]:
    """One line read by the lark grammar: errors located as if the whole text had been parsed
    (the line keeps its newline unless it is the last, so an unfinished line is reported as
    such), with the line number shifted to the line's own."""
    from lark.exceptions import UnexpectedInput

    text = line if last else line + "\n"
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as exc:
        error = _syntax_error(text, exc, source)
        raise ParseError(error.message, file=source, line=None if error.line is None else error.line + number - 1,
                         column=error.column, hint=error.hint) from None
    conjunctions: list[Conjunction] = []
    for tree_line in tree.children:
        for disjunction in tree_line.children:
            for conj in disjunction.children:
                if conj.data == "false":
                    continue
                if conj.data == "true":
                    conjunctions.append(Conjunction(()))
                    continue
                choices = []   # per atom, its alternatives: one, or two for '!='
                for node in conj.children:
                    try:
                        choices.append(_atom(node, source))
                    except ParseError as exc:
                        raise _BadNumber(ParseError(exc.message, file=source, line=exc.line + number - 1,
                                                    column=exc.column, hint=exc.hint)) from None
                split = sum(len(c) > 1 for c in choices)
                if split > MAX_NOT_EQUAL:
                    raise ParseError(f"{split} '!=' atoms in one conjunction split it into 2^{split} conjunctions; "
                                     f"at most {MAX_NOT_EQUAL} are read", file=source, line=number)
                conjunctions.extend(Conjunction(sum(picked, ())) for picked in itertools.product(*choices))
    return conjunctions


#: '!=' atoms one conjunction may hold (each doubles the conjunctions it becomes)
MAX_NOT_EQUAL = 10


def _atom(node, source: str | None) -> list[tuple[Atom, ...]]:
    """The atom's alternatives, each a tuple of atoms: ``x == 3`` is ``[(x >= 3, x <= 3)]``,
    ``x != 3`` is ``[(x < 3,), (x > 3,)]``, any other one atom ``[(atom,)]``."""
    feature_node, op_token, value_node = node.children
    name = str(feature_node.children[0])
    if feature_node.data == "quoted_name":
        name = re.sub(r"\\(.)", r"\1", name[1:-1])
    token = value_node.children[0]
    if value_node.data == "nonfinite":
        raise ParseError(f"bounds must be finite numbers, not {str(token)!r}", file=source, line=token.line,
                         column=token.column, hint="drop the atom: an infinite bound always or never holds")
    value = float(str(token))
    if not math.isfinite(value):
        raise ParseError(f"the number {str(token)} is too large for a float", file=source, line=token.line,
                         column=token.column)
    op = _UNICODE_OPS.get(str(op_token), str(op_token))
    if op == "==":
        return [(Atom(name, ">=", value), Atom(name, "<=", value))]
    if op in ("!=", "\u2260"):
        return [(Atom(name, "<", value),), (Atom(name, ">", value),)]
    return [(Atom(name, op, value),)]


_UNICODE_MINUSES = "\u2212\u2013\u2014\u2010\u2011\u2012\ufe63\uff0d"  # minus sign, dashes, hyphens

_TERMINALS = {
    "NAME": "a feature name", "QUOTED": "a quoted feature name", "OP": "a comparison (< <= > >= == !=)",
    "NUMBER": "a number", "_AND": "'&'", "_OR": "'|'", "_NL": "end of line", "TRUE": "true", "FALSE": "false",
    # the symbols are other spellings of true and false: named as those, not as lark's token names
    "TOP": "true", "BOTTOM": "false", "$END": "end of input",
}


def _syntax_error(text: str, exc, source: str | None) -> ParseError:
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

    lines = text.split("\n")
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        row = len(lines)
        col = len(lines[-1].split("#")[0].rstrip()) + 1
        what = "unexpected end of input"
    elif isinstance(exc, UnexpectedToken) and exc.token.type == "_NL":
        row, col = exc.line, exc.column
        what = "unexpected end of line"
    else:
        row, col = max(exc.line, 1), max(exc.column, 1)
        if isinstance(exc, UnexpectedCharacters):
            what = f"unexpected character {text[exc.pos_in_stream]!r}"
        else:
            what = f"unexpected {str(exc.token)!r}"
    expected_names = getattr(exc, "expected", None) or getattr(exc, "allowed", None) or ()
    expected = sorted({_TERMINALS.get(n, n.lower()) for n in expected_names if n not in ("QUOTED", "NONFINITE")})
    here = lines[row - 1] if 0 < row <= len(lines) else ""
    message = what
    if expected:
        message += "; expected " + (expected[0] if len(expected) == 1 else "one of " + ", ".join(expected))
    hint = None
    rest = here[col - 1:] if col - 1 < len(here) else ""
    if rest.startswith(("=", "!")):
        hint = "< <= > >= == != compare a feature with a number (== for equality)"
    elif rest.split()[:1] and rest.split()[0].lower() in ("and", "or"):
        hint = "write '&' between atoms and one conjunction per line (or '|' between conjunctions)"
    elif rest[:1] and rest[0] in _UNICODE_MINUSES:
        hint = "write the ASCII '-' for a minus sign"
    elif rest[:1] and (rest[0].isdigit() or rest[0] in "+-.") and "a feature name" in expected:
        # '1 < x': the grammar has the feature on the left only
        hint = "an atom is 'feature op number', the feature first: write x > 1 for 1 < x"
    return ParseError(message, file=source, line=row, column=col, hint=hint)
