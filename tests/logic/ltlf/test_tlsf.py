"""Basic TLSF (SYNTCOMP's finite-trace format) read as one LTLf formula."""

from __future__ import annotations

import json

import pytest

from symlearn.errors import ParseError
from symlearn.logic.ltlf import parse
from symlearn.logic.ltlf.tlsf import MAX_DEPTH, parse_tlsf
from symlearn.logic.ltlf.to_dfa import equivalent

HEADER = 'INFO {\n  TITLE: "t"\n  DESCRIPTION: "d"\n  SEMANTICS: Finite,Moore\n  TARGET: Moore\n}\n'


def spec(main: str):
    return parse_tlsf(HEADER + "MAIN {\n" + main + "\n}\n", source="spec.tlsf")


def test_a_syntcomp_style_file():
    s = spec("  INPUTS {\n    p1;\n  }\n  OUTPUTS {\n    p2;\n  }\n  GUARANTEES {\n    (G(p1)) && (F(p2));\n  }")
    assert s.formula == parse("G p1 & F p2") and s.inputs == ("p1",) and s.outputs == ("p2",)
    assert s.info["TITLE"] == "t" and s.semantics == ("Finite", "Moore")


def test_strong_and_weak_next():
    s = spec("INPUTS { a; } OUTPUTS { b; } GUARANTEES { X[!] a; X b; }")
    assert s.formula == parse("X a & N b")  # under finite semantics TLSF's X is the weak next


def test_sections_combine_as_the_implication_semantics():
    s = spec("INPUTS { i; } OUTPUTS { o; } INITIALLY { !i; } PRESET { !o; } REQUIRE { i -> X[!] !i; } "
             "ASSERT { o -> i; } ASSUMPTIONS { F i; } GUARANTEES { F o; G (i || o); }")
    expected = parse("!i -> (!o & ((G (i -> X !i) & F i) -> (G (o -> i) & (F o & G (i | o)))))")
    assert s.formula == expected
    assert s.sections["GUARANTEES"] == (parse("F o"), parse("G (i | o)"))
    only_guarantees = spec("INPUTS { i; } OUTPUTS { o; } GUARANTEES { F o; }")
    assert only_guarantees.formula == parse("F o")
    assumed = spec("INPUTS { i; } OUTPUTS { o; } ASSUMPTIONS { G F i; } GUARANTEES { F o; }")
    assert equivalent(assumed.formula, parse("G F i -> F o"))


def test_precedence_and_associativity():
    s = spec("INPUTS { a; b; c; } OUTPUTS { d; } GUARANTEES { a U b && c || d -> a -> b <-> c; a U b U c; !a R b W c; }")
    first, second, third = s.sections["GUARANTEES"]
    assert first == parse("((((a U b) & c) | d) -> (a -> b)) <-> c")
    assert second == parse("a U (b U c)") and third == parse("(!a) R (b W c)")


def test_comments_constants_and_empty_declarations():
    s = spec("// a comment\nINPUTS { a; ; } /* a\nlong one */ OUTPUTS { b; } GUARANTEES { true -> (false || G a); }")
    assert s.formula == parse("true -> (false | G a)") and s.inputs == ("a",)


@pytest.mark.parametrize("main, message, line", [
    ("INPUTS { a; } OUTPUTS { b; } GUARANTEES { G c; }", "names 'c', which is declared neither", 8),
    ("INPUTS { a; } OUTPUTS { a; } GUARANTEES { G a; }", "signal 'a' is declared twice", 8),
    ("INPUTS { a; } OUTPUTS { b; } GUARANTEES { G a }", "expected ';' after the formula", 8),
    ("INPUTS { a; } OUTPUTS { b; } GUARANTEES { G (a && b; }", "expected ')'", 8),
    ("INPUTS { a; } OUTPUTS { b; } GUARANTEES { a & b; }", "unexpected character '&'", 8),
    ("INPUTS { a; } OUTPUTS { b; } GUARDS { G a; }", "unknown MAIN section 'GUARDS'", 8),
    ("INPUTS { a; } OUTPUTS { b; } GUARANTEES { U a; }", "'U' needs a formula on its left", 8),
])
def test_mistakes_are_located(main, message, line):
    with pytest.raises(ParseError) as info:
        spec(main)
    assert message in info.value.message and info.value.file == "spec.tlsf" and info.value.line == line
    assert info.value.column is not None


def test_full_tlsf_is_refused_with_the_way_out():
    text = HEADER + "GLOBAL {\n  PARAMETERS { N = 2; }\n}\nMAIN { INPUTS { a; } OUTPUTS { b; } GUARANTEES { G a; } }"
    with pytest.raises(ParseError) as info:
        parse_tlsf(text, source="chomp.tlsf")
    assert "parameterised (full) TLSF" in info.value.message and info.value.line == 7
    assert "syfco -f basic" in info.value.hint
    with pytest.raises(ParseError, match="no MAIN section"):
        parse_tlsf(HEADER)
    with pytest.raises(ParseError, match="nests more than"):
        spec("INPUTS { a; } OUTPUTS { b; } GUARANTEES { " + "(" * (MAX_DEPTH + 5) + "a"
             + ")" * (MAX_DEPTH + 5) + "; }")


def test_the_cli_reads_tlsf_files(tmp_path, run_cli):
    path = tmp_path / "req.tlsf"
    path.write_text(HEADER + "MAIN { INPUTS { r; } OUTPUTS { g; } GUARANTEES { G (r -> X[!] g); } }")
    from_file = run_cli("ltl", "dfa", "--tlsf", path, "--json")
    written = run_cli("ltl", "dfa", "G (r -> X g)", "--json")
    assert from_file.returncode == 0, from_file.stderr
    a, b = json.loads(from_file.stdout), json.loads(written.stdout)
    assert (a["states"], a["edges"]) == (b["states"], b["edges"])
    parsed = run_cli("ltl", "parse", "--tlsf", path)
    assert parsed.returncode == 0 and parsed.stdout.startswith("G(r -> X g)")
    bad = tmp_path / "bad.tlsf"
    bad.write_text(HEADER + "MAIN { INPUTS { r; } OUTPUTS { g; } GUARANTEES { G (r -> X[!] h); } }")
    refused = run_cli("ltl", "dfa", "--tlsf", bad)
    assert refused.returncode == 2 and "bad.tlsf:7:" in refused.stderr and "'h'" in refused.stderr
    both = run_cli("ltl", "parse", "F a", "--tlsf", path)
    assert both.returncode == 2 and "not both" in both.stderr
