"""Hypothesis spaces: every rule the mode bias allows, each once up to variable renaming.

Generation, for each head choice (none for integrity constraints, else each ``#modeh`` atom):

1. choose a multiset of body modes (``#modeb``/``#modec``), at most ``max_body`` literals and each
   mode at most ``recall`` times;
2. fill the ``var(t)`` slots of head and body with variables: every *set partition* of the slots
   into same-typed groups, at most ``maxv`` groups (restricted-growth strings visit each partition
   once, which is exactly "each assignment once up to renaming");
3. fill ``const(t)`` slots with the ``#constant`` values of type ``t``;
4. keep rules that are safe (every global variable in a positive body atom, or bound by ``=``
   from bound variables; local variables of a conditional literal bound by its condition) and not
   trivially useless (a literal and its negation, ``X < X``, the head in its own body).

Only when a mode is used twice can two partitions describe the same rule with its literals in
another order. Such a rule is kept only when its partition is the smallest among those of the
same rule with the repeated literals reordered (each reordering's variables renumbered by first
occurrence): a few reorderings per rule (at most ``max_body!``) instead of every renaming of up
to ``#maxv`` variables (``8! = 40320``), which made ``#maxv 8`` with two 4-ary modes take minutes.
Rules such as ``:- on(V1,V2), V1 < V2.`` and ``:- on(V1,V2), V2 < V1.`` (not renamings of each
other) both stay in the space.

Generation shows a progress bar (:mod:`symlearn.progress`) and stops with
:class:`~symlearn.errors.LimitExceededError` when ``timeout`` runs out.
"""

from __future__ import annotations

import itertools
import math
import time
from collections import Counter
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from symlearn.errors import LimitExceededError, SymlearnError
from symlearn.logic.ilp.modes import ModeAtom, ModeComparison, ModeDeclaration, ModeFunction, Placeholder, render_mode
from symlearn.logic.ilp.task import ILPTask
from symlearn.progress import progress

DEFAULT_SPACE_LIMIT = 200_000
#: head and body-mode multisets the generator may look at (each is expanded into its rules)
MAX_SHAPES = 2_000_000


@dataclass(frozen=True)
class BodyLiteral:
    """A filled-in body literal: ``kind`` is ``atom``, ``cmp`` or ``cond``."""

    kind: str
    text: str  # atom text (without "not"), or the comparison
    negated: bool = False
    condition: tuple[str, ...] = ()  # atoms of a conditional literal's condition

    def render(self) -> str:
        lit = ("not " if self.negated else "") + self.text
        return f"{lit} : {', '.join(self.condition)}" if self.kind == "cond" else lit

    def length(self) -> int:
        return 1 + len(self.condition)

    def tagged(self, tag: str) -> str:
        """The literal inside example copy ``tag`` (see :mod:`symlearn.logic.ilp.encoding`)."""
        if self.kind == "cmp":
            return self.text
        lit = ("not " if self.negated else "") + _tag_atom(self.text, tag)
        if self.kind == "cond":
            return f"{lit} : {', '.join(_tag_atom(c, tag) for c in self.condition)}"
        return lit


def _tag_atom(atom: str, tag: str) -> str:
    name, paren, rest = atom.partition("(")
    return f"{name}({tag},{rest}" if paren else f"{name}({tag})"


@dataclass(frozen=True)
class Candidate:
    """One rule of the hypothesis space."""

    index: int
    head: str | None  # None for an integrity constraint
    body: tuple[BodyLiteral, ...]
    length: int
    cost: int = 0  # length, or the #bias penalty

    @property
    def text(self) -> str:
        body = ""
        for i, b in enumerate(self.body):  # after a conditional literal "," would extend its condition
            body += ("" if i == 0 else "; " if self.body[i - 1].kind == "cond" else ", ") + b.render()
        if self.head is None:
            return f":- {body}."
        return f"{self.head} :- {body}." if body else f"{self.head}."

    @property
    def is_constraint(self) -> bool:
        return self.head is None

    def tagged_rule(self, tag: str, guards: tuple[str, ...] = ()) -> str:
        """This rule inside example copy ``tag``, with extra ``guards`` in the body."""
        body = "; ".join([b.tagged(tag) for b in self.body] + list(guards))
        head = "" if self.head is None else _tag_atom(self.head, tag)
        return f"{head} :- {body}." if body else f"{head}."


@dataclass
class HypothesisSpace:
    candidates: list[Candidate]
    truncated: bool = False
    notes: list[str] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.candidates)

    def __iter__(self) -> Iterator[Candidate]:
        return iter(self.candidates)


# -- filling templates -----------------------------------------------------------------------------

def _slots(term, out: list[Placeholder]) -> None:
    if isinstance(term, Placeholder):
        out.append(term)
    elif isinstance(term, ModeFunction):
        for a in term.args:
            _slots(a, out)


def _fill(term, values: Iterator[str]) -> str:
    if isinstance(term, Placeholder):
        return next(values)
    if isinstance(term, ModeFunction):
        return term.name + (f"({','.join(_fill(a, values) for a in term.args)})" if term.args else "")
    return term.text  # Literal_


def _atom_text(atom: ModeAtom, values: Iterator[str]) -> str:
    return atom.name + (f"({','.join(_fill(a, values) for a in atom.args)})" if atom.args else "")


def _literal_slots(literal) -> list[Placeholder]:
    out: list[Placeholder] = []
    if isinstance(literal, ModeAtom):
        for a in literal.args:
            _slots(a, out)
    elif isinstance(literal, ModeComparison):
        for t in (literal.left, literal.right, literal.right2):
            if t is not None:
                _slots(t, out)
    else:
        out.extend(_literal_slots(literal.literal))
        for c in literal.condition:
            out.extend(_literal_slots(c))
    return out


@dataclass
class _Filled:
    literal: BodyLiteral
    positive_vars: set[str]  # variables bound by this literal (positive atom)
    all_vars: set[str]
    cond_local: set[str] = field(default_factory=set)  # vars bound inside a conditional's condition
    assign: tuple[str, set[str]] | None = None  # "V = expr": (V, vars of expr)


def _instantiate(literal, values: list[str], kinds: list[str]) -> _Filled:
    it = iter(values)
    var_of = [v for v, k in zip(values, kinds) if k == "var"]
    if isinstance(literal, ModeAtom):
        text = _atom_text(literal, it)
        vs = set(var_of)
        return _Filled(BodyLiteral("atom", text, literal.negated), set() if literal.negated else vs, vs)
    if isinstance(literal, ModeComparison):
        left = _fill(literal.left, it)
        right = _fill(literal.right, it)
        if literal.arith_op:
            right = f"{right}{literal.arith_op}{_fill(literal.right2, it)}"
        text = f"{left} {literal.op} {right}"
        vs = set(var_of)
        assign = None
        if literal.op == "=" and isinstance(literal.left, Placeholder) and literal.left.kind == "var":
            assign = (left, vs - {left})
        return _Filled(BodyLiteral("cmp", text), set(), vs, assign=assign)
    # conditional literal
    n_lit = len(_literal_slots(literal.literal))
    lit_values, lit_kinds = values[:n_lit], kinds[:n_lit]
    lit_text = _atom_text(literal.literal, iter(lit_values))
    rest = iter(values[n_lit:])
    cond = tuple(_atom_text(c, rest) for c in literal.condition)
    cond_vars = {v for v, k in zip(values[n_lit:], kinds[n_lit:]) if k == "var"}
    lit_vars = {v for v, k in zip(lit_values, lit_kinds) if k == "var"}
    return _Filled(BodyLiteral("cond", lit_text, literal.literal.negated, cond), set(), lit_vars | cond_vars,
                   cond_local=cond_vars)


def _partitions(types: Sequence[str], max_blocks: int) -> Iterator[list[int]]:
    """Restricted-growth strings over ``types``: slot i gets block b[i]; blocks hold one type."""
    n = len(types)
    assignment = [0] * n
    block_type: list[str] = []

    def rec(i: int) -> Iterator[list[int]]:
        if i == n:
            yield list(assignment)
            return
        for b, t in enumerate(block_type):
            if t == types[i]:
                assignment[i] = b
                yield from rec(i + 1)
        if len(block_type) < max_blocks:
            block_type.append(types[i])
            assignment[i] = len(block_type) - 1
            yield from rec(i + 1)
            block_type.pop()

    yield from rec(0)


# -- the generator -------------------------------------------------------------------------------

def _body_modes(task: ILPTask) -> tuple[list[ModeDeclaration], list[int]]:
    """Body modes with their recall group. ILASP dialect: an atom mode without ``(positive)``
    may also be used negated (both polarities share the recall). FastLAS dialect: as written."""
    modes: list[ModeDeclaration] = []
    groups: list[int] = []
    as_written = task.dialect == "fastlas"
    for group, mode in enumerate(task.modeb + task.modec):
        modes.append(mode)
        groups.append(group)
        lit = mode.literal
        if mode.kind == "b" and isinstance(lit, ModeAtom) and not lit.negated and not mode.positive and not as_written:
            modes.append(ModeDeclaration("b", ModeAtom(lit.name, lit.args, True), mode.recall, False,
                                         mode.line, mode.column))
            groups.append(group)
    return modes, groups


def _first_occurrence(blocks: Sequence[int]) -> tuple[int, ...]:
    """Renumber blocks in order of first occurrence (the restricted-growth form)."""
    names: dict[int, int] = {}
    return tuple(names.setdefault(b, len(names)) for b in blocks)


class _Generator:
    def __init__(self, task: ILPTask, max_body: int, limit: int, deadline: float = math.inf) -> None:
        self.task = task
        self.max_body = max_body
        self.limit = limit
        self.deadline = deadline
        self._ticks = 0
        self.body_modes, self.groups = _body_modes(task)
        # body modes whose literal reads like another mode's once types are dropped (a mode
        # declared twice, or for two types): their rules may coincide up to renaming across
        # different mode multisets, which only the full canonical form detects (rare, slow)
        shapes = Counter(_shape(m.literal) for m in self.body_modes)
        self.ambiguous = {i for i, m in enumerate(self.body_modes) if shapes[_shape(m.literal)] > 1}
        self.notes: list[str] = []
        self.seen: set[tuple] = set()
        self.rules: list[tuple[str | None, tuple[BodyLiteral, ...]]] = []
        self.truncated = False
        for mode in self.body_modes + task.modeh:
            for slot in _literal_slots(mode.literal):
                if slot.kind == "const" and not task.constants.get(slot.type):
                    self.notes.append(f"{mode} uses const({slot.type}) but the task declares no "
                                      f"#constant({slot.type}, ...); the mode generates no literal")

    def body_multisets(self) -> Iterator[tuple[int, ...]]:
        modes = self.body_modes
        for size in range(0, self.max_body + 1):
            for combo in itertools.combinations_with_replacement(range(len(modes)), size):
                counts = Counter(self.groups[m] for m in combo)  # recall counts both polarities of a mode
                recall = {self.groups[m]: modes[m].recall for m in combo}
                if all(recall[g] is None or c <= recall[g] for g, c in counts.items()):
                    yield combo

    def generate(self) -> None:
        heads: list[ModeDeclaration | None] = list(self.task.modeh) if self.task.modeh else [None]
        # Shapes are enumerated lazily and counted: a bias of 20,000 #modeb allows ~10^12 of
        # them, which listing first (as before) took minutes and gigabytes before any limit could
        # apply. ``total`` is the count without recalls (an upper bound, for the bar only).
        n_modes = len(self.body_modes)
        total = len(heads) * sum(math.comb(n_modes + size - 1, size) for size in range(self.max_body + 1))
        shapes = ((head, combo) for head in heads for combo in self.body_multisets() if head is not None or combo)
        for count, (head, combo) in enumerate(progress(shapes, total=total, desc="hypothesis space", unit="shapes"), 1):
            if count > MAX_SHAPES:
                raise LimitExceededError(f"the mode bias allows more than {MAX_SHAPES:,} rule shapes ({n_modes} body "
                                         f"modes, up to {self.max_body} body literals)", file=self.task.source,
                                         hint="declare fewer #modeb, lower their recalls or max_body")
            self._check_time()
            self._expand(head, combo)
            if self.truncated:
                return

    def _check_time(self) -> None:
        self._ticks += 1
        if self._ticks % 512 == 0 and time.perf_counter() > self.deadline:
            raise LimitExceededError(f"time limit reached while generating the hypothesis space "
                                     f"({len(self.rules)} rules so far)", file=self.task.source,
                                     hint="raise the timeout, or lower #maxv, the recalls or max_body")

    def _reorderings(self, head: ModeDeclaration | None, combo: tuple[int, ...],
                     slot_lists: list[list[Placeholder]]) -> list[tuple[list[int], list[int]]]:
        """(var slot order, const slot order) for every reordering of equal body literals other
        than the identity; empty when no literal template repeats."""
        offset = 1 if head is not None else 0
        templates = [self.body_modes[m].literal for m in combo]
        groups: dict[object, list[int]] = {}
        for position, template in enumerate(templates):
            groups.setdefault(template, []).append(position)
        movable = [g for g in groups.values() if len(g) > 1]
        if not movable:
            return []
        # indices of each literal's var and const slots in the flat (var-only / const-only) orders
        var_index: list[list[int]] = []
        const_index: list[list[int]] = []
        n_var = n_const = 0
        for slots in slot_lists:
            var_index.append([])
            const_index.append([])
            for slot in slots:
                if slot.kind == "var":
                    var_index[-1].append(n_var)
                    n_var += 1
                else:
                    const_index[-1].append(n_const)
                    n_const += 1
        orders = []
        for choice in itertools.product(*(itertools.permutations(g) for g in movable)):
            order = list(range(len(templates)))
            for group, permuted in zip(movable, choice):
                for at, position in zip(group, permuted):
                    order[at] = position
            if order == list(range(len(templates))):
                continue
            literals = list(range(offset)) + [offset + p for p in order]
            orders.append(([i for lit in literals for i in var_index[lit]],
                           [i for lit in literals for i in const_index[lit]]))
        return orders

    def _expand(self, head: ModeDeclaration | None, combo: tuple[int, ...]) -> None:
        literals = ([head.literal] if head else []) + [self.body_modes[m].literal for m in combo]
        slot_lists = [_literal_slots(lit) for lit in literals]
        flat = [s for slots in slot_lists for s in slots]
        var_types = [s.type for s in flat if s.kind == "var"]
        const_choices = [self.task.constants.get(s.type, []) for s in flat if s.kind == "const"]
        if any(not c for c in const_choices):
            return
        reorderings = self._reorderings(head, combo, slot_lists)
        full_canonical = len(combo) > 1 and any(m in self.ambiguous for m in combo)
        for partition in _partitions(var_types, self.task.n_variables):
            for consts in itertools.product(*const_choices) if const_choices else [()]:
                self._check_time()
                if reorderings:
                    own = (tuple(partition), tuple(str(c) for c in consts))
                    if any((_first_occurrence([partition[i] for i in var_order]),
                            tuple(str(consts[i]) for i in const_order)) < own
                           for var_order, const_order in reorderings):
                        continue  # the same rule comes (came) with its repeated literals in another order
                self._build(head, literals, slot_lists, partition, [str(c) for c in consts], full_canonical)
                if self.truncated:
                    return

    def _build(self, head, literals, slot_lists, partition, consts, full_canonical=False) -> None:
        var_iter = iter(f"V{b + 1}" for b in partition)
        const_iter = iter(consts)
        filled: list[_Filled] = []
        for lit, slots in zip(literals, slot_lists):
            values = [next(var_iter) if s.kind == "var" else next(const_iter) for s in slots]
            kinds = [s.kind for s in slots]
            if head is not None and lit is literals[0] and not filled:
                head_text = _atom_text(lit, iter(values))
                filled.append(_Filled(BodyLiteral("atom", head_text), set(), {v for v, k in zip(values, kinds) if k == "var"}))
                continue
            filled.append(_instantiate(lit, values, kinds))
        head_filled = filled[0] if head is not None else None
        body = filled[1:] if head is not None else filled
        if not self._useful(head_filled, body):
            return
        head_text = head_filled.literal.text if head_filled else None
        body_lits = tuple(f.literal for f in body)
        key = _canonical(head_text, body_lits) if full_canonical else \
            (head_text, tuple(sorted(lit.render() for lit in body_lits)))
        if key in self.seen:
            return
        self.seen.add(key)
        self.rules.append((head_text, body_lits))
        if len(self.rules) >= self.limit:
            self.truncated = True

    @staticmethod
    def _useful(head: _Filled | None, body: list[_Filled]) -> bool:
        texts = [b.literal.render() for b in body]
        if len(set(texts)) < len(texts):
            return False
        atoms_pos = {b.literal.text for b in body if b.literal.kind == "atom" and not b.literal.negated}
        atoms_neg = {b.literal.text for b in body if b.literal.kind == "atom" and b.literal.negated}
        if atoms_pos & atoms_neg:
            return False
        if head is not None and head.literal.text in atoms_pos:
            return False
        for b in body:
            if b.literal.kind == "cmp":
                parts = b.literal.text.split(" ")
                if len(parts) == 3 and parts[0] == parts[2]:
                    return False  # V < V, V = V, ...
        # safety: global variables = those outside conditional literals
        bound: set[str] = set()
        for b in body:
            bound |= b.positive_vars
        changed = True
        while changed:
            changed = False
            for b in body:
                if b.assign and b.assign[0] not in bound and b.assign[1] <= bound:
                    bound.add(b.assign[0])
                    changed = True
        global_vars: set[str] = set()
        for b in body:
            if b.literal.kind != "cond":
                global_vars |= b.all_vars
        if head is not None:
            global_vars |= head.all_vars
        if not global_vars <= bound:
            return False
        for b in body:
            if b.literal.kind == "cond":
                local = b.all_vars - global_vars
                if not local <= b.cond_local:
                    return False
        return True


def _shape(literal) -> str:
    """A mode literal with its placeholder types dropped: ``p(var,const)``."""
    import re

    return re.sub(r"\b(var|const)\([^()]*\)", r"\1", render_mode(literal))


def _rename(text: str, mapping: dict[str, str]) -> str:
    import re

    return re.sub(r"\bV\d+\b", lambda m: mapping.get(m.group(0), m.group(0)), text)


def _canonical(head: str | None, body: tuple[BodyLiteral, ...]) -> tuple:
    """The rule's form minimised over all variable renamings (the sorted literal texts): the slow
    path, only for modes that read alike (see ``_Generator.ambiguous``)."""
    import re

    names = sorted({v for lit in body for v in re.findall(r"\bV\d+\b", lit.render())}
                   | (set(re.findall(r"\bV\d+\b", head)) if head else set()))
    best = None
    for perm in itertools.permutations(names):
        mapping = {old: f"_{new}" for old, new in zip(names, perm)}
        form = ((_rename(head, mapping) if head else None),
                tuple(sorted(_rename(lit.render(), mapping) for lit in body)))
        if best is None or form < best:
            best = form
    return best


def _reading_order(literal: BodyLiteral) -> int:
    """Positive atoms first, then negated atoms, comparisons, conditional literals (stable)."""
    if literal.kind == "atom":
        return 1 if literal.negated else 0
    return 2 if literal.kind == "cmp" else 3


def generate_space(task: ILPTask, *, max_body: int | None = None, limit: int = DEFAULT_SPACE_LIMIT,
                   on_limit: str = "raise", timeout: float | None = None) -> HypothesisSpace:
    """All candidate rules of ``task``'s mode bias (see module docstring), scored by length or #bias.

    ``timeout`` (seconds, None: none) bounds the generation: past it, LimitExceededError."""
    if not task.modeb and not task.modec and not task.modeh:
        raise SymlearnError("the task declares no #modeh, #modeb or #modec: the hypothesis space is empty",
                            file=task.source, hint="add mode declarations such as #modeb(1, p(var(t))).")
    deadline = math.inf if timeout is None or math.isnan(timeout) else time.perf_counter() + timeout
    generator = _Generator(task, task.max_body if max_body is None else max_body, limit, deadline)
    generator.generate()
    if generator.truncated and on_limit == "raise":
        raise LimitExceededError(f"the hypothesis space has more than {limit} rules",
                                 file=task.source, hint="lower #maxv, the recalls or max_body, or raise the limit")
    candidates = []
    for i, (head, body) in enumerate(generator.rules):
        body = tuple(sorted(body, key=_reading_order))
        length = (0 if head is None else 1) + sum(b.length() for b in body)
        candidates.append(Candidate(i, head, body, length, length))
    space = HypothesisSpace(candidates, generator.truncated, generator.notes)
    if task.bias:
        from symlearn.logic.ilp.scoring import apply_bias

        space = apply_bias(task, space)
    return space
