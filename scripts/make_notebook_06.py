"""Write notebooks/06_separating_ltl.ipynb (kept as a script so the notebook stays reviewable)."""

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# Learning a separating LTLf formula from labelled traces

Given finite traces labelled positive or negative, find a small LTLf formula that every
positive trace satisfies and no negative one does. `learn_ltl` enumerates formulas by size,
each represented by its truth values at every position of every trace (bit words), keeps one
formula per distinct behaviour, and stops at the first size that separates: that formula is
a smallest one (`optimal=True`). When the exact search runs out of budget it combines the
candidates it has with a greedy set cover and a Boolean search, and says the answer is not
proven smallest."""),
    new_code_cell("""import os
from pathlib import Path

from symlearn.data.ltl_samples import load_sample, sample_from_traces
from symlearn.learners.temporal.separating_ltl import learn_from_sample, learn_ltl
from symlearn.logic.ltlf import holds, parse, size
from symlearn.logic.ltlf.vectorized import evaluate_many

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
TIMEOUT = 3 if QUICK else 10"""),
    new_markdown_cell("""## A tiny sample

The robot must pick up (`a`) and deliver (`b`) afterwards; the negatives deliver first or
never."""),
    new_code_cell("""positive = [[{"a"}, {"b"}], [set(), {"a"}, set(), {"b"}], [{"a"}, {"a"}, {"b"}]]
negative = [[{"b"}, {"a"}], [{"a"}], [set(), {"b"}]]
result = learn_ltl(positive, negative, timeout=TIMEOUT)
print(result.message)
result.formula"""),
    new_code_cell("""# check it with the core semantics, and that the printed text reads back to the same tree
assert all(holds(result.formula, t) for t in positive)
assert not any(holds(result.formula, t) for t in negative)
assert parse(str(result.formula)) == result.formula"""),
    new_markdown_cell("""## Planting a formula

Label random traces with a known formula and learn it back: the learner returns a formula no
larger than the planted one (possibly a different but equivalent-on-the-sample one)."""),
    new_code_cell("""import random

rng = random.Random(0)
planted = parse("G(a -> F b)")
traces = {tuple(frozenset(p for p in "ab" if rng.random() < 0.4) for _ in range(rng.randint(2, 8)))
          for _ in range(60 if QUICK else 200)}
traces = sorted(traces, key=str)
pos = [t for t in traces if holds(planted, t)]
neg = [t for t in traces if not holds(planted, t)]
learned = learn_ltl(pos, neg, timeout=TIMEOUT)
print(f"planted {planted} (size {size(planted)}) -> learned {learned.formula} (size {learned.size}, "
      f"optimal={learned.optimal}, {learned.candidates_explored} candidates, {learned.seconds:.3f} s)")"""),
    new_markdown_cell("""## A benchmark problem

The public LTLf learning benchmarks store samples as JSON (propositions -> 0/1 lists per
trace) with the smallest formula known, in Spot's dialect. When the shared benchmark folder
is present we learn one of them; otherwise we write a sample in that format ourselves."""),
    new_code_cell("""candidates = [folder / "shared" / "benchmarks" / "ltlf_learning" / "dev" for folder in Path.cwd().resolve().parents]
files = [f for bench in candidates for f in sorted(bench.glob("Subset/*.json"))][:1]
if files:
    sample = load_sample(files[0])
else:
    sample = sample_from_traces(pos, neg, smallest_known_formula="G(a -> F b)")
print(sample)
result = learn_from_sample(sample, timeout=TIMEOUT)
known = sample.smallest_known_formula
print("learned:", result.message)
if known:
    print("smallest known:", known, "size", size(parse(known, dialect="spot")))
verdicts = evaluate_many(result.formula, list(sample.positive) + list(sample.negative))
print("separates:", bool(verdicts[:len(sample.positive)].all() and not verdicts[len(sample.positive):].any()))"""),
    new_markdown_cell("""The same from the command line: `symlearn ltl learn SAMPLES.json --timeout 10 --json`
prints `formula` (our syntax, `null` when none was found), `size`, `optimal` and `seconds`."""),
]

nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(nb, "notebooks/06_separating_ltl.ipynb")
