"""A sweep file: what to run, over which parameters and seeds, what to keep.

.. code-block:: toml

    [sweep]
    name = "gridworld stochasticity"
    function = "../gridworld_stochasticity.py:cell"  # or "package.module:function", or
    # command = ["symlearn", "ltl", "learn", "{sample}", "--json"]
    seeds = 5                 # 0..4, or a list: [0, 3, 7]
    metrics = ["reward"]      # keys of the function's result to keep (default: all)
    timeout = 600             # seconds per attempt of a cell (default: none)
    retries = 2               # further attempts after a crash or a timeout (default 2)
    cpus = 1                  # CPUs one cell uses (Ray reserves them; OMP threads follow)

    [fixed]                   # passed to every cell
    episodes = 300

    [grid]                    # every combination (the cartesian product), in file order
    p = [0.0, 0.3, 0.5]
    method = ["MCE-ICRL", "ME-ICRL"]

    [[cases]]                 # optional: explicit parameter sets, each crossed with the grid
    demos = 10

    [report]                  # optional: how `symlearn sweep report` draws it
    x = "p"                   # the parameter on the x axis of line plots
    group = "method"          # one line / bar per value of this parameter
    plot = ["reward"]         # the metrics that get figures (default: every one)
    curve_x = { returns = "training episode" }   # x axis of a list-valued metric
    [report.labels]           # axis text with units, by parameter or metric name
    p = "slip probability p"

A cell is one parameter set and one seed; the function is called as ``function(**params,
seed=seed)`` and returns a mapping of metrics (numbers, strings, lists of numbers for curves).
Every parameter must be one the function accepts (checked against its signature before anything
runs, so a typo does not cost a grid of failed cells). A command gets its parameters and
``{seed}`` through ``{name}`` placeholders in its words and must print one JSON document;
``metrics`` then are dotted paths into it (``result.score``).

Mistakes are :class:`~symlearn.errors.ParseError` / :class:`~symlearn.errors.DataError` with the
file and, where a key is to blame, its line.
"""

from __future__ import annotations

import datetime
import hashlib
import inspect
import itertools
import json
import re
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symlearn.errors import DataError, ParseError
from symlearn.input_limits import MAX_JSON_DEPTH, depth, load_toml, read_input_text
from symlearn.sweep.target_policy import command_refusal, function_refusal, outside_refusal, path_word

SECTIONS = {"sweep", "fixed", "grid", "cases", "report"}
SWEEP_KEYS = {"name", "function", "command", "seeds", "metrics", "timeout", "retries", "cpus"}
REPORT_KEYS = {"x", "group", "labels", "curve_x", "plot"}
#: the parameter every cell receives; a grid may not set it
SEED = "seed"
DEFAULT_RETRIES = 2
#: cells one sweep may have (each is a record in the store; a typo such as seeds = 1000000000
#: must not list a billion of them)
MAX_CELLS = 1_000_000
#: seeds are passed to numpy's and torch's generators
MAX_SEED = 2**32 - 1
#: nesting of a sweep file's values (they are written as JSON)
MAX_DEPTH = MAX_JSON_DEPTH - 10
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_PLACEHOLDER = re.compile(r"\{([A-Za-z_][A-Za-z0-9_]*)\}")


@dataclass(frozen=True)
class Cell:
    """One unit of work: a parameter set and a seed; ``id`` is stable across runs and machines."""

    id: str
    params: dict[str, Any]
    seed: int
    index: int

    def label(self) -> str:
        shown = ", ".join(f"{k}={v}" for k, v in self.params.items())
        return f"{shown}{', ' if shown else ''}seed={self.seed}"


@dataclass
class SweepSpec:
    """A parsed sweep file (see the module docstring)."""

    path: Path
    name: str
    function: str | None
    command: list[str] | None
    seeds: list[int]
    metrics: list[str] | None
    timeout: float | None
    retries: int
    cpus: float
    fixed: dict[str, Any]
    grid: dict[str, list[Any]]
    cases: list[dict[str, Any]]
    report: dict[str, Any] = field(default_factory=dict)

    @property
    def target(self) -> str:
        """What runs, as recorded in cell ids: the function reference or the command words."""
        return self.function if self.function is not None else json.dumps(self.command)

    def identity(self) -> dict[str, Any]:
        """What decides the results: a folder written for another identity is another experiment.
        Timeouts, retries, CPUs and report settings may change between runs of one sweep."""
        return {"target": self.target, "fixed": self.fixed, "grid": self.grid, "cases": self.cases,
                "seeds": self.seeds, "metrics": self.metrics}

    def fingerprint(self) -> str:
        return hashlib.sha256(_canonical(self.identity()).encode()).hexdigest()

    def parameter_names(self) -> list[str]:
        names = list(self.fixed)
        for case in self.cases:
            names += [k for k in case if k not in names]
        return names + [k for k in self.grid if k not in names]

    def cells(self) -> list[Cell]:
        """Every cell, in a fixed order: cases, then the grid in file order, then seeds."""
        cells = []
        grid_keys = list(self.grid)
        for case in self.cases or [{}]:
            for values in itertools.product(*(self.grid[k] for k in grid_keys)):
                params = {**self.fixed, **case, **dict(zip(grid_keys, values))}
                for seed in self.seeds:
                    cells.append(Cell(cell_id(self.target, params, seed, self.metrics), params, seed, len(cells)))
        return cells

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "function": self.function, "command": self.command, "seeds": self.seeds,
                "metrics": self.metrics, "timeout": self.timeout, "retries": self.retries, "cpus": self.cpus,
                "fixed": self.fixed, "grid": self.grid, "cases": self.cases, "report": self.report,
                "path": str(self.path)}

    @classmethod
    def from_json(cls, doc: dict[str, Any]) -> "SweepSpec":
        """The spec a results folder recorded; a field of the wrong type is a :class:`DataError`
        naming it (the file may have been edited by hand)."""
        problem = _recorded_problem(doc)
        if problem:
            raise DataError(f"the recorded sweep is malformed: {problem}")
        return cls(path=Path(doc["path"]), name=doc["name"], function=doc["function"], command=doc["command"],
                   seeds=list(doc["seeds"]), metrics=doc["metrics"], timeout=doc["timeout"],
                   retries=doc["retries"], cpus=doc["cpus"], fixed=dict(doc["fixed"]),
                   grid={k: list(v) for k, v in doc["grid"].items()}, cases=[dict(c) for c in doc["cases"]],
                   report=dict(doc.get("report") or {}))


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _recorded_problem(doc: Any) -> str | None:
    """What is wrong with a recorded spec (``sweep.json``'s ``spec``), or None."""
    if not isinstance(doc, dict):
        return "'spec' must be an object"
    strings = lambda v: isinstance(v, list) and all(isinstance(w, str) for w in v)  # noqa: E731
    checks = {
        "path": lambda v: isinstance(v, str),
        "name": lambda v: isinstance(v, str),
        "function": lambda v: v is None or isinstance(v, str),
        "command": lambda v: v is None or (strings(v) and bool(v)),
        "seeds": lambda v: isinstance(v, list) and bool(v) and all(_is_int(x) for x in v),
        "metrics": lambda v: v is None or strings(v),
        "timeout": lambda v: v is None or (_is_number(v) and v > 0),
        "retries": lambda v: _is_int(v) and v >= 0,
        "cpus": lambda v: _is_number(v) and v > 0,
        "fixed": lambda v: isinstance(v, dict),
        "grid": lambda v: isinstance(v, dict) and all(isinstance(x, list) and x for x in v.values()),
        "cases": lambda v: isinstance(v, list) and all(isinstance(c, dict) for c in v),
    }
    for key, valid in checks.items():
        if key not in doc:
            return f"it lacks {key!r}"
        if not valid(doc[key]):
            return f"{key!r} has the wrong type ({type(doc[key]).__name__})"
    if not isinstance(doc.get("report") or {}, dict):
        return "'report' must be an object"
    if (doc["function"] is None) == (doc["command"] is None):
        return "it needs exactly one of 'function' and 'command'"
    seeds, grid, cases = doc["seeds"], doc["grid"], doc["cases"]
    count = len(seeds) * max(1, len(cases))
    for values in grid.values():
        count *= len(values)
        if count > MAX_CELLS:
            return f"it has more than {MAX_CELLS:,} cells"
    return None


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def cell_id(target: str, params: dict[str, Any], seed: int, metrics: list[str] | None = None) -> str:
    """16 hex digits of the hash of what the cell computes and keeps: the same cell in another
    sweep file (a grid grown by a value, more seeds) has the same id, so its record can be
    reused; one that keeps other metrics has another (its old records lack them)."""
    key = {"target": target, "params": params, "seed": seed, "metrics": metrics}
    return hashlib.sha256(_canonical(key).encode()).hexdigest()[:16]


# -- reading ----------------------------------------------------------------------------------------

def read_spec(path: str | Path, *, check_target: bool = True, allow_packages: Iterable[str] = (),
              allow_outside: bool = False) -> SweepSpec:
    """Parse and check the sweep file at ``path``. ``check_target``: import the function and check
    the parameters against its signature (off when only the recorded spec is re-read);
    ``allow_packages``: installed packages whose functions the user lets the file name;
    ``allow_outside``: let its function file and its command's paths lie outside the sweep file's
    folder and the current folder (symlearn/sweep/target_policy.py)."""
    path = Path(path)
    text = read_input_text(path)
    try:
        doc = load_toml(text, source=path)
    except tomllib.TOMLDecodeError as exc:
        line, column = _toml_position(str(exc), text)
        message = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)", "", str(exc))
        raise ParseError(f"invalid TOML: {message}", file=path, line=line, column=column) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise ParseError(f"TOML nested more than {MAX_DEPTH} levels deep", file=path) from None
    if depth(doc) > MAX_DEPTH:  # the values are written as JSON (cell ids, records): bounded nesting
        raise ParseError(f"TOML nested more than {MAX_DEPTH} levels deep", file=path)
    where = _Locator(path, text)
    _refuse_dates(doc, where)
    for section in doc:
        if section not in SECTIONS:
            raise where.error(f"unknown section [{section}]", None, section,
                              hint=f"the sections are {', '.join(sorted(SECTIONS))}")
    sweep = doc.get("sweep")
    if not isinstance(sweep, dict):
        raise DataError("a sweep file needs a [sweep] table", file=path,
                        hint='[sweep] with function = "module:function" (or command = [...]) and seeds')
    for key in sweep:
        if key not in SWEEP_KEYS:
            raise where.error(f"unknown key {key!r} in [sweep]", "sweep", key,
                              hint=f"the keys are {', '.join(sorted(SWEEP_KEYS))}")
    function, command = sweep.get("function"), sweep.get("command")
    if (function is None) == (command is None):
        raise where.error("[sweep] needs exactly one of function = \"module:function\" and command = [...]",
                          "sweep", "function" if function is not None else None)
    if function is not None and (not isinstance(function, str) or ":" not in function):
        raise where.error(f"function must be \"module:function\" or \"file.py:function\", not {function!r}",
                          "sweep", "function")
    if command is not None and (not isinstance(command, list) or not command
                                or not all(isinstance(w, str) for w in command)):
        raise where.error("command must be a non-empty list of strings", "sweep", "command")
    refusal = (function_refusal(function, path.parent, allow_packages, allow_outside=allow_outside)
               if function is not None else command_refusal(command))
    if refusal:  # before anything is imported or run (symlearn/sweep/target_policy.py)
        raise where.error(f"refused: {refusal}", "sweep", "function" if function is not None else "command",
                          hint="see 'Sweep files' in docs/FORMATS.md for what a sweep may run")
    seeds = _seeds(sweep.get("seeds", 1), where)
    metrics = sweep.get("metrics")
    if metrics is not None and (not isinstance(metrics, list) or not metrics
                                or not all(isinstance(m, str) and m for m in metrics)):
        raise where.error("metrics must be a non-empty list of names", "sweep", "metrics")
    timeout = _positive(sweep.get("timeout"), "timeout", where)
    retries = sweep.get("retries", DEFAULT_RETRIES)
    if not isinstance(retries, int) or isinstance(retries, bool) or retries < 0:
        raise where.error(f"retries must be a whole number >= 0, not {retries!r}", "sweep", "retries")
    cpus = _positive(sweep.get("cpus", 1), "cpus", where)
    fixed = _table(doc, "fixed", where)
    grid = _table(doc, "grid", where)
    for key, values in grid.items():
        if not isinstance(values, list):
            raise where.error(f"grid parameter {key!r} must be a list of values", "grid", key,
                              hint=f"put a single value under [fixed]: {key} = {_canonical(values)}")
        if not values:
            raise where.error(f"grid parameter {key!r} is an empty list: the grid has 0 cells", "grid", key)
        if len({_canonical(v) for v in values}) != len(values):
            raise where.error(f"grid parameter {key!r} lists a value twice", "grid", key)
        if key in fixed:
            raise where.error(f"parameter {key!r} is both in [fixed] and in [grid]", "grid", key)
    cases = doc.get("cases", [])
    if not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases):
        raise where.error("cases must be [[cases]] tables", None, "cases")
    for case in cases:
        for key in case:
            _check_name(key, "cases", where)
            if key in grid:
                raise where.error(f"parameter {key!r} is both in [[cases]] and in [grid]", "cases", key)
    report = doc.get("report", {})
    if not isinstance(report, dict):
        raise where.error("[report] must be a table", None, "report")
    for key in report:
        if key not in REPORT_KEYS:
            raise where.error(f"unknown key {key!r} in [report]", "report", key,
                              hint=f"the keys are {', '.join(sorted(REPORT_KEYS))}")
    _check_cell_count(seeds, grid, cases, where)
    spec = SweepSpec(path=path, name=str(sweep.get("name") or path.stem), function=function, command=command,
                     seeds=seeds, metrics=metrics, timeout=timeout, retries=retries, cpus=cpus, fixed=fixed,
                     grid=grid, cases=[dict(c) for c in cases], report=dict(report))
    names = spec.parameter_names()
    for key in ("x", "group"):
        if key in report and report[key] not in names:
            raise where.error(f"[report] {key} = {report[key]!r} is not a parameter of the sweep", "report", key,
                              hint=f"the parameters are {', '.join(names) or '(none)'}")
    plot = report.get("plot")
    if plot is not None and (not isinstance(plot, list) or not all(isinstance(m, str) for m in plot)):
        raise where.error("[report] plot must be a list of metric names", "report", "plot")
    if command is not None and not allow_outside:
        _check_command_paths(spec, where)
    if check_target:
        if function is not None:
            check_parameters(resolve_function(function, path.parent, where), names, where)
        else:
            _check_command(command, names, where)
    return spec


def _refuse_dates(doc: dict[str, Any], where: "_Locator") -> None:
    """TOML's dates and times (``1979-05-27T07:32:00Z``) have no JSON form, and every value of a
    sweep is written as JSON (cell ids, records): refused at their key, without recursion."""
    for section, table in doc.items():
        tables = table if isinstance(table, list) else [table]  # [[cases]] is a list of tables
        keyed = [(section, k, v) for t in tables if isinstance(t, dict) for k, v in t.items()]
        keyed += [(None, section, t) for t in tables if not isinstance(t, dict)]
        for place, key, value in keyed:
            stack = [value]
            while stack:
                item = stack.pop()
                if isinstance(item, (datetime.date, datetime.time)):
                    raise where.error(f"{key} holds {item.isoformat()}, a TOML date or time: a sweep's values "
                                      "are passed on as JSON, which has none", place, key,
                                      hint=f'write it as a string: "{item.isoformat()}"')
                if isinstance(item, dict):
                    stack.extend(item.values())
                elif isinstance(item, list):
                    stack.extend(item)


def _seeds(value: Any, where: "_Locator") -> list[int]:
    if isinstance(value, int) and not isinstance(value, bool):
        if value < 1:
            raise where.error(f"seeds = {value}: the grid has 0 cells", "sweep", "seeds",
                              hint="seeds = N runs seeds 0..N-1; give at least 1")
        if value > MAX_CELLS:  # before range(value) is listed
            raise where.error(f"seeds = {value:,} makes more than {MAX_CELLS:,} cells", "sweep", "seeds")
        return list(range(value))
    if isinstance(value, list) and all(isinstance(s, int) and not isinstance(s, bool) for s in value):
        if not value:
            raise where.error("seeds is an empty list: the grid has 0 cells", "sweep", "seeds")
        if len(set(value)) != len(value):
            raise where.error("seeds lists a seed twice", "sweep", "seeds")
        bad = [s for s in value if not 0 <= s <= MAX_SEED]
        if bad:
            raise where.error(f"seed {bad[0]} is out of range", "sweep", "seeds",
                              hint=f"seeds are whole numbers from 0 to {MAX_SEED:,}")
        return list(value)
    raise where.error(f"seeds must be a count or a list of whole numbers, not {value!r}", "sweep", "seeds")


def _check_cell_count(seeds: list[int], grid: dict[str, list[Any]], cases: list[Any], where: "_Locator") -> None:
    """Refuse a sweep of more than :data:`MAX_CELLS` cells from its sizes, before listing them."""
    count = len(seeds) * max(1, len(cases))
    for values in grid.values():
        count *= len(values)
        if count > MAX_CELLS:
            break
    if count > MAX_CELLS:
        raise where.error(f"the sweep has more than {MAX_CELLS:,} cells (seeds x cases x grid)", None, "grid",
                          hint="split it into several sweeps")


def _positive(value: Any, name: str, where: "_Locator") -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0 or value == float("inf"):
        raise where.error(f"{name} must be a positive number, not {value!r}", "sweep", name)
    return float(value)


def _table(doc: dict, section: str, where: "_Locator") -> dict[str, Any]:
    table = doc.get(section, {})
    if not isinstance(table, dict):
        raise where.error(f"[{section}] must be a table", None, section)
    for key in table:
        _check_name(key, section, where)
    return dict(table)


def _check_name(key: str, section: str, where: "_Locator") -> None:
    if not _NAME.match(key):
        raise where.error(f"parameter name {key!r} is not an identifier", section, key)
    if key == SEED:
        raise where.error("'seed' is set per cell from [sweep] seeds, not as a parameter", section, key)


# -- the target -----------------------------------------------------------------------------------

def resolve_function(reference: str, base: Path, where: "_Locator | None" = None):
    """The callable named by ``module:function`` or ``file.py:function`` (relative to ``base``)."""
    from symlearn.sweep.cell import load_function

    try:
        return load_function(reference, str(base))
    except (ImportError, AttributeError, OSError, SyntaxError) as exc:
        message = f"cannot load function {reference!r}: {type(exc).__name__}: {exc}"
        if where is None:
            raise DataError(message) from None
        raise where.error(message, "sweep", "function") from None


def check_parameters(function, names: list[str], where: "_Locator") -> None:
    """Every parameter of the sweep (and ``seed``) must be one ``function`` accepts, and every
    parameter it requires must be given."""
    try:
        signature = inspect.signature(function)
    except (TypeError, ValueError):
        return  # a builtin without a signature: it will say so itself
    accepted = signature.parameters
    open_keywords = any(p.kind is p.VAR_KEYWORD for p in accepted.values())
    keyword_ok = {n for n, p in accepted.items() if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)}
    qualified = getattr(function, "__qualname__", str(function))
    for name in [*names, SEED]:
        if name not in keyword_ok and not open_keywords:
            section, key = where.section_of(name)
            raise where.error(f"unknown parameter {name!r}: {qualified}() takes "
                              f"{', '.join(sorted(keyword_ok)) or 'no keyword parameters'}", section, key,
                              hint="every cell is seeded: the function needs a 'seed' parameter"
                              if name == SEED else "check the spelling, or add the parameter to the function")
    missing = [n for n, p in accepted.items() if p.default is p.empty
               and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and n not in names and n != SEED]
    if missing:
        raise where.error(f"{qualified}() needs parameter{'s' if len(missing) > 1 else ''} "
                          f"{', '.join(missing)}, which the sweep does not give", "sweep", "function",
                          hint="add them under [fixed] or [grid]")


def _check_command(command: list[str], names: list[str], where: "_Locator") -> None:
    used = {m for word in command for m in _PLACEHOLDER.findall(word)}
    for name in names:
        if name not in used:
            section, key = where.section_of(name)
            raise where.error(f"unknown parameter {name!r}: the command has no {{{name}}} placeholder", section, key)
    for name in sorted(used - set(names) - {SEED}):
        raise where.error(f"the command's placeholder {{{name}}} is no parameter of the sweep", "sweep", "command")


def _command_paths(spec: SweepSpec) -> Iterable[str]:
    """The distinct words of the spec's commands, with every cell's parameters put in (seeds are
    numbers and name no path): listed over the parameters the words use only, so a large grid of
    other parameters costs nothing."""
    used = {m for word in spec.command for m in _PLACEHOLDER.findall(word)} - {SEED}
    grid_keys = [k for k in spec.grid if k in used]
    seen = set()
    for case in spec.cases or [{}]:
        base = {k: v for k, v in {**spec.fixed, **case}.items() if k in used}
        for values in itertools.product(*(spec.grid[k] for k in grid_keys)):
            params = {**base, **dict(zip(grid_keys, values)), SEED: 0}
            text = {k: v if isinstance(v, str) else json.dumps(v) for k, v in params.items()}
            for word in spec.command:
                try:
                    filled = word.format_map(text)
                except (KeyError, ValueError, IndexError):  # a malformed placeholder: refused later, by name
                    filled = word
                if filled not in seen:
                    seen.add(filled)
                    yield filled


def _check_command_paths(spec: SweepSpec, where: "_Locator") -> None:
    """A command's words that climb out of the sweep file's folder must stay inside it or the
    current folder (symlearn/sweep/target_policy.py), checked before any cell runs."""
    for word in _command_paths(spec):
        named = path_word(word)
        refusal = named and outside_refusal(named, spec.path.parent)
        if refusal:
            raise where.error(f"refused: the command's word {word!r}: {refusal}", "sweep", "command",
                              hint="see 'Sweep files' in docs/FORMATS.md for what a sweep may run")


# -- locating keys in the file ----------------------------------------------------------------------

def _toml_position(message: str, text: str) -> tuple[int | None, int | None]:
    found = re.search(r"at line (\d+), column (\d+)", message)
    if found:
        return int(found.group(1)), int(found.group(2))
    if "end of document" in message:  # an unclosed value: point at the end
        lines = text.splitlines() or [""]
        return len(lines), len(lines[-1]) + 1
    return None, None


class _Locator:
    """Finds the line of ``key`` in ``[section]`` (tomllib keeps no positions) for located errors."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()

    def line_of(self, section: str | None, key: str | None) -> tuple[int | None, int | None]:
        current = None
        for number, line in enumerate(self.lines, 1):
            stripped = line.strip()
            header = re.match(r"^\[\[?\s*([A-Za-z0-9_.\-]+)\s*\]\]?", stripped)
            if header:
                current = header.group(1)
                if section is None and key is not None and current == key:
                    return number, 1
                continue
            if key is not None and current is not None and current.split(".")[0] == section:
                match = re.match(r"^(\s*)([A-Za-z0-9_\-]+|\"[^\"]*\")\s*=", line)
                if match and match.group(2).strip('"') == key:
                    return number, len(match.group(1)) + 1
            if key is None and current == section:
                return number - 1 if number > 1 else number, 1
        return None, None

    def section_of(self, name: str) -> tuple[str, str]:
        for section in ("grid", "fixed", "cases"):
            if self.line_of(section, name)[0] is not None:
                return section, name
        return "grid", name

    def error(self, message: str, section: str | None, key: str | None, *, hint: str | None = None) -> DataError:
        line, column = self.line_of(section, key) if (section or key) else (None, None)
        return DataError(message, file=self.path, line=line, column=column, hint=hint)
