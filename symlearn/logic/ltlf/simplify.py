"""Simplification of LTLf formulas (meaning preserved on every non-empty trace).

>>> from symlearn.logic.ltlf.parser import parse
>>> str(simplify(parse("F F a & (b | b) & true")))
'F a & b'
>>> str(simplify(parse("G G (a & (a | c)) | false")))
'G a'
>>> str(simplify(parse("(a & b) | (a & !b)"), propositional=True))
'a'

Rules, applied bottom-up until nothing changes: constants (``a & true``, ``F false``, ``X false``,
``WX true``, ``F true``, ``G false``, ``a U true``, ``false U b`` ...), double negation,
idempotence and complements in ``&``/``|`` chains (``a & a``, ``a & !a``), absorption
(``a & (a | b)``), ``F F a = F a``, ``G G a = G a``, ``true U b = F b``, ``false R b = G b``.
With ``propositional=True`` every maximal temporal-free part over at most 8 propositions is
replaced by sympy's minimal sum of products when that is shorter.

``F true`` and ``G false`` become ``true``/``false`` although they differ on the empty trace
(see :mod:`symlearn.logic.ltlf.semantics`); on non-empty traces every rule is an equivalence.
"""

from __future__ import annotations

from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release,
    Then, Until, WeakNext, WeakUntil, conjunction, disjunction, size, subformulas,
)

__all__ = ["simplify", "mk_and", "mk_or", "mk_not", "mk_iff"]

_SYMPY_LIMIT = 8


def mk_not(a: Formula) -> Formula:
    if isinstance(a, Const):
        return FALSE if a.value else TRUE
    if isinstance(a, Not):
        return a.arg
    return Not(a)


def _chain(formula: Formula, kind: type) -> list[Formula]:
    out, stack = [], [formula]
    while stack:
        node = stack.pop()
        if isinstance(node, kind):
            stack.append(node.right)
            stack.append(node.left)
        else:
            out.append(node)
    return out


def _junction(a: Formula, b: Formula, kind: type) -> Formula:
    unit, zero = (TRUE, FALSE) if kind is And else (FALSE, TRUE)
    dual = Or if kind is And else And
    items: list[Formula] = []
    seen: set[Formula] = set()
    for item in _chain(a, kind) + _chain(b, kind):
        if item == zero:
            return zero
        if item == unit or item in seen:
            continue
        seen.add(item)
        items.append(item)
    if any(mk_not(item) in seen for item in items):
        return zero
    # absorption: a & (a | b) = a, a | (a & b) = a
    kept = [item for item in items
            if not (isinstance(item, dual) and any(d in seen for d in _chain(item, dual)))]
    return (conjunction if kind is And else disjunction)(*kept)


def mk_and(a: Formula, b: Formula) -> Formula:
    return _junction(a, b, And)


def mk_or(a: Formula, b: Formula) -> Formula:
    return _junction(a, b, Or)


def mk_iff(a: Formula, b: Formula) -> Formula:
    if a == b:
        return TRUE
    for x, y in ((a, b), (b, a)):
        if isinstance(x, Const):
            return y if x.value else mk_not(y)
    if mk_not(a) == b:
        return FALSE
    return Iff(a, b)


def _rewrite(node: Formula, c: list[Formula]) -> Formula:
    if isinstance(node, (Const, Prop)):
        return node
    if isinstance(node, Not):
        return mk_not(c[0])
    if isinstance(node, Next):
        return FALSE if c[0] == FALSE else Next(c[0])
    if isinstance(node, WeakNext):
        return TRUE if c[0] == TRUE else WeakNext(c[0])
    if isinstance(node, Eventually):
        a = c[0]
        if isinstance(a, Const):
            return a
        return a if isinstance(a, Eventually) else Eventually(a)
    if isinstance(node, Always):
        a = c[0]
        if isinstance(a, Const):
            return a
        return a if isinstance(a, Always) else Always(a)
    a, b = c
    if isinstance(node, And):
        return mk_and(a, b)
    if isinstance(node, Or):
        return mk_or(a, b)
    if isinstance(node, Implies):
        if a == FALSE or b == TRUE or a == b:
            return TRUE
        if a == TRUE:
            return b
        if b == FALSE:
            return mk_not(a)
        return Implies(a, b)
    if isinstance(node, Iff):
        return mk_iff(a, b)
    if isinstance(node, Until):
        if isinstance(b, Const) or a == b or a == FALSE:
            return b
        return Eventually(b) if a == TRUE else Until(a, b)
    if isinstance(node, Release):
        if isinstance(b, Const) or a == b or a == TRUE:
            return b
        return Always(b) if a == FALSE else Release(a, b)
    if isinstance(node, WeakUntil):  # a W b = (a U b) | G a
        if b == TRUE or a == TRUE:
            return TRUE
        if a == FALSE or a == b:
            return b
        return Always(a) if b == FALSE else WeakUntil(a, b)
    if isinstance(node, Then):  # F(a & X F b)
        if a == FALSE or b == FALSE:
            return FALSE
        return Then(a, b)
    raise TypeError(f"not an LTLf formula node: {node!r}")


def _one_pass(formula: Formula) -> Formula:
    out: dict[int, Formula] = {}
    for node in subformulas(formula):
        out[id(node)] = _rewrite(node, [out[id(c)] for c in node.children()])
    return out[id(formula)]


def simplify(formula: Formula, *, propositional: bool = False) -> Formula:
    """A simpler formula with the same meaning on non-empty traces (never larger)."""
    current = formula
    for _ in range(50):  # each pass only shrinks; a handful suffices in practice
        nxt = _one_pass(current)
        if propositional:
            nxt = _minimise_propositional(nxt)
        if nxt == current:
            break
        current = nxt
    return current if size(current) <= size(formula) else formula


_TEMPORAL_TYPES = (Next, WeakNext, Eventually, Always, Until, Release, WeakUntil, Then)


def _minimise_propositional(formula: Formula) -> Formula:
    temporal_free: dict[int, bool] = {}
    for node in subformulas(formula):
        temporal_free[id(node)] = not isinstance(node, _TEMPORAL_TYPES) and all(
            temporal_free[id(c)] for c in node.children())
    out: dict[int, Formula] = {}
    for node in subformulas(formula):
        if temporal_free[id(node)] and not isinstance(node, (Prop, Const)):
            out[id(node)] = _sympy_minimal(node)
            continue
        children = [out[id(c)] for c in node.children()]
        if not children:
            out[id(node)] = node
        elif len(children) == 1:
            out[id(node)] = type(node)(children[0])
        else:
            out[id(node)] = type(node)(*children)
    return out[id(formula)]


def _sympy_minimal(node: Formula) -> Formula:
    from symlearn.logic.ltlf.ast import propositions

    names = sorted(propositions(node))
    if len(names) > _SYMPY_LIMIT:
        return node
    import sympy
    from sympy.logic import boolalg

    symbols = {n: sympy.Symbol(f"p{i}") for i, n in enumerate(names)}
    back = {v: k for k, v in symbols.items()}

    def to_sympy(f: Formula, cache: dict[int, object]):
        for sub in subformulas(f):
            c = [cache[id(x)] for x in sub.children()]
            if isinstance(sub, Const):
                cache[id(sub)] = sympy.true if sub.value else sympy.false
            elif isinstance(sub, Prop):
                cache[id(sub)] = symbols[sub.name]
            elif isinstance(sub, Not):
                cache[id(sub)] = sympy.Not(c[0])
            elif isinstance(sub, And):
                cache[id(sub)] = sympy.And(*c)
            elif isinstance(sub, Or):
                cache[id(sub)] = sympy.Or(*c)
            elif isinstance(sub, Implies):
                cache[id(sub)] = sympy.Implies(*c)
            else:
                cache[id(sub)] = sympy.Equivalent(*c)
        return cache[id(f)]

    expr = boolalg.simplify_logic(to_sympy(node, {}), form="dnf", force=True)

    def from_sympy(e) -> Formula:
        if e is sympy.true:
            return TRUE
        if e is sympy.false:
            return FALSE
        if isinstance(e, sympy.Symbol):
            return Prop(back[e])
        if isinstance(e, sympy.Not):
            return Not(from_sympy(e.args[0]))
        parts = [from_sympy(a) for a in sorted(e.args, key=str)]
        return (conjunction if isinstance(e, sympy.And) else disjunction)(*parts)

    candidate = from_sympy(expr)
    return candidate if size(candidate) < size(node) else node
