import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

cells = [
    new_markdown_cell("""# 04 · Learning constraints as ASP rules (ILP)

This notebook walks through the ILP workflow of `symlearn.logic.ilp`:

1. author a background-knowledge file (`.lp`, plain clingo) and a task file in the ILASP format;
2. learn the cheapest set of integrity constraints that separates allowed from forbidden
   state-action pairs;
3. read the rules and ask them questions (`allowed`, `forbidden_interpretations`);
4. write them to an editable `.lp` file, edit one rule by hand and re-check it against the examples
   (what `symlearn ilp check` does).

Set `SYMLEARN_QUICK=1` for a smaller run."""),
    new_code_cell("""import os
import random
import tempfile
from pathlib import Path

from symlearn.atomic import write_text
from symlearn.logic.asp import Hypothesis, Program
from symlearn.logic.ilp import generate_space, learn, load_task, score

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
N_EXAMPLES = 60 if QUICK else 400
work = Path(tempfile.mkdtemp(prefix="symlearn_ilp_"))
work"""),
    new_markdown_cell("""## 1 · Background knowledge and a task

A robot on a corridor grid chooses a direction. The background derives `blocked(D)` when there is a
wall or a person in direction `D`. Hidden rules (used only to label the examples): never move into
a blocked direction, and never go `west` (a one-way corridor)."""),
    new_code_cell("""background = '''\
dir(north; south; east; west).
blocked(D) :- wall(D).
blocked(D) :- person(D).
'''
write_text(work / "corridor_bk.lp", background)

def truth_allows(walls, people, go):
    return go not in walls and go not in people and go != "west"

rng = random.Random(0)
dirs = ["north", "south", "east", "west"]
lines = [
    "% modes: which literals rules may use (constraints only: no #modeh)",
    "#modeb(1, blocked(var(d)), (positive)).",
    "#modeb(1, go(var(d)), (positive)).",
    "#modeb(1, go(const(d)), (positive)).",
    "#modeb(1, wall(var(d)), (positive)).",
    *[f"#constant(d, {d})." for d in dirs],
    "#maxv(2).",
]
for i in range(N_EXAMPLES):
    walls = [d for d in dirs if rng.random() < 0.3]
    people = [d for d in dirs if rng.random() < 0.2]
    go = rng.choice(dirs)
    facts = " ".join([f"wall({d})." for d in walls] + [f"person({d})." for d in people] + [f"go({go})."])
    kind = "pos" if truth_allows(walls, people, go) else "neg"
    lines.append(f"#{kind}(e{i}, {{}}, {{}}, {{ {facts} }}).")
write_text(work / "corridor.las", "\\n".join(lines) + "\\n")
print("\\n".join(lines[:9] + lines[9:12]))"""),
    new_code_cell("""task = load_task(work / "corridor.las", extra_background=[work / "corridor_bk.lp"])
space = generate_space(task)
print(f"{len(task.positives)} positive and {len(task.negatives)} negative examples; "
      f"{len(space)} candidate rules, e.g.")
for candidate in space.candidates[:: max(1, len(space) // 6)][:6]:
    print("   ", candidate.text, "  % length", candidate.cost)"""),
    new_markdown_cell("## 2 · Learn"),
    new_code_cell("""result = learn(task, timeout=30)
print(f"score {result.score}, optimal {result.optimal}, {result.seconds:.2f} s via the {result.method} path")
for rule in result.hypothesis.rules:
    print("   ", rule)
assert result.optimal and all(result.coverage.values())"""),
    new_markdown_cell("""## 3 · Read the rules

`blocked/1` from the background absorbed walls and people into one literal, so the learner needs
only `:- go(V1), blocked(V1).` and `:- go(west).` The hypothesis answers questions directly:"""),
    new_code_cell("""hyp = result.hypothesis
print("go north with a person there:", hyp.allowed("person(north).", "go(north)"))
print("go east in an empty corridor:", hyp.allowed("", "go(east)"))
print("go west in an empty corridor:", hyp.allowed("", "go(west)"))

# every state-action pair of a small domain that the rules forbid (answer sets of B ∪ D, not of B ∪ D ∪ H)
domain = "{ wall(D) : dir(D) }. 1 { go(D) : dir(D) } 1."
forbidden = hyp.forbidden_interpretations(domain, show=[("wall", 1), ("go", 1)])
print(len(forbidden), "of", 16 * 4, "wall/go combinations are forbidden, e.g.", sorted(forbidden[0]))"""),
    new_markdown_cell("""## 4 · Write, edit, re-check

The rules go to an editable `.lp` file with a header. We edit one rule by hand — replace
`blocked` by `wall`, forgetting people — and re-score: the examples where a person blocks the way
are no longer covered."""),
    new_code_cell("""path = work / "corridor_learned.lp"
hyp.to_lp(path, header="learned from corridor.las in notebook 04")
print(path.read_text())

edited_text = path.read_text().replace("blocked(V1)", "wall(V1)")
write_text(path, edited_text)
edited = Hypothesis.from_lp(path, background=task.background)
report = score(task, edited)
print("edited rules:", edited.rules)
print(f"covered {report['covered']}/{report['total']} examples; score {report['score']}")
missed = [e for e, ok in report["coverage"].items() if not ok]
print("no longer covered:", missed[:8], "..." if len(missed) > 8 else "")
assert report["covered"] < report["total"]"""),
    new_markdown_cell("""The same check from a shell:

```
symlearn ilp learn corridor.las --bk corridor_bk.lp -o corridor_learned.lp
symlearn ilp check corridor.las corridor_learned.lp --bk corridor_bk.lp
```"""),
]
nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(nb, "notebooks/04_ilp_constraints.ipynb")
