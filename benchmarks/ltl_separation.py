"""Separating-formula learning on the public LTLf learning benchmarks, against Scarlet in the same run.

    .venv/bin/python benchmarks/ltl_separation.py                       # test set, 6 problems per family
    .venv/bin/python benchmarks/ltl_separation.py --per-family 0        # every test problem
    .venv/bin/python benchmarks/ltl_separation.py --split dev --no-peer # tuning runs

For each family: fraction solved within the time limit (a separating formula returned, checked
with the core's vectorised evaluator), median time, and how the size compares with the file's
``smallest_known_formula`` (parsed in the Spot dialect, measured as syntax-tree nodes). Scarlet
runs on the same problems with its own timeout; its median time counts unfinished runs at the
timeout. The subset per family is stratified: problems evenly spaced in manifest order (the
manifest lists each family's parameter grid in order).
"""

from __future__ import annotations

import argparse
import csv
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from symlearn.data.ltl_samples import load_sample  # noqa: E402
from symlearn.learners.temporal.separating_ltl import learn_from_sample  # noqa: E402
from symlearn.logic.ltlf import parse, size  # noqa: E402
from symlearn.logic.ltlf.vectorized import evaluate_many  # noqa: E402

DEFAULT_DATA = ROOT.parent / "shared" / "benchmarks" / "ltlf_learning"


def known_size(text: str) -> int | None:
    if not text:
        return None
    while text.count(")") > text.count("("):  # OrderedSequence: the generator's surplus ')'
        text = text[: text.rindex(")")] + text[text.rindex(")") + 1:]
    return size(parse(text, dialect="spot"))


def select(rows: list[dict], per_family: int) -> list[dict]:
    families: dict[str, list[dict]] = {}
    for row in rows:
        families.setdefault(row["family"], []).append(row)
    chosen = []
    for family in sorted(families):
        items = families[family]
        if per_family and len(items) > per_family:
            items = [items[round(i * (len(items) - 1) / (per_family - 1))] for i in range(per_family)] \
                if per_family > 1 else items[:1]
        chosen.extend(items)
    return chosen


def solve(folder: Path, file: str, family: str, *, timeout: float, max_size: int, peer: bool,
          peer_timeout: float) -> dict:
    """One problem: our formula (checked to separate), its size against the known one, and
    Scarlet's run on the same sample when ``peer``."""
    sample = load_sample(folder / file)
    result = learn_from_sample(sample, timeout=timeout, max_size=max_size)
    separates = None
    if result.formula is not None:
        verdicts = evaluate_many(result.formula, list(sample.positive) + list(sample.negative))
        n_pos = len(sample.positive)
        separates = bool(verdicts[:n_pos].all() and not verdicts[n_pos:].any())
    record = {"file": file, "family": family, "known": known_size(sample.smallest_known_formula or ""),
              "formula": None if result.formula is None else str(result.formula), "size": result.size,
              "optimal": result.optimal, "seconds": result.seconds, "separates": separates,
              "method": result.method}
    record["solved"] = bool(separates) and result.seconds <= timeout
    if peer:
        from symlearn.learners.temporal.scarlet_peer import run_scarlet

        found = run_scarlet(sample, timeout=peer_timeout)
        record.update(peer_formula=found.formula, peer_size=found.size, peer_seconds=found.seconds,
                      peer_finished=found.finished)
    return record


def cell(problem: str, family: str, seed: int, split: str = "test", timeout: float = 10.0, max_size: int = 40,
         peer: bool = False, peer_timeout: float = 10.0, data: str = "") -> dict:
    """One cell of ``benchmarks/sweeps/ltl_separation*.toml``: :func:`solve` on one problem file
    (the learner is deterministic: ``seed`` only names the cell); ``solved`` as 0/1, so its mean
    over problems is the solved share, and the size over the known size as ``size_ratio``."""
    record = solve(Path(data) if data else DEFAULT_DATA / split, problem, family, timeout=timeout,
                   max_size=max_size, peer=peer, peer_timeout=peer_timeout)
    record["solved"] = int(record["solved"])
    record["size_ratio"] = record["size"] / record["known"] if record["solved"] and record["known"] else None
    return record


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA)
    parser.add_argument("--split", default="test", choices=["dev", "test"])
    parser.add_argument("--per-family", type=int, default=6, help="problems per family (0: all)")
    parser.add_argument("--timeout", type=float, default=10.0, help="our time limit per problem")
    parser.add_argument("--peer-timeout", type=float, default=10.0, help="Scarlet's time limit per problem")
    parser.add_argument("--max-size", type=int, default=40, help="our size bound (default 40, as the CLI)")
    parser.add_argument("--family", action="append", help="only these families (repeatable)")
    parser.add_argument("--no-peer", action="store_true", help="skip Scarlet")
    parser.add_argument("--json-out", type=Path, help="write the per-problem rows as JSON")
    args = parser.parse_args(argv)

    folder = args.data / args.split
    rows = [r for r in csv.DictReader((folder / "manifest.csv").open()) if not args.family or r["family"] in args.family]
    rows = select(rows, args.per_family)
    print(f"command: {' '.join([Path(sys.argv[0]).name] + (argv or sys.argv[1:]))}")
    print(f"{len(rows)} problems from {folder}; our timeout {args.timeout} s"
          + ("" if args.no_peer else f"; Scarlet timeout {args.peer_timeout} s"), flush=True)
    results = []
    for row in rows:
        record = solve(folder, row["file"], row["family"], timeout=args.timeout, max_size=args.max_size,
                       peer=not args.no_peer, peer_timeout=args.peer_timeout)
        results.append(record)
        peer_text = "" if args.no_peer else \
            f" | scarlet {record['peer_seconds']:5.2f}s size={record['peer_size']} finished={record['peer_finished']}"
        print(f"{row['file'][:58]:58s} {record['seconds']:6.2f}s size={record['size']} known={record['known']} "
              f"{'ok' if record['solved'] else 'UNSOLVED'}{peer_text}", flush=True)
    report(results, args)
    if args.json_out:
        args.json_out.write_text(json.dumps(results, indent=1))
    return 0


def report(results: list[dict], args) -> None:
    print()
    header = "| family | problems | solved <= %gs | median s | size <= known | size vs known (median ratio) |" % args.timeout
    if not args.no_peer:
        header += " Scarlet finished | Scarlet median s | speed-up (median) |"
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    groups: dict[str, list[dict]] = {}
    for r in results:
        groups.setdefault(r["family"], []).append(r)
    groups["all"] = results
    for family, rs in groups.items():
        solved = [r for r in rs if r["solved"]]
        with_known = [r for r in solved if r["known"]]
        not_larger = sum(r["size"] <= r["known"] for r in with_known)
        ratio = statistics.median([r["size"] / r["known"] for r in with_known]) if with_known else float("nan")
        line = (f"| {family} | {len(rs)} | {len(solved)}/{len(rs)} ({len(solved) / len(rs):.0%}) | "
                f"{statistics.median(r['seconds'] for r in rs):.3f} | "
                f"{not_larger}/{len(with_known)} | {ratio:.2f} |")
        if not args.no_peer:
            peer_median = statistics.median(r["peer_seconds"] for r in rs)
            ours_median = statistics.median(r["seconds"] for r in rs)
            line += (f" {sum(r['peer_finished'] for r in rs)}/{len(rs)} | {peer_median:.2f} | "
                     f"{peer_median / max(ours_median, 1e-3):.0f}x |")
        print(line)
    print(f"\nmachine: 2 cores, 24 GiB, no GPU; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")


if __name__ == "__main__":
    sys.exit(main())
