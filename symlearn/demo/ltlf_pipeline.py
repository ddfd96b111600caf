"""Demo pipeline: an LTLf task specification checked on FrozenLake demonstrations.

A spec over the FrozenLake labels ``start``/``hole``/``goal`` is parsed from editable text,
evaluated on expert and random episodes with the vectorised evaluator (and cross-checked
against the reference semantics), translated to its minimal DFA (drawn as DOT/SVG, saved as
JSON, compared with LTLf2DFA + MONA when installed), and used to explain why a failing episode
violates it (the DFA's shortest fix). Then the spec is edited and checked again.
"""

from __future__ import annotations

import time

import numpy as np

from symlearn.atomic import write_text
from symlearn.demo.registry import DemoContext, Pipeline, Section
from symlearn.rendering import dot_available, render_dot

SPEC = "G(!hole) & F goal"
# edited: additionally, once the agent has left the start tile it never comes back to it
EDITED_SPEC = "G(!hole) & F goal & G(start & X[!] !start -> X[!] G !start)"

_TILE_PROPS = {"S": ["start"], "F": [], "H": ["hole"], "G": ["goal"]}


def _record(context: DemoContext, n_episodes: int):
    import gymnasium as gym

    from symlearn.data import record
    from symlearn.mdp import TabularMDP
    from symlearn.rl.tabular import value_iteration

    env = gym.make("FrozenLake-v1", map_name="8x8", is_slippery=True)
    tiles = [c.decode() if isinstance(c, bytes) else c for c in env.unwrapped.desc.ravel()]
    labeler = lambda state: _TILE_PROPS[tiles[int(state)]]  # noqa: E731
    solution = value_iteration(TabularMDP.from_gymnasium(env), discount=0.99)
    expert = record(env, lambda s: int(solution.policy[int(s)]), n_episodes, seed=context.seed,
                    labeler=labeler, desc="expert episodes")
    random_demos = record(env, "random", n_episodes, seed=context.seed + 1, labeler=labeler, desc="random episodes")
    return expert, random_demos


def _words(demos) -> list[list[frozenset[str]]]:
    return [[frozenset(label) for label in t.labels] for t in demos]


def _draw(dfa, title: str, context: DemoContext, stem: str, files: list[str]) -> None:
    dot = dfa.to_dot(title=title)
    write_text(context.path("ltlf", f"{stem}.dot"), dot)
    files.append(f"ltlf/{stem}.dot")
    if dot_available():
        render_dot(dot, context.path("ltlf", f"{stem}.svg"))
        files.append(f"ltlf/{stem}.svg")
    dfa.save(context.path("ltlf", f"{stem}.json"))
    files.append(f"ltlf/{stem}.json")


def run(context: DemoContext) -> Section:
    from symlearn.logic.automata.explain import explain
    from symlearn.logic.ltlf import holds, parse, to_string, translate
    from symlearn.logic.ltlf.vectorized import TraceBatch, evaluate

    n_episodes = 30 if context.quick else 200
    expert, random_demos = _record(context, n_episodes)
    files: list[str] = []

    # the spec lives in a text file a user edits; we read it back like a user's file
    spec_path = context.path("ltlf", "spec.ltl")
    write_text(spec_path, f"# FrozenLake task: never fall into a hole, reach the goal\n{SPEC}\n")
    files.append("ltlf/spec.ltl")
    text = next(l for l in spec_path.read_text().splitlines() if l.strip() and not l.startswith("#"))
    spec = parse(text, source=str(spec_path))

    words = {"expert": _words(expert), "random": _words(random_demos)}
    batches = {k: TraceBatch.from_traces(v) for k, v in words.items()}
    start = time.perf_counter()
    verdicts = {k: evaluate(spec, b) for k, b in batches.items()}
    eval_ms = 1000 * (time.perf_counter() - start)
    agree = all(verdicts[k].tolist() == [holds(spec, w) for w in words[k]] for k in words)

    start = time.perf_counter()
    dfa = translate(spec)
    dfa_ms = 1000 * (time.perf_counter() - start)
    _draw(dfa, to_string(spec), context, "spec_dfa", files)
    dfa_agrees = all(dfa.accepts(w) == bool(v) for k in words for w, v in zip(words[k], verdicts[k]))

    mona_identical = None
    from symlearn.optional import available

    if available("mona"):
        from symlearn.logic.ltlf.mona import mona_dfa

        mona = mona_dfa(spec)
        mona_identical = len(mona.word_states()) == dfa.n_states and \
            dfa.equivalent(_mona_as_dfa(mona, dfa.alphabet))[0]

    failing_index = int(np.flatnonzero(~verdicts["random"])[0]) if (~verdicts["random"]).any() else None
    explanation_md = "Every random episode satisfied the spec; nothing to explain."
    if failing_index is not None:
        trace = words["random"][failing_index]
        report = explain(dfa, trace)
        shown = " ".join("{" + ",".join(sorted(s)) + "}" for s in trace[-6:])
        explanation_md = (f"Random episode {failing_index} ({len(trace)} steps, last steps `{shown}`) violates "
                          f"the spec: {report.summary()}.")
        write_text(context.path("ltlf", "explanation.txt"), report.summary() + "\n")
        files.append("ltlf/explanation.txt")

    edited = parse(EDITED_SPEC)
    write_text(context.path("ltlf", "spec_edited.ltl"), f"# edited: never return to the start tile\n{EDITED_SPEC}\n")
    files.append("ltlf/spec_edited.ltl")
    edited_dfa = translate(edited)
    _draw(edited_dfa, to_string(edited), context, "spec_edited_dfa", files)
    edited_rates = {k: float(evaluate(edited, b).mean()) for k, b in batches.items()}

    rates = {k: float(v.mean()) for k, v in verdicts.items()}
    figures = {
        "episodes_per_policy": n_episodes,
        "spec": to_string(spec),
        "spec_satisfaction": rates,
        "edited_spec": to_string(edited),
        "edited_spec_satisfaction": edited_rates,
        "dfa_states": dfa.n_states,
        "dfa_edges": dfa.n_edges,
        "edited_dfa_states": edited_dfa.n_states,
        "translation_ms": round(dfa_ms, 3),
        "vectorised_eval_ms_all_traces": round(eval_ms, 3),
        "vectorised_agrees_with_reference": agree,
        "dfa_agrees_with_evaluator": dfa_agrees,
        "identical_to_mona": mona_identical,
    }
    mona_line = {None: "LTLf2DFA/MONA is not installed, so no cross-check was run.",
                 True: "LTLf2DFA + MONA produce the same minimal DFA (same language, same number of states).",
                 False: "**LTLf2DFA + MONA disagree with this DFA** (please report)."}[mona_identical]
    markdown = f"""
Task spec (editable text in `ltlf/spec.ltl`): `{to_string(spec)}` — never step on a hole, reach the goal.
{n_episodes} expert (value iteration) and {n_episodes} random FrozenLake 8x8 episodes, labelled
`start`/`hole`/`goal`, were checked with the vectorised evaluator in {eval_ms:.1f} ms
(agrees with the reference semantics: {agree}).

| policy | spec satisfied | edited spec satisfied |
|---|---|---|
| value-iteration expert | {rates['expert']:.2f} | {edited_rates['expert']:.2f} |
| uniform random | {rates['random']:.2f} | {edited_rates['random']:.2f} |

Minimal DFA: {dfa.n_states} states, {dfa.n_edges} edges, built in {dfa_ms:.2f} ms
(`ltlf/spec_dfa.dot`/`.svg`/`.json`); it accepts exactly the episodes the evaluator accepts
({dfa_agrees}). {mona_line}

Explanation from the DFA: {explanation_md}

Edited spec `{to_string(edited)}` (also: once the agent leaves the start tile it never returns):
{edited_dfa.n_states} states; the slippery ice makes even the expert drift back to the start,
which the edited spec now counts as a violation.
"""
    return Section("LTLf task specification: evaluate, translate, explain (FrozenLake)", markdown, figures, files)


def _mona_as_dfa(mona, propositions):
    from symlearn.logic.automata.dfa import DFA

    states = sorted(mona.word_states())
    index = {q: i for i, q in enumerate(states)}
    transitions = {}
    for q in states:
        merged = {}
        for guard, target in mona.edges[q]:
            merged[index[target]] = merged[index[target]] | guard if index[target] in merged else guard
        transitions[index[q]] = list((g, t) for t, g in merged.items())
    accepting = [index[q] for q in states if q in mona.accepting]
    return DFA(propositions, len(states), index[mona.word_start], accepting, transitions)


PIPELINE = Pipeline("ltlf", "LTLf task spec on FrozenLake demonstrations: evaluate, translate, explain", run)
