"""Algorithms on guarded DFAs: completion, minimisation, products, shortest words, equivalence.

None of them enumerates the 2^|AP| letters: they work on guards, and because guards are
canonical BDDs, "same guard" is a dictionary lookup. Shortest words come from
breadth-first search; each letter of a returned word is
:meth:`~symlearn.logic.guards.Guard.satisfying_label` of the edge taken (the label with the
fewest true propositions), so words are deterministic and small.

Minimisation is Hopcroft's algorithm with symbolic splitters (:func:`coarsest_partition`);
Moore's round-based refinement is kept as :func:`minimize_moore` for cross-checking.

A DFA with symbolic transitions (:meth:`DFA.is_symbolic`) is handled by the diagram algorithms
of :mod:`~symlearn.logic.automata.transition_diagram` instead (an explicit operand of a product
is converted), so none of these produces its guarded edges. So is an explicit DFA with more
than :data:`~symlearn.logic.automata.transition_diagram.EXPLICIT_EDGES` edges in
:func:`minimize`, so that it numbers states as the LTLf translation does.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata.dfa import DFA
from symlearn.logic.automata import transition_diagram as td
from symlearn.logic.automata.partition_refinement import split_blocks
from symlearn.logic.guards import Guard

SINK_NAME = "sink"


def complete(dfa: DFA) -> DFA:
    """Add a rejecting sink catching every label no edge matches (unchanged if already total)."""
    if dfa.is_symbolic():
        return dfa  # diagrams are total
    missing = [~Guard.any_of(g for g, _ in dfa.successors(q)) for q in dfa.states]
    if all(g.is_false() for g in missing):
        return dfa
    sink = dfa.n_states
    edges = [list(dfa.successors(q)) + ([(missing[q], sink)] if not missing[q].is_false() else [])
             for q in dfa.states]
    edges.append([(Guard.true(), sink)])
    names = None if dfa.state_names is None else list(dfa.state_names) + [_fresh_name(dfa.state_names)]
    return DFA._trusted(dfa.alphabet, dfa.n_states + 1, dfa.initial, dfa.accepting, edges, names)


def _fresh_name(names: Iterable[str]) -> str:
    taken, name = set(names), SINK_NAME
    while name in taken:
        name += "'"
    return name


def reachable_states(dfa: DFA, start: int | None = None) -> frozenset[int]:
    start = dfa.initial if start is None else start
    if dfa.is_symbolic():
        return frozenset(td.reachable(dfa._diagram, dfa._roots, start))
    seen, queue = {start}, deque([start])
    while queue:
        for _, target in dfa.successors(queue.popleft()):
            if target not in seen:
                seen.add(target)
                queue.append(target)
    return frozenset(seen)


def live_states(dfa: DFA) -> frozenset[int]:
    """States from which some accepting state is reachable (backward search)."""
    if dfa.is_symbolic():
        return frozenset(td.live(dfa._diagram, dfa._roots, dfa.accepting))
    predecessors: list[set[int]] = [set() for _ in dfa.states]
    for source, _, target in dfa.edges():
        predecessors[target].add(source)
    seen, queue = set(dfa.accepting), deque(dfa.accepting)
    while queue:
        for source in predecessors[queue.popleft()]:
            if source not in seen:
                seen.add(source)
                queue.append(source)
    return frozenset(seen)


def distances_to_acceptance(dfa: DFA) -> list[int | None]:
    """Fewest steps from each state to an accepting state (``None`` where unreachable)."""
    predecessors: list[set[int]] = [set() for _ in dfa.states]
    for source, _, target in dfa.edges():
        predecessors[target].add(source)
    distance: list[int | None] = [None] * dfa.n_states
    queue = deque()
    for q in dfa.accepting:
        distance[q] = 0
        queue.append(q)
    while queue:
        q = queue.popleft()
        for source in predecessors[q]:
            if distance[source] is None:
                distance[source] = distance[q] + 1  # type: ignore[operator]
                queue.append(source)
    return distance


def _renumber(dfa: DFA, keep: Iterable[int]) -> DFA:
    """The sub-automaton on ``keep`` (which contains the initial state), BFS-numbered."""
    keep = set(keep)
    order = canonical_order(dfa, keep)
    index = {q: i for i, q in enumerate(order)}
    edges = [[(g, index[t]) for g, t in dfa.successors(q) if t in index] for q in order]
    names = None if dfa.state_names is None else [dfa.state_names[q] for q in order]
    return DFA._trusted(dfa.alphabet, len(order), 0, [index[q] for q in order if q in dfa.accepting], edges, names)


def canonical_order(dfa: DFA, keep: Iterable[int] | None = None) -> list[int]:
    """States in breadth-first order from the initial state, edges taken by guard order."""
    keep = set(dfa.states) if keep is None else set(keep)
    order, seen, queue = [], {dfa.initial}, deque([dfa.initial])
    while queue:
        q = queue.popleft()
        order.append(q)
        for _, target in dfa.successors(q):  # successors are sorted by Guard.sort_key
            if target in keep and target not in seen:
                seen.add(target)
                queue.append(target)
    return order


def trim(dfa: DFA) -> DFA:
    """Only the states that are reachable and can still reach acceptance (initial always kept)."""
    keep = (reachable_states(dfa) & live_states(dfa)) | {dfa.initial}
    return _renumber(dfa, keep)


def minimize(dfa: DFA) -> DFA:
    """The minimal complete DFA of ``dfa``'s language, numbered in canonical BFS order.

    Two DFAs with the same language (and alphabet) give structurally equal results
    (:meth:`DFA.same_structure`). A merged block keeps the name of its lowest-numbered state.
    """
    if dfa.is_symbolic() or (dfa.state_names is None and dfa.count_edges(td.EXPLICIT_EDGES) is None):
        diagram, roots = dfa.transition_diagram()
        accepting = [q in dfa.accepting for q in range(len(roots))]  # complete() appends a rejecting sink
        return td.minimal(diagram, roots, accepting, dfa.initial, dfa.alphabet, state_names=dfa.state_names)
    total = complete(dfa)
    dfa = _renumber(total, reachable_states(total))
    block = coarsest_partition(dfa)
    n_blocks = max(block) + 1
    representative: dict[int, int] = {}
    for q in dfa.states:
        representative.setdefault(block[q], q)
    edges = []
    for b in range(n_blocks):
        into: dict[int, Guard] = {}
        for guard, target in dfa.successors(representative[b]):
            into[block[target]] = into[block[target]] | guard if block[target] in into else guard
        edges.append([(g, t) for t, g in into.items()])
    accepting = {block[q] for q in dfa.accepting}
    names = None if dfa.state_names is None else [dfa.state_names[representative[b]] for b in range(n_blocks)]
    quotient = DFA._trusted(dfa.alphabet, n_blocks, block[dfa.initial], accepting, edges, names)
    return _renumber(quotient, quotient.states)


def coarsest_partition(dfa: DFA) -> list[int]:
    """Block number of every state in the language-equivalence partition of a complete DFA.

    Hopcroft's algorithm with symbolic splitters: processing block ``B`` gives each state ``q``
    the guard ``g_B(q)``, the disjunction of its edges into ``B``; a block splits into the
    classes of equal ``g_B`` (canonical guards make this a dictionary lookup), which is the
    split every letter would cause at once. All parts but the largest go on the worklist.
    """
    predecessors: list[list[tuple[int, Guard]]] = [[] for _ in dfa.states]
    for source, guard, target in dfa.edges():
        predecessors[target].append((source, guard))
    initial_blocks = [b for b in (set(dfa.accepting), set(dfa.states) - set(dfa.accepting)) if b]
    blocks: list[set[int]] = initial_blocks
    block_of = [0] * dfa.n_states
    for i, members in enumerate(blocks):
        for q in members:
            block_of[q] = i
    work = list(range(len(blocks)))
    while work:
        splitter = work.pop()
        into: dict[int, Guard] = {}
        for target in blocks[splitter]:
            for source, guard in predecessors[target]:
                into[source] = into[source] | guard if source in into else guard
        touched: dict[int, dict[Guard, list[int]]] = {}
        for q, guard in into.items():
            touched.setdefault(block_of[q], {}).setdefault(guard, []).append(q)
        split_blocks(blocks, block_of, touched, work)
    return block_of


def minimize_moore(dfa: DFA) -> DFA:
    """Reference minimisation by Moore's round-based refinement (quadratic; used in tests)."""
    total = complete(dfa)
    dfa = _renumber(total, reachable_states(total))
    block = [1 if q in dfa.accepting else 0 for q in dfa.states]
    n_blocks = len(set(block))
    while True:
        signatures: dict[tuple, int] = {}
        new_block = []
        for q in dfa.states:
            into: dict[int, Guard] = {}
            for guard, target in dfa.successors(q):
                b = block[target]
                into[b] = into[b] | guard if b in into else guard
            new_block.append(signatures.setdefault((block[q], frozenset(into.items())), len(signatures)))
        block = new_block
        if len(signatures) == n_blocks:
            break
        n_blocks = len(signatures)
    edges = [[] for _ in range(n_blocks)]
    done = set()
    for q in dfa.states:
        if block[q] in done:
            continue
        done.add(block[q])
        into: dict[int, Guard] = {}
        for guard, target in dfa.successors(q):
            into[block[target]] = into[block[target]] | guard if block[target] in into else guard
        edges[block[q]] = [(g, t) for t, g in into.items()]
    quotient = DFA._trusted(dfa.alphabet, n_blocks, block[dfa.initial], {block[q] for q in dfa.accepting}, edges)
    return _renumber(quotient, quotient.states)


_MODES = {
    "and": lambda x, y: x and y,
    "or": lambda x, y: x or y,
    "xor": lambda x, y: x != y,
    "minus": lambda x, y: x and not y,
}


def product(left: DFA, right: DFA, mode: str = "and", *, max_states: int | None = None) -> DFA:
    """Synchronous product over the union of the alphabets, reachable part only.

    ``mode`` decides acceptance of a pair: ``and`` (intersection), ``or`` (union), ``xor``
    (symmetric difference), ``minus`` (left but not right). Both sides are completed first
    so that a word one side rejects by getting stuck is still read by the other.
    """
    if mode not in _MODES:
        raise ModelError(f"unknown product mode {mode!r}", hint=f"use one of {', '.join(_MODES)}")
    accept = _MODES[mode]
    left, right = complete(left), complete(right)
    if left.is_symbolic() or right.is_symbolic():
        return _symbolic_product(left, right, accept, max_states)
    start = (left.initial, right.initial)
    index = {start: 0}
    pairs, edges = [start], []
    i = 0
    while i < len(pairs):
        p, q = pairs[i]
        row = []
        for g1, t1 in left.successors(p):
            for g2, t2 in right.successors(q):
                guard = g1 & g2
                if guard.is_false():
                    continue
                pair = (t1, t2)
                if pair not in index:
                    if max_states is not None and len(pairs) >= max_states:
                        raise LimitExceededError(f"the product automaton exceeds {max_states} states",
                                                 hint="raise max_states or minimise the operands first")
                    index[pair] = len(pairs)
                    pairs.append(pair)
                row.append((guard, index[pair]))
        edges.append(row)
        i += 1
    accepting = [k for k, (p, q) in enumerate(pairs) if accept(p in left.accepting, q in right.accepting)]
    names = None
    if left.state_names is not None or right.state_names is not None:
        names = [f"({left.name(p)}, {right.name(q)})" for p, q in pairs]
    return DFA._trusted(left.alphabet | right.alphabet, len(pairs), 0, accepting, edges, names)


def _symbolic_product(left: DFA, right: DFA, accept, max_states: int | None) -> DFA:
    """The product on transition diagrams (both operands complete), states in discovery order."""
    d1, r1 = left.transition_diagram()
    d2, r2 = right.transition_diagram()
    diagram, roots, pairs = td.product((d1, r1, left.initial), (d2, r2, right.initial), max_states=max_states)
    accepting = [k for k, (p, q) in enumerate(pairs) if accept(p in left.accepting, q in right.accepting)]
    names = None
    if left.state_names is not None or right.state_names is not None:
        names = [f"({left.name(p)}, {right.name(q)})" for p, q in pairs]
    return DFA._symbolic(left.alphabet | right.alphabet, len(pairs), 0, accepting, diagram, roots, names)


def complement(dfa: DFA) -> DFA:
    """The DFA accepting exactly the words (over the same alphabet) ``dfa`` rejects."""
    total = complete(dfa)
    accepting = set(total.states) - set(total.accepting)
    if total.is_symbolic():
        return DFA._symbolic(total.alphabet, total.n_states, total.initial, accepting, total._diagram, total._roots,
                             total.state_names)
    return DFA._trusted(total.alphabet, total.n_states, total.initial, accepting,
                        [total.successors(q) for q in total.states], total.state_names)


def shortest_word(dfa: DFA, targets: Iterable[int], start: int | None = None) -> list[frozenset[str]] | None:
    """A shortest word leading from ``start`` into one of ``targets`` (BFS), or ``None``."""
    targets = set(targets)
    start = dfa.initial if start is None else start
    if dfa.is_symbolic():
        return td.shortest_word(dfa._diagram, dfa._roots, start, targets)
    parent: dict[int, tuple[int, Guard] | None] = {start: None}
    queue = deque([start])
    while queue:
        q = queue.popleft()
        if q in targets:
            word = []
            while parent[q] is not None:
                q, guard = parent[q]  # type: ignore[misc]
                word.append(guard.satisfying_label())
            return word[::-1]
        for guard, target in dfa.successors(q):
            if target not in parent:
                parent[target] = (q, guard)
                queue.append(target)
    return None


def shortest_rejected(dfa: DFA, start: int | None = None) -> list[frozenset[str]] | None:
    total = complete(dfa)
    return shortest_word(total, set(total.states) - set(total.accepting), start)


def equivalent(left: DFA, right: DFA) -> tuple[bool, list[frozenset[str]] | None]:
    """Language equality; on inequality a shortest word accepted by exactly one side."""
    xor = product(left, right, "xor")
    witness = shortest_word(xor, xor.accepting)
    return (witness is None, witness)
