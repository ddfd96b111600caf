"""A/B of `symlearn ltl dfa --tlsf FILE --json -q` for two source trees: whole-process wall time.

Each file runs ``--repeats`` times per tree, one process each, the trees alternating; the rows record
every wall time, the medians and their ratio, and whether both trees gave the same result (status,
states, edges and a digest of the whole JSON document but its time).

    git archive HEAD | tar -x -C /tmp/ab/before        # the tree to compare against
    python benchmarks/tlsf_dfa_ab.py --before /tmp/ab/before --after . --files FILES \\
        --root <SYNTCOMP/benchmarks>/tlsf-fin --json benchmarks/results/tlsf_moore_vectorised.json
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import time


def run_once(tree: str, tlsf: str, timeout: float) -> tuple[float | None, dict]:
    """Wall seconds (None on timeout) and what the run printed, as a result row."""
    env = dict(os.environ, PYTHONPATH=os.path.abspath(tree))
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "symlearn", "ltl", "dfa", "--tlsf", tlsf, "--json", "-q"],
                              capture_output=True, text=True, env=env, timeout=timeout, cwd="/tmp")
    except subprocess.TimeoutExpired:
        return None, {"status": "timeout"}
    wall = time.perf_counter() - start
    try:
        doc = json.loads(done.stdout)
    except ValueError:
        return wall, {"status": "error", "error": done.stderr.strip()[-200:]}
    if "states" not in doc:
        return wall, {"status": "error", "error": str(doc.get("error", doc))[:200]}
    seconds = doc.pop("seconds", None)
    # the whole document but the time: states, edges, accepting, sink, nodes, transitions
    digest = hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()
    return wall, {"status": "ok", "states": doc["states"], "edges": doc.get("edges"),
                  "diagram_nodes": doc.get("diagram_nodes"), "in_process_s": seconds, "output_sha256": digest}


def compare(path: str, trees: dict[str, str], repeats: int, timeout: float) -> dict:
    row: dict = {"file": path}
    for name in trees:
        row[name] = {"wall_s": []}
    for rep in range(repeats):
        for name in (list(trees) if rep % 2 == 0 else list(reversed(trees))):
            wall, result = run_once(trees[name], path, timeout)
            row[name]["wall_s"].append(None if wall is None else round(wall, 3))
            row[name].update(result)
    b, a = row["before"], row["after"]
    fields = ("status", "states", "edges", "output_sha256")
    row["same_result"] = all(b.get(f) == a.get(f) for f in fields)
    if None not in b["wall_s"] + a["wall_s"]:
        row["median_before_s"] = statistics.median(b["wall_s"])
        row["median_after_s"] = statistics.median(a["wall_s"])
        row["ratio_after_before"] = round(row["median_after_s"] / row["median_before_s"], 3)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="source tree put on PYTHONPATH for 'before'")
    parser.add_argument("--after", required=True, help="source tree for 'after'")
    parser.add_argument("--files", required=True, help="file of .tlsf paths, one a line, relative to --root")
    parser.add_argument("--root", default="", help="directory the paths are relative to")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=150.0)
    parser.add_argument("--json", help="write the rows here (rewritten after every file)")
    args = parser.parse_args()
    trees = {"before": args.before, "after": args.after}
    files = [line.strip() for line in open(args.files) if line.strip()]
    out = {"command": " ".join(sys.argv), "repeats": args.repeats, "timeout_s": args.timeout, "rows": []}
    for path in files:
        row = compare(os.path.join(args.root, path), trees, args.repeats, args.timeout)
        row["file"] = path
        out["rows"].append(row)
        print(path, row["before"].get("states"), row.get("median_before_s"), row.get("median_after_s"),
              row.get("ratio_after_before"), "same" if row["same_result"] else "DIFFERENT", flush=True)
        if args.json:
            with open(args.json, "w") as handle:
                json.dump(out, handle, indent=1)


if __name__ == "__main__":
    main()
