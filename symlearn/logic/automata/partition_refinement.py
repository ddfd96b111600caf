"""One refinement step of Hopcroft's algorithm, shared by the explicit and the symbolic
minimisation (:func:`symlearn.logic.automata.operations.coarsest_partition`,
:func:`symlearn.logic.automata.transition_diagram.coarsest_blocks`)."""

from __future__ import annotations

from collections.abc import Hashable


def split_blocks(blocks: list[set[int]], block_of: list[int], touched: dict[int, dict[Hashable, list[int]]],
                 work: list[int]) -> None:
    """Split every block ``c`` of ``touched`` into the classes ``touched[c]`` (states with equal
    signatures towards the splitter) and the untouched rest; new blocks are appended to
    ``blocks`` and ``work``, ``block_of`` follows.

    The largest part keeps the block's id (and its worklist status); only the others are
    relabelled, each at most half the block, so a state moves O(log n) times. The untouched rest
    is listed only when it is not the largest part: walking a chain's long block once per
    splitter would be quadratic."""
    for c, classes in touched.items():
        parts = list(classes.values())
        members = blocks[c]
        rest_size = len(members) - sum(len(part) for part in parts)
        if len(parts) == 1 and rest_size == 0:
            continue
        largest = max(parts, key=len)
        if rest_size >= len(largest):
            for part in parts:
                members.difference_update(part)
            moved = parts
        else:
            touched_states = {q for part in parts for q in part}
            rest = [q for q in members if q not in touched_states]
            blocks[c] = set(largest)
            moved = [part for part in parts if part is not largest] + ([rest] if rest else [])
        for part in moved:
            blocks.append(set(part))
            for q in part:
                block_of[q] = len(blocks) - 1
            work.append(len(blocks) - 1)
