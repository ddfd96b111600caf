"""Write notebooks/03_automata.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# Automata: guards, DFAs, PDFAs and reward machines

Task specifications become automata whose edges carry *propositional guards* over the
propositions a labelling function reports at each step. This notebook builds the task
"first reach `a`, then reach `b`, and never touch `c`" as a DFA, explains a failing trace,
turns the DFA into a probabilistic DFA to sample and score traces, and into a reward machine
with potential-based shaping for an RL agent."""),
    new_code_cell("""import os
import tempfile
from pathlib import Path

import numpy as np

from symlearn.errors import SymlearnError
from symlearn.logic.automata import DFA, PDFA, RewardMachine, explain, parse_mona_dot, parse_rm_text
from symlearn.logic.guards import Guard

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
N_SAMPLES = 300 if QUICK else 5000
OUT = Path(tempfile.mkdtemp(prefix="symlearn-automata-"))"""),
    new_markdown_cell("""## Guards

A guard is a Boolean function of proposition names. Guards are canonical (a reduced ordered
BDD underneath), so `==` means *logically equivalent*, and they print as a small sum of
products."""),
    new_code_cell("""a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")
g = (a & b) | (a & ~b & ~c) | (a & c & ~b)
print(g, "| equal to a:", g == a)
print(Guard.parse("!(a | b) | a"), "| satisfied by", set(Guard.parse("a & !b").satisfying_label()))
try:
    Guard.parse("a and b")
except SymlearnError as err:
    print("error:", err)"""),
    new_markdown_cell("""## A task DFA

Edges leaving a state must be mutually exclusive (checked when the DFA is built). Here the DFA
is written by hand with a redundant copy of the waiting state; `minimize()` merges it and
adds the rejecting sink that the hand-written, partial DFA left implicit."""),
    new_code_cell("""task = DFA({"a", "b", "c"}, 4, 0, [3], {
    0: [(~a & ~c, 0), (a & ~c, 1)],
    1: [(~b & ~c, 2), (b & ~c, 3)],
    2: [(~b & ~c, 1), (b & ~c, 3)],   # behaves exactly like state 1
    3: [(~c, 3)],
}, state_names=["wait_a", "wait_b", "wait_b'", "done"])
minimal = task.minimize()
print(task)
print(minimal)
print("same language:", minimal.equivalent(task))
minimal"""),
    new_code_cell("""print("shortest accepted:", [set(s) for s in minimal.shortest_accepted()])
print("shortest rejected:", [set(s) for s in minimal.shortest_rejected()])
print("accepts a, b:", minimal.accepts([{"a"}, {"b"}]), "| accepts a, c, b:", minimal.accepts([{"a"}, {"c"}, {"b"}]))"""),
    new_markdown_cell("""## Why is a trace rejected?

`explain` runs the trace, reports the step where acceptance became impossible and the fewest
step edits (substitute, delete, insert) that make the trace accepted."""),
    new_code_cell("""report = explain(minimal, [{"a"}, {"c"}, set(), {"b"}])
print(report.summary())
print("fixed trace:", [set(s) for s in report.fixed_trace])"""),
    new_markdown_cell("""## Editing: a second requirement by product

Adding "and eventually `d`" is a product with the DFA of `F d`; the product lives over the union
of the alphabets. Redrawing shows the new automaton."""),
    new_code_cell("""d = Guard.var("d")
eventually_d = DFA({"d"}, 2, 0, [1], {0: [(~d, 0), (d, 1)], 1: [(Guard.true(), 1)]})
edited = (minimal & eventually_d).minimize()
print(edited, "| old trace now:", edited.accepts([{"a"}, {"b"}]), "| with d:", edited.accepts([{"a"}, {"b", "d"}]))
edited"""),
    new_markdown_cell("""## A probabilistic DFA

`PDFA.from_dfa` makes a random walk over the useful part of the DFA: accepting states stop with
the given probability, and edges share the rest in proportion to how many labels their guard
allows, so every sample is an accepted trace. Probabilities are over *guard classes*; with
`per_label=True` labels inside a guard count as uniformly distributed, matching
`sample(label_choice="uniform")`."""),
    new_code_cell("""pdfa = PDFA.from_dfa(minimal, termination=0.3)
rng = np.random.default_rng(0)
samples = [pdfa.sample(rng) for _ in range(N_SAMPLES)]
print("all samples accepted:", all(minimal.accepts(w) for w in samples))
print("mean length:", np.mean([len(w) for w in samples]).round(2))
word, p = pdfa.most_probable_accepted()
print("most probable accepted word:", [set(s) for s in word], "p =", round(p, 4))
print("P([a], [b]) =", round(pdfa.probability([{"a"}, {"b"}]), 4),
      "| per label:", round(pdfa.probability([{"a"}, {"b"}], per_label=True), 5))
pdfa"""),
    new_code_cell("""# normalisation is checked when a PDFA is built
try:
    PDFA({"a"}, 1, 0, {0: [(a, 0, 0.5)]}, [0.4])
except SymlearnError as err:
    print("error:", err)"""),
    new_markdown_cell("""## A reward machine with shaping

`RewardMachine.from_dfa` pays 1 when the task is completed. With `shaping=True` each edge also
carries `gamma * phi(u') - phi(u)` with `phi(u) = -distance to acceptance`, so progress is
rewarded immediately while optimal policies stay the same (potential-based shaping)."""),
    new_code_cell("""rm = RewardMachine.from_dfa(minimal, shaping=True, gamma=0.9)
print("potential:", rm.potential, "| terminal:", sorted(rm.terminal))
u = rm.initial
for label in [set(), {"a"}, set(), {"b"}]:
    u_next, r = rm.step(u, label)
    print(f"{rm.state_names[u]:>7} --{sorted(label)}--> {rm.state_names[u_next]:<7} reward {r:+.3f}")
    u = u_next
rm"""),
    new_markdown_cell("""## Files: JSON, DOT, HOA, and the formats of other tools

Every automaton has a versioned JSON form that round-trips exactly, DOT for Graphviz, and (for
DFAs) HOA text for Spot. We also read the DOT written by LTLf2DFA/MONA and the text format of the
public reward-machines code (parsed, never evaluated)."""),
    new_code_cell("""path = rm.save(OUT / "task_rm.json")
print("JSON round trip exact:", RewardMachine.from_json(path.read_text()) == rm)
(OUT / "task.dot").write_text(minimal.to_dot())
print(minimal.to_hoa(name="a then b, never c"))"""),
    new_code_cell("""ltlf2dfa_dot = '''digraph MONA_DFA {
 rankdir = LR;
 node [shape = doublecircle]; 3;
 node [shape = circle]; 1;
 init [shape = plaintext, label = ""];
 init -> 1;
 1 -> 2 [label="~b"];
 1 -> 1 [label="b & ~a"];
 1 -> 3 [label="a & b"];
 2 -> 2 [label="true"];
 3 -> 2 [label="~b"];
 3 -> 3 [label="b"];
}'''
f_a_and_g_b = parse_mona_dot(ltlf2dfa_dot)   # LTLf2DFA's DFA for  F a & G b
print(f_a_and_g_b, f_a_and_g_b.accepts([{"b"}, {"a", "b"}]))

office = parse_rm_text('''0
[2]
(0,0,'!e&!n',ConstantRewardFunction(0))
(0,1,'e&!g&!n',ConstantRewardFunction(0))
(1,1,'!g&!n',ConstantRewardFunction(0))
(1,2,'g&!n',ConstantRewardFunction(1))
''')
print(office.run([{"e"}, set(), {"g"}]))
office"""),
]

notebook = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3"}})
nbformat.write(notebook, "notebooks/03_automata.ipynb")
