"""``symlearn doctor``: which optional engines this installation can use."""

from __future__ import annotations


def register(subparsers, common) -> None:
    parser = subparsers.add_parser("doctor", parents=[common()], help="list optional engines and whether they are installed",
                                   description="Show which optional engines (Spot, MONA, SUMO, ...) are available.")
    parser.set_defaults(handler=_doctor)


def _doctor(args, out) -> None:
    import platform

    from symlearn import __version__
    from symlearn.optional import report

    rows = report()
    doc = {"symlearn": __version__, "python": platform.python_version(), "engines": rows}

    def render(d: dict) -> str:
        lines = [f"symlearn {d['symlearn']} on Python {d['python']}"]
        for r in d["engines"]:
            mark = "yes" if r["available"] else "no "
            extra = "" if r["available"] else f"  -> {r['install']}"
            lines.append(f"  [{mark}] {r['name']:<13} {r['purpose']}{extra}")
        return "\n".join(lines)

    out.result(doc, render)
