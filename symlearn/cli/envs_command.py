"""``symlearn envs``: the bundled environments and what can be learned in each."""

from __future__ import annotations


def register(subparsers, common) -> None:
    parser = subparsers.add_parser(
        "envs", parents=[common()], help="list the bundled environments",
        description="List the bundled environments: where constraints can be learned (`symlearn learn constraints`) "
                    "and where task specifications can be learned (`symlearn learn spec`).")
    parser.set_defaults(handler=_envs)


def _envs(args, out) -> None:
    from symlearn.envs.constraint_envs import CONSTRAINT_ENVS, constraint_setting
    from symlearn.envs.spec_tasks import TASKS

    constraints = []
    for name, (domain, description) in CONSTRAINT_ENVS.items():
        setting = constraint_setting(name)
        constraints.append({
            "name": name, "description": description, "states": setting.mdp.n_states,
            "actions": setting.mdp.n_actions, "pairs": int(setting.space.sum()),
            "forbidden_by_truth": int(setting.truth.sum()),
            "methods": ["logic", "ml"] if domain else ["ml", "mce-icrl"],
        })
    specs = [{"name": t.name, "env": t.env_name, "formula": t.formula, "description": t.description}
             for t in TASKS.values()]
    out.result({"constraints": constraints, "specs": specs}, _render)


def _render(doc: dict) -> str:
    lines = ["constraint learning (symlearn learn constraints --env NAME):"]
    for r in doc["constraints"]:
        lines.append(f"  {r['name']:<18} {r['states']:>4} states x {r['actions']} actions, {r['pairs']} pairs "
                     f"({r['forbidden_by_truth']} forbidden)  methods: {', '.join(r['methods'])}")
        lines.append(f"  {'':<18} {r['description']}")
    lines.append("task specifications (symlearn learn spec --env NAME):")
    for r in doc["specs"]:
        lines.append(f"  {r['name']:<18} {r['formula']:<40} {r['description']}")
    return "\n".join(lines)
