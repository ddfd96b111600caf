"""``symlearn envs``: the bundled environments (:mod:`symlearn.envs.registry`) and what can be
learned in each.

``--json`` prints ``{"constraints": [...], "specs": [...], "continuous": [...], "machines": [...],
"subgoals": [...], "gymnasium": [...]}``: one row per registry entry of kind ``constraints`` (with the size of its MDP
and ground truth), ``spec`` (with its formula), ``continuous`` (continuous states, constraints over
named features, or learned costs) ``machine`` (reward machines from image demonstrations) or ``subgoals`` (sub-goal automata from
frames of object positions), each with ``kinds``, ``methods``, ``expert`` (``scripted``,
``trained`` or ``null``) and ``gym_id`` (``null`` where there is no gymnasium
environment), then one row per gymnasium id with the entries that use it.
"""

from __future__ import annotations


def register(subparsers, common) -> None:
    parser = subparsers.add_parser(
        "envs", parents=[common()], help="list the bundled environments",
        description="List the bundled environments: where constraints can be learned (`symlearn learn constraints`), "
                    "where task specifications can be learned (`symlearn learn spec`), and their gymnasium ids.")
    parser.set_defaults(handler=_envs)


def _envs(args, out) -> None:
    from symlearn.envs.constraint_envs import constraint_setting
    from symlearn.envs.registry import Kind, entries

    constraints = []
    for entry in entries(Kind.CONSTRAINTS):
        setting = constraint_setting(entry.name)
        constraints.append({**_row(entry), "states": setting.mdp.n_states, "actions": setting.mdp.n_actions,
                            "pairs": int(setting.space.sum()), "forbidden_by_truth": int(setting.truth.sum())})
    specs = [{**_row(entry), "env": entry.gym_name, "formula": entry.formula} for entry in entries(Kind.SPEC)]
    continuous = [_row(entry) for entry in entries(Kind.CONTINUOUS)]
    machines = [_row(entry) for entry in entries(Kind.MACHINE)]
    subgoals = [_row(entry) for entry in entries(Kind.SUBGOALS)]
    gym_ids: dict[str, list[str]] = {}
    for entry in entries():
        if entry.gym_id is not None:
            gym_ids.setdefault(entry.gym_id, []).append(entry.name)
    gymnasium = [{"id": gym_id, "entries": used_by} for gym_id, used_by in gym_ids.items()]
    out.result({"constraints": constraints, "specs": specs, "continuous": continuous, "machines": machines,
                "subgoals": subgoals, "gymnasium": gymnasium}, _render)


def _row(entry) -> dict:
    from symlearn.envs.registry import Kind

    return {"name": entry.name, "description": entry.description,
            "kinds": [kind.value for kind in Kind if kind in entry.kinds],
            "methods": list(entry.methods), "gym_id": entry.gym_id,
            "expert": "scripted" if entry.expert is not None else ("trained" if entry.trained_expert else None)}


def _render(doc: dict) -> str:
    rows = doc["constraints"] + doc["specs"] + doc["continuous"] + doc["machines"] + doc["subgoals"]
    w = max([18, *(len(r["name"]) for r in rows)])  # the name column fits the longest name
    lines = ["constraint learning (symlearn learn constraints --env NAME):"]
    for r in doc["constraints"]:
        lines.append(f"  {r['name']:<{w}} {r['states']:>4} states x {r['actions']} actions, {r['pairs']} pairs "
                     f"({r['forbidden_by_truth']} forbidden)  methods: {', '.join(r['methods'])}")
        lines.append(f"  {'':<{w}} {r['description']}")
    lines.append("task specifications (symlearn learn spec --env NAME):")
    for r in doc["specs"]:
        lines.append(f"  {r['name']:<{w}} {r['formula']:<40} {r['description']}")
    if doc["continuous"]:
        lines.append("continuous constraints (DNF over info['features'] or learned costs, ground truth in "
                     "info['cost']):")
        for r in doc["continuous"]:
            lines.append(f"  {r['name']:<{w}} {r['description']}")
    if doc["machines"]:
        lines.append("reward machines from image demonstrations (symlearn learn rm; train --algo dqrm|dqn):")
        for r in doc["machines"]:
            lines.append(f"  {r['name']:<{w}} {r['description']}")
    if doc["subgoals"]:
        lines.append("sub-goals and preferred orderings from frames (symlearn learn pdfa --env NAME):")
        for r in doc["subgoals"]:
            lines.append(f"  {r['name']:<{w}} {r['description']}")
    lines.append("gymnasium environments (import symlearn.envs, then gymnasium.make(ID)):")
    for r in doc["gymnasium"]:
        lines.append(f"  {r['id']:<30} {', '.join(r['entries'])}")
    without = [r["name"] for r in rows if r["gym_id"] is None]
    if without:
        lines.append(f"  (no gymnasium environment: {', '.join(without)})")
    lines.append("your own environment: --env module:EnvId (or any registered gymnasium id) with --demos; "
                 "see docs/GUIDE.md")
    return "\n".join(lines)
