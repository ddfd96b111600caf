"""Group sparsity on the inputs of a feature network: a learned cost that reads few inputs.

A cost network reading the whole observation is free to lean on every entry that differs between
the expert's states and the policy's, relevant to the constraint or not. The group lasso
(Yuan and Lin, 2006) on the first layer's weights, one group per input,

    penalty(W) = sum_j || W[:, j] ||_2          (W: hidden x inputs, column j = input j)

is the convex surrogate of "the number of inputs read": its subgradient pulls every column toward
zero with the same force, whatever its size, so a column whose data gradient is weaker than that
force ends at (about) zero and the input is not read; inputs that carry the signal keep theirs.

:func:`input_penalty` is the term a learner adds to its loss, :func:`input_norms` the column
norms (a ranking of the inputs by how much the network reads them), and :func:`input_shares`
the same normalised to sum to 1 -- what a result reports so a user sees which entries the cost
reads.
"""

from __future__ import annotations

import torch

from symlearn.learners.neural.feature_network import FeatureNetwork


def first_layer_weight(phi: FeatureNetwork) -> torch.Tensor:
    """The first linear layer's weight ``(hidden, n_inputs)`` of ``phi`` (a parameter)."""
    return phi.body[0].weight


def input_penalty(phi: FeatureNetwork) -> torch.Tensor:
    """``sum_j ||W[:, j]||_2`` over the first layer's input columns (differentiable)."""
    return first_layer_weight(phi).norm(dim=0).sum()


def input_norms(phi: FeatureNetwork) -> list[float]:
    """The norm of every input's column of the first layer, in input order (observation entries,
    then action entries)."""
    with torch.no_grad():
        return [float(x) for x in first_layer_weight(phi).norm(dim=0)]


def input_shares(phi: FeatureNetwork) -> list[float]:
    """:func:`input_norms` divided by their sum (all 0 when every column is 0)."""
    norms = input_norms(phi)
    total = sum(norms)
    return [x / total if total > 0 else 0.0 for x in norms]


__all__ = ["first_layer_weight", "input_norms", "input_penalty", "input_shares"]
