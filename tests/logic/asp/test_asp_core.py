"""ASP core: programs with source maps, the clingo adapter, hypotheses."""

import pytest

from symlearn.errors import LimitExceededError, ParseError
from symlearn.logic.asp import Hypothesis, Program, answer_sets, is_satisfiable, optimize, solve
from symlearn.logic.asp import clingo_adapter as cl


def test_compose_files_and_strings_keeps_sources(tmp_path):
    bk = tmp_path / "bk.lp"
    bk.write_text("a.\nb :- a.\n")
    program = Program.compose([bk, "c :- b."])
    assert [sorted(map(str, m)) for m in answer_sets(program)] == [["a", "b", "c"]]
    assert program.locate(4, 2) == ("<string>", 1, 2)  # the file ends with a newline: 3 lines
    assert program.locate(1, 1) == (str(bk), 1, 1)


def test_syntax_error_points_at_our_file_line_and_column(tmp_path):
    bk = tmp_path / "rules.lp"
    bk.write_text("ok.\n\nbroken(X :- q.\n")
    with pytest.raises(ParseError) as info:
        solve(Program.from_text("first.") + Program.from_file(bk))
    err = info.value
    assert err.file == str(bk) and err.line == 3 and err.column is not None
    assert "syntax error" in err.message


def test_error_inside_embedded_piece_is_shifted_by_its_offset():
    piece = Program.from_text("p(1).\nq(X) :- r.", source="task.las", line=10, column=7)
    with pytest.raises(ParseError) as info:
        solve(piece)
    assert (info.value.file, info.value.line) == ("task.las", 11)
    assert "unsafe" in info.value.message and "X" in info.value.message


def test_enumeration_optimisation_and_satisfiability():
    program = Program.from_text("{a; b; c}. :- a, b. #minimize { 1,x : not a ; 2,y : not c }.")
    outcome = optimize(program)
    assert outcome.optimal and outcome.costs[-1] == [0]
    assert len(answer_sets(Program.from_text("{a; b}."))) == 4
    assert is_satisfiable(Program.from_text("a."))
    assert not is_satisfiable(Program.from_text("a. :- a."))


def test_timeout_is_reported_not_hidden():
    hard = Program.from_text("{x(1..40)}.")  # 2^40 answer sets: enumeration cannot finish
    outcome = solve(hard, max_models=0, timeout=0.2)
    assert not outcome.complete
    with pytest.raises(LimitExceededError):
        Hypothesis([":- x(1)."], background=hard).forbidden_interpretations("", timeout=0.2)


def test_tag_program_copies_predicates_not_terms():
    text = cl.tag_program(Program.from_text("at(cell(1,2)). n(1..3). p(X) :- at(cell(X,_)), not q. "
                                            ":- not onRoad(V) : dir(V)."), "E", ["ex(E)"])
    assert "at(E,cell(1,2)) :- ex(E)." in text
    assert "onRoad(E,V): dir(E,V)" in text and "not q(E)" in text


def test_hypothesis_text_and_ast_forms_and_cost():
    h = Hypothesis([":- on(V1,V2), V1 < V2", "p(X) :- q(X), not r(X)."])
    assert h.rules == [":- on(V1,V2), V1 < V2.", "p(X) :- q(X), not r(X)."]
    assert len(h.asts) == 2 and h.cost == 2 + 3 and not h.is_constraints_only
    assert Hypothesis([":- not onRoad(V) : dir(V)."]).cost == 2


def test_eliminates_allowed_and_forbidden_interpretations():
    bk = "dir(n;s). blocked(X) :- wall(X)."
    h = Hypothesis([":- go(X), blocked(X)."], background=bk)
    assert h.eliminates("wall(n). go(n).") and not h.eliminates("wall(n). go(s).")
    assert h.allowed("wall(n).", "go(s)") and not h.allowed("wall(n).", "go(n).")
    domain = "{wall(X) : dir(X)}. 1 {go(X) : dir(X)} 1."
    forbidden = h.forbidden_interpretations(domain, show=[("wall", 1), ("go", 1)])
    # exactly the pairs where the agent walks into a wall: 2 directions x 2 settings of the other wall
    assert len(forbidden) == 4
    assert all(any(f"wall({d})" in i and f"go({d})" in i for d in "ns") for i in forbidden)
    # a non-constraint hypothesis goes through the set difference of both enumerations
    h2 = Hypothesis(["stop :- wall(X), go(X).", ":- stop."], background=bk)
    assert h2.forbidden_interpretations(domain, show=[("wall", 1), ("go", 1)]) == forbidden


def test_lp_round_trip_and_edit(tmp_path):
    path = tmp_path / "h.lp"
    Hypothesis([":- on(V1,V2), V1 < V2."]).to_lp(path, header="learned from hanoi.las")
    text = path.read_text()
    assert text.startswith("% learned from hanoi.las") and "cost" in text
    path.write_text(text.replace("V1 < V2", "V2 < V1") + "% trailing comment\n:- on(X,Y),\n   X = Y.\n")
    again = Hypothesis.from_lp(path)
    assert again.rules == [":- on(V1,V2), V2 < V1.", ":- on(X,Y), X = Y."]
    path.write_text(":- on(X,Y) X < Y.\n")
    with pytest.raises(ParseError) as info:
        Hypothesis.from_lp(path)
    assert info.value.file == str(path) and info.value.line == 1
