"""Write notebooks/01_demonstrations.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# Demonstrations: record, inspect, save, reload

Demonstrations are the input of every symlearn learner. This notebook records expert and random
episodes in FrozenLake, looks at their statistics and labels, saves them in both file formats and
shows what happens with a malformed file."""),
    new_code_cell("""import os
import numpy as np
import gymnasium as gym

from symlearn.data import Demonstrations, Trajectory, record, load
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import value_iteration
from symlearn.errors import SymlearnError

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
N_EPISODES = 20 if QUICK else 200"""),
    new_markdown_cell("""## An expert from the environment's own model

FrozenLake exposes its transition model, so we can read it as a `TabularMDP` and compute an
optimal policy exactly with value iteration."""),
    new_code_cell("""env = gym.make("FrozenLake-v1", map_name="4x4", is_slippery=True)
mdp = TabularMDP.from_gymnasium(env, action_names=["left", "down", "right", "up"])
solution = value_iteration(mdp, discount=0.99)
print(mdp.n_states, "states;", solution.iterations, "sweeps; start value", round(solution.values[0], 3))
print(np.array(mdp.action_names)[solution.policy].reshape(4, 4))"""),
    new_markdown_cell("""## Recording with labels

A *labeler* maps each state to the propositions true in it; the labels become the words that
LTLf formulas and automata read."""),
    new_code_cell("""tiles = "".join(row.decode() for row in env.unwrapped.desc.ravel())
labeler = lambda s: {"H": ["hole"], "G": ["goal"]}.get(tiles[s], [])

expert = record(env, lambda s: int(solution.policy[s]), N_EPISODES, seed=0, labeler=labeler)
random_demos = record(env, "random", N_EPISODES, seed=1, labeler=labeler)
for name, demos in [("expert", expert), ("random", random_demos)]:
    s = demos.summary()
    print(f"{name:7s} success {s['return']['mean']:.2f}  mean length {s['length']['mean']:.1f}  labels {s['label_counts']}")"""),
    new_code_cell("""first = expert[0]
print(first)
print("states :", first.states.tolist())
print("actions:", [mdp.action_names[a] for a in first.actions])
print("labels :", [sorted(l) for l in first.label_word()])"""),
    new_markdown_cell("""## Slicing, joining, converting"""),
    new_code_cell("""successful = expert[[t.total_reward() > 0 for t in expert]]
both = successful + random_demos[:3]
pairs = both.to_state_action_pairs()
print(len(successful), "successful expert episodes;", len(both), "after joining;", len(pairs), "state-action pairs")"""),
    new_markdown_cell("""## Saving and loading

JSONL is plain text (one trajectory per line after a header); NPZ stores arrays compactly and is
read without pickle. Both round-trip exactly and are written atomically."""),
    new_code_cell("""expert.save("expert.jsonl")
expert.save("expert.npz")
assert load("expert.jsonl") == expert and load("expert.npz") == expert
print(open("expert.jsonl").read()[:300])"""),
    new_markdown_cell("""## A malformed file

Errors name the file, line and column, and say how to fix the problem."""),
    new_code_cell("""lines = open("expert.jsonl").read().splitlines()
with open("broken.jsonl", "w") as f:
    f.write(lines[0] + "\\n" + '{"states": [0, 4], "actions": [1, 1, 2]}\\n')
try:
    load("broken.jsonl")
except SymlearnError as err:
    print(err)
    assert err.line == 2"""),
]
nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(nb, "notebooks/01_demonstrations.ipynb")
