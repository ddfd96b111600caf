"""``symlearn dnf``: read DNF constraint files and evaluate them on points.

``symlearn dnf eval RULES.dnf --points P.npz [--features a,b,...] [--per-conjunction] [--json]``

prints ``{"unsafe": [one bool per point], ...}``: a point is unsafe when one conjunction of the
file holds on it. ``P.npz`` (read with ``allow_pickle=False``) holds either one array
``points`` of shape ``(N, k)``, its columns named by ``--features`` (or by a 1-D string member
``features``), or one 1-D array per feature, named after it. Every feature the rules use must
be there, else a one-line error names the missing ones.

``symlearn dnf show RULES.dnf [--simplify] [--style ascii|unicode|latex]`` prints the rules
(canonical spelling), their features and size; ``--simplify`` prints the simplified rules and
whether they are equivalent (always, checked by box algebra).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from symlearn.cli.output import blame_file


def register(subparsers, common) -> None:
    group = subparsers.add_parser("dnf", help="show DNF constraint files and evaluate them on points",
                                  description="DNF constraints over named features: one conjunction per line, "
                                              "atoms 'feature op number' joined by '&' (docs/FORMATS.md).")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="dnf_command", metavar="SUBCOMMAND")

    evaluate = commands.add_parser("eval", parents=[common()], help="which points the rules flag as unsafe",
                                   description="Evaluate a DNF file on the points of an NPZ archive: one array "
                                               "'points' (N, k) with --features naming its columns, or one 1-D "
                                               "array per feature; or on the states of demonstrations (--demos), "
                                               "to re-check edited rules against the data.")
    evaluate.add_argument("rules", metavar="RULES", help="a .dnf text file (or its .json form)")
    where = evaluate.add_mutually_exclusive_group(required=True)
    where.add_argument("--points", metavar="P.npz", help="the points (NPZ, no pickle)")
    where.add_argument("--demos", metavar="D.jsonl|D.npz",
                       help="demonstrations: every state is a point (feature-dict states by their keys, vector "
                            "states as x0, x1, ... or --features), as learn dnf reads them")
    evaluate.add_argument("--features", help="comma-separated names of the columns of 'points' (or of the "
                                             "demonstrations' vector states)")
    evaluate.add_argument("--per-conjunction", action="store_true",
                          help="also list, per point, which conjunctions hold")
    evaluate.set_defaults(handler=_eval)

    show = commands.add_parser("show", parents=[common()], help="print the rules, their features and size",
                               description="Parse a DNF file and print it in canonical spelling.")
    show.add_argument("rules", metavar="RULES")
    show.add_argument("--simplify", action="store_true", help="print the simplified, equivalent rules")
    show.add_argument("--style", choices=("ascii", "unicode", "latex"), default="ascii")
    show.set_defaults(handler=_show)


def read_points(path: str, features: str | None):
    """``(columns, n)``: a ``name -> 1-D array`` mapping read from an NPZ file without pickle."""
    import numpy as np

    from symlearn.errors import DataError

    from symlearn.data.npz_format import open_npz

    # a regular file, sizes and dtypes from the headers before anything is decompressed (a zip
    # bomb or /dev/zero stops here)
    archive = open_npz(path)
    try:
        if isinstance(archive, np.ndarray):      # a bare .npy: the points array itself
            members = {"points": archive}
        else:
            with archive:
                members = {name: archive[name] for name in archive.files}
    except ValueError as exc:  # object arrays refuse to load without pickle
        raise DataError(f"malformed archive: {exc}", file=path) from None
    if "points" not in members and ("__meta__" in members or "observations" in members):
        # demonstrations (symlearn's or a D4RL table): the points are not its members one by one
        raise DataError("this is a demonstrations file, not points: dnf eval reads an array 'points' (N, k) or one "
                        "1-D array per feature", file=path,
                        hint="dnf eval RULES --demos FILE reads the demonstrations' states as the points; "
                             "or save the states you care about as np.savez('points.npz', points=states, "
                             "features=names)")
    if "points" in members:
        points = members["points"]
        if points.ndim != 2:
            raise DataError(f"'points' must have shape (N, k), not {points.shape}", file=path)
        if features is not None:
            names = [n.strip() for n in features.split(",")]
        elif "features" in members and members["features"].dtype.kind == "U" and members["features"].ndim == 1:
            names = [str(n) for n in members["features"]]
        else:
            raise DataError(f"name the {points.shape[1]} columns of 'points'", file=path,
                            hint="--features a,b,... (or store a 1-D string member 'features')")
        if len(names) != points.shape[1] or len(set(names)) != len(names) or not all(names):
            raise DataError(f"--features gives {len(names)} names ({', '.join(names)}) for the "
                            f"{points.shape[1]} columns of 'points' (names must be distinct)", file=path)
        columns = {name: points[:, j] for j, name in enumerate(names)}
    else:
        if features is not None:
            raise DataError("--features names the columns of a 'points' array; this archive has one array "
                            "per feature", file=path)
        columns = {name: a for name, a in members.items()}
        bad = [f"{name} {a.shape}" for name, a in columns.items() if a.ndim != 1]
        if bad:
            raise DataError(f"per-feature arrays must be 1-D: {', '.join(bad)}", file=path,
                            hint="or store one (N, k) array named 'points'")
        if len({a.shape[0] for a in columns.values()}) > 1:
            raise DataError("per-feature arrays have different lengths: "
                            + ", ".join(f"{n} {a.shape[0]}" for n, a in columns.items()), file=path)
    n = len(next(iter(columns.values()))) if columns else 0
    return columns, n


EVAL_BLOCK_CELLS = 1 << 24  # booleans of the points x conjunctions table held at once (16 MB)
MAX_HOLDING = 10_000_000  # (point, conjunction) pairs --per-conjunction may list


def _eval(args: argparse.Namespace, out) -> None:
    import numpy as np

    from symlearn.errors import DataError, LimitExceededError
    from symlearn.logic.dnf import load

    rules = load(args.rules)
    source = args.points or args.demos
    where = None
    if args.demos:
        from symlearn.cli.dnf_demos import demonstration_points

        columns, n, where = demonstration_points(args.demos, args.features)
    else:
        columns, n = read_points(args.points, args.features)
    missing = [f for f in rules.features if f not in columns]
    if missing:
        close = _close_names(missing, columns)
        unnamed = None
        if where is not None:
            from symlearn.cli.dnf_demos import unnamed_columns_hint

            unnamed = unnamed_columns_hint(args.demos, args.features, columns)
        raise DataError(f"the rules use feature{'s' if len(missing) > 1 else ''} {', '.join(missing)}, "
                        f"which the {'demonstrations' if where else 'points'} do not have (they have: "
                        f"{', '.join(columns) or 'none'})", file=source,
                        hint=unnamed or (f"did you mean {close}? (a feature renamed in the rules or in the data)"
                                         if close else None))
    m = len(rules)
    # the points x conjunctions table is built a block of points at a time (at most
    # EVAL_BLOCK_CELLS cells): 2e4 points x 2e5 conjunctions asked numpy for 3.7 GiB at once
    rows = max(1, EVAL_BLOCK_CELLS // max(m, 1))
    unsafe = np.zeros(n, dtype=bool)
    hits = np.zeros(m, dtype=np.int64)
    holding: list[list[int]] = []
    listed = 0
    for start in range(0, max(n, 1), rows):
        block = {name: column[start:start + rows] for name, column in columns.items()}
        with blame_file(source):
            per = rules.evaluate(block, per_conjunction=True)
        unsafe[start:start + len(per)] = per.any(axis=1)
        hits += per.sum(axis=0, dtype=np.int64)
        if args.per_conjunction:
            listed += int(per.sum())
            if listed > MAX_HOLDING:
                raise LimitExceededError(f"--per-conjunction would list more than {MAX_HOLDING:,} (point, "
                                         f"conjunction) pairs ({m:,} conjunctions, {n:,} points); leave it "
                                         f"out for the counts per conjunction", file=args.rules)
            holding.extend(np.flatnonzero(row).tolist() for row in per)
    doc = {"rules": str(args.rules), "points": str(source), "n_points": n,
           "features": list(rules.features), "conjunctions": m,
           "unsafe_count": int(unsafe.sum()),
           "conjunction_hits": hits.tolist(),
           "unsafe": unsafe.tolist()}
    if args.per_conjunction:
        doc["holding"] = holding
    if where is not None:
        # which demonstration and step: the row number alone is meaningless to whoever edits the rules
        doc["demos"] = str(args.demos)
        doc["first_unsafe"] = None
        if unsafe.any():
            row = int(np.flatnonzero(unsafe)[0])
            point = {name: column[row:row + 1] for name, column in columns.items()}
            conjunction = int(np.flatnonzero(rules.evaluate(point, per_conjunction=True)[0])[0])
            doc["first_unsafe"] = {"demonstration": where[row][0], "step": where[row][1], "conjunction": conjunction}
    out.result(doc, _render_eval)


def _close_names(missing: list[str], columns) -> str | None:
    """The data's feature names close to the rules' missing ones (``speed`` for ``sped``)."""
    import difflib

    close = []
    for name in missing:
        match = difflib.get_close_matches(name, list(columns), n=1, cutoff=0.6) or \
            [c for c in columns if c.lower() == name.lower()]
        if match:
            close.append(f"{match[0]} for {name}")
    return ", ".join(close) or None


def _render_eval(doc: dict) -> str:
    from symlearn.cli.dnf_demos import first_unsafe_line

    what = "demonstrated states" if "demos" in doc else "points"
    lines = [f"{doc['rules']}: {doc['unsafe_count']} of {doc['n_points']} {what} unsafe "
             f"({doc['conjunctions']} conjunctions over {', '.join(doc['features']) or 'no features'})"]
    hits = [f"#{i + 1}: {h}" for i, h in enumerate(doc["conjunction_hits"])]
    if hits:
        lines.append("points per conjunction (in file order): " + ", ".join(hits))
    flagged = [i for i, u in enumerate(doc["unsafe"]) if u]
    if flagged:
        shown = ", ".join(map(str, flagged[:50])) + (f", ... ({len(flagged) - 50} more)" if len(flagged) > 50 else "")
        lines.append(f"unsafe {what}: {shown}")
    first = first_unsafe_line(doc)
    if first:
        lines.append(first)
    return "\n".join(lines)


def _show(args: argparse.Namespace, out) -> None:
    from symlearn.logic.dnf import load

    rules = load(args.rules)
    doc = {"rules": str(args.rules), "text": rules.to_string(args.style), "features": list(rules.features),
           "conjunctions": len(rules), "atoms": sum(len(c) for c in rules)}
    if args.simplify:
        simple = rules.simplify()
        doc.update({"simplified": simple.to_string(args.style), "simplified_conjunctions": len(simple),
                    "simplified_atoms": sum(len(c) for c in simple), "equivalent": simple.equivalent(rules)})

    def render(d: dict) -> str:
        text = d["simplified"] if "simplified" in d else d["text"]
        size = (f"{d['simplified_conjunctions']} conjunctions, {d['simplified_atoms']} atoms "
                f"(from {d['conjunctions']}, {d['atoms']})" if "simplified" in d
                else f"{d['conjunctions']} conjunction{'s' if d['conjunctions'] != 1 else ''}, {d['atoms']} "
                     f"atom{'s' if d['atoms'] != 1 else ''}")
        return f"{text}\n# {size}; features: {', '.join(d['features']) or 'none'}"

    out.result(doc, render)
