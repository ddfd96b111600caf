"""Compositional LTLf -> DFA: a minimal DFA per part of the formula's Boolean skeleton, joined by
products that are minimised as they are built.

Progression (:mod:`~symlearn.logic.ltlf.to_dfa`) explores the obligations of the whole formula at
once. When the top of a formula is a Boolean combination of parts that share propositions, the
obligations multiply before minimisation can merge them: the 18 conjuncts ``G F a -> G F b`` and
``G !(b & c)`` of a Random/Lydia specification of SYNTCOMP's ``tlsf-fin`` set give thousands of
obligation sets and a 30 s timeout, for a minimal DFA of 3 states. Built part by part, each part's
DFA is minimal before it enters a product, and each product is minimised before the next one, so
the intermediate automata stay near the size of the result (how MONA, Lydia and LydiaSyft stay
ahead on those families).

The skeleton is read down from the top: ``&`` and ``|`` (flattened, n-ary), ``->``, ``<->`` and
``!`` over one of these. Everything else -- a temporal operator, a proposition -- is a *leaf*,
translated by progression. Languages combine exactly (the empty word included: its verdict,
:func:`~symlearn.logic.ltlf.progression.holds_at_end`, is itself Boolean in the parts), so the
result is the same unique minimal DFA progression gives, numbered the same canonical way.

When the parts of a junction are pairwise *independent* (no shared proposition), products have
nothing to merge and progression builds the same automaton faster: ``F p1 & ... & F p14`` (16,384
states) stays one progression, as do its refusals from a proven state bound
(:mod:`~symlearn.logic.ltlf.conjunct_bound`). Parts are grouped by shared propositions
(connected components); the independent single parts of a junction are translated together by
progression, each group of dependent parts by products, and the groups' DFAs joined smallest
first (the order Lydia uses). ``max_states`` bounds every product before minimisation, as it
bounds the obligations of a progression.

Two rewrites reach below the Boolean top. A leaf that is a chain of ``G``/``X``/``WX`` over a
conjunction (or of ``F``/``X``/``WX`` over a disjunction) of dependent parts is distributed when
progression of the leaf fails its trial: ``X[!] G (r1 & ... & r40)``, a double counter's rules,
becomes forty small parts. And a part joined to its start conditions that is itself a composite
skeleton is progressed whole only within :data:`JOINED_NODES`, then composed with its conditions
apart, their DFAs joining the enclosing conjunction's products one by one (a composite part is
joined only to the conditions it reads at the first letter: the others cannot restrict it); the
measurements that chose these are in ``docs/BENCHMARKS.md`` (issue 27).

An assumption joins its guarantee's products. ``A -> G`` is ``!A | G``, which is also
``!A | (A & G)``; when ``G`` is composed from parts, ``A``'s DFA is one more member of the
products of every group of parts it shares a proposition with, so they only follow what the
assumption allows. A specification's guarantees, built alone, can grow past what the assumption
lets happen: SYNTCOMP's Syft ``145`` built a 260-state guarantee that the assumption's complement
then made universal (53 ms of its 137); with the assumption in its products, 27 ms in all.
"""

from __future__ import annotations

from collections.abc import Callable

from symlearn.errors import LimitExceededError
from symlearn.logic.automata import transition_diagram as td
from symlearn.logic.automata.dfa import DFA
from symlearn.logic.automata.operations import complement
from symlearn.logic.ltlf.ast import (Always, And, Binary, Const, Eventually, Formula, Iff, Implies, Next, Not, Or,
                                     Prop, Then, Unary, WeakNext)


def _all_children(node: Formula) -> tuple:
    """Every operand (a junction chain's operands at once)."""
    return (node.arg,) if isinstance(node, Unary) else \
        _operands(node) if isinstance(node, (And, Or)) else \
        (node.left, node.right) if isinstance(node, Binary) else ()


def _first_letter_children(node: Formula) -> tuple:
    """The operands read at the first letter: none under ``X``/``WX``, only the left of ``T``."""
    return () if isinstance(node, (Next, WeakNext)) else \
        (node.left,) if isinstance(node, Then) else \
        _operands(node) if isinstance(node, (And, Or)) else node.children()


def _propositions_below(formula: Formula, memo: dict[int, frozenset[str]], children_of) -> frozenset[str]:
    """The propositions reachable from ``formula`` through ``children_of``, memoised by node id in
    ``memo`` (children before parents, without recursion: TLSF formulas are deep)."""
    stack = [formula]
    while stack:
        node = stack[-1]
        if id(node) in memo:
            stack.pop()
            continue
        children = children_of(node)
        waiting = [c for c in children if id(c) not in memo]
        if waiting:
            stack += waiting
            continue
        stack.pop()
        if isinstance(node, Prop):
            memo[id(node)] = frozenset((node.name,))
        else:
            memo[id(node)] = frozenset().union(*(memo[id(c)] for c in children))
    return memo[id(formula)]

__all__ = ["compose", "is_composite"]

Direct = Callable[..., DFA]  # direct(formula, max_states, max_nodes=None, first_nodes=None): progression

#: a composite formula is first given to progression within these bounds: small formulas (the
#: LTLf learning benchmark's, Dwyer's patterns) finish there, 1.5-5x faster than through products
#: of their parts; past them, progression is dropped for composition (measured on tlsf-fin and
#: our formula set, docs/BENCHMARKS.md). A failed trial's time is lost, and it is spent mostly on
#: the first state (the one-step unfolding of the whole formula), so the node bound is just above
#: what the largest successful trial of our formula set needs (10,195 nodes): a failure then costs
#: ~10 ms, not the ~100 ms of the former 100,000 (benchmarks/ltlf_trial_budget.py)
TRIAL_STATES = 256
TRIAL_NODES = 12_000
#: ... and of those nodes, the first state (with the steps of the formula's temporal nodes it is
#: built from) may take at most this many: the largest first state of a successful trial on our
#: formula set and the tlsf-fin sample takes 2,755 (a single counter's), while most failures run
#: out of the whole budget before their first state is done, so they now stop at a third of it
TRIAL_FIRST_NODES = 4_000
#: a composite part joined to its start conditions is progressed whole within this many BDD nodes
#: (a fifth of the default translation limit) before it is composed instead: SYNTCOMP's Nim games
#: finish whole within it (nim_pb_02_07: 235 states, under 1,000,000 nodes, 5 s; composed, over
#: 60 s), its double counters do not (the 5-bit one ran to the 5,000,000-node limit, 14-57 s, before
#: being composed)
JOINED_NODES = 1_000_000
#: ... of which its first state may take this many: the Nim games that finish whole need up to
#: 120,483 for it (nim_pb_02_07; 48,911 for nim_pb_03_03), while the double counters run out of
#: the whole million before their first state is done (1.6 s lost on countersDouble_pb_05)
JOINED_FIRST_NODES = 300_000

_ACCEPT = {
    "and": lambda a, b: a and b,
    "or": lambda a, b: a or b,
    "iff": lambda a, b: a == b,
}


def is_composite(formula: Formula) -> bool:
    """Whether ``formula``'s top is a Boolean combination whose parts share a proposition (the
    case composition is for); otherwise progression translates it whole."""
    return _Composer(None, 0).composite(formula)


def compose(formula: Formula, direct: Direct, max_states: int) -> DFA:
    """The minimal complete DFA of ``formula``: leaves (and independent junctions) by ``direct``
    (progression), the Boolean skeleton above them by minimised products.

    The bounded trial comes first, before the skeleton is read: nearly every formula a learner
    translates finishes there, and reading the skeleton (its parts' propositions) cost ~25 us of
    their ~0.5 ms. A formula that is not composite and fails the trial is progressed unbounded."""
    result = _Composer(direct, max_states).dfa(formula, trial_first=True)
    if result.is_symbolic():  # products stay symbolic (_product): listed edges where they are few
        diagram, roots = result.transition_diagram()
        accepting = result.accepting
        result = td.finish(diagram, roots, [q in accepting for q in range(result.n_states)], result.initial,
                           result.alphabet)
    return result


class _Composer:
    """One composition: the propositions and verdicts of sub-formulas are memoised by identity,
    so a deep skeleton is read in time linear in its size."""

    def __init__(self, direct: Direct | None, max_states: int) -> None:
        self.direct = direct
        self.max_states = max_states
        self.props: dict[int, frozenset[str]] = {}
        self.first_props: dict[int, frozenset[str]] = {}  # read at the first letter (first_letter_propositions)
        self.verdicts: dict[int, bool] = {}
        self.spread: dict[int, Formula] = {}  # distributed forms, by the identity of the original
        self.unjoined: dict[int, tuple[Formula, list[Formula]]] = {}  # a part joined to its start conditions

    def composite(self, formula: Formula) -> bool:
        found = self.verdicts.get(id(formula))
        if found is None:
            if isinstance(formula, Not):
                found = self.composite(formula.arg)
            elif isinstance(formula, (Implies, Iff)):
                found = bool(self.propositions(formula.left) & self.propositions(formula.right)) or \
                    self.composite(formula.left) or self.composite(formula.right)
            elif isinstance(formula, (And, Or)):
                parts = _operands(formula)
                found = any(len(g) > 1 for g in self.groups(parts)) or any(self.composite(p) for p in parts)
            else:
                found = False
            self.verdicts[id(formula)] = found
        return found

    def dfa(self, formula: Formula, trial_first: bool = False, under: DFA | None = None) -> DFA:
        """The formula's DFA. A part (``trial_first`` false) that is not composite is progressed
        at once, without a trial it would mostly fail; the whole formula is tried first.

        With ``under`` (the DFA of an assumption ``A`` of ``A -> formula``) the result may be
        the DFA of ``under & formula`` instead: both give the same ``!A | ...``."""
        distributable = self.distributable(formula)
        if not trial_first and not self.composite(formula) and not distributable:
            return self.progressed(formula)
        try:
            return self.direct(formula, min(self.max_states, TRIAL_STATES), TRIAL_NODES, TRIAL_FIRST_NODES)
        except LimitExceededError:
            if not self.composite(formula) and not distributable:  # (a refusal within the trial's bounds comes again, as fast)
                return self.progressed(formula)
        # too large for progression of the whole: compose its parts
        formula = self.distributed(formula) if distributable else formula
        if isinstance(formula, Not):
            return complement(self.dfa(formula.arg))
        if isinstance(formula, Implies):
            assumption = self.dfa(formula.left)
            return self.join([complement(assumption), self.dfa(formula.right, under=assumption)], "or")
        if isinstance(formula, Iff):
            return self.join([self.dfa(formula.left), self.dfa(formula.right)], "iff")
        mode = "and" if isinstance(formula, And) else "or"
        parts = _operands(formula)
        if mode == "and":
            parts = self.attach_state_conditions(parts)
        groups = self.groups(parts)
        # parts sharing nothing with the others and composite in nothing: one progression
        loose = [parts[g[0]] for g in groups if len(g) == 1 and not self.composite(parts[g[0]])]
        dfas = []
        if len(loose) == 1:
            dfas.append(self.progressed(loose[0]))
        elif loose:
            dfas.append(self.direct(_rebuild(loose, And if mode == "and" else Or), self.max_states))
        for group in groups:
            if len(group) > 1 or self.composite(parts[group[0]]):
                members = []
                for i in group:
                    members += self.conjuncts(parts[i]) if mode == "and" else [self.dfa(parts[i])]
                if under is not None and mode == "and" and under.alphabet & frozenset().union(
                        *(m.alphabet for m in members)):
                    members.append(under)
                dfas.append(self.join(members, mode))
        return self.join(dfas, mode)

    def progressed(self, formula: Formula) -> DFA:
        """Progression of a part that is not composite. A part that is a composite skeleton joined
        to its start conditions (:meth:`attach_state_conditions`) falls back to composing the
        skeleton and the conditions separately when progression of the whole runs out of nodes:
        a Nim game's assumption -> rules progress with their start in 5 s, a double counter's
        do not within :data:`JOINED_NODES` and compose."""
        found = self.unjoined.get(id(formula))
        if found is None:
            return self.direct(formula, self.max_states)
        return self.join(self.unjoined_conjuncts(formula, *found), "and")

    def conjuncts(self, formula: Formula) -> list[DFA]:
        """DFAs whose product is ``formula``'s: a part joined to its start conditions that falls
        back to composition gives its skeleton's and its conditions' DFAs apart, so that the
        conjunction it is in multiplies them with its other parts smallest first. Joined
        first, each tiny condition met the skeleton's large DFA in a product of its own:
        countersDouble_pb_05 multiplied its 4,038-state part by a 3-state condition (0.6 s),
        then the result by the product of the other small parts."""
        found = self.unjoined.get(id(formula))
        if found is None or self.distributable(formula):
            return [self.dfa(formula)]
        return self.unjoined_conjuncts(formula, *found)

    def unjoined_conjuncts(self, formula: Formula, part: Formula, conditions: list[Formula]) -> list[DFA]:
        try:
            return [self.direct(formula, self.max_states, JOINED_NODES, JOINED_FIRST_NODES)]
        except LimitExceededError:
            return [self.dfa(part), *(self.dfa(c) for c in conditions)]

    def distributable(self, formula: Formula) -> bool:
        """Whether ``formula`` is a leaf whose temporal chain distributes over a junction of
        dependent parts: composed like a skeleton when progression of it fails the trial (a Nim
        game's rules, with their start, progress faster whole than as products of their parts)."""
        spread = self.distributed(formula)
        return spread is not formula and self.composite(spread)

    def distributed(self, formula: Formula) -> Formula:
        """``formula`` with a chain of ``G``/``X``/``WX`` over a conjunction pushed into it, or of
        ``F``/``X``/``WX`` over a disjunction: ``X[!] G (a & b)`` is ``X[!] G a & X[!] G b`` (each
        of these operators distributes over that junction on finite traces too), so the
        conjuncts of a large ``G (...)`` become parts of the skeleton -- a game's rules, e.g. the
        40 carry and bit rules of SYNTCOMP's double counters, each a small DFA, instead of one
        leaf whose obligations multiply in progression. Anything else is returned as it is."""
        found = self.spread.get(id(formula))
        if found is not None:
            return found
        chain, core = [], formula
        while isinstance(core, (Always, Eventually, Next, WeakNext)):
            chain.append(type(core))
            core = core.arg
        result = formula
        if chain and isinstance(core, (And, Or)):
            over = {Always, Next, WeakNext} if isinstance(core, And) else {Eventually, Next, WeakNext}
            if all(kind in over for kind in chain):
                parts = []
                for part in _operands(core):
                    for kind in reversed(chain):
                        part = kind(part)
                    parts.append(part)
                result = _rebuild(parts, type(core))
        self.spread[id(formula)] = result
        self.spread[id(result)] = result
        return result

    def attach_state_conditions(self, parts: list[Formula]) -> list[Formula]:
        """Conjuncts without a temporal operator (conditions on the first letter, such as a game's
        initial position) joined to every temporal conjunct they share a proposition with:
        ``(A & c) & (B & c)`` is ``A & B & c``, and progression of ``A & c`` explores only what
        follows a first letter satisfying ``c`` -- alone, the ``G(...)`` rules of a Nim game
        reach every position (273 states, 4.3 s), with their start 235 in 3.0 s."""
        conditions = [p for p in parts if self.state_condition(p)]
        if not conditions or len(conditions) == len(parts):
            return parts
        condition_ids = {id(c) for c in conditions}
        joined, used = [], set()
        for part in parts:
            if id(part) in condition_ids:
                continue
            mine = [c for c in conditions if self.propositions(c) & self.propositions(part)]
            composite = self.composite(part) or self.distributable(part)
            if composite:
                # joined, a composite part is progressed whole before it is composed: worth it
                # only where its conditions restrict it (first_letter_propositions)
                mine = [c for c in mine if self.propositions(c) & self.first_letter_propositions(part)]
            if mine:
                used.update(id(c) for c in mine)
                original, part = part, _rebuild([part, *mine], And)
                # one progression: composed, the part would lose its start again (and a composite
                # part, taken apart, would meet its conditions here once more); where that
                # progression runs out of nodes, the part and its conditions are composed instead
                self.verdicts[id(part)] = False
                if composite:
                    self.unjoined[id(part)] = (original, mine)
            joined.append(part)
        return joined + [c for c in conditions if id(c) not in used]

    def first_letter_propositions(self, formula: Formula) -> frozenset[str]:
        """The propositions ``formula``'s verdict may read at the first letter: those not under a
        ``X``/``WX`` (nor on the right of ``T``, which is ``F(left & X F right)``).

        A state condition ``c`` sharing none of these with a part ``P`` does not restrict ``P``'s
        exploration: after a first letter ``a``, ``P & c`` goes on as ``P`` progressed by ``a``,
        and which of those obligations are reached does not depend on the propositions ``c``
        constrains. So a composite ``P`` joined to such a ``c`` is progressed whole (within
        :data:`JOINED_NODES`) for nothing its composition would not give. SYNTCOMP's double
        counters start their system counter at 0 (``!counter_sys_i``) while their rules and goal
        sit under ``X[!] G`` / ``X[!] F``: joined, the 4-bit one took 1.5 s, composed 0.5 s. A Nim
        game's rules are ``G (...)`` from the first letter, where its start position restricts
        them: composed, they took 2.3-7.7x as long as joined (nim_pb_03_04: 6 s joined, past 40 s
        composed; docs/BENCHMARKS.md, issue 27's fourth round). (Over-approximated, never under:
        a proposition counted here only keeps the join.)"""
        return _propositions_below(formula, self.first_props, _first_letter_children)

    def state_condition(self, formula: Formula) -> bool:
        """Whether ``formula`` is Boolean over propositions only (it speaks of the first letter)."""
        stack = [formula]
        while stack:
            node = stack.pop()
            if isinstance(node, (And, Or, Implies, Iff)):
                stack += (node.left, node.right)
            elif isinstance(node, Not):
                stack.append(node.arg)
            elif not isinstance(node, (Prop, Const)):
                return False
        return True

    def join(self, dfas: list[DFA], mode: str) -> DFA:
        """The product of ``dfas`` under ``mode``, the two smallest first, minimised after each.

        A heap keyed by (states, arrival): ties go to the earlier one, the order a stable sort of
        the list before every step gave (re-sorting was quadratic in the number of parts: 8,000
        conjuncts, 2.9 s of sorting)."""
        import heapq

        accept = _ACCEPT[mode]
        heap = [(d.n_states, i, d) for i, d in enumerate(dfas)]
        heapq.heapify(heap)
        arrival = len(heap)
        while len(heap) > 1:
            _, _, left = heapq.heappop(heap)
            _, _, right = heapq.heappop(heap)
            joined = _product(left, right, accept, self.max_states)
            heapq.heappush(heap, (joined.n_states, arrival, joined))
            arrival += 1
        return heap[0][2]

    def groups(self, parts: list[Formula]) -> list[list[int]]:
        """Indices of ``parts`` grouped by shared propositions (connected components), in order."""
        parent = list(range(len(parts)))

        def find(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        owner: dict[str, int] = {}
        for i, part in enumerate(parts):
            for name in self.propositions(part):
                a, b = find(i), find(owner.setdefault(name, i))
                if a != b:
                    parent[max(a, b)] = min(a, b)
        groups: dict[int, list[int]] = {}
        for i in range(len(parts)):
            groups.setdefault(find(i), []).append(i)
        return list(groups.values())

    def propositions(self, formula: Formula) -> frozenset[str]:
        """The propositions ``formula`` mentions (children before parents, without recursion).

        A chain of one junction counts as one node over its operands: a set per inner node of
        a left-deep ``c1 & ... & cn`` would hold n(n+1)/2 names in all (100,000 TLSF
        assumptions filled 4 GB before anything was translated)."""
        return _propositions_below(formula, self.props, _all_children)


def _product(left: DFA, right: DFA, accept, max_states: int) -> DFA:
    """The minimal DFA of the product of two complete DFAs, a pair accepting by ``accept``."""
    for one, other in ((left, right), (right, left)):
        if one.n_states == 1:  # every word or none: the other part, its complement or this constant
            return _with_constant(one, other, accept)
    from symlearn.input_limits import limit

    d1, r1 = left.transition_diagram()
    d2, r2 = right.transition_diagram()
    # the product's diagram is bounded like progression's obligations (the same limit): parts that
    # share one proposition (F(z & p1) & ... & F(z & pn)) stay under max_states per product while
    # the diagrams of their pairs grow past the memory (2,000 parts: a MemoryError at 3.6 GB)
    nodes = limit("SYMLEARN_MAX_TRANSLATION_NODES")
    try:
        diagram, roots, pairs = td.product((d1, r1, left.initial), (d2, r2, right.initial), max_states=max_states,
                                           max_nodes=nodes)
    except td.ProductNodesExceeded:
        raise LimitExceededError(f"the automaton of this formula needs more than {nodes:,} decision-diagram "
                                 "nodes while its parts are joined",
                                 hint="split the formula or raise SYMLEARN_MAX_TRANSLATION_NODES (0: no "
                                      "limit)") from None
    except LimitExceededError:
        raise LimitExceededError(f"the automaton of this formula needs more than {max_states} states",
                                 hint="raise max_states (CLI: --max-states) or split the formula") from None
    a1, a2 = left.accepting, right.accepting
    accepting = [accept(p in a1, q in a2) for p, q in pairs]
    # kept symbolic: listing a product's edges as guards costs memory the next product does not
    # use (250 intermediate 256-state products of F(z & p1) & ... & F(z & p2000) held 2 GB of
    # guards); compose() lists the final automaton's edges where they are few
    return td.minimal(diagram, roots, accepting, 0, left.alphabet | right.alphabet, explicit_edges=0)


def _with_constant(one: DFA, other: DFA, accept) -> DFA:
    """The product of a one-state (minimal, complete) DFA with another minimal DFA, without building
    it: a conjunct ``true`` or a part whose product came out universal left a 67-state product of
    SYNTCOMP's Syft 122 to be rebuilt and minimised again (43 ms), to give the same automaton.
    (``accept`` is symmetric: and, or, iff.)"""
    alphabet = one.alphabet | other.alphabet
    verdict = bool(one.accepting)
    on_accepted, on_rejected = accept(verdict, True), accept(verdict, False)
    if on_accepted == on_rejected:  # the constant decides: and with none, or with every word
        return one.with_alphabet(alphabet)
    return (other if on_accepted else complement(other)).with_alphabet(alphabet)


def _operands(formula: Formula) -> list[Formula]:
    """The operands of a tree of one kind of junction, left to right (no recursion: trees are deep)."""
    kind = type(formula)
    out, stack = [], [formula]
    while stack:
        node = stack.pop()
        if type(node) is kind:
            stack += (node.right, node.left)
        else:
            out.append(node)
    return out


def _rebuild(parts: list[Formula], kind: type) -> Formula:
    """The junction of ``parts`` as a balanced tree (progression joins long ones balanced anyway)."""
    while len(parts) > 1:
        joined = [kind(parts[i], parts[i + 1]) for i in range(0, len(parts) - 1, 2)]
        if len(parts) % 2:
            joined.append(parts[-1])
        parts = joined
    return parts[0]

