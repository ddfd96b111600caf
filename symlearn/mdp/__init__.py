"""Models of environments for exact algorithms."""

from symlearn.mdp.tabular import TabularMDP

__all__ = ["TabularMDP"]
