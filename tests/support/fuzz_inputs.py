"""A seeded mutation fuzzer for symlearn's readers of user files (issue 15).

Valid inputs of every format (built from bundled data: an expert's demonstrations, a translated
DFA, the MONA/LTLf2DFA DOT test files, a reward machine, a labeling, an LTL sample, formulas,
traces; since issue 26 also DNF rule files (text and JSON), a PDFA, image and frame archives, a
TLSF specification, a sweep file with its results store, a learned-cost model and a domain
folder) are mutated: truncated, bytes flipped or inserted, a JSON key duplicated, brackets nested
deeply, numbers made huge, lines duplicated or swapped, NPZ members given huge shapes, odd dtypes
or dropped. Each mutant goes to its reader; the promise is that the reader returns a value or
raises a :class:`~symlearn.errors.SymlearnError`, nothing else (no ``RecursionError``,
``MemoryError``, ``IndexError``, ...).

* :func:`seeds(folder)` writes the valid inputs and returns ``[(format, path)]``;
* :func:`mutants(data, fmt, rng)` yields ``(mutation name, bytes)``;
* :data:`READERS` maps a format to its in-process reader and :data:`COMMANDS` to the CLI
  command reading it (``{path}`` is replaced);
* :func:`fuzz_readers(n, seed, folder)` runs ``n`` mutants in-process and returns a report
  (counts per format and outcome, and every crash with the mutant's file kept in
  ``folder/crashes``); the hostile tests run it in a child process under memory and time
  limits, ``benchmarks/fuzz_inputs.py`` runs it long and also through the CLI.
"""

from __future__ import annotations

import io
import json
import random
import re
import time
import zipfile
from collections import Counter, defaultdict
from collections.abc import Callable, Iterator
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOT_FILES = sorted((REPO / "tests" / "logic" / "automata" / "data").glob("*.dot"))

# -- valid inputs -------------------------------------------------------------------------------


def seeds(folder: str | Path) -> list[tuple[str, Path]]:
    """Write one or more valid inputs per format into ``folder``; ``[(format, path)]``."""
    from symlearn.data import Demonstrations, Trajectory
    from symlearn.data.ltl_samples import sample_from_traces, save_sample
    from symlearn.logic.automata import RewardMachine
    from symlearn.logic.ltlf import parse, to_dfa

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out: list[tuple[str, Path]] = []

    symbolic = Demonstrations([
        Trajectory(states=[0, 1, 2], actions=["go(east)", "go(east)"], rewards=[0.0, 2.0], labels=[[], ["key"], ["door"]],
                   info={"seed": 3}),
        Trajectory(states=[2, 1], actions=["go(west)"], rewards=[1.5], labels=[["door"], ["key"]]),
    ], metadata={"env": "toy", "note": "fuzz seed"})
    vector = Demonstrations([
        Trajectory(states=[[0.5, 1.0], [1.5, -2.0], [0.0, 0.25]], actions=[0, 1], rewards=[0.0, 1.0]),
        Trajectory(states=[[1.0, 1.0], [2.0, 2.0]], actions=[1], rewards=[0.5]),
    ])
    features = Demonstrations([Trajectory(states=[{"x": 1.0, "ok": True}, {"x": 2.5, "ok": False}], actions=[0])])
    for name, demos in (("symbolic", symbolic), ("vector", vector), ("features", features)):
        for suffix, fmt in ((".jsonl", "demos-jsonl"), (".npz", "demos-npz")):
            path = folder / f"{name}{suffix}"
            demos.save(path)
            out.append((fmt, path))

    dfa = to_dfa(parse("(coffee T office) & G !plant"))
    (folder / "dfa.json").write_text(dfa.to_json())
    out.append(("automaton-json", folder / "dfa.json"))
    rm = RewardMachine.from_dfa(dfa, shaping=True, gamma=0.9)
    (folder / "rm.json").write_text(rm.to_json())
    out.append(("automaton-json", folder / "rm.json"))
    (folder / "rm.txt").write_text(rm.to_text())
    out.append(("rm-text", folder / "rm.txt"))
    for dot in DOT_FILES[:4]:
        target = folder / dot.name
        target.write_bytes(dot.read_bytes())
        out.append(("mona-dot", target))

    (folder / "formulas.ltl").write_text("# specs\nF a & G !b\n(coffee T office) & G !plant\n"
                                         "a U (b R c)\nG(a -> X b)\n!(F p0 & F p1) | WX q\n")
    out.append(("formulas", folder / "formulas.ltl"))
    (folder / "traces.jsonl").write_text('[["a"], [], ["a", "b"]]\n[["b"], ["c"]]\n[[]]\n')
    out.append(("traces", folder / "traces.jsonl"))
    (folder / "trace.json").write_text('[["coffee"], ["office"], []]')
    out.append(("trace", folder / "trace.json"))

    from symlearn.grounding.labeling import Labeling

    labeling = Labeling({0: {"a"}, 1: {"a", "b"}, (2, 3): {"c"}}, meanings={"a": "at A", "b": "has B", "c": ""})
    (folder / "labeling.json").write_text(labeling.to_json())
    out.append(("labeling", folder / "labeling.json"))

    sample = sample_from_traces([[{"a"}, {"b"}], [{"a", "b"}]], [[set(), {"b"}], [{"b"}]], propositions=["a", "b"])
    save_sample(sample, folder / "sample.json")
    out.append(("ltl-sample", folder / "sample.json"))
    out += _newer_seeds(folder, dfa)
    return out


def _newer_seeds(folder: Path, dfa) -> list[tuple[str, Path]]:
    """The readers added since issue 15 (issue 26): DNF rule files, PDFA JSON, image and frame
    archives, TLSF, sweep files and result stores, learned-cost models, domain folders. Formats
    in :data:`IN_FOLDER` are one file of a folder: the mutant replaces it in a copy of the folder."""
    import numpy as np

    from symlearn.data import Demonstrations, Trajectory
    from symlearn.data.frame_archive import save_frames
    from symlearn.logic import dnf
    from symlearn.logic.automata.pdfa import PDFA

    out: list[tuple[str, Path]] = []
    rules = dnf.parse("x > 0.5 & y <= 2\n\"a b\" >= 1\nz < -3.25 & x >= 1e3\n", source="seed")
    rules.save(folder / "rules.dnf", header="fuzz seed")
    rules.save(folder / "rules.json")
    out += [("dnf-text", folder / "rules.dnf"), ("dnf-json", folder / "rules.json")]
    (folder / "pdfa.json").write_text(PDFA.from_dfa(dfa, termination=0.25).to_json())
    out.append(("automaton-json", folder / "pdfa.json"))
    images = Demonstrations([Trajectory(states=np.arange(3 * 4 * 5, dtype=np.float32).reshape(3, 4, 5) / 60,
                                        actions=[0, 1])])
    images.save(folder / "images.npz")
    out.append(("demos-npz", folder / "images.npz"))
    save_frames(folder / "frames.npz", [np.array([[0.0, np.nan], [1.0, 2.0]]), np.zeros((3, 2))], ["x", "y"])
    out.append(("frames-npz", folder / "frames.npz"))
    (folder / "spec.tlsf").write_text(TLSF_SEED)
    out.append(("tlsf", folder / "spec.tlsf"))

    sweep = folder / "sweep"
    sweep.mkdir(exist_ok=True)
    (sweep / "cells.py").write_text("def cell(seed, n=1, rate=0.5):\n    return {'value': seed * n * rate}\n")
    (sweep / "s.toml").write_text('[sweep]\nfunction = "cells.py:cell"\nseeds = 2\nmetrics = ["value"]\n'
                                  '[grid]\nn = [1, 2]\n[fixed]\nrate = 0.25\n')
    out.append(("sweep-toml", sweep / "s.toml"))
    from symlearn.sweep.runner import run_sweep
    from symlearn.sweep.spec import read_spec

    run_sweep(read_spec(sweep / "s.toml"), sweep / "out", backend="local", workers=1, progress=False)
    out += [("sweep-meta", sweep / "out" / "sweep.json"), ("sweep-results", sweep / "out" / "results.jsonl")]

    cost = folder / "cost"
    cost.mkdir(exist_ok=True)
    _save_cost(cost / "cost.safetensors")
    out += [("cost-config", cost / "cost.json"), ("cost-weights", cost / "cost.safetensors")]

    import warehouse_domain  # tests/support

    domain = warehouse_domain.write_warehouse(folder / "domain")
    out += [("domain", domain / name) for name in ("domain.toml", "bk.lp", "bias.las", "states.jsonl",
                                                     "actions.jsonl", "truth.lp")]
    return out


TLSF_SEED = """INFO {
  TITLE:       "fuzz seed"
  DESCRIPTION: "a request is granted"
  SEMANTICS:   Finite,Mealy
  TARGET:      Mealy
}

MAIN {
  INPUTS { req; }
  OUTPUTS { grant; }
  ASSUMPTIONS { G F req; }
  GUARANTEES {
    G (req -> X[!] grant);
    !grant W req;
  }
}
"""

#: formats whose file is read with its folder (the mutant replaces the file in a copy)
IN_FOLDER = {"sweep-toml", "sweep-meta", "sweep-results", "cost-config", "cost-weights", "domain"}


def _save_cost(path: Path) -> None:
    import gymnasium as gym
    import torch

    import symlearn.envs  # noqa: F401  (registers the gymnasium ids)
    from symlearn.envs.registry import get
    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    cost = NeuralCost.for_env(gym.make(get("blocked-point").gym_id),
                              FeatureNetwork([0], 0, 1, (8,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([1.0])
    cost.save(path)


def place(work: Path, fmt: str, seed: Path, data: bytes) -> Path:
    """Write a mutant where its reader finds it: ``work/mutant.SUFFIX``, or, for a format of
    :data:`IN_FOLDER`, in place of ``seed`` inside a fresh copy of the seed's folder."""
    import shutil

    if fmt not in IN_FOLDER:
        target = work / f"mutant{seed.suffix}"
        target.write_bytes(data)
        return target
    top = seed.parent.parent if fmt in ("sweep-meta", "sweep-results") else seed.parent
    copy = work / f"mutant-{fmt}"
    if copy.exists():
        shutil.rmtree(copy)
    shutil.copytree(top, copy, symlinks=True)
    target = copy / seed.relative_to(top)
    target.write_bytes(data)
    return target


# -- readers --------------------------------------------------------------------------------------


def _read_demos(path: Path):
    from symlearn.data import load

    return load(path)


def _read_automaton(path: Path):
    from symlearn.logic.automata import load_automaton

    automaton = load_automaton(path)
    return automaton.to_json()  # printing is part of reading (guards)


def _read_dot(path: Path):
    from symlearn.logic.automata import read_mona_dot

    return read_mona_dot(path).to_json()


def _read_rm(path: Path):
    from symlearn.logic.automata import read_rm_text

    return read_rm_text(path).to_text()


def _read_formulas(path: Path):
    """What ``ltl dfa --file`` does: read the file, parse every formula line, print it."""
    import symlearn
    from symlearn.logic.ltlf import parse, to_string

    if (Path(symlearn.__file__).parent / "input_limits.py").is_file():
        from symlearn.input_limits import read_input_text

        text = read_input_text(path)
    else:  # an older tree (benchmarks/fuzz_inputs.py --source): read as it did
        text = Path(path).read_text(encoding="utf-8")
    done = []
    for number, line in enumerate(text.split("\n"), start=1):
        if line.strip() and not line.lstrip().startswith("#"):
            done.append(to_string(parse(line, source=str(path), line=number)))
    return done


def _read_traces(path: Path):
    from symlearn.logic.ltlf.traces_file import read_traces

    return read_traces(path)


def _read_trace(path: Path):
    from symlearn.cli.automaton_command import read_trace

    return read_trace(str(path))


def _read_labeling(path: Path):
    from symlearn.grounding.labeling import load_labeling

    return load_labeling(path)


def _read_sample(path: Path):
    from symlearn.data.ltl_samples import load_sample

    return load_sample(path)


def _read_dnf(path: Path):
    from symlearn.logic import dnf

    return str(dnf.load(path))


def _read_frames(path: Path):
    from symlearn.data.frame_archive import load_frames

    return load_frames(path)


def _read_tlsf(path: Path):
    """What ``ltl parse|dfa --tlsf`` read: the specification and its formula, printed."""
    from symlearn.logic.ltlf import to_string
    from symlearn.logic.ltlf.tlsf import load_tlsf

    return to_string(load_tlsf(path).formula)


def _read_sweep(path: Path):
    """What ``sweep run`` reads before any cell runs: the file, its target and its cells."""
    from symlearn.sweep.spec import read_spec

    return [cell.label for cell in read_spec(path).cells()]


def _read_store(path: Path):
    """What ``sweep report`` reads: the record and the results of the store ``path`` is in."""
    from symlearn.sweep.report import load_results

    return load_results(path.parent)


def _read_cost(path: Path):
    from symlearn.learners.neural import NeuralCost

    return NeuralCost.load(path.with_suffix(".safetensors"))


def _read_domain(path: Path):
    """What ``domain check DIR`` does, in its bounded worker (grounding a mutated program in
    this process could run until the machine's memory is gone: that is why the CLI uses one)."""
    from symlearn.cli.domain_command import _check_document
    from symlearn.worker import run_limited

    return run_limited(_check_document, str(path.parent), None, None, False, seconds=30, memory_mb=768,
                       what="reading a mutated domain folder")


READERS: dict[str, Callable[[Path], object]] = {
    "demos-jsonl": _read_demos, "demos-npz": _read_demos, "automaton-json": _read_automaton,
    "mona-dot": _read_dot, "rm-text": _read_rm, "formulas": _read_formulas, "traces": _read_traces,
    "trace": _read_trace, "labeling": _read_labeling, "ltl-sample": _read_sample,
    "dnf-text": _read_dnf, "dnf-json": _read_dnf, "frames-npz": _read_frames, "tlsf": _read_tlsf,
    "sweep-toml": _read_sweep, "sweep-meta": _read_store, "sweep-results": _read_store,
    "cost-config": _read_cost, "cost-weights": _read_cost, "domain": _read_domain,
}

#: the CLI command that reads each format (``{path}`` replaced by the mutant's file)
COMMANDS: dict[str, list[str]] = {
    "demos-jsonl": ["data", "validate", "{path}"],
    "demos-npz": ["data", "validate", "{path}"],
    "automaton-json": ["automaton", "show", "{path}"],
    "mona-dot": ["automaton", "show", "{path}"],
    "rm-text": ["automaton", "show", "{path}"],
    "formulas": ["ltl", "dfa", "--file", "{path}"],
    "traces": ["ltl", "eval", "F a", "--traces", "{path}"],
    "trace": ["automaton", "explain", "{dfa}", "--trace", "{path}"],
    "dnf-text": ["dnf", "show", "{path}"],
    "dnf-json": ["dnf", "show", "{path}", "--json"],
    "frames-npz": ["learn", "pdfa", "--demos", "{path}", "-o", "pdfa.json"],
    "tlsf": ["ltl", "dfa", "--tlsf", "{path}"],
    "sweep-toml": ["sweep", "run", "{path}", "--out", "{folder}/fresh", "--local", "--workers", "1"],
    "sweep-meta": ["sweep", "report", "{folder}"],
    "sweep-results": ["sweep", "report", "{folder}"],
    "cost-config": ["train", "--env", "blocked-point", "--cost", "{folder}/cost.safetensors", "--steps", "64"],
    "cost-weights": ["train", "--env", "blocked-point", "--cost", "{folder}/cost.safetensors", "--steps", "64"],
    "domain": ["domain", "check", "{folder}", "--timeout", "30"],
}

#: CLI runs per format at most (a training command takes seconds just to start)
CLI_CAP: dict[str, int] = {"cost-config": 5, "cost-weights": 5}

# -- mutations ------------------------------------------------------------------------------------

_NUMBER = re.compile(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?")
_KEY = re.compile(rb'"[A-Za-z_][A-Za-z0-9_]*"\s*:')
_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"')
_HUGE = [b"1e309", b"-1e309", b"99999999999999999999999999", b"-1", b"0", b"2147483648", b"9223372036854775808",
         b"1000000000", b"1e-400", b"NaN", b"Infinity", b"true", b"null", b'"x"', b"[]", b"{}", b"0.5"]
_BYTES = [b"\x00", b"\xff", b"\xfe", b"\xc3", b"\x80", b"\n", b"\r", b'"', b"\\", b"{", b"[", b"]", b"}", b",",
          b":", b"(", b")", b"|", b"&", b"!", b"->", b"~", b"\xe2\x80\x8b"]


def _truncate(data: bytes, rng: random.Random) -> bytes:
    return data[:rng.randrange(len(data) + 1)]


def _flip(data: bytes, rng: random.Random) -> bytes:
    if not data:
        return bytes([rng.randrange(256)])
    out = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def _insert(data: bytes, rng: random.Random) -> bytes:
    at = rng.randrange(len(data) + 1)
    return data[:at] + rng.choice(_BYTES) * rng.randint(1, 3) + data[at:]


def _delete(data: bytes, rng: random.Random) -> bytes:
    if not data:
        return data
    at = rng.randrange(len(data))
    return data[:at] + data[at + rng.randint(1, 16):]


def _duplicate_key(data: bytes, rng: random.Random) -> bytes:
    keys = list(_KEY.finditer(data))
    if not keys:
        return _insert(data, rng)
    match = rng.choice(keys)
    value_end = data.find(b",", match.end())
    value_end = len(data) if value_end < 0 else value_end
    copy = data[match.start():value_end]
    return data[:match.start()] + copy + b", " + data[match.start():]


def _deep(data: bytes, rng: random.Random) -> bytes:
    depth = rng.choice([250, 1000, 5000, 100_000])
    at = rng.randrange(len(data) + 1)
    opener, closer = rng.choice([(b"[", b"]"), (b"{\"a\":", b"}"), (b"(", b")"), (b"!", b""), (b"X ", b"")])
    closing = closer * depth if rng.random() < 0.5 else b""
    return data[:at] + opener * depth + b"0" + closing + data[at:]


def _huge_number(data: bytes, rng: random.Random) -> bytes:
    numbers = list(_NUMBER.finditer(data))
    if not numbers:
        return _insert(data, rng)
    match = rng.choice(numbers)
    return data[:match.start()] + rng.choice(_HUGE) + data[match.end():]


def _long_string(data: bytes, rng: random.Random) -> bytes:
    strings = list(_STRING.finditer(data))
    if not strings:
        return _insert(data, rng)
    match = rng.choice(strings)
    return data[:match.start()] + b'"' + b"a" * rng.choice([1000, 100_000]) + b'"' + data[match.end():]


def _lines(data: bytes, rng: random.Random) -> bytes:
    lines = data.split(b"\n")
    if len(lines) < 2:
        return data + b"\n" + data
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    if rng.random() < 0.5:
        lines.insert(j, lines[i])
    else:
        lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def _empty(data: bytes, rng: random.Random) -> bytes:
    return rng.choice([b"", b"\n", b"   \n\n", b"{}", b"[]", b"null", b"\xef\xbb\xbf"])


TEXT_MUTATIONS: dict[str, Callable[[bytes, random.Random], bytes]] = {
    "truncate": _truncate, "flip": _flip, "insert": _insert, "delete": _delete, "duplicate-key": _duplicate_key,
    "deep-nesting": _deep, "huge-number": _huge_number, "long-string": _long_string, "lines": _lines,
    "empty": _empty,
}


def _npz_members(data: bytes) -> dict[str, bytes]:
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        return {info.filename: archive.read(info) for info in archive.infolist()}


def _npz_pack(members: dict[str, bytes]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, payload in members.items():
            archive.writestr(name, payload)
    return buffer.getvalue()


def _npy_header(payload: bytes, rng: random.Random) -> bytes:
    """Rewrite a member's .npy header: a huge shape, an odd dtype, or more columns."""
    import numpy as np

    handle = io.BytesIO(payload)
    version = np.lib.format.read_magic(handle)
    shape, fortran, dtype = (np.lib.format.read_array_header_1_0(handle) if version == (1, 0)
                             else np.lib.format.read_array_header_2_0(handle))
    body = payload[handle.tell():]
    choice = rng.randrange(5)
    if choice == 0:
        shape = (rng.choice([10**9, 2**40, 400_000_000]),) + tuple(shape[1:])
    elif choice == 1:
        dtype = rng.choice(["<U1000000000", "|O", "|V2000000000", "(1000,1000,100)<f8", "<c16", "|S5", "<m8"])
    elif choice == 2:
        shape = tuple(shape) + (rng.choice([2, 7]),)
    elif choice == 3:
        shape = () if shape else (1,)
    else:
        shape = tuple(max(0, s - 1) for s in shape)
    header = io.BytesIO()
    try:
        np.lib.format.write_array_header_1_0(header, {"descr": dtype if isinstance(dtype, str) else
                                                     np.lib.format.dtype_to_descr(dtype),
                                                     "fortran_order": fortran, "shape": tuple(shape)})
    except (ValueError, TypeError):
        return payload
    return header.getvalue() + body


def npz_mutants(data: bytes, rng: random.Random) -> tuple[str, bytes]:
    """One structure-aware NPZ mutation: a member's header rewritten, a member dropped or
    swapped, ``__meta__`` or ``info`` text mutated, or raw bytes flipped."""
    import numpy as np

    members = _npz_members(data)
    names = sorted(members)
    choice = rng.randrange(6)
    if choice == 0:
        name = rng.choice(names)
        members[name] = _npy_header(members[name], rng)
        return f"npy-header:{name[:-4]}", _npz_pack(members)
    if choice == 1:
        name = rng.choice(names)
        del members[name]
        return f"drop:{name[:-4]}", _npz_pack(members)
    if choice == 2 and len(names) > 1:
        a, b = rng.sample(names, 2)
        members[a], members[b] = members[b], members[a]
        return "swap-members", _npz_pack(members)
    if choice == 3:
        for name in ("__meta__.npy", "info.npy"):
            if name in members and rng.random() < 0.7:
                array = np.load(io.BytesIO(members[name]), allow_pickle=False)
                texts = [str(x) for x in np.atleast_1d(array)]
                k = rng.randrange(len(texts))
                mutation = rng.choice(list(TEXT_MUTATIONS))
                texts[k] = TEXT_MUTATIONS[mutation](texts[k].encode(), rng).decode("utf-8", "replace")
                out = io.BytesIO()
                np.save(out, np.asarray(texts[0] if array.ndim == 0 else texts), allow_pickle=False)
                members[name] = out.getvalue()
                return f"text:{name[:-4]}:{mutation}", _npz_pack(members)
    if choice == 4:
        return "truncate", _truncate(data, rng)
    return "flip", _flip(data, rng)


def mutants(data: bytes, fmt: str, rng: random.Random) -> Iterator[tuple[str, bytes]]:
    """Endless ``(mutation, bytes)`` for an input of format ``fmt``."""
    while True:
        if fmt.endswith("-npz") and rng.random() < 0.85:
            yield npz_mutants(data, rng)
            continue
        name = rng.choice(list(TEXT_MUTATIONS))
        mutated = TEXT_MUTATIONS[name](data, rng)
        if rng.random() < 0.3:  # stack a second mutation now and then
            second = rng.choice(list(TEXT_MUTATIONS))
            mutated, name = TEXT_MUTATIONS[second](mutated, rng), f"{name}+{second}"
        yield name, mutated


# -- the in-process run -----------------------------------------------------------------------------


def fuzz_readers(n: int, seed: int, folder: str | Path, *, formats: list[str] | None = None,
                 deadline: float | None = None) -> dict:
    """``n`` mutants spread over every format (round robin; a seed file of the format at random),
    each read in-process; ``formats``: only these.

    Returns ``{"inputs", "seconds", "per_format": {fmt: {"accepted", "refused", "crashed"}},
    "crashes": [{"format", "mutation", "file", "error"}]}``; a crash's input is kept in
    ``folder/crashes``. ``deadline``: stop early at this ``time.monotonic()``.
    """
    from symlearn.errors import SymlearnError

    folder = Path(folder)
    rng = random.Random(seed)
    inputs = [(fmt, path) for fmt, path in seeds(folder / "seeds") if formats is None or fmt in formats]
    by_format: dict[str, list] = defaultdict(list)
    for fmt, path in inputs:
        by_format[fmt].append((fmt, path, mutants(path.read_bytes(), fmt, rng)))
    # round robin over the formats (not the seed files), so each reader gets its share
    order = sorted(by_format)
    work = folder / "work"
    work.mkdir(parents=True, exist_ok=True)
    crash_dir = folder / "crashes"
    per_format: dict[str, Counter] = defaultdict(Counter)
    crashes, mutations = [], Counter()
    start = time.perf_counter()
    done = 0
    for i in range(n):
        if deadline is not None and time.monotonic() > deadline:
            break
        fmt, path, stream = rng.choice(by_format[order[i % len(order)]])
        mutation, data = next(stream)
        target = place(work, fmt, path, data)
        mutations[mutation.split(":")[0].split("+")[0]] += 1
        try:
            READERS[fmt](target)
            per_format[fmt]["accepted"] += 1
        except SymlearnError:
            per_format[fmt]["refused"] += 1
        except Exception as exc:  # noqa: BLE001 - exactly what the fuzzer looks for
            per_format[fmt]["crashed"] += 1
            crash_dir.mkdir(parents=True, exist_ok=True)
            kept = crash_dir / f"crash{len(crashes)}-{fmt}{path.suffix}"
            kept.write_bytes(data)
            crashes.append({"format": fmt, "seed": path.name, "mutation": mutation, "file": str(kept),
                            "error": f"{type(exc).__name__}: {str(exc)[:300]}"})
        done += 1
    return {"inputs": done, "seed": seed, "seconds": round(time.perf_counter() - start, 3),
            "per_format": {k: dict(v) for k, v in sorted(per_format.items())},
            "mutations": dict(sorted(mutations.items())), "crashes": crashes}


if __name__ == "__main__":  # python tests/support/fuzz_inputs.py N SEED FOLDER -> JSON report
    import sys

    report = fuzz_readers(int(sys.argv[1]), int(sys.argv[2]), sys.argv[3])
    print(json.dumps(report, indent=1))
