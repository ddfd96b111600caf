"""Logic constraint inference: maximum-likelihood constraint inference + ASP rule induction.

The loop of the reference thesis (chapter 3, Algorithm 3.1), on a bundled logic domain
(:func:`symlearn.envs.logic_mdp.logic_mdp`). Each iteration

1. **infers** the most likely constraint: the unobserved state-action pair the nominal MaxEnt
   policy visits most, plus the empty states it creates and the pairs leading into them
   (:class:`~symlearn.learners.ml_constraint_inference.MLConstraintInference` does this step);
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
>>> learner = LogicConstraintInference(lm, iterations=3).fit(lm.expert_demonstrations(10, seed=0))
>>> learner.rules_
[':- on(V1,V2), V1 < V2.']
>>> learner.score(lm.truth_forbidden)["accuracy"]
1.0
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.envs.ilp_tasks import Example, number_examples, task_text
from symlearn.envs.logic_mdp import LogicMDP, logic_mdp
from symlearn.errors import DataError, SymlearnError
from symlearn.learners.constraint_metrics import constraint_metrics
from symlearn.learners.ml_constraint_inference import MLConstraintInference
from symlearn.learners.tabular_demos import tabular_episodes
from symlearn.rl.tabular import check_mask, restrict
from symlearn.progress import progress


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

    def as_dict(self) -> dict[str, Any]:
        return {"iteration": self.iteration, "inferred": self.inferred, "visitation": self.visitation,
                "rules": list(self.rules), "optimal": self.optimal, "positives": self.n_positive,
                "negatives": self.n_negative, "constraints": self.n_constraints,
                "inference_seconds": self.inference_seconds, "induction_seconds": self.induction_seconds}


class LogicConstraintInference:
    """Scikit-learn style: ``LogicConstraintInference(domain, iterations=...).fit(demos)``.

    ``domain``: a :class:`LogicMDP` or a bundled domain name. ``iterations`` is the thesis'
    eta (one inferred constraint and one induction per iteration; the loop ends earlier when no
    unobserved pair is likely any more). The ILP step must cover every demonstrated pair but
    may leave an inferred constraint uncovered at ``penalty`` (a rule costs its length), since
    inference can pick an allowed pair that no demonstration happened to show.
    ``noise=True`` declares the demonstrations noisy: pairs that break ``known`` constraints are
    counted in a warning instead of an error, and the ILP step may then also leave a
    demonstrated pair uncovered at ``penalty`` (a slip of one expert need not block a rule the
    rest support; the rule still has to be cheaper than the penalties it incurs).

    ``start`` is where the nominal visitation starts (see :class:`MLConstraintInference`). The
    default 0.1 keeps 90 % of the mass on the demonstrations' starts (the maximum-likelihood
    objective of the thesis) and spreads 10 % over every state. Why: rules should hold in the
    whole domain, but once the first rules make a region unreachable from where demonstrations
    start (the off-road cells of a junction, once turning off the road is forbidden), the pure
    objective never proposes a pair there, so a rule about it ("stay on the road") is never
    induced; measured in ``benchmarks/logic_constraints.py``. ``"demonstrations"`` is the
    thesis' objective exactly; ``"uniform"`` starts everywhere, which also proposes pairs in
    states no expert would be in (Hanoi configurations with a disk on a smaller one), where a
    move that repairs the configuration is allowed and wastes iterations.

    Results: ``hypothesis_`` (:class:`~symlearn.logic.asp.Hypothesis`, None if no rule was
    induced), ``rules_``, ``rule_constraints_`` (the pairs the rules forbid), ``constraints_``
    (forbidden ``(S, A)`` mask: the rules' pairs plus the inferred ones, closed), ``inferred_`` (the pairs chosen by inference alone), ``history_``
    (:class:`LogicIteration` list), ``seconds_``, ``final_induction_seconds_`` (the induction after
    the loop's last closure, 0 when that closure added nothing; see :meth:`_final_induction`).
    """

    def __init__(self, domain: LogicMDP | str, *, iterations: int = 10, horizon: int = 30,
                 reward: str | np.ndarray = "sparse", rationality: float = 1.0,
                 min_visitation: float = 1e-3, ilp_timeout: float = 30.0, noise: bool = False,
                 penalty: int = 10, known: np.ndarray | None = None, start: str | float = 0.1) -> None:
        self.domain = logic_mdp(domain) if isinstance(domain, str) else domain
        self.iterations = iterations
        self.horizon = horizon
        self.reward = reward
        self.rationality = rationality
        self.start = start
        self.min_visitation = min_visitation
        self.ilp_timeout = ilp_timeout
        self.noise = noise
        self.penalty = penalty
        self.known = known

    def fit(self, demos: Any) -> LogicConstraintInference:
        if self.iterations < 1:
            raise SymlearnError(f"iterations must be at least 1, got {self.iterations}")
        started = time.perf_counter()
        lm = self.domain
        episodes = tabular_episodes(demos, lm.mdp)
        _check_available(episodes, lm)
        known = lm.unavailable & ~lm.mdp.terminal[:, None]
        if self.known is not None:
            known = known | check_mask(lm.mdp, self.known, "known constraints")
        # Pairs each induced rule set forbids: consecutive iterations often induce the same rules,
        # and translating them back is a full answer-set enumeration.
        self._rule_masks: dict[tuple[str, ...], np.ndarray] = {}
        self._best: tuple[tuple[str, ...], Any] = ((), None)
        inference = MLConstraintInference(
            lm.mdp, reward=self.reward, horizon=self.horizon, max_iterations=self.iterations,
            min_visitation=self.min_visitation, known_constraints=known,
            on_violation="warn" if self.noise else "error", generalize=self._generalize,
            rationality=self.rationality, start=self.start)
        self._bar = progress(range(self.iterations), total=self.iterations, desc=f"logic inference {lm.name}")
        self._bar_iter = iter(self._bar)
        self._records: list[tuple[tuple[str, ...], bool, int, int, float]] = []
        self._last_negatives: np.ndarray | None = None
        try:
            inference.fit(episodes)
            closed = self._final_induction(inference.constraints_, inference.demonstrated_)
        finally:
            close = getattr(self._bar, "close", None)
            if close:
                close()
        history = []
        known = int(inference.known_constraints.sum())
        for step, (rules, optimal, n_pos, n_neg, induction) in zip(inference.history_, self._records):
            state_name, action_name = lm.mdp.state_names[step.state], lm.mdp.action_names[step.action]
            history.append(LogicIteration(step.iteration, f"{state_name} / {action_name}", step.visitation,
                                          rules, optimal, n_pos, n_neg, step.n_forbidden - known,
                                          max(step.seconds - induction, 0.0), induction))
        rules, hypothesis = self._best
        self.rules_ = list(rules)
        self.hypothesis_ = hypothesis
        self.constraints_ = closed & ~lm.unavailable
        self.rule_constraints_ = self._rule_masks.get(rules, np.zeros_like(self.constraints_))
        self.inferred_ = np.zeros_like(self.constraints_)
        for step in inference.history_:
            self.inferred_[step.state, step.action] = True
        self.demonstrated_ = inference.demonstrated_
        self.history_ = history
        self.stopped_because_ = inference.stopped_because_
        self.seconds_ = time.perf_counter() - started
        return self

    def _final_induction(self, closed: np.ndarray, seen: np.ndarray) -> np.ndarray:
        """Algorithm 3.1 closes the constraint set (pairs into empty states) *before* each
        induction, so every closure is generalised. The inference loop closes after the hook, so
        the pairs its last closure added (typically: every move into a state the last rules left
        without a valid action, e.g. off the road) were never examples. Induce once more when
        they exist, and close the result again."""
        lm = self.domain
        self.final_induction_seconds_ = 0.0
        negatives = closed & ~lm.unavailable
        if self._last_negatives is None or np.array_equal(negatives, self._last_negatives):
            return closed
        extra = self._generalize(closed, seen)
        self.final_induction_seconds_ = self._records.pop()[-1]
        return restrict(lm.mdp, closed | (extra & ~seen), protected=seen).forbidden

    # --- the induction step, called by the inference loop ---------------------------------------
    def _generalize(self, forbidden: np.ndarray, seen: np.ndarray) -> np.ndarray:
        lm = self.domain
        t0 = time.perf_counter()
        next(self._bar_iter, None)
        # Demonstrated pairs are taken as valid unless the data is declared noisy: then a rule may
        # forbid one at a penalty too (an expert's slip should not block a rule every other
        # demonstration supports).
        positives = number_examples(((lm.facts(s, a), True) for s, a in np.argwhere(seen & ~lm.unavailable)),
                                    self.penalty if self.noise else None)
        # Inferred constraints may be wrong (an allowed pair nobody happened to demonstrate), so
        # each negative may be left uncovered at a penalty.
        negatives = number_examples(((lm.facts(s, a), False) for s, a in np.argwhere(forbidden & ~lm.unavailable)),
                                    self.penalty)
        self._last_negatives = forbidden & ~lm.unavailable
        examples = positives + negatives
        result = _induce(lm, examples, self.ilp_timeout)
        extra = np.zeros_like(forbidden)
        rules: tuple[str, ...] = ()
        optimal = False
        if result.hypothesis is not None:
            rules = tuple(result.hypothesis.rules)
            optimal = result.optimal
            self._best = (rules, result.hypothesis)
            if rules not in self._rule_masks:
                self._rule_masks[rules] = lm.rule_mask(list(rules)) if rules else np.zeros_like(forbidden)
            extra = self._rule_masks[rules]
        self._records.append((rules, optimal, len(positives), len(negatives), time.perf_counter() - t0))
        return extra

    # --- using the result ----------------------------------------------------------------------
    def score(self, truth_forbidden: np.ndarray | None = None, *, of: str = "rules") -> dict[str, float]:
        """FPR, FNR and accuracy against the ground truth of the pairs the learned rules forbid
        (``of="rules"``), or of the whole inferred constraint set (``of="constraints"``)."""
        lm = self.domain
        truth = lm.truth_forbidden if truth_forbidden is None else truth_forbidden
        learned = {"rules": self.rule_constraints_, "constraints": self.constraints_}[of]
        return constraint_metrics(learned, truth, ~lm.unavailable)

    def to_lp(self, path: Any) -> Any:
        """Write the rules as an editable ``.lp`` file with a provenance header."""
        if self.hypothesis_ is None:
            raise SymlearnError("no rules were induced, so there is nothing to write",
                                hint="give more demonstrations or more iterations")
        header = (f"Rules learned by logic constraint inference on {self.domain.name} "
                  f"({len(self.history_)} iterations, {self.seconds_:.1f} s). Edit freely; "
                  "re-check them with `symlearn ilp check`.")
        return self.hypothesis_.to_lp(path, header=header)


def _check_available(episodes, lm: LogicMDP) -> None:
    """A demonstrated move that does not exist is a wrong file, not noise: say where it is."""
    for i, e in enumerate(episodes):
        n = len(e.actions)
        bad = np.flatnonzero(lm.unavailable[e.states[:n], e.actions])
        if bad.size:
            t = int(bad[0])
            s, a = int(e.states[t]), int(e.actions[t])
            where = "after the episode ended" if lm.mdp.terminal[s] else "there"
            raise DataError(f"demonstration {i}, step {t}: action {lm.mdp.action_names[a]!r} is not available in "
                            f"state {lm.mdp.state_names[s]!r} ({where})",
                            hint=f"{lm.name}: were the demonstrations recorded in another environment?")


def _induce(lm: LogicMDP, examples: list[Example], timeout: float):
    from symlearn.logic.ilp import learn, parse_task

    text = task_text(lm.domain, examples, f"{lm.domain.description}: logic constraint inference")
    task = parse_task(text, source=f"<{lm.name} induction task>")
    return learn(task, timeout=timeout, noise=True)


__all__ = ["LogicConstraintInference", "LogicIteration"]
