"""DFA minimisation: symlearn's symbolic Hopcroft vs AALpy's explicit-letter minimisation.

Each case is one DFA over k propositions, built twice: with guarded edges for symlearn and with
one edge per letter (2^k letters) for AALpy (``Dfa.minimize``, in place). Both must reach the
same number of states (also symlearn fed letter by letter, one cube guard per letter, which
its constructor merges back into the same guarded DFA); we report median wall times over
repeats and their ratio.

Families: ``counter(n, k)`` (counts ``p1`` modulo n, in two copies that minimisation merges) and
``random(n, k)`` (each state tests one random proposition, or a cube of two; seeded).

    .venv/bin/python benchmarks/automata_minimize.py [--quick] [--repeats 3]
"""

from __future__ import annotations

import argparse
import itertools
import platform
import random
import statistics
import time

from symlearn.logic.automata import DFA
from symlearn.logic.guards import Guard


def counter(n: int, k: int) -> tuple[list[str], int, set[int], dict]:
    props = [f"p{i}" for i in range(1, k + 1)]
    p = Guard.var(props[0])
    # copy c of counter value i: p advances the counter, !p jumps to the same value in the other
    # copy, so every state is reachable and the two copies merge
    transitions = {q: [(p, (q % n + 1) % n + n * (q // n)), (~p, q % n + n * (1 - q // n))] for q in range(2 * n)}
    return props, 2 * n, {0, n}, transitions


def random_dfa(n: int, k: int, seed: int) -> tuple[list[str], int, set[int], dict]:
    rng = random.Random(seed)
    props = [f"p{i}" for i in range(1, k + 1)]
    transitions = {}
    for q in range(n):
        x = Guard.var(rng.choice(props))
        if rng.random() < 0.5:
            transitions[q] = [(x, rng.randrange(n)), (~x, rng.randrange(n))]
        else:
            y = Guard.var(rng.choice(props))
            both = x & y
            transitions[q] = [(both, rng.randrange(n)), (~both, rng.randrange(n))] if not both.is_false() else [
                (Guard.true(), rng.randrange(n))]
    accepting = {q for q in range(n) if rng.random() < 0.3} or {0}
    return props, n, accepting, transitions


def reachable_part(spec):
    """The same DFA restricted to the states reachable from 0, renumbered."""
    props, n, accepting, transitions = spec
    order, seen = [0], {0}
    for q in order:
        for _, t in transitions[q]:
            if t not in seen:
                seen.add(t)
                order.append(t)
    index = {q: i for i, q in enumerate(order)}
    return (props, len(order), {index[q] for q in accepting if q in index},
            {index[q]: [(g, index[t]) for g, t in transitions[q]] for q in order})


def letters(props: list[str]) -> list[frozenset[str]]:
    return [frozenset(p for p, bit in zip(props, bits) if bit) for bits in itertools.product((0, 1), repeat=len(props))]


def explicit_dfa(props, n, accepting, transitions) -> DFA:
    alphabet = letters(props)
    rows = {}
    for q, edges in transitions.items():
        rows[q] = [(Guard.label(letter, props), next(t for g, t in edges if g.evaluate(letter)))
                   for letter in alphabet]
    return DFA(props, n, 0, accepting, rows)


def aalpy_dfa(props, n, accepting, transitions):
    from aalpy.automata import Dfa, DfaState

    states = [DfaState(f"q{q}", q in accepting) for q in range(n)]
    names = {letter: ",".join(sorted(letter)) or "-" for letter in letters(props)}
    for q, edges in transitions.items():
        for letter, name in names.items():
            states[q].transitions[name] = states[next(t for g, t in edges if g.evaluate(letter))]
    return Dfa(states[0], states)


def timed(fn, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small cases only")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    # AALpy's minimisation recomputes a characterisation set per merge and did not finish
    # counter(20, 3) within minutes, so it runs on the random family up to 120 states only.
    cases = [("random", 25, 3), ("random", 60, 4), ("counter", 100, 3)]
    if not args.quick:
        cases += [("random", 120, 5), ("random", 400, 8), ("counter", 1000, 6)]
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}")
    print(f"# command: .venv/bin/python benchmarks/automata_minimize.py{' --quick' if args.quick else ''}")
    print(f"{'case':<16}{'states':>7}{'min':>6}{'symlearn s':>12}{'AALpy s':>10}{'AALpy/ours':>12}")
    ratios = []
    for family, n, k in cases:
        spec = reachable_part(counter(n, k) if family == "counter" else random_dfa(n, k, seed=n * 31 + k))
        symbolic = DFA(spec[0], spec[1], 0, spec[2], spec[3])
        ours, minimal = timed(symbolic.minimize, args.repeats)
        explicit = explicit_dfa(*spec)
        minimal_explicit = explicit.minimize()

        def run_aalpy():
            automaton = aalpy_dfa(*spec)  # minimisation is in place: rebuild outside the clock
            start = time.perf_counter()
            automaton.minimize()
            return time.perf_counter() - start, automaton

        assert minimal_explicit.n_states == minimal.n_states, "symbolic and explicit minimisation disagree"
        row = f"{family + f'({n},{k})':<16}{spec[1]:>7}{minimal.n_states:>6}{ours:>12.4f}"
        if family != "random" or spec[1] > 120:
            print(row + f"{'-':>10}{'-':>12}")
            continue
        aalpy_times = [run_aalpy() for _ in range(args.repeats)]
        theirs = statistics.median(t for t, _ in aalpy_times)
        assert aalpy_times[-1][1].size == minimal.n_states, (minimal.n_states, aalpy_times[-1][1].size)
        ratios.append(theirs / ours)
        print(row + f"{theirs:>10.4f}{theirs / ours:>12.1f}")
    print(f"median AALpy/symlearn time ratio: {statistics.median(ratios):.1f}")


if __name__ == "__main__":
    main()
