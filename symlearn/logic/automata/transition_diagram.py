"""Symbolic transitions: every state's transition function as one shared decision diagram.

A :class:`TransitionDiagram` is a reduced, ordered, hash-consed multi-terminal decision
diagram. Internal nodes (ids ``>= 0``) test proposition ``names[var[u]]`` (``names`` sorted, the
order of the shared guard table) and go to ``high[u]`` when it is true, ``low[u]`` when false;
*leaves* are states, encoded as negative ids: state ``s`` is leaf ``~s`` (``-s - 1``). A
complete DFA over it is one root per state (``step(q, label)`` walks ``roots[q]`` down to a
leaf). Nodes are shared between states, so a DFA with 2^n states and 3^n letter classes (``F p1
& ... & F pn``) needs n·2^(n-1) nodes instead of 3^n guarded edges: this is how MONA stores
automata, here in three flat integer lists (typed arrays once an automaton is finished). No
pass recurses: a diagram can test hundreds of propositions.

Nothing here enumerates (state, successor) pairs unless asked to:

* exploring states (``reachable``, shortest words, products) walks each diagram node once for
  the whole automaton, not once per state: a node met again was already walked from a state
  no later in breadth-first order, so every leaf below it is already found (and at no greater
  distance, which keeps breadth-first search exact);
* minimisation (:func:`coarsest_blocks`) is Moore's refinement on *signatures*: a state's
  diagram with every leaf replaced by its block, hash-consed per round, so one round costs one
  pass over the nodes and equal signatures are equal ids (on large diagrams the pass runs in numpy,
  one proposition's nodes at a time: :func:`_moore_rounds_numpy`);
* guarded edges are produced only by :func:`materialise`, with a size limit that says so.

The canonical numbering of a symbolic DFA (:func:`canonical_numbering`) is breadth-first from
the initial state, a state's successors taken in the order a low-first walk of its diagram first
meets them (nodes walked once overall). Explicit DFAs keep their guard-order numbering
(:func:`symlearn.logic.automata.operations.canonical_order`); :func:`finish` decides which one a
minimal DFA gets by its number of edges (:data:`EXPLICIT_EDGES`).
"""

from __future__ import annotations

import sys
from array import array
from collections import deque
from contextlib import contextmanager
from collections.abc import Iterable, Sequence
from typing import AbstractSet

from symlearn.errors import LimitExceededError
from symlearn.logic.automata.partition_refinement import split_blocks

__all__ = ["TransitionDiagram", "ProductNodesExceeded", "EXPLICIT_EDGES", "MAX_MATERIALISED_EDGES", "materialise", "count_edges",
           "coarsest_blocks", "canonical_numbering", "finish", "from_guarded", "product", "reachable",
           "shortest_word", "live", "minimal", "quotient", "canonical_form"]

#: a minimal DFA with at most this many guarded edges is returned with explicit edges (numbered
#: in guard order, as before symbolic transitions existed); above, its transitions stay symbolic
EXPLICIT_EDGES = 10_000
#: producing more guarded edges than this from a symbolic DFA raises LimitExceededError
MAX_MATERIALISED_EDGES = 1_000_000


class ProductNodesExceeded(LimitExceededError):
    """A product's diagram would need more nodes than its ``max_nodes`` (its states may be few):
    a kind of its own, so that a caller names the right limit without reading the message."""


class TransitionDiagram:
    """Hash-consed nodes ``(var, low, high)``; leaves ``~state``. Grows only (no collection):
    a diagram belongs to the automata built on it and dies with them.

    Children are always built before their parents, so *a node's children have smaller ids*:
    the passes below (signatures, renaming) are plain loops over ``range(len(diagram))``
    instead of memoised recursions, which is what makes them cheap in Python.
    """

    __slots__ = ("names", "var", "low", "high", "_unique")

    def __init__(self, names: Sequence[str]) -> None:
        self.names: tuple[str, ...] = tuple(names)
        self.var: list[int] = []
        self.low: list[int] = []
        self.high: list[int] = []
        self._unique: dict[tuple[int, int, int], int] | None = {}

    @classmethod
    def from_arrays(cls, names: Sequence[str], var: list[int], low: list[int], high: list[int]) -> TransitionDiagram:
        """A diagram from node lists that are already reduced, unique and children-first (not
        checked: for the passes here, which produce them so); the unique table is built only if
        a node is ever added."""
        diagram = cls(names)
        diagram.var, diagram.low, diagram.high, diagram._unique = var, low, high, None
        return diagram

    def __len__(self) -> int:
        """Internal nodes (leaves are not stored)."""
        return len(self.var)

    def node(self, var: int, low: int, high: int) -> int:
        """The node testing proposition index ``var`` (above the variables of ``low``/``high``)."""
        if low == high:
            return low
        key = (var, low, high)
        unique = self._unique
        if unique is None:
            unique = self._unique = {k: u for u, k in enumerate(zip(self.var, self.low, self.high))}
        found = unique.get(key)
        if found is None:
            found = unique[key] = len(self.var)
            self.var.append(var)
            self.low.append(low)
            self.high.append(high)
        return found

    def step(self, root: int, label: AbstractSet[str]) -> int:
        """The state reached from diagram ``root`` under ``label``."""
        var, low, high, names = self.var, self.low, self.high, self.names
        u = root
        while u >= 0:
            u = high[u] if names[var[u]] in label else low[u]
        return ~u

    def leaves(self, root: int) -> list[int]:
        """The states below ``root``, in low-first order (one walk of this root alone)."""
        found: list[int] = []
        seen_leaves: set[int] = set()
        seen: set[int] = set()
        stack = [root]
        low, high = self.low, self.high
        while stack:
            u = stack.pop()
            if u < 0:
                if u not in seen_leaves:
                    seen_leaves.add(u)
                    found.append(~u)
            elif u not in seen:
                seen.add(u)
                stack.append(high[u])
                stack.append(low[u])
        return found

    def memory_bytes(self) -> int:
        """Bytes held by the node lists and the unique table (``sys.getsizeof``, keys included)."""
        size = sum(sys.getsizeof(x) for x in (self.var, self.low, self.high))
        if self._unique is not None:
            size += sys.getsizeof(self._unique) + len(self._unique) * sys.getsizeof((0, 0, 0))
        return size


def _walk_new(diagram: TransitionDiagram, root: int, visited: set[int]) -> Iterable[tuple[int, tuple[int, ...]]]:
    """Leaves met walking ``root`` low-first, skipping nodes in ``visited`` (which grows), each
    with the proposition indices set true on the path that met it."""
    low, high, var = diagram.low, diagram.high, diagram.var
    stack: list[tuple[int, tuple[int, ...]]] = [(root, ())]
    while stack:
        u, path = stack.pop()
        if u < 0:
            yield ~u, path
        elif u not in visited:
            visited.add(u)
            stack.append((high[u], path + (var[u],)))
            stack.append((low[u], path))


def reachable(diagram: TransitionDiagram, roots: Sequence[int], start: int) -> list[int]:
    """States reachable from ``start``, in canonical breadth-first order."""
    return _explore(diagram, roots, start)[0]


def _explore(diagram: TransitionDiagram, roots: Sequence[int], start: int) -> tuple[list[int], bytearray]:
    """States reachable from ``start`` in canonical order, and which nodes their roots reach."""
    low, high = diagram.low, diagram.high
    order, seen = [start], {start}
    visited = bytearray(len(diagram))
    for q in order:
        stack = [roots[q]]
        while stack:
            u = stack.pop()
            if u < 0:
                t = ~u
                if t not in seen:
                    seen.add(t)
                    order.append(t)
            elif not visited[u]:
                visited[u] = 1
                stack.append(high[u])
                stack.append(low[u])
    return order, visited


def canonical_numbering(diagram: TransitionDiagram, roots: Sequence[int], initial: int) -> list[int]:
    """The states reachable from ``initial`` in the canonical order of symbolic DFAs."""
    return _explore(diagram, roots, initial)[0]


def shortest_word(diagram: TransitionDiagram, roots: Sequence[int], start: int,
                  targets: AbstractSet[int]) -> list[frozenset[str]] | None:
    """A shortest word from ``start`` into ``targets`` (breadth-first), or ``None``.

    Each letter is the path label of the first diagram path found to the next state: the
    propositions tested true on it, every other one false.
    """
    names = diagram.names
    parent: dict[int, tuple[int, tuple[int, ...]] | None] = {start: None}
    queue, visited = deque([start]), set()
    while queue:
        q = queue.popleft()
        if q in targets:
            word = []
            while parent[q] is not None:
                q, path = parent[q]  # type: ignore[misc]
                word.append(frozenset(names[i] for i in path))
            return word[::-1]
        for t, path in _walk_new(diagram, roots[q], visited):
            if t not in parent:
                parent[t] = (q, path)
                queue.append(t)
    return None


def live(diagram: TransitionDiagram, roots: Sequence[int], accepting: Iterable[int]) -> set[int]:
    """States from which an accepting state is reachable: a backward search over the states'
    successor sets (linear in their total size; a fixpoint of passes over the nodes took one
    pass per state of a chain)."""
    predecessors: list[list[int]] = [[] for _ in roots]
    for q, leaves in enumerate(_successor_sets(diagram, roots, None)):
        for leaf in leaves:
            predecessors[~leaf].append(q)
    alive = set(accepting)
    stack = list(alive)
    while stack:
        for q in predecessors[stack.pop()]:
            if q not in alive:
                alive.add(q)
                stack.append(q)
    return alive


#: Moore rounds tried before minimisation switches to Hopcroft (see :func:`coarsest_blocks`)
MOORE_ROUNDS = 24
#: Moore rounds on diagrams with at least this many nodes, and this many per level (proposition),
#: use numpy (:func:`_moore_rounds_numpy`): below, numpy's fixed cost per array operation (a dozen
#: per level and round) outweighs the Python loop's cost per node (measured in docs/BENCHMARKS.md)
VECTOR_MOORE_NODES = 2000
VECTOR_MOORE_NODES_PER_LEVEL = 200
#: while numpy is not imported, Moore rounds stay in Python until rounds x nodes reaches this (about
#: the 0.1 s numpy's import costs): a small translation never pays the import for a few rounds
NUMPY_IMPORT_WORK = 300_000


def coarsest_blocks(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool]) -> list[int]:
    """Block of every state in the language-equivalence partition.

    Moore's rounds first (:func:`coarsest_blocks_moore`): one pass over the shared diagram per
    round, which is what a wide automaton wants (``F p1 & ... & F p13``: 8,192 states, 13 rounds,
    well under a second; Hopcroft's per-splitter walks took 50 s there). A round refines the
    partition, so when :data:`MOORE_ROUNDS` rounds have not converged -- a long chain needs one
    round per state -- Hopcroft (:func:`coarsest_blocks_hopcroft`) finishes from the partition
    reached, which is correct from any partition coarser than the result."""
    block, converged = _moore_rounds(diagram, roots, accepting, MOORE_ROUNDS)
    return block if converged else coarsest_blocks_hopcroft(diagram, roots, accepting, start=block)


def coarsest_blocks_hopcroft(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool], *,
                             start: Sequence[int] | None = None) -> list[int]:
    """The partition by Hopcroft's algorithm with symbolic splitters (from the partition
    ``start``, default: accepting / rejecting), as :func:`symlearn.logic.automata.operations.coarsest_partition` does it
    for guarded edges. Processing block ``B`` gives each predecessor ``q`` of ``B`` the function
    "which letters lead into ``B``": ``q``'s diagram with every leaf replaced by whether it lies
    in ``B``, hash-consed, so equal functions are equal numbers. A block splits by those numbers
    (the states without an edge into ``B`` form one more part); every part but the largest goes
    on the worklist, so a state changes block O(log n) times. A chain of 10^5 states takes
    seconds, where Moore's rounds (:func:`coarsest_blocks_moore`, one per state of the chain)
    were quadratic."""
    n = len(roots)
    if n == 0:
        return []
    var, low, high = diagram.var, diagram.low, diagram.high
    predecessors: list[list[int]] = [[] for _ in range(n)]
    for q, leaves in enumerate(_successor_sets(diagram, roots, None)):
        for leaf in leaves:
            predecessors[~leaf].append(q)
    if start is None:
        first = bool(accepting[0])
        start = [0 if bool(accepting[q]) == first else 1 for q in range(n)]
    grouped: dict[int, set[int]] = {}
    for q, b in enumerate(start):
        grouped.setdefault(b, set()).add(q)
    blocks = list(grouped.values())
    block_of = [0] * n
    for b, members in enumerate(blocks):
        for q in members:
            block_of[q] = b
    work = list(range(len(blocks)))
    while work:
        inside = blocks[work.pop()]
        unique: dict[tuple[int, int, int], int] = {}
        memo: dict[int, int] = {}

        def into(root: int) -> int:
            """The hash-consed "leads into B" function of the node ``root`` (leaves: ~1 inside B,
            ~0 outside); children first by an explicit stack, shared nodes computed once."""
            if root < 0:
                return ~1 if ~root in inside else ~0
            stack = [root]
            while stack:
                u = stack[-1]
                if u in memo:
                    stack.pop()
                    continue
                lo, hi = low[u], high[u]
                if lo >= 0 and lo not in memo:
                    stack.append(lo)
                    continue
                if hi >= 0 and hi not in memo:
                    stack.append(hi)
                    continue
                stack.pop()
                a = memo[lo] if lo >= 0 else (~1 if ~lo in inside else ~0)
                b = memo[hi] if hi >= 0 else (~1 if ~hi in inside else ~0)
                memo[u] = a if a == b else unique.setdefault((var[u], a, b), len(unique))
            return memo[root]

        touched: dict[int, dict[int, list[int]]] = {}
        for q in {q for t in inside for q in predecessors[t]}:
            touched.setdefault(block_of[q], {}).setdefault(into(roots[q]), []).append(q)
        split_blocks(blocks, block_of, touched, work)
    return block_of


def coarsest_blocks_moore(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool]) -> list[int]:
    """The partition by Moore's rounds with symbolic signatures (one round per refinement step:
    quadratic on a chain; the reference the tests compare Hopcroft with)."""
    return _moore_rounds(diagram, roots, accepting, None)[0]


def _moore_rounds(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool],
                  max_rounds: int | None) -> tuple[list[int], bool]:
    """``(partition, whether it converged)`` after at most ``max_rounds`` Moore rounds: numpy
    rounds on large ordered diagrams (:func:`_moore_rounds_numpy`), the Python loop on the rest.
    Both give the same blocks, numbered alike (by each block's first state), so a run can start
    in one and finish in the other."""
    block = _initial_blocks(accepting, len(roots))
    if len(diagram) >= VECTOR_MOORE_NODES and len(roots) > 0:
        # numpy's import (~0.1 s) is worth it only for enough rounds: while numpy is not loaded,
        # Python rounds first, until they have cost about as much as the import would
        first = 0 if _numpy_loaded() else -(-NUMPY_IMPORT_WORK // len(diagram))
        if max_rounds is not None:
            first = min(first, max_rounds)
        block, converged, done = _moore_rounds_python(diagram, roots, block, first)
        left = None if max_rounds is None else max_rounds - done
        if converged or left == 0:
            return block, converged
        levels = _levels_worth_numpy(diagram, len(roots))
        if levels is not None:
            return _moore_rounds_numpy(roots, block, left, levels, len(diagram))
        max_rounds = left
    return _moore_rounds_python(diagram, roots, block, max_rounds)[:2]


def _numpy_loaded() -> bool:
    """Whether numpy is imported already (by anything), so using it costs no import."""
    return "numpy" in sys.modules


def _levels_worth_numpy(diagram: TransitionDiagram, n_states: int):
    """The diagram's levels (:func:`_variable_levels`) when it is large enough, in nodes and in
    nodes per level, for the numpy passes to beat the Python loops, else None."""
    if len(diagram) < VECTOR_MOORE_NODES or n_states == 0:
        return None
    if len(diagram) < VECTOR_MOORE_NODES_PER_LEVEL * len(set(diagram.var)):  # one level a proposition
        return None
    return _variable_levels(diagram, n_states)


def _initial_blocks(accepting: Sequence[bool], n_states: int) -> list[int]:
    """Accepting / rejecting, the block of state 0 numbered 0."""
    first = bool(accepting[0]) if n_states else False
    return [0 if bool(a) == first else 1 for a in accepting]


def _moore_rounds_python(diagram: TransitionDiagram, roots: Sequence[int], block: list[int],
                         max_rounds: int | None) -> tuple[list[int], bool, int]:
    """Moore's rounds from partition ``block`` as one Python loop over the nodes per round
    (cheapest on small diagrams): ``(partition, converged, rounds done)``."""
    n_blocks = len(set(block))  # block ids 0..n_blocks-1
    var, low, high = diagram.var, diagram.low, diagram.high
    n_nodes = len(var)
    rounds = 0
    while True:
        if max_rounds is not None and rounds >= max_rounds:
            return block, False, rounds
        rounds += 1
        # a node's signature: the node with every leaf replaced by its state's block, hash-consed
        # (ids >= 0; a leaf's signature is ~block); children first, so one loop per round
        unique: dict[tuple[int, int, int], int] = {}
        sig = [0] * n_nodes
        for u in range(n_nodes):
            lo, hi = low[u], high[u]
            lo = sig[lo] if lo >= 0 else ~block[~lo]
            hi = sig[hi] if hi >= 0 else ~block[~hi]
            if lo == hi:
                sig[u] = lo
            else:
                key = (var[u], lo, hi)
                found = unique.get(key)
                if found is None:
                    found = unique[key] = len(unique)
                sig[u] = found
        classes: dict[tuple[int, int], int] = {}
        new_block = [classes.setdefault((block[q], sig[r] if r >= 0 else ~block[~r]), len(classes))
                     for q, r in enumerate(roots)]
        if len(classes) == n_blocks:
            return block, True, rounds
        block, n_blocks = new_block, len(classes)


def _variable_levels(diagram: TransitionDiagram, n_states: int):
    """The nodes grouped by the proposition they test, last proposition first, as ``[(nodes,
    low, high)]`` with every child shifted by ``n_states`` (leaf ``~s`` -> ``n_states - 1 - s``,
    node ``u`` -> ``n_states + u``: one non-negative index into one table of signatures); None
    if the diagram is not ordered.

    Why levels by proposition (and not by height): in an ordered diagram a node's children test
    later propositions, so a level depends only on the levels before it; and a signature node
    testing proposition ``v`` can only be made at level ``v``, so hash-consing (low, high)
    within a level gives equal functions equal ids -- what the Python loop's global table
    does. Heights would not: relabelling leaves by blocks merges nodes, and one function could
    then come out of two heights with two ids."""
    import numpy as np  # here, not at the top: small translations never pay numpy's import

    var = np.asarray(diagram.var, dtype=np.int64)
    low = np.asarray(diagram.low, dtype=np.int64)
    high = np.asarray(diagram.high, dtype=np.int64)
    for child in (low, high):
        inner = child >= 0
        if not np.all(var[child[inner]] > var[inner]):
            return None
    # stable: a level's nodes stay in increasing id order; on 16-bit keys numpy sorts by radix
    last = int(var.max())
    key = last - var
    order = np.argsort(key.astype(np.int16) if last < 2 ** 15 else key, kind="stable")
    starts = np.flatnonzero(np.diff(var[order])) + 1
    return [(nodes + n_states, low[nodes] + n_states, high[nodes] + n_states)
            for nodes in np.split(order, starts)]


def _moore_rounds_numpy(roots: Sequence[int], block: list[int], max_rounds: int | None,
                        levels, n_nodes: int) -> tuple[list[int], bool]:
    """Moore's rounds from partition ``block`` with numpy, one level (:func:`_variable_levels`)
    at a time: a few array operations per level instead of a Python step per node. Signatures
    live in one table, leaves first (``~block``, negative) then nodes (ids >= 0, distinct across
    levels)."""
    import numpy as np

    n = len(roots)
    block = np.asarray(block, dtype=np.int64)
    n_blocks = len(np.unique(block))
    roots_at = np.asarray(roots, dtype=np.int64) + n
    table = np.empty(n + n_nodes, dtype=np.int64)
    width = n + n_nodes  # signatures + n lie in [0, width)
    rounds = 0
    while True:
        if max_rounds is not None and rounds >= max_rounds:
            return block.tolist(), False
        rounds += 1
        _signature_pass(table, block, levels)
        new_block, n_classes = _first_seen_classes(block * width + (table[roots_at] + n))
        if n_classes == n_blocks:
            return block.tolist(), True
        block, n_blocks = new_block, n_classes


def _signature_pass(table, block, levels, creators: list | None = None) -> None:
    """Fill ``table`` (leaves, then nodes; see :func:`_variable_levels`) with every node's
    signature under ``block``: its diagram with each leaf replaced by the state's block,
    hash-consed level by level (a node whose children agree is its child). With ``creators``,
    append per level the first (lowest) node that made each new id, in id order."""
    import numpy as np

    n = len(block)
    width = len(table)  # signatures lie in [-n, len(table) - n): shifted by n, one factor of a key
    table[:n] = ~block[::-1]  # leaf ~s sits at n - 1 - s
    next_id = 0
    for nodes, low, high in levels:
        lo, hi = table[low], table[high]
        split = lo != hi  # the others take their child's signature
        if split.any():
            key = (lo[split] + n) * width + (hi[split] + n)
            if creators is None:
                distinct, ids = np.unique(key, return_inverse=True)
            else:
                # a level's nodes are in increasing id order, so the first occurrence is the lowest node
                distinct, first, ids = np.unique(key, return_index=True, return_inverse=True)
                creators.append(nodes[split][first] - n)
            lo[split] = ids.ravel() + next_id
            next_id += len(distinct)
        table[nodes] = lo


def _first_seen_classes(key):
    """Class ids of the keys numbered in the order of first occurrence (as the Python loop's
    ``setdefault`` numbers them), and their count."""
    import numpy as np

    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first)] = np.arange(len(first))
    return rank[inverse.ravel()], len(first)


def quotient(diagram: TransitionDiagram, roots: Sequence[int], block: Sequence[int],
             accepting: Sequence[bool], initial: int) -> tuple[TransitionDiagram, list[int], list[bool], int, list[int]]:
    """The DFA on blocks (one representative each), renumbered canonically, in a fresh diagram:
    ``(diagram, roots, accepting, initial, order)``, ``order[i]`` the block that became state ``i``."""
    representative: dict[int, int] = {}
    for q, b in enumerate(block):
        representative.setdefault(b, q)
    if len(representative) == len(roots):  # nothing merged: the states are the blocks
        block = range(len(roots))
        representative = {q: q for q in block}
        staged, block_roots = diagram, list(roots)
    else:
        # one pass: worth numpy's import only if it is loaded already (by the Moore rounds)
        levels = _levels_worth_numpy(diagram, len(roots)) if _numpy_loaded() else None
        if levels is not None:
            staged, block_roots = _merged_diagram_numpy(diagram, roots, block, representative, levels)
        else:
            staged, block_roots = _merged_diagram_python(diagram, roots, block, representative)
    order, keep = _explore(staged, block_roots, block[initial])
    index = [0] * len(block_roots)
    for i, b in enumerate(order):
        index[b] = i
    # keep the nodes the reachable blocks use, children first as before; rename leaves
    if len(staged) >= VECTOR_MOORE_NODES and _numpy_loaded():
        result, position = _kept_nodes_numpy(staged, keep, index)
    else:
        result, position = _kept_nodes_python(staged, keep, index)
    new_roots = []
    for b in order:
        r = block_roots[b]
        new_roots.append(position[r] if r >= 0 else ~index[~r])
    new_accepting = [accepting[representative[b]] for b in order]
    return result, new_roots, new_accepting, 0, order


def _merged_diagram_python(diagram: TransitionDiagram, roots: Sequence[int], block: Sequence[int],
                           representative: dict[int, int]) -> tuple[TransitionDiagram, list[int]]:
    """The diagram with leaves replaced by blocks, and one root per block: merged states can
    make nodes equal, so hash-cons again (nodes numbered in the order they are first made)."""
    staged = TransitionDiagram(diagram.names)
    var, low, high = diagram.var, diagram.low, diagram.high
    new_id = [0] * len(var)
    node = staged.node
    for u in range(len(var)):
        lo, hi = low[u], high[u]
        new_id[u] = node(var[u], new_id[lo] if lo >= 0 else ~block[~lo], new_id[hi] if hi >= 0 else ~block[~hi])
    block_roots = [0] * len(representative)
    for b, q in representative.items():
        r = roots[q]
        block_roots[b] = new_id[r] if r >= 0 else ~block[~r]
    return staged, block_roots


def _merged_diagram_numpy(diagram: TransitionDiagram, roots: Sequence[int], block: Sequence[int],
                          representative: dict[int, int], levels) -> tuple[TransitionDiagram, list[int]]:
    """:func:`_merged_diagram_python` by one signature pass: the merged diagram's nodes are the
    signatures under ``block``. node() numbers a node when the lowest original node that makes
    it comes by, so the signatures, ordered by that node, are numbered exactly as there (and
    stay children-first: a node's children were made by lower nodes)."""
    import numpy as np

    n = len(roots)
    table = np.empty(n + len(diagram), dtype=np.int64)
    creators: list = []
    _signature_pass(table, np.asarray(block, dtype=np.int64), levels, creators)
    creator = np.concatenate(creators) if creators else np.zeros(0, dtype=np.int64)
    made = np.argsort(creator)  # signature ids in the order node() would have made them
    renumber = np.empty(len(made), dtype=np.int64)
    renumber[made] = np.arange(len(made))

    def merged(at):
        """Merged ids of the table entries ``at`` (node signatures renumbered, leaves kept)."""
        sig = table[at]
        inner = sig >= 0
        sig[inner] = renumber[sig[inner]]
        return sig

    maker = creator[made]
    var = np.asarray(diagram.var, dtype=np.int64)
    low = np.asarray(diagram.low, dtype=np.int64)
    high = np.asarray(diagram.high, dtype=np.int64)
    staged = TransitionDiagram.from_arrays(diagram.names, var[maker].tolist(), merged(low[maker] + n).tolist(),
                                           merged(high[maker] + n).tolist())
    blocks = sorted(representative)
    at = np.asarray([roots[representative[b]] for b in blocks], dtype=np.int64) + n
    block_roots = [0] * len(representative)
    for b, r in zip(blocks, merged(at).tolist()):
        block_roots[b] = r
    return staged, block_roots


def _kept_nodes_python(staged: TransitionDiagram, keep: bytearray, index: list[int]):
    """The final diagram of the nodes marked in ``keep``, children first as before, leaves
    renamed by ``index``; and every kept node's new position."""
    svar, slow, shigh = staged.var, staged.low, staged.high
    position = [0] * len(svar)
    nvar: list[int] = []
    nlow: list[int] = []
    nhigh: list[int] = []
    for u in range(len(svar)):
        if keep[u]:
            lo, hi = slow[u], shigh[u]
            position[u] = len(nvar)
            nvar.append(svar[u])
            nlow.append(position[lo] if lo >= 0 else ~index[~lo])
            nhigh.append(position[hi] if hi >= 0 else ~index[~hi])
    # typed arrays: 4 bytes a field instead of a pointer and an int object (36 bytes): the
    # diagram of a minimal DFA is what lives on with it
    return TransitionDiagram.from_arrays(staged.names, array("i", nvar), array("i", nlow), array("i", nhigh)), position


def _kept_nodes_numpy(staged: TransitionDiagram, keep: bytearray, index: list[int]):
    """:func:`_kept_nodes_python` with numpy: the same typed arrays and positions (a kept node's
    position is the number of kept nodes before it)."""
    import numpy as np

    kept = np.frombuffer(keep, dtype=np.uint8).astype(bool)
    position = np.cumsum(kept) - 1
    leaf_index = np.asarray(index, dtype=np.int64)

    def renamed(children):
        children = np.asarray(children, dtype=np.int64)[kept]
        inner = children >= 0
        return np.where(inner, position[np.where(inner, children, 0)], ~leaf_index[~np.minimum(children, -1)])

    fields = [np.asarray(staged.var, dtype=np.int64)[kept], renamed(staged.low), renamed(staged.high)]
    typed = [array("i", f.astype(np.intc).tobytes()) for f in fields]
    return TransitionDiagram.from_arrays(staged.names, *typed), position.tolist()


def canonical_form(diagram: TransitionDiagram, roots: Sequence[int]) -> tuple:
    """A value equal for two diagrams exactly when their states have the same transitions:
    nodes renumbered in the order a walk from the roots (in state order) finishes them."""
    names, var, low, high = diagram.names, diagram.var, diagram.low, diagram.high
    ids: dict[int, int] = {}
    nodes: list[tuple[str, int, int]] = []
    encoded = []
    for root in roots:
        stack = [root]
        while stack:
            u = stack[-1]
            if u < 0 or u in ids:
                stack.pop()
                continue
            lo, hi = low[u], high[u]
            waiting = [c for c in (hi, lo) if c >= 0 and c not in ids]
            if waiting:
                stack.extend(waiting)
                continue
            stack.pop()
            ids[u] = len(nodes)
            nodes.append((names[var[u]], lo if lo < 0 else ids[lo], hi if hi < 0 else ids[hi]))
        encoded.append(root if root < 0 else ids[root])
    return tuple(encoded), tuple(nodes)


def _successor_sets(diagram: TransitionDiagram, roots: Sequence[int], limit: int | None):
    """Per root, the frozenset of leaves below it; ``None`` once their sizes sum past ``limit``
    (only the nodes below the roots looked at so far are visited)."""
    low, high = diagram.low, diagram.high
    below: dict[int, frozenset[int]] = {}
    result = []
    total = 0
    for root in roots:
        stack = [root]
        while stack:  # children first, by an explicit stack
            u = stack[-1]
            if u in below:
                stack.pop()
            elif u < 0:
                below[u] = frozenset((u,))
                stack.pop()
            else:
                lo, hi = low[u], high[u]
                if lo in below and hi in below:
                    below[u] = below[lo] | below[hi]
                    stack.pop()
                    if limit is not None and len(below[u]) > limit:
                        return None
                else:
                    stack.append(hi)
                    stack.append(lo)
        result.append(below[root])
        total += len(below[root])
        if limit is not None and total > limit:
            return None
    return result


#: bytes of successor bit sets :func:`count_edges` keeps alive at once before it counts with
#: frozensets instead (bit sets are ~100x smaller than frozensets, but a few successors far apart
#: in numbering make a wide one)
COUNT_BITSET_BYTES = 64 << 20


def count_edges(diagram: TransitionDiagram, roots: Sequence[int], limit: int | None = None) -> int | None:
    """Guarded edges of the DFA (distinct successors summed over states); ``None`` beyond ``limit``."""
    counted = _count_by_bitsets(diagram, roots, limit, COUNT_BITSET_BYTES)
    if counted is not _TOO_WIDE:
        return counted
    sets = _successor_sets(diagram, roots, limit)
    return None if sets is None else sum(len(x) for x in sets)


_TOO_WIDE = object()


def _count_by_bitsets(diagram: TransitionDiagram, roots: Sequence[int], limit: int | None, budget: int):
    """:func:`count_edges` in one children-first loop over the nodes below the roots (ids are
    children-first), each node's successors an integer bit set (bit ``i`` is state ``offset + i``),
    freed when its last parent has used it. Unions are single big-integer ORs, so the 3^14
    successors of ``F p1 & ... & F p14`` are counted in a fraction of the time per-node
    frozensets take. ``_TOO_WIDE`` when the live sets would pass ``budget`` bytes."""
    low, high = diagram.low, diagram.high
    total = 0
    root_uses: dict[int, int] = {}
    for r in roots:
        if r < 0:
            total += 1  # every letter goes to one state
        else:
            root_uses[r] = root_uses.get(r, 0) + 1
    if limit is not None and total > limit:
        return None
    if not root_uses:
        return total
    top = max(root_uses)
    # uses still to come of each node below the roots: one per parent below a root, one per root
    uses = [0] * (top + 1)
    for r, k in root_uses.items():
        uses[r] = k
    for u in range(top, -1, -1):
        if uses[u]:
            lo, hi = low[u], high[u]
            if lo >= 0:
                uses[lo] += 1
            if hi >= 0:
                uses[hi] += 1
    offsets = [0] * (top + 1)
    sets = [0] * (top + 1)
    live = 0
    for u in range(top + 1):
        if not uses[u]:
            continue
        lo, hi = low[u], high[u]
        if lo < 0:
            o1, b1 = ~lo, 1
        else:
            o1, b1 = offsets[lo], sets[lo]
            uses[lo] -= 1
            if not uses[lo]:
                live -= b1.bit_length() >> 3
                sets[lo] = 0
        if hi < 0:
            o2, b2 = ~hi, 1
        else:
            o2, b2 = offsets[hi], sets[hi]
            uses[hi] -= 1
            if not uses[hi]:
                live -= b2.bit_length() >> 3
                sets[hi] = 0
        if o1 <= o2:
            offset, bits = o1, b1 | (b2 << (o2 - o1))
        else:
            offset, bits = o2, b2 | (b1 << (o1 - o2))
        k = root_uses.get(u)
        if k is not None:
            total += k * bits.bit_count()
            if limit is not None and total > limit:
                return None
            uses[u] -= k
        if uses[u]:  # a parent above still needs it
            offsets[u], sets[u] = offset, bits
            live += bits.bit_length() >> 3
            if live > budget:
                return _TOO_WIDE
    return total


def materialise(diagram: TransitionDiagram, roots: Sequence[int], limit: int | None = MAX_MATERIALISED_EDGES):
    """Per state ``[(Guard, target), ...]`` (one guard per target, canonical BDD guards).

    Raises :class:`LimitExceededError` when the DFA has more than ``limit`` edges.
    """
    from symlearn.logic.bdd import BDD, TRUE
    from symlearn.logic.guards import from_bdd

    if limit is not None and count_edges(diagram, roots, limit) is None:
        raise LimitExceededError(
            f"this DFA ({len(roots):,} states) has more than {limit:,} guarded edges; its transitions are "
            "kept symbolic (one decision diagram per state) and are not materialised",
            hint="use what works on the symbolic form (run, accepts, product, minimize, complement, "
                 "is_empty, shortest words, equivalent) or pass a larger limit to materialise()")
    bdd = BDD()
    var, low, high = diagram.var, diagram.low, diagram.high
    memo: dict[int, dict[int, int]] = {}

    def split(root: int) -> dict[int, int]:
        """target -> guard node of ``root`` (children first, by an explicit stack)."""
        stack = [root]
        while stack:
            u = stack[-1]
            if u in memo:
                stack.pop()
            elif u < 0:
                memo[u] = {~u: TRUE}
                stack.pop()
            else:
                lo_u, hi_u = low[u], high[u]
                if lo_u in memo and hi_u in memo:
                    lo, hi = memo[lo_u], memo[hi_u]
                    memo[u] = bdd.nodes_by_key(var[u], lo, hi)
                    stack.pop()
                else:
                    stack.append(hi_u)
                    stack.append(lo_u)
        return memo[root]

    rows = [list(split(root).items()) for root in roots]
    guards = iter(from_bdd(bdd, [g for row in rows for _, g in row], list(diagram.names)))
    return [[(next(guards), t) for t, _ in row] for row in rows]


@contextmanager
def _recursion_for(depth: int):
    """Room for a recursion one frame per proposition (apply and Shannon expansion recurse)."""
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 4 * depth + 1000))
    try:
        yield
    finally:
        sys.setrecursionlimit(limit)


def from_guarded(names: Sequence[str], rows: Sequence[Sequence[tuple]]) -> tuple[TransitionDiagram, list[int]]:
    """The diagram of a complete DFA given as guarded edges ``[(Guard, target), ...]`` per state.

    Shannon expansion on the first proposition any remaining guard tests; the edges of one
    state are disjoint and cover every label (the caller completes the DFA first).
    """
    from symlearn.logic.guards import _MANAGER

    names = tuple(names)
    position = {name: i for i, name in enumerate(names)}
    level, glow, ghigh = _MANAGER.level, _MANAGER.low, _MANAGER.high
    diagram = TransitionDiagram(names)
    memo: dict[tuple, int] = {}

    def build(cases: tuple[tuple[int, int], ...]) -> int:
        live_cases = tuple(c for c in cases if c[0] != 0)
        if len(live_cases) == 1:
            return ~live_cases[0][1]
        if not live_cases:
            raise ValueError("from_guarded needs a complete DFA")  # pragma: no cover - callers complete first
        found = memo.get(live_cases)
        if found is None:
            top = min((level[g] for g, _ in live_cases if g > 1), key=position.__getitem__)
            lo = tuple((glow[g] if g > 1 and level[g] == top else g, t) for g, t in live_cases)
            hi = tuple((ghigh[g] if g > 1 and level[g] == top else g, t) for g, t in live_cases)
            found = memo[live_cases] = diagram.node(position[top], build(lo), build(hi))
        return found

    with _recursion_for(len(names)):
        roots = [build(tuple((g._node, t) for g, t in row)) for row in rows]
    return diagram, roots


def product(left: tuple[TransitionDiagram, Sequence[int], int], right: tuple[TransitionDiagram, Sequence[int], int],
            *, max_states: int | None = None,
            max_nodes: int | None = None) -> tuple[TransitionDiagram, list[int], list[tuple[int, int]]]:
    """Synchronous product of two complete symbolic DFAs ``(diagram, roots, initial)``.

    Returns the product's diagram (over the union of the propositions), one root per reachable
    pair and the pairs, numbered in discovery order. Pairs of nodes are combined once for the
    whole product (memoised apply), so the work is the size of the result's diagram.
    ``max_nodes`` bounds the pairs of nodes combined (what the memory holds: ~250 bytes each),
    so a product whose diagram explodes below ``max_states`` stops before memory runs out.
    """
    d1, roots1, start1 = left
    d2, roots2, start2 = right
    names = tuple(sorted(set(d1.names) | set(d2.names)))
    position = {name: i for i, name in enumerate(names)}
    map1 = [position[n] for n in d1.names]
    map2 = [position[n] for n in d2.names]
    result = TransitionDiagram(names)
    start = (start1, start2)
    index = {start: 0}
    pairs = [start]
    memo: dict[int, int] = {}
    # each node's variable as the product's index, looked up once per node here instead of twice
    # per visit; and the result's node table filled inline (a method call per node was a tenth of
    # a large product's time: countersDouble_pb_05's products 2.14 -> 1.87 s)
    t1 = [map1[x] for x in d1.var]
    t2 = [map2[x] for x in d2.var]
    l1, h1, l2, h2 = d1.low, d1.high, d2.low, d2.high
    rvar, rlow, rhigh, unique = result.var, result.low, result.high, result._unique
    # one int per pair of nodes instead of a tuple (leaves ~s are negative: shifted by the states):
    # the memo is what a large product's memory is made of, ~80 bytes less an entry
    shift1, shift2 = len(roots1), len(roots2)
    stride = len(d2) + shift2 + 1

    def apply(u: int, v: int) -> int:
        key = (u + shift1) * stride + v + shift2
        found = memo.get(key)
        if found is not None:
            return found
        if u < 0:
            if v < 0:
                pair = (~u, ~v)
                j = index.get(pair)
                if j is None:
                    if max_states is not None and len(pairs) >= max_states:
                        raise LimitExceededError(f"the product automaton exceeds {max_states} states",
                                                 hint="raise max_states or minimise the operands first")
                    j = index[pair] = len(pairs)
                    pairs.append(pair)
                memo[key] = ~j
                return ~j
            top = t2[v]
            low, high = apply(u, l2[v]), apply(u, h2[v])
        elif v < 0:
            top = t1[u]
            low, high = apply(l1[u], v), apply(h1[u], v)
        else:
            a, b = t1[u], t2[v]
            if a == b:
                top = a
                low, high = apply(l1[u], l2[v]), apply(h1[u], h2[v])
            elif a < b:
                top = a
                low, high = apply(l1[u], v), apply(h1[u], v)
            else:
                top = b
                low, high = apply(u, l2[v]), apply(u, h2[v])
        if low == high:
            found = low
        else:
            node = (top, low, high)
            found = unique.get(node)
            if found is None:
                found = unique[node] = len(rvar)
                rvar.append(top)
                rlow.append(low)
                rhigh.append(high)
        if max_nodes is not None and len(memo) >= max_nodes:
            raise ProductNodesExceeded(f"the product automaton's diagram needs more than {max_nodes:,} nodes",
                                       hint="minimise the operands first or split the formula")
        memo[key] = found
        return found

    roots: list[int] = []
    i = 0
    with _recursion_for(len(names)):
        while i < len(pairs):
            p, q = pairs[i]
            roots.append(apply(roots1[p], roots2[q]))
            i += 1
    return result, roots, pairs


def minimal(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool], initial: int,
            alphabet: Iterable[str], *, explicit_edges: int = EXPLICIT_EDGES, state_names=None):
    """The minimal complete DFA of a complete automaton given symbolically (see :func:`finish`);
    a block is named after its lowest-numbered state."""
    # unreachable states only add blocks that quotient() leaves out (it numbers from the initial one)
    block = coarsest_blocks(diagram, roots, accepting)
    names = None
    if state_names is not None:
        first: dict[int, str] = {}
        for q, b in enumerate(block):
            first.setdefault(b, state_names[q] if q < len(state_names) else "sink")
        names = first
    diagram, new_roots, new_accepting, new_initial, order = quotient(diagram, roots, block, accepting, initial)
    return finish(diagram, new_roots, new_accepting, new_initial, alphabet, explicit_edges=explicit_edges,
                  state_names=None if names is None else [names[b] for b in order])


def finish(diagram: TransitionDiagram, roots: Sequence[int], accepting: Sequence[bool], initial: int,
           alphabet: Iterable[str], *, explicit_edges: int = EXPLICIT_EDGES, state_names=None):
    """The DFA of a minimal complete automaton numbered by :func:`quotient`: explicit guarded
    edges numbered in guard order (as :meth:`DFA.minimize` numbers them) when it has at most
    ``explicit_edges`` edges, else symbolic transitions in the canonical symbolic order."""
    from symlearn.logic.automata.dfa import DFA

    if count_edges(diagram, roots, explicit_edges) is not None:
        # a DFA's edges of one state are disjoint: label_key orders them as sort_key does
        table = [sorted(row, key=lambda e: e[0].label_key) for row in materialise(diagram, roots, None)]
        index = {initial: 0}
        order = [initial]
        for q in order:  # breadth-first, edges in guard order
            for _, t in table[q]:
                if t not in index:
                    index[t] = len(order)
                    order.append(t)
        names = None if state_names is None else [state_names[q] for q in order]
        return DFA._trusted(alphabet, len(order), 0, [index[q] for q in order if accepting[q]],
                            [[(g, index[t]) for g, t in table[q]] for q in order], names, ordered=True)
    return DFA._symbolic(alphabet, len(roots), initial, [q for q, a in enumerate(accepting) if a], diagram, roots,
                         state_names)
