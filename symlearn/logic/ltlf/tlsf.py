"""Basic TLSF specifications (the SYNTCOMP format) read as one LTLf formula.

The finite-trace benchmarks of the LTLf synthesis community (SYNTCOMP's ``tlsf-fin``) are
written in TLSF (Jacobs, Klein and Schirmer, *A High-Level LTL Synthesis Format: TLSF v1.1*).
This reader takes the *basic* fragment, the one every file of those families but the
parameterised ones is written in::

    INFO { TITLE: "..." DESCRIPTION: "..." SEMANTICS: Finite,Moore TARGET: Moore }
    MAIN {
      INPUTS { a; b; }          OUTPUTS { c; }
      INITIALLY { ... }  PRESET { ... }  REQUIRE { ... }  ASSERT { ... }  (each optional)
      ASSUMPTIONS { f; ... }    GUARANTEES { g; ... }
    }

Formulas use ``! && || -> <-> X X[!] F G U R W`` and ``true``/``false``; ``//`` and ``/* */`` are
comments. Under finite semantics ``X`` is the *weak* next (our ``N``) and ``X[!]`` the strong next
(our ``X``). The sections combine as TLSF's (non-strict) implication semantics does::

    INITIALLY -> (PRESET && ((G REQUIRE && ASSUMPTIONS) -> (G ASSERT && GUARANTEES)))

where a section stands for the conjunction of its formulas and an empty one for ``true``.
``INVARIANTS`` is accepted as TLSF's older name of ``ASSERT``. A file with a ``GLOBAL`` section
(parameters, definitions, buses, big operators) is full TLSF: it is refused with a message saying
how to get its basic form (``syfco -f basic -op N=3 FILE``). A formula naming a signal that is
declared neither input nor output is an error, as is a signal declared twice.

Precedence, tightest first: the unary operators, then ``U R W`` (right-associative), ``&&``,
``||``, ``->`` (right-associative), ``<->``. Errors name the file, line and column.

>>> spec = parse_tlsf('INFO { SEMANTICS: Finite,Moore TARGET: Moore } '
...                   'MAIN { INPUTS { r; } OUTPUTS { g; } GUARANTEES { G (r -> X[!] g); } }')
>>> str(spec.formula), spec.inputs, spec.outputs
('G(r -> X g)', ('r',), ('g',))
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from symlearn.errors import ParseError
from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Until, WeakNext,
    WeakUntil, conjunction, propositions,
)

#: deepest nesting of parentheses and operators read (a deeper file is refused, not overflowed;
#: the SYNTCOMP files nest at most 20 deep)
MAX_DEPTH = 100

_SECTIONS = ("INITIALLY", "PRESET", "REQUIRE", "ASSERT", "INVARIANTS", "ASSUMPTIONS", "GUARANTEES",
             "ASSUME", "GUARANTEE")
_SIGNALS = ("INPUTS", "OUTPUTS")

_TOKEN = re.compile(r"""
    (?P<space>\s+|//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:[^"\\\n]|\\.)*")
  | (?P<op>X\[!\]|&&|\|\||<->|->|[{}();:,!])
  | (?P<name>[A-Za-z_][A-Za-z0-9_@'.]*)
  | (?P<other>.)
""", re.VERBOSE | re.DOTALL)


@dataclass(frozen=True)
class Token:
    kind: str  # "op", "name", "string", "end"
    text: str
    line: int
    column: int


@dataclass(frozen=True)
class TlsfSpec:
    """A basic TLSF file: its ``INFO`` fields, signals, sections and the one formula they mean."""

    formula: Formula
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    info: dict[str, str] = field(default_factory=dict)
    sections: dict[str, tuple[Formula, ...]] = field(default_factory=dict)

    @property
    def semantics(self) -> tuple[str, ...]:
        return tuple(s.strip() for s in self.info.get("SEMANTICS", "").split(",") if s.strip())


def _tokens(text: str, source: str | None) -> Iterator[Token]:
    line, line_start = 1, 0
    for match in _TOKEN.finditer(text):
        kind = match.lastgroup
        start = match.start()
        column = start - line_start + 1
        value = match.group()
        if kind == "other":
            raise ParseError(f"unexpected character {value!r}", file=source, line=line, column=column,
                             hint=_character_hint(value))
        if kind == "string" or kind == "op" or kind == "name":
            yield Token("op" if kind == "op" else kind, value, line, column)
        newlines = value.count("\n")
        if newlines:
            line += newlines
            line_start = start + value.rindex("\n") + 1
        if kind == "space" and value.startswith("/*") and not value.endswith("*/"):
            raise ParseError("unterminated comment", file=source, line=line, column=column)
    yield Token("end", "", line, len(text) - line_start + 1)


def _character_hint(char: str) -> str | None:
    return {"&": "write '&&' for 'and'", "|": "write '||' for 'or'", "[": "strong next is written 'X[!]'; "
            "buses (a[0]) and big operators (&&[i IN ...]) are full TLSF: convert with syfco -f basic",
            "=": "parameters and definitions are full TLSF (a GLOBAL section): convert with syfco -f basic",
            "<": "write '<->' or '->'"}.get(char)


class _Reader:
    def __init__(self, text: str, source: str | None) -> None:
        self.source = source
        self.tokens = list(_tokens(text, source))
        self.i = 0
        self.depth = 0

    # -- tokens ---------------------------------------------------------------------------------

    @property
    def peek(self) -> Token:
        return self.tokens[self.i]

    def take(self) -> Token:
        token = self.tokens[self.i]
        if token.kind != "end":
            self.i += 1
        return token

    def error(self, message: str, token: Token | None = None, hint: str | None = None) -> ParseError:
        token = token or self.peek
        return ParseError(message, file=self.source, line=token.line, column=token.column, hint=hint)

    def expect(self, text: str, what: str | None = None) -> Token:
        token = self.take()
        if token.text != text or token.kind == "string":
            found = "end of file" if token.kind == "end" else repr(token.text)
            raise self.error(f"expected {what or repr(text)}, found {found}", token)
        return token

    # -- sections -------------------------------------------------------------------------------

    def spec(self) -> TlsfSpec:
        info: dict[str, str] = {}
        main = None
        while self.peek.kind != "end":
            token = self.take()
            if token.text == "INFO":
                info = self.info_block()
            elif token.text == "MAIN":
                if main is not None:
                    raise self.error("a second MAIN section", token)
                main = self.main_block(token)
            elif token.text == "GLOBAL":
                raise self.error("this is a parameterised (full) TLSF file: its GLOBAL section defines parameters "
                                 "or functions, which basic TLSF does not have", token,
                                 hint="convert it with syfco's basic output first, e.g. "
                                      "`syfco -f basic -op N=3 FILE > basic.tlsf`, then read basic.tlsf")
            else:
                raise self.error(f"expected INFO, GLOBAL or MAIN, found {token.text!r}", token)
        if main is None:
            raise ParseError("no MAIN section", file=self.source, hint="a TLSF file has INFO { ... } MAIN { ... }")
        inputs, outputs, sections = main
        formula = _combine(sections)
        return TlsfSpec(formula, inputs, outputs, info, {k: tuple(v) for k, v in sections.items()})

    def info_block(self) -> dict[str, str]:
        self.expect("{", "'{' after INFO")
        info: dict[str, str] = {}
        while self.peek.text != "}":
            key = self.take()
            if key.kind != "name":
                raise self.error(f"expected an INFO field such as TITLE, found {key.text or 'end of file'!r}", key)
            self.expect(":", f"':' after {key.text}")
            parts = []
            first = self.peek
            while True:
                value = self.take()
                if value.kind == "end":
                    raise self.error("INFO is not closed with '}'", value)
                parts.append(value.text[1:-1] if value.kind == "string" else value.text)
                if self.peek.text != ",":
                    break
                self.take()
            if key.text == "SEMANTICS" and "finite" not in {p.strip().lower() for p in parts}:
                # Mealy/Moore alone mean infinite traces (LTL): the same formula read as LTLf means
                # something else, so translating it would silently answer another question
                raise self.error(f"SEMANTICS: {','.join(parts)} is infinite-trace (LTL) semantics; symlearn reads "
                                 "finite-trace TLSF (SEMANTICS: Finite,Moore or Finite,Mealy)", first,
                                 hint="a specification meant for finite traces says Finite in SEMANTICS")
            info[key.text] = ",".join(parts)
        self.take()
        return info

    def main_block(self, opening: Token):
        self.expect("{", "'{' after MAIN")
        declared: dict[str, tuple[str, Token]] = {}
        signals: dict[str, list[str]] = {"INPUTS": [], "OUTPUTS": []}
        sections: dict[str, list[Formula]] = {}
        pending: list[tuple[str, Formula, Token]] = []
        while self.peek.text != "}":
            head = self.take()
            if head.kind == "end":
                raise self.error("MAIN is not closed with '}'", opening)
            if head.text in _SIGNALS:
                self.expect("{", f"'{{' after {head.text}")
                while self.peek.text != "}":
                    if self.peek.text == ";":  # an empty declaration (some generated files have one)
                        self.take()
                        continue
                    name = self.take()
                    if name.kind != "name":
                        raise self.error(f"expected a signal name in {head.text}, found "
                                         f"{name.text or 'end of file'!r}", name)
                    if self.peek.text == "[":
                        raise self.error(f"signal {name.text!r} is a bus (full TLSF)", hint="convert with syfco -f basic")
                    if name.text in declared:
                        raise self.error(f"signal {name.text!r} is declared twice "
                                         f"(first in {declared[name.text][0]})", name)
                    declared[name.text] = (head.text, name)
                    signals[head.text].append(name.text)
                    self.expect(";", f"';' after {name.text}")
                self.take()
            elif head.text in _SECTIONS:
                key = {"INVARIANTS": "ASSERT", "ASSUME": "ASSUMPTIONS", "GUARANTEE": "GUARANTEES"}.get(head.text,
                                                                                                       head.text)
                self.expect("{", f"'{{' after {head.text}")
                while self.peek.text != "}":
                    start = self.peek
                    if start.kind == "end":
                        raise self.error(f"{head.text} is not closed with '}}'", head)
                    first = self.i
                    formula = self.formula()
                    self.expect(";", "';' after the formula (every formula in a section ends with ';')")
                    sections.setdefault(key, []).append(formula)
                    pending.append((key, formula, start, self.tokens[first:self.i]))
                self.take()
            else:
                raise self.error(f"unknown MAIN section {head.text!r}", head,
                                 hint="basic TLSF has INPUTS, OUTPUTS, INITIALLY, PRESET, REQUIRE, ASSERT, "
                                      "ASSUMPTIONS, GUARANTEES")
        self.take()
        known = set(declared)  # once: built per formula, n formulas over n signals cost n^2
        for section, formula, start, tokens in pending:
            unknown = sorted(propositions(formula) - known)
            if unknown:
                import difflib

                # at the name itself (the formula's start was named before), with the declared name meant
                where = next((t for t in tokens if t.text == unknown[0]), start)
                close = difflib.get_close_matches(unknown[0], sorted(known), n=1) or \
                    [k for k in sorted(known) if k.lower() == unknown[0].lower()]
                raise self.error(f"{section} names {unknown[0]!r}, which is declared neither in INPUTS nor in "
                                 "OUTPUTS", where, hint=f"did you mean {close[0]!r}?" if close else
                                 "declare it in INPUTS or OUTPUTS")
        return tuple(signals["INPUTS"]), tuple(signals["OUTPUTS"]), sections

    # -- formulas (precedence climbing) ---------------------------------------------------------

    def formula(self) -> Formula:
        return self.iff()

    def _enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self.error(f"the formula nests more than {MAX_DEPTH} levels deep")

    def _left_chain(self, symbol: str, node: type, operand) -> Formula:
        """``operand (symbol operand)*`` grouped to the left."""
        left = operand()
        while self.peek.text == symbol:
            self.take()
            left = node(left, operand())
        return left

    def iff(self) -> Formula:
        return self._left_chain("<->", Iff, self.implies)

    def _right_chain(self, nodes: dict[str, type], kind: str, level, operand) -> Formula:
        """``operand (symbol level)?`` grouped to the right (``level`` is the method itself)."""
        left = operand()
        node = nodes.get(self.peek.text)
        if node is None or self.peek.kind != kind:
            return left
        self.take()
        self._enter()
        right = level()
        self.depth -= 1
        return node(left, right)

    def implies(self) -> Formula:
        return self._right_chain({"->": Implies}, "op", self.implies, self.disjunction)

    def disjunction(self) -> Formula:
        return self._left_chain("||", Or, self.conjunction)

    def conjunction(self) -> Formula:
        return self._left_chain("&&", And, self.binary_temporal)

    def binary_temporal(self) -> Formula:
        return self._right_chain({"U": Until, "R": Release, "W": WeakUntil}, "name", self.binary_temporal, self.unary)

    def unary(self) -> Formula:
        token = self.peek
        unary = {"!": Not, "X[!]": Next, "X": WeakNext, "F": Eventually, "G": Always}.get(token.text)
        if unary is not None and token.kind in ("op", "name") and (token.kind == "op" or self._is_operator()):
            self.take()
            self._enter()
            operand = self.unary()
            self.depth -= 1
            return unary(operand)
        return self.atom()

    def _is_operator(self) -> bool:
        # ``X``, ``F``, ``G`` are operators unless a signal is called that (then the file is
        # ambiguous only if such a name is followed by an operand, which we read as the operator)
        following = self.tokens[self.i + 1]
        return following.kind in ("name", "op") and following.text not in (")", ";", "&&", "||", "->", "<->", "}",
                                                                             ",")

    def atom(self) -> Formula:
        token = self.take()
        if token.text == "(":
            self._enter()
            inner = self.formula()
            self.depth -= 1
            self.expect(")", "')'")
            return inner
        if token.kind == "name":
            if token.text == "true":
                return TRUE
            if token.text == "false":
                return FALSE
            if token.text in ("U", "R", "W"):
                raise self.error(f"{token.text!r} needs a formula on its left", token)
            return Prop(token.text)
        found = "end of file" if token.kind == "end" else repr(token.text)
        raise self.error(f"expected a formula, found {found}", token)


def _combine(sections: dict[str, list[Formula]]) -> Formula:
    def all_of(key: str) -> Formula:
        return conjunction(*sections[key]) if sections.get(key) else TRUE

    def always(key: str) -> Formula:
        return Always(all_of(key)) if sections.get(key) else TRUE

    assume = _and(always("REQUIRE"), all_of("ASSUMPTIONS"))
    guarantee = _and(always("ASSERT"), all_of("GUARANTEES"))
    body = guarantee if assume == TRUE else Implies(assume, guarantee)
    body = _and(all_of("PRESET"), body)
    return body if all_of("INITIALLY") == TRUE else Implies(all_of("INITIALLY"), body)


def _and(a: Formula, b: Formula) -> Formula:
    if a == TRUE:
        return b
    if b == TRUE:
        return a
    return And(a, b)


def parse_tlsf(text: str, *, source: str | None = None) -> TlsfSpec:
    """Read a basic TLSF specification from ``text`` (``source`` names it in errors)."""
    if not isinstance(text, str):
        raise ParseError(f"a TLSF specification must be text, not {type(text).__name__}")
    found = _GLOBAL.search(text)
    if found is not None:  # before tokens: its definitions use syntax basic TLSF does not have
        line = text.count("\n", 0, found.start("word")) + 1
        column = found.start("word") - (text.rfind("\n", 0, found.start("word")) + 1) + 1
        raise ParseError("this is a parameterised (full) TLSF file: its GLOBAL section defines parameters or "
                         "functions, which basic TLSF does not have", file=source, line=line, column=column,
                         hint="convert it with syfco's basic output first, e.g. `syfco -f basic -op N=3 FILE > "
                              "basic.tlsf`, then read basic.tlsf")
    try:
        return _Reader(text, source).spec()
    except RecursionError:  # a chain of operators deeper than the interpreter's stack
        raise ParseError(f"the specification nests more than {MAX_DEPTH} levels deep", file=source) from None


_GLOBAL = re.compile(r"^[ \t]*(?P<word>GLOBAL)\s*\{", re.M)


def load_tlsf(path: str | Path) -> TlsfSpec:
    """Read the basic TLSF file at ``path`` (size-checked like every input file)."""
    from symlearn.input_limits import read_input_text

    return parse_tlsf(read_input_text(path), source=str(path))


__all__ = ["MAX_DEPTH", "TlsfSpec", "load_tlsf", "parse_tlsf"]
