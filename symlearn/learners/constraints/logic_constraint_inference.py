"""Logic constraint inference: maximum-likelihood constraint inference + ASP rule induction.

The loop of the reference thesis (chapter 3, Algorithm 3.1), on any
:class:`~symlearn.grounding.Domain` (a user's folder or a bundled one). Each iteration

1. **infers** the most likely constraint: the unobserved state-action pair the nominal MaxEnt
   policy visits most, plus the empty states it creates and the pairs leading into them
   (:class:`~symlearn.learners.constraints.ml_constraint_inference.MLConstraintInference` does this step);
2. **induces** an ASP hypothesis with our ILP learner: every demonstrated pair is a positive
   example, every constraint inferred so far a negative one, the domain's background knowledge
   and mode bias define the hypothesis space;
3. **translates** the hypothesis back: every pair it forbids (answer sets of B that are no
   answer sets of B u H) joins the constraint set, which is how a handful of inferred pairs
   generalises to the whole domain;
4. restricts the MDP, so the next inference step plans with what has been learned.

Why the induction step matters: inference alone only removes the pairs a rule-free planner
would use first; the rules remove every pair that shares their reason (all red-light crossings,
not just the one the planner tried).

The reward is inferred as sparse by default (1 for reaching a state where a demonstration
ended), so only demonstrations, background knowledge and bias are needed.

>>> from symlearn.envs.logic_mdp import logic_mdp
>>> lm = logic_mdp("hanoi")
>>> learner = LogicConstraintInference(iterations=3).fit(lm.expert_demonstrations(10, seed=0), lm.domain)
>>> learner.rules_
[':- on(V1,V2), V1 < V2.']
>>> learner.score()["accuracy"]
1.0
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DemonstrationError, SymlearnError
from symlearn.grounding import Domain, as_domain
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import FIT_CALLER, renamed_arguments
from symlearn.learners.constraints.constraint_metrics import constraint_metrics
from symlearn.learners.constraints.ml_constraint_inference import STOP_REASONS as ML_STOP_REASONS
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.progress import progress
from symlearn.rl.tabular import check_mask, restrict


@dataclass(frozen=True)
class LogicIteration:
    """One iteration: the inferred pair, the rules induced after it, sizes and times."""

    iteration: int
    inferred: str  # "state / action" of the pair chosen by maximum likelihood
    visitation: float
    rules: tuple[str, ...]
    optimal: bool
    n_positive: int
    n_negative: int
    n_constraints: int  # forbidden pairs after translating the rules back and closing the set
    inference_seconds: float
    induction_seconds: float
    gained: bool = True  # the rules forbid a pair they did not forbid before this iteration
    # pairs the iteration's rules forbid by themselves: what the final "constraints" count is, where
    # ``n_constraints`` also holds inferred pairs no rule covers (87 vs 75 on a drone domain)
    rule_pairs: int | None = None

    def as_dict(self) -> dict[str, Any]:
        return {"iteration": self.iteration, "inferred": self.inferred, "visitation": self.visitation,
                "rules": list(self.rules), "optimal": self.optimal, "positives": self.n_positive,
                "negatives": self.n_negative, "constraints": self.n_constraints,
                "inference_seconds": self.inference_seconds, "induction_seconds": self.induction_seconds,
                "gained": self.gained, "rule_pairs": self.rule_pairs}


@dataclass(frozen=True)
class Unexplained:
    """A pair maximum-likelihood inference would have forbidden, but no rule of the bias can
    forbid without forbidding a demonstrated pair: passed over, reported instead of inferred."""

    iteration: int
    state: int
    action: int
    pair: str  # "state / action"
    visitation: float

    def as_dict(self) -> dict[str, Any]:
        return {"iteration": self.iteration, "state": self.state, "action": self.action, "pair": self.pair,
                "visitation": self.visitation}


#: why the loop ended, in words (``stop_reason_`` -> text for the CLI and the rule file)
STOP_REASONS = {
    "converged": "converged: the rules forbade no new pair in the last {patience} iterations",
    "min_visitation": ML_STOP_REASONS["min_visitation"],
    "min_evidence": ML_STOP_REASONS["min_evidence"],
    # the body length is part of "the bias": a user reads the mode declarations and sees no limit
    "no_candidates": "no undemonstrated pair the bias can forbid (with rules of at most {max_body} body literals, "
                     "--max-body) is left",
    "max_iterations": "the iteration budget ({iterations}) ran out before convergence",
}


@dataclass(frozen=True)
class Induction:
    """What one induction step produced."""

    rules: tuple[str, ...]
    optimal: bool
    n_positive: int
    n_negative: int
    seconds: float
    gained: bool = True


class RuleInduction:
    """The induction step of one fit, as the ``generalize`` hook of maximum-likelihood inference.

    Called with the constraint set so far and the demonstrated pairs, it induces rules with the
    ILP learner (demonstrated pairs positive, constraints negative at ``penalty``) and returns
    every pair the rules forbid. It owns what the calls share: the hypothesis space (built once
    from the bias), the pairs each rule set forbids (consecutive iterations often induce the same
    rules), the best rules so far and one :class:`Induction` record per call.
    """

    def __init__(self, domain: Domain, *, noise: bool, penalty: int, timeout: float, bar: Any = None,
                 known: np.ndarray | None = None, max_body: int | None = None) -> None:
        self.domain, self.noise, self.penalty, self.timeout = domain, noise, penalty, timeout
        self.max_body = max_body
        # pairs the given rules forbid already: no learned rule is needed for them, so they are
        # no negatives (else induction learns the given rules again, as if from the data)
        self.known = np.zeros(domain.unavailable.shape, dtype=bool) if known is None else known
        self.bar = iter(bar) if bar is not None else None
        self.rule_masks: dict[tuple[str, ...], np.ndarray] = {}
        self.best: tuple[tuple[str, ...], Any] = ((), None)
        self.records: list[Induction] = []
        self.last_negatives: np.ndarray | None = None
        self.mask = np.zeros(domain.unavailable.shape, dtype=bool)  # what the latest rules forbid
        self.stale = 0  # inductions in a row whose rules forbade nothing new

    def converged(self, patience: int) -> str | None:
        """The stopping test of one fit: "converged" once rules exist and ``patience`` inductions
        in a row added no forbidden pair to them (each inferred pair since was one the rules
        reject: an allowed pair no demonstration happened to show)."""
        return "converged" if self.mask.any() and self.stale >= patience else None

    def __call__(self, forbidden: np.ndarray, seen: np.ndarray) -> np.ndarray:
        from symlearn.logic.ilp import learn

        d = self.domain
        t0 = time.perf_counter()
        if self.bar is not None:
            next(self.bar, None)
        available = ~d.unavailable
        # Demonstrated pairs are taken as valid unless the data is declared noisy: then a rule may
        # forbid one at a penalty too (an expert's slip should not block a rule every other
        # demonstration supports).
        positives = d.examples(map(tuple, np.argwhere(seen & available)), True,
                               self.penalty if self.noise else None)
        # Inferred constraints may be wrong (an allowed pair nobody happened to demonstrate), so
        # each negative may be left uncovered at a penalty.
        negatives = d.examples(map(tuple, np.argwhere(forbidden & available & ~self.known)), False, self.penalty)
        self.last_negatives = forbidden & available
        result = learn(d.ilp_task(positives + negatives), timeout=self.timeout, noise=True,
                       space=d.space(self.max_body))
        extra = np.zeros_like(forbidden)
        rules: tuple[str, ...] = ()
        optimal = False
        if result.hypothesis is not None:
            rules = tuple(result.hypothesis.rules)
            optimal = result.optimal
            self.best = (rules, result.hypothesis)
            if rules not in self.rule_masks:
                self.rule_masks[rules] = d.rule_mask(list(rules)) if rules else np.zeros_like(forbidden)
            extra = self.rule_masks[rules]
        gained = bool((extra & ~self.mask).any())
        self.mask = extra
        self.stale = 0 if gained else self.stale + 1
        self.records.append(Induction(rules, optimal, len(positives), len(negatives), time.perf_counter() - t0,
                                      gained))
        return extra

    def snapshot(self) -> tuple:
        """What a call changes (the rules so far, their mask, the stale count, the records), for
        :meth:`restore` when the inference loop undoes a step that lacked evidence."""
        return self.best, self.mask, self.stale, len(self.records), self.last_negatives

    def restore(self, snapshot: tuple) -> None:
        self.best, self.mask, self.stale, n_records, self.last_negatives = snapshot
        del self.records[n_records:]

    def final(self, closed: np.ndarray, seen: np.ndarray) -> tuple[np.ndarray, float]:
        """Algorithm 3.1 closes the constraint set (pairs into empty states) *before* each
        induction, so every closure is generalised. The inference loop closes after the hook, so
        the pairs its last closure added (typically: every move into a state the last rules left
        without a valid action, e.g. off the road) were never examples. Induce once more when
        they exist, and close the result again. Returns the closed set and the seconds spent."""
        d = self.domain
        negatives = closed & ~d.unavailable
        if self.last_negatives is None or np.array_equal(negatives, self.last_negatives):
            return closed, 0.0
        extra = self(closed, seen)
        seconds = self.records.pop().seconds
        return restrict(d.mdp, closed | (extra & ~seen), protected=seen).forbidden, seconds


class LogicConstraintInference(Learner):
    """``LogicConstraintInference(iterations=...).fit(demonstrations, world)``.

    ``world``: a :class:`~symlearn.grounding.Domain` (or a bundled wrapper with ``.domain``).

    **When it stops.** Algorithm 3.1 runs a fixed eta iterations and gives no convergence test, so
    ``iterations`` is a cap here and the loop stops earlier on a measured criterion
    (``stop_reason_``): ``"converged"`` once rules exist and ``patience`` iterations in a row
    induced rules that forbid no pair the previous rules allowed (the inferred pairs since were
    allowed pairs that no demonstration happened to show, which the ILP step leaves uncovered);
    ``"min_visitation"`` when no undemonstrated pair is likely any more; ``"min_evidence"`` when
    the likeliest one's absence is no evidence (below); ``"no_candidates"``
    when no undemonstrated pair the bias can forbid is left; ``"max_iterations"`` at the cap.

    **What the bias cannot express.** Before the loop every candidate rule of the bias is
    evaluated on every pair (:func:`~symlearn.learners.constraints.bias_reach.bias_reach`): a pair
    that no candidate forbids without forbidding a demonstrated pair can never be explained by a
    rule. Inference passes such pairs over instead of spending an iteration on each (``wait`` in
    one cell, then the next, ...) and reports them in ``unexplained_`` (:class:`Unexplained`:
    the pair and the visitation that would have chosen it) and in the rule file's header: either
    the bias lacks a literal (e.g. a negated condition), the rule needs more body literals than
    ``max_body`` (None: the ILP default, 3; a rule joining an object and a place through two
    variables, ``:- put, at(P), hot(P), holding(O), fragile(O).``, needs 5), or the demonstrations
    leave a real constraint undemonstrated that no rule distinguishes from what the expert did.

    Each iteration infers one constraint and runs one induction. The ILP step must cover
    every demonstrated pair but may leave an inferred constraint uncovered at ``penalty`` (a rule
    costs its length), since inference can pick an allowed pair that no demonstration happened to
    show. ``noise=True`` declares the demonstrations noisy: pairs that break ``known`` constraints
    are counted in a warning instead of an error, and the ILP step may then also leave a
    demonstrated pair uncovered at ``penalty``.

    ``known``: constraints given in advance, a forbidden ``(S, A)`` mask or rules (an ``.lp`` path,
    rule text or a list, as :meth:`~symlearn.grounding.Domain.rule_mask` takes). Their pairs are
    forbidden throughout but are no examples for induction, so ``rules_`` holds learned rules
    only, and rule support judges those against the given constraints; given rules are kept in
    ``known_rules_`` and listed apart in the rule file's header.

    ``rationality`` is the MaxEnt model's inverse temperature; ``"auto"`` (the default) fits it to
    the demonstrations by maximum likelihood before the loop (see
    :mod:`~symlearn.learners.constraints.rationality_fit`; ``rationality_`` is the value used) and,
    with ``refit_rationality`` (the default), again after every iteration under the constraints
    found so far: one likelihood, maximised over the constraints and the temperature in turn. It
    only matters with a reward other than the sparse one, where it cancels.

    **Evidence.** ``min_evidence`` (nats, default 1): an iteration is kept only if what it forbids
    -- the inferred pair, the pairs its induced rules add, the closure -- makes the demonstrated
    actions at least that many nats likelier under the nominal policies (checked only when the
    pair alone falls short: its expected visits in as many episodes as were demonstrated,
    ``visitation x len(demonstrations)``, which is about its own gain). 1 nat per added
    constraint is Akaike's price of a parameter. Below it the step's absence from the data is
    what the nominal policy itself would show about as often as not, so the step is undone and
    the loop stops (``"min_evidence"``; one Hanoi game is enough: its rule forbids 102 pairs) --
    unless the pair lies in a state no demonstration could reach under the constraints found so
    far (only the uniform start share visits it): there the data can say nothing either way, and
    the share's guess goes on as before (the junctions' off-road rule is one). Together with the
    refitted temperature this keeps a deliberate expert's unused moves (waiting, actions that
    change nothing) from being read as constraints; the price is that a rule the expert never
    had a reason to break (a blocked cell off every shortest path) is not learned -- the
    demonstrations do not show it. ``None`` turns the test off (and ``refit_rationality=False``
    with it gives the behaviour before 2026-12-08; docs/BENCHMARKS.md, "Evidence and the
    refitted temperature").

    ``start`` is where the nominal visitation starts (see :class:`MLConstraintInference`): the
    default 0.1 keeps 90 % of the mass on the demonstrations' starts (the thesis' objective) and
    spreads 10 % over every state, so rules about regions the first rules make unreachable from
    the demonstrated starts can still be induced; ``"demonstrations"`` is the thesis' objective
    exactly, ``"uniform"`` starts everywhere (measurements in ``docs/BENCHMARKS.md``).

    Results: ``hypothesis_`` (:class:`~symlearn.logic.asp.Hypothesis`, None if no rule was
    induced), ``rules_``, ``rule_constraints_`` (the pairs the rules forbid), ``constraints_``
    (forbidden ``(S, A)`` mask: the rules' pairs plus the inferred ones, closed), ``inferred_``
    (the pairs chosen by inference alone), ``history_`` (:class:`LogicIteration` list),
    ``seconds_``, ``final_induction_seconds_`` (the induction after the loop's last closure, 0 when
    that closure added nothing), ``stop_reason_`` (``stopped_because_`` is the same),
    ``unexplained_``, ``rule_support_`` (:class:`~symlearn.learners.constraints.rule_support.RuleSupport`
    per rule: how much likelier the demonstrations are with it, the planner's rationality refitted
    with and without it; where the planner has a rationality, a weakly supported rule -- one the
    demonstrations never needed, like ``:- wait.`` when every step costs -- is a
    :class:`~symlearn.learners.constraints.rule_support.WeakRuleWarning`, a note in the CLI, and a
    line of the rule file's header), ``result_``.
    """

    artefact_suffix = ".lp"

    def __init__(self, *, iterations: int = 10, horizon: int = 30, reward: str | np.ndarray = "sparse",
                 rationality: float | str = "auto", min_visitation: float = 1e-3, ilp_timeout: float = 30.0,
                 noise: bool = False, penalty: int = 10, known: np.ndarray | None = None,
                 start: str | float = 0.1, patience: int = 2, min_evidence: float | None = 1.0,
                 refit_rationality: bool = True, max_body: int | None = None) -> None:
        self.iterations = iterations
        self.max_body = max_body
        self.patience = patience
        self.horizon = horizon
        self.reward = reward
        self.rationality = rationality
        self.start = start
        self.min_visitation = min_visitation
        self.min_evidence = min_evidence
        self.refit_rationality = refit_rationality
        self.ilp_timeout = ilp_timeout
        self.noise = noise
        self.penalty = penalty
        self.known = known

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> LogicConstraintInference:
        if self.iterations < 1:
            raise SymlearnError(f"iterations must be at least 1, got {self.iterations}")
        if self.patience < 1:
            raise SymlearnError(f"patience must be at least 1, got {self.patience}")
        if self.max_body is not None and (isinstance(self.max_body, bool) or not isinstance(self.max_body, int)
                                          or self.max_body < 1):
            raise SymlearnError(f"max_body must be a whole number of at least 1, got {self.max_body!r}",
                                hint="leave it out for the default, 3 body literals")
        if world is None:
            raise SymlearnError("logic constraint inference needs the domain: fit(demonstrations, world=domain)")
        started = time.perf_counter()
        d = as_domain(world)
        episodes = d.episodes(demonstrations)
        check_available(episodes, d)
        from symlearn.learners.constraints.bias_reach import bias_reach
        from symlearn.mdp.episodes import demonstrated_pairs

        reach = bias_reach(d, demonstrated_pairs(episodes, d.mdp), noise=self.noise, max_body=self.max_body)
        known, self.known_rules_ = _known(self.known, d)
        bar = progress(range(self.iterations), total=self.iterations, desc=f"logic inference {d.name}")
        induction = RuleInduction(d, noise=self.noise, penalty=self.penalty, timeout=self.ilp_timeout, bar=bar,
                                  max_body=self.max_body,
                                  known=None if known is None else check_mask(d.mdp, known, "known constraints"))
        inference = MLConstraintInference(
            reward=self.reward, horizon=self.horizon, max_iterations=self.iterations,
            min_visitation=self.min_visitation, known_constraints=known,
            on_violation="warn" if self.noise else "error", generalize=induction,
            rationality=self.rationality, start=self.start, choosable=reach,
            stop_when=lambda: induction.converged(self.patience), min_evidence=self.min_evidence,
            refit_rationality=self.refit_rationality)
        try:
            inference.fit(episodes, d)
            closed, self.final_induction_seconds_ = induction.final(inference.constraints_, inference.demonstrated_)
        finally:
            close = getattr(bar, "close", None)
            if close:
                close()
        history = []
        n_known = int(inference.known_.sum())
        for step, record in zip(inference.history_, induction.records):
            history.append(LogicIteration(step.iteration, d.describe_pair(step.state, step.action), step.visitation,
                                          record.rules, record.optimal, record.n_positive, record.n_negative,
                                          step.n_forbidden - n_known, max(step.seconds - record.seconds, 0.0),
                                          record.seconds, record.gained,
                                          _rule_pairs(induction.rule_masks.get(record.rules))))
        rules, hypothesis = induction.best
        self.domain_name_ = d.name
        self.rules_ = list(rules)
        self.hypothesis_ = hypothesis
        self.constraints_ = closed & ~d.unavailable
        self.rule_constraints_ = induction.rule_masks.get(rules, np.zeros_like(self.constraints_))
        self.inferred_ = np.zeros_like(self.constraints_)
        for step in inference.history_:
            self.inferred_[step.state, step.action] = True
        self.demonstrated_ = inference.demonstrated_
        self.history_ = history
        self.stop_reason_ = self.stopped_because_ = inference.stop_reason_
        self.rationality_, self.rationality_fit_ = inference.rationality_, inference.rationality_fit_
        self.unexplained_ = [Unexplained(p.iteration, p.state, p.action, d.describe_pair(p.state, p.action),
                                         p.visitation) for p in inference.passed_over_]
        self.seconds_ = time.perf_counter() - started
        self.truth_forbidden_ = d.truth_forbidden
        self.pair_space_ = ~d.unavailable
        from symlearn.learners.constraints.rule_support import WeakRuleWarning, rule_support

        # how much the demonstrations need each rule, the planner's rationality refitted with and
        # without it (module rule_support): what a wandering nominal planner made look avoided
        self.rule_support_ = rule_support(d, episodes, self.rules_, self.reward, self.horizon, inference.known_,
                                          rationality=inference.rationality_)
        for support in self._weak_rules():
            warnings.warn(support.text(), WeakRuleWarning, stacklevel=FIT_CALLER)
        self.seconds_ = time.perf_counter() - started
        metrics: dict[str, Any] = {"rules": len(self.rules_), "constraints": int(self.rule_constraints_.sum()),
                                   "stopped_because": self.stop_reason_, "stop_reason": self.stop_reason_,
                                   "unexplained": len(self.unexplained_), "rationality": self.rationality_,
                                   "weak_rules": len(self._weak_rules())}
        if self.truth_forbidden_ is not None:
            metrics.update({k: v for k, v in self.score().items() if k != "forbidden"})
        inference_seconds = sum(h.inference_seconds for h in history)
        self._set_result(hypothesis, self._lp_text(),
                         metrics=metrics, history=history,
                         timings={"total": self.seconds_, "inference": inference_seconds,
                                  "induction": sum(h.induction_seconds for h in history),
                                  "final_induction": self.final_induction_seconds_})
        return self

    # --- using the result ----------------------------------------------------------------------
    def score(self, truth_forbidden: np.ndarray | None = None, *, of: str = "rules") -> dict[str, float]:
        """FPR, FNR and accuracy against the ground truth (the domain's truth rules unless
        ``truth_forbidden`` is given) of the pairs the learned rules forbid (``of="rules"``), or of
        the whole inferred constraint set (``of="constraints"``)."""
        if "rules_" not in self.__dict__:
            self.check_fitted()
        truth = self.truth_forbidden_ if truth_forbidden is None else truth_forbidden
        if truth is None:
            raise SymlearnError("this domain has no ground truth to score against",
                                hint="give truth rules in the domain (truth = ...) or pass truth_forbidden")
        if of not in ("rules", "constraints"):
            raise SymlearnError(f"unknown score target {of!r}", hint="use 'rules' or 'constraints'")
        learned = {"rules": self.rule_constraints_, "constraints": self.constraints_}[of]
        return constraint_metrics(learned, truth, self.pair_space_)

    def _weak_rules(self) -> list:
        """The weakly supported rules that are reported (warning, file header): only where the
        planner has a rationality (fitted or given) -- the case of a temperature that made absences look
        avoided. With the sparse reward (nothing to fit) a rule the demonstrations do not need is
        typically one of dead ends the goal-directed planner never enters (leaving the road), found
        by the closure and the bias' generalisation: its gain is still in ``rule_support_``."""
        fit = self.__dict__.get("rationality_fit_")
        if fit is None or fit.source == "flat":
            return []
        return [r for r in self.__dict__.get("rule_support_", []) if r.weak]

    def stop_text(self) -> str:
        """``stop_reason_`` in words."""
        if "stop_reason_" not in self.__dict__:
            self.check_fitted()
        from symlearn.logic.ilp.task import DEFAULT_MAX_BODY

        max_body = DEFAULT_MAX_BODY if self.max_body is None else self.max_body
        return STOP_REASONS.get(self.stop_reason_, self.stop_reason_).format(patience=self.patience,
                                                                              iterations=self.iterations,
                                                                              max_body=max_body)

    def needed_none(self) -> bool:
        """No rule was induced because the demonstrations needed none: the loop stopped on the
        evidence (no undemonstrated pair likely enough) before any rule. A result, written as a
        rule file of comments; other ways to end without rules (a bias that cannot forbid) are not."""
        return self.hypothesis_ is None and self.stop_reason_ in ("min_evidence", "min_visitation")

    def _no_rules_text(self, recheck: str | None) -> str:
        lines = [f"No rules learned by logic constraint inference on {self.domain_name_} "
                 f"({len(self.history_)} of at most {self.iterations} iterations, {self.seconds_:.1f} s).",
                 f"Stopped: {self.stop_text()}.",
                 f"At the rationality {self.rationality_:g} a planner as deliberate as the expert does what the "
                 "demonstrations show without any constraint, so they give no evidence for one.",
                 "Write rules you know below (or give them with --known), or record demonstrations in which",
                 "breaking them would have paid.",
                 f"re-check with: {recheck or 'symlearn domain check DOMAIN_DIR --rules THIS.lp [--demos DEMOS.jsonl]'}"]
        return "".join(f"% {line}\n" for line in lines)

    def _lp_text(self, recheck: str | None = None) -> str:
        if self.hypothesis_ is None:
            return self._no_rules_text(recheck) if self.needed_none() else ""
        header = (f"Rules learned by logic constraint inference on {self.domain_name_} "
                  f"({len(self.history_)} of at most {self.iterations} iterations, {self.seconds_:.1f} s).\n"
                  f"Stopped: {self.stop_text()}.")
        fit = self.__dict__.get("rationality_fit_")
        if fit is not None and fit.source == "fitted":
            under = " under the learned constraints" if self.refit_rationality else ""
            header += (f"\nMaxEnt rationality {self.rationality_:g}, fitted to the demonstrations{under} (maximum "
                       "likelihood; --rationality sets it).")
        given = self.__dict__.get("known_rules_") or []
        if given:
            header += "\nGiven in advance (known, not learned; not among the rules below):"
            header += "".join(f"\n  {rule}" for rule in given)
        weak = self._weak_rules()
        if weak:
            header += "\nWeakly supported (the demonstrations are about as likely without the rule, the planner's " \
                      "rationality refitted; see symlearn.learners.constraints.rule_support):"
            header += "".join(f"\n  {r.rule}  ({r.gain:.2f} nats"
                              + ("" if not r.overlaps else f"; {' and '.join(r.overlaps)} "
                                 f"{'forbids' if len(r.overlaps) == 1 else 'forbid'} "
                                 f"{'its pairs' if r.overlaps_cover else 'some of its pairs'} too: keep "
                                 f"{'that' if len(r.overlaps) == 1 else 'those'}")
                              + ")" for r in weak)
        if self.unexplained_:
            header += "\n" + "\n".join(unexplained_lines(self.unexplained_, max_body=self.max_body))
        return self.hypothesis_.lp_text(header, recheck=recheck or "symlearn domain check DOMAIN_DIR --rules THIS.lp "
                                                                   "[--demos DEMOS.jsonl] (or Domain.rule_mask in "
                                                                   "Python)")

    def to_lp(self, path: Any, *, recheck: str | None = None) -> Any:
        """Write the rules as an editable ``.lp`` file with a provenance header (see :meth:`save`);
        ``recheck``: the command the header's last line recommends after an edit (the CLI names
        the domain folder, this file and the demonstrations), instead of the placeholder one."""
        self.check_fitted()
        if self.hypothesis_ is None and not self.needed_none():
            raise SymlearnError("no rules were induced, so there is nothing to write",
                                hint="give more demonstrations or more iterations")
        if recheck is None:
            return self.save(path)
        from symlearn.atomic import write_text

        return write_text(path, self._lp_text(recheck))


def _known(known: Any, d: Domain) -> tuple[np.ndarray | None, list[str]]:
    """The ``known`` argument as a forbidden mask, and its rules when it was given as rules."""
    rules = isinstance(known, (str, os.PathLike)) or (
        isinstance(known, (list, tuple)) and bool(known) and all(isinstance(r, str) for r in known))
    if not rules:
        return known, []
    return d.rule_mask(known), list(d.hypothesis(known).rules)


def unexplained_lines(unexplained: list[Unexplained], shown: int = 20, max_body: int | None = None) -> list[str]:
    """The header/console lines for the constraints the bias cannot express (most visited first).

    The body length is named because nothing else tells a user that a rule of 4 or more literals
    (a join of two variables) is outside the space: the bias file looks as if it allowed it."""
    if not unexplained:
        return []
    from symlearn.logic.ilp.task import DEFAULT_MAX_BODY

    body = DEFAULT_MAX_BODY if max_body is None else max_body
    lines = [f"Unexplained: {len(unexplained)} pair(s) inference found likely forbidden (never demonstrated, often "
             "visited by the nominal policy) that no rule of the bias can forbid without forbidding a demonstrated "
             "pair -- allowed moves the expert never chose, constraints the bias has no literal for, or rules "
             f"longer than {body} body literals (--max-body) "
             "(state / action, nominal visitation when passed over):"]
    ranked = sorted(unexplained, key=lambda u: -u.visitation)
    lines += [f"  {u.pair}  ({u.visitation:.3g})" for u in ranked[:shown]]
    if len(ranked) > shown:
        lines.append(f"  ... and {len(ranked) - shown} more")
    return lines


def check_available(episodes, d: Domain) -> None:
    """A demonstrated move that does not exist is a wrong file, not noise: say where it is."""
    for i, e in enumerate(episodes):
        n = len(e.actions)
        bad = np.flatnonzero(d.unavailable[e.states[:n], e.actions])
        if bad.size:
            t = int(bad[0])
            s, a = int(e.states[t]), int(e.actions[t])
            where = "after the episode ended" if d.mdp.terminal[s] else "there"
            raise DemonstrationError(f"demonstration {i}, step {t}: action {d.action_names[a]!r} is not available "
                                     f"in state {d.state_names[s]!r} ({where})", demonstration=i, key="actions",
                                     step=t, hint=f"the state is terminal in {d.name}'s model: end the demonstration "
                                                  "there (its last state, with no action after it)" if d.mdp.terminal[s]
                                     else f"{d.name}: were the demonstrations recorded in another environment?")


__all__ = ["STOP_REASONS", "Induction", "check_available", "LogicConstraintInference", "LogicIteration", "RuleInduction", "Unexplained",
           "unexplained_lines"]


def _rule_pairs(mask: np.ndarray | None) -> int | None:
    """How many (state, action) pairs an iteration's rules forbid, counted as the final result is."""
    return None if mask is None else int(mask.sum())
