"""Learn every bundled Hanoi/traffic task; time the single-grounding path against the general one.

    python benchmarks/ilp_domains.py [--repeat 3] [--timeout 60]

For each task in symlearn.envs.ilp_tasks.DEFAULT_TASKS it prints the best-of-N wall and CPU time
of ``learn(task, method=...)`` for ``single`` (one grounding + set-cover optimisation) and
``general`` (full ASP semantics, the peer measured in the same run), the CPU-time ratio
general / single, the score, whether the optimum was proven, and, for the exhaustive tasks, how
many state-action pairs the learned rules classify differently from the ground truth (must be 0).
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

from symlearn.envs.ilp_tasks import DEFAULT_TASKS
from symlearn.envs.logic_domains import logic_domain
from symlearn.logic.ilp import learn, load_task
from symlearn.resources import background_kb_path


def _best_time(task, method: str, repeat: int, timeout: float):
    """Best wall-clock and best CPU seconds over ``repeat`` runs, and the last result."""
    best_wall, best_cpu, result = float("inf"), float("inf"), None
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        result = learn(task, timeout=timeout, method=method)
        best_wall = min(best_wall, time.perf_counter() - wall)
        best_cpu = min(best_cpu, time.process_time() - cpu)
    return best_wall, best_cpu, result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=60.0)
    args = parser.parse_args()
    print(f"command: python benchmarks/ilp_domains.py --repeat {args.repeat} --timeout {args.timeout}")
    print(f"machine: {platform.machine()}, python {platform.python_version()}")
    header = f"{'task':34} {'examples':>8} {'space':>6} {'single s':>9} {'cpu s':>6} {'general s':>10} " \
             f"{'cpu s':>6} {'ratio':>6} {'score':>5} {'optimal':>7} {'wrong pairs':>11}"
    print(header)
    for relative, (name, recipe) in DEFAULT_TASKS.items():
        task = load_task(background_kb_path(*Path(relative).parts))
        single_s, single_cpu, single = _best_time(task, "single", args.repeat, args.timeout)
        general_s, general_cpu, general = _best_time(task, "general", args.repeat, args.timeout)
        wrong = "-"
        if recipe == "exhaustive":
            domain = logic_domain(name)
            forbidden = set(domain.forbidden_pairs(single.hypothesis.rules))
            wrong = str(sum((pair in forbidden) == domain.is_allowed(*pair) for pair in domain.state_actions()))
        same = "" if single.score == general.score else f"  (general score {general.score})"
        print(f"{relative:34} {len(task.examples):>8} {single.space_size:>6} {single_s:>9.2f} {single_cpu:>6.2f} "
              f"{general_s:>10.2f} {general_cpu:>6.2f} {general_cpu / single_cpu:>6.1f} {single.score:>5} "
              f"{str(single.optimal and general.optimal):>7} {wrong:>11}{same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
