"""Write notebooks/08_logic_constraints.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# Rules from demonstrations: logic constraint inference and a shielded agent

A car drives through a junction with priority to the right and one-way roads. Nobody tells us
the traffic rules; we only see rule-abiding drives. Logic constraint inference alternates two
steps: **inference** (the state-action pair a rule-free MaxEnt planner would use most but no
driver ever did is probably forbidden) and **induction** (ASP rules that explain every
forbidden pair so far and allow every demonstrated one, learned with our clingo-based ILP
learner from the background knowledge in `background_kb/traffic/`). The rules then shield a
Q-learning agent so that it never breaks them, not even while exploring."""),
    new_code_cell("""import os
import numpy as np

from symlearn.envs.logic_mdp import logic_mdp
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
from symlearn.learners.constraints.constraint_metrics import constraint_metrics

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
lm = logic_mdp("junction-priority")
demos = lm.expert_demonstrations(50 if QUICK else 100, seed=0)
print(lm.mdp.n_states, "states x", lm.mdp.n_actions, "actions;", len(demos), "demonstrations")
print("first drive:", [lm.mdp.state_names[s] for s in demos[0].states])"""),
    new_markdown_cell("""## Learn

The learner takes its settings in the constructor and the data in `fit(demonstrations, domain)`;
`lm.domain` is the junction as a `symlearn.grounding.Domain` (nominal model, ASP facts of every
pair, background, bias, truth), and its moves that do not exist are known constraints. Each
iteration prints what inference chose and how many rules induction found."""),
    new_code_cell("""learner = LogicConstraintInference(iterations=15).fit(demos, lm.domain)
for step in learner.history_:
    print(f"{step.iteration:2d}  inferred {step.inferred:28s} -> {len(step.rules)} rules, "
          f"{step.n_constraints:3d} forbidden pairs  ({step.inference_seconds:.2f} s + {step.induction_seconds:.2f} s)")
print()
print("\\n".join(learner.rules_))
print(learner.score())"""),
    new_markdown_cell("""## Read, edit, re-check

The rules are an ordinary `.lp` file. Suppose we doubt the priority rule and delete it: the
edited file is re-loaded and scored against the ground truth again."""),
    new_code_cell("""from pathlib import Path
from symlearn.logic.asp import Hypothesis

path = Path("priority_rules.lp")
learner.to_lp(path)
print(path.read_text())
edited = [r for r in Hypothesis.from_lp(path).rules if "carOnTheRight" not in r]
path.write_text("\\n".join(edited) + "\\n")
reloaded = Hypothesis.from_lp(path).rules
print("edited:", constraint_metrics(lm.rule_mask(reloaded), lm.truth_forbidden, ~lm.unavailable))"""),
    new_markdown_cell("""## Shield a learning agent

Q-learning with epsilon 0.05, learning rate 0.9, discount 0.75; the cost is the L1 distance to
the goal plus 10 for every broken rule. The shield masks the actions the learned rules forbid
(`info["action_mask"]`), so the shielded agent never breaks a learned rule."""),
    new_code_cell("""from symlearn.backends.masks import env_mask
from symlearn.backends.shield import Shield
from symlearn.envs.junction_env import JunctionEnv
from symlearn.rl.q_learning import q_learning

# The learned rules forbid pairs of the domain's model; env_mask closes that set and keeps the
# pairs of the states the environment observes (checked by name: the same ids, the same order).
env = JunctionEnv("priority")
mask = env_mask(lm.mdp, learner.rule_constraints_, env.state_names, unavailable=lm.unavailable)
episodes = 150 if QUICK else 500
plain = q_learning(JunctionEnv("priority"), episodes, seed=0)
shielded = q_learning(Shield(env, mask, seed=0), episodes, seed=0)
print("rule violations while training: plain", int(plain.violations.sum()), " shielded", int(shielded.violations.sum()))
print("mean cost of the last 20 episodes: plain", -plain.returns[-20:].mean(), " shielded", -shielded.returns[-20:].mean())"""),
    new_markdown_cell("""## Transfer

The rules speak of roads, lights and cars, not of cells, so they carry over to a larger 7 x 7
junction with a traffic light as well (the same background knowledge, sized to the new grid).
Rules from the priority junction cover its one-way and priority rules but know nothing of red
lights."""),
    new_code_cell("""combined = logic_mdp("junction-combined")
transferred = combined.rule_mask(learner.rules_)
print(constraint_metrics(transferred, combined.truth_forbidden, ~combined.unavailable))"""),
    new_markdown_cell("""## Bad input is reported, not crashed on"""),
    new_code_cell("""from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import SymlearnError

try:
    LogicConstraintInference().fit(Demonstrations([Trajectory(states=[0, 999], actions=[0])]), lm.domain)
except SymlearnError as error:
    print("error:", error)"""),
]

notebook = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(notebook, "notebooks/08_logic_constraints.ipynb")
