"""Many examples in one clingo program: every atom gets the example's number as first argument.

Example ``i`` is the program B ∪ context_i with each atom ``p(X)`` renamed to ``p(i, X)``; the
copies share nothing, so the answer sets of the union are the combinations of the copies' answer
sets. Rules of B are guarded by ``active__(E)`` so one grounding instantiates B for all examples;
an example whose ``active__`` atom is false contributes nothing (that is how soft examples are
dropped and how negatives are checked independently of each other).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.task import Example, ILPTask

ACTIVE = "active__"


def tag_symbol(symbol: cl.Symbol, tag: int) -> cl.Symbol:
    return cl.Function(symbol.name, [cl.Number(tag), *symbol.arguments], symbol.positive)


def tagged_background(task: ILPTask) -> str:
    return located_background(task).text


def located_background(task: ILPTask) -> Program:
    """The tagged background, each line mapped back to the user's file (for clingo's errors)."""
    return cl.tag_programs_located([(task.background, "E__", (f"{ACTIVE}(E__)",))])[0]


def tagged_context(example: Example, tag: int) -> str:
    if example.context.is_empty():
        return ""
    return cl.tag_program(example.context, str(tag), [f"{ACTIVE}({tag})"])


def acceptance_constraints(example: Example, tag: int) -> str:
    """Constraints that make copy ``tag`` extend the example's partial interpretation."""
    lines = [f":- {ACTIVE}({tag}), not {tag_symbol(s, tag)}." for s in example.inclusions]
    lines += [f":- {ACTIVE}({tag}), {tag_symbol(s, tag)}." for s in example.exclusions]
    return "\n".join(lines)


def tagged_rules(rules: Sequence[str] | Program, guard: Sequence[str] = ()) -> Program:
    """Hypothesis rules copied into every active example (``guard`` adds more body literals).
    Given as a :class:`Program` (``Hypothesis.program()``), clingo's errors name the rule's file
    and line."""
    program = rules if isinstance(rules, Program) else Program.from_text("\n".join(rules), source="<hypothesis>")
    if program.is_empty():
        return Program()
    return cl.tag_programs_located([(program, "E__", (f"{ACTIVE}(E__)", *guard))])[0]


def examples_program(task: ILPTask, indexed: Iterable[tuple[int, Example]], *, accept: bool = True) -> Program:
    """Background once plus, per example, its context and (optionally) acceptance constraints."""
    parts = [located_background(task)]
    indexed = [(tag, e) for tag, e in indexed]
    with_context = [(tag, e) for tag, e in indexed if not e.context.is_empty()]
    parts += cl.tag_programs_located([(e.context, str(tag), (f"{ACTIVE}({tag})",)) for tag, e in with_context])
    if accept:
        chunks = [acceptance_constraints(e, tag) for tag, e in indexed]
        parts.append(Program.from_text("\n".join(c for c in chunks if c), source=f"{task.source} (examples)"))
    return Program.compose(p for p in parts if p.parts)


def accepted_by(task: ILPTask, rules: Sequence[str] | Program, examples: Sequence[Example], *,
                timeout: float | None = None) -> dict[str, bool]:
    """For each example: does B ∪ rules ∪ context have an answer set extending it?"""
    return {k: v is not None for k, v in witnesses(task, rules, examples, timeout=timeout, atoms=False).items()}


def witnesses(task: ILPTask, rules: Sequence[str] | Program, examples: Sequence[Example], *,
              timeout: float | None = None, atoms: bool = True) -> dict[str, list[cl.Symbol] | None]:
    """Per example, an answer set of B ∪ rules ∪ context extending it (atoms tagged with the
    example's position in ``examples``), or None when there is none.

    One clingo call for all examples (:func:`_best_copies`). ``atoms=False``: which examples only
    (an accepted one gets an empty list); the answer set is not read back, which for rules that
    derive many atoms is most of the time (``ilp check``, issue 26).
    """
    if not examples:
        return {}
    indexed = list(enumerate(examples))
    program = examples_program(task, indexed) + tagged_rules(rules)
    return _best_copies(program, indexed, timeout=timeout, atoms=atoms)


class PairCheck:
    """Does B ∪ {rules[j]} ∪ context accept example ``examples[i]``, for many (j, i) pairs?

    One copy of B per pair in one clingo call, the pair's example and rule switched on in that
    copy only: ``of__(copy, i)`` guards the contexts and acceptance constraints of example i,
    ``pick__(copy, j)`` the rule j. Contexts and rules are tagged once here, not once per pair
    (tagging a context through clingo's AST costs more than grounding its copy).
    """

    def __init__(self, task: ILPTask, rules: Sequence[Program], examples: Sequence[Example]) -> None:
        self.task, self.rules = task, rules
        self.examples = list(examples)
        contexts = [(e.context, "E__", (f"{ACTIVE}(E__)", f"of__(E__,{i})"))
                    for i, e in enumerate(self.examples) if not e.context.is_empty()]
        accept = [_acceptance_of(e, i) for i, e in enumerate(self.examples)]
        self.base = Program.compose([located_background(task), *cl.tag_programs_located(contexts),
                                     Program.from_text("\n".join(a for a in accept if a),
                                                       source=f"{task.source} (examples)")])
        self.tagged: dict[int, Program] = {}

    def accepted(self, pairs: Sequence[tuple[int, int]], *, timeout: float | None = None) -> list[bool]:
        """For each (rule index, example index) pair: accepted? One clingo call."""
        if not pairs:
            return []
        self._tag([j for j, _i in pairs])
        links = "\n".join(f"of__({k},{i}). pick__({k},{j})." for k, (j, i) in enumerate(pairs))
        program = Program.compose([self.base, *(self.tagged[j] for j in sorted({j for j, _i in pairs})),
                                   Program.from_text(links, source="<coverage check>")])
        indexed = [(k, self.examples[i]) for k, (_j, i) in enumerate(pairs)]
        found = _best_copies(program, indexed, timeout=timeout, atoms=False, by_id=False)
        return [found[k] is not None for k, _example in indexed]

    def _tag(self, wanted: Iterable[int]) -> None:
        missing = sorted(set(wanted) - set(self.tagged))
        pieces = [(self.rules[j], "E__", (f"{ACTIVE}(E__)", f"pick__(E__,{j})")) for j in missing]
        self.tagged.update(zip(missing, cl.tag_programs_located(pieces)))


def _acceptance_of(example: Example, index: int) -> str:
    """:func:`acceptance_constraints` for every copy ``E__`` that ``of__`` links to the example."""
    def tagged(s: cl.Symbol) -> str:
        return f"{'' if s.positive else '-'}{s.name}({','.join(['E__', *map(str, s.arguments)])})"

    guard = f"{ACTIVE}(E__), of__(E__,{index})"
    lines = [f":- {guard}, not {tagged(s)}." for s in example.inclusions]
    lines += [f":- {guard}, {tagged(s)}." for s in example.exclusions]
    return "\n".join(lines)


def _best_copies(program: Program, indexed: list[tuple[int, Example]], *, timeout: float | None, atoms: bool,
                 by_id: bool = True) -> dict:
    """Switch on as many copies of ``program`` as have an answer set; per example (by id, or by
    copy number when ``by_id`` is False) its copy's atoms or None when it has none.

    Each copy may be switched off (``{active__(i)}``) and the number of active copies is
    maximised; since the copies are independent, the optimum switches on exactly the examples
    that are accepted. ``atoms=False``: which examples only (an accepted one gets an empty list).
    """
    key = (lambda i, e: e.id) if by_id else (lambda i, e: i)
    program = program + Program.from_text(
        "\n".join(f"{{ {ACTIVE}({i}) }}." for i, _ in indexed)
        + f"\n#maximize {{ 1,E : {ACTIVE}(E) }}." + ("" if atoms else f"\n#show {ACTIVE}/1."),
        source="<coverage check>")
    # core-guided optimisation: every copy that cannot be active is one small unsatisfiable core,
    # where branch-and-bound would improve the count one copy at a time
    # (the tagged copies have no #show of their own: tagging drops it)
    outcome = cl.optimize(program, timeout=timeout, shown_only=not atoms, arguments=["--opt-strategy=usc"])
    if not outcome.models and outcome.complete:
        return {key(i, e): None for i, e in indexed}
    if not outcome.complete:  # also before the first model: no copy has been decided
        raise cl.LimitExceededError(f"checking {len(indexed)} examples did not finish within {timeout} s",
                                    hint="raise the timeout")
    model = outcome.models[-1]
    active = {s.arguments[0].number for s in model if s.name == ACTIVE}
    if not atoms:
        return {key(i, e): ([] if i in active else None) for i, e in indexed}
    by_tag: dict[int, list[cl.Symbol]] = {i: [] for i in active}
    for atom in model:
        if atom.name != ACTIVE and atom.arguments and atom.arguments[0].type == cl.SymbolType.Number:
            tag = atom.arguments[0].number
            if tag in by_tag:
                by_tag[tag].append(atom)
    return {key(i, e): (by_tag[i] if i in active else None) for i, e in indexed}


def firing_rows(candidates: Iterable, atoms: Iterable[cl.Symbol], tags: Iterable[int]) -> dict[int, set[int]]:
    """For each candidate constraint, the copies (tags) whose answer set its body holds in.

    ``atoms`` are the tagged answer sets, given as facts; one grounding decides every body on
    every copy (the program is stratified: facts plus one ``fires__`` rule per candidate).
    """
    tags = list(tags)
    candidates = list(candidates)
    if not tags or not candidates:
        return {}
    facts = "\n".join(f"{a}." for a in atoms if a.name != ACTIVE)
    facts += "\n" + "\n".join(f"{ACTIVE}({i})." for i in tags)
    # ';' separates body elements: after a conditional literal ',' would extend its condition
    rules = [f"fires__(E__,{c.index}) :- {'; '.join(b.tagged('E__') for b in c.body)}; {ACTIVE}(E__)."
             for c in candidates]
    program = Program.from_text(facts, source="<answer sets>") + Program.from_text(
        "\n".join(rules), source="<candidate bodies>")
    rows: dict[int, set[int]] = {}
    for atom in cl.ground_atoms(program, [("fires__", 2)]):
        rows.setdefault(atom.arguments[1].number, set()).add(atom.arguments[0].number)
    return rows
