"""The lark-free reader agrees with the lark grammar wherever it answers, and gives up otherwise."""

import random
from pathlib import Path

import pytest
from hypothesis import given, settings

from ltlf_strategies import formulas
from symlearn.errors import ParseError
from symlearn.logic.ltlf import parse, to_string
from symlearn.logic.ltlf.fast_parser import read
from symlearn.logic.ltlf.parser import DIALECTS, _parser

FORMULAS_TXT = Path(__file__).resolve().parents[3].parent / "shared/benchmarks/ltlf_learning/formulas.txt"
TOKENS = ["a", "b", "c1", "true", "false", "1", "0", "trueish", "X", "X[!]", "WX", "N", "F", "G", "!", "~", "U", "R",
          "W", "T", "&", "&&", "|", "||", "->", "<->", "(", ")", " ", "\u2194", "\u2192", "\u00ac", "\u25c7", "\u25a1",
          "\u25cb", "\u2227", "\u2228", "\u22a4", "\u22a5", '"x y"', '"a\\"b"', "\t", "\n", "Fa", "aU", "&&&", "=>",
          "[", "Foo", "_x", "WXa"]


def lark(text: str, dialect: str):
    from lark.exceptions import UnexpectedInput

    try:
        return _parser(dialect).parse(text)
    except UnexpectedInput:
        return None


def agree(text: str) -> None:
    for dialect in DIALECTS:
        expected, got = lark(text, dialect), read(text, dialect)
        assert got == expected, (dialect, text)  # same formula, or both give up / refuse


@settings(max_examples=150, deadline=None)
@given(formulas(max_leaves=10))
def test_printed_formulas_read_the_same_in_every_dialect(f):
    for dialect in DIALECTS:
        for style in ("ascii", "unicode"):
            agree(to_string(f, dialect, style=style))


def test_token_soup_agrees_with_the_grammar():
    rng = random.Random(16)
    for _ in range(1500):
        words = [rng.choice(TOKENS) for _ in range(rng.randint(1, 8))]
        agree("".join(words))
        agree(" ".join(words))


@pytest.mark.skipif(not FORMULAS_TXT.is_file(), reason="benchmark formulas not present")
def test_benchmark_formulas_read_without_lark():
    for text in FORMULAS_TXT.read_text().splitlines()[::5]:
        if text.strip():
            assert read(text, "spot") is not None and read(text, "spot") == lark(text, "spot")


def test_errors_and_deep_nesting_still_go_through_the_grammar():
    with pytest.raises(ParseError, match="unexpected '&' at column 5"):
        parse("a & & b")
    deep = "(" * 3000 + "a" + ")" * 3000
    assert read(deep, "ours") is None  # too deep for recursive descent: lark reads it
    assert parse(deep) == parse("a")
    assert parse("!" * 5000 + "a").arg.arg is not None  # unary runs are not recursive
