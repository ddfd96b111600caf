import pytest
from hypothesis import given, settings, strategies as st

from ltlf_strategies import formulas
from symlearn.errors import ParseError, SymlearnError
from symlearn.logic.ltlf import (
    FALSE, TRUE, Always, And, Eventually, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until, WeakNext,
    operator_count, parse, size, to_latex, to_string,
)

a, b, c = Prop("a"), Prop("b"), Prop("c")


@pytest.mark.parametrize("text, expected", [
    ("a & b | c", Or(And(a, b), c)),
    ("a | b & c", Or(a, And(b, c))),
    ("a && b || c", Or(And(a, b), c)),
    ("!a U b", Until(Not(a), b)),
    ("F a U b", Until(Eventually(a), b)),
    ("a U b U c", Until(a, Until(b, c))),
    ("a U b & c", And(Until(a, b), c)),
    ("a -> b -> c", Implies(a, Implies(b, c))),
    ("a & b & c", And(And(a, b), c)),
    ("~a", Not(a)),
    ("X[!] a", Next(a)),
    ("N a", WeakNext(a)),
    ("WX a", WeakNext(a)),
    ("a T b", Then(a, b)),
    ("Fa", Eventually(a)),
    ("true | false", Or(TRUE, FALSE)),
    ("1 & 0", And(TRUE, FALSE)),
    ('"Door open" & "true"', And(Prop("Door open"), Prop("true"))),
    ('"say \\"hi\\""', Prop('say "hi"')),
    ("trueish", Prop("trueish")),
    ("¬a ∧ ◇b → □c", Implies(And(Not(a), Eventually(b)), Always(c))),
])
def test_parses_with_the_documented_precedence(text, expected):
    assert parse(text) == expected


def test_dialects_disagree_on_bare_x_and_arrow_grouping():
    assert parse("X a") == Next(a) == parse("X a", "ltlf2dfa")
    assert parse("X a", "spot") == WeakNext(a)
    assert parse("X[!] a", "spot") == Next(a)
    assert parse("a -> b <-> c") == Iff(Implies(a, b), c)
    assert parse("a -> b <-> c", "spot") == Implies(a, Iff(b, c))
    assert to_string(Next(a), "spot") == "X[!] a"
    assert to_string(WeakNext(a), "spot") == "X a"
    assert to_string(Iff(Implies(a, b), c), "spot") == "(a -> b) <-> c"


def test_printing_styles():
    f = parse("G(a -> X b) & !c")
    assert to_string(f) == "G(a -> X b) & !c"
    assert to_string(f, style="unicode") == "G(a → X b) ∧ ¬c"
    assert to_latex(f) == r"\mathsf{G}\left(a \rightarrow \mathsf{X} b\right) \land \lnot c"
    assert f._repr_latex_().startswith("$") and str(f) == to_string(f)
    assert size(f) == 8 and operator_count(f) == 5


@settings(max_examples=300, deadline=None)
@given(formulas(names=st.sampled_from(["x_1", "_y", "Door open", "true", 'q"uote', "back\\slash"])))
def test_printing_then_parsing_gives_the_same_formula_in_every_dialect(f):
    for dialect in ("ours", "spot", "ltlf2dfa"):
        assert parse(to_string(f, dialect), dialect) == f
    assert parse(to_string(f, style="unicode")) == f
    assert hash(parse(str(f))) == hash(f)


def _error(text, dialect="ours"):
    with pytest.raises(ParseError) as info:
        parse(text, dialect)
    return info.value


def test_syntax_error_shows_a_caret_and_what_was_expected():
    err = _error("a & & b")
    assert err.column == 5 and err.line == 1
    assert "unexpected '&' at column 5" in err.message
    assert "a proposition" in err.message
    lines = err.message.split("\n")
    assert lines[1] == "  a & & b" and lines[2] == "      ^"
    assert "end of formula" in _error("F (a |").message
    assert "expected ')'" in _error("(a").message


@pytest.mark.parametrize("text, hint", [
    ("a &&& b", "'&' or '&&'"),
    ("a => b", "'->'"),
    ("a <=> b", "'<->'"),
    ("<> a", "'F'"),
    ("[] a", "'G'"),
    ("a and b", "'&'"),
    ("a or b", "'|'"),
    ("A & b", 'quote other names: "A"'),
    ("a M b", "strong release"),
    ("a V b", "'R'"),
    ("Y a", "past-time"),
    ("a == b", "'<->'"),
    ("a ^ b", "exclusive or"),
    ("X[ a", "X[!]"),
])
def test_unknown_operators_suggest_the_right_spelling(text, hint):
    err = _error(text)
    assert err.hint and hint in err.hint, err


def test_other_bad_inputs():
    assert "empty formula" in _error("   ").message
    with pytest.raises(ParseError, match="unknown LTLf dialect"):
        parse("a", "lola")
    err = parse_error_in_file()
    assert (err.file, err.line) == ("specs.txt", 7)


def parse_error_in_file():
    with pytest.raises(ParseError) as info:
        parse("a |", source="specs.txt", line=7)
    return info.value


def test_deep_nesting_parses_and_prints_without_recursion_errors():
    text = "(" * 3000 + "a" + ")" * 3000
    assert parse(text) == a
    deep = a
    for _ in range(3000):
        deep = Not(Next(deep))
    assert parse(str(deep)) == deep


@settings(max_examples=500, deadline=None)
@given(st.one_of(st.text(max_size=40),
                 st.text(alphabet="ab()!&|-<>XFGURWTN[] ~\"01\\", max_size=40)))
def test_fuzz_parser_only_raises_symlearn_errors(text):
    try:
        parse(text)
    except SymlearnError:
        pass


def test_ltlf2dfa_dialect_binds_release_tighter_and_prints_no_chains():
    assert parse("a R b U c", "ltlf2dfa") == Until(Release(a, b), c)
    assert parse("a R b U c") == Release(a, Until(b, c))
    assert to_string(Until(a, Until(b, c)), "ltlf2dfa") == "a U (b U c)"
    assert to_string(Implies(a, Implies(b, c)), "ltlf2dfa") == "a -> (b -> c)"
    assert to_string(Until(Release(a, b), c), "ltlf2dfa") == "a R b U c"
