"""What running a grid through ``symlearn sweep`` costs, and what a second worker buys.

Three measurements in one run (docs/BENCHMARKS.md, "Sweeps"):

* overhead: 200 cells of a CPU-bound 0.1-second function (a pure-Python loop calibrated on this
  machine) through the sweep, against the same 200 calls in a plain loop in one process divided
  by the number of cores (the ideal). On Ray: a cold run (the command starts Ray itself, as
  ``symlearn sweep run`` does) and a warm one (Ray already up: the scheduling cost alone); and on
  the ``--local`` process pool. Target: sweep / ideal <= 1.5. The same grid of idle cells (0.1 s
  of sleep) gives the scheduling cost alone, whatever else loads the machine.
* speed-up: CPU-bound cells (0.25 s each) with 1 worker and with 2, alternated over rounds on one
  warm Ray session and on the local pool. Target: >= 1.7x.
* resume: a ``--local`` sweep whose driver is SIGKILLed once half the cells have records, then
  re-run: the cells finished before the kill must not run again (counted from a log every cell
  appends to when it starts).

    python benchmarks/sweep_scaling.py                # the full measurement (about 2 minutes)
    python benchmarks/sweep_scaling.py --quick        # fewer cells, a smoke test
    python benchmarks/sweep_scaling.py --json benchmarks/results/sweep_scaling.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()
REPO = HERE.parents[1]


def spin(iterations: int, seed: int, index: int = 0, log: str = "") -> dict:
    """The CPU-bound cell: ``iterations`` rounds of integer arithmetic (a fixed amount of work,
    so a slow cell means a busy core, not a slow scheduler)."""
    if log:
        with open(log, "a") as handle:
            handle.write(f"{index} {seed}\n")
    total = seed
    for i in range(iterations):
        total = (total * 1103515245 + i) & 0xFFFFFFFF
    return {"checksum": total}


def pause(seconds: float, seed: int, index: int = 0) -> dict:
    """The idle cell: sleeps, so its duration does not depend on what else runs on the machine;
    the sweep's time over the ideal is then the scheduling cost alone."""
    time.sleep(seconds)
    return {"index": index}


def calibrate(seconds: float) -> int:
    """Iterations of :func:`spin` that take ``seconds`` here (best of 3, so a busy moment does
    not make every cell shorter)."""
    probe = 200_000
    best = min(_timed(spin, probe, 0) for _ in range(3))
    return max(1000, int(probe * seconds / best))


def _timed(function, *args) -> float:
    started = time.perf_counter()
    function(*args)
    return time.perf_counter() - started


def _sweep_file(folder: Path, name: str, iterations: int, cells: int, extra: dict | None = None,
                function: str = "spin") -> Path:
    lines = ["[sweep]", f'name = "{name}"', f'function = "{HERE}:{function}"', "seeds = 1", "retries = 0",
             "[fixed]"]
    lines += [f"iterations = {iterations}"] if function == "spin" else []
    lines += [f"{k} = {json.dumps(v)}" for k, v in (extra or {}).items()]
    lines += ["[grid]", f"index = {json.dumps(list(range(cells)))}"]
    path = folder / f"{name}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def _run(path: Path, out: Path, backend: str, workers: int) -> float:
    from symlearn.sweep.runner import run_sweep
    from symlearn.sweep.spec import read_spec

    started = time.perf_counter()
    summary = run_sweep(read_spec(path), out, backend=backend, workers=workers, progress=False)
    seconds = time.perf_counter() - started
    if summary.finished != summary.cells:
        raise SystemExit(f"{path.name}: {summary.failed} cells failed: {summary.failures[:2]}")
    return seconds


def overhead(folder: Path, cells: int, cell_seconds: float, cores: int) -> dict:
    iterations = calibrate(cell_seconds)
    started = time.perf_counter()
    for index in range(cells):
        spin(iterations, 0, index)
    loop = time.perf_counter() - started
    ideal = loop / cores
    path = _sweep_file(folder, "overhead", iterations, cells)
    result = {"cells": cells, "cell_seconds_target": cell_seconds, "iterations": iterations,
              "plain_loop_seconds": round(loop, 3), "ideal_seconds": round(ideal, 3), "runs": {}}
    runs = [("ray_cold", "ray"), ("local", "local")]
    for name, backend in runs:
        seconds = _run(path, folder / f"out-{name}", backend, cores)
        result["runs"][name] = {"seconds": round(seconds, 3), "ratio_to_ideal": round(seconds / ideal, 3)}
        print(f"overhead {name}: {seconds:.2f} s = {seconds / ideal:.2f} x ideal ({ideal:.2f} s)", file=sys.stderr)
    import ray

    from symlearn.sweep.ray_pool import EMBEDDED_OBJECT_STORE_BYTES

    started = time.perf_counter()
    ray.init(num_cpus=cores, include_dashboard=False, log_to_driver=False, logging_level="ERROR",
             object_store_memory=EMBEDDED_OBJECT_STORE_BYTES)
    result["ray_init_seconds"] = round(time.perf_counter() - started, 3)
    _run(_sweep_file(folder, "warmup", iterations, 2 * cores), folder / "out-warmup", "ray", cores)
    seconds = _run(path, folder / "out-ray_warm", "ray", cores)
    result["runs"]["ray_warm"] = {"seconds": round(seconds, 3), "ratio_to_ideal": round(seconds / ideal, 3)}
    print(f"overhead ray_warm: {seconds:.2f} s = {seconds / ideal:.2f} x ideal", file=sys.stderr)
    # the same grid of idle cells: ideal = cells x cell_seconds / cores whatever the machine's load
    idle = _sweep_file(folder, "idle", 0, cells, {"seconds": cell_seconds}, function="pause")
    idle_ideal = cells * cell_seconds / cores
    result["idle"] = {"ideal_seconds": round(idle_ideal, 3), "runs": {}}
    for name, backend in (("ray_warm", "ray"), ("local", "local")):
        seconds = _run(idle, folder / f"out-idle-{name}", backend, cores)
        result["idle"]["runs"][name] = {"seconds": round(seconds, 3), "ratio_to_ideal": round(seconds / idle_ideal, 3)}
        print(f"idle {name}: {seconds:.2f} s = {seconds / idle_ideal:.2f} x ideal", file=sys.stderr)
    return result


def speedup(folder: Path, cells: int, cell_seconds: float, rounds: int) -> dict:
    """Ray must be up (from :func:`overhead`) with 2 CPUs; 1 vs 2 cells at once, alternated."""
    iterations = calibrate(cell_seconds)
    path = _sweep_file(folder, "speedup", iterations, cells)
    times: dict[str, dict[int, list[float]]] = {"ray": {1: [], 2: []}, "local": {1: [], 2: []}}
    run = 0
    for _ in range(rounds):
        for backend in ("ray", "local"):
            for workers in (1, 2):
                run += 1
                seconds = _run(path, folder / f"out-speedup-{run}", backend, workers)
                times[backend][workers].append(seconds)
                print(f"speed-up {backend} {workers} worker(s): {seconds:.2f} s", file=sys.stderr)
    result = {"cells": cells, "cell_seconds_target": cell_seconds, "iterations": iterations, "rounds": rounds}
    for backend, by_workers in times.items():
        one, two = min(by_workers[1]), min(by_workers[2])
        result[backend] = {"seconds_1_worker": [round(t, 3) for t in by_workers[1]],
                           "seconds_2_workers": [round(t, 3) for t in by_workers[2]],
                           "speedup_best_of_rounds": round(one / two, 3)}
    return result


def resume(folder: Path, cells: int, cell_seconds: float) -> dict:
    """Kill the driver (SIGKILL) once half the cells have records; re-run; count executions."""
    iterations = calibrate(cell_seconds)
    log = folder / "executions.log"
    path = _sweep_file(folder, "resume", iterations, cells, {"log": str(log)})
    out = folder / "out-resume"
    harness = ("import sys; from symlearn.cli import main as m; "
               "m.COMMAND_MODULES = tuple(dict.fromkeys((*m.COMMAND_MODULES, 'symlearn.cli.sweep_command'))); "
               "sys.exit(m.main(sys.argv[1:]))")
    command = [sys.executable, "-c", harness, "sweep", "run", str(path), "--out", str(out), "--local",
               "--workers", "2", "--quiet"]
    results = out / "results.jsonl"
    driver = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
    while not results.exists() or len(results.read_text().splitlines()) < cells // 2:
        time.sleep(0.02)
        if driver.poll() is not None:
            raise SystemExit("the driver ended before it could be killed")
    driver.send_signal(signal.SIGKILL)
    driver.wait()
    time.sleep(1.5)  # the orphaned workers notice within 0.5 s and stop
    before = [json.loads(line) for line in results.read_text().splitlines()]
    finished_before = {(r["params"]["index"], r["seed"]) for r in before if r["status"] == "ok"}
    started_before = len(log.read_text().splitlines())
    done = subprocess.run(command[:-1] + ["--json"], capture_output=True, text=True, cwd=REPO, check=True)
    summary = json.loads(done.stdout)
    after = [tuple(map(int, line.split())) for line in log.read_text().splitlines()[started_before:]]
    ok = [r for r in map(json.loads, results.read_text().splitlines()) if r["status"] == "ok"]
    return {"cells": cells, "finished_before_kill": len(finished_before),
            "in_flight_lost": started_before - len(finished_before),
            "skipped_on_resume": summary["skipped"], "run_on_resume": len(after),
            "finished_cells_run_again": len(set(after) & finished_before),
            "ok_records": len(ok), "distinct_ok_cells": len({r["cell"] for r in ok})}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="50 overhead cells, 12 speed-up cells, 1 round")
    parser.add_argument("--json", default=None, help="also write the results to this file")
    args = parser.parse_args(argv)
    os.environ.setdefault("SYMLEARN_QUIET", "1")
    cores = os.cpu_count() or 1
    load_before = os.getloadavg()
    command = "python benchmarks/sweep_scaling.py" + (" --quick" if args.quick else "")
    with tempfile.TemporaryDirectory(prefix="sweep-scaling-") as tmp:
        folder = Path(tmp)
        over = overhead(folder, 50 if args.quick else 200, 0.1, cores)
        speed = speedup(folder, 12 if args.quick else 24, 0.25, 1 if args.quick else 2)
        import ray

        ray.shutdown()
        resumed = resume(folder, 20 if args.quick else 40, 0.2)
    doc = {"command": command, "machine": platform.platform(), "python": platform.python_version(), "cpus": cores,
           "ray": __import__("ray").__version__, "load_average_before": [round(x, 2) for x in load_before],
           "load_average_after": [round(x, 2) for x in os.getloadavg()],
           "overhead": over, "speedup": speed, "resume": resumed}
    print(f"command: {command}")
    print(f"machine: {platform.machine()}, {cores} cpus, python {platform.python_version()}, load average "
          f"{' '.join(f'{x:.2f}' for x in load_before)} before, {' '.join(f'{x:.2f}' for x in os.getloadavg())} after")
    print(f"\noverhead: {over['cells']} cells x {over['cell_seconds_target']} s; plain loop {over['plain_loop_seconds']} s,"
          f" ideal (/{cores} cores) {over['ideal_seconds']} s\n")
    print("| executor | seconds | / ideal |\n|---|---|---|")
    for name, run in over["runs"].items():
        print(f"| {name} | {run['seconds']:.2f} | {run['ratio_to_ideal']:.2f} |")
    print(f"\nthe same grid of idle (sleeping) cells: ideal {over['idle']['ideal_seconds']} s\n")
    print("| executor | seconds | / ideal |\n|---|---|---|")
    for name, run in over["idle"]["runs"].items():
        print(f"| {name} | {run['seconds']:.2f} | {run['ratio_to_ideal']:.2f} |")
    print(f"\nray.init alone: {over['ray_init_seconds']:.2f} s (in ray_cold, not in ray_warm)")
    print(f"\nspeed-up, {speed['cells']} cells x {speed['cell_seconds_target']} s, best of {speed['rounds']} round(s)\n")
    print("| executor | 1 worker (s) | 2 workers (s) | speed-up |\n|---|---|---|---|")
    for backend in ("ray", "local"):
        row = speed[backend]
        print(f"| {backend} | {min(row['seconds_1_worker']):.2f} | {min(row['seconds_2_workers']):.2f} | "
              f"{row['speedup_best_of_rounds']:.2f} |")
    print(f"\nresume: {json.dumps(resumed)}")
    if args.json:
        from symlearn.atomic import write_text

        write_text(args.json, json.dumps(doc, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
