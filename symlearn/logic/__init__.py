"""The symbolic core: ASP and ILP, LTLf, propositional guards, automata, groundings.

Imports nothing heavy (no torch, no gymnasium, no learner); import the subpackages you need.
"""
