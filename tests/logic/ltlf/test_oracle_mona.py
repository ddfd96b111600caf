"""Cross-checks against LTLf2DFA + MONA (and Spot when it can be imported)."""

import importlib.util
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from ltlf_oracle import compare
from ltlf_strategies import formulas
from symlearn.logic.ltlf import parse, to_string, translate
from symlearn.logic.ltlf.ast import (
    Always, And, Const, Eventually, Iff, Implies, Next, Not, Or, Prop, Release, Until, WeakNext, subformulas,
)

MONA = importlib.util.find_spec("ltlf2dfa") is not None and shutil.which("mona") is not None
pytestmark = [pytest.mark.oracle, pytest.mark.skipif(not MONA, reason="needs ltlf2dfa and the mona program")]

FORMULAS_TXT = Path(__file__).resolve().parents[3].parent / "shared/benchmarks/ltlf_learning/formulas.txt"


def _lines():
    if not FORMULAS_TXT.is_file():
        return []
    return [line.strip() for line in FORMULAS_TXT.read_text().splitlines() if line.strip()]


def _check(f):
    from symlearn.logic.ltlf.mona import mona_dfa

    ours = translate(f, max_states=200_000)
    problems = compare(ours, mona_dfa(f))
    assert not problems, problems


@pytest.mark.parametrize("text", ["true", "false", "a", "!a", "X a", "WX a", "G a", "F a & G !a", "a R b",
                                  "a W b", "a T b", "!(a U b)", "X X a <-> WX b", "G(a -> X b) & F c"])
def test_corner_cases_agree_with_mona(text):
    _check(parse(text))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(formulas(max_leaves=9))
def test_random_formulas_agree_with_mona(f):
    _check(f)


_ALL = _lines()
_FAST = _ALL[::8] + _ALL[-11:-9]  # every family, and two of the large counter formulas


@pytest.mark.skipif(not _ALL, reason="benchmark formulas not present")
@pytest.mark.parametrize("index", range(len(_FAST)))
def test_benchmark_formulas_subset_agree_with_mona(index):
    _check(parse(_FAST[index], "spot"))


@pytest.mark.slow
@pytest.mark.skipif(not _ALL, reason="benchmark formulas not present")
@pytest.mark.parametrize("index", range(len(_ALL)))
def test_all_201_benchmark_formulas_agree_with_mona(index):
    _check(parse(_ALL[index], "spot"))


def _spot_word_formula(word, props):
    steps = []
    for i, label in enumerate(word):
        lits = " & ".join(p if p in label else f"!{p}" for p in props)
        steps.append("X " * i + f"(alive & {lits})")
    steps.append("X " * len(word) + "G !alive")
    return " & ".join(steps)


def test_spot_agrees_when_installed():
    spot = pytest.importorskip("spot")
    import itertools

    from symlearn.logic.ltlf import to_string

    for text in ["F a & F b", "G(a -> X b)", "a U b U c", "X a", "X[!] a", "a R (b | X[!] c)"]:
        f = parse(text, "spot")
        ours = translate(f)
        theirs = spot.translate(spot.from_ltlf(spot.formula(to_string(f, "spot"))))
        props = ["a", "b", "c"]
        letters = [frozenset(c) for n in range(4) for c in itertools.combinations(props, n)]
        for length in range(1, 4):
            for word in itertools.product(letters, repeat=length):
                check = spot.translate(_spot_word_formula(word, props))
                assert ours.accepts(word) == theirs.intersects(check), (text, word)


_CORE = (Prop, Const, Not, And, Or, Implies, Iff, Next, WeakNext, Eventually, Always, Until, Release)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(formulas(max_leaves=7).filter(lambda f: all(isinstance(n, _CORE) for n in subformulas(f))))
def test_ltlf2dfa_dialect_text_means_the_same_to_ltlf2dfa(f):
    from symlearn.logic.ltlf.mona import mona_dfa

    problems = compare(translate(f), mona_dfa(f, printed=True))
    assert not problems, (to_string(f, "ltlf2dfa"), problems)
