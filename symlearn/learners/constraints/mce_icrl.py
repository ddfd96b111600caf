"""Tabular maximum causal entropy inverse constrained RL (MCE-ICRL) and its non-causal baseline.

The learner looks for the policy that maximises reward plus ``beta`` times the causal entropy
while its expected (discounted) features do not exceed the expert's. Its Lagrangian dual is
solved by alternating

1. soft policy iteration with cost ``C(s, a) = lambda . phi(s, a)`` subtracted from the reward
   (exact soft value iteration, warm-started from the previous round), and
2. a projected gradient step on the multipliers,
   ``lambda <- max(0, lambda - eta * (E_D[phi] - E_pi[phi]))``, where ``E_pi`` is computed
   exactly with a forward pass in the true (stochastic) dynamics and ``E_D`` from the
   demonstrations.

Features whose expected count under the policy exceeds the expert's gain cost; the learned
constraint map is the set of features whose multiplier ends above ``threshold``, less what the
expert does on purpose. A multiplier only says that the entropy-regularised policy would visit a
feature more often than the demonstrations did -- on a user's world with a small step reward the
policy wanders, and every cell of the expert's own route gets a cost. So the binary reading
(``constraint_map_``, ``forbidden_``) leaves out the states the expert *heads for*: a start state
of a demonstration, and the most likely successor of a demonstrated move made from a state it
heads for (a fixpoint over the demonstrations), and with pair features the moves it makes from
them. A slip -- a successor other than the most likely one -- does not count, so a forbidden cell
the dynamics carried the expert into stays forbidden, and so does a move it made from there. The
multipliers, the cost and the policy are unchanged by this reading.

:class:`MEICRL` is the same loop with *non-causal* (trajectory) entropy: the policy comes from
the trajectory-level MaxEnt model ``P(tau) ~ prod P(s'|s,a) exp(return / beta)``, whose backup
is ``Q = R - C + gamma * beta * log E_{s'}[exp(V(s') / beta)]`` (see
:mod:`symlearn.rl.maxent`). That model credits the agent with choosing its own successor, so a
risky action is valued by its lucky outcomes: with stochastic dynamics no multiplier can stop
the policy from taking it, and the violations stay. With deterministic dynamics the two coincide.

>>> from symlearn.envs.gridworld import StochasticGridworld
>>> from symlearn.data import record
>>> env = StochasticGridworld(0.0); policy = env.expert_policy()
>>> demos = record(env, lambda s: int(policy[s]), 5, seed=0, max_steps=200)
>>> learner = MCEICRL(n_iterations=200).fit(demos, env.to_tabular())
>>> bool(learner.constraint_map_[env.forbidden_states].mean() > 0.5)
True
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from symlearn.errors import ModelError, SymlearnError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.constraints.ml_constraint_inference import tabular_model
from symlearn.mdp import TabularMDP
from symlearn.mdp.episodes import check_constraints, discounted_counts, require_steps, tabular_episodes
from symlearn.rl.maxent import Entropy, forward_pass, soft_value_iteration
from symlearn.rl.tabular import check_mask


def state_features(mdp: TabularMDP) -> np.ndarray:
    """``phi(s, a) = one-hot(s)``: one multiplier, hence one cost, per state."""
    return np.broadcast_to(np.eye(mdp.n_states)[:, None, :], (mdp.n_states, mdp.n_actions, mdp.n_states))


def state_action_features(mdp: TabularMDP) -> np.ndarray:
    """``phi(s, a) = one-hot(s, a)``: one multiplier per state-action pair."""
    k = mdp.n_states * mdp.n_actions
    return np.eye(k).reshape(mdp.n_states, mdp.n_actions, k)


_FEATURES = {"state": state_features, "state_action": state_action_features}


@dataclass(frozen=True)
class DualStep:
    iteration: int
    excess: float  # largest amount by which a policy feature count exceeds the expert's
    n_active: int  # multipliers above the threshold
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


class MCEICRL(Learner):
    """Tabular MCE-ICRL: ``MCEICRL(...).fit(demonstrations, world)``.

    ``world``: a :class:`~symlearn.grounding.Domain`, a :class:`TabularMDP` or an environment
    with ``to_tabular()``; its rewards are the known reward, moves it does not have are known
    constraints. Parameters: ``reward`` (``"given"``: the model's rewards; ``"sparse"``: 1 for
    entering a state where a demonstration ended, which becomes terminal -- for worlds without a
    reward), ``features`` (``"state"``,
    ``"state_action"`` or a non-negative array ``(S, A, k)``), ``beta`` (entropy weight),
    ``discount``, ``horizon`` (steps counted in feature expectations; demonstrations are cut
    there too), ``learning_rate`` (eta), ``n_iterations``, ``budget`` (alpha: the slack of the
    feature-matching constraint; 0 = hard constraints), ``tol`` (stop once no policy feature
    count exceeds the expert's by more than ``tol + budget``), ``patience`` and ``min_improvement``
    (stop as stalled once the largest excess has not fallen by ``min_improvement``, a share, in the
    last ``patience`` iterations: with hard feature matching and noisy demonstrations the
    constraints are often not exactly feasible, and the excess settles above ``tol`` while the
    multipliers keep growing; ``patience=None`` runs to ``n_iterations``), ``threshold`` (a multiplier
    above it marks a constrained feature), ``known_constraints`` (a forbidden (S, A) mask that
    is known in advance: removed from the policy; demonstrations breaking it raise a
    :class:`~symlearn.errors.DataError`, or with ``on_violation="warn"`` a warning with the
    count), ``max_sweeps`` (soft value iteration sweeps per round; the solve is warm-started).

    Results: ``lambda_`` (k,), ``cost_`` (S, A), ``policy_`` (S, A), ``constraint_map_``
    (``lambda_ > threshold``, less the states the expert heads for with state features and the
    moves it makes from them with state-action features -- see the module docstring; per state
    for state features), ``headed_for_`` (S,) bool, ``multipliers_`` (positive multipliers by state name, state features only),
    ``expert_features_``,
    ``policy_features_``, ``history_`` (one :class:`DualStep` per iteration), ``converged_``,
    ``stop_reason_`` (``"converged"``, ``"stalled"`` or ``"max_iterations"``), ``n_iter_``, ``seconds_``.
    """

    entropy: Entropy = "causal"

    artefact_suffix = ".json"

    def __init__(
        self,
        *,
        reward: Literal["given", "sparse"] = "given",
        features: str | np.ndarray = "state",
        beta: float = 0.5,
        discount: float = 0.99,
        horizon: int = 200,
        learning_rate: float = 2.0,
        n_iterations: int = 300,
        budget: float = 0.0,
        tol: float = 1e-3,
        threshold: float = 0.5,
        known_constraints: np.ndarray | None = None,
        on_violation: Literal["error", "warn"] = "error",
        max_sweeps: int = 50,
        patience: int | None = 100,
        min_improvement: float = 0.02,
    ) -> None:
        self.reward = reward
        self.features = features
        self.beta = beta
        self.discount = discount
        self.horizon = horizon
        self.learning_rate = learning_rate
        self.n_iterations = n_iterations
        self.budget = budget
        self.tol = tol
        self.threshold = threshold
        self.known_constraints = known_constraints
        self.on_violation = on_violation
        self.max_sweeps = max_sweeps
        self.patience = patience
        self.min_improvement = min_improvement

    def _phi(self, mdp: TabularMDP) -> np.ndarray:
        if isinstance(self.features, str):
            try:
                return _FEATURES[self.features](mdp)
            except KeyError:
                raise SymlearnError(f"unknown features {self.features!r}", hint=f"use one of {sorted(_FEATURES)} or an array") from None
        phi = np.asarray(self.features, dtype=np.float64)
        if phi.ndim != 3 or phi.shape[:2] != (mdp.n_states, mdp.n_actions):
            raise ModelError(f"features must have shape (S, A, k) with (S, A) = {(mdp.n_states, mdp.n_actions)}, got {phi.shape}")
        if (phi < 0).any() or not np.isfinite(phi).all():
            raise ModelError("features must be finite and non-negative")
        return phi

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Iterable[Any], world: Any = None) -> MCEICRL:
        if self.learning_rate <= 0 or self.n_iterations < 1 or self.horizon < 1:
            raise SymlearnError("learning_rate must be positive, n_iterations and horizon at least 1")
        if self.patience is not None and (self.patience < 1 or not 0 <= self.min_improvement < 1):
            raise SymlearnError("patience must be at least 1 (or None) and min_improvement in [0, 1)")
        started = time.perf_counter()
        mdp, known = tabular_model(world)
        episodes = tabular_episodes(demonstrations, mdp)
        require_steps(episodes)
        if self.reward == "sparse":
            # no reward given: the expert is taken to head for where its demonstrations end
            # (reward 1 for entering such a state, which then ends the episode)
            from symlearn.mdp.episodes import final_states

            mdp = mdp.with_goal(sorted(set(final_states(episodes).tolist())), goal_reward=1.0)
        elif self.reward != "given":
            raise SymlearnError(f"unknown reward {self.reward!r}", hint="use 'given' or 'sparse'")
        if self.known_constraints is not None:
            given = check_mask(mdp, self.known_constraints, "known constraints")
            known = given if known is None else known | given
        allowed = None
        if known is not None and known.any():
            check_constraints(episodes, known, self.on_violation)
            allowed = ~known
        phi = self._phi(mdp)
        flat_phi = phi.reshape(-1, phi.shape[2])
        expert = discounted_counts(episodes, mdp, self.discount, self.horizon).reshape(-1) @ flat_phi
        lam = np.zeros(phi.shape[2])
        values = None
        history: list[DualStep] = []
        converged = False
        stop = "max_iterations"
        excesses: list[float] = []
        policy_features = np.zeros_like(expert)
        policy = None
        for iteration in range(1, self.n_iterations + 1):
            t0 = time.perf_counter()
            cost = (flat_phi @ lam).reshape(mdp.n_states, mdp.n_actions)
            solved = soft_value_iteration(mdp, beta=self.beta, discount=self.discount, cost=cost, allowed=allowed,
                                          entropy=self.entropy, tol=1e-6, initial_values=values,
                                          max_iterations=self.max_sweeps)
            values = solved.values
            policy = solved.policy
            visits = forward_pass(mdp, policy, self.horizon, discount=self.discount, tol=1e-12)
            policy_features = visits.state_actions.reshape(-1) @ flat_phi
            gap = expert - policy_features - self.budget  # gradient of the Lagrangian in lambda
            excess = float(np.max(-gap))
            if excess <= self.tol:
                converged = True
            else:
                lam = np.maximum(0.0, lam - self.learning_rate * gap)
            history.append(DualStep(iteration, excess, int((lam > self.threshold).sum()), time.perf_counter() - t0))
            excesses.append(excess)
            if converged:
                stop = "converged"
                break
            if self._stalled(excesses):
                stop = "stalled"
                break
        self.lambda_ = lam
        self.cost_ = (flat_phi @ lam).reshape(mdp.n_states, mdp.n_actions)
        self.policy_ = policy
        self.expert_features_ = expert
        self.policy_features_ = policy_features
        self.headed_for_, deliberate = deliberate_moves(mdp, episodes)
        self.deliberate_ = deliberate
        self.constraint_map_ = lam > self.threshold
        if self.constraint_map_.shape == (mdp.n_states,) and self._state_features():
            self.constraint_map_ &= ~self.headed_for_
        elif isinstance(self.features, str) and self.features == "state_action":
            self.constraint_map_ &= ~deliberate.reshape(-1)
        self.history_ = history
        self.converged_ = converged
        self.stop_reason_ = stop
        self.n_iter_ = len(history)
        self.seconds_ = time.perf_counter() - started
        self.forbidden_ = self._forbidden_pairs(mdp, known)
        from symlearn.learners.constraints.constraint_file import constraint_set_text, world_name

        names = mdp.state_names or tuple(str(s) for s in range(mdp.n_states))
        # by state name, for one multiplier per state (state features); None otherwise
        self.multipliers_ = ({names[s]: float(v) for s, v in enumerate(lam) if v > 0}
                             if lam.shape[0] == mdp.n_states else None)
        self._set_result(self.forbidden_, constraint_set_text(self.forbidden_, mdp, method="mce-icrl",
                                                              domain=world_name(world), multipliers=self.multipliers_),
                         metrics={"constraints": int(self.forbidden_.sum()), "converged": converged,
                                  "stop_reason": stop},
                         timings={"total": self.seconds_}, history=history)
        return self

    def _forbidden_pairs(self, mdp: TabularMDP, known: np.ndarray | None) -> np.ndarray:
        """The constraint set the multipliers imply, as forbidden (S, A) pairs: with state
        features every move whose most likely successor is a constrained state; with
        state-action (or custom) features every pair whose cost exceeds the threshold."""
        if self.constraint_map_.shape == (mdp.n_states,) and self._state_features():
            forbidden = self.constraint_map_[np.argmax(mdp.transitions, axis=2)]
        else:
            forbidden = (self.cost_ > self.threshold) & ~self.deliberate_
        forbidden = forbidden & ~mdp.terminal[:, None]
        return forbidden if known is None else forbidden & ~known

    def stop_text(self) -> str:
        """``stop_reason_`` in words."""
        self.check_fitted()
        return {"converged": "converged: no feature count of the policy exceeds the expert's by more than the "
                             "tolerance",
                "stalled": f"stalled: the largest excess of a policy feature count over the expert's fell by less "
                           f"than {self.min_improvement:.0%} in the last {self.patience} iterations (the "
                           "demonstrations' counts are not exactly reachable)",
                "max_iterations": f"the iteration cap ({self.n_iterations}) was reached"}[self.stop_reason_]

    def _stalled(self, excesses: list[float]) -> bool:
        """Whether the best excess of the last ``patience`` iterations is no more than
        ``min_improvement`` (a share) below the best one before them."""
        k = self.patience
        if k is None or len(excesses) < 2 * k:
            return False
        before, recent = min(excesses[:-k]), min(excesses[-k:])
        return recent > (1.0 - self.min_improvement) * before

    def _state_features(self) -> bool:
        """Whether the features are read per state (the string ``"state"`` or a custom array of
        one column per state)."""
        return not isinstance(self.features, str) or self.features == "state"


def deliberate_moves(mdp: TabularMDP, episodes) -> tuple[np.ndarray, np.ndarray]:
    """``(headed_for, moves)``: the states the expert heads for -- the demonstrations' start states
    and, to a fixpoint, the most likely successor of every demonstrated move made from such a
    state -- as an (S,) mask, and those moves as an (S, A) mask (see the module docstring)."""
    target = np.argmax(mdp.transitions, axis=2)  # the intended successor of every move
    demonstrated = np.zeros((mdp.n_states, mdp.n_actions), dtype=bool)
    headed = np.zeros(mdp.n_states, dtype=bool)
    for e in episodes:
        states, actions = np.asarray(e.states[: len(e.actions)]), np.asarray(e.actions)
        demonstrated[states, actions] = True
        if len(states):
            headed[int(states[0])] = True
    # the fixpoint as a search over the demonstrated moves' intended successors: each state once
    stack = list(np.flatnonzero(headed))
    while stack:
        s = stack.pop()
        for nxt in target[s, demonstrated[s]]:
            if not headed[nxt]:
                headed[nxt] = True
                stack.append(int(nxt))
    return headed, demonstrated & headed[:, None]


class MEICRL(MCEICRL):
    """The baseline with non-causal (trajectory) entropy; see the module docstring."""

    entropy: Entropy = "trajectory"
