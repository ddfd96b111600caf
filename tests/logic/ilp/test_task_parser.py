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


# -- issue 15: unsupported features refused in every place a program comes from (class 4) ----------

_BASE = "#pos(p1, {}, {}, { a. }).\n#neg(n1, {}, {}, { b. }).\n#modeb(1, b).\n"
_FEATURES = [("#script (python)\nimport os.path\nos.system('x')\n#end.", "#script (python)"),
             ("#script (lua) function f() return 1 end #end.", "#script (lua)"),
             ("#minimize { 1 : a }.", "#minimize/#maximize"),
             (":~ a. [1@1]", "weak constraint (:~)"),
             ("#external e.", "#external"),
             ("#heuristic a. [1, level]", "#heuristic")]


@pytest.mark.parametrize("statement, feature", _FEATURES)
@pytest.mark.parametrize("place", ["background", "context", "bk", "include"])
def test_unsupported_statement_named_at_its_file_and_line(tmp_path, statement, feature, place):
    from symlearn.logic.ilp import learn

    task_path, bk_path = tmp_path / "t.las", tmp_path / "bk.lp"
    extra = []
    if place == "background":
        task_path.write_text("x.\n" + statement + "\n" + _BASE)
        where, line = task_path, 2
    elif place == "context":
        task_path.write_text(_BASE + "#pos(p2, {}, {}, {\n  a.\n  " + statement + "\n}).\n")
        where, line = task_path, 6
    else:
        bk_path.write_text("% extra knowledge\n" + statement + "\n")
        where, line = bk_path, 2
        if place == "bk":
            task_path.write_text(_BASE)
            extra = [bk_path]
        else:
            task_path.write_text('#include "bk.lp".\n' + _BASE)
    with pytest.raises(ParseError) as info:
        learn(load_task(task_path, extra_background=extra), timeout=10)
    error = info.value
    assert f"unsupported feature {feature} at line {line}" in error.message, str(error)
    assert error.file == str(where) and error.line == line


def test_unsupported_statement_in_a_hypothesis_file(tmp_path):
    from symlearn.logic.asp import Hypothesis

    path = tmp_path / "h.lp"
    path.write_text(":- b.\n#external e.\n")
    with pytest.raises(ParseError, match="unsupported feature #external at line 2") as info:
        Hypothesis.from_lp(path)
    assert info.value.file == str(path)


# -- #include and locations (class 8) ----------------------------------------------------------------

def test_include_is_resolved_next_to_the_including_file(tmp_path, monkeypatch):
    from symlearn.logic.ilp import learn

    (tmp_path / "kb").mkdir()
    (tmp_path / "kb" / "rules.lp").write_text('#include "more/facts.lp".\nb :- c.\n')
    (tmp_path / "kb" / "more").mkdir()
    (tmp_path / "kb" / "more" / "facts.lp").write_text("d.\n")
    task = tmp_path / "kb" / "t.las"
    task.write_text('#include "rules.lp".\n#pos(p, {d}, {}, { a. }).\n#neg(n, {}, {}, { c. }).\n#modeb(1, b).\n')
    monkeypatch.chdir(tmp_path)  # not the task's folder
    result = learn(load_task(task), timeout=10)
    assert result.hypothesis.rules == [":- b."]


def test_include_errors_name_the_included_file_and_line(tmp_path):
    from symlearn.logic.ilp import learn

    (tmp_path / "bad.lp").write_text("ok.\nb :- c\nfoo(.\n")
    task = tmp_path / "t.las"
    task.write_text('#include "bad.lp".\n' + _BASE)
    with pytest.raises(ParseError, match="no '.'") as info:
        learn(load_task(task), timeout=10)
    # clingo stumbles on line 3; the rule without its '.' ends on line 2
    assert info.value.file == str(tmp_path / "bad.lp") and (info.value.line, info.value.column) == (2, 7)
    (tmp_path / "bad.lp").write_text("ok.\nb :- c.\nfoo(.\n")
    with pytest.raises(ParseError) as info:
        learn(load_task(task), timeout=10)
    assert info.value.file == str(tmp_path / "bad.lp") and info.value.line == 3
    task.write_text('#include "missing.lp".\n' + _BASE)
    with pytest.raises(ParseError, match="no such file") as info:
        load_task(task)
    assert info.value.file == str(task) and info.value.line == 1
    task.write_text('#include <incmode>.\n' + _BASE)
    with pytest.raises(ParseError, match="unsupported feature #include <incmode> at line 1"):
        load_task(task)
    task.write_text('#include "t.las".\n% #include "nowhere.lp". (a comment)\n' + _BASE)  # itself: once, as clingo
    assert len(load_task(task).examples) == 2


@pytest.mark.parametrize("place", ["background", "context", "bk", "hypothesis"])
def test_unsafe_rule_is_reported_at_its_file_and_line(tmp_path, place):
    from symlearn.logic.asp import Hypothesis
    from symlearn.logic.ilp import learn, score

    task_path, other = tmp_path / "t.las", tmp_path / "other.lp"
    unsafe = "q(Y) :- a."
    if place == "background":
        task_path.write_text("x.\n\n" + unsafe + "\n" + _BASE)
        where, line = task_path, 3
    elif place == "context":
        task_path.write_text(_BASE + "#pos(p2, {}, {}, {\n  a.\n  " + unsafe + "\n}).\n")
        where, line = task_path, 6
    else:
        task_path.write_text(_BASE)
        other.write_text("% comment\nz.\n" + unsafe + "\n")
        where, line = other, 3
    with pytest.raises(ParseError, match="unsafe variable Y: a variable must occur in a positive body atom") as info:
        task = load_task(task_path, extra_background=[other] if place == "bk" else [])
        if place == "hypothesis":
            score(task, Hypothesis.from_lp(other, background=task.background))
        else:
            learn(task, timeout=10)
    assert (info.value.file, info.value.line) == (str(where), line), str(info.value)


def test_deep_nesting_is_refused_before_it_reaches_a_recursive_parser(tmp_path):
    """Class 5 in ILP files: a term nested 3,000 deep raised RecursionError; clingo crashed
    (segmentation fault) grounding one nested 100,000 deep."""
    from symlearn.logic.asp import Hypothesis, Program

    deep = "f(" * 3000 + "1" + ")" * 3000
    for text, line in ((f"#pos(p, {{}}, {{}}, {{ a. }}).\n#modeb(1, p({deep})).\n", 2),
                       (f"#pos(p, {{}}, {{}}, {{\n a({deep}). }}).\n#modeb(1, a(var(t))).\n", 2)):
        with pytest.raises(ParseError, match="nested more than 100 levels deep") as info:
            parse_task(text, source="deep.las")
        assert info.value.line == line
    lp = tmp_path / "deep.lp"
    lp.write_text(f"ok.\n% {'(' * 500} a comment\nb({deep}).\n")
    with pytest.raises(ParseError, match="nested more than 100") as info:
        Program.from_file(lp)
    assert (info.value.file, info.value.line) == (str(lp), 3)
    with pytest.raises(ParseError, match="nested more than 100"):
        Hypothesis.from_lp(lp)
