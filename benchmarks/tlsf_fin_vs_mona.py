"""LTLf -> minimal DFA on SYNTCOMP's finite-trace families (``tlsf-fin``): symlearn vs MONA's construction.

The benchmark set is not committed. Fetch the public SYNTCOMP benchmark repository
(``SYNTCOMP/benchmarks`` on GitHub) and point ``--root`` at its ``tlsf-fin`` folder::

    python benchmarks/tlsf_fin_vs_mona.py --root /path/to/benchmarks/tlsf-fin --per-family 5 \\
        --timeout 60 --json benchmarks/results/tlsf_fin_vs_mona.json

Per formula, both sides run as their own process under the same wall-clock limit and a 4 GB
address-space cap:

* **symlearn**: ``python -m symlearn ltl dfa --tlsf FILE --json`` -- the whole process a user
  waits for (start-up, reading the TLSF file, translation, minimisation); also recorded, as
  ``translate_s``, the translation and minimisation alone as the process timed it (its JSON's
  ``seconds``: no interpreter start-up, imports, TLSF reading or printing) -- the part that
  corresponds to MONA's construction, whose process starts in milliseconds;
* **MONA**: ``mona -q -u -w PROGRAM`` on the MONA program LTLf2DFA writes for the same formula (the
  program is written before the clock starts, so only MONA's own DFA construction is timed).

* **Lydia** (optional, ``--lydia PATH``): the ``lydia`` binary built from its public repository
  (``whitemech/lydia``; it needs CUDD, MONA and Syft+ from the same organisation, see its README;
  set ``LD_LIBRARY_PATH`` to their libraries), run as ``lydia -l ltlf -s -f FILE`` on the same
  formula printed in Lydia's syntax (``X[!]`` strong next, ``X`` weak next; the file on one line
  without a newline, which its parser needs). Recorded: the whole process's wall time and
  Lydia's own "DFA construction" time, and its state count (complete DFA, like ours).

State counts are compared where both finish (MONA's automaton has one extra start state, see
:mod:`symlearn.logic.ltlf.mona`). Parameterised files (full TLSF, with a ``GLOBAL`` section) are
refused by symlearn's basic-TLSF reader and reported as "full TLSF" for both. The sample takes the
files of each family in size order and picks ``--per-family`` of them spread over the sizes, so
the largest of a family is always in. Families are the folder two levels under ``tlsf-fin``
(``Random/Syft``, ``Two-player-Game/Nim``), or one level where there is no deeper one.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

MEMORY = 4 * 1024**3


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def family_of(path: Path, root: Path) -> str:
    parts = path.relative_to(root).parts
    return "/".join(parts[:2]) if len(parts) > 2 else parts[0]


def sample(root: Path, per_family: int) -> dict[str, list[Path]]:
    families: dict[str, list[Path]] = defaultdict(list)
    for path in sorted(root.rglob("*.tlsf")):
        families[family_of(path, root)].append(path)
    chosen = {}
    for family, files in sorted(families.items()):
        files.sort(key=lambda p: (p.stat().st_size, str(p)))
        if len(files) <= per_family:
            chosen[family] = files
            continue
        step = (len(files) - 1) / max(per_family - 1, 1)
        picks = sorted({round(i * step) for i in range(per_family)})
        chosen[family] = [files[i] for i in picks]
    return chosen


def run_symlearn(path: Path, timeout: float) -> dict:
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "symlearn", "ltl", "dfa", "--tlsf", str(path), "--json"],
                              capture_output=True, text=True, timeout=timeout, preexec_fn=_limit_memory,
                              env={**os.environ, "SYMLEARN_QUIET": "1"})
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "seconds": timeout}
    seconds = time.perf_counter() - start
    if done.returncode == 0:
        doc = json.loads(done.stdout)
        return {"status": "ok", "seconds": seconds, "states": doc["states"], "translate_s": doc.get("seconds")}
    message = (done.stderr.strip().splitlines() or [""])[-1]
    status = "full TLSF" if "parameterised (full) TLSF" in message else (
        "memory" if "MemoryError" in message or "memory" in message.lower() else "error")
    return {"status": status, "seconds": seconds, "message": message[:300]}


def _formula(path: Path):
    """The file's formula, or the row of a peer that cannot run on it (full TLSF, bad file)."""
    from symlearn.errors import SymlearnError
    from symlearn.logic.ltlf.tlsf import load_tlsf

    try:
        return load_tlsf(path).formula, None
    except SymlearnError as exc:
        return None, {"status": "full TLSF" if "full) TLSF" in exc.message else "error",
                      "message": exc.message[:300]}


def _run_peer(command: list[str], text: str, suffix: str, timeout: float):
    """``command`` plus a file holding ``text`` (written before the clock starts), under the
    timeout and the memory cap: ``(completed process, seconds)``; ``(None, timeout)`` past it."""
    fd, name = tempfile.mkstemp(suffix=suffix)
    with os.fdopen(fd, "w") as handle:
        handle.write(text)
    try:
        start = time.perf_counter()
        try:
            done = subprocess.run([*command, name], capture_output=True, text=True, timeout=timeout,
                                  preexec_fn=_limit_memory)
        except subprocess.TimeoutExpired:
            return None, timeout
        return done, time.perf_counter() - start
    finally:
        os.unlink(name)


def _failed(done, seconds: float) -> dict:
    # MONA and Lydia stop with an allocation failure under the 4 GB cap: counted as memory
    text = (done.stderr or done.stdout)[-300:]
    status = "memory" if done.returncode < 0 or "alloc" in text.lower() or "memory" in text.lower() else "error"
    return {"status": status, "seconds": seconds, "message": text}


def run_mona(path: Path, timeout: float) -> dict:
    from symlearn.logic.ltlf.mona import _program

    formula, refused = _formula(path)
    if refused:
        return refused
    try:  # LTLf2DFA writes MONA's program; its lark parser recurses once per nesting level
        program, names = _program(formula, printed=False)
    except RecursionError:
        return {"status": "error", "message": "LTLf2DFA could not write the MONA program (recursion depth)"}
    done, seconds = _run_peer(["mona", "-q", "-u", "-w"], program, ".mona", timeout)
    if done is None:
        return {"status": "timeout", "seconds": timeout}
    if done.returncode != 0 or "Automaton has" not in done.stdout:
        return _failed(done, seconds)
    # only the state count is compared: read from MONA's own line, not by building its edges'
    # guards in this process (thousands of files' guards would fill the shared BDD table)
    count = re.search(r"Automaton has (\d+) states?", done.stdout)
    if count is None:
        return {"status": "error", "seconds": seconds, "message": done.stdout[:300]}
    # MONA's dummy start state; a language empty even of the empty word is one state on both sides
    return {"status": "ok", "seconds": seconds, "states": max(int(count.group(1)) - 1, 1)}


def lydia_text(formula) -> str:
    """``formula`` in Lydia's LTLf syntax (fully parenthesised; no recursion: TLSF trees are deep)."""
    from symlearn.logic.ltlf.ast import (Always, And, Const, Eventually, Iff, Implies, Next, Not, Or, Prop,
                                         Release, Then, Until, WeakNext, WeakUntil)

    unary = {Not: "!", Next: "X[!]", WeakNext: "X", Eventually: "F", Always: "G"}
    binary = {And: "&", Or: "|", Implies: "->", Iff: "<->", Until: "U", Release: "R"}
    out: list[str] = []
    stack: list = [formula]
    while stack:
        node = stack.pop()
        if isinstance(node, str):
            out.append(node)
        elif isinstance(node, Const):
            out.append("true" if node.value else "false")
        elif isinstance(node, Prop):
            out.append(node.name if re.fullmatch(r"[a-z_][a-z0-9_]*", node.name) else f'"{node.name}"')
        elif type(node) in unary:
            stack += [")", node.arg, f"{unary[type(node)]}("]
        elif isinstance(node, WeakUntil):  # a W b = b R (a | b)
            stack.append(Release(node.right, Or(node.left, node.right)))
        elif isinstance(node, Then):  # a T b = F(a & X[!] F b)
            stack.append(Eventually(And(node.left, Next(Eventually(node.right)))))
        elif type(node) in binary:
            stack += [")", node.right, f" {binary[type(node)]} ", node.left, "("]
        else:
            raise TypeError(f"no Lydia syntax for {type(node).__name__}")
    return "".join(out)


def run_lydia(path: Path, timeout: float, binary: str) -> dict:
    formula, refused = _formula(path)
    if refused:
        return refused
    # one line without a newline: Lydia's parser stops at one
    done, seconds = _run_peer([binary, "-l", "ltlf", "-s", "-f"], lydia_text(formula), ".ltlf", timeout)
    if done is None:
        return {"status": "timeout", "seconds": timeout}
    count = re.search(r"Number of states (\d+)", done.stdout)
    built = re.search(r"Time elapsed for DFA construction: ([0-9.]+) ?ms", done.stdout)
    if done.returncode != 0 or count is None:
        return _failed(done, seconds)
    return {"status": "ok", "seconds": seconds, "states": int(count.group(1)),
            "construction_s": float(built.group(1)) / 1000 if built else None}


def _lydia_columns(mine: list[dict]) -> dict:
    """The Lydia columns of a family: solved, disagreements with symlearn, and on the family's
    largest DFA that both build, symlearn's translation time over Lydia's construction time."""
    if not any("lydia" in r for r in mine):
        return {}
    both = [r for r in mine if r["symlearn"]["status"] == "ok" and r.get("lydia", {}).get("status") == "ok"]
    largest = max(both, key=lambda r: (r["symlearn"]["states"], r["symlearn"]["seconds"]), default=None)
    ratio = None
    if largest is not None and largest["lydia"].get("construction_s") and largest["symlearn"].get("translate_s"):
        ratio = largest["symlearn"]["translate_s"] / max(largest["lydia"]["construction_s"], 1e-9)
    paired = [(r["symlearn"]["translate_s"], r["lydia"]["construction_s"]) for r in both
              if r["symlearn"].get("translate_s") is not None and r["lydia"].get("construction_s")]
    return {"lydia_solved": sum(r.get("lydia", {}).get("status") == "ok" for r in mine),
            "median_ratio_translate_over_lydia_construction":
                statistics.median(t / max(c, 1e-9) for t, c in paired) if paired else None,
            "lydia_state_disagreements": sum(r["symlearn"]["states"] != r["lydia"]["states"] for r in both),
            "lydia_median_s": statistics.median([r["lydia"]["seconds"] for r in both]) if both else None,
            "largest_both_file": largest["file"] if largest else None,
            "largest_both_states": largest["symlearn"]["states"] if largest else None,
            "largest_translate_over_lydia_construction": ratio}


def summarise(rows: list[dict]) -> dict[str, dict]:
    table: dict[str, dict] = {}
    for family in sorted({r["family"] for r in rows}):
        mine = [r for r in rows if r["family"] == family]
        both = [r for r in mine if r["symlearn"]["status"] == "ok" and r["mona"]["status"] == "ok"]
        ratios = [r["symlearn"]["seconds"] / max(r["mona"]["seconds"], 1e-9) for r in both]
        translated = [r["symlearn"].get("translate_s") for r in both]
        translated = translated if all(t is not None for t in translated) else []
        table[family] = {
            "formulas": len(mine),
            "symlearn_solved": sum(r["symlearn"]["status"] == "ok" for r in mine),
            "mona_solved": sum(r["mona"]["status"] == "ok" for r in mine),
            "full_tlsf": sum(r["symlearn"]["status"] == "full TLSF" for r in mine),
            "state_disagreements": sum(r["symlearn"]["states"] != r["mona"]["states"] for r in both),
            "symlearn_median_s": statistics.median([r["symlearn"]["seconds"] for r in both]) if both else None,
            "symlearn_max_s": max((r["symlearn"]["seconds"] for r in both), default=None),
            "mona_median_s": statistics.median([r["mona"]["seconds"] for r in both]) if both else None,
            "mona_max_s": max((r["mona"]["seconds"] for r in both), default=None),
            "median_ratio_symlearn_over_mona": statistics.median(ratios) if ratios else None,
            "symlearn_translate_median_s": statistics.median(translated) if translated else None,
            "median_ratio_translate_over_mona": statistics.median(
                [t / max(r["mona"]["seconds"], 1e-9) for t, r in zip(translated, both)]) if translated else None,
            "largest_dfa": max((r["symlearn"]["states"] for r in both), default=None),
            **_lydia_columns(mine),
        }
    return table


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", required=True, type=Path, help="the tlsf-fin folder of SYNTCOMP/benchmarks")
    parser.add_argument("--per-family", type=int, default=5)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--json", type=Path, help="write the raw rows and the per-family table here")
    parser.add_argument("--lydia", metavar="PATH", help="also run this lydia binary on every formula")
    parser.add_argument("--families", help="only these families (comma-separated, as printed)")
    args = parser.parse_args(argv)
    chosen = sample(args.root, args.per_family)
    if args.families:
        wanted = set(args.families.split(","))
        chosen = {family: files for family, files in chosen.items() if family in wanted}
    rows = []
    for family, files in chosen.items():
        for path in files:
            row = {"family": family, "file": str(path.relative_to(args.root)),
                   "symlearn": run_symlearn(path, args.timeout), "mona": run_mona(path, args.timeout)}
            if args.lydia:
                row["lydia"] = run_lydia(path, args.timeout, args.lydia)
            rows.append(row)
            if args.json:  # written after every formula: a killed run keeps what it measured
                _write(args, rows)
            print(f"{family:32s} {path.name:40s} symlearn {row['symlearn']['status']:9s} "
                  f"{row['symlearn'].get('seconds', 0):7.2f}s {row['symlearn'].get('states', '-')!s:>7}   "
                  f"mona {row['mona']['status']:9s} {row['mona'].get('seconds', 0):7.2f}s "
                  f"{row['mona'].get('states', '-')!s:>7}"
                  + (f"   lydia {row['lydia']['status']:9s} {row['lydia'].get('seconds', 0):7.2f}s "
                     f"{row['lydia'].get('states', '-')!s:>7}" if "lydia" in row else ""), flush=True)
    print(json.dumps(summarise(rows), indent=1))
    if args.json:
        _write(args, rows)
    return 0


def _write(args: argparse.Namespace, rows: list[dict]) -> None:
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps({"command": "python benchmarks/tlsf_fin_vs_mona.py " + " ".join(sys.argv[1:]),
                                     "timeout": args.timeout, "memory_bytes": MEMORY, "rows": rows,
                                     "families": summarise(rows)}, indent=1))


if __name__ == "__main__":
    raise SystemExit(main())
