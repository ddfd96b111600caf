"""How much the demonstrations need each learned rule: its profile-likelihood gain.

Maximum-likelihood constraint inference forbids what a nominal MaxEnt planner would do and the
demonstrations never show. How random that planner is (its rationality) decides how much an
absence counts: the rationality is fitted to the demonstrations *before* any rule is known, and
the expert's detours around forbidden pairs then look like randomness, so the fit is low, the
planner wanders, and pairs the expert merely never needed (waiting, where every step costs) look
as avoided as the pairs it had to avoid. The guide's floor showed it (the rug rule and ``:- wait.``)
until the learner refitted the rationality after every iteration and asked each inferred pair for
evidence (``LogicConstraintInference(refit_rationality=, min_evidence=)``, 2026-12-08); with a
given low ``--rationality`` it still does.

This module asks of each rule, once the learning is done, whether the demonstrations need it:
the log-likelihood of the demonstrated actions with every learned rule, minus the same without
this one, *each at its own maximum-likelihood rationality* (a profile likelihood; fitted as in
:mod:`~symlearn.learners.constraints.rationality_fit`). A rule the expert had to obey is needed
at any temperature: without the rug rule, a deliberate planner drives over the rug and the
expert's detour is improbable (on the guide's floor: 108 nats with a full search, the rationality
fitted at 24 with it and 1.3 without; 119 with the learner's three-value shortcut below). A rule
about what the expert never needed costs nothing to drop once the planner is allowed to be as
deliberate as the expert (``:- wait.``: 0.00 nats at rationality 24 either way).

Rules that forbid the same pairs (two spellings of one rule, or a rule and a more general one)
each cost nothing to drop while the other stays, so each alone looks unneeded; deleting both
would lose what they forbid together. The weak rules are therefore checked together, weakest
first (and among equal gains, the one forbidding more pairs first: its surplus is what the
demonstrations never asked for): a rule joins the set reported weak only while dropping the whole set still costs less
than :data:`WEAK_SUPPORT`; one that would push it over is needed after all (``joint_gain``, the
drop measured with the weaker rules already gone), and the weak rules whose pairs it shares name
it (``overlaps``): delete those, keep it.

A gain below :data:`WEAK_SUPPORT` nats (the demonstrations are less than ``e^3 ~ 20`` times
likelier with the rule) is reported as weak: a :class:`WeakRuleWarning` (a ``note:`` line of the
CLI, JSON ``notes``) and a line of the rule file's header. Weak is
not wrong -- a rule can hold and still never have mattered to these demonstrations (an expert
that never had a reason to break it); what the data cannot tell, the user has to. The rules are
not changed. With the sparse reward there is no temperature to fit (it cancels), and the gain is
the plain likelihood ratio.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

#: nats below which a rule's support is reported as weak (a likelihood ratio of about 20)
WEAK_SUPPORT = 3.0


class WeakRuleWarning(UserWarning):
    """A learned rule the demonstrations do not need (issued by the logic learner's fit): a remark
    about the evidence, not about a mistake -- the CLI prints it as a note, not a warning."""


@dataclass(frozen=True)
class RuleSupport:
    """One rule's profile-likelihood gain (see the module docstring)."""

    rule: str
    gain: float  # nats, over all demonstrated steps
    rationality_with: float  # fitted with every learned rule
    rationality_without: float  # fitted with the others only
    # the drop when this rule goes *with* the weaker rules reported before it (module docstring);
    # None where the rule's own gain already made it strong
    joint_gain: float | None = None
    overlaps: tuple[str, ...] = ()  # stronger rules forbidding some of the same pairs (delete this, keep them)
    overlaps_cover: bool = True  # whether they forbid every pair this rule forbids, or only some

    @property
    def weak(self) -> bool:
        return (self.gain if self.joint_gain is None else self.joint_gain) < WEAK_SUPPORT

    def as_dict(self) -> dict[str, Any]:
        return {"rule": self.rule, "gain": self.gain, "rationality_with": self.rationality_with,
                "rationality_without": self.rationality_without, "joint_gain": self.joint_gain,
                "overlaps": list(self.overlaps), "overlaps_cover": bool(self.overlaps) and self.overlaps_cover,
                "weak": self.weak}

    def text(self) -> str:
        """The warning for a weak rule (one line)."""
        temperature = (f" (planner rationality {self.rationality_with:g} with it, {self.rationality_without:g} "
                       "without)" if self.rationality_with != self.rationality_without else
                       f" (planner rationality {self.rationality_with:g})")
        one = len(self.overlaps) == 1
        shared = ("" if not self.overlaps else
                  f" ({' and '.join(self.overlaps)} also forbid{'s' if one else ''} "
                  f"{'its pairs' if self.overlaps_cover else 'some of its pairs'} and "
                  f"{'is' if one else 'are'} needed: keep {'that one' if one else 'those'})")
        return (f"rule {self.rule} is weakly supported: the demonstrations are {self.gain:.2f} nats likelier with "
                f"it than without{temperature}, below {WEAK_SUPPORT:g}{shared}: they do not show that it matters -- "
                "keep it if you know it holds, delete it otherwise")


def rule_support(domain: Any, episodes, rules: list[str], reward: Any, horizon: int,
                 known: np.ndarray | None = None, rationality: float | None = None) -> list[RuleSupport]:
    """:class:`RuleSupport` of each of ``rules`` (ASP integrity constraints) in ``domain`` (a
    :class:`~symlearn.grounding.Domain`) on ``episodes`` (its tabular episodes); ``reward`` and
    ``horizon`` as the learner planned with; ``known``: pairs forbidden in advance.

    ``rationality``: the value the learner planned with (fitted before any rule was known). Then
    the likelihood without a rule is not searched afresh (a dozen backward passes per rule) but
    taken at the best of three values -- the one fitted with every rule, ``rationality`` and their
    geometric mean: that is at most the profile's maximum, so the gain is if anything overstated,
    and a rule reported weak is weak. None: a full search per rule."""
    from symlearn.learners.constraints.ml_constraint_inference import MaxEntVisitation
    from symlearn.learners.constraints.rationality_fit import demonstration_log_likelihood, fit_rationality

    if not rules:
        return []
    mdp = domain.mdp
    planner = MaxEntVisitation(mdp, [], reward, horizon, 1.0)
    sparse = isinstance(reward, str) and reward == "sparse"
    base = domain.unavailable.copy()
    if known is not None:
        base |= known
    masks = [domain.rule_mask([rule]) for rule in rules]  # integrity constraints forbid independently
    steps = sum(len(e.actions) for e in episodes)

    def allowed_without(leave_out: int | frozenset[int] | None) -> np.ndarray:
        gone = {leave_out} if isinstance(leave_out, int) else (leave_out or set())
        forbidden = base.copy()
        for i, mask in enumerate(masks):
            if i not in gone:
                forbidden |= mask
        return ~forbidden

    def at(beta: float, allowed: np.ndarray) -> float:
        return demonstration_log_likelihood(mdp, episodes, planner._reward, beta, horizon, allowed) * steps

    def profile(leave_out: int | None) -> tuple[float, float]:
        allowed = allowed_without(leave_out)
        fit = fit_rationality(mdp, episodes, planner._reward, horizon, allowed, sparse=sparse)
        if fit.mean_log_likelihood is None:  # flat: nothing was fitted, the likelihood at the value used
            return fit.value, at(fit.value, allowed)
        return fit.value, fit.mean_log_likelihood * steps

    with_all, total = profile(None)
    if sparse or rationality is None:  # nothing to fit, or no hint: a full search per rule
        profile_without = profile
    else:
        candidates = sorted({round(v, 4) for v in (with_all, rationality, (with_all * rationality) ** 0.5)})

        def profile_without(leave_out: int | frozenset[int]) -> tuple[float, float]:
            allowed = allowed_without(leave_out)
            values = {beta: at(beta, allowed) for beta in candidates}
            best = max(values, key=values.get)
            return best, values[best]

    out = []
    for i, rule in enumerate(rules):
        without, partial = profile_without(i)
        out.append(RuleSupport(rule, round(max(total - partial, 0.0), 4), with_all, without))
    return _checked_together(out, masks, lambda gone: total - profile_without(frozenset(gone))[1])


def _checked_together(support: list[RuleSupport], masks: list[np.ndarray], drop: Any) -> list[RuleSupport]:
    """The weak rules checked as a set, weakest first (module docstring); ``drop(indices)`` is the
    log-likelihood lost when all of ``indices`` go at once."""
    # weakest first; among equal gains the rule forbidding more pairs goes first: what it forbids
    # beyond the other is what the demonstrations did not ask for (kitchen: `:- holding, onStove.`
    # before the true `:- move(V1), stoveAhead(V1), holding.`, both 0.00 nats alone)
    weak = sorted((i for i, s in enumerate(support) if s.weak),
                  key=lambda i: (round(support[i].gain, 2), -int(masks[i].sum()), i))
    if len(weak) < 2:
        return support
    out, gone = list(support), []
    for i in weak:
        lost = round(max(drop([*gone, i]), 0.0), 4)
        if lost < WEAK_SUPPORT:
            gone.append(i)
        else:   # needed once the weaker rules are gone: strong, and they name it
            out[i] = replace(support[i], joint_gain=lost)
    for i in gone:
        sharing = [j for j in weak if j not in gone and (masks[i] & masks[j]).any()]
        if sharing:
            kept = np.logical_or.reduce([masks[j] for j in sharing])
            out[i] = replace(support[i], overlaps=tuple(out[j].rule for j in sharing),
                             overlaps_cover=not (masks[i] & ~kept).any())
    return out


__all__ = ["RuleSupport", "WEAK_SUPPORT", "WeakRuleWarning", "rule_support"]
