"""Groundings: what connects raw states and actions to symbols.

A learned rule or formula is meaningless without the grounding it was learned under, so each
grounding is a value of its own that prints, compares and saves as text/JSON:

* :class:`Labeling`, :class:`FeatureLabeling`, :class:`CallableLabeling`: state -> propositions;
  :class:`FunctionLabeling` and :func:`read_labeling`: a user's labeling of an environment's
  ``(observation, info)``, from a JSON file or ``FILE.py:function``;
* :class:`FactGrounding`: state / action -> ASP facts;
* :class:`FeatureMap`: state -> named numeric features;
* :class:`Domain`: background program + mode bias + fact grounding + nominal tabular model
  (+ optional truth rules and labeling): everything constraint learning needs, bundled or a
  user's folder alike.

This package sits beside :mod:`symlearn.logic` and below the learners: it imports neither torch,
gymnasium, :mod:`symlearn.envs` nor :mod:`symlearn.learners`.
"""

from symlearn.grounding.domain import Domain, as_domain
from symlearn.grounding.facts import FactGrounding, split_facts
from symlearn.grounding.feature_labeling import CallableLabeling, FeatureLabeling, parse_condition
from symlearn.grounding.features import FeatureMap
from symlearn.grounding.labeling import Labeling, load_labeling
from symlearn.grounding.labeling_function import FunctionLabeling, load_labeling_function, read_labeling

__all__ = ["CallableLabeling", "Domain", "FactGrounding", "FeatureLabeling", "FeatureMap", "FunctionLabeling",
           "Labeling", "as_domain", "load_labeling", "load_labeling_function", "parse_condition", "read_labeling",
           "split_facts"]
