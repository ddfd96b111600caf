"""Temporal learners: LTLf formulas that separate traces or specify the demonstrated task."""
