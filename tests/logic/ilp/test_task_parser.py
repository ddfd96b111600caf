"""ILASP-style task files: what parses, and the precise errors for what does not."""

import pytest

from symlearn.errors import ParseError
from symlearn.logic.asp import answer_sets
from symlearn.logic.ilp import load_task, parse_task
from symlearn.logic.ilp.modes import ModeAtom, ModeComparison, ModeConditional, Placeholder

TASK = """
% background: any clingo program
disk(1..3).
cell(cell(X,Y)) :- X = 1..2, Y = 1..2.
big(D) :- disk(D), #count { E : disk(E), E < D } >= 1.

#pos(p1, {on(1,2)}, {on(2,1)}, { on(1,2). }).
#neg(n1@10, {}, {}, {
  on(2,1).   % a context may hold rules, choices and comments
  {extra}.
}).
#pos({}, {}, {}).
#pos(eg(id0)@3, {}, {}, {}).

#modeh(valid(var(cell))).
#modeb(2, on(var(disk), var(disk)), (positive)).
#modeb(not big(var(disk))).
#modeb(1, var(disk) < var(disk)).
#modeb(1, var(n2) = var(disk) + var(disk)).
#modec(1, not onRoad(var(dir)) : dir(var(dir))).
#constant(direction, north).
#constant(direction, "south").
#maxv(4).
#max_penalty(50).
#bias("penalty(1, X) :- in_body(X).").
"""


def test_every_declaration_kind():
    task = parse_task(TASK, source="t.las")
    assert [e.id for e in task.examples] == ["p1", "n1", "pos3", "eg(id0)"]
    p1, n1, _, eg = task.examples
    assert p1.positive and not n1.positive and n1.penalty == 10 and eg.penalty == 3 and p1.penalty is None
    assert [str(s) for s in p1.inclusions] == ["on(1,2)"] and [str(s) for s in p1.exclusions] == ["on(2,1)"]
    assert n1.line == 8 and n1.context.parts[0].line == 8
    assert task.modeh[0].literal == ModeAtom("valid", (Placeholder("var", "cell"),))
    on, big, less, plus = task.modeb
    assert on.recall == 2 and on.positive and big.literal.negated and big.recall is None
    assert isinstance(less.literal, ModeComparison) and less.literal.op == "<"
    assert plus.literal.arith_op == "+"
    cond = task.modec[0].literal
    assert isinstance(cond, ModeConditional) and cond.literal.negated and cond.condition[0].name == "dir"
    assert [str(c) for c in task.constants["direction"]] == ["north", '"south"']
    assert task.maxv == 4 and task.max_penalty == 50 and task.bias == ["penalty(1, X) :- in_body(X)."]
    # the background is a clingo program that still runs
    (model,) = answer_sets(task.background)
    assert {str(a) for a in model} >= {"disk(3)", "big(2)", "cell(cell(2,1))"}


def test_extra_background_files_are_appended(tmp_path):
    task_file = tmp_path / "t.las"
    task_file.write_text("#pos(a, {q}, {}, {}).\n#modeb(1, p).\n")
    bk = tmp_path / "extra.lp"
    bk.write_text("q.\n")
    task = load_task(task_file, extra_background=[bk])
    assert task.background.parts[-1].source == str(bk)


@pytest.mark.parametrize("text, line, fragment", [
    ("#modeb(1, p(var(t)).\n", 1, "#modeb declaration"),
    ("a.\n#pos(p1, {a}, {}, {b.}\n", 2, "#pos declaration starting at line 2"),
    ("a.\n\n#modeh(p(var(t)) :- q).\n", 3, "unexpected"),
    ("a.\n#neg(n1, {a}).\n", 2, "expected"),
])
def test_syntax_errors_in_bias_and_examples(text, line, fragment):
    with pytest.raises(ParseError) as info:
        parse_task(text, source="bad.las")
    assert info.value.file == "bad.las" and info.value.line == line
    assert fragment in str(info.value)


@pytest.mark.parametrize("text, feature, line", [
    ("a.\n#modeo(a).\n", "#modeo", 2),
    ("#maxp(3).\n", "#maxp", 1),
    ("a.\nb.\n#brave_ordering(o1, eg1, eg2).\n", "#brave_ordering", 3),
    ('#final_bias("x.").\n', "#final_bias", 1),
    ("#predict(e, {p}, {}, {}).\n", "#predict", 1),
    ("a.\n#modeb(1, p(num_var(t))).\n", "num_var", 2),
    ("\n#modeb(1, p(var(t)), (anti_reflexive)).\n", "mode flag (anti_reflexive)", 2),
])
def test_unsupported_features_are_refused_with_their_line(text, feature, line):
    with pytest.raises(ParseError) as info:
        parse_task(text, source="x.las")
    assert f"unsupported feature {feature} at line {line}" in str(info.value)
    assert info.value.file == "x.las" and info.value.line == line


def test_background_syntax_error_is_reported_in_the_task_file():
    from symlearn.logic.ilp import learn

    task = parse_task("ok.\n#pos(p, {}, {}, {}).\nbad(X :- q.\n#modeb(1, q).\n", source="bk.las")
    with pytest.raises(ParseError) as info:
        learn(task, timeout=5)
    assert info.value.file == "bk.las" and info.value.line == 3


def test_context_syntax_error_is_reported_at_its_line_in_the_task_file():
    from symlearn.logic.ilp import learn

    task = parse_task("#pos(p, {}, {}, {\n  fine.\n  broken(.\n}).\n#modeb(1, q).\n", source="ctx.las")
    with pytest.raises(ParseError) as info:
        learn(task, timeout=5)
    assert info.value.file == "ctx.las" and info.value.line == 3


def test_duplicate_example_ids_and_bad_numbers():
    with pytest.raises(ParseError, match="used twice"):
        parse_task("#pos(a, {}, {}, {}).\n#neg(a, {}, {}, {}).\n")
    with pytest.raises(ParseError, match="#maxv must be at least 1"):
        parse_task("#maxv(0).\n")
    with pytest.raises(ParseError, match="recall must be at least 1"):
        parse_task("#modeb(0, p).\n")
