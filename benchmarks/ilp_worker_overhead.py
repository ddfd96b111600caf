"""What the bounded worker costs: ``symlearn ilp learn`` with and without it, same run.

    python benchmarks/ilp_worker_overhead.py [--repeat 5] [--fastlas]

Since issue 15 ``ilp learn|check|space`` read and ground the user's programs in a worker process
with a time and memory limit (``symlearn/worker.py``). This script runs the whole command
(``python -m symlearn ilp learn TASK --json``) on every bundled task (and with ``--fastlas`` the
FastLAS test tasks that solve in seconds), alternating the default (worker) with
``SYMLEARN_WORKER=off`` (the same code in one process, no limits: what the command did before),
and prints the best and median wall-clock seconds of each, the best CPU seconds (user + system of
the command and its worker), the wall and CPU ratios worker / in-process (best of N) and the
extra wall milliseconds. Results must agree (same score). CPU time is the steadier measure on a
loaded machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from symlearn.envs.ilp_tasks import DEFAULT_TASKS
from symlearn.resources import background_kb_path

FASTLAS = Path(__file__).resolve().parents[2] / "shared" / "benchmarks" / "ilp" / "fastlas"
FASTLAS_QUICK = ["fastlas__testing__aaai_presentation_task.las", "fastlas__testing__agent_abduction.las",
                 "fastlas__testing__arithmetic2.las", "fastlas__testing__simple_agent.las"]


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # waited-for children and their children
    return usage.ru_utime + usage.ru_stime


def _run(path: Path, dialect: str, worker: bool) -> tuple[float, float, dict]:
    env = dict(os.environ, SYMLEARN_QUIET="1")
    if not worker:
        env["SYMLEARN_WORKER"] = "off"
    command = [sys.executable, "-m", "symlearn", "ilp", "learn", str(path), "--json", "--timeout", "120",
               "--dialect", dialect]
    start, cpu = time.perf_counter(), _cpu()
    done = subprocess.run(command, capture_output=True, text=True, env=env, check=False)
    seconds, cpu = time.perf_counter() - start, _cpu() - cpu
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}): {done.stderr.strip()}")
    return seconds, cpu, json.loads(done.stdout)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--fastlas", action="store_true", help="also the quick FastLAS test tasks")
    args = parser.parse_args()
    print(f"command: python benchmarks/ilp_worker_overhead.py --repeat {args.repeat}"
          + (" --fastlas" if args.fastlas else ""))
    print(f"machine: {platform.machine()}, {os.cpu_count()} cpus, python {platform.python_version()}, "
          f"load average {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    tasks = [(background_kb_path(*Path(rel).parts), "ilasp") for rel in DEFAULT_TASKS]
    if args.fastlas and FASTLAS.exists():
        tasks += [(FASTLAS / name, "fastlas") for name in FASTLAS_QUICK]
    print(f"{'task':42} {'in-proc s':>9} {'median':>7} {'cpu s':>6} {'worker s':>9} {'median':>7} {'cpu s':>6} "
          f"{'wall x':>6} {'cpu x':>6} {'+ms':>5}")
    ratios, cpu_ratios, extra = [], [], []
    for path, dialect in tasks:
        times: dict[bool, list[float]] = {True: [], False: []}
        cpus: dict[bool, list[float]] = {True: [], False: []}
        scores = set()
        for _ in range(args.repeat):
            for worker in (False, True):  # alternate, so load drifts hit both alike
                seconds, cpu, doc = _run(path, dialect, worker)
                times[worker].append(seconds)
                cpus[worker].append(cpu)
                scores.add(doc["score"])
        if len(scores) != 1:
            raise SystemExit(f"{path.name}: results differ: {scores}")
        best_in, best_worker = min(times[False]), min(times[True])
        cpu_in, cpu_worker = min(cpus[False]), min(cpus[True])
        ratios.append(best_worker / best_in)
        cpu_ratios.append(cpu_worker / cpu_in)
        extra.append(best_worker - best_in)
        print(f"{path.name:42} {best_in:>9.3f} {statistics.median(times[False]):>7.3f} {cpu_in:>6.2f} "
              f"{best_worker:>9.3f} {statistics.median(times[True]):>7.3f} {cpu_worker:>6.2f} "
              f"{best_worker / best_in:>6.2f} {cpu_worker / cpu_in:>6.2f} {1000 * (best_worker - best_in):>5.0f}")
    print(f"geometric mean ratio: wall {statistics.geometric_mean(ratios):.3f}, cpu "
          f"{statistics.geometric_mean(cpu_ratios):.3f}; median extra wall {1000 * statistics.median(extra):.0f} ms "
          "per command")
    return 0


if __name__ == "__main__":
    sys.exit(main())
