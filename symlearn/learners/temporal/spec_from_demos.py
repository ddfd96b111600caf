"""Learning an LTLf task specification from expert demonstrations, alternating inference and
policy updates (the method of the thesis, chapter 5).

Start from the specification ``true`` and a random nominal policy. Each iteration samples
nominal trajectories, picks the instantiated template (``F p``, ``G p``, ``p T q`` or a
negation) that best separates expert from nominal trajectories by information gain, conjoins it
to the specification and retrains the nominal policy on the new specification (DFA -> reward
machine -> CRM Q-learning). It stops when the best gain falls below ``threshold`` (that formula
is not added) or after ``max_iterations`` (a cap: 25 by default where the thesis used 10 with its
given propositions; with learned propositions, every cell a proposition, Office-4 takes 9-12
iterations to converge, measurements in ``docs/BENCHMARKS.md``). Finally each conjunct is held out in turn: if a
policy trained without it still satisfies it with probability at least ``prune_threshold``, it
is implied by the rest and dropped.

Nominal trajectories that reproduce a demonstration state for state are left out of the
information-gain dataset (``drop_reproduced``): every candidate formula treats them exactly like
their expert twin, so they only add entropy no formula can remove (only exact copies go; the
measurements behind this, Office-2 with learned propositions, are in ``docs/BENCHMARKS.md``,
"Specification learning").

Propositions are either *given* (a :class:`~symlearn.grounding.labeling.Labeling`, by default the
environment's) or *learned*: then every state visited by an expert or nominal trajectory is a
candidate proposition "the agent is in this state", and a chosen state becomes a new
proposition ``p0``, ``p1``, ... in order of discovery; :attr:`SpecLearner.labeling_` is the
grown labeling.

>>> from symlearn.envs.spec_experts import expert_demonstrations
>>> from symlearn.envs.spec_tasks import get_task
>>> demos = expert_demonstrations("office-1", 20, seed=0)
>>> learner = SpecLearner(random_state=0).fit(demos, get_task("office-1").make_env())
>>> learner.success_rate("(f T g) & G !n")
1.0
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from symlearn.errors import DataError, ModelError
from symlearn.learners.base import Learner, NotFittedError
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.temporal.spec_env_world import EnvWorld
from symlearn.learners.temporal.task_model import TaskModel, task_model
from symlearn.mdp.episodes import state_sequences
from symlearn.learners.temporal.spec_templates import ARITY, Choice, TraceBounds, best_candidate, instantiate, novelty_depth
from symlearn.grounding.labeling import Labeling
from symlearn.logic.ltlf.ast import Formula, conjunction, size

__all__ = ["SpecIteration", "SpecLearner"]


@dataclass(frozen=True)
class SpecIteration:
    """One iteration: the best candidate, whether it was added, the nominal policy's success."""

    iteration: int
    spec: str  # the specification after this iteration
    added: bool
    template: str | None
    formula: str | None
    gain: float
    expert_rate: float | None
    nominal_rate: float | None
    candidates: int | None
    nominal_success: float  # share of nominal trajectories satisfying the specification before it
    nominal_reproduced: float  # share of nominal trajectories identical to a demonstration
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)

    def __getitem__(self, key: str) -> Any:  # records also read like the JSON they print as
        if not isinstance(key, str) or key not in self.__dataclass_fields__:
            raise KeyError(f"{key!r} is no field of SpecIteration (use as_dict() for a mapping)")
        return getattr(self, key)


@dataclass
class _SpecFit:
    """The working state of one :meth:`SpecLearner.fit`: built when it starts and dropped when it
    returns, so two fits on one learner share nothing and a fit that fails leaves the previous
    results whole. What the fit learned is copied onto the learner at its end."""

    rng: np.random.Generator  # draws the seeds of nominal rollouts, in order
    model: TaskModel | None  # the successor-table world, or
    world: EnvWorld | None  # a gymnasium environment read through its labeling
    history: list[SpecIteration] = field(default_factory=list)
    pruned: list[str] = field(default_factory=list)  # conjuncts dropped by pruning, in order

    @property
    def n_states(self) -> int:
        return self.world.n_states if self.world is not None else self.model.n_states


class SpecLearner(Learner):
    """Learn ``formula_`` (and, without given propositions, ``labeling_``) from demonstrations.

    ``fit(demonstrations, world)``: ``world`` is a :class:`~symlearn.grounding.Domain` (its
    stochastic moves and start states are sampled), or a labelled tabular environment (see
    :mod:`symlearn.learners.temporal.task_model`).

    Parameters: ``propositions`` is ``"given"`` (use ``labeling`` or the environment's),
    ``"learn"``, or a list of proposition names of the given labeling to search over;
    ``policy_updates=False`` keeps the nominal policy random (an ablation); ``q_steps`` is the
    CRM Q-learning budget in environment transitions (default: scaled with the product size);
    ``min_expert_rate`` is the fraction of expert trajectories a conjunct must satisfy to be
    considered at all (our addition to the information-gain criterion: without it, a detail
    some experts show by chance, such as one of two equally short detours, can win on gain
    when demonstrations are few); ``drop_reproduced`` leaves nominal trajectories identical to a
    demonstration out of the information-gain dataset (see the module docstring; ``False`` is
    the plain thesis dataset); ``horizon`` is the episode length of nominal rollouts (default:
    the environment's ``max_steps``, 200 for a domain).

    In a gymnasium environment without a model (see
    :mod:`~symlearn.learners.temporal.spec_env_world`), ``labeling`` labels its observations
    (any form: a function ``(observation, info) -> names``, a feature or table labeling; else
    the environment's ``labeling`` attribute), ``policy`` picks the policy update (``"auto"``:
    tabular CRM Q-learning for discrete observations and actions, PPO otherwise; ``"tabular"``,
    ``"ppo"``), ``q_steps`` / ``ppo_steps`` are their budgets in environment steps and
    ``state_key(env, observation)`` is the Q-table key when the observation is not the state.
    After fitting, :attr:`rejected_` lists the candidates that were not kept and why.
    """

    artefact_suffix = ".ltl"

    def __init__(self, *, propositions: str | Sequence[str] = "given", labeling: Labeling | None = None,
                 threshold: float = 0.2, max_iterations: int = 25, n_nominal: int | None = None,
                 min_expert_rate: float = 0.9, drop_reproduced: bool = True, policy_updates: bool = True,
                 prune: bool = True, prune_threshold: float = 0.9,
                 q_steps: int | None = None, n_envs: int = 128, discount: float = 0.99, epsilon: float = 0.1,
                 n_eval: int = 20, horizon: int | None = None, random_state: int | None = 0,
                 callback: Callable[[dict[str, Any]], None] | None = None, policy: str = "auto",
                 ppo_steps: int | None = None, state_key: Callable[[Any, Any], Any] | None = None) -> None:
        self.propositions = propositions
        self.labeling = labeling
        self.threshold = threshold
        self.max_iterations = max_iterations
        self.n_nominal = n_nominal
        self.min_expert_rate = min_expert_rate
        self.drop_reproduced = drop_reproduced
        self.policy_updates = policy_updates
        self.prune = prune
        self.prune_threshold = prune_threshold
        self.q_steps = q_steps
        self.n_envs = n_envs
        self.discount = discount
        self.epsilon = epsilon
        self.n_eval = n_eval
        self.horizon = horizon
        self.random_state = random_state
        self.callback = callback
        self.policy = policy
        self.ppo_steps = ppo_steps
        self.state_key = state_key

    # ------------------------------------------------------------------------------------------
    @renamed_arguments(domain="world")
    def fit(self, demonstrations, world=None) -> SpecLearner:
        """Learn from ``demonstrations`` (Demonstrations, trajectories or state sequences) in
        ``world``: a Domain or a labelled tabular environment (see :func:`task_model`; the fast
        path), or any gymnasium environment or factory of one, whose observations ``labeling``
        labels (see :mod:`~symlearn.learners.temporal.spec_env_world`)."""
        t_start = time.perf_counter()
        self._check_parameters()
        if world is None:
            raise ModelError("specification learning needs the world: fit(demonstrations, world=domain_or_env)")
        learn = self.propositions == "learn"
        if _has_model(world):
            run = _SpecFit(np.random.default_rng(self.random_state), task_model(world, horizon=self.horizon), None)
            experts = state_sequences(demonstrations, run.model.n_states, run.model.state_names)
            labeling, names = (Labeling({}), []) if learn else self._given_labeling(run.model)
        else:
            if learn:
                raise ModelError("learned propositions need a tabular model (states to name); in a gymnasium "
                                 "environment give a labeling", hint="propositions='given' with labeling=")
            run = _SpecFit(np.random.default_rng(self.random_state), None,
                           EnvWorld(world, self.labeling, horizon=self.horizon, policy=self.policy,
                                    q_steps=self.q_steps, ppo_steps=self.ppo_steps, discount=self.discount,
                                    epsilon=self.epsilon, state_key=self.state_key))
            labeling = run.world.labeling
            experts = run.world.expert_traces(demonstrations)
            names = None  # read from the labels met, every iteration
        model = run.model
        n_nominal = self.n_nominal or len(experts)

        conjuncts: list[tuple[Formula, tuple[str, tuple[str, ...]]]] = []
        policy = last_policy = None
        stopped_because = "max_iterations"
        for iteration in range(1, self.max_iterations + 1):
            t0 = time.perf_counter()
            nominal = (self._random_traces(run, n_nominal) if policy is None else
                       self._policy_traces(run, policy, n_nominal))
            spec = conjunction(*(f for f, _ in conjuncts))
            nominal_success = self._satisfaction(run, spec, labeling, nominal)
            if run.world is not None:  # label ids stand in for states (see spec_env_world)
                atom_names = self._env_names(run.world)
                atom_of_state = run.world.atoms(atom_names)
            elif learn:
                states = np.unique(np.concatenate([*experts, *nominal]))
                atom_names = [self._state_name(labeling, int(s)) for s in states]
                atom_of_state = np.zeros((model.n_states, len(states)), dtype=bool)
                atom_of_state[states, np.arange(len(states))] = True
            else:
                atom_names = list(names)
                atom_of_state = np.array([[p in labeling.label(s) for p in names] for s in range(model.n_states)],
                                         dtype=bool).reshape(model.n_states, len(names))
            covered = np.zeros(run.n_states, dtype=bool)
            covered[np.concatenate(nominal)] = True
            exclude = {(key[0], tuple(atom_names.index(a) for a in key[1]), False)
                       for _, key in conjuncts if all(a in atom_names for a in key[1])}
            # the nominal side of the gain dataset: what the nominal agent does that no expert did
            contrast = _without_reproductions(nominal, experts) if self.drop_reproduced else nominal
            choice = None if not contrast else best_candidate(
                TraceBounds.from_traces(experts, atom_of_state), TraceBounds.from_traces(contrast, atom_of_state),
                preference=novelty_depth(experts, atom_of_state, covered), exclude=exclude,
                min_expert_rate=self.min_expert_rate)
            record = {"iteration": iteration, "nominal_success": nominal_success, "spec": str(spec),
                      "nominal_reproduced": 1.0 - len(contrast) / len(nominal)}
            if choice is None or choice.gain < self.threshold:
                record.update(self._describe(choice, atom_names, None), added=False,
                              seconds=time.perf_counter() - t0)
                self._log(run, record)
                stopped_because = ("gain below threshold" if choice is not None else
                                         "no candidates" if contrast else "nominal reproduces the demonstrations")
                break
            chosen = [atom_names[i] for i in choice.atoms]
            if learn:
                for k, name in enumerate(chosen):
                    if name.startswith("s"):  # a state not yet a proposition
                        state = int(name[1:])
                        new = f"p{len(labeling.propositions)}"
                        labeling = labeling.with_proposition(new, [state], model.describe(state))
                        chosen[k] = new
            formula = instantiate(choice.template, chosen, choice.negated)
            conjuncts.append((formula, (choice.template, tuple(chosen))))
            if self.policy_updates:
                policy = last_policy = self._train(run, conjunction(*(f for f, _ in conjuncts)), labeling,
                                                   seed=iteration)
            record.update(self._describe(choice, atom_names, formula), added=True,
                          spec=str(conjunction(*(f for f, _ in conjuncts))), seconds=time.perf_counter() - t0)
            self._log(run, record)

        unpruned = conjunction(*(f for f, _ in conjuncts))
        if self.prune and len(conjuncts) > 1:
            conjuncts = self._pruned(run, conjuncts, labeling)
        formula = conjunction(*(f for f, _ in conjuncts))
        same = last_policy is not None and formula == unpruned
        policy = last_policy if same else self._train(run, formula, labeling, seed=10_000)
        entropy = self._entropy(run, policy)

        # the results, all set together once the fit has succeeded
        self.model_, self.world_ = run.model, run.world
        self.history_ = run.history
        self.pruned_ = run.pruned
        self.stopped_because_ = stopped_because
        self.unpruned_formula_ = unpruned
        self.formula_ = formula
        self.full_labeling_ = labeling
        self.labeling_ = _restrict(labeling, formula) if learn else labeling
        self.policy_ = policy
        self.entropy_ = entropy
        self.rejected_ = self._rejected(run)
        self.dfa_ = self._dfa(formula)
        self.iterations_ = sum(1 for h in run.history if h.added)
        self.seconds_ = time.perf_counter() - t_start
        self._set_result(self.formula_, str(self.formula_) + "\n",
                         metrics={"length": self.length_, "iterations": self.iterations_, "entropy": self.entropy_,
                                  "pruned": list(self.pruned_), "stopped_because": self.stopped_because_},
                         timings={"total": self.seconds_}, history=self.history_)
        return self

    # --- results ------------------------------------------------------------------------------
    @property
    def length_(self) -> int:
        """Number of nodes of the learned formula (``true`` counts 1)."""
        return size(self.formula_)

    def success_rate(self, truth, n: int | None = None, labeling: Labeling | None = None) -> float:
        """Fraction of greedy rollouts of the learned nominal policy satisfying ``truth``
        (a formula over the environment's ground-truth labeling unless ``labeling`` is given)."""
        from symlearn.logic.ltlf import holds, parse
        from symlearn.rl.crm_q_learning import sample_episodes

        self._check_fitted()
        truth = parse(truth) if isinstance(truth, str) else truth
        if self.world_ is not None:
            traces = self.world_.policy_traces(self.policy_, n or self.n_eval, seed=self._seed(0))
            return float(np.mean([holds(truth, self.world_.word(t)) for t in traces]))
        labeling = self.model_.labeling if labeling is None else labeling
        if labeling is None:
            raise DataError("the world has no labeling to read the truth formula with; pass labeling=")
        paths = sample_episodes(self.policy_, n or self.n_eval, seed=self.random_state, greedy=True)
        return float(np.mean([holds(truth, [labeling.label(int(s)) for s in p]) for p in paths]))

    # --- steps ----------------------------------------------------------------------------------
    def _check_parameters(self) -> None:
        if not 0 <= self.threshold <= 1:
            raise ModelError(f"threshold must lie in [0, 1], got {self.threshold}")
        if int(self.max_iterations) < 1:
            raise ModelError(f"max_iterations must be at least 1, got {self.max_iterations}")
        if not (self.propositions in ("given", "learn") or
                (not isinstance(self.propositions, str) and all(isinstance(p, str) for p in self.propositions))):
            raise ModelError(f"propositions must be 'given', 'learn' or a list of names, got {self.propositions!r}")

    def _given_labeling(self, model: TaskModel) -> tuple[Labeling, list[str]]:
        labeling = self.labeling if self.labeling is not None else model.labeling
        if labeling is None:
            raise DataError("the world has no labeling, so there are no given propositions",
                            hint="give the domain a labeling (labeling = ... in domain.toml), pass labeling=, "
                                 "or use propositions='learn'")
        n_states = model.n_states
        for state, _ in getattr(labeling, "items", lambda: [])():
            if not (isinstance(state, (int, np.integer)) and 0 <= state < n_states):
                raise DataError(f"the labeling labels state {state!r}, which is not one of the environment's "
                                f"{n_states} states")
        if getattr(labeling, "arity", None) == 3:
            # a finite model (a domain folder) has states, not an environment to hand the function:
            # said here, at the function, instead of "not at hand ... record while recording" at the data
            raise DataError(f"labeling function {labeling.name} takes a third parameter (the environment), which "
                            "a domain or tabular task does not have: it is called with the state id and an "
                            "empty info", file=getattr(labeling, "path", None),
                            hint="drop the third parameter: def label(state, info) -> names")
        if not getattr(labeling, "declared", True):
            # a labeling function without PROPOSITIONS discovers them from what it returns; on a finite
            # model ask it about every state first (before, --domain with such a function stopped at
            # "the given labeling has no propositions": nothing had been labelled yet)
            for state in range(n_states):
                labeling.label(state, where=f"state {state}")
        names = list(labeling.propositions) if self.propositions == "given" else list(self.propositions)
        unknown = [p for p in names if p not in labeling.propositions]
        if unknown:
            raise DataError(f"unknown proposition {unknown[0]!r}: not in the given labeling",
                            hint="known propositions: " + ", ".join(labeling.propositions))
        if not names:
            raise DataError("the given labeling has no propositions (it labels no state with any)",
                            hint="use propositions='learn' (the CLI's --props learn), or a labeling whose "
                                 "propositions hold somewhere")
        return labeling, names

    def _state_name(self, labeling: Labeling, state: int) -> str:
        found = [p for p in labeling.label(state)]
        return found[0] if found else f"s{state}"

    def _seed(self, offset: int) -> int:
        base = 0 if self.random_state is None else int(self.random_state)
        return base * 100_003 + offset

    def _env_names(self, world: EnvWorld) -> list[str]:
        names = world.propositions()
        if self.propositions == "given":
            return names
        unknown = [p for p in self.propositions if p not in names and p not in
                   getattr(world.labeling, "propositions", ())]
        if unknown:
            raise DataError(f"unknown proposition {unknown[0]!r}: the labeling never produced it",
                            hint="met so far: " + (", ".join(names) or "none"))
        return list(self.propositions)

    def _random_traces(self, run: _SpecFit, n: int) -> list[np.ndarray]:
        if run.world is not None:
            return run.world.random_traces(n, seed=int(run.rng.integers(1 << 31)))
        model = run.model
        n_a = model.successors.shape[1]
        s = model.starts(n, run.rng)
        path = [s]
        for _ in range(model.horizon):
            s = model.step(s, run.rng.integers(0, n_a, n), run.rng)
            path.append(s)
        return list(np.stack(path, axis=1))

    def _policy_traces(self, run: _SpecFit, policy, n: int) -> list[np.ndarray]:
        from symlearn.rl.crm_q_learning import sample_episodes

        if run.world is not None:
            return run.world.policy_traces(policy, n, seed=int(run.rng.integers(1 << 31)))
        return sample_episodes(policy, n, seed=int(run.rng.integers(1 << 31)))

    def _train(self, run: _SpecFit, formula: Formula, labeling: Labeling, seed: int):
        from symlearn.logic.automata.reward_machine import RewardMachine
        from symlearn.rl.crm_q_learning import crm_q_learning

        if run.world is not None:
            return run.world.train(formula, seed=self._seed(seed))
        model = run.model
        machine = RewardMachine.from_formula(formula)
        steps = self.q_steps or min(400 * model.n_states * (1 + machine.n_states // 8), 4_000_000)
        labels = [labeling.label(s) for s in range(model.n_states)]
        return crm_q_learning(model.successors, labels, machine, model.start, n_steps=steps, n_envs=self.n_envs,
                              horizon=model.horizon, discount=self.discount, epsilon=self.epsilon,
                              seed=self._seed(seed), dynamics=model.dynamics)

    def _satisfaction(self, run: _SpecFit, formula: Formula, labeling: Labeling,
                      traces: Sequence[np.ndarray]) -> float:
        from symlearn.logic.ltlf import evaluate_many

        label = run.world.label if run.world is not None else (lambda s: labeling.label(int(s)))
        words = [[label(s) for s in t] for t in traces]
        return float(np.mean(evaluate_many(formula, words)))

    def _pruned(self, run: _SpecFit, conjuncts, labeling):
        kept = list(conjuncts)
        for item in list(conjuncts):
            rest = [c for c in kept if c is not item]
            if not rest:
                break
            policy = self._train(run, conjunction(*(f for f, _ in rest)), labeling, seed=20_000 + len(run.pruned))
            rate = self._satisfaction(run, item[0], labeling, self._policy_traces(run, policy, self.n_eval * 2))
            if rate >= self.prune_threshold:
                kept = rest
                run.pruned.append(str(item[0]))
                self._log(run, {"pruned": str(item[0]), "satisfied_without_it": rate})
        return kept

    def _entropy(self, run: _SpecFit, policy) -> float:
        from symlearn.rl.crm_q_learning import policy_entropy

        if run.world is not None:
            self._policy_traces(run, policy, self.n_eval)
            return run.world.last_entropy
        return policy_entropy(policy, self._policy_traces(run, policy, self.n_eval))

    @staticmethod
    def _dfa(formula: Formula):
        from symlearn.logic.ltlf import to_dfa

        return to_dfa(formula)

    def _rejected(self, run: _SpecFit) -> list[dict[str, Any]]:
        """The candidates the search weighed and did not keep: the last, below-threshold best
        candidate and every conjunct pruning dropped."""
        out = [{"formula": h.formula, "why": f"information gain {h.gain:.3f} is below the threshold {self.threshold}"}
               for h in run.history if not h.added and h.formula]
        out += [{"formula": f, "why": "implied by the rest (a policy trained without it still satisfies it)"}
                for f in run.pruned]
        return out

    def _describe(self, choice: Choice | None, atom_names, formula) -> dict[str, Any]:
        if choice is None:
            return {"template": None, "formula": None, "gain": 0.0}
        shown = formula if formula is not None else instantiate(choice.template, [atom_names[i] for i in choice.atoms],
                                                                choice.negated)
        template = ("!" if choice.negated else "") + {1: f"{choice.template} p", 2: "p T q"}[ARITY[choice.template]]
        return {"template": template, "formula": str(shown), "gain": choice.gain, "expert_rate": choice.expert_rate,
                "nominal_rate": choice.nominal_rate, "candidates": choice.n_candidates}

    def _log(self, run: _SpecFit, record: dict[str, Any]) -> None:
        if "iteration" in record:
            run.history.append(SpecIteration(**{f: record.get(f) for f in SpecIteration.__dataclass_fields__}))
        if self.callback is not None:
            self.callback(record)

    def _check_fitted(self) -> None:
        if not hasattr(self, "formula_"):
            raise NotFittedError("this SpecLearner is not fitted yet; call fit(demonstrations, world) first")


def _has_model(world: Any) -> bool:
    """A Domain or a labelled tabular environment (the successor-table fast path)."""
    from symlearn.grounding import Domain

    return isinstance(world, Domain) or isinstance(getattr(world, "domain", None), Domain) or \
        hasattr(world, "next_state")


def _without_reproductions(nominal: Sequence[np.ndarray], experts: Sequence[np.ndarray]) -> list[np.ndarray]:
    """The nominal trajectories that are not, state for state, one of the expert trajectories."""
    shown = {t.tobytes() for t in experts}
    return [t for t in nominal if np.asarray(t, dtype=np.int64).tobytes() not in shown]


def _restrict(labeling: Labeling, formula: Formula) -> Labeling:
    """The labeling cut down to the propositions the formula uses (kept in discovery order)."""
    from symlearn.logic.ltlf.ast import propositions

    return labeling.restrict(propositions(formula))

