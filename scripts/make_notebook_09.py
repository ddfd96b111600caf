"""Write notebooks/09_your_own_domain.ipynb (kept as a script so the notebook stays reviewable).

Cell sources are raw strings, so the code in them reads exactly as it runs in the notebook.
"""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell(r"""# Your own domain: from an empty folder to a shielded agent

The other notebooks use domains that come with symlearn. This one starts from nothing: we
describe a small world of our own in a folder of plain files, record an expert, learn the rules
the expert obeys, read and edit them, and finally use them to keep a learning agent out of
trouble.

**The world.** A cleaning robot in a kitchen of 4 x 3 floor tiles. It starts at its dock at
(0, 1) and has to vacuum the crumbs by the window at (3, 1). Two house rules apply, but nobody
writes them down for the robot:

* the strip between dock and window, tiles (1, 1) and (2, 1), has just been mopped: **do not
  drive onto the wet floor**;
* a baby naps next door, on and off: **do not vacuum while the baby is asleep**.

The shortest way to the crumbs crosses the wet strip, and vacuuming right away is quicker than
waiting, so a robot that only chases reward would break both rules. We will see whether the
rules can be recovered from an expert's behaviour alone."""),
    new_code_cell(r"""import json
import os
import tempfile
from pathlib import Path

import numpy as np

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"  # the test suite asks for small settings
workspace = tempfile.TemporaryDirectory(prefix="symlearn-kitchen-")
work = Path(workspace.name)
folder = work / "kitchen"  # the domain folder we are about to write
folder.mkdir()
print("working in", work)"""),
    new_markdown_cell(r"""## 1. States and actions

A domain is *finite*: we list every state and every action and give each an id.

* A state is the robot's tile plus whether the baby is asleep (12 tiles x 2 = 24 states), and
  one extra state `clean` that ends the episode once the crumbs are gone: 25 states.
* The actions are four moves, `wait` and `vacuum`. Their names are written as ASP atoms
  (`move(east)`), because that is how the rules will talk about them."""),
    new_code_cell(r"""WIDTH, HEIGHT = 4, 3
WET = {(1, 1), (2, 1)}
DOCK, CRUMBS = (0, 1), (3, 1)
ASLEEP_PROB = 0.3  # at every step the baby is asleep with this probability
MOVES = {"north": (0, 1), "south": (0, -1), "east": (1, 0), "west": (-1, 0)}
ACTIONS = [f"move({d})" for d in MOVES] + ["wait", "vacuum"]

TILES = [(x, y) for y in range(HEIGHT) for x in range(WIDTH)]
STATES = [(tile, asleep) for tile in TILES for asleep in (False, True)] + ["clean"]
STATE_ID = {s: i for i, s in enumerate(STATES)}


def describe(s):
    # a readable name for state id s (the domain itself only knows ids and facts)
    if STATES[s] == "clean":
        return "clean"
    tile, asleep = STATES[s]
    return f"{tile}{' baby asleep' if asleep else ''}"


print(len(STATES), "states,", len(ACTIONS), "actions:", ACTIONS)"""),
    new_markdown_cell(r"""## 2. The nominal model: what *can* happen

`model.npz` holds numpy arrays: `transitions[s, a, s']` (probabilities), `initial[s]`,
`terminal[s]` and, optionally, `rewards[s, a]` and `available[s, a]`. The model describes what
the robot is *able* to do, not what it *should* do: driving onto the wet floor and vacuuming
next to the sleeping baby are perfectly possible here. Finding out what is forbidden is the
learner's job.

Every step costs 1, vacuuming the crumbs earns 10 and ends the episode, vacuuming anywhere else
achieves nothing. Driving into a wall leaves the robot where it is (a move that exists, so we
need no `available` array). Whatever the robot does, the baby is asleep at the next step with
probability 0.3."""),
    new_code_cell(r"""n_states, n_actions = len(STATES), len(ACTIONS)
P = np.zeros((n_states, n_actions, n_states))
R = np.full((n_states, n_actions), -1.0)
clean = STATE_ID["clean"]
P[clean, :, clean] = 1.0  # the terminal state loops on itself, worth nothing
R[clean] = 0.0
for (x, y), asleep in STATES[:-1]:
    s = STATE_ID[((x, y), asleep)]
    for a, action in enumerate(ACTIONS):
        tile = (x, y)
        if action.startswith("move("):
            dx, dy = MOVES[action[5:-1]]
            if 0 <= x + dx < WIDTH and 0 <= y + dy < HEIGHT:
                tile = (x + dx, y + dy)  # into a wall: stay
        elif action == "vacuum" and tile == CRUMBS:
            P[s, a, clean] = 1.0
            R[s, a] = 10.0
            continue
        P[s, a, STATE_ID[(tile, False)]] += 1 - ASLEEP_PROB
        P[s, a, STATE_ID[(tile, True)]] += ASLEEP_PROB

initial = np.zeros(n_states)
initial[STATE_ID[(DOCK, False)]] = 1.0
terminal = np.zeros(n_states, dtype=bool)
terminal[clean] = True
np.savez(folder / "model.npz", transitions=P, initial=initial, terminal=terminal, rewards=R)
print("every row of P sums to 1:", np.allclose(P.sum(axis=2), 1.0))"""),
    new_markdown_cell(r"""## 3. Facts, background knowledge, bias

The learner reasons in answer set programming (ASP), so each state and action also needs a
symbolic description:

* `states.jsonl`: the ASP **facts** true in each state, e.g. `at(0,1). asleep.`;
* `actions.jsonl`: the ASP **atom** of each action, e.g. `move(east)`;
* `bk.lp`: **background knowledge**, a clingo program that derives useful concepts from those
  facts: here `wetAhead(D)` (the tile in direction `D` is wet) and `onCrumbs`. Together with one
  state's facts and one action atom it must have exactly one answer set;
* `bias.las`: the **mode bias**, the vocabulary rules may use (`#modeb` lines: which atoms may
  appear in a rule body; `#maxv`: at most one variable). Including an atom does not make it
  part of a rule; `onCrumbs` and `wait` are offered but should not be needed;
* `truth.lp` (optional): the real rules. The learner never reads them; they are only used to
  *score* what it learns. Without a truth file, everything below works except the scores;
* `domain.toml`: names the files."""),
    new_code_cell(r"""def state_facts(state):
    if state == "clean":
        return "clean."
    (x, y), asleep = state
    return f"at({x},{y})." + (" asleep." if asleep else "")


(folder / "states.jsonl").write_text(
    "".join(json.dumps({"id": i, "facts": state_facts(s)}) + "\n" for i, s in enumerate(STATES)))
(folder / "actions.jsonl").write_text(
    "".join(json.dumps({"id": a, "atom": atom}) + "\n" for a, atom in enumerate(ACTIONS)))

(folder / "bk.lp").write_text('''\
% the kitchen floor: a freshly mopped strip, crumbs by the window
dir(north; south; east; west).
delta(north, 0, 1). delta(south, 0, -1). delta(east, 1, 0). delta(west, -1, 0).
wet(1, 1). wet(2, 1).
crumbs(3, 1).
wetAhead(D) :- at(X, Y), delta(D, DX, DY), wet(X + DX, Y + DY).
onCrumbs :- at(X, Y), crumbs(X, Y).
''')
(folder / "bias.las").write_text('''\
#modeb(1, asleep, (positive)).
#modeb(1, onCrumbs, (positive)).
#modeb(1, move(var(dir)), (positive)).
#modeb(1, wetAhead(var(dir)), (positive)).
#modeb(1, wait, (positive)).
#modeb(1, vacuum, (positive)).
#maxv(1).
''')
(folder / "truth.lp").write_text('''\
% the house rules (used only to score the learned rules)
:- move(D), wetAhead(D).
:- vacuum, asleep.
''')
(folder / "domain.toml").write_text('''\
name = "kitchen"
description = "a cleaning robot: keep off the wet floor, let the baby sleep"
background = "bk.lp"
bias = "bias.las"
model = "model.npz"
states = "states.jsonl"
actions = "actions.jsonl"
truth = "truth.lp"
''')
for path in sorted(folder.iterdir()):
    print(f"{path.name:14s} {path.stat().st_size:6d} bytes")
print()
print((folder / "states.jsonl").read_text().splitlines()[9])"""),
    new_markdown_cell(r"""## 4. Load and check

`Domain.from_folder` reads everything and checks it: array shapes against the state and action
lists, every transition row a distribution, every state's facts with every action giving
exactly one answer set of the background. A mistake is reported in one line that names the
file, here a copy of the folder with an action missing."""),
    new_code_cell(r"""import shutil

from symlearn.errors import SymlearnError
from symlearn.grounding import Domain

domain = Domain.from_folder(folder)
print(domain)
print("the truth forbids", int(domain.truth_forbidden.sum()), "state-action pairs")

broken = Path(shutil.copytree(folder, work / "broken"))
lines = (broken / "actions.jsonl").read_text().splitlines()
(broken / "actions.jsonl").write_text("\n".join(lines[:-1]) + "\n")
try:
    Domain.from_folder(broken)
except SymlearnError as error:
    print("error:", error)"""),
    new_markdown_cell(r"""## 5. Record an expert

In real life the demonstrations would come from people or logs. Here we simulate a careful
robot: value iteration on the nominal model with the forbidden pairs of `truth.lp` removed,
choosing at random among equally good actions (so the demonstrations are varied). It goes
around the wet strip and, if the baby is asleep when it reaches the crumbs, waits.

Each demonstration is a `Trajectory` of state ids and actions (here named by their atoms; ids
work too); `Demonstrations.save` writes the JSONL file the CLI reads."""),
    new_code_cell(r"""from symlearn.data import Demonstrations, Trajectory, load
from symlearn.rl.tabular import value_iteration

expert = value_iteration(domain.mdp, discount=0.95, allowed=~domain.truth_forbidden)
rng = np.random.default_rng(0)
recorded = []
for _ in range(30 if QUICK else 60):
    s = domain.mdp.sample_initial(rng)
    states, actions = [s], []
    while not domain.mdp.terminal[s] and len(actions) < 50:
        q = expert.q_values[s]
        a = int(rng.choice(np.flatnonzero(q >= q.max() - 1e-9)))
        s = domain.mdp.sample_next(s, a, rng)
        states.append(s)
        actions.append(ACTIONS[a])
    recorded.append(Trajectory(states=states, actions=actions))

demos_path = work / "demos.jsonl"
Demonstrations(recorded).save(demos_path)
demos = load(demos_path)
print(len(demos), "demonstrations, mean length", np.mean([len(t.actions) for t in demos]))
print("first:", " -> ".join(f"{describe(s)} [{a}]" for s, a in zip(demos[0].states, demos[0].actions)))"""),
    new_markdown_cell(r"""## 6. Learn the rules

Logic constraint inference repeats two steps. **Inference:** a planner that knows the model and
the reward but no rules predicts what a reward-seeking robot would do; the state-action pair it
would use most but the expert never used is probably forbidden. **Induction:** our ILP learner
looks for the shortest ASP rules, built from the bias, that forbid every pair inferred so far
and allow every demonstrated one. The rules then forbid *all* pairs that share the reason, not
just the ones inferred.

Settings: `reward="given"` plans with the rewards of `model.npz` (the default, `"sparse"`, only
rewards reaching where demonstrations ended); `rationality=3.0` tells the planner that the
expert is nearly optimal for that reward. With the default `rationality=1.0` the planner spreads
its choices so widely that, in this kitchen, vacuuming next to the sleeping baby never stands
out and only the wet-floor rule is found."""),
    new_code_cell(r"""from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference

learner = LogicConstraintInference(iterations=20, reward="given", rationality=3.0).fit(demos, domain)


def readable(pair):
    # history entries name a pair as "state / action", and our domain's state names are ids
    state, action = pair.split(" / ")
    return f"{describe(int(state))} / {action}"


for step in learner.history_[:5]:
    print(f"iteration {step.iteration}: inferred {readable(step.inferred):32s} -> {len(step.rules)} rule(s), "
          f"{step.n_constraints} forbidden pairs")
print("...")
print()
print("\n".join(learner.rules_))
print(learner.score())"""),
    new_markdown_cell(r"""The same from the command line (what you would type in a shell; here it runs through
`python -m symlearn` so that it uses this notebook's environment). `--json` prints a machine
readable report, `-o` writes the rules."""),
    new_code_cell(r"""import shlex
import subprocess
import sys

arguments = ["learn", "constraints", "--domain", str(folder), "--demos", str(demos_path),
             "--method", "logic", "--reward", "given", "--rationality", "3", "-o", str(work / "cli_rules.lp"),
             "--json"]
print("$", shlex.join(["symlearn", *arguments]))
run = subprocess.run([sys.executable, "-m", "symlearn", *arguments], capture_output=True, text=True, check=True)
report = json.loads(run.stdout)
print(report["rules"], {key: report[key] for key in ("fpr", "fnr", "accuracy", "constraints")})
print("same rules as the API:", sorted(report["rules"]) == sorted(learner.rules_))"""),
    new_markdown_cell(r"""## 7. Read the rules

A rule `:- A, B.` says "never A and B together". So

* `:- move(V1), wetAhead(V1).`: never move in a direction in which the next tile is wet;
* `:- asleep, vacuum.`: never vacuum while the baby is asleep.

`domain.rule_mask(rules)` turns rules into the `(state, action)` pairs they forbid, which is
what an agent needs. `fpr` (allowed pairs wrongly forbidden) and `fnr` (forbidden pairs
wrongly allowed) compare them with `truth.lp`."""),
    new_code_cell(r"""for rule in learner.rules_:
    forbidden = domain.rule_mask([rule])
    examples = [f"{describe(s)} / {ACTIONS[a]}" for s, a in np.argwhere(forbidden)[:3]]
    print(f"{rule:28s} forbids {int(forbidden.sum()):2d} pairs, e.g. {'; '.join(examples)}")"""),
    new_markdown_cell(r"""## 8. Edit and re-check

The rules are a plain `.lp` file: review it, change it, keep it under version control. After
an edit, check the file again, against the truth when you have one and always against the
data: a rule that forbids something the expert did contradicts the demonstrations. (The file's
header suggests `symlearn ilp check`, which checks ILP task files; for a domain, the check is the
few lines below.)

Two edits to try: *dropping* the wet-floor rule (the check against the truth shows the
forbidden pairs it lets through again), and *changing* the sleep rule into the stricter
`:- vacuum.` (the demonstrations disagree: every one of them ends by vacuuming)."""),
    new_code_cell(r"""from symlearn.learners.constraints.constraint_metrics import constraint_metrics

rules_path = learner.to_lp(work / "kitchen_rules.lp")
print(rules_path.read_text())
episodes = domain.episodes(demos)  # the demonstrations as id arrays, actions mapped from atoms


def recheck(path):
    forbidden = domain.rule_mask(Path(path))
    scores = constraint_metrics(forbidden, domain.truth_forbidden, ~domain.unavailable)
    clashes = sum(int(forbidden[e.states[:len(e.actions)], e.actions].sum()) for e in episodes)
    return f"fpr {scores['fpr']:.2f}  fnr {scores['fnr']:.2f}  demonstrated steps it forbids: {clashes}"


text = rules_path.read_text()
dropped = work / "dropped.lp"
dropped.write_text(text.replace(":- move(V1), wetAhead(V1).", ""))
changed = work / "changed.lp"
changed.write_text(text.replace(":- asleep, vacuum.", ":- vacuum."))
for path in (rules_path, dropped, changed):
    print(f"{path.name:18s} {recheck(path)}")"""),
    new_markdown_cell(r"""## 9. Shield a learning agent

`TabularEnv` turns the domain's model into a gymnasium environment (observation = state id,
action = action id). We give it the truth only so that it can *count* broken rules
(`info["violation"]`); the agents never see it and the reward does not punish rule breaking.

A `Shield` wraps the environment with the forbidden pairs of our rule file: it reports the
allowed actions in `info["action_mask"]`, which tabular Q-learning respects while exploring and
while acting. The unshielded agent learns that crossing the wet floor and vacuuming straight
away pays off; the shielded one cannot even try."""),
    new_code_cell(r"""from symlearn.backends.shield import Shield
from symlearn.envs.tabular_env import TabularEnv
from symlearn.rl.q_learning import q_learning

episodes_rl = 200 if QUICK else 600
plain = q_learning(TabularEnv(domain, max_steps=50, violations=domain.truth_forbidden), episodes_rl, seed=0)
shield = Shield(TabularEnv(domain, max_steps=50, violations=domain.truth_forbidden),
                domain.rule_mask(rules_path), seed=0)
shielded = q_learning(shield, episodes_rl, seed=0)
for name, result in (("unshielded", plain), ("shielded", shielded)):
    print(f"{name:10s}: {int(result.violations.sum()):4d} broken rules while learning, "
          f"mean return of the last 50 episodes {result.returns[-50:].mean():.1f}")"""),
    new_markdown_cell(r"""The unshielded agent earns a little more by cutting corners; the shielded one takes the way
around and waits for the baby, and never breaks a rule, not even during its first random
steps."""),
    new_code_cell(r"""try:
    import matplotlib.pyplot as plt
except ImportError:  # matplotlib is not a dependency of symlearn: say so and print the numbers
    plt = None

curves = {"unshielded": np.cumsum(plain.violations), "shielded": np.cumsum(shielded.violations)}
if plt is None:
    print("(pip install matplotlib for the plot) cumulative broken rules every 50 episodes:")
    for name, curve in curves.items():
        print(f"  {name:10s}", curve[49::50].astype(int).tolist())
else:
    fig, ax = plt.subplots(figsize=(6, 3))
    for name, curve in curves.items():
        ax.plot(np.arange(1, len(curve) + 1), curve, label=name)
    ax.set_xlabel("episode")
    ax.set_ylabel("broken rules so far")
    ax.set_title("Q-learning in the kitchen")
    ax.legend()
    plt.show()"""),
    new_markdown_cell(r"""## Where next

* Your own world: copy the cells of sections 1 to 3 and change the model, facts, background and
  bias. `docs/FORMATS.md` and the docstring of `symlearn/grounding/domain_folder.py` describe
  the folder.
* Other learners read the same folder: `symlearn learn constraints --method ml` (a set of
  forbidden pairs, no rules) or `--method mce-icrl` (a cost per pair).
* The folder was temporary; the next cell deletes it."""),
    new_code_cell(r"""workspace.cleanup()"""),
]

notebook = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(notebook, "notebooks/09_your_own_domain.ipynb")
