"""How large the bounded progression trial of composite formulas should be (issue 27).

:func:`symlearn.logic.ltlf.composition.compose` first gives a composite formula to progression
within ``TRIAL_STATES`` states and ``TRIAL_NODES`` BDD nodes; when the trial runs out, the time it
spent is lost and the formula is composed from its parts. A larger budget lets more formulas
finish by progression (1.5-5x faster than products on small ones), a smaller one wastes less on
formulas that will be composed anyway. This script times every formula of two workloads at each
budget in one process (best of ``--repeat``, the budgets alternating round by round, so load on
the machine hits them alike):

* ``ours``: the LTLf -> DFA benchmark families and the 201 formulas of the public LTLf learning
  benchmark (the same set as benchmarks/ltlf_translation_ab.py);
* ``tlsf``: basic TLSF files named by ``--tlsf-list`` (one path per line), e.g. the files of a
  ``tlsf_fin_vs_mona.py`` sample that symlearn translates within a few seconds.

    .venv/bin/python benchmarks/ltlf_trial_budget.py --tlsf-list FILES.txt --budgets 100000,50000,25000,10000 \\
        --json benchmarks/results/ltlf_trial_budget.json
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parent))

import ltlf_to_dfa as bench  # noqa: E402  (the family generators beside this script)

from symlearn.logic.ltlf import composition, parse, translate  # noqa: E402
from symlearn.logic.ltlf.tlsf import load_tlsf  # noqa: E402


def workloads(tlsf_list: Path | None) -> dict[str, list[tuple[str, object]]]:
    families = [bench.conjunctions_of_f(8), bench.chains_of_t(10), bench.task_templates(6), bench.DWYER,
                bench.random_family([5, 10, 15, 20, 25, 30], 8, seed=2026)]
    ours = [(t, parse(t)) for family in families for t in family]
    lines = [line.strip() for line in bench.FORMULAS_TXT.read_text().splitlines() if line.strip()]
    ours += [(t, parse(t, "spot")) for t in lines]
    out = {"ours": ours}
    if tlsf_list is not None:
        paths = [p.strip() for p in tlsf_list.read_text().splitlines() if p.strip()]
        out["tlsf"] = [(p, load_tlsf(p).formula) for p in paths]
    return out


def timed(formula, repeat: int) -> tuple[float, int]:
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        dfa = translate(formula, max_states=500_000)
        best = min(best, time.perf_counter() - start)
    return best, dfa.n_states


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tlsf-list", type=Path, help="file with one basic TLSF path per line")
    parser.add_argument("--budgets", default="100000,50000,25000,10000", help="TRIAL_NODES values to compare")
    parser.add_argument("--knob", choices=("TRIAL_NODES", "TRIAL_FIRST_NODES"), default="TRIAL_NODES",
                        help="which bound of the trial --budgets sets (TRIAL_FIRST_NODES: the first state's "
                             "share; a value >= TRIAL_NODES turns it off)")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    budgets = [int(b) for b in args.budgets.split(",")]
    loads = workloads(args.tlsf_list)
    times = {b: {name: [float("inf")] * len(items) for name, items in loads.items()} for b in budgets}
    states: dict[str, list[int]] = {}
    original = getattr(composition, args.knob)
    try:
        for _ in range(args.rounds):
            for b in budgets:
                setattr(composition, args.knob, b)
                for name, items in loads.items():
                    for i, (_, formula) in enumerate(items):
                        seconds, n = timed(formula, args.repeat)
                        times[b][name][i] = min(times[b][name][i], seconds)
                        found = states.setdefault(name, [None] * len(items))
                        if found[i] is not None and found[i] != n:
                            raise SystemExit(f"state counts differ across budgets on {items[i][0]!r}")
                        found[i] = n
    finally:
        setattr(composition, args.knob, original)
    reference = budgets[0]
    print(f"# {' '.join(sys.argv)}")
    for name, items in loads.items():
        print(f"{name} ({len(items)} formulas): total ms / per-formula median ratio to {reference:,}")
        for b in budgets:
            total = sum(times[b][name])
            ratios = [t / r for t, r in zip(times[b][name], times[reference][name])]
            worst = max(range(len(items)), key=lambda i: ratios[i])
            print(f"  {b:>8,}: {1000 * total:9.1f} ms  median ratio {statistics.median(ratios):.3f}  "
                  f"worst {ratios[worst]:.2f} ({items[worst][0][-60:]})")
    if args.json:
        doc = {"command": " ".join(sys.argv), "knob": args.knob, "budgets": budgets,
               "formulas": {name: [label for label, _ in items] for name, items in loads.items()},
               "states": states, "seconds": {str(b): times[b] for b in budgets}}
        args.json.write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
