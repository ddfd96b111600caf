"""Write notebooks/02_ltlf_task_specs.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# LTLf task specifications: write, translate, draw, explain, edit

A task specification in LTLf (linear temporal logic on finite traces) says what a whole
episode must look like. Here we write one for a small delivery task, check it on traces, turn
it into its minimal DFA, draw the automaton, ask the DFA why a trace fails and how to fix it,
then edit the specification and redraw."""),
    new_code_cell("""import os
import time

from IPython.display import SVG, display

from symlearn.errors import SymlearnError
from symlearn.logic.automata.explain import explain
from symlearn.logic.ltlf import equivalent, holds, parse, simplify, to_string, translate
from symlearn.logic.ltlf.vectorized import TraceBatch, evaluate
from symlearn.rendering import dot_to_svg_text

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
N_RANDOM = 300 if QUICK else 5000"""),
    new_markdown_cell("""## Write a spec

Propositions are lowercase names; `a T b` ("then") means `a` now or later, and `b` strictly
after it. The robot must pick up the parcel, then deliver it, never enter the `lava`, and may
only enter the `door` after it has the `key`."""),
    new_code_cell("""spec = parse("G(!lava) & (parcel T deliver) & (!door W key)")
spec"""),
    new_code_cell("""print(to_string(spec))                       # canonical ASCII, read back by parse()
print(to_string(spec, style="unicode"))
print(to_string(spec, dialect="spot"))       # Spot's dialect: bare X would be weak next there
assert parse(to_string(spec)) == spec"""),
    new_markdown_cell("""Mistakes are reported with a caret and a hint:"""),
    new_code_cell("""for bad in ["G(!lava) && (parcel => deliver)", "[] !lava", "F(key &&& door)"]:
    try:
        parse(bad)
    except SymlearnError as err:
        print(err, end="\\n\\n")"""),
    new_markdown_cell("""## Check it on traces

A trace is a list of steps; each step is the set of propositions true there."""),
    new_code_cell("""good = [set(), {"parcel"}, {"key"}, {"door"}, {"deliver"}]
sneaky = [{"parcel"}, {"door"}, {"key"}, {"deliver"}]
burnt = [{"parcel"}, {"lava"}, {"deliver"}]
for name, trace in [("good", good), ("sneaky", sneaky), ("burnt", burnt)]:
    print(f"{name:7s} {holds(spec, trace)}")"""),
    new_markdown_cell("""The vectorised evaluator checks many traces at once (one boolean matrix per sub-formula):"""),
    new_code_cell("""import random

rng = random.Random(0)
props = ["parcel", "deliver", "key", "door", "lava"]
traces = [[{p for p in props if rng.random() < 0.15} for _ in range(rng.randint(1, 12))] for _ in range(N_RANDOM)]
batch = TraceBatch.from_traces(traces)
start = time.perf_counter()
verdicts = evaluate(spec, batch)
print(f"{len(traces)} traces in {1000 * (time.perf_counter() - start):.1f} ms; {verdicts.mean():.1%} satisfy the spec")
assert verdicts.tolist()[:200] == [holds(spec, t) for t in traces[:200]]"""),
    new_markdown_cell("""## Translate to the minimal DFA and draw it

The translation progresses formula obligations symbolically (the 2^|AP| letters are never
listed one by one) and minimises; edges carry propositional guards."""),
    new_code_cell("""start = time.perf_counter()
dfa = translate(spec)
print(f"{dfa.n_states} states, {dfa.n_edges} edges in {1000 * (time.perf_counter() - start):.2f} ms")
assert all(dfa.accepts(t) == bool(v) for t, v in zip(traces[:300], verdicts[:300]))
svg = dot_to_svg_text(dfa.to_dot(title=to_string(spec)))
display(SVG(svg)) if svg else print(dfa.to_dot())"""),
    new_markdown_cell("""## Why does a trace fail?

The DFA locates the step after which the spec can no longer be satisfied and computes the
fewest step edits that make the trace acceptable."""),
    new_code_cell("""for name, trace in [("sneaky", sneaky), ("burnt", burnt)]:
    print(f"{name}: {explain(dfa, trace).summary()}")
print("shortest trace that satisfies the spec:", dfa.shortest_accepted())"""),
    new_markdown_cell("""## Edit the spec and redraw

Suppose the door may now be opened without the key, but the parcel must be delivered
*through* the door: `parcel T (door T deliver)`. We edit the text, check the edit against the
old traces, and redraw."""),
    new_code_cell("""edited = parse("G(!lava) & (parcel T (door T deliver))")
for name, trace in [("good", good), ("sneaky", sneaky), ("burnt", burnt)]:
    print(f"{name:7s} old {holds(spec, trace)!s:5s} new {holds(edited, trace)}")
edited_dfa = translate(edited)
print(f"edited DFA: {edited_dfa.n_states} states, {edited_dfa.n_edges} edges")
svg = dot_to_svg_text(edited_dfa.to_dot(title=to_string(edited)))
display(SVG(svg)) if svg else None"""),
    new_markdown_cell("""Simplification and equivalence help keep edited specs tidy: `T` chains are the same as
nested eventualities, and redundant parts disappear."""),
    new_code_cell("""print(equivalent(parse("parcel T (door T deliver)"), parse("F(parcel & X F(door & X F deliver))")))
print(to_string(simplify(parse("G G !lava & F F (deliver | deliver) & true"))))"""),
]

nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                                        "language": "python"}})
nbformat.write(nb, "notebooks/02_ltlf_task_specs.ipynb")
