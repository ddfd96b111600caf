"""The long fuzz run of issue 15: seeded mutants of valid inputs through every reader and command.

Two parts, both in child processes under 1 GB of address space (tests/support/hostile.py):

* ``--inputs N``: N mutants read in-process by the library readers (tests/support/fuzz_inputs.py:
  demonstrations JSONL/NPZ (image kind too), automaton JSON (DFA, PDFA, reward machine),
  MONA/LTLf2DFA DOT, reward-machine text, formula files, trace files, a trace, labelings, LTL
  samples, DNF rule files (text, JSON), frame archives, TLSF, sweep files, sweep records and
  results, learned-cost models (configuration, weights), domain folders (in the bounded worker
  ``domain check`` uses)), round robin over the formats;
* ``--cli K``: K mutants per format through the real CLI (``data validate|info``, ``automaton
  show``/``explain``, ``ltl dfa --file|--tlsf``, ``ltl eval --traces``, ``dnf show``, ``sweep
  run|report``, ``domain check``, ``train --cost``: at most 5 each, a training run takes seconds),
  each checked for the promise: exit 0 or a clean exit 2 with one line, no traceback, within 60 s
  and 1 GB.

Counts per reader/command, and every crash (kept under ``--work``/crashes), go to
``benchmarks/results/fuzz_inputs.json``. ``--source DIR`` runs another source tree (a "before"
tree made with ``git archive HEAD symlearn grammars | tar -x -C DIR``) for a before/after table::

    .venv/bin/python benchmarks/fuzz_inputs.py --inputs 20000 --cli 25
    .venv/bin/python benchmarks/fuzz_inputs.py --inputs 3000 --cli 10 --source /tmp/before --out /tmp/before.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import sys
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(REPO / "tests" / "support"))

from fuzz_inputs import CLI_CAP, COMMANDS, mutants, place, seeds  # noqa: E402  (tests/support)
from hostile import assert_survived, run_command, run_python  # noqa: E402


def _env(source: str | None) -> dict[str, str]:
    """The children's path: ``source`` or this checkout first (not whatever symlearn the
    interpreter has installed, which may be another checkout's)."""
    support = str(REPO / "tests" / "support")
    return {"PYTHONPATH": os.pathsep.join([str(Path(source).resolve()) if source else str(REPO), support])}


def run_reader_fuzz(n: int, seed: int, folder: Path, source: str | None = None, timeout: float = 3600) -> dict:
    """``fuzz_readers`` in a child under 1 GB (a reader that blows up must not take us down)."""
    code = f"""
import json
from fuzz_inputs import fuzz_readers
print(json.dumps(fuzz_readers({n}, {seed}, {str(folder)!r})))
"""
    folder.mkdir(parents=True, exist_ok=True)
    result = run_python(code, cwd=folder, timeout=timeout, memory_mb=1024, env=_env(source))
    if result.returncode != 0:
        return {"inputs": None, "error": result.stderr[-2000:], "exit": result.returncode, "timed_out": result.timed_out}
    return json.loads(result.stdout)


def run_cli_fuzz(per_command: int, seed: int, folder: Path, source: str | None = None) -> dict:
    """``per_command`` mutants of each format through its command; counts and crashes."""
    folder = Path(folder)
    rng = random.Random(seed)
    valid = seeds(folder / "seeds")
    dfa = next(path for fmt, path in valid if fmt == "automaton-json" and path.name == "dfa.json")
    by_format = defaultdict(list)
    for fmt, path in valid:
        if fmt in COMMANDS:
            by_format[fmt].append(path)
    work = folder / "cli"
    work.mkdir(parents=True, exist_ok=True)
    crash_dir = folder / "crashes"
    counts: dict[str, Counter] = defaultdict(Counter)
    crashes = []
    start = time.perf_counter()
    for fmt, paths in sorted(by_format.items()):
        streams = [(p, mutants(p.read_bytes(), fmt, rng)) for p in paths]
        for i in range(min(per_command, CLI_CAP.get(fmt, per_command))):
            path, stream = streams[i % len(streams)]
            mutation, data = next(stream)
            target = place(work, fmt, path, data)
            relative = target.relative_to(work)
            args = [a.replace("{path}", str(relative)).replace("{folder}", str(relative.parent))
                    .replace("{dfa}", str(dfa)) for a in COMMANDS[fmt]]
            command = " ".join(COMMANDS[fmt][:2]) + (f" ({fmt})" if fmt.split("-")[0] in ("sweep", "cost", "dnf")
                                                     else "")
            result = run_command(args, cwd=work, timeout=60, memory_mb=1024, env=_env(source))
            try:
                assert_survived(result)
                counts[command]["accepted" if result.returncode == 0 else "refused"] += 1
            except AssertionError as exc:
                counts[command]["crashed"] += 1
                crash_dir.mkdir(parents=True, exist_ok=True)
                kept = crash_dir / f"cli{len(crashes)}-{fmt}{path.suffix}"
                kept.write_bytes(data)
                crashes.append({"command": args, "format": fmt, "mutation": mutation, "file": str(kept),
                                "exit": result.returncode, "seconds": round(result.seconds, 2),
                                "peak_mb": round(result.max_rss_mb), "why": str(exc).splitlines()[0][:300],
                                "stderr": result.stderr[-400:]})
            counts[command]["runs"] += 1
            counts[command]["max_seconds"] = max(counts[command]["max_seconds"], round(result.seconds, 2))
            counts[command]["max_peak_mb"] = max(counts[command]["max_peak_mb"], round(result.max_rss_mb))
    return {"per_command": {k: dict(v) for k, v in sorted(counts.items())}, "crashes": crashes,
            "seconds": round(time.perf_counter() - start, 1)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--inputs", type=int, default=20000, help="in-process mutants in all (default 20000)")
    parser.add_argument("--cli", type=int, default=25, help="CLI runs per format (default 25)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--source", help="another source tree to fuzz (a 'before' tree)")
    parser.add_argument("--work", help="keep mutants and crashes here (default: a temporary folder)")
    parser.add_argument("--out", default=str(HERE / "results" / "fuzz_inputs.json"))
    args = parser.parse_args(argv)

    work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="symlearn-fuzz-"))
    work.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    readers = run_reader_fuzz(args.inputs, args.seed, work / "readers", args.source) if args.inputs else None
    cli = run_cli_fuzz(args.cli, args.seed, work / "commands", args.source) if args.cli else None
    report = {
        "command": "python benchmarks/fuzz_inputs.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "source": args.source or "working tree", "seed": args.seed, "machine": platform.platform(),
        "python": platform.python_version(), "cpus": os.cpu_count(), "seconds": round(time.perf_counter() - started, 1),
        "readers": readers, "cli": cli, "work": str(work),
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(report, indent=1) + "\n")
    crashed = (len(readers.get("crashes", [])) if readers and readers.get("inputs") is not None else 0) + \
              (len(cli["crashes"]) if cli else 0)
    print(f"readers: {readers and readers.get('inputs')} inputs, "
          f"{len(readers.get('crashes', [])) if readers else 0} crashes; "
          f"cli: {sum(v['runs'] for v in cli['per_command'].values()) if cli else 0} runs, "
          f"{len(cli['crashes']) if cli else 0} crashes -> {args.out}")
    return 1 if crashed else 0


if __name__ == "__main__":
    sys.exit(main())
