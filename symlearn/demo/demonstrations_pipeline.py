"""Demo pipeline: expert demonstrations in FrozenLake, recorded, saved, reloaded and summarised.

The expert acts greedily on values from exact value iteration over the environment's own
model; a random policy is recorded in the same run as the reference point.
"""

from __future__ import annotations

import time
from collections import Counter

import numpy as np

from symlearn.atomic import write_text
from symlearn.data import Demonstrations, load, record
from symlearn.demo.registry import DemoContext, Pipeline, Section
from symlearn.rendering import dot_available, render_dot

_TILE_PROPS = {"S": ["start"], "F": [], "H": ["hole"], "G": ["goal"]}
_ACTIONS = ("left", "down", "right", "up")


def _labeler(desc: np.ndarray):
    tiles = [c.decode() if isinstance(c, bytes) else c for c in desc.ravel()]
    return lambda state: _TILE_PROPS[tiles[int(state)]]


def _success(demos: Demonstrations) -> float:
    return float(np.mean([("goal" in t.labels[-1]) for t in demos]))


_ARROWS = ("\u2190", "\u2193", "\u2192", "\u2191")  # left, down, right, up (FrozenLake's action order)


def _state_graph_dot(demos: Demonstrations, desc: np.ndarray) -> str:
    """The map as a grid (one cell per tile, laid out as FrozenLake draws it): the tile, how
    often the expert was there, and the arrow of the move it chose most often there; darker blue
    = more visits. A graph of states and moves laid out left to right was 4291 x 1321 px for the
    8 x 8 map and unreadable."""
    height, width = desc.shape
    tiles = [c.decode() if isinstance(c, bytes) else c for c in desc.ravel()]
    visits = Counter(int(t.state(i)) for t in demos for i in range(len(t)))
    moves: dict[int, Counter] = {}
    for t in demos:
        for i in range(t.n_actions):
            moves.setdefault(int(t.state(i)), Counter())[int(t.actions[i])] += 1
    top = max(visits.values()) if visits else 1
    fixed = {"H": "#9e9e9e", "G": "#a5e3a5"}
    rows = []
    for r in range(height):
        cells = []
        for c in range(width):
            s = r * width + c
            n = visits.get(s, 0)
            if tiles[s] in fixed:
                colour = fixed[tiles[s]]
            else:
                shade = int(255 - 150 * (n / top) ** 0.5) if n else 255
                colour = f"#{shade:02x}{min(255, shade + 20):02x}ff"
            arrow = _ARROWS[moves[s].most_common(1)[0][0]] if s in moves else ""
            name = {"S": "start", "H": "hole", "G": "goal"}.get(tiles[s], "")
            text = f"<b>{name or '&#160;'}</b><br/>{n if n else '&#160;'}<br/><font point-size=\"16\">{arrow or '&#160;'}</font>"
            cells.append(f'<td width="56" height="56" fixedsize="true" bgcolor="{colour}">{text}</td>')
        rows.append("<tr>" + "".join(cells) + "</tr>")
    caption = (f'<tr><td colspan="{width}" border="0"><font point-size="12">Expert visits per tile ({len(demos)} '
               "episodes)<br/>and its most frequent move there</font></td></tr>")
    table = '<table border="0" cellborder="1" cellspacing="0">' + caption + "".join(rows) + "</table>"
    return ("digraph visits {\n  fontname=\"Helvetica\";\n"
            f"  map [shape=plaintext, fontname=\"Helvetica\", fontsize=10, label=<{table}>];\n}}\n")


def run(context: DemoContext) -> Section:
    import gymnasium as gym

    from symlearn.mdp import TabularMDP
    from symlearn.rl.tabular import value_iteration

    n_episodes = 20 if context.quick else 200
    env = gym.make("FrozenLake-v1", map_name="8x8", is_slippery=True)
    desc = env.unwrapped.desc
    width = desc.shape[1]
    names = tuple(f"r{s // width}c{s % width}" for s in range(desc.size))
    mdp = TabularMDP.from_gymnasium(env, state_names=names, action_names=_ACTIONS)
    solution = value_iteration(mdp, discount=0.99)
    start = int(np.flatnonzero(mdp.initial)[0])

    labeler = _labeler(desc)
    expert = record(env, lambda s: int(solution.policy[int(s)]), n_episodes, seed=context.seed,
                    labeler=labeler, metadata={"policy": "value-iteration expert"}, desc="expert episodes")
    baseline = record(env, "random", n_episodes, seed=context.seed + 1, labeler=labeler,
                      metadata={"policy": "uniform random"}, desc="random episodes")

    round_trip = {}
    for suffix in ("jsonl", "npz"):
        path = context.path("demonstrations", f"frozenlake_expert.{suffix}")
        t0 = time.perf_counter()
        expert.save(path)
        again = load(path)
        round_trip[suffix] = {"exact": again == expert, "bytes": path.stat().st_size,
                              "seconds": round(time.perf_counter() - t0, 4)}

    files = ["demonstrations/frozenlake_expert.jsonl", "demonstrations/frozenlake_expert.npz"]
    dot = _state_graph_dot(expert, desc)
    write_text(context.path("frozenlake_visits.dot"), dot)
    files.append("frozenlake_visits.dot")
    if dot_available():
        render_dot(dot, context.path("frozenlake_visits.svg"))
        files.append("frozenlake_visits.svg")

    summary = expert.summary()
    figures = {
        "episodes": n_episodes,
        "value_iteration_sweeps": solution.iterations,
        "start_value": float(solution.values[start]),
        "expert_success_rate": _success(expert),
        "random_success_rate": _success(baseline),
        "expert_mean_length": summary["length"]["mean"],
        "distinct_states_visited": summary["n_distinct_states"],
        "round_trip_exact": all(r["exact"] for r in round_trip.values()),
        "file_bytes": {k: v["bytes"] for k, v in round_trip.items()},
    }
    markdown = f"""
FrozenLake 8x8 (slippery). A tabular model was read from the environment ({mdp.n_states} states,
{mdp.n_actions} actions); value iteration converged in {solution.iterations} sweeps (discount 0.99,
value of the start state {figures['start_value']:.3f}). {n_episodes} expert and {n_episodes} random
episodes were recorded with per-step labels `start`, `hole`, `goal`.

| policy | success rate | mean length | mean return |
|---|---|---|---|
| value-iteration expert | {figures['expert_success_rate']:.2f} | {summary['length']['mean']:.1f} | {summary['return']['mean']:.3f} |
| uniform random | {figures['random_success_rate']:.2f} | {baseline.summary()['length']['mean']:.1f} | {baseline.summary()['return']['mean']:.3f} |

The expert demonstrations were saved as JSONL ({round_trip['jsonl']['bytes']} bytes) and NPZ
({round_trip['npz']['bytes']} bytes) and read back: round trip exact = {figures['round_trip_exact']}.
`frozenlake_visits.dot` draws the map with the expert's visits per tile and its most frequent move there.
"""
    return Section("Demonstrations: record, save, reload (FrozenLake)", markdown, figures, files)


PIPELINE = Pipeline("demonstrations", "Record expert demonstrations in FrozenLake and round-trip them", run)
