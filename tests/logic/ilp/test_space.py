"""Hypothesis-space generation: complete up to renaming, and nothing merged that differs."""

import itertools
import re

import pytest

from symlearn.errors import SymlearnError
from symlearn.logic.ilp import generate_space, learn, parse_task


def _canonical(rule: str) -> tuple:
    """Brute force: minimum over all renamings of the sorted body (independent of space.py)."""
    body = rule[3:-1].split(", ")
    names = sorted(set(re.findall(r"V\d+", rule)))
    forms = []
    for perm in itertools.permutations(range(len(names))):
        mapping = dict(zip(names, (f"X{p}" for p in perm)))
        forms.append(tuple(sorted(re.sub(r"V\d+", lambda m: mapping[m.group(0)], lit) for lit in body)))
    return min(forms)


def _brute_force_space(max_vars: int) -> set:
    """All constraints with 1..2 on/2 literals and at most one '<', every way to name variables."""
    rules = set()
    names = [f"V{i}" for i in range(1, max_vars + 1)]
    for n_on in (1, 2):
        for with_less in (False, True):
            slots = 2 * n_on + (2 if with_less else 0)
            for values in itertools.product(names, repeat=slots):
                on = [f"on({values[2 * i]},{values[2 * i + 1]})" for i in range(n_on)]
                lits = list(on)
                if with_less:
                    a, b = values[-2:]
                    if a == b or not {a, b} <= set(values[:2 * n_on]):
                        continue  # trivial or unsafe
                    lits.append(f"{a} < {b}")
                if len(set(lits)) < len(lits):
                    continue
                rules.add(_canonical(":- " + ", ".join(lits) + "."))
    return rules


def test_space_is_exactly_the_rules_up_to_renaming():
    task = parse_task("#modeb(2, on(var(d), var(d)), (positive)).\n#modeb(1, var(d) < var(d)).\n#maxv(3).\n"
                      "#pos(p, {}, {}, {}).\n")
    space = generate_space(task)
    generated = [_canonical(c.text) for c in space]
    assert len(generated) == len(set(generated)), "a rule appears twice up to renaming"
    assert set(generated) == _brute_force_space(3)
    texts = {c.text for c in space}
    # regression: the two directions of the comparison are different rules and both are kept
    assert ":- on(V1,V2), V1 < V2." in texts and ":- on(V1,V2), V2 < V1." in texts
    # regression: with a repeated mode, chains, forks and cycles are all distinct rules
    for shape in ("on(V1,V2), on(V2,V3)", "on(V1,V2), on(V1,V3)", "on(V1,V2), on(V3,V2)", "on(V1,V2), on(V2,V1)"):
        assert sum(_canonical(f":- {shape}.") == g for g in generated) == 1, shape


def test_symmetric_rule_is_learned_in_both_numberings():
    """Only a careful symmetry treatment keeps the rule needed for each numbering of the disks."""
    def task(numbering_large_first: bool):
        small_on_big = "on(2,1)" if numbering_large_first else "on(1,2)"
        big_on_small = "on(1,2)" if numbering_large_first else "on(2,1)"
        return parse_task(f"#pos(p, {{}}, {{}}, {{ {small_on_big}. }}).\n#neg(n, {{}}, {{}}, {{ {big_on_small}. }}).\n"
                          "#modeb(1, on(var(d), var(d))).\n#modeb(1, var(d) < var(d)).\n")
    assert learn(task(True)).hypothesis.rules == [":- on(V1,V2), V1 < V2."]
    assert learn(task(False)).hypothesis.rules == [":- on(V1,V2), V2 < V1."]


def test_conditional_literal_variables_are_local_and_safe():
    task = parse_task("#modec(1, not onRoad(var(dir)) : dir(var(dir))).\n#modeb(1, go(const(direction))).\n"
                      "#constant(direction, north).\n#maxv(1).\n#pos(p, {}, {}, {}).\n")
    texts = {c.text for c in generate_space(task)}
    assert ":- not onRoad(V1) : dir(V1)." in texts
    assert ":- go(north), not onRoad(V1) : dir(V1)." in texts
    assert all("V2" not in t for t in texts)


def test_unsafe_and_useless_rules_are_not_generated():
    task = parse_task("#modeb(1, not p(var(t))).\n#modeb(1, p(var(t))).\n#modeb(1, var(t) < var(t)).\n"
                      "#pos(x, {}, {}, {}).\n")
    texts = {c.text for c in generate_space(task)}
    assert ":- not p(V1)." not in texts                 # unsafe
    assert ":- p(V1), not p(V1)." not in texts          # never fires
    assert ":- p(V1), V1 < V1." not in texts            # never fires
    assert ":- p(V1), not p(V2)." not in texts          # V2 unsafe
    assert ":- p(V1), V1 < V2." not in texts and ":- p(V1)." in texts


def test_head_variables_must_be_bound_and_bias_scores_rules():
    task = parse_task("#modeh(r(var(t))).\n#modeb(1, q(var(t))).\n#modeb(1, s(var(t))).\n#maxv(2).\n"
                      "#pos(x, {}, {}, {}).\n"
                      '#bias("penalty(1, head).").\n#bias("penalty(2, X) :- in_body(X).").\n'
                      '#bias(":- in_body(s(X)).").\n')
    space = generate_space(task)
    # r(V1) :- q(V2). is unsafe; every rule using s/1 positively is excluded by the bias constraint
    # (the negated literal is described as naf(s(var(1))), which the constraint does not match)
    assert [(c.text, c.cost) for c in space] == [("r(V1) :- q(V1).", 3), ("r(V1) :- q(V1), not s(V1).", 5)]


def test_empty_space_and_missing_constants_are_explained():
    task = parse_task("#modeb(1, p(const(colour))).\n#pos(x, {}, {}, {}).\n")
    space = generate_space(task)
    assert len(space) == 0 and "no #constant(colour" in space.notes[0]
    with pytest.raises(SymlearnError, match="makes the hypothesis space empty"):
        learn(task)
    with pytest.raises(SymlearnError, match="no #modeh, #modeb or #modec"):
        generate_space(parse_task("#pos(x, {}, {}, {}).\n"))


def test_dialects_decide_whether_body_atoms_may_be_negated():
    text = "#modeb(1, p(var(t))).\n#modeb(1, q(var(t))).\n#modeb(1, r(var(t)), (positive)).\n#maxv(1).\n"
    ilasp = {c.text for c in generate_space(parse_task(text))}
    fastlas = {c.text for c in generate_space(parse_task(text, dialect="fastlas"))}
    assert ":- p(V1), not q(V1)." in ilasp and ":- q(V1), not p(V1)." in ilasp
    assert not any("not r" in t for t in ilasp)  # (positive)
    assert not any("not" in t for t in fastlas) and fastlas < ilasp
    # the recall is shared by both polarities of a mode
    assert ":- p(V1), not p(V1)." not in ilasp and not any(t.count("p(") > 1 for t in ilasp)


# -- issue 15: hypothesis-space generation is fast, shows progress and stops at its timeout (class 9) --

FOUR_ARY = "#modeb(2, p(var(t),var(t),var(t),var(t))).\n#maxv({}).\n#pos(x, {{}}, {{}}, {{}}).\n"


def test_repeated_four_ary_modes_with_many_variables_are_fast():
    """The canonical form used to try every renaming of up to #maxv variables (8! per rule):
    #maxv 6/7 took 6 s / 9 s here, 8 several minutes. Now at most max_body! reorderings."""
    import time

    for maxv, size in ((6, 2135), (8, 2152)):
        start = time.perf_counter()
        space = generate_space(parse_task(FOUR_ARY.format(maxv), dialect="fastlas"))
        assert len(space) == size and time.perf_counter() - start < 3.0
    generated = [_canonical(c.text) for c in generate_space(parse_task(FOUR_ARY.format(4), dialect="fastlas"))]
    assert len(generated) == len(set(generated))  # each rule once up to renaming


def test_modes_that_read_alike_are_still_merged_up_to_renaming():
    """A mode declared twice (or for two types) can give the same rule from two mode multisets."""
    text = "#modeb(1, p(var(t))).\n#modeb(1, p(var(t))).\n#modeb(2, q(var(t),var(t))).\n#maxv(3).\n#pos(x, {}, {}, {}).\n"
    for dialect in ("ilasp", "fastlas"):
        generated = [_canonical(c.text) for c in generate_space(parse_task(text, dialect=dialect))]
        assert len(generated) == len(set(generated))


def test_generation_stops_at_its_timeout_and_shows_progress(capsys):
    from symlearn.errors import LimitExceededError
    from symlearn.progress import progress_bars

    task = parse_task(FOUR_ARY.format(8).replace("#modeb(2,", "#modeb(3,"), dialect="fastlas")
    with pytest.raises(LimitExceededError, match=r"time limit reached while generating the hypothesis space "
                                                 r"\(\d+ rules so far\)"):
        generate_space(task, timeout=0.3)
    with progress_bars(True):
        generate_space(parse_task(FOUR_ARY.format(3), dialect="fastlas"))
    assert "hypothesis space" in capsys.readouterr().err
