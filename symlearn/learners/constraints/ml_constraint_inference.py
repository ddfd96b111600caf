"""Maximum-likelihood constraint inference in a tabular MDP (in the style of Scobee & Sastry).

Under the maximum-entropy model a demonstration's probability is proportional to
``exp(reward)`` among all trajectories still valid in the constrained MDP, so the constraint
that raises the likelihood of the demonstrations most is the one removing the most probability
mass: the *unobserved* state-action pair that the nominal (constraint-free so far) MaxEnt
policy visits most often. Each iteration

1. computes, for every goal ``g`` (a state where a demonstration ended), the goal-conditioned
   MaxEnt policy ``Z_sa / Z_s`` with a planning horizon, and its expected state-action
   visitation from the demonstrations' start states (weighted by how many demonstrations
   pursue ``g``);
2. adds the unobserved, still allowed pair with the highest visitation;
3. closes the set: a state left with no valid action becomes *empty* and every pair that can
   enter it (positive probability) is forbidden too (:func:`symlearn.rl.tabular.restrict`);
   demonstrated pairs are never forbidden;
4. optionally lets ``generalize`` extend the set (the hook where logic constraint inference
   plugs in an ILP step: induce rules from demonstrated and forbidden pairs, translate them
   back to every pair they forbid);
5. restricts the MDP.

**Stopping criterion**: the loop ends when the best candidate's expected visitation drops below
``min_visitation`` (adding it would barely change the likelihood), when ``min_evidence`` (nats,
off by default) is given and a step lacks evidence: the candidate lies in a state the
demonstrations could reach, the nominal policy would have visited it fewer than ``min_evidence``
times in as many episodes as were demonstrated, and forbidding what the step forbids (the
candidate, what ``generalize`` adds, the closure) makes the demonstrated actions fewer than
``min_evidence`` nats likelier under the nominal policies -- such a step is undone (a
``generalize`` hook with ``snapshot()``/``restore()`` is rolled back with it) and the loop ends
(``"min_evidence"``) --, when no unobserved allowed pair is left, when ``stop_when`` (a hook, e.g. logic inference's convergence test) names a reason,
or after ``max_iterations`` (a cap). ``stop_reason_`` says which.

``choosable`` (an ``(S, A)`` mask) limits which pairs may be inferred: a pair outside it at least
as visited as the pair chosen is passed over and recorded once in ``passed_over_``
(iteration, state, action, visitation) --
logic inference uses it for the pairs its rule language cannot express.

``refit_rationality`` (off by default) refits a fitted rationality (``"auto"``) after every
iteration, under the constraints found so far: coordinate ascent on the one likelihood.

The reward is the MDP's own (``reward="given"``), an explicit ``(S, A)``/``(S, A, S)`` array,
or ``"sparse"``: 1 for entering a state where a demonstration ended, 0 otherwise.
``rationality`` multiplies it (the inverse temperature of the MaxEnt model): with many actions
and a small step cost, long wandering paths can outweigh short ones unless it is raised.
``"auto"`` (the default) fits it to the demonstrations by maximum likelihood before the loop
(:mod:`symlearn.learners.constraints.rationality_fit`); ``rationality_`` is the value used and
``rationality_fit_`` how it was found. With the sparse reward it cancels and 1 is used.

``start`` says where the nominal visitation starts: from the demonstrations' start states
(``"demonstrations"``, the maximum-likelihood objective, default), uniformly from every
non-terminal state (``"uniform"``), or a mixture: a number ``w`` in [0, 1] puts that share of
the start mass uniformly on every non-terminal state and the rest on the demonstrations' starts.
A uniform share also weighs pairs in regions no demonstration starts near -- a state the
learned constraints make unreachable from the demonstrated starts (off-road cells once turning
off the road is forbidden) still gets candidates, so rules about such regions can be learned;
a small share keeps the demonstrated flow first, so the likeliest constraints come first.

>>> from symlearn.envs.gridworld import StochasticGridworld
>>> from symlearn.data import record
>>> env = StochasticGridworld(0.0); policy = env.expert_policy()
>>> demos = record(env, lambda s: int(policy[s]), 3, seed=0, max_steps=200)
>>> learner = MLConstraintInference(horizon=30).fit(demos, env.to_tabular())
>>> int(learner.constraints_.sum()) > 0, learner.stopped_because_ in {"min_visitation", "no_candidates"}
(True, True)
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner
from symlearn.learners.constraints.constraint_metrics import reachable_pairs
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.mdp import TabularMDP
from symlearn.mdp.episodes import (as_tabular, check_constraints, demonstrated_pairs, final_states, require_steps,
                                    tabular_episodes)
from symlearn.rl.maxent import forward_pass, maxent_backward_pass
from symlearn.rl.tabular import check_mask, restrict

Generalizer = Callable[[np.ndarray, np.ndarray], np.ndarray]


#: why the loop ended, in words (``stop_reason_`` -> text, :meth:`MLConstraintInference.stop_text`)
STOP_REASONS = {
    "min_visitation": "no undemonstrated pair is likely any more (visitation below min_visitation)",
    "no_candidates": "no undemonstrated pair is left to forbid",
    "max_iterations": "the iteration cap ({iterations}) was reached",
    "min_evidence": "forbidding the likeliest undemonstrated pair, with what its rules forbid, would make the "
                    "demonstrations less than min_evidence nats likelier",
}


@dataclass(frozen=True)
class InferenceStep:
    iteration: int
    state: int
    action: int
    visitation: float  # expected visits of the chosen pair under the nominal policy
    n_forbidden: int  # size of the closed constraint set after this step
    n_generalized: int  # pairs added by ``generalize`` in this step
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def tabular_model(domain: Any) -> tuple[TabularMDP, np.ndarray | None]:
    """The nominal MDP of ``domain`` and the pairs it forbids in advance (moves that do not exist).

    ``domain``: a :class:`~symlearn.grounding.Domain` (its ``mdp`` and ``known``), a
    :class:`TabularMDP`, or an environment with ``to_tabular()``.
    """
    from symlearn.grounding import Domain, as_domain

    if isinstance(domain, Domain) or isinstance(getattr(domain, "domain", None), Domain):
        d = as_domain(domain)
        return d.mdp, d.known
    if domain is None:
        raise SymlearnError("constraint inference needs the domain: fit(demonstrations, world=domain)",
                            hint="a symlearn.grounding.Domain, a TabularMDP or an environment with to_tabular()")
    return as_tabular(domain), None


class MaxEntVisitation:
    """Goal-conditioned MaxEnt visitation of an MDP under a constraint set (one fit's planner)."""

    def __init__(self, mdp: TabularMDP, goal_groups: list[tuple[int, float, np.ndarray]], reward: Any,
                 horizon: int, rationality: float) -> None:
        self.mdp, self.goal_groups, self.reward = mdp, goal_groups, reward
        self.horizon, self.rationality = horizon, rationality

    def _reward(self, goal: int) -> np.ndarray:
        mdp = self.mdp
        if isinstance(self.reward, str):
            if self.reward == "given":
                return mdp.rewards
            if self.reward == "sparse":
                sparse = np.zeros(mdp.transitions.shape)
                sparse[:, :, goal] = 1.0
                return sparse
            raise SymlearnError(f"unknown reward {self.reward!r}", hint="use 'given', 'sparse' or an array")
        return np.asarray(self.reward, dtype=np.float64)

    def __call__(self, forbidden: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Expected state-action visitation (S, A) of the goal-conditioned nominal policies in
        the MDP restricted by ``forbidden``, and the policy for the most frequent goal."""
        mdp = self.mdp
        allowed = ~forbidden
        total = np.zeros(forbidden.shape)
        main_policy = None
        for goal, weight, start in self.goal_groups:
            reward = self.rationality * self._reward(goal)
            backward = maxent_backward_pass(mdp, [goal], self.horizon, reward=reward, allowed=allowed)
            goal_mdp = mdp.make_absorbing([goal]) if not mdp.terminal[goal] else mdp
            visits = forward_pass(goal_mdp, backward.policy, self.horizon, initial=start, tol=1e-12)
            total += weight * visits.state_actions
            if main_policy is None:
                main_policy = backward.policy
        return total, main_policy


@dataclass(frozen=True)
class PassedOver:
    """A pair inference would have chosen but was not allowed to (outside ``choosable``)."""

    iteration: int
    state: int
    action: int
    visitation: float


class MLConstraintInference(Learner):
    """``MLConstraintInference(reward=..., horizon=..., ...).fit(demonstrations, world)``.

    ``world``: a :class:`~symlearn.grounding.Domain` (moves it does not have are known
    constraints), a :class:`TabularMDP` or an environment with ``to_tabular()``.

    Results: ``constraints_`` (forbidden (S, A) mask), ``empty_states_``, ``policy_`` (nominal
    MaxEnt policy of the restricted MDP for the most frequent goal), ``goals_``, ``history_``
    (one :class:`InferenceStep` per added constraint), ``stop_reason_`` ("min_visitation",
    "no_candidates", "max_iterations" or the reason ``stop_when`` gave; ``stopped_because_`` is the
    same), ``passed_over_`` (:class:`PassedOver` list), ``seconds_``,
    ``known_`` (the constraints given in advance), ``result_``.
    """

    artefact_suffix = ".json"

    def __init__(
        self,
        *,
        reward: Literal["given", "sparse"] | np.ndarray = "given",
        horizon: int = 50,
        max_iterations: int = 200,
        min_visitation: float = 1e-3,
        known_constraints: np.ndarray | None = None,
        on_violation: Literal["error", "warn"] = "error",
        generalize: Generalizer | None = None,
        rationality: float | Literal["auto"] = "auto",
        start: Literal["demonstrations", "uniform"] | float = "demonstrations",
        choosable: np.ndarray | None = None,
        stop_when: Callable[[], str | None] | None = None,
        min_evidence: float | None = None,
        refit_rationality: bool = False,
    ) -> None:
        self.reward = reward
        self.horizon = horizon
        self.max_iterations = max_iterations
        self.min_visitation = min_visitation
        self.known_constraints = known_constraints
        self.on_violation = on_violation
        self.generalize = generalize
        self.rationality = rationality
        self.start = start
        self.choosable = choosable
        self.stop_when = stop_when
        self.min_evidence = min_evidence
        self.refit_rationality = refit_rationality

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Iterable[Any], world: Any = None) -> MLConstraintInference:
        if self.horizon < 1 or self.max_iterations < 0:
            raise SymlearnError("horizon must be at least 1 and max_iterations non-negative")
        share = _uniform_share(self.start)
        started = time.perf_counter()
        mdp, domain_known = tabular_model(world)
        episodes = tabular_episodes(demonstrations, mdp)
        seen = demonstrated_pairs(episodes, mdp)
        require_steps(episodes)
        known = np.zeros_like(seen) if domain_known is None else domain_known.copy()
        if self.known_constraints is not None:
            known |= check_mask(mdp, self.known_constraints, "known constraints")
        forbidden = known.copy()
        if forbidden.any():
            check_constraints(episodes, forbidden, self.on_violation)
            forbidden &= ~seen  # with on_violation="warn" the noisy pairs stay allowed
        visitation = MaxEntVisitation(mdp, _goal_groups(mdp, episodes, share), self.reward, self.horizon, 1.0)
        starts = np.zeros(mdp.n_states)  # where the demonstrations start: what "reachable" is measured from
        starts[[int(e.states[0]) for e in episodes]] = 1.0
        fitted = resolve_rationality(self.rationality, visitation, episodes, ~forbidden)
        visitation.rationality = fitted.value
        forbidden = restrict(mdp, forbidden, protected=seen).forbidden
        history: list[InferenceStep] = []
        passed: list[PassedOver] = []
        passed_mask = np.zeros_like(seen)
        choosable = None if self.choosable is None else check_mask(mdp, self.choosable, "choosable pairs")
        stopped = "max_iterations"
        policy = None
        for iteration in range(1, self.max_iterations + 2):
            t0 = time.perf_counter()
            visits, policy = visitation(forbidden)
            if iteration > self.max_iterations:
                break
            candidates = np.where(~forbidden & ~seen & ~mdp.terminal[:, None], visits, -np.inf)
            if choosable is not None:
                outside = np.where(~choosable, candidates, -np.inf)
                candidates = np.where(choosable, candidates, -np.inf)
            best = int(np.argmax(candidates))
            value = float(candidates.flat[best])
            if choosable is not None and value >= self.min_visitation:
                # what would have been chosen before this pair, recorded once each (when nothing
                # choosable is left the loop ends, and what it would still infer is not recorded)
                for ps, pa in np.argwhere((outside >= value) & ~passed_mask):
                    passed.append(PassedOver(iteration, int(ps), int(pa), float(outside[ps, pa])))
                    passed_mask[ps, pa] = True
            if not np.isfinite(value):
                stopped = "no_candidates"
                break
            if value < self.min_visitation:
                stopped = "min_visitation"
                break
            # the evidence test (min_evidence) is asked of this step only when the pair alone is
            # not enough and its state is one the demonstrations could reach under the constraints
            # so far: a pair in a state none can reach (only the uniform start share visits it)
            # can have no evidence either way -- the share's guess, bounded by min_visitation
            ask = (self.min_evidence is not None and value * len(episodes) < self.min_evidence
                   and bool(reachable_pairs(mdp, forbidden, initial=starts).flat[best]))
            previous = forbidden
            snapshot = self.generalize.snapshot() if ask and hasattr(self.generalize, "snapshot") else None
            s, a = divmod(best, mdp.n_actions)
            forbidden = forbidden.copy()
            forbidden[s, a] = True
            before = int(restrict(mdp, forbidden, protected=seen).forbidden.sum())
            n_generalized = 0
            if self.generalize is not None:
                extra = check_mask(mdp, self.generalize(forbidden, seen), "generalized constraints")
                extra &= ~seen
                n_generalized = int((extra & ~forbidden).sum())
                forbidden |= extra
            forbidden = restrict(mdp, forbidden, protected=seen).forbidden
            if ask and _gain(visitation, episodes, previous, forbidden) < self.min_evidence:
                # the step raises the demonstrations' log-likelihood by fewer than min_evidence
                # nats (Akaike's price of a parameter at 1): what it forbids is what the nominal
                # policy itself would leave undemonstrated about as often as not -- undo it, stop
                forbidden = previous
                if snapshot is not None:
                    self.generalize.restore(snapshot)
                stopped = "min_evidence"
                break
            if self.refit_rationality and fitted.source == "fitted":
                # coordinate ascent on the one likelihood: the temperature that best explains the
                # demonstrations under the constraints found so far. Fitted without them it is
                # biased low (detours around forbidden pairs look like randomness), and a planner
                # that random visits allowed moves a deliberate expert never needed (waiting,
                # no-op actions) often enough to make their absence look like a constraint.
                fitted = resolve_rationality("auto", visitation, episodes, ~forbidden)
                visitation.rationality = fitted.value
            history.append(InferenceStep(iteration, s, a, value, int(forbidden.sum()),
                                         max(n_generalized, int(forbidden.sum()) - before), time.perf_counter() - t0))
            reason = self.stop_when() if self.stop_when is not None else None
            if reason:
                stopped = reason
                visits, policy = visitation(forbidden)
                break
        final = restrict(mdp, forbidden, protected=seen)
        self.constraints_ = final.forbidden
        self.empty_states_ = final.empty_states
        self.demonstrated_ = seen
        self.known_ = known
        self.policy_ = policy
        self.goals_ = tuple(g for g, _, _ in visitation.goal_groups)
        self.history_ = history
        self.stop_reason_ = self.stopped_because_ = stopped
        self.passed_over_ = passed
        self.rationality_, self.rationality_fit_ = fitted.value, fitted
        self.seconds_ = time.perf_counter() - started
        from symlearn.learners.constraints.constraint_file import constraint_set_text, world_name

        learned = self.constraints_ & ~known
        self._set_result(learned, constraint_set_text(learned, mdp, method="ml", domain=world_name(world)),
                         metrics={"constraints": int(learned.sum()), "stopped_because": stopped,
                                  "rationality": fitted.value},
                         timings={"total": self.seconds_}, history=history)
        return self


    def stop_text(self) -> str:
        """``stop_reason_`` in words (a reason ``stop_when`` gave as it is)."""
        self.check_fitted()
        return STOP_REASONS.get(self.stop_reason_, self.stop_reason_).format(iterations=self.max_iterations)


def _gain(visitation: MaxEntVisitation, episodes, before: np.ndarray, after: np.ndarray) -> float:
    """How many nats likelier the demonstrated actions are under the goal-conditioned nominal
    policies with ``after`` forbidden than with ``before`` (the same likelihood the rationality is
    fitted by, at the current rationality). Not the pairs' expected visits: a visit after a first
    forbidden step lies off every demonstration and changes no demonstrated action's probability."""
    from symlearn.learners.constraints.rationality_fit import demonstration_log_likelihood

    steps = sum(len(e.actions) for e in episodes)
    ll = [demonstration_log_likelihood(visitation.mdp, episodes, visitation._reward, visitation.rationality,
                                       visitation.horizon, ~mask) for mask in (before, after)]
    return (ll[1] - ll[0]) * steps


def resolve_rationality(setting: Any, visitation: MaxEntVisitation, episodes, allowed: np.ndarray):
    """The rationality a fit plans with: ``setting`` itself when it is a number (checked: positive and
    finite), fitted to ``episodes`` by maximum likelihood for ``"auto"``."""
    from symlearn.learners.constraints.rationality_fit import RationalityFit, check_rationality, fit_rationality

    if isinstance(setting, str):
        if setting != "auto":
            raise SymlearnError(f"unknown rationality {setting!r}", hint="use 'auto' or a positive number")
        return fit_rationality(visitation.mdp, episodes, visitation._reward, visitation.horizon, allowed,
                               sparse=isinstance(visitation.reward, str) and visitation.reward == "sparse")
    return RationalityFit(check_rationality(setting), "given")


def _goal_groups(mdp: TabularMDP, episodes, share: float) -> list[tuple[int, float, np.ndarray]]:
    """(goal, share of demonstrations, start distribution) per state where demonstrations end."""
    ends = final_states(episodes)
    groups = []
    for goal in sorted(set(ends.tolist()), key=lambda g: (-int(np.sum(ends == g)), g)):
        members = [e for e, end in zip(episodes, ends) if end == goal]
        start = np.bincount([int(e.states[0]) for e in members], minlength=mdp.n_states) / len(members)
        if share > 0:
            everywhere = (~mdp.terminal).astype(np.float64) / np.sum(~mdp.terminal)
            start = (1 - share) * start + share * everywhere
        groups.append((goal, len(members) / len(episodes), start))
    return groups


def _uniform_share(start: Any) -> float:
    """The share of start mass spread over every state, from a ``start`` setting."""
    if isinstance(start, str):
        shares = {"demonstrations": 0.0, "uniform": 1.0}
        if start not in shares:
            raise SymlearnError(f"unknown start {start!r}", hint="use 'demonstrations', 'uniform' or a share in [0, 1]")
        return shares[start]
    share = float(start)
    if not 0.0 <= share <= 1.0:
        raise SymlearnError(f"a uniform start share must lie in [0, 1], got {start}")
    return share
