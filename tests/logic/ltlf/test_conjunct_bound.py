"""The a-priori bounds of symlearn.logic.ltlf.conjunct_bound: they refuse only what the exploration
would refuse too (soundness), and they refuse the products of many independent conjuncts at once."""

from __future__ import annotations

import random
import time

import pytest

from symlearn.errors import LimitExceededError
from symlearn.logic.ltlf import parse, translate
from symlearn.logic.ltlf import conjunct_bound
from symlearn.logic.ltlf.to_dfa import _AND, _FF, _LIT, _NLIT, _TT, _Translation

TEMPLATES = ["F a", "G(a -> X b)", "a U b", "G(a -> F b)", "X X a", "!a", "a & !a", "F(a & X b)", "WX a", "G a",
             "a R b", "X a", "a T b", "X(a | WX b)", "F a | G b", "!(a U b)", "G(a -> WX !a)", "a W b"]


def _conjunction(rng: random.Random, groups: int) -> str:
    parts = []
    for g in range(groups):
        text = rng.choice(TEMPLATES)
        parts.append("(" + text.replace("a", f"g{g}x").replace("b", f"g{g}y") + ")")
    return " & ".join(parts)


def _outcome(formula, max_states: int) -> str:
    try:
        return f"{translate(formula, max_states=max_states).n_states} states"
    except LimitExceededError as exc:
        return "refused: " + str(exc)


def test_groups_share_nothing():
    t = _Translation(parse(" & ".join(["F a", "G(a -> b)", "X c", "F d", "G !e", "c U f", "X X g", "h", "F i"])))
    groups = conjunct_bound.independent_groups(t.nodes, t.root, _AND, (_LIT, _NLIT), (_TT, _FF))
    names = sorted(sorted({t.nodes[n][1] for g in [group] for op in g for n in _below(t, op)
                           if t.nodes[n][0] in (_LIT, _NLIT)}) for group in groups)
    assert names == [["a", "b"], ["c", "f"], ["d"], ["e"], ["g"], ["h"], ["i"]]


def _below(t: _Translation, nid: int) -> set[int]:
    seen, stack = set(), [nid]
    while stack:
        n = stack.pop()
        if n not in seen:
            seen.add(n)
            key = t.nodes[n]
            if key[0] not in (_LIT, _NLIT, _TT, _FF):
                stack += key[1:]
    return seen


def test_the_bound_refuses_only_what_the_exploration_refuses(monkeypatch):
    """Random conjunctions of 8-11 independent small formulas at small state limits: wherever the
    bound refuses, the translation without it refuses too; where it does not, both agree."""
    rng = random.Random(26)
    cases = [(parse(_conjunction(rng, rng.randint(8, 11))), rng.choice([20, 60, 200, 600])) for _ in range(40)]
    with_bound = [_outcome(f, m) for f, m in cases]
    monkeypatch.setattr(conjunct_bound, "MIN_GROUPS", 10**9)  # the exploration alone
    without = [_outcome(f, m) for f, m in cases]
    early = 0
    for a, b in zip(with_bound, without):
        if "independent conjuncts" in a:
            early += 1
            assert b.startswith("refused"), (a, b)
        else:
            assert a == b
    assert early >= 5 and sum(not a.startswith("refused") for a in with_bound) >= 5


def test_the_width_bound_refuses_only_what_the_node_limit_refuses(monkeypatch):
    """With a small node limit, a refusal for the width of the first transitions in name order
    is one the exploration meets too (it must build that BDD)."""
    monkeypatch.setenv("SYMLEARN_MAX_TRANSLATION_NODES", "3000")
    formulas = [" & ".join(f"G(!p{i} | q{i})" for i in range(1, n + 1)) for n in (8, 10, 12)]
    formulas.append(" & ".join(f"G(!a{i}p | a{i}q)" for i in range(1, 13)))  # sorted together: small
    with_bound = [_outcome(parse(f), 10**6) for f in formulas]
    monkeypatch.setattr(conjunct_bound, "MIN_GROUPS", 10**9)
    without = [_outcome(parse(f), 10**6) for f in formulas]
    assert "interleave in name order" in with_bound[-2] and without[-2].startswith("refused")
    assert with_bound[-1] == without[-1] == "2 states"
    for a, b in zip(with_bound, without):
        assert not a.startswith("refused") or b.startswith("refused"), (a, b)


@pytest.mark.parametrize("text, words", [
    (" & ".join(f"F p{i}" for i in range(2000)), "reach at least about 10^602 combinations"),
    (" & ".join(f"G(p{i} -> F q{i})" for i in range(500)), "500 independent conjuncts"),
    (" & ".join(f"G(!p{i} | q{i})" for i in range(2000)), "interleave in name order"),
])
def test_products_of_many_conjuncts_are_refused_before_the_work(text, words):
    start = time.perf_counter()
    with pytest.raises(LimitExceededError) as caught:
        translate(parse(text))
    assert words in str(caught.value)
    assert time.perf_counter() - start < 5


def test_many_independent_conjuncts_below_the_limits_still_translate():
    assert translate(parse(" & ".join(f"F p{i}" for i in range(12)))).n_states == 4096
    assert translate(parse(" & ".join(f"G p{i}" for i in range(2000)))).n_states == 2
    dfa = translate(parse(" & ".join(f"X p{i}" for i in range(2000)) + " & F z"))
    assert dfa.accepts([set(), {f"p{i}" for i in range(2000)} | {"z"}])
    assert not dfa.accepts([set(), {f"p{i}" for i in range(1999)} | {"z"}])


def test_balanced_junctions_give_the_same_automata(monkeypatch):
    """Joining long junctions in a balanced order (NNF trees, and runs in a state's obligation) is
    only a different order of the same Boolean operations: forced on every junction of two or more,
    the DFAs are identical (== compares states, acceptance and guards)."""
    import importlib

    to_dfa = importlib.import_module("symlearn.logic.ltlf.to_dfa")  # the module (the package exports a function)
    rng = random.Random(7)
    texts = [_conjunction(rng, rng.randint(2, 5)) for _ in range(30)]
    texts += [" | ".join(f"(F g{i}x & G g{i}y)" for i in range(4)), "G(a & b & c & d) & F(e | f | g | h)"]
    expected = [translate(parse(t)) for t in texts]
    monkeypatch.setattr(to_dfa, "_LONG_JUNCTION", 1)
    monkeypatch.setattr(to_dfa, "_LONG_RUN", 0)
    assert [translate(parse(t)) for t in texts] == expected
