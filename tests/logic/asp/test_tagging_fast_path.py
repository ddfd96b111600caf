"""The text-level fast path of example tagging, predicate uses and rule length (issue 26,
``ilp check`` with many rules) against the AST walk it replaces, on thousands of generated rules.

Every generated rule goes both ways; the fast path must either decline (None: the AST way is
taken) or print exactly what the AST way prints."""

from __future__ import annotations

import random

import clingo
import clingo.ast
import pytest

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.hypothesis import rule_length
from symlearn.logic.asp.program import Program

NAMES = ["p", "q", "r", "at", "on'", "_s", "go", "wall", "aB1"]
VARIABLES = ["X", "Y", "Z", "_", "V1", "_W"]
CONSTANTS = ["a", "b", "c'", "0", "1", "-1", "42", "#inf", "#sup", "inf", "sup"]
STRINGS = ['"x"', '"a;b"', '"p(X) :- q, r."', '"with \\"quote\\""', '"%"']


def _term(rng: random.Random, depth: int = 0) -> str:
    roll = rng.random()
    if depth > 2 or roll < 0.45:
        return rng.choice(VARIABLES + CONSTANTS)
    if roll < 0.55:
        return rng.choice(STRINGS)
    if roll < 0.7:
        args = ",".join(_term(rng, depth + 1) for _ in range(rng.randint(1, 3)))
        return f"{rng.choice(['f', 'g', 'cell'])}({args})"
    if roll < 0.78:
        return "(" + ",".join(_term(rng, depth + 1) for _ in range(rng.randint(1, 3))) + rng.choice(["", ","]) + ")"
    if roll < 0.9:
        op = rng.choice(["+", "-", "*", "/", "\\", "**", "..", "&", "?", "^"])
        return f"{_term(rng, depth + 1)}{op}{_term(rng, depth + 1)}"
    if roll < 0.93:
        return f"-{_term(rng, depth + 1)}"
    if roll < 0.96:
        return f"|{_term(rng, depth + 1)}|"
    if roll < 0.98:
        return f"{_term(rng, depth + 1)};{_term(rng, depth + 1)}"  # a pool inside an argument
    return f"@h({_term(rng, depth + 1)})"


def _atom(rng: random.Random) -> str:
    name = rng.choice(NAMES)
    roll = rng.random()
    if roll < 0.2:
        atom = name
    elif roll < 0.9:
        atom = f"{name}({', '.join(_term(rng) for _ in range(rng.randint(1, 3)))})"
    else:  # a pool of atoms
        atom = f"{name}({_term(rng)};{_term(rng)})"
    return ("-" if rng.random() < 0.15 else "") + atom


def _literal(rng: random.Random) -> str:
    roll = rng.random()
    if roll < 0.55:
        return rng.choice(["", "", "", "not ", "not not "]) + _atom(rng)
    if roll < 0.85:
        op = rng.choice(["=", "!=", "<", "<=", ">", ">="])
        text = f"{_term(rng)} {op} {_term(rng)}"
        if rng.random() < 0.15:
            text += f" {rng.choice(['<', '<='])} {_term(rng)}"
        return ("not " if rng.random() < 0.1 else "") + text
    return rng.choice(["#true", "#false", "not #true", "not #false"])


def _body_element(rng: random.Random) -> str:
    roll = rng.random()
    if roll < 0.85:
        return _literal(rng)
    if roll < 0.93:  # a conditional literal
        return f"{_literal(rng)} : {', '.join(_literal(rng) for _ in range(rng.randint(1, 2)))}"
    function = rng.choice(["#count", "#sum", "#min", "#max"])
    elements = f"{_term(rng)} : {_literal(rng)}"
    return rng.choice([f"{_term(rng)} = {function} {{ {elements} }}", f"{function} {{ {elements} }} > 1",
                       f"not {function} {{ {elements} }} < 2"])


def _head(rng: random.Random) -> str:
    roll = rng.random()
    if roll < 0.45:
        return _atom(rng)
    if roll < 0.7:
        return ""  # an integrity constraint
    if roll < 0.75:
        return rng.choice(["#false", "#true", "not " + _atom(rng), "not not " + _atom(rng)])
    if roll < 0.82:
        return " ; ".join(_atom(rng) for _ in range(rng.randint(2, 3)))
    if roll < 0.87:
        return f"{_atom(rng)} : {_literal(rng)}"
    if roll < 0.95:
        elements = "; ".join(_atom(rng) + (f" : {_literal(rng)}" if rng.random() < 0.3 else "")
                             for _ in range(rng.randint(1, 3)))
        return rng.choice(["", "1 ", "X "]) + f"{{ {elements} }}" + rng.choice(["", " 2", " = 1"])
    return f"#count {{ {_term(rng)} : {_atom(rng)} : {_literal(rng)} }} = 1"


def _plain_term(rng: random.Random, depth: int = 0) -> str:
    roll = rng.random()
    if depth > 1 or roll < 0.6:
        return rng.choice(VARIABLES + CONSTANTS)
    if roll < 0.8:
        return f"{rng.choice(['f', 'cell'])}({','.join(_plain_term(rng, depth + 1) for _ in range(rng.randint(1, 2)))})"
    if roll < 0.9:
        return f"({_plain_term(rng, depth + 1)},{_plain_term(rng, depth + 1)})"
    return f"{_plain_term(rng, depth + 1)}{rng.choice(['+', '-', '*', '..'])}{_plain_term(rng, depth + 1)}"


def _plain_atom(rng: random.Random) -> str:
    name = rng.choice(NAMES)
    if rng.random() < 0.2:
        return name
    args = ", ".join(_plain_term(rng) for _ in range(rng.randint(1, 3)))
    return ("-" if rng.random() < 0.1 else "") + f"{name}({args})"


def _plain_literal(rng: random.Random) -> str:
    if rng.random() < 0.7:
        return rng.choice(["", "", "", "not ", "not not "]) + _plain_atom(rng)
    return f"{_plain_term(rng)} {rng.choice(['=', '!=', '<', '<=', '>', '>='])} {_plain_term(rng)}"


def _rule(rng: random.Random) -> str:
    if rng.random() < 0.5:  # what learned and edited rules look like: mostly the fast path
        head = rng.choice(["", _plain_atom(rng)])
        body = rng.choice([", ", "; "]).join(_plain_literal(rng) for _ in range(rng.randint(0 if head else 1, 4)))
        return (f"{head} :- {body}." if head else f":- {body}.") if body else f"{head}."
    head = _head(rng)
    n_body = rng.randint(0 if head else 1, 4)
    body = rng.choice([", ", "; "]).join(_body_element(rng) for _ in range(n_body))
    if not body:
        return f"{head}."
    return f"{head} :- {body}." if head else f":- {body}."


def _generated(n: int, seed: int) -> list[clingo.ast.AST]:
    """``n`` generated rules that clingo parses (the others are skipped)."""
    rng = random.Random(seed)
    statements: list[clingo.ast.AST] = []
    while len(statements) < n:
        text = _rule(rng)
        parsed: list[clingo.ast.AST] = []
        try:
            clingo.ast.parse_string(text, parsed.append, logger=lambda _c, _m: None)
        except RuntimeError:
            continue
        statements.extend(s for s in parsed if s.ast_type == clingo.ast.ASTType.Rule)
    return statements[:n]


def _tagger(tag: str, guard: tuple[str, ...], constraint_head: str | None, untagged: frozenset[str]) -> cl._Tagger:
    parsed: list[clingo.ast.AST] = []
    guard_text = ", ".join(guard)
    clingo.ast.parse_string(f"__probe({tag}) :- {guard_text}." if guard_text else f"__probe({tag}).", parsed.append)
    rule = parsed[-1]
    return cl._Tagger(rule.head.atom.symbol.arguments[0], list(rule.body), constraint_head, untagged)


SETTINGS = [("E__", ("active__(E__)",), None, frozenset()),
            ("3", ("active__(3)",), "excluded__", frozenset()),
            ("E", ("ex(E)", "not off(E)"), "c__", frozenset({"q", "wall"})),
            ("R__", (), None, frozenset({"p"})),
            ("-1", ("x(-1)",), "h", frozenset())]


@pytest.mark.parametrize("tag, guard, constraint_head, untagged", SETTINGS)
def test_fast_tagging_prints_what_the_ast_rewrite_prints(tag, guard, constraint_head, untagged):
    rules = _generated(2000, seed=len(tag) + len(guard))
    tagger = _tagger(tag, guard, constraint_head, untagged)
    guard_texts = [str(g) for g in tagger.guard]
    fast = 0
    for statement in rules:
        printed = str(statement)
        new = cl._tag_simple(printed, str(tagger.tag), guard_texts, constraint_head, untagged)
        try:
            old = str(tagger.visit(statement))
        except cl.ParseError:
            assert new is None, printed
            continue
        if new is not None:
            fast += 1
            assert new == old, printed
    # the generator exercises both ways
    assert 500 < fast < len(rules) - 500


def test_fast_predicate_uses_and_rule_length_match_the_ast_walk():
    rules = _generated(3000, seed=7)
    fast = 0
    for statement in rules:
        printed = str(statement)
        simple = cl._simple_rule(printed)
        walked = cl._atom_uses(statement)
        assert cl.simple_rule_length(printed) in (None, _ast_rule_length(statement)), printed
        if simple is None:
            continue
        fast += 1
        head, body = simple
        signatures = ([(head[1], head[3], True)] if head is not None else []) + \
            [(b[1], b[3], False) for b in body if not isinstance(b, str)]
        assert signatures == [(u.name, u.arity, u.defines) for u in walked], printed
    assert fast > 1000


def _ast_rule_length(statement: clingo.ast.AST) -> int:
    """rule_length through the AST only (the text shortcut switched off)."""
    saved = cl.simple_rule_length
    cl.simple_rule_length = lambda _text: None
    try:
        return rule_length(statement)
    finally:
        cl.simple_rule_length = saved


def _program(n: int, seed: int) -> Program:
    """Generated rules as a file: one or two a line, some over two lines, comments between."""
    rng = random.Random(seed)
    lines = []
    for statement in _generated(n, seed):
        text = str(statement)
        roll = rng.random()
        if roll < 0.1 and " :- " in text and '"' not in text:
            lines.extend(text.replace(" :- ", " :-  % split\n    ", 1).split("\n"))
        elif roll < 0.2 and lines:
            lines[-1] += "  " + text
        else:
            lines.append(text)
        if rng.random() < 0.05:
            lines.append("% a comment")
    return Program.from_text("\n".join(lines) + "\n", source="gen.lp", line=3, column=1)


def test_whole_programs_tag_and_locate_the_same_both_ways(monkeypatch):
    program = _program(1000, seed=11)
    pieces = [(program, "E__", ("active__(E__)",))]
    fast_tagged = cl.tag_programs_located(pieces, constraint_head="x__")[0]
    fast_uses = cl.PredicateUses(program)
    fast_located = [fast_uses.located(i) for i in range(len(fast_uses))]
    monkeypatch.setattr(cl, "_simple_rule", lambda _text: None)  # every rule the AST way
    slow_tagged = cl.tag_programs_located(pieces, constraint_head="x__")[0]
    slow_uses = cl.PredicateUses(program)
    assert fast_tagged.text == slow_tagged.text
    assert fast_tagged.parts[0].positions == slow_tagged.parts[0].positions
    lines = fast_tagged.text.count("\n") + 1
    assert [fast_tagged.locate(i, 1) for i in range(1, lines + 1)] == \
        [slow_tagged.locate(i, 1) for i in range(1, lines + 1)]
    assert fast_uses.signatures == slow_uses.signatures
    assert fast_located == [slow_uses.located(i) for i in range(len(slow_uses))] == cl.predicate_uses(program)


def test_undefined_predicates_are_located_in_the_file_as_before(monkeypatch):
    from symlearn.logic.asp.predicates import undefined_predicates

    program = _program(1500, seed=5)
    fast = [u.as_dict() for u in undefined_predicates(program, {("p", 1), ("at", 2)})]
    monkeypatch.setattr(cl, "_simple_rule", lambda _text: None)
    assert fast == [u.as_dict() for u in undefined_predicates(program, {("p", 1), ("at", 2)})]
    assert fast  # the generated file uses predicates that nothing defines
