"""Demonstrations as words of sub-goal symbols (thesis, Algorithm 6.1).

Scanning a demonstration frame by frame, a frame appends the *first* sub-goal (in the order of
the sub-goal set) that it reaches and that is not yet in the word -- at most one symbol per
frame, as the algorithm's ``break`` says. Words are therefore repetition-free.

Rather than testing every sub-goal in every frame in Python, the frames where each sub-goal is
reached are computed at once (vectorised), and the scan jumps from event to event: the next
symbol is the sub-goal with the earliest reaching frame at or after the current one (ties to the
earlier sub-goal), and the scan resumes one frame later. That is the same word, in
``O(T * G)`` numpy work plus ``O(G^2 log T)`` Python steps per demonstration.

>>> import numpy as np
>>> from symlearn.grounding.subgoals import SubGoal, SubGoalSet
>>> goals = SubGoalSet([SubGoal("a", "x", (0,), (1.0,), 0.1), SubGoal("b", "x", (0,), (2.0,), 0.1)])
>>> demonstration_word(goals, np.array([[0.0], [2.0], [1.0], [2.0], [np.nan]]))
('b', 'a')
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from symlearn.grounding.subgoals import SubGoalSet


def word_from_reached(reached: np.ndarray) -> list[int]:
    """Algorithm 6.1 on a ``(T, G)`` boolean matrix: sub-goal indices in the order they are added."""
    hits = [np.flatnonzero(reached[:, g]) for g in range(reached.shape[1])]
    remaining = [g for g in range(len(hits)) if len(hits[g])]
    word: list[int] = []
    t = 0
    while remaining:
        best, best_frame = -1, None
        for g in remaining:  # ascending order: ties go to the earlier sub-goal
            i = np.searchsorted(hits[g], t)
            if i < len(hits[g]) and (best_frame is None or hits[g][i] < best_frame):
                best, best_frame = g, int(hits[g][i])
        if best < 0:
            break
        word.append(best)
        remaining.remove(best)
        t = best_frame + 1
    return word


def demonstration_word(subgoals: SubGoalSet, frames: np.ndarray) -> tuple[str, ...]:
    """The word of one demonstration (``(T, k)`` frames, NaN = unobserved)."""
    names = subgoals.propositions
    return tuple(names[g] for g in word_from_reached(subgoals.reached_matrix(frames)))


def demonstration_words(subgoals: SubGoalSet, frames: Sequence[np.ndarray]) -> list[tuple[str, ...]]:
    """The word of each demonstration."""
    return [demonstration_word(subgoals, f) for f in frames]
