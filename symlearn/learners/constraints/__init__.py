"""Constraint learners: what an expert never does, as constraint sets, ASP rules or cost maps."""
