"""Write ILASP-style learning tasks for the bundled logic domains, labelled by the ground truth.

A task file holds, in this order: a comment header, the domain's background knowledge (inlined,
so the file is self-contained), its mode bias, and one example per state-action pair::

    #pos(p1, {}, {}, { at(0,0,0). at(1,0,1). at(2,0,2). move(2,1). }).
    #neg(n1, {}, {}, { at(0,0,0). at(1,0,1). at(2,1,0). move(1,1). }).

The context of an example is the pair's facts (state, then action); positives are pairs the
ground truth allows, negatives pairs it forbids. Two ways to choose the pairs:

* :func:`exhaustive_examples` -- every pair of the domain, so any hypothesis that covers all
  examples classifies the whole domain exactly like the ground truth;
* :func:`sampled_examples` -- a seeded uniform sample of allowed and of forbidden pairs;
* :func:`demonstration_examples` -- like learning from demonstrations: positives are the
  distinct pairs of rule-abiding expert episodes, negatives the forbidden actions in states the
  expert visited (the violations an observer can point at), optionally capped.

Both are deterministic for a given seed.

>>> from symlearn.envs.logic_domains import logic_domain
>>> domain = logic_domain("junction-lights")
>>> examples = exhaustive_examples(domain)
>>> len(examples), sum(e.positive for e in examples)
(250, 54)
>>> examples[0].to_text()
'#neg(n1, {}, {}, { at(1,1). tls0. go(zero). }).'
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from symlearn.atomic import write_text
from symlearn.envs.logic_domains import DOMAIN_NAMES, LogicDomain, logic_domain
from symlearn.errors import DataError
from symlearn.logic.ilp.task import Example


def number_examples(labelled: Iterable[tuple[tuple[str, ...], bool]], penalty: int | None = None) -> list[Example]:
    """Examples `p1, p2, ...` and `n1, n2, ...` from (facts, positive) pairs, in order."""
    counts = {True: 0, False: 0}
    examples = []
    for facts, positive in labelled:
        counts[positive] += 1
        prefix = "p" if positive else "n"
        examples.append(Example.from_facts(f"{prefix}{counts[positive]}", positive, tuple(facts), penalty))
    return examples


def exhaustive_examples(domain: LogicDomain) -> list[Example]:
    """Every state-action pair of the domain, labelled by the ground truth, in model order."""
    return number_examples(domain.pairs())


def sampled_examples(domain: LogicDomain, n_positive: int, n_negative: int, seed: int = 0) -> list[Example]:
    """A seeded uniform sample (without replacement) of allowed and of forbidden pairs.

    Raises :class:`DataError` when the domain has fewer pairs of a kind than requested.
    """
    rng = np.random.default_rng(seed)
    chosen = []
    for positive, wanted in ((True, n_positive), (False, n_negative)):
        pool = [facts for facts, ok in domain.pairs() if ok == positive]
        kind = "allowed" if positive else "forbidden"
        if not 0 <= wanted <= len(pool):
            raise DataError(f"asked for {wanted} {kind} pairs, {domain.name} has {len(pool)}")
        chosen.extend((pool[i], positive) for i in sorted(rng.choice(len(pool), size=wanted, replace=False)))
    return number_examples(chosen)


def demonstration_examples(domain: LogicDomain, n_episodes: int = 20, seed: int = 0,
                           max_negatives: int | None = None, penalty: int | None = None) -> list[Example]:
    """Positives from expert episodes, negatives from forbidden actions in the visited states.

    ``max_negatives`` keeps a seeded random subset of the negatives (all of them by default);
    ``penalty`` (for noisy learning) is attached to every example when given.
    """
    if n_episodes < 1:
        raise DataError(f"n_episodes must be at least 1, got {n_episodes}")
    rng = np.random.default_rng(seed)
    demonstrated = list(dict.fromkeys(domain.expert_pairs(n_episodes, rng)))
    positives = [domain.facts(s, a) for s, a in demonstrated]
    visited = list(dict.fromkeys(s for s, _ in demonstrated))
    negatives = []
    for state in visited:
        for action in domain.model.available_actions(state):
            if not domain.is_allowed(state, action):
                negatives.append(domain.facts(state, action))
    if max_negatives is not None and len(negatives) > max_negatives:
        chosen = sorted(rng.choice(len(negatives), size=max_negatives, replace=False))
        negatives = [negatives[i] for i in chosen]
    return number_examples([(f, True) for f in positives] + [(f, False) for f in negatives], penalty)


def with_label_noise(examples: Sequence[Example], fraction: float, penalty: int, seed: int = 0) -> list[Example]:
    """A copy with a seeded ``fraction`` of the labels flipped and ``penalty`` on every example.

    For noisy learning (``learn(task, noise=True)``): a flipped example is data noise the
    learner may leave uncovered at the cost of its penalty. Ids are kept, so the file still says
    which examples were flipped only by comparison with the noise-free one.
    """
    if not 0.0 <= fraction <= 1.0:
        raise DataError(f"the noise fraction must be in [0, 1], got {fraction}")
    if penalty < 1:
        raise DataError(f"the penalty must be a positive integer, got {penalty}")
    rng = np.random.default_rng(seed)
    flipped = set(rng.choice(len(examples), size=round(fraction * len(examples)), replace=False).tolist())
    return [replace(e, positive=e.positive != (i in flipped), penalty=penalty) for i, e in enumerate(examples)]


def task_text(domain: LogicDomain, examples: Sequence[Example], title: str | None = None) -> str:
    """The complete task file: header, background, bias, examples."""
    if not examples:
        raise DataError("a learning task needs at least one example")
    n_pos = sum(e.positive for e in examples)
    header = [
        f"% {title or domain.description}",
        f"% domain {domain.name}: {n_pos} positive and {len(examples) - n_pos} negative examples,",
        "% labelled by the ground truth " + f"background_kb/{domain.folder}/{domain.truth_file}.",
        "% Generated by symlearn.envs.ilp_tasks (python benchmarks/make_ilp_tasks.py); do not edit.",
    ]
    sections = [
        "\n".join(header),
        f"% ---- background knowledge (background_kb/{domain.folder}/{domain.bk_file})\n"
        + domain.background().strip(),
        f"% ---- language bias (background_kb/{domain.folder}/{domain.bias_file})\n" + domain.bias().strip(),
        "% ---- examples\n" + "\n".join(e.to_text() for e in examples),
    ]
    return "\n\n".join(sections) + "\n"


def write_task(path: str | os.PathLike[str], domain: LogicDomain, examples: Sequence[Example],
               title: str | None = None) -> Path:
    return write_text(path, task_text(domain, examples, title))


#: The default tasks bundled under ``background_kb/<folder>/tasks/``: file name -> recipe.
DEFAULT_TASKS: dict[str, tuple[str, str]] = {
    "hanoi/tasks/hanoi.las": ("hanoi", "exhaustive"),
    "hanoi/tasks/hanoi_demos.las": ("hanoi", "demonstrations"),
    "traffic/tasks/lights.las": ("junction-lights", "exhaustive"),
    "traffic/tasks/lights_demos.las": ("junction-lights", "demonstrations"),
    "traffic/tasks/priority.las": ("junction-priority", "exhaustive"),
    "traffic/tasks/priority_demos.las": ("junction-priority", "demonstrations"),
}

#: Settings of the demonstration tasks (episodes, seed).
DEMONSTRATION_SETTINGS = {"n_episodes": 20, "seed": 0}


def default_task_text(relative_path: str) -> str:
    """The text of one of :data:`DEFAULT_TASKS`."""
    name, recipe = DEFAULT_TASKS[relative_path]
    domain = logic_domain(name)
    if recipe == "exhaustive":
        return task_text(domain, exhaustive_examples(domain),
                         f"{domain.description}; every state-action pair is an example")
    examples = demonstration_examples(domain, **DEMONSTRATION_SETTINGS)
    settings = ", ".join(f"{k}={v}" for k, v in DEMONSTRATION_SETTINGS.items())
    return task_text(domain, examples, f"{domain.description}; examples from expert demonstrations ({settings})")


def write_default_tasks(root: str | os.PathLike[str]) -> list[Path]:
    """Write every default task below ``root`` (the ``background_kb`` folder)."""
    return [write_text(Path(root) / rel, default_task_text(rel)) for rel in DEFAULT_TASKS]


__all__ = ["DEFAULT_TASKS", "DOMAIN_NAMES", "Example", "default_task_text", "number_examples", "demonstration_examples",
           "exhaustive_examples", "sampled_examples", "task_text", "with_label_noise", "write_default_tasks",
           "write_task"]
