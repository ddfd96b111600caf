"""Graphviz DOT text for a one-class tree.

Top-down layout. The root shows its sample count and the data's bounds; an internal node the
feature it splits on and the split's gain; an edge the child's interval on that feature
(``L <= x <= R``, tightened to the child's data); a child lists the other features it tightens
relative to its parent's box. Leaves -- the safe boxes -- are filled green. Long lists of
features are cut after ``max_lines`` lines (``...``).

>>> from symlearn.learners.trees import OneClassTreeConstraint
>>> dot = OneClassTreeConstraint(min_samples_leaf=1).fit([[0.0], [0.1], [5.0], [5.1]]).to_dot()
>>> dot.splitlines()[0], dot.count("->")
('digraph one_class_tree {', 2)
"""

from __future__ import annotations

from symlearn.rendering import quote

_LEAF_STYLE = 'style="rounded,filled", fillcolor="#d9f2d9"'


def _num(value: float, digits: int) -> str:
    return f"{value:.{digits}g}"


def _lines(items: list[str], max_lines: int) -> list[str]:
    return items if len(items) <= max_lines else items[: max_lines - 1] + [f"... ({len(items) - max_lines + 1} more)"]


def tree_to_dot(tree, *, digits: int = 4, title: str | None = None, max_lines: int = 8) -> str:
    """DOT for a :class:`~symlearn.learners.trees.OneClassTree`."""
    from symlearn.learners.trees.one_class_tree import tightened

    names = tree.feature_names
    lines = ["digraph one_class_tree {", "  rankdir=TB;"]
    if title:
        lines.append(f"  label={quote(title)}; labelloc=t;")
    lines += ['  graph [fontname="Helvetica"];', '  node [shape=box, style=rounded, fontname="Helvetica"];',
              '  edge [fontname="Helvetica"];']
    ids: dict[int, int] = {}

    def node_id(node) -> int:
        return ids.setdefault(id(node), len(ids))

    def label(node, parent) -> str:
        head = [f"n = {node.n_samples}"]
        if parent is None:
            head.insert(0, "root")
            body = [f"{n} in [{_num(node.box.lower[d], digits)}, {_num(node.box.upper[d], digits)}]"
                    for d, n in enumerate(names)]
        else:
            body = tightened(parent.box, node.box, names, parent.feature, digits)
        if node.is_leaf:
            head.insert(0 if parent is not None else 1, "safe box")
        else:
            head.append(f"split on {names[node.feature]} (gain {node.gain:.3f})")
        return "\n".join(head + _lines(body, max_lines))

    def visit(node, parent) -> None:
        me = node_id(node)
        style = f", {_LEAF_STYLE}" if node.is_leaf else ""
        lines.append(f"  {me} [label={quote(label(node, parent))}{style}];")
        for child in node.children:
            j = node.feature
            edge = f"{_num(child.box.lower[j], digits)} <= {names[j]} <= {_num(child.box.upper[j], digits)}"
            visit(child, node)
            lines.append(f"  {me} -> {node_id(child)} [label={quote(edge)}];")

    visit(tree.root, None)
    lines.append("}")
    return "\n".join(lines) + "\n"


__all__ = ["tree_to_dot"]
