"""Write notebooks/11_guide_tasks.ipynb and execute it, so it is saved with its outputs.

    .venv/bin/python scripts/make_notebook_11.py            # full settings
    SYMLEARN_QUICK=1 .venv/bin/python scripts/make_notebook_11.py   # the test suite's small ones

Sections 4 and 5 of docs/GUIDE.md in Python: sub-goal automata and reward machines from the
guide robot's tours (docs/guide/guide_robot.py, GuideTour-v0).
"""

import sys
from pathlib import Path

from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

sys.path.insert(0, str(Path(__file__).resolve().parent))
from notebook_execution import execute_and_write, guide_setup_cell  # noqa: E402

cells = [
    new_markdown_cell(r"""# Tasks on your own robot: sub-goal automata and reward machines

The Python side of sections 4 and 5 of [docs/GUIDE.md](../docs/GUIDE.md). The guide's robot
(`docs/guide/guide_robot.py`, `GuideTour-v0`) has two stations to visit, the charger (top left)
and the dock (top right), in either order. From its positions we learn the sub-goals and the
order the demonstrator prefers; from camera pictures alone, a reward machine that trains an
agent."""),
    guide_setup_cell('from IPython.display import SVG, display', '', 'EPISODES = 20 if QUICK else 40'),
    new_markdown_cell(r"""## Record

The demonstrator waits at the start, visits both stations (the charger first in about 80 % of
the tours), pausing at each, and parks at the last."""),
    new_code_cell(r"""from symlearn.data import record

env = gym.make("GuideTour-v0")
tours = record(env, guide_robot.tour_expert(env, prefer_charger=0.8), EPISODES, seed=0)
fig, ax = plt.subplots(figsize=(3.4, 3.2))
for t in tours:
    xy = np.asarray(t.states)
    ax.plot(xy[:, 0], xy[:, 1], lw=0.6, alpha=0.6)
for name, where in (("charger", guide_robot.CHARGER), ("dock", guide_robot.DOCK)):
    ax.annotate(name, where, ha="center", va="bottom", xytext=(0, 8), textcoords="offset points")
ax.set(xlim=(-1, 1), ylim=(-1, 1), title=f"{len(tours)} tours", xlabel="x", ylabel="y")
plt.tight_layout()
plt.show()"""),
    new_markdown_cell(r"""## 5. Sub-goal automata

Sub-goals are where the state lingers (DBSCAN per feature subset, here one subset `robot` of
both coordinates); each tour becomes a word of sub-goals; the PDFA counts the orders."""),
    new_code_cell(r"""from symlearn.learners.subgoals import SubgoalPDFALearner
from symlearn.rendering import dot_to_svg_text

learner = SubgoalPDFALearner(subsets="robot=0,1").fit(tours, ["x", "y"])
for goal in learner.subgoals_:
    print(goal.name, "centre", np.round(goal.centre, 2).tolist(), "radius", round(float(goal.radius), 3))
print("plan:", " -> ".join(learner.plan_))
learner.save("tour_plan.json")
svg = dot_to_svg_text(learner.pdfa_.to_dot("orders of the tours"))
display(SVG(svg)) if svg else print(learner.pdfa_.to_dot())"""),
    new_markdown_cell(r"""**Read and edit:** `tour_plan.json` holds the automaton with the sub-goals and the plan
(`symlearn automaton show tour_plan.json`). **Act:** `execute` drives a controller through the
plan. Our controller steers the robot to a sub-goal's centre in the real environment; we hide
the charger (`reachable`) and the executor replans through the dock first."""),
    new_code_cell(r"""from symlearn.backends.subgoal_plan import execute

centres = {g.name: np.asarray(g.centre) for g in learner.subgoals_}
charger = min(centres, key=lambda n: np.linalg.norm(centres[n] - guide_robot.CHARGER))
robot = gym.make("GuideTour-v0")
robot.reset(seed=1)

def drive_to(name):
    for _ in range(40):
        delta = centres[name] - robot.unwrapped.position
        if np.linalg.norm(delta) < 0.05:
            return True
        robot.step(np.clip(delta, -0.1, 0.1).astype(np.float32))
    return False

print(execute(learner.pdfa_, drive_to))
robot.reset(seed=1)
hidden = execute(learner.pdfa_, drive_to, reachable=lambda name: name != charger or robot.unwrapped.t > 0)
print(hidden.achieved, "| stations visited:", sorted(robot.unwrapped.visited))"""),
    new_markdown_cell(r"""## 4. Reward machines from video

The same tours seen by the camera (24 x 24 pictures; charger first every time, since a reward
machine describes one task). `RewardMachineInference` clusters the still frames into sub-goals,
keeps a prototype picture of each, labels every frame by its nearest prototype and builds the
machine of the label sequences."""),
    new_code_cell(r"""from symlearn.learners.reward_machines import RewardMachineInference

camera = gym.make("GuideTour-v0", camera=True)
videos = record(camera, guide_robot.tour_expert(camera, prefer_charger=1.0), EPISODES, seed=0)
rm = RewardMachineInference().fit(videos)
svg = dot_to_svg_text(rm.machine_.to_dot("reward machine"))
display(SVG(svg)) if svg else print(rm.machine_.to_dot())
fig, axes = plt.subplots(1, len(rm.prototype_frames_), figsize=(2 * len(rm.prototype_frames_), 2.2))
for k, (ax, frame) in enumerate(zip(axes, rm.prototype_frames_)):
    ax.imshow(frame, cmap="gray")
    ax.set(title=f"u{k}: p{k}", xticks=[], yticks=[])
plt.tight_layout()
plt.show()"""),
    new_markdown_cell(r"""**Re-check** the labeling on new videos (the dock-first tours the machine has never seen: they
never reach the goal state), then **train** PPO with the shaped machine as the reward.
`RewardMachineWrapper` adds the machine state to the observation; its labeling is any callable,
so the agent may see the robot's position while the labeling looks at the camera picture of it
(from pixels alone PPO would need far more steps than a notebook should take)."""),
    new_code_cell(r"""from symlearn.backends.reward_machine import RewardMachineWrapper
from symlearn.rl.ppo import PPOConfig, train_ppo

other = record(camera, guide_robot.tour_expert(camera, prefer_charger=0.0, seed=5), 3, seed=9)
for word in rm.label_words(other):
    seen = [sorted(label)[0] for label in word if label]
    order = [p for i, p in enumerate(seen) if i == 0 or p != seen[i - 1]]
    end = rm.machine_.run(word)[0][-1]
    print(" -> ".join(order), f"| ends in u{end}", "(goal)" if end in rm.machine_.accepting else "(not the goal)")

machine = rm.shaped_machine_
sees = lambda position: rm.labeling_.label(guide_robot.render(position))  # the camera's view of a position
make = lambda: RewardMachineWrapper(gym.make("GuideTour-v0"), machine, sees, observation="flat")
result = train_ppo(make, 1024 if QUICK else 16384, PPOConfig(n_envs=4, n_steps=128, seed=0))
curve = [(h.steps, h.mean_return, h.mean_length) for h in result.history]
fig, ax = plt.subplots(figsize=(4, 2.6))
ax.plot([c[0] for c in curve], [c[1] for c in curve], marker=".")
ax.set(xlabel="environment steps", ylabel="machine reward per episode", title="PPO on the learned machine")
plt.tight_layout()
plt.show()
print("last iteration: reward", round(curve[-1][1], 3), "episode length", round(curve[-1][2], 1),
      "(the episode ends when the machine accepts)")"""),
]

nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                                        "language": "python"}})
execute_and_write(nb, Path(__file__).resolve().parent.parent / "notebooks" / "11_guide_tasks.ipynb")
