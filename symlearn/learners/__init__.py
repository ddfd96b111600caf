"""Learners: one module per method, each ``fit(demonstrations, ...) -> self`` with results in
attributes ending in ``_`` (see docs/ARCHITECTURE.md)."""
