"""Fresh-process first-translation wall times, trees interleaved (issue 27, docs/BENCHMARKS.md "Per-formula overheads"):
wall_ab.py OUT.json REPS TREE... < FILES (one basic TLSF path a line; a TREE holds symlearn/). Also checks the trees
 give the same DFA (a digest of the listed edges, for DFAs of at most 300 states)."""
import sys, json, subprocess, statistics, os
from pathlib import Path
HERE = Path(__file__).resolve().parent
out, reps, trees = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
files = [l.strip() for l in sys.stdin if l.strip()]
res = {t: {f: [] for f in files} for t in trees}
meta = {}
for r in range(reps):
    for f in files:
        for t in (trees if r % 2 == 0 else trees[::-1]):
            p = subprocess.run([sys.executable, str(HERE / "fresh.py"), f], capture_output=True, text=True,
                               env={**os.environ, "PYTHONPATH": t, "OMP_NUM_THREADS": "1"}, cwd=t)
            d = json.loads(p.stdout)
            res[t][f].append(d["s"])
            meta.setdefault(f, {}).setdefault(t, (d["states"], d["digest"]))
rows = []
for f in files:
    med = [statistics.median(res[t][f]) for t in trees]
    same = len({meta[f][t] for t in trees}) == 1
    rows.append({"file": f.split("tlsf-fin/")[1], "states": meta[f][trees[0]][0], "same_dfa": same,
                 **{f"median_ms_{i}": round(m * 1000, 2) for i, m in enumerate(med)},
                 "all_s": {t: res[t][f] for t in trees}})
    print(f"{f.split('tlsf-fin/')[1]:75s} {meta[f][trees[0]][0]:6d} " + " ".join(f"{m*1000:8.2f}" for m in med)
          + f"  ratio {med[-1]/med[0]:.2f} same={same}", flush=True)
json.dump({"trees": trees, "reps": reps, "rows": rows}, open(out, "w"), indent=1)
