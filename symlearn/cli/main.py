"""The ``symlearn`` entry point.

Each sub-command lives in its own module with a ``register(subparsers, common)`` function that
adds its parser and sets ``handler`` (``handler(args, out) -> int | None``). To add a command,
write such a module and list it in :data:`COMMAND_MODULES`; modules import heavy libraries only
inside handlers, so ``symlearn --help`` stays fast.

Start-up: a module ``symlearn.cli.NAME_command`` registers the top-level command ``NAME``, so
when the command line names one, :func:`main` imports only that module (``symlearn ltl dfa``
never imports the learners' or environments' modules); ``--help``, no command or an unknown
one import them all, so usage messages list every command.

Exit codes: 0 success, 2 bad input or usage (:class:`SymlearnError`), 1 internal failure,
130 interrupted (SIGINT), 143 terminated (SIGTERM, turned into an exception so that files being
written are cleaned up). With ``--json`` an error also prints ``{"error": {...}}`` on stdout
(:func:`error_document`), besides the one line on stderr.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import re
import signal
import sys
import threading
import warnings
import traceback
from collections.abc import Sequence

from symlearn.cli.output import Output
from symlearn.cli.spare_inputs import check_outputs_spare_inputs
from symlearn.errors import SymlearnError, printable

COMMAND_MODULES: tuple[str, ...] = (
    "symlearn.cli.learn_command",
    "symlearn.cli.ilp_command",
    "symlearn.cli.demo_command",
    "symlearn.cli.data_command",
    "symlearn.cli.ltl_command",
    "symlearn.cli.automaton_command",
    "symlearn.cli.doctor_command",
    "symlearn.cli.envs_command",
    "symlearn.cli.domain_command",
    "symlearn.cli.train_command",
    "symlearn.cli.dnf_command",
    "symlearn.cli.sweep_command",
)

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE, EXIT_INTERRUPTED, EXIT_TERMINATED = 0, 1, 2, 130, 143


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so ``finally`` blocks and atomic writers clean up."""


def _raise_terminated(signum, frame):  # pragma: no cover - exercised through a subprocess
    raise Terminated()


def error_document(exc: BaseException, kind: str | None = None) -> dict:
    """The ``{"error": {...}}`` document ``--json`` prints for a failed command."""
    if isinstance(exc, SymlearnError):
        body = {"kind": kind or type(exc).__name__, "message": exc.message, "file": exc.file,
                "line": exc.line, "column": exc.column, "hint": exc.hint}
    elif isinstance(exc, OSError):
        body = {"kind": kind or type(exc).__name__, "message": exc.strerror or str(exc),
                "file": exc.filename, "line": None, "column": None, "hint": None}
    else:
        body = {"kind": kind or type(exc).__name__, "message": str(exc), "file": None, "line": None,
                "column": None, "hint": None}
    return {"error": body}


def common_options(json_output: bool = True) -> argparse.ArgumentParser:
    """Options every command accepts after its name, too (``symlearn demo --quiet``).

    ``SUPPRESS`` defaults keep a value given before the command name from being overwritten.
    """
    parent = argparse.ArgumentParser(add_help=False)
    group = parent.add_argument_group("common options")
    group.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show tracebacks instead of one-line errors")
    group.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS,
                       help="no progress bars or notes on stderr")
    group.add_argument("--seed", type=int, default=argparse.SUPPRESS, help="random seed (default 0)")
    if json_output:
        group.add_argument("--json", action="store_true", default=argparse.SUPPRESS,
                           help="print exactly one JSON document on stdout")
    return parent


class _Parser(argparse.ArgumentParser):
    """One command-line grammar for every command (sub-command parsers are of the same class):
    no silent prefix abbreviations of flags (``--env-kw`` is not ``--env-kwargs``), and a usage
    error is one line like every other error, with "did you mean" for a misspelt flag or choice.
    Remembers the message, so ``--json`` can put it in the error document."""

    last_error: str | None = None
    argv: Sequence[str] = ()  # the words being parsed (set by main), to find the sub-command's flags

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)

    def error(self, message: str):
        # the root parser reports flags its sub-commands did not know: name the sub-command
        parser = _innermost(self, _Parser.argv) if message.startswith("unrecognized arguments") else self
        message = printable(message + _did_you_mean(parser, message))
        _Parser.last_error = f"{parser.prog}: {message}"
        self.exit(EXIT_USAGE, f"{parser.prog}: error: {message} (see {parser.prog} --help)\n")


def _innermost(parser: argparse.ArgumentParser, argv: Sequence[str]) -> argparse.ArgumentParser:
    """The deepest sub-command parser the words select (``symlearn learn dnf`` for ``learn dnf ...``)."""
    words = [w for w in argv if not w.startswith("-")]
    while True:
        chosen = None
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                chosen = next((action.choices[w] for w in words if w in action.choices), None)
        if chosen is None:
            return parser
        parser = chosen


def _did_you_mean(parser: argparse.ArgumentParser, message: str) -> str:
    """`` (did you mean --x?)`` for the first unknown flag or invalid choice in ``message``."""
    import re
    from difflib import get_close_matches

    unknown = re.match(r"unrecognized arguments: (\S+)", message)
    if unknown and unknown[1].startswith("-"):
        flag = unknown[1].split("=")[0]
        close = get_close_matches(flag, [o for o in parser._option_string_actions if o.startswith("--")], n=1)
        return f" (did you mean {close[0]}?)" if close else ""
    choice = re.match(r"argument [^:]+: invalid choice: '([^']*)' \(choose from (.*)\)", message)
    if choice:
        options = [c.strip().strip("'") for c in choice[2].split(",")]
        close = get_close_matches(choice[1], options, n=1)
        return f" (did you mean {close[0]!r}?)" if close else ""
    return ""


def command_name(module: str) -> str:
    """The top-level command a module registers: ``symlearn.cli.ltl_command`` -> ``ltl``."""
    return module.rsplit(".", 1)[-1].removesuffix("_command")


# top-level options that take a value (so the word after them is not the command name)
_VALUED_OPTIONS = ("--seed",)


def requested_command(argv: Sequence[str]) -> str | None:
    """The command named on the command line, if it is one of :data:`COMMAND_MODULES`."""
    words = iter(argv)
    for word in words:
        if word in ("-h", "--help", "--version"):
            return None
        if word in _VALUED_OPTIONS:
            next(words, None)
            continue
        if word.startswith("-"):
            continue
        known = {command_name(m): m for m in COMMAND_MODULES}
        return known.get(word)
    return None


class _VersionAction(argparse.Action):
    """``--version``, reading the installed version only when asked (it costs ~30 ms of start-up)."""

    def __call__(self, parser, namespace, values, option_string=None):  # noqa: ANN001 - argparse's signature
        from symlearn import __version__

        sys.stdout.write(f"symlearn {__version__}\n")  # on stdout, as argparse's own version action
        parser.exit()


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The full parser, or with ``only`` (a module of :data:`COMMAND_MODULES`) just that command."""
    parser = _Parser(
        prog="symlearn",
        description="Learn interpretable symbolic models of behaviour from demonstrations.",
        epilog="Run 'symlearn COMMAND --help' for the options of a command.",
    )
    parser.add_argument("--version", action=_VersionAction, nargs=0, help="show the version and exit")
    parser.add_argument("--debug", action="store_true", help="show tracebacks instead of one-line errors")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bars or notes on stderr")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--json", action="store_true", help="print exactly one JSON document on stdout")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES if only is None else (only,):
        importlib.import_module(name).register(subparsers, common_options)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser(requested_command(sys.argv[1:] if argv is None else list(argv)))
    _Parser.argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse printed the usage error (or --help) on stderr
        words = sys.argv[1:] if argv is None else list(argv)
        if exc.code == EXIT_USAGE and "--json" in words:
            message = _Parser.last_error or "invalid command line"
            print(json.dumps({"error": {"kind": "usage", "message": message, "file": None, "line": None,
                                        "column": None, "hint": "see the usage on stderr"}}))
        raise
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        return _run(parser, args)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


#: a terminal colour or cursor code (CSI), as libraries embed in their warnings
_ANSI_CODE = re.compile(r"\x1b\[[0-9;?]*[ -/]*[@-~]")


@contextlib.contextmanager
def _one_line_warnings(debug: bool):
    """Warnings no command turned into a note of its own (a library's, a learner's) printed as one
    ``warning:`` line without the source path and line Python's default format shows; ``--debug``
    keeps that format. The format, not the display, is replaced, so code that records warnings
    (``warnings.catch_warnings(record=True)``) still gets them."""
    if debug:
        yield
        return
    previous = warnings.formatwarning
    shown: set[str] = set()

    def one_line(message, category, filename, lineno, line=None):
        # gymnasium colours its checker's warnings (ESC[33m ... ESC[0m): the codes are dropped and
        # any other control character escaped, so a log file gets one plain line
        text = "warning: " + printable(_ANSI_CODE.sub("", " ".join(str(message).split()))) + "\n"
        # once per command: a library warns on every environment copy it builds (highway-env's
        # "roundabout-v0 is out of date" came 5 times in one train), and the catch_warnings
        # blocks elsewhere reset Python's own once-per-place registry
        if text in shown:
            return ""
        shown.add(text)
        return text

    warnings.formatwarning = one_line
    try:
        yield
    finally:
        warnings.formatwarning = previous


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    if not getattr(args, "handler", None):
        if args.command:  # a command group such as 'symlearn data' without its sub-command
            args.group_parser.print_help(sys.stderr)
        else:
            parser.print_help(sys.stderr)
        return EXIT_USAGE

    from symlearn.progress import progress_bars

    out = Output(json_mode=getattr(args, "json", False), quiet=args.quiet)
    try:
        check_seed(getattr(args, "seed", 0))
        check_outputs_spare_inputs(args)
        with progress_bars(False if (args.quiet or out.json_mode and not sys.stderr.isatty()) else None), \
                _one_line_warnings(args.debug):
            code = args.handler(args, out)
        return EXIT_OK if code is None else int(code)
    except SymlearnError as exc:
        if args.debug:
            traceback.print_exc()
        print(f"symlearn: error: {exc}", file=sys.stderr)
        _json_error(out, exc)
        return EXIT_USAGE
    except OSError as exc:
        if not _about_a_path(exc):
            return _internal(args, out, exc)
        if args.debug:
            traceback.print_exc()
        where = f"{printable(exc.filename)}: " if exc.filename else ""
        print(f"symlearn: error: {where}{printable(exc.strerror or exc)}", file=sys.stderr)
        _json_error(out, exc)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("symlearn: interrupted", file=sys.stderr)
        _json_error(out, KeyboardInterrupt("interrupted"), "interrupted")
        return EXIT_INTERRUPTED
    except Terminated:
        print("symlearn: terminated", file=sys.stderr)
        _json_error(out, Terminated("terminated"), "terminated")
        return EXIT_TERMINATED
    except Exception as exc:  # a bug in symlearn, not the user's fault
        return _internal(args, out, exc)


def _internal(args: argparse.Namespace, out: Output, exc: BaseException) -> int:
    if args.debug:
        traceback.print_exc()
    else:
        print(f"symlearn: internal error: {type(exc).__name__}: {printable(exc)} "
              "(rerun with --debug for the traceback and please report it)", file=sys.stderr)
    _json_error(out, exc, "internal")
    return EXIT_INTERNAL


def _about_a_path(exc: OSError) -> bool:
    """An OS error about a path the user named (missing, a directory, a file where a folder
    should be, a name over 255 bytes, a read-only disk ...): the user's to fix, reported in one
    line. Others (no path: a broken pipe, a failed fork) stay internal errors."""
    return exc.filename is not None or isinstance(exc, (FileNotFoundError, IsADirectoryError, PermissionError,
                                                        NotADirectoryError, FileExistsError))


#: the seeds numpy's and torch's generators accept
MAX_SEED = 2**32 - 1


def check_seed(seed: int) -> None:
    """``--seed`` within ``0 .. 2**32 - 1`` (numpy's legacy seeding refuses the rest, torch wraps
    them), checked once here for every command."""
    if not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise SymlearnError(f"--seed {seed} is out of range", hint=f"give a whole number from 0 to {MAX_SEED:,}")


def _json_error(out: Output, exc: BaseException, kind: str | None = None) -> None:
    """With ``--json``, the error as the one JSON document on stdout (unless one was printed)."""
    if out.json_mode and not getattr(out, "_emitted", False):
        out.stdout.write(json.dumps(error_document(exc, kind), indent=2) + "\n")
        out.stdout.flush()


def run() -> None:
    sys.exit(main())


if __name__ == "__main__":
    run()
