"""Write notebooks/05_constraint_inference.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# Learning constraints from demonstrations in a stochastic gridworld

An expert walks from the start `S` to the goal `G` and never enters the forbidden block `X`; the
shortest path runs straight through it. From the expert's demonstrations and the known reward we
learn the constraints three ways -- maximum-likelihood constraint inference (a set of forbidden
state-action pairs), MCE-ICRL (a cost per cell, causal entropy) and ME-ICRL (the same with
non-causal entropy) -- and check them by running the learned policies in the true environment.
Everything is exact: the gridworld exposes its model as a `TabularMDP`."""),
    new_code_cell("""import os
import warnings
import numpy as np

from symlearn.data import record
from symlearn.envs.gridworld import StochasticGridworld, make_gridworld, ACTIONS
from symlearn.learners.constraints.mce_icrl import MCEICRL, MEICRL
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.rl.tabular import sample_rollouts
from symlearn.errors import SymlearnError

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
ITERATIONS = 60 if QUICK else 300
EPISODES = 200 if QUICK else 1000
env = StochasticGridworld(0.0)
print(env.render_text())"""),
    new_markdown_cell("""## The MaxEnt machinery

`maxent_backward_pass` computes the goal-conditioned partition functions `Z_sa`, `Z_s` in log
space and the policy `Z_sa / Z_s`; `forward_pass` the expected visitation of a policy. Without
constraints the MaxEnt agent walks along the bottom row, straight through the block."""),
    new_code_cell("""from symlearn.rl.maxent import maxent_backward_pass, forward_pass

mdp = env.to_tabular()
nominal = maxent_backward_pass(mdp, [env.goal_state], horizon=30, reward=3 * mdp.rewards)
visits = forward_pass(mdp, nominal.policy, horizon=30).states
print(np.round(visits.reshape(env.shape), 2))"""),
    new_markdown_cell("""## Maximum-likelihood constraint inference (deterministic dynamics)

Demonstrations from a MaxEnt expert (it spreads over all near-optimal valid paths). Each
iteration forbids the unobserved state-action pair the nominal policy visits most. Like every
learner it takes its settings in the constructor and the data in `fit(demonstrations, mdp)`."""),
    new_code_cell("""pi = env.maxent_expert_policy()
rng = np.random.default_rng(0)
demos = record(env, lambda s: int(rng.choice(4, p=pi[s])), 30, seed=0)
ml = MLConstraintInference(horizon=30, rationality=3, min_visitation=1e-4).fit(demos, mdp)
print(len(ml.history_), "constraints added; stopped because", ml.stopped_because_)
for step in ml.history_[:5]:
    print(f"  {env.state_name(step.state)} {ACTIONS[step.action]:5s} visitation {step.visitation:.3f}")
truth = env.constraint_mask()
entries = truth & ~env.forbidden_states[:, None]   # moves into the block from outside it
print(f"moves into the block forbidden: {(ml.constraints_ & entries).sum()} of {entries.sum()}")
print(f"other pairs forbidden (never demonstrated, so the likelihood cannot tell): {(ml.constraints_ & ~truth).sum()}")
print("demonstrated pairs forbidden:", int((ml.constraints_ & ml.demonstrated_).sum()))"""),
    new_markdown_cell("""## MCE-ICRL versus ME-ICRL when the dynamics are stochastic

With stochasticity 0.3 a move is replaced by a random neighbouring cell 30% of the time. The
non-causal (trajectory) entropy model credits the agent with choosing its successor, so it
values a risky move by its lucky outcomes and keeps walking into the block however much cost
the block gets; causal entropy does not."""),
    new_code_cell("""noisy = StochasticGridworld(0.3)
noisy_mdp = noisy.to_tabular()
expert = noisy.expert_policy()
demos = record(noisy, lambda s: int(expert[s]), 50, seed=1)

def run(policy):
    r = sample_rollouts(noisy_mdp, policy, EPISODES, 200, np.random.default_rng(0))
    return round(float(r.returns().mean()), 1), round(float(r.fraction_in(noisy.forbidden_states).mean()), 3)

mce = MCEICRL(n_iterations=ITERATIONS).fit(demos, noisy_mdp)
me = MEICRL(n_iterations=ITERATIONS).fit(demos, noisy_mdp)
print("expert   (reward, violation rate):", run(np.eye(4)[expert]))
print("MCE-ICRL (reward, violation rate):", run(mce.policy_))
print("ME-ICRL  (reward, violation rate):", run(me.policy_))
print("MCE-ICRL learned cost per cell:")
print(np.round(mce.lambda_.reshape(noisy.shape), 1))"""),
    new_markdown_cell("""## From constraints to a safe agent

A shield built from a constraint set exposes `info["action_mask"]` and replaces forbidden
actions; the masked Q-learner never chooses one. The cost wrapper adds `info["cost"]`."""),
    new_code_cell("""from symlearn.backends import Shield, CostWrapper
from symlearn.rl.q_learning import q_learning

plain = q_learning(make_gridworld(0.0), 150, learning_rate=0.5, discount=0.95, seed=0)
safe = q_learning(Shield(make_gridworld(0.0), ml.constraints_), 150, learning_rate=0.5, discount=0.95, seed=0)
print("violating steps: plain", int(plain.violations.sum()), "- shielded", int(safe.violations.sum()))
costed = CostWrapper.from_array(make_gridworld(0.3), mce.cost_)
costed.reset(seed=0)
print("cost of moving right from the start:", costed.step(1)[4]["cost"])"""),
    new_markdown_cell("""## Bad input is reported, not crashed on"""),
    new_code_cell("""from symlearn.data import Demonstrations, Trajectory
try:
    MLConstraintInference().fit(Demonstrations([Trajectory([42, 35, 99], [0, 0])]), mdp)
except SymlearnError as error:
    print("error:", error)
try:
    bad = Demonstrations([Trajectory([42, 43, 44], [1, 1])])
    MLConstraintInference(known_constraints=truth).fit(bad, mdp)
except SymlearnError as error:
    print("error:", error)"""),
]

notebook = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(notebook, "notebooks/05_constraint_inference.ipynb")
