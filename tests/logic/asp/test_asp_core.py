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


# -- issue 15 ---------------------------------------------------------------------------------------

def test_errors_raised_inside_a_clingo_callback_arrive_unchanged():
    """clingo re-raises a callback's exception as ``type(exc)(exc)``: our ParseError used to come
    out as ``TypeError: __str__ returned non-string`` (45 lines of traceback)."""
    program = Program.from_text("a.\n#external e.\n", source="bk.lp")
    with pytest.raises(ParseError) as info:
        cl.tag_program(program, "E", ["ex(E)"])
    assert str(info.value).startswith("bk.lp:2:1: unsupported feature #external at line 2")
    with pytest.raises(ZeroDivisionError):
        cl.parse_statements("a. b.", lambda statement: 1 / 0)


def test_scripts_are_refused_before_clingo_sees_them():
    with pytest.raises(ParseError, match=r"unsupported feature #script \(python\) at line 2") as info:
        solve(Program.from_text("a.\n#script (python)\nimport os\n#end.\n", source="s.lp"))
    assert (info.value.file, info.value.line) == ("s.lp", 2)
    assert answer_sets(Program.from_text('a. % #script (python) in a comment\nb("#script").')) != []


@pytest.mark.parametrize("timeout", [None, float("inf"), 1e10, 1e308])
def test_huge_timeouts_do_not_overflow_into_the_past(timeout):
    assert cl.wait_seconds(timeout) == -1.0
    outcome = solve(Program.from_text("{a; b}."), timeout=timeout)
    assert outcome.complete and len(outcome.models) == 4


def test_tagged_copies_map_back_to_the_statements_they_came_from():
    pieces = [(Program.from_text("a.\n\nq(Y) :- a.", source="ctx.las", line=7, column=5), "1", ("on(1)",))]
    tagged = cl.tag_programs_located(pieces)[0]
    assert tagged.text.splitlines()[1].startswith("q(1,Y)")
    assert tagged.locate(2, 1) == ("ctx.las", 9, 1)


def test_symbols_and_hypotheses_pickle_by_text():
    """clingo's own pickling of a Symbol copies a pointer into the symbol table of the process;
    unpickled in another process (the worker's result) it crashed the interpreter."""
    import pickle
    import subprocess
    import sys

    symbols = [cl.parse_term(t) for t in ('f(a,-1,"x\\"y")', "#inf", "(1,b)", "-g(c)")]
    blob = pickle.dumps(symbols)
    code = ("import pickle, sys; from symlearn.logic.asp import clingo_adapter; "
            "print(' '.join(map(str, pickle.loads(sys.stdin.buffer.read()))))")
    done = subprocess.run([sys.executable, "-c", code], input=blob, capture_output=True, timeout=60)
    assert done.returncode == 0 and done.stdout.decode().strip() == " ".join(map(str, symbols))
    hypothesis = Hypothesis.from_text(":- a.\nb :- c.", source="h.lp")
    copy = pickle.loads(pickle.dumps(hypothesis))
    assert copy == hypothesis and copy.lengths == [1, 2] and copy.program().locate(2, 1) == ("h.lp", 2, 1)


def test_include_in_a_program_file(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "inner.lp").write_text("b :- a.\n")
    main = tmp_path / "main.lp"
    main.write_text('a. #include "sub/inner.lp". c :- b.\n')
    program = Program.from_file(main)
    assert [sorted(map(str, m)) for m in answer_sets(program)] == [["a", "b", "c"]]
    assert [p.source for p in program.parts] == [str(main), str(tmp_path / "sub" / "inner.lp"), str(main)]


def test_lp_header_names_the_task_to_recheck_against(tmp_path):
    path = tmp_path / "rules.lp"
    Hypothesis([":- a."], provenance={"task": "kb/hanoi.las"}).to_lp(path)
    assert f"% edit the rules below; re-check with: symlearn ilp check kb/hanoi.las {path}\n" in path.read_text()
    assert "symlearn ilp check TASK.las THIS.lp" in Hypothesis([":- a."]).lp_text()  # task unknown
