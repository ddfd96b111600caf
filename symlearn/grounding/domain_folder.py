"""A domain folder a user can author: ``domain.toml`` and the files it names.

::

    DIR/domain.toml
      name = "warehouse"
      description = "..."          # optional
      background = "bk.lp"         # clingo; one state's facts + one action atom: exactly one answer set
      bias = "bias.las"            # #modeb / #modec / #constant / #maxv, no examples
      model = "model.npz"          # transitions [S,A,S], initial [S], terminal [S] bool;
                                   #   optional available [S,A] bool, rewards [S,A] float
      states = "states.jsonl"      # {"id": 0, "facts": "at(0,0). loaded."} per state id
      actions = "actions.jsonl"    # {"id": 0, "atom": "move(north)"} per action id
      truth = "truth.lp"           # optional ground-truth rules
      labeling = "labeling.json"   # optional labeling (for specification learning)
      features = "features.json"   # optional feature map (named numeric features of the states)

Paths are relative to ``DIR``. Every mistake is a one-line :class:`~symlearn.errors.DataError`
naming the file (and the key of ``domain.toml`` that pointed there).
"""

from __future__ import annotations

import json
import re
import tomllib
import zipfile
import zlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import write_bytes, write_text
from symlearn.errors import DataError, ModelError, ParseError, SymlearnError
from symlearn.input_limits import load_toml, read_input_text
from symlearn.json_position import JsonPathError, located

REQUIRED = ("name", "background", "bias", "model", "states", "actions")
OPTIONAL = ("description", "truth", "labeling", "features")
MODEL_ARRAYS = {"transitions": 3, "initial": 1, "terminal": 1, "available": 2, "rewards": 2}


def read_domain_folder(folder: Path, *, allow_outside: bool = False):
    """The :class:`~symlearn.grounding.domain.Domain` of ``folder``. Unless ``allow_outside``,
    everything it reads lies inside the folder: the paths of ``domain.toml`` (no absolute paths,
    no ``..``, no symlink leading out) and the files the background and bias ``#include``;
    ``#include`` in a state's facts or an action atom is refused either way (facts are facts)."""
    from symlearn.grounding.domain import Domain
    from symlearn.grounding.facts import FactGrounding

    toml_path = folder / "domain.toml"
    if not folder.is_dir():
        raise DataError(f"{folder} is not a folder", file=str(folder), hint="a domain is a folder with domain.toml")
    if not toml_path.is_file():
        raise DataError("the domain folder has no domain.toml", file=str(folder))
    if not allow_outside:  # domain.toml itself, like every file it names, is the folder's own
        try:
            outside = not toml_path.resolve().is_relative_to(folder.resolve())
        except (OSError, RuntimeError):
            outside = True
        if outside:
            raise DataError("domain.toml is a link to a file outside the domain folder", file=str(toml_path),
                            hint="a domain folder reads only itself (--allow-outside lifts this for a trusted folder)")
    toml_text = read_input_text(toml_path)
    try:
        config = load_toml(toml_text, source=toml_path)
    except RecursionError:
        raise ParseError("domain.toml is nested too deeply", file=str(toml_path)) from None
    except tomllib.TOMLDecodeError as exc:
        # Python 3.11's error has no line attributes; its message ends "(at line L, column C)"
        where = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        line, column = (int(where.group(1)), int(where.group(2))) if where else (None, None)
        raise ParseError(f"invalid TOML: {str(exc).split(' (at')[0]}", file=str(toml_path), line=line,
                         column=column) from None
    # an unknown key first: a misspelt one is why a required key is missing ('backgrund')
    unknown = sorted(set(config) - set(REQUIRED) - set(OPTIONAL))
    if unknown:
        import difflib

        close = difflib.get_close_matches(unknown[0], [k for k in REQUIRED + OPTIONAL if k not in config], n=1)
        line = next((i for i, text in enumerate(toml_text.splitlines(), start=1)
                     if re.match(rf"\s*[\"']?{re.escape(unknown[0])}[\"']?\s*=", text)
                     # a table "[extra]" (or "[[extra]]", "extra.x = 1") is an unknown key too
                     or re.match(rf"\s*\[\[?\s*[\"']?{re.escape(unknown[0])}[\"']?\s*[\].]", text)
                     or re.match(rf"\s*[\"']?{re.escape(unknown[0])}[\"']?\s*\.", text)), None)
        raise DataError(f"unknown key {unknown[0]!r}" + (f" (did you mean {close[0]!r}?)" if close else ""),
                        file=str(toml_path), line=line, hint="known keys: " + ", ".join(REQUIRED + OPTIONAL))
    for key in REQUIRED:
        if key not in config:
            raise DataError(f"missing key {key!r}", file=str(toml_path),
                            hint="required: " + ", ".join(REQUIRED) + "; optional: " + ", ".join(OPTIONAL))
    for key in config:
        if not isinstance(config[key], str):
            line = next((i for i, text in enumerate(toml_text.splitlines(), start=1)
                         if re.match(rf"\s*[\"']?{re.escape(key)}[\"']?\s*=", text)), None)
            several = key == "background" and isinstance(config[key], list)
            raise DataError(f"key {key!r} must be a string, got {type(config[key]).__name__}", file=str(toml_path),
                            line=line, hint='name one program; #include "more.lp". in it brings in the others'
                            if several else f'write it in quotes: {key} = "..."')

    inside = None if allow_outside else folder.resolve()

    def path(key: str) -> Path:
        p = folder / config[key]
        if inside is not None:
            _check_inside(config[key], p, inside, key, toml_path)
        try:
            found = p.is_file()
        except OSError as exc:  # a name the file system refuses (a component over 255 bytes, ...)
            raise DataError(f"key {key!r}: {_shown(config[key])} is not a usable file name ({exc.strerror})",
                            file=str(toml_path)) from None
        if not found:
            raise DataError(f"key {key!r}: file {_shown(config[key])} not found in {folder}", file=str(toml_path))
        return p

    sources = {k: str(path(k)) for k in (*REQUIRED[1:], *[k for k in ("truth", "labeling", "features") if k in config])}
    background = _read_program(path("background"), inside)
    bias = read_input_text(path("bias"))
    if inside is not None:  # the bias's #include directives are followed when the task is parsed
        from symlearn.logic.asp.program import Program, expand_includes

        expand_includes(Program.from_text(bias, source=str(path("bias"))), within=inside)
    model = _read_model(path("model"))
    grounding = FactGrounding.from_jsonl(path("states"), path("actions"))
    n_s, n_a = model["transitions"].shape[:2]
    if grounding.n_states != n_s:
        raise DataError(f"{config['states']} lists {grounding.n_states} states, {config['model']} has {n_s}",
                        file=sources["states"])
    if grounding.n_actions != n_a:
        raise DataError(f"{config['actions']} lists {grounding.n_actions} actions, {config['model']} has {n_a}",
                        file=sources["actions"])
    mdp = _model_mdp(model, sources["model"], grounding.action_atoms, grounding.state_names)
    truth = read_input_text(path("truth")) if "truth" in config else None
    feature_map = None
    if "features" in config:
        from symlearn.grounding.features import FeatureMap

        feature_map = FeatureMap.load(path("features"))
        table = feature_map._table
        if isinstance(table, dict) and grounding.state_names and any(isinstance(k, str) for k in table):
            # "table_by_state" keyed by the states' names (as demonstrations may name them): read as
            # their ids; before, every named row was ignored and state 0 "not in the feature table"
            ids = {name: i for i, name in enumerate(grounding.state_names)}
            feature_map = FeatureMap(feature_map.names, table={ids.get(k, k): v for k, v in table.items()})
    labeling = None
    if "labeling" in config:
        from symlearn.grounding.labeling import load_labeling

        labeling = labeling_of_states(load_labeling(path("labeling")), feature_map, sources["labeling"],
                                      grounding.n_states, grounding.state_names)
    domain = Domain(config["name"], background=background, bias=bias, grounding=grounding, mdp=mdp, truth=truth,
                    labeling=labeling, available=model.get("available"), description=config.get("description", ""),
                    sources=sources, feature_map=feature_map)
    if not domain.pair_ids:
        # nothing to learn or check: and every later message (a predicate "defined nowhere", a
        # demonstrated step "after the episode ended") would name a consequence, not the cause
        raise DataError("the model has no state-action pair: every state is terminal or has no available move",
                        file=sources.get("model"), hint="terminal[s] is True only where an episode ends")
    if truth is not None:  # a syntax error in the truth file should surface now, located
        domain.hypothesis(Path(sources["truth"]))
    if feature_map is not None:
        _check_every_state_has_features(feature_map, grounding.n_states, sources["features"])
    return domain


def _in_file(error):
    """``error`` (a :class:`JsonPathError`) at its line and column when its file can be read again:
    the labeling was read before its states could be checked against the domain's."""
    try:
        if error.file and Path(error.file).is_file():
            return located(error, read_input_text(error.file))
    except (OSError, SymlearnError):  # the check's own message stands without a position
        pass
    return error


def labeling_of_states(labeling: Any, feature_map: Any, source: str, n_states: int | None = None,
                       state_names: Sequence[str] | None = None) -> Any:
    """``labeling`` as it labels the folder's states, which are ids: a feature labeling (conditions
    over named features, ``height > 3``) reads each id's features from the folder's feature map
    (``features = ...``); any other labeling is returned as it is. A feature labeling in a folder
    without a feature map, or over a name the map lacks, is one error naming ``source``; so is a
    table labeling a state that is no id ``0..n_states-1``."""
    from symlearn.grounding.feature_labeling import FeatureLabeling
    from symlearn.grounding.features import FeatureMap
    from symlearn.grounding.labeling import Labeling

    items = list(getattr(labeling, "items", lambda: [])())
    if state_names and isinstance(labeling, Labeling) and any(isinstance(state, str) for state, _ in items):
        # a table that names the states as states.jsonl does (as demonstrations may): read by their ids
        ids = {name: i for i, name in enumerate(state_names)}
        labeling = Labeling({ids.get(state, state): props for state, props in items}, meanings=labeling.meanings,
                            propositions=labeling.propositions)
    if n_states is not None:
        for k, (state, _) in enumerate(getattr(labeling, "items", lambda: [])()):
            if not (isinstance(state, (int, np.integer)) and not isinstance(state, bool) and 0 <= state < n_states):
                raise _in_file(JsonPathError(f"the labeling labels state {state!r}, which is not one of the domain's "
                                             f"{n_states} states (ids 0..{n_states - 1})", path=("table", k),
                                             file=source, hint="a domain's states are the ids of its states.jsonl"))
    own = getattr(labeling, "feature_map", None)
    if not isinstance(labeling, FeatureLabeling) or own != FeatureMap(own.names):   # a table or function of its own
        return labeling
    if feature_map is None:
        raise DataError(f"the labeling's propositions are conditions over the features {', '.join(own.names)}, and "
                        "the domain's states are ids with no features", file=source,
                        hint='add a feature map of every state (features = "features.json" in domain.toml)')
    try:
        return FeatureLabeling(feature_map, {p: labeling.condition(p) for p in labeling.propositions},
                               meanings=labeling.meanings)
    except DataError as exc:
        raise DataError(f"{exc.message} (the domain's feature map)", file=source, hint=exc.hint) from None


def _check_every_state_has_features(feature_map, n_states: int, source: str) -> None:
    """The folder's feature map must give every state id its features (a table one row short
    would otherwise fail only when a learner reaches that state)."""
    for state in range(n_states):
        try:
            feature_map.features(state)
        except DataError as exc:
            raise DataError(f"state {state} of {n_states} has no features: {exc.message}", file=source,
                            hint="give one row per state id 0..S-1 (\"table\") or every state id in "
                                 "\"table_by_state\"") from None


def _shown(name: str, limit: int = 80) -> str:
    """A file name from domain.toml as a message quotes it: cut short (one line stays readable)."""
    return repr(name) if len(name) <= limit else repr(name[:limit]) + f"... ({len(name):,} characters)"


def _read_program(path: Path, inside: Path | None):
    from symlearn.logic.asp.program import Program

    return Program.from_file(path, within=inside)


def _check_inside(name: str, path: Path, inside: Path, key: str, toml_path: Path) -> None:
    """Refuse a path of ``domain.toml`` that leaves the domain folder: absolute, through ``..``,
    or (symlinks followed) resolving outside it. Checked before the file is opened."""
    hint = ("paths in domain.toml are relative to its folder and stay inside it (--allow-outside lifts "
            "this for a trusted folder)")
    if Path(name).is_absolute() or ".." in Path(name).parts:
        raise DataError(f"key {key!r}: {_shown(name)} leaves the domain folder", file=str(toml_path), hint=hint)
    try:
        resolved = path.resolve()
    except (OSError, RuntimeError):  # a symlink loop
        raise DataError(f"key {key!r}: {_shown(name)} cannot be resolved (a symlink loop?)", file=str(toml_path)) from None
    if not resolved.is_relative_to(inside):
        raise DataError(f"key {key!r}: {_shown(name)} is a link to a file outside the domain folder", file=str(toml_path),
                        hint=hint)


def _read_model(path: Path) -> dict[str, np.ndarray]:
    from symlearn.data.npz_format import open_checked

    headers, archive = open_checked(path)  # declared sizes checked before anything is decompressed
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("the model is a single array; it needs an archive of named arrays", file=str(path),
                        hint="write it with numpy.savez")
    if any(dtype.kind not in "biuf" for dtype, _ in headers.values()):
        archive.close()
        raise DataError("the model archive holds text arrays; it needs numbers and booleans only", file=str(path))
    try:
        with archive:
            arrays = {k: np.asarray(archive[k]) for k in archive.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error, RuntimeError) as exc:
        raise DataError(f"cannot read the model archive: {exc}", file=str(path),
                        hint="write it with numpy.savez (no object arrays)") from None
    for key in ("transitions", "initial", "terminal"):
        if key not in arrays:
            raise DataError(f"the model has no array {key!r}", file=str(path),
                            hint="needed: transitions [S,A,S], initial [S], terminal [S]")
    unknown = sorted(set(arrays) - set(MODEL_ARRAYS))
    if unknown:
        raise DataError(f"unknown array {unknown[0]!r} in the model", file=str(path),
                        hint="known: " + ", ".join(MODEL_ARRAYS))
    for key, ndim in MODEL_ARRAYS.items():
        if key in arrays and arrays[key].ndim != ndim:
            raise DataError(f"array {key!r} must have {ndim} dimension(s), got shape {arrays[key].shape}",
                            file=str(path))
    P = arrays["transitions"]
    n_s, n_a, n_next = P.shape
    if n_next != n_s:
        raise DataError(f"transitions must have shape [S, A, S], got {P.shape}", file=str(path))
    expected = {"initial": (n_s,), "terminal": (n_s,), "available": (n_s, n_a), "rewards": (n_s, n_a)}
    for key, shape in expected.items():
        if key in arrays and arrays[key].shape != shape:
            raise DataError(f"array {key!r} must have shape {list(shape)} to match transitions {list(P.shape)}, "
                            f"got {list(arrays[key].shape)}", file=str(path))
    for key in ("terminal", "available"):
        if key in arrays and arrays[key].dtype != bool:
            # 0/1 integers are how numpy users often write flags (np.zeros(S, dtype=int)); other values are a mistake
            values = arrays[key]
            if values.dtype.kind in "iu" and np.isin(values, (0, 1)).all():
                arrays[key] = values.astype(bool)
                continue
            raise DataError(f"array {key!r} must be boolean (or 0/1 integers), got {values.dtype}"
                            + (" with values other than 0 and 1" if values.dtype.kind in "iu" else ""),
                            file=str(path))
    if not np.isfinite(P).all() or (P < 0).any():
        raise DataError("transitions must be finite and non-negative", file=str(path))
    sums = P.sum(axis=2)
    # a move that does not exist (available false) and a terminal state have no next state to give: an
    # all-zero row there is how a user writes "nothing happens" (refused as "sums to 0" before); it is
    # read as staying put, the self-loop the bundled domains write
    idle = (sums == 0) & (~arrays["available"] if "available" in arrays else False)
    if "terminal" in arrays:
        idle |= (sums == 0) & arrays["terminal"][:, None]
    if idle.any():
        P = arrays["transitions"] = P.astype(np.float64 if P.dtype.kind != "f" else P.dtype, copy=True)
        s_idx, a_idx = np.nonzero(idle)
        P[s_idx, a_idx, s_idx] = 1
        sums = P.sum(axis=2)
    bad = np.argwhere(np.abs(sums - 1.0) > 1e-6)
    if bad.size:
        s, a = map(int, bad[0])
        hint = f"{len(bad)} row(s) in all; every P[s, a, :] is a distribution"
        if sums[s, a] == 0:
            hint += (" (an all-zero row is read as staying put only where the move does not exist, 'available' "
                     "false, or the state is 'terminal')")
        raise DataError(f"transition row (s, a) = ({s}, {a}) sums to {sums[s, a]:.6g}, not 1",
                        file=str(path), hint=hint)
    return arrays


def _model_mdp(model: dict[str, np.ndarray], source: str, action_atoms, state_names):
    from symlearn.mdp import TabularMDP

    n_s, n_a = model["transitions"].shape[:2]
    rewards = model.get("rewards", np.zeros((n_s, n_a)))
    try:
        return TabularMDP(model["transitions"].astype(np.float64), rewards.astype(np.float64),
                          model["initial"].astype(np.float64), model["terminal"],
                          tuple(state_names or (str(s) for s in range(n_s))), tuple(action_atoms))
    except (ModelError, DataError) as exc:
        raise DataError(exc.message, file=source, hint=exc.hint) from None


def write_domain_folder(domain, folder: Path) -> Path:
    """Write ``domain`` as a folder (a per-pair fact grounding cannot be written: refused)."""
    import io

    folder.mkdir(parents=True, exist_ok=True)
    mdp = domain.mdp
    buffer = io.BytesIO()
    arrays = {"transitions": mdp.transitions, "initial": mdp.initial, "terminal": np.asarray(mdp.terminal, bool),
              "available": ~domain.unavailable | mdp.terminal[:, None], "rewards": mdp.rewards}
    if np.asarray(mdp.rewards).ndim != 2:
        arrays.pop("rewards")
    np.savez(buffer, **arrays)
    domain.grounding.save_jsonl(folder / "states.jsonl", folder / "actions.jsonl")
    write_bytes(folder / "model.npz", buffer.getvalue())
    write_text(folder / "bk.lp", domain.background.text)
    write_text(folder / "bias.las", domain.bias_text)
    lines = [f"name = {json.dumps(domain.name)}", f"description = {json.dumps(domain.description)}",
             'background = "bk.lp"', 'bias = "bias.las"', 'model = "model.npz"', 'states = "states.jsonl"',
             'actions = "actions.jsonl"']
    if domain.truth is not None:
        write_text(folder / "truth.lp", domain.truth)
        lines.append('truth = "truth.lp"')
    if domain.labeling is not None:
        write_text(folder / "labeling.json", domain.labeling.to_json() + "\n")
        lines.append('labeling = "labeling.json"')
    if domain.feature_map is not None:
        domain.feature_map.save(folder / "features.json")
        lines.append('features = "features.json"')
    write_text(folder / "domain.toml", "\n".join(lines) + "\n")
    return folder
