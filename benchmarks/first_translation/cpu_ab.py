"""CPU-time A/B (issue 27, docs/BENCHMARKS.md "Per-formula overheads"): cpu_ab.py OUT.json ROUNDS REPS TREE... < FILES; per file, ROUNDS child processes per tree (alternating order), each timing its first
translate() and the median of REPS more (time.process_time, so other jobs' load counts less)."""
import sys, json, subprocess, statistics, os
from pathlib import Path
HERE = Path(__file__).resolve().parent
out, rounds, reps, trees = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]
files = [l.strip() for l in sys.stdin if l.strip()]
rows = []
for f in files:
    res = {t: {"first": [], "warm": []} for t in trees}
    for r in range(rounds):
        for t in (trees if r % 2 == 0 else trees[::-1]):
            p = subprocess.run([sys.executable, str(HERE / "cpu.py"), f, str(reps)], capture_output=True,
                               text=True, env={**os.environ, "PYTHONPATH": t, "OMP_NUM_THREADS": "1"}, cwd=t)
            d = json.loads(p.stdout)
            for k in d: res[t][k].append(d[k])
    row = {"file": f.split("tlsf-fin/")[1], "runs": res,
           "median_first_ms": [round(statistics.median(res[t]["first"]) * 1000, 2) for t in trees],
           "median_warm_ms": [round(statistics.median(res[t]["warm"]) * 1000, 2) for t in trees]}
    rows.append(row)
    print(f"{row['file']:75s} first {row['median_first_ms']} warm {row['median_warm_ms']}", flush=True)
json.dump({"trees": trees, "rounds": rounds, "reps": reps, "clock": "time.process_time", "rows": rows}, open(out, "w"), indent=1)
