"""Reacher-v5 as a sub-goal task: four sub-goals from >= 10 demonstrations, the plan executed by the
IK + PD controller in >= 95 % of 20 episodes (skipped without the mujoco extra)."""

import numpy as np
import pytest

from symlearn.backends.subgoal_plan import execute
from symlearn.errors import DataError
from symlearn.optional import available

pytestmark = pytest.mark.skipif(not available("mujoco"), reason="needs the mujoco extra")


def test_inverse_kinematics_is_exact_on_both_branches():
    from symlearn.envs.reacher_subgoals import inverse_kinematics

    lengths = (0.1, 0.11)
    for point in [(0.12, 0.0), (0.0, -0.12), (-0.05, 0.15)]:
        for elbow in (1.0, -1.0):
            q1, q2 = inverse_kinematics(point, lengths, elbow)
            tip = (0.1 * np.cos(q1) + 0.11 * np.cos(q1 + q2), 0.1 * np.sin(q1) + 0.11 * np.sin(q1 + q2))
            assert np.allclose(tip, point, atol=1e-12)
    with pytest.raises(DataError, match="out of the arm's reach"):
        inverse_kinematics((0.3, 0.0), lengths)


def test_subgoals_orderings_and_execution():
    from symlearn.envs.reacher_subgoals import ReacherDemonstrator, make_reacher, reach, truth_pdfa, truth_subgoals
    from symlearn.learners.subgoals import SubgoalPDFALearner
    from symlearn.learners.subgoals.scoring import renamed

    runs, orders = ReacherDemonstrator(seed=0).demonstrations(12)
    assert len(set(orders)) == 2  # both directions shown
    learner = SubgoalPDFALearner().fit(runs, ["x", "y"])
    mapping = learner.subgoals_.match(truth_subgoals(), 0.02)
    assert len(learner.subgoals_) == len(mapping) == 4
    assert renamed(learner.pdfa_, mapping).equivalent(truth_pdfa().dfa)[0]
    assert [mapping[s] for s in learner.plan_] == ["px", "py", "nx", "ny"]  # counter-clockwise preferred
    successes = 0
    for episode in range(20):
        env = make_reacher(episode)
        report = execute(learner.pdfa_, lambda name: reach(env, learner.subgoals_[name].centre, hold=3)[0])
        successes += report.success and len(report.achieved) == 4
    assert successes >= 19
