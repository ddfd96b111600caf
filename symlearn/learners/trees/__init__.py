"""Tree learners: one-class decision trees over named features and the DNF constraints they define."""

from symlearn.learners.trees.one_class_tree import (
    Box,
    OneClassTree,
    OneClassTreeConstraint,
    SplitRecord,
    TreeNode,
    binned_kde,
)

__all__ = ["Box", "OneClassTree", "OneClassTreeConstraint", "SplitRecord", "TreeNode", "binned_kde"]
