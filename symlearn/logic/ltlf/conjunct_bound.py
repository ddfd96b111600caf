"""A lower bound on the states of an LTLf translation, from its independent conjuncts, before the work.

``F p1 & ... & F p2000`` has 2^2000 reachable obligations. Exploring them until the state limit
stops the translation costs memory long before: the first state's transition function alone
branches on 2,000 propositions. This module proves, cheaply and before the exploration, that
the exploration would pass the limit, so the refusal comes first.

The argument (sound: a formula is refused only when the exploration would refuse it too):

* Split the top-level conjunction ``c1 & ... & cn`` (negation normal form,
  :mod:`~symlearn.logic.ltlf.to_dfa`) into *independent groups*: conjuncts that share a
  proposition or a sub-formula are in one group, so groups share neither propositions nor
  obligation variables.
* The translation's state after a word ``w`` is the conjunction of each group's state after
  ``w`` (composition with the one-step unfolding commutes with ``&``), and each group's state
  depends only on its own propositions. Words of one length ``t`` can be chosen per group
  independently, so every tuple of group states reachable in exactly ``t`` steps is the
  translation's state after some ``t``-letter word.
* Conjunctions of satisfiable Boolean functions over disjoint variables are equal only when the
  tuples are: for ``f1 & f2 = g1 & g2``, fix the second group's variables to a model of ``f2``,
  which gives ``f1 = g1 & g2(model)``, and ``g2(model)`` is true as ``f1`` is satisfiable. The
  groups do share one variable, ``NE`` ("the rest of the trace is not empty", strong and weak
  next); so states are compared by their cofactor ``NE = true``, which is also a conjunction over
  the groups: distinct tuples of satisfiable cofactors are distinct states.

So for every ``t``, the product over the groups of the number of distinct satisfiable
``NE``-cofactors among the group's states at exactly step ``t`` is a lower bound on the states
the exploration reaches. Each group is explored for a few steps only (:data:`STEPS`), at most
:data:`PER_STEP` states a step and within a node budget, in the translation's own BDD manager
(what it builds there is reused by the exploration that follows); a group cut short counts what
was found, which keeps the bound a lower bound.
"""

from __future__ import annotations

import math

from symlearn.errors import LimitExceededError
from symlearn.logic.bdd import FALSE, TRUE

__all__ = ["independent_groups", "check_state_bound", "MIN_GROUPS", "STEPS", "PER_STEP"]

#: the bound is computed for conjunctions of at least this many independent groups
MIN_GROUPS = 8
#: steps explored per group (blow-ups of products show from the first step: ``F p`` has two
#: states after one letter, so ``F p1 & ... & F pn`` has 2^n)
STEPS = 6
#: states counted per group and step (more would not change a refusal that a product makes)
PER_STEP = 64
#: nodes one group's exploration may add to the manager before it is cut short
NODE_BUDGET = 20_000
#: propositions tested on the way from a composed state to its successors, per state
WALK_BUDGET = 4_096


def independent_groups(nodes: list[tuple], root: int, conjunction: int, literals: tuple[int, int],
                       leaves: tuple[int, int]) -> list[list[int]]:
    """The operands of the top-level conjunction at ``root`` grouped so that no two groups share
    a node or a proposition (union-find over what each operand reaches).

    ``nodes``: the translation's NNF nodes (kind first, children as ids); ``conjunction``: the
    kind of ``&``; ``literals``: the kinds of a proposition and its negation (their second field
    is the name); ``leaves``: the constant kinds. Linear in the number of nodes.
    """
    if nodes[root][0] != conjunction:
        return []
    operands, stack = [], [root]
    while stack:  # the operands of the &-tree, without recursion (a long conjunction is deep)
        nid = stack.pop()
        key = nodes[nid]
        if key[0] == conjunction:
            stack += (key[2], key[1])
        else:
            operands.append(nid)
    if len(operands) < MIN_GROUPS:
        return [operands]  # too few to make MIN_GROUPS groups: no need to tell them apart
    parent = list(range(len(operands)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner: dict[int, int] = {}
    prop_owner: dict[str, int] = {}
    for index, operand in enumerate(operands):
        walk = [operand]
        while walk:
            nid = walk.pop()
            other = owner.get(nid)
            if other is not None:  # reached before, from this operand or another: one group
                parent[find(other)] = find(index)
                continue
            owner[nid] = index
            key = nodes[nid]
            kind = key[0]
            if kind in literals:
                seen = prop_owner.setdefault(key[1], index)
                parent[find(seen)] = find(index)
            elif kind not in leaves:
                walk += [c for c in key[1:]]
    groups: dict[int, list[int]] = {}
    for index, operand in enumerate(operands):
        groups.setdefault(find(index), []).append(operand)
    return list(groups.values())


def check_state_bound(translation, groups: list[list[int]], max_states: int) -> None:
    """Raise :class:`~symlearn.errors.LimitExceededError` when the groups prove that more than
    ``max_states`` states are reachable, or that the first state's transition function needs
    more nodes than the translation's BDD may hold (see the module docstring); else return.

    ``translation``: a :class:`~symlearn.logic.ltlf.to_dfa._Translation` whose levels are set
    (``_now``, ``_compose_state``, ``_balanced``, ``bdd``, ``props``, ``ne_level`` ready).
    """
    if len(groups) < MIN_GROUPS:
        # few groups: their states multiply too, but each state's transitions then test few
        # groups' propositions, so the exploration meets its own limits before the memory is
        # gone; and the check would cost small formulas a third of their translation time
        return
    bdd = translation.bdd
    max_nodes = bdd.max_nodes
    products = [1] * (STEPS + 1)
    widths: list[list[tuple[int, int]] | None] = []
    for group in groups:
        counts, profile = _explore_group(translation, group)
        for t in range(STEPS + 1):
            products[t] *= counts[t] if t < len(counts) else 0
        widths.append(profile)
    best = max(range(STEPS + 1), key=lambda t: products[t])
    if products[best] > max_states:
        raise LimitExceededError(
            f"the automaton of this formula needs more than {max_states} states: its {len(groups)} independent "
            f"conjuncts reach at least {_count_text(products[best])} combinations of their states after {best} "
            f"step{'s' if best != 1 else ''}",
            hint="raise max_states (CLI: --max-states) or split the formula")
    if max_nodes is not None and all(w is not None for w in widths):
        where = _widest_cut(widths, max_nodes + 2)
        if where is not None:
            level, count = where
            name = sorted(translation.props, key=translation.props.get)[level]
            raise LimitExceededError(
                f"the first state's transitions need more than {max_nodes:,} BDD nodes: the {len(groups)} "
                f"independent conjuncts' propositions interleave in name order, which the BDD tests them in "
                f"({_count_text(count)} distinct cases after proposition {name!r})",
                hint="name each conjunct's propositions so that they sort next to each other (p1, p1q, p2, ...), "
                     "split the formula, or raise SYMLEARN_MAX_TRANSLATION_NODES (0: no limit)")


def _explore_group(translation, group: list[int]) -> tuple[list[int], list[tuple[int, int]] | None]:
    """``(counts, profile)`` of one group: distinct satisfiable ``NE``-cofactors among its states
    at step 0, 1, ... (the list stops where the budget ran out: later steps count as unknown,
    i.e. 0), and the width profile of its first transition function (:func:`_profile`; None
    where unknown)."""
    bdd = translation.bdd
    n_props, ne = len(translation.props), translation.ne_level
    saved = bdd.max_nodes
    budget = len(bdd.level) + NODE_BUDGET
    bdd.max_nodes = budget if saved is None else min(saved, budget)
    counts: list[int] = []
    profile = None
    level, low, high = bdd.level, bdd.low, bdd.high
    try:
        states = {translation._balanced([translation._now(nid) for nid in group], True)}
        for step in range(STEPS + 1):
            counts.append(len({c for c in (bdd.restrict(s, ne, True) for s in states) if c != FALSE}))
            following: set[int] = set()
            for state in states:
                if state == FALSE:
                    continue
                top = translation._compose_state(state)
                if step == 0:
                    profile = _profile(bdd, top, n_props, ne)
                stack, walked = [top], set()
                while stack and len(following) < PER_STEP and len(walked) < WALK_BUDGET:
                    u = stack.pop()
                    if u <= TRUE or level[u] >= n_props:
                        following.add(u)  # below the proposition layer: a successor state
                    elif u not in walked:
                        walked.add(u)
                        stack.append(high[u])
                        stack.append(low[u])
                if len(following) >= PER_STEP:
                    break
            states = following
    except LimitExceededError:
        pass  # budget spent: what was counted stands
    finally:
        bdd.max_nodes = saved
    return counts, profile


def _profile(bdd, top: int, n_props: int, ne: int) -> list[tuple[int, int]] | None:
    """``[(level, width)]``: for each proposition level the group's transition function ``top``
    tests, the number of distinct satisfiable (``NE``-cofactored) functions reached right below
    that level, over all values of the propositions down to it. None when ``top`` is
    unsatisfiable (NE = true) or its proposition layer is larger than the budget."""
    level, low, high = bdd.level, bdd.low, bdd.high
    if bdd.restrict(top, ne, True) == FALSE:
        return None
    layer, stack, seen = [], [top], set()
    while stack:
        u = stack.pop()
        if u <= TRUE or level[u] >= n_props or u in seen:
            continue
        if len(layer) >= WALK_BUDGET:
            return None
        seen.add(u)
        layer.append(u)
        stack.append(low[u])
        stack.append(high[u])
    cofactor = (lambda u: bdd.restrict(u, ne, True)) if ne in bdd.support(top) else (lambda u: u)

    def below(u: int) -> int:
        return n_props if u <= TRUE or level[u] >= n_props else level[u]

    profile = []
    for cut in sorted({level[u] for u in layer}):
        reached = {c for u in layer if level[u] <= cut for c in (low[u], high[u]) if below(c) > cut}
        profile.append((cut, len({f for f in map(cofactor, reached) if f != FALSE})))
    return profile


def _widest_cut(profiles: list[list[tuple[int, int]]], bound: int) -> tuple[int, int] | None:
    """A proposition level below which the conjunction of the groups' transition functions has
    more than ``bound`` distinct satisfiable cases (the product of the groups' widths there: they
    test disjoint propositions), as ``(level, count)``; None when there is none."""
    events = sorted((cut, group, width) for group, profile in enumerate(profiles) for cut, width in profile)
    factors = [1] * len(profiles)
    logs, target = 0.0, math.log2(bound) - 1e-6  # rounding: every candidate is confirmed exactly
    for cut, group, width in events:
        if width < 1:
            return None  # cannot happen for a satisfiable function; no claim then
        logs += math.log2(width) - math.log2(factors[group])
        factors[group] = width
        if logs > target:
            count = math.prod(factors)
            if count > bound:
                return cut, count
    return None


def _count_text(n: int) -> str:
    if n < 10**12:
        return f"{n:,}"
    return f"about 10^{int(math.log10(n))}"
