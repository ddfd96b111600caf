"""LTLf -> minimal DFA, by symbolic formula progression.

Construction (our own; sound by the progression identities, exact by minimisation):

1. The formula is rewritten into negation normal form over ``& |``, literals, ``X WX F G U R``
   (``a W b`` = ``b R (a | b)``, ``a T b`` = ``F(a & X F b)``); equal sub-formulas share one id.
2. A DFA state is an *obligation on the rest of the trace*: a Boolean function, kept as a
   reduced ordered BDD, of *elementary* sub-formulas (literals and temporal nodes) that the
   remaining suffix must satisfy. Two states are the same exactly when their obligations are
   propositionally equivalent, which BDD node identity decides in O(1).
3. Reading one letter replaces every elementary formula by its one-step unfolding, e.g.
   ``F f`` -> ``f_now | F f``, ``f U g`` -> ``g_now | (f_now & (f U g))``, where ``*_now`` are
   BDD variables of the *current letter's propositions*, ordered above the obligation
   variables. The top (proposition) layer of the composed BDD *is* the state's transition
   function: its nodes test propositions and the first node below them is the successor
   obligation. Layer nodes are shared between states, so exploration walks each of them once
   for the whole automaton and never lists (state, successor) pairs: ``F p1 & ... & F pn`` has
   2^n states and 3^n such pairs, but about n 2^(n-1) layer nodes.
4. The remaining suffix may be empty, so each state also decides the empty suffix: literals,
   ``X``, ``F``, ``U`` are false there and ``WX``, ``G``, ``R`` true. Strong ``X f`` unfolds to
   ``f & NE`` and weak ``WX f`` to ``f | !NE`` where ``NE`` ("the rest is not empty") is needed
   (only when ``f`` itself decides the empty suffix the other way). A state is accepting when
   its obligation holds on the empty suffix. The empty *word* itself is decided by
   :func:`~symlearn.logic.ltlf.progression.holds_at_end` (negation as complement, as MONA does),
   which can differ from the start obligation's verdict (``!a``: true; NNF ``!a``: false); then
   the start state is split off before minimisation.
5. When the explored automaton has at most
   :data:`~symlearn.logic.automata.transition_diagram.EXPLICIT_EDGES` (state, successor) pairs,
   each layer is split into guarded edges and the states are minimised by partition refinement
   whose signatures compare canonical guard BDDs per target block (Hopcroft). Otherwise the
   layer is copied into a :class:`~symlearn.logic.automata.transition_diagram.TransitionDiagram`
   (leaves: state numbers), the obligation manager is dropped, and the states are minimised there
   (:func:`~symlearn.logic.automata.transition_diagram.minimal`: Moore refinement on hash-consed
   signatures). Either way the result is the unique minimal complete DFA (the rejecting sink,
   when there is one, is a state like any other).

6. Large inputs: junctions of more than 16 operands (``c1 & ... & cn``) and states that are long
   conjunctions (disjunctions) of obligation variables are joined in a balanced order, so a
   conjunction of 10,000 conjuncts costs about n log n node operations, not n^2. Before the
   exploration, a conjunction of at least 8 independent conjuncts is checked against the state
   and node limits by a proven lower bound (:mod:`~symlearn.logic.ltlf.conjunct_bound`), so
   ``F p1 & ... & F p2000`` is refused before its first state's 2^2000 successors are built.

7. Boolean skeletons: :func:`translate` hands a formula whose top is ``& | -> <-> !`` over
   parts sharing propositions to :mod:`~symlearn.logic.ltlf.composition` first, which tries this
   progression within a small budget and otherwise builds a minimal DFA per part and joins them
   by minimised products (the same DFA, without the obligations of every part multiplying before
   minimisation can merge them).

The result is a :class:`~symlearn.logic.automata.dfa.DFA` over the formula's propositions,
complete and minimal. With at most
:data:`~symlearn.logic.automata.transition_diagram.EXPLICIT_EDGES` guarded edges it has explicit
edges, numbered as :meth:`~symlearn.logic.automata.dfa.DFA.minimize` numbers states (state 0
initial, then breadth-first in guard order); above, its transitions stay symbolic
(:meth:`~symlearn.logic.automata.dfa.DFA.is_symbolic`; state 0 initial, breadth-first in diagram
order) and guarded edges are produced only on request. The translation checks nothing it builds
by construction (disjoint, complete transitions): tests assert that, not every call.

>>> from symlearn.logic.ltlf.parser import parse
>>> dfa = translate(parse("F a & F b"))
>>> dfa.n_states, dfa.accepts([{"a"}, {"b"}]), dfa.accepts([{"a"}])
(4, True, False)
"""

from __future__ import annotations

import gc
import sys

from typing import TYPE_CHECKING

from symlearn.errors import LimitExceededError
from symlearn.logic.bdd import BDD, FALSE, TRUE
from symlearn.logic.ltlf.ast import (
    Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil,
)
from symlearn.logic.ltlf.conjunct_bound import check_state_bound, independent_groups
from symlearn.logic.ltlf.progression import holds_at_end

if TYPE_CHECKING:
    from symlearn.logic.automata.dfa import DFA

# The automata side (DFA, transition diagrams, guards) is imported where a translation needs it,
# not with this module: `symlearn ltl parse` imports the ltlf package, and with it this module,
# but never translates (~60 ms of its start-up without bytecode files, issue 27).

__all__ = ["translate", "to_dfa", "equivalent", "DEFAULT_MAX_STATES"]

DEFAULT_MAX_STATES = 100_000  # obligations before minimisation (docs/BENCHMARKS.md: tlsf-fin, the default)
#: transition_diagram.EXPLICIT_EDGES, repeated so this module need not import the automata side
#: (tests/logic/ltlf/test_to_dfa.py checks the two agree)
EXPLICIT_EDGES = 10_000
_RECURSION_LIMIT = 12_000
#: trees of one of ``& |`` with more operands than this are joined in a balanced order;
#: smaller ones exactly as they are written
_LONG_JUNCTION = 16
#: runs of conjunctive (disjunctive) obligation nodes longer than this are composed as one
#: balanced junction; shorter ones node by node, which reuses more between states (measured:
#: a run threshold of 16 made ``p1 T ... T p12`` 1.5x slower, 64 leaves it as it was)
_LONG_RUN = 64

# NNF node kinds
_TT, _FF, _LIT, _NLIT, _AND, _OR, _X, _WX, _F, _G, _U, _R = range(12)
_ELEMENTARY = {_LIT, _NLIT, _X, _WX, _F, _G, _U, _R}
_TRUE_AT_END = {_WX, _G, _R}


class _Translation:
    def __init__(self, formula: Formula) -> None:
        self.nodes: list[tuple] = []
        self.ids: dict[tuple, int] = {}
        self.props: dict[str, int] = {}
        self.memo: dict[tuple[int, bool], int] = {}
        self.formula = formula
        self.root = self._nnf(formula, False)

    # -- negation normal form with shared nodes ------------------------------------------------
    def _mk(self, key: tuple) -> int:
        found = self.ids.get(key)
        if found is None:
            found = len(self.nodes)
            self.nodes.append(key)
            self.ids[key] = found
        return found

    def _and(self, a: int, b: int) -> int:
        return self._junction(a, b, _AND, _FF, _TT)

    def _or(self, a: int, b: int) -> int:
        return self._junction(a, b, _OR, _TT, _FF)

    def _junction(self, a: int, b: int, kind: int, absorbing: int, neutral: int) -> int:
        ka, kb = self.nodes[a][0], self.nodes[b][0]
        if ka == absorbing or kb == absorbing:
            return self._mk((absorbing,))
        if ka == neutral:
            return b
        if kb == neutral or a == b:
            return a
        return self._mk((kind, min(a, b), max(a, b)))

    def _nnf(self, root: Formula, negated: bool) -> int:
        # explicit stack: formulas from files can be nested deeper than Python's recursion limit
        # A node waiting for its parts is pushed back with them (None: not yet asked), so its
        # parts are listed once; composition builds the negation normal form of each part it
        # progresses, and on Random/Syft 145 that was a third of the translation (issue 27).
        memo = self.memo
        parts_of, combine = self._parts, self._combine
        stack: list[tuple[Formula, bool, list | None]] = [(root, negated, None)]
        while stack:
            node, neg, parts = stack.pop()
            key = (id(node), neg)
            if key in memo:
                continue
            if parts is None:
                parts = parts_of(node, neg)
                missing = [(c, n) for c, n in parts if (id(c), n) not in memo]
                if missing:
                    stack.append((node, neg, parts))
                    stack.extend((c, n, None) for c, n in missing)
                    continue
            memo[key] = combine(node, neg, [memo[(id(c), n)] for c, n in parts])
        return memo[(id(root), negated)]

    @staticmethod
    def _parts(node: Formula, neg: bool) -> list[tuple[Formula, bool]]:
        kind = type(node)
        if kind is And or kind is Or:  # the commonest nodes first (exact types; subclasses below)
            return [(node.left, neg), (node.right, neg)]
        if kind is Prop:
            return []
        if isinstance(node, (Const, Prop)):
            return []
        if isinstance(node, Not):
            return [(node.arg, not neg)]
        if isinstance(node, (Next, WeakNext, Eventually, Always)):
            return [(node.arg, neg)]
        if isinstance(node, Implies):
            return [(node.left, not neg), (node.right, neg)]
        if isinstance(node, Iff):
            return [(node.left, False), (node.left, True), (node.right, False), (node.right, True)]
        return [(node.left, neg), (node.right, neg)]

    def _combine(self, node: Formula, neg: bool, c: list[int]) -> int:
        kind = type(node)
        if kind is And or kind is Or:  # the commonest nodes first, as in _parts
            return self._and(c[0], c[1]) if (kind is And) != neg else self._or(c[0], c[1])
        mk, AND, OR = self._mk, self._and, self._or
        if isinstance(node, Const):
            return mk((_TT,) if node.value != neg else (_FF,))
        if isinstance(node, Prop):
            self.props.setdefault(node.name, len(self.props))
            return mk((_NLIT if neg else _LIT, node.name))
        if isinstance(node, Not):
            return c[0]
        if isinstance(node, (Next, WeakNext)):
            strong = isinstance(node, Next) != neg
            if strong and self.nodes[c[0]][0] == _FF:
                return c[0]
            if not strong and self.nodes[c[0]][0] == _TT:
                return c[0]
            return mk((_X if strong else _WX, c[0]))
        if isinstance(node, (Eventually, Always)):
            kind = _F if isinstance(node, Eventually) != neg else _G
            inner = self.nodes[c[0]][0]
            if (kind == _F and inner == _FF) or (kind == _G and inner == _TT):
                return c[0]
            return mk((kind, c[0]))
        if isinstance(node, Iff):
            lp, ln, rp, rn = c
            if neg:
                return OR(AND(lp, rn), AND(ln, rp))
            return OR(AND(lp, rp), AND(ln, rn))
        left, right = c
        if isinstance(node, (And, Or, Implies)):
            conj = isinstance(node, And) != neg if not isinstance(node, Implies) else neg
            return AND(left, right) if conj else OR(left, right)
        if isinstance(node, Until):
            return mk((_R if neg else _U, left, right))
        if isinstance(node, Release):
            return mk((_U if neg else _R, left, right))
        if isinstance(node, WeakUntil):  # a W b = b R (a | b);  !(a W b) = !b U (!a & !b)
            if neg:
                return mk((_U, right, AND(left, right)))
            return mk((_R, right, OR(left, right)))
        if isinstance(node, Then):  # a T b = F(a & X F b);  !(a T b) = G(!a | WX G !b)
            if neg:
                return mk((_G, OR(left, self._wx(mk((_G, right))))))
            return mk((_F, AND(left, mk((_X, mk((_F, right)))))))
        raise TypeError(f"not an LTLf formula node: {node!r}")  # pragma: no cover

    def _wx(self, arg: int) -> int:
        return arg if self.nodes[arg][0] == _TT else self._mk((_WX, arg))

    # -- symbolic automaton --------------------------------------------------------------------
    def explore(self, max_states: int, max_nodes: int | None = None, first_nodes: int | None = None) -> tuple | DFA:
        """``(diagram, roots, accepting, initial, propositions)`` of the reachable obligations, or
        the minimal DFA itself when it has at most EXPLICIT_EDGES edges before minimisation)."""
        # a manager of its own, dropped after the translation: obligation nodes outnumber the edge
        # guards it produces (3.8x on the benchmark families, see symlearn/logic/bdd.py)
        from symlearn.input_limits import limit
        from symlearn.logic.automata.transition_diagram import TransitionDiagram

        # bounded like the guard table, so a formula whose obligations explode stops with a clear
        # error before memory runs out (SYMLEARN_MAX_TRANSLATION_NODES, docs/FORMATS.md); a limit
        # of its own, as large minimal DFAs (2^18 states) need more nodes than the guard table ever holds
        nodes = limit("SYMLEARN_MAX_TRANSLATION_NODES")
        if max_nodes is not None:  # a trial (composition.py): the smaller of the two
            nodes = max_nodes if nodes is None else min(nodes, max_nodes)
        bdd = self.bdd = BDD(max_nodes=nodes,
                             limit_hint="the formula's obligations need too many BDD nodes; split the formula "
                                        "or raise SYMLEARN_MAX_TRANSLATION_NODES (0: no limit)")
        # propositions take the top levels in name order, the order of the shared guard table, so
        # converting an edge guard to a Guard is one node construction per node (guards.from_bdd)
        self.props = {name: level for level, name in enumerate(sorted(self.props))}
        n_props = len(self.props)
        # BDD levels: propositions 0..n_props-1, then one per elementary node, then NE
        self.level_of: dict[int, int] = {}
        self.end_value: dict[int, bool] = {}
        # obligations in reverse creation order: a temporal node above the parts it unfolds into
        # (measured: about 1.3x faster overall than the opposite order on the benchmark families)
        for nid in reversed(range(len(self.nodes))):
            key = self.nodes[nid]
            if key[0] in _ELEMENTARY:
                level = n_props + len(self.level_of)
                self.level_of[nid] = level
                self.end_value[level] = key[0] in _TRUE_AT_END
        self.ne_level = n_props + len(self.level_of)
        if first_nodes is not None:  # the steps and the first state within a bound of their own
            bdd.max_nodes = first_nodes if nodes is None else min(nodes, first_nodes)
        self.end_value[self.ne_level] = False
        self.ne = bdd.var(self.ne_level)
        self.now_memo: dict[int, int] = {}
        self.step_memo: dict[int, int] = {}
        self.step_of_level: dict[int, int] = {self.ne_level: TRUE}
        for nid, level in self.level_of.items():
            self.step_of_level[level] = self._step(nid)
        self.compose_memo: dict[int, int] = {}
        self.split_memo: dict[int, dict[int, int]] = {}
        self.paths_memo: dict[int, int] = {}
        # independent conjuncts multiply their states (F p1 & ... & F pn: 2^n): refuse from a
        # proven lower bound before the exploration spends the memory (conjunct_bound.py)
        groups = independent_groups(self.nodes, self.root, _AND, (_LIT, _NLIT), (_TT, _FF))
        check_state_bound(self, groups, max_states)

        start = self._now(self.root)
        index = {start: 0}
        states = [start]
        # the composed obligation's proposition layer *is* the state's transition function: its
        # nodes test this letter's propositions, and the first node below them (an obligation)
        # is the successor. While the automaton is small, each layer is split into guarded edges
        # (one guard per successor); past EXPLICIT_EDGES edges the splitting stops and the layers
        # are only walked, each node once overall: successors are then found without listing
        # (state, successor) pairs, which F p1 & ... & F pn has 3^n of, against n 2^(n-1) nodes.
        n_props = len(self.props)
        level, low, high = bdd.level, bdd.low, bdd.high
        walked: set[int] = set()
        roots = []
        edges: list[list[tuple[int, int]]] | None = []
        n_edges = 0

        def register(u: int) -> int:
            j = index.get(u)
            if j is None:
                if len(states) >= max_states:
                    raise LimitExceededError(
                        f"the automaton of this formula needs more than {max_states} states",
                        hint="raise max_states (CLI: --max-states) or split the formula")
                j = index[u] = len(states)
                states.append(u)
            return j

        for state in states:  # grows while we iterate: breadth-first exploration
            top = self._compose_state(state)
            bdd.max_nodes = nodes
            roots.append(top)
            if edges is not None:
                if self._successors_fit(top, EXPLICIT_EDGES - n_edges):
                    out = self._split(top)
                    get = index.get
                    edges.append([(get(t) if t in index else register(t), g) for t, g in out.items()])
                    n_edges += len(out)
                    continue
                # large: symbolic from here on (the successors so far are registered; this
                # state's are found by the walk below). Checked before splitting: the split of
                # F p1 & ... & F p14's first state alone would build 16,384 guards, then be dropped
                edges = None
                self.split_memo = self.paths_memo = {}
            stack = [top]
            while stack:  # discover the successors below nodes not walked before
                u = stack.pop()
                if u <= TRUE or level[u] >= n_props:
                    if u not in index:
                        register(u)
                elif u not in walked:
                    walked.add(u)
                    stack.append(high[u])
                    stack.append(low[u])
        accepting = [self._end(s) for s in states]
        initial = 0
        empty_word = holds_at_end(self.formula)
        if edges is not None:
            # few edges: minimise them explicitly (Hopcroft on canonical guards), which beats the
            # diagram passes on small automata and on long chains, where Moore's rounds are many
            if empty_word != accepting[0]:
                # the start obligation may recur later with the other verdict on "the rest is
                # empty", so the empty word gets a start state of its own (same edges)
                initial = len(states)
                states.append(states[0])
                edges.append(list(edges[0]))
                accepting.append(empty_word)
            return self._minimal(states, edges, accepting, initial)
        # the proposition layer as a diagram whose leaves are state numbers (now all known). The
        # BDD is reduced and distinct obligations are distinct states, so distinct nodes stay
        # distinct: no hash-consing needed, ids assigned children first
        memo: dict[int, int] = {}
        dvar: list[int] = []
        dlow: list[int] = []
        dhigh: list[int] = []
        for k, top in enumerate(roots):  # children first, by an explicit stack (no closure cycles)
            stack = [top]
            while stack:
                u = stack[-1]
                if u <= TRUE or level[u] >= n_props or u in memo:
                    stack.pop()
                    continue
                lo, hi = low[u], high[u]
                waiting = [c for c in (hi, lo) if not (c <= TRUE or level[c] >= n_props or c in memo)]
                if waiting:
                    stack.extend(waiting)
                    continue
                stack.pop()
                memo[u] = len(dvar)
                dvar.append(level[u])
                dlow.append(~index[lo] if lo <= TRUE or level[lo] >= n_props else memo[lo])
                dhigh.append(~index[hi] if hi <= TRUE or level[hi] >= n_props else memo[hi])
            roots[k] = ~index[top] if top <= TRUE or level[top] >= n_props else memo[top]
        diagram = TransitionDiagram.from_arrays(sorted(self.props, key=self.props.get), dvar, dlow, dhigh)
        if empty_word != accepting[0]:
            # the start obligation may recur later with the other verdict on "the rest is empty",
            # so the empty word gets a start state of its own (same transitions)
            initial = len(states)
            roots.append(roots[0])
            accepting.append(empty_word)
        return diagram, roots, accepting, initial, sorted(self.props)

    def build(self, max_states: int) -> DFA:
        """The minimal DFA (the translation object keeps its manager: benchmarks count its nodes)."""
        from symlearn.logic.automata.dfa import DFA
        from symlearn.logic.automata.transition_diagram import minimal

        explored = self.explore(max_states)
        return explored if isinstance(explored, DFA) else minimal(*explored)

    def _end(self, u: int) -> bool:
        ev = self.end_value
        return self.bdd.evaluate(u, lambda level: ev[level])

    def _now(self, nid: int) -> int:
        """The obligation 'the remaining suffix satisfies node nid' over elementary variables."""
        found = self.now_memo.get(nid)
        if found is not None:
            return found
        key = self.nodes[nid]
        kind = key[0]
        if kind == _TT:
            found = TRUE
        elif kind == _FF:
            found = FALSE
        elif kind == _AND or kind == _OR:
            found = self._junction_bdd(nid, self._now)
        else:
            found = self.bdd.var(self.level_of[nid])
        self.now_memo[nid] = found
        return found

    def _step(self, nid: int) -> int:
        """Node nid at the current step: a BDD over this letter's propositions and next obligations."""
        found = self.step_memo.get(nid)
        if found is not None:
            return found
        bdd, key = self.bdd, self.nodes[nid]
        kind = key[0]
        if kind == _TT:
            found = TRUE
        elif kind == _FF:
            found = FALSE
        elif kind == _LIT:
            found = bdd.var(self.props[key[1]])
        elif kind == _NLIT:
            found = bdd.negate(bdd.var(self.props[key[1]]))
        elif kind == _AND or kind == _OR:
            found = self._junction_bdd(nid, self._step)
        elif kind == _X:
            nxt = self._now(key[1])
            found = bdd.apply_and(nxt, self.ne) if self._end(nxt) else nxt
        elif kind == _WX:
            nxt = self._now(key[1])
            found = nxt if self._end(nxt) else bdd.apply_or(nxt, bdd.negate(self.ne))
        else:
            me = bdd.var(self.level_of[nid])
            if kind == _F:
                found = bdd.apply_or(self._step(key[1]), me)
            elif kind == _G:
                found = bdd.apply_and(self._step(key[1]), me)
            elif kind == _U:
                found = bdd.apply_or(self._step(key[2]), bdd.apply_and(self._step(key[1]), me))
            else:  # _R
                found = bdd.apply_and(self._step(key[2]), bdd.apply_or(self._step(key[1]), me))
        self.step_memo[nid] = found
        return found

    def _compose(self, u: int) -> int:
        """Substitute every obligation variable of u by its one-step unfolding."""
        if u <= TRUE:
            return u
        found = self.compose_memo.get(u)
        if found is None:
            bdd = self.bdd
            found = bdd.ite(self.step_of_level[bdd.level[u]], self._compose(bdd.high[u]), self._compose(bdd.low[u]))
            self.compose_memo[u] = found
        return found

    def _compose_state(self, u: int) -> int:
        """:meth:`_compose` of a state. A state that starts with a long run of nodes whose low
        (high) child is FALSE (TRUE) is a conjunction (disjunction) of obligation variables and
        what lies below: composed as one balanced junction of their unfoldings, not by one ite
        per node, each of which would copy the proposition layer built so far (quadratic on
        ``G p1 & ... & G pn``). The run stops at a node composed before (another state's work
        is reused); only states are probed, so a short run costs one probe, not one per node."""
        if u <= TRUE or u in self.compose_memo:
            return self._compose(u)
        bdd = self.bdd
        low, high = bdd.low, bdd.high
        absorbing = FALSE if low[u] == FALSE else TRUE if high[u] == TRUE else None
        if absorbing is None:
            return self._compose(u)
        memo = self.compose_memo
        run, w = [], u
        while w > TRUE and (low[w] if absorbing == FALSE else high[w]) == absorbing and (w == u or w not in memo):
            run.append(bdd.level[w])
            w = high[w] if absorbing == FALSE else low[w]
        if len(run) <= _LONG_RUN:
            return self._compose(u)
        parts = [self.step_of_level[level] for level in run]
        parts.append(self._compose(w))
        found = memo[u] = self._balanced(parts, absorbing == FALSE)
        return found

    def _junction_bdd(self, nid: int, part) -> int:
        """``part`` of an ``&``/``|`` node: of its two operands, or, for a long tree of one kind
        (``c1 & c2 & ... & cn``), of all its operands joined in a balanced order."""
        nodes = self.nodes
        kind = nodes[nid][0]
        operands, stack = [], [nid]
        while stack and len(operands) + len(stack) <= _LONG_JUNCTION:  # small trees: as before
            key = nodes[stack.pop()]
            if key[0] == kind:
                stack += (key[2], key[1])
            else:
                operands.append(key)
        if len(operands) + len(stack) <= _LONG_JUNCTION:
            key = nodes[nid]
            op = self.bdd.apply_and if kind == _AND else self.bdd.apply_or
            return op(part(key[1]), part(key[2]))
        operands, stack = [], [nid]
        while stack:  # the tree's operands, left to right, without recursion (a long chain is deep)
            child = stack.pop()
            key = nodes[child]
            if key[0] == kind:
                stack += (key[2], key[1])
            else:
                operands.append(child)
        return self._balanced([part(c) for c in operands], kind == _AND)

    def _balanced(self, parts: list[int], conjunction: bool) -> int:
        """The conjunction (disjunction) of ``parts``: sorted by top variable, then joined in
        pairs of neighbours, round by round. Joining the n parts one by one costs up to n times
        the size of the result (each step walks what is built so far); in pairs of neighbours,
        about log n times."""
        bdd = self.bdd
        absorbing = FALSE if conjunction else TRUE
        if absorbing in parts:
            return absorbing
        level = bdd.level
        parts = sorted({p for p in parts if p > TRUE}, key=lambda p: level[p])
        if not parts:
            return TRUE if conjunction else FALSE
        op = bdd.apply_and if conjunction else bdd.apply_or
        while len(parts) > 1:
            joined = [op(parts[i], parts[i + 1]) for i in range(0, len(parts) - 1, 2)]
            if len(parts) % 2:
                joined.append(parts[-1])
            parts = joined
        return parts[0]

    def _successors_fit(self, u: int, room: int) -> bool:
        """Whether u's proposition layer leads to at most ``room`` distinct obligations: at once
        when its paths are that few (counted once per node overall), else by a walk that stops
        at the first obligation past ``room``."""
        if self._paths(u) <= room:
            return True
        bdd = self.bdd
        n_props, level, low, high = len(self.props), bdd.level, bdd.low, bdd.high
        found: set[int] = set()
        seen: set[int] = set()
        stack = [u]
        while stack:
            w = stack.pop()
            if w <= TRUE or level[w] >= n_props:
                found.add(w)
                if len(found) > room:
                    return False
            elif w not in seen:
                seen.add(w)
                stack.append(high[w])
                stack.append(low[w])
        return True

    def _paths(self, u: int) -> int:
        """Paths through u's proposition layer to the obligations below it (>= their number)."""
        bdd = self.bdd
        if u <= TRUE or bdd.level[u] >= len(self.props):
            return 1
        found = self.paths_memo.get(u)
        if found is None:
            found = self.paths_memo[u] = self._paths(bdd.low[u]) + self._paths(bdd.high[u])
        return found

    def _split(self, u: int) -> dict[int, int]:
        """Successor obligations of u (below the proposition layer) -> guard over propositions."""
        found = self.split_memo.get(u)
        if found is not None:
            return found
        bdd = self.bdd
        level = bdd.level[u]
        if u <= TRUE or level >= len(self.props):
            found = {u: TRUE}
        else:
            # child guards only mention later propositions, so each guard is one new node
            high, low = self._split(bdd.high[u]), self._split(bdd.low[u])
            found = bdd.nodes_by_key(level, low, high)
        self.split_memo[u] = found
        return found

    # -- minimisation ----------------------------------------------------------------------------
    def _refine(self, edges: list[list[tuple[int, int]]], accepting: list[bool]) -> list[int]:
        """Coarsest partition compatible with acceptance and transitions (Hopcroft, symbolic).

        Splitting by a block B separates states whose guards into B differ (canonical BDD
        nodes, so one comparison covers every letter); when a block not waiting to be used
        splits, only its smaller parts need to wait (Hopcroft's argument holds per letter).
        """
        bdd = self.bdd
        n = len(edges)
        predecessors: list[list[tuple[int, int]]] = [[] for _ in range(n)]
        for q, out in enumerate(edges):
            for target, guard in out:
                predecessors[target].append((q, guard))
        block = [1 if a else 0 for a in accepting]
        members: list[list[int]] = [[q for q in range(n) if not accepting[q]], [q for q in range(n) if accepting[q]]]
        if not members[0] or not members[1]:
            return [0] * n
        waiting = {0 if len(members[0]) <= len(members[1]) else 1}
        while waiting:
            splitter = waiting.pop()
            into: dict[int, int] = {}
            for t in members[splitter]:
                for q, guard in predecessors[t]:
                    into[q] = bdd.apply_or(into[q], guard) if q in into else guard
            groups: dict[int, dict[int, list[int]]] = {}
            for q, guard in into.items():
                groups.setdefault(block[q], {}).setdefault(guard, []).append(q)
            for c, by_guard in groups.items():
                parts = list(by_guard.values())
                touched = sum(len(p) for p in parts)
                if touched < len(members[c]):
                    seen = set(into)
                    parts.append([q for q in members[c] if q not in seen])
                if len(parts) == 1:
                    continue
                parts.sort(key=len, reverse=True)
                members[c] = parts[0]
                for part in parts[1:]:
                    new_id = len(members)
                    members.append(part)
                    for q in part:
                        block[q] = new_id
                    waiting.add(new_id)
                if c in waiting:
                    continue
                # c keeps the largest part; the smaller ones were queued above
        return block

    def _minimal(self, states: list[int], edges: list[list[tuple[int, int]]], accepting: list[bool],
                 initial: int) -> DFA:
        from symlearn.logic.automata.dfa import DFA
        from symlearn.logic.guards import from_bdd

        bdd = self.bdd
        block = self._refine(edges, accepting)
        # the blocks reachable from the initial state (numbered as found), one representative each
        order: dict[int, int] = {block[initial]: 0}
        representative = [initial]
        for q in representative:
            for target, _ in edges[q]:
                b = block[target]
                if b not in order:
                    order[b] = len(order)
                    representative.append(target)
        rows = []
        for q in representative:
            merged: dict[int, int] = {}
            for target, guard in edges[q]:
                b = order[block[target]]
                merged[b] = bdd.apply_or(merged[b], guard) if b in merged else guard
            rows.append(list(merged.items()))
        # propositions hold the top levels in name order, so each guard node maps to one node of
        # the shared guard table (one conversion for the whole automaton)
        names = sorted(self.props, key=self.props.get)
        guards = iter(from_bdd(bdd, [g for row in rows for _, g in row], names))
        # (a state's edges are disjoint: label_key orders them as sort_key does, without supports)
        table = [sorted(((next(guards), b) for b, _ in row), key=lambda e: e[0].label_key) for row in rows]
        # renumber as DFA.minimize does (breadth-first, edges in guard order), so equal languages
        # give equal DFAs whichever way they were built
        index = {0: 0}
        canonical = [0]
        for q in canonical:
            for _, t in table[q]:
                if t not in index:
                    index[t] = len(canonical)
                    canonical.append(t)
        accepting_blocks = [index[order[block[q]]] for q in representative if accepting[q]]
        # the edges are canonical already (disjoint, complete, one per target): skip validation
        return DFA._trusted(names, len(table), 0, accepting_blocks,
                            [[(g, index[t]) for g, t in table[q]] for q in canonical], ordered=True)


def translate(formula: Formula, *, max_states: int = DEFAULT_MAX_STATES) -> DFA:
    """The minimal complete DFA of ``formula`` (state 0 initial, breadth-first numbering).

    Raises :class:`~symlearn.errors.LimitExceededError` when more than ``max_states``
    obligations are reachable before minimisation.
    """
    if not isinstance(formula, Formula):
        raise TypeError(f"expected an LTLf formula, got {type(formula).__name__}")
    # BDD operations recurse once per variable level and obligations once per nesting level
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, _RECURSION_LIMIT))
    # the construction allocates many small acyclic tables; cyclic GC passes only slow it down
    collecting = gc.isenabled()
    gc.disable()
    try:
        # a Boolean combination of parts sharing propositions: a DFA per part, joined by
        # minimised products (composition.py); anything else: progression of the whole formula
        from symlearn.logic.ltlf.composition import compose

        return compose(formula, _progression, max_states)
    except RecursionError:
        raise LimitExceededError("the formula is nested too deeply to translate",
                                 hint="split it into smaller conjuncts") from None
    finally:
        sys.setrecursionlimit(limit)
        if collecting:
            gc.enable()


def _progression(formula: Formula, max_states: int, max_nodes: int | None = None,
                 first_nodes: int | None = None) -> DFA:
    """The minimal DFA of ``formula`` by progression of the whole formula (steps 1-6 above);
    ``max_nodes`` bounds the obligation manager below its configured limit, ``first_nodes``
    the part of it spent before the first state is built (a trial's early exit)."""
    from symlearn.logic.automata.dfa import DFA
    from symlearn.logic.automata.transition_diagram import minimal

    translation = _Translation(formula)  # (the negation normal form is built without recursion)
    # room for the BDD operations: a few frames per variable level (propositions, then one
    # per elementary sub-formula), so a conjunction of 10,000 conjuncts is not "too deep"
    levels = len(translation.props) + sum(key[0] in _ELEMENTARY for key in translation.nodes) + 1
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 3 * levels + 1000))
    explored = translation.explore(max_states, max_nodes, first_nodes)
    # the obligation manager and its caches go before minimisation, whose peak memory then
    # does not add to the exploration's
    del translation
    return explored if isinstance(explored, DFA) else minimal(*explored)


to_dfa = translate  # the name the automata side reads better with


def equivalent(f: Formula, g: Formula, *, max_states: int = DEFAULT_MAX_STATES) -> bool:
    """Whether ``f`` and ``g`` hold on exactly the same non-empty traces."""
    # f <-> g is valid iff the DFA of its negation accepts no non-empty word
    dfa = translate(Not(Iff(f, g)), max_states=max_states)
    frontier = [t for _, t in dfa.successors(dfa.initial)]
    seen = set(frontier)
    while frontier:
        q = frontier.pop()
        if q in dfa.accepting:
            return False
        for _, t in dfa.successors(q):
            if t not in seen:
                seen.add(t)
                frontier.append(t)
    return True
