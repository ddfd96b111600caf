"""Where ``ilp check`` spends its time on one rule of many body literals (issue 26, ninth round):
clingo's grounding against everything else (reading, tagging, lengths, warnings, solving).

The worker's side of ``symlearn ilp check background_kb/hanoi/tasks/hanoi.las HYP.lp`` runs in
this process (``_check_job``, the same code the worker runs) on the ``long`` and
``long_undefined`` rules of ``benchmarks/ilp_check_scale.py``; ``clingo.Control.ground`` is
timed by a wrapper. CPU seconds (``time.process_time``), steadier than wall time on a loaded
machine. A second table grounds the bare rule (untagged, one example's facts) in clingo alone.

``python benchmarks/ilp_long_rule_profile.py [--sizes 2500 5000 10000]`` writes
``benchmarks/results/ilp_long_rule_profile.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import clingo

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from ilp_check_scale import TASK, long_rule, long_undefined_rule  # noqa: E402

SHAPES = {"long": long_rule, "long_undefined": long_undefined_rule}


class GroundTimer:
    """Adds up the CPU seconds spent in ``clingo.Control.ground`` while installed."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self.original = clingo.Control.ground

    def __enter__(self) -> GroundTimer:
        timer = self

        def timed(control, *args, **kwargs):
            start = time.process_time()
            try:
                return timer.original(control, *args, **kwargs)
            finally:
                timer.seconds += time.process_time() - start

        clingo.Control.ground = timed
        return self

    def __exit__(self, *_exc) -> None:
        clingo.Control.ground = self.original


def check_job(path: Path) -> tuple[float, float]:
    """(total, grounding) CPU seconds of the worker's side of ``ilp check`` on ``path``."""
    from symlearn.cli import ilp_command

    job = {"task": str(TASK), "bk": [], "dialect": "ilasp", "max_body": None, "seconds": float("inf"),
           "started": time.monotonic(), "hypothesis": str(path), "coverage": False}
    with GroundTimer() as timer:
        start = time.process_time()
        ilp_command._check_job(job)
        total = time.process_time() - start
    return total, timer.seconds


def bare_grounding(n: int) -> float:
    """CPU seconds clingo alone takes to ground the rule over one example's facts."""
    control = clingo.Control(logger=lambda _code, _message: None)
    control.add("base", [], "move(1,2). at(1,0,0).\n" + long_rule(n))
    start = time.process_time()
    control.ground([("base", [])])
    return time.process_time() - start


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[2500, 5000, 10000])
    parser.add_argument("--output", type=Path, default=HERE / "results" / "ilp_long_rule_profile.json")
    args = parser.parse_args(argv)
    os.environ["SYMLEARN_QUIET"] = "1"
    results: dict = {"what": "worker side of ilp check in-process, CPU seconds", "task": str(TASK.name),
                     "check": [], "bare_clingo": []}
    with tempfile.TemporaryDirectory() as tmp:
        warm = Path(tmp) / "warm.lp"
        warm.write_text(long_rule(10))
        check_job(warm)  # imports and clingo's first start
        for shape, make in SHAPES.items():
            for n in args.sizes:
                path = Path(tmp) / f"{shape}_{n}.lp"
                path.write_text(make(n))
                total, grounding = check_job(path)
                case = {"shape": shape, "literals": n, "total_s": round(total, 2),
                        "clingo_ground_s": round(grounding, 2), "rest_s": round(total - grounding, 2)}
                results["check"].append(case)
                print(json.dumps(case), flush=True)
    for n in args.sizes:
        case = {"literals": n, "clingo_ground_s": round(bare_grounding(n), 3)}
        results["bare_clingo"].append(case)
        print(json.dumps(case), flush=True)
    results["load_average"] = [round(x, 2) for x in os.getloadavg()]
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(results, indent=1) + "\n")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
