"""Model files: a torch module's weights in ``safetensors`` and its configuration in JSON beside it.

``save_torch_module("runs/agent.safetensors", module, config)`` writes two files:

* ``runs/agent.safetensors``: every entry of ``module.state_dict()`` (parameters and buffers) as
  a plain tensor. The safetensors format is a JSON header plus raw little-endian numbers, so
  reading it never runs code (unlike ``torch.save`` pickles, which symlearn never writes).
* ``runs/agent.json``: ``{"format": "symlearn-torch-module", "version": 1, "kind": ...,
  "config": {...}}``, the JSON-able settings a builder needs to make an empty module of the
  right shape again.

``load_torch_module(path, build, kind=)`` reads the JSON, calls ``build(config)`` for an empty
module and copies the tensors in. A file whose tensor names or shapes differ from the module's
(a missing entry, an extra one, a shape that does not match) is refused with a
:class:`~symlearn.errors.ModelError` naming the entry; nothing is partly loaded.

Both files are written atomically (:mod:`symlearn.atomic`).
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import torch
from safetensors import SafetensorError
from safetensors.torch import load as load_tensors
from safetensors.torch import save as save_tensors

from symlearn.atomic import write_bytes, write_text
from symlearn.errors import ModelError
from symlearn.input_limits import load_json, read_input_bytes, read_input_text

FORMAT = "symlearn-torch-module"
VERSION = 1

M = TypeVar("M", bound=torch.nn.Module)


def model_paths(path: str | os.PathLike[str]) -> tuple[Path, Path]:
    """``(weights, config)`` paths for ``path``: ``x.safetensors`` and ``x.json`` (a path
    without a suffix gets ``.safetensors``)."""
    weights = Path(path)
    if weights.suffix != ".safetensors":
        weights = weights.with_name(weights.name + ".safetensors")
    return weights, weights.with_suffix(".json")


def save_torch_module(
    path: str | os.PathLike[str], module: torch.nn.Module, config: dict[str, Any], *, kind: str
) -> Path:
    """Write ``module``'s state dict as safetensors and ``config`` as JSON; returns the weights path."""
    weights, config_path = model_paths(path)
    try:
        config_text = json.dumps({"format": FORMAT, "version": VERSION, "kind": kind, "config": config},
                                 indent=1, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"the model configuration is not plain JSON: {exc}") from None
    # contiguous CPU copies: safetensors stores raw buffers and refuses views that share memory
    tensors = {name: tensor.detach().to("cpu").contiguous().clone() for name, tensor in module.state_dict().items()}
    write_bytes(weights, save_tensors(tensors, metadata={"format": FORMAT, "kind": kind}))
    write_text(config_path, config_text + "\n")
    return weights


def read_model_config(path: str | os.PathLike[str], *, kind: str | None = None) -> dict[str, Any]:
    """The ``config`` of the JSON file beside ``path``, checked for format, version and ``kind``."""
    return _read_document(path, kind)["config"]


def read_model_kind(path: str | os.PathLike[str]) -> str:
    """The ``kind`` the JSON file beside ``path`` declares (format and version checked), for a
    reader that takes several kinds of model."""
    kind = _read_document(path, None).get("kind")
    if not isinstance(kind, str):
        raise ModelError("the model configuration names no 'kind'", file=model_paths(path)[1])
    return kind


def _read_document(path: str | os.PathLike[str], kind: str | None) -> dict[str, Any]:
    weights, config_path = model_paths(path)
    try:  # a user may bring this file: size-capped, nesting and duplicate keys refused
        text = read_input_text(config_path, what="model configuration")
    except FileNotFoundError:
        if not weights.exists():   # not "no configuration beside the weights" when there are none
            raise ModelError(f"no such model: neither {weights.name} nor {config_path.name} exists", file=path,
                             hint="a model is two files, NAME.safetensors and NAME.json, as `-o` wrote them") from None
        raise ModelError("no model configuration beside the weights", file=config_path,
                         hint="a model is two files, NAME.safetensors and NAME.json") from None
    document = load_json(text, source=config_path, error=ModelError, syntax="not JSON")
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise ModelError(f"not a {FORMAT} file", file=config_path)
    if document.get("version") != VERSION:
        raise ModelError(f"unsupported version {document.get('version')!r} (this symlearn reads {VERSION})",
                         file=config_path)
    if kind is not None and document.get("kind") != kind:
        raise ModelError(f"the file holds a {document.get('kind')!r} model, not a {kind!r} one", file=config_path)
    if not isinstance(document.get("config"), dict):
        raise ModelError("'config' must be a JSON object", file=config_path)
    return document


def load_torch_module(
    path: str | os.PathLike[str], build: Callable[[dict[str, Any]], M], *, kind: str | None = None,
    meta_check: bool = True,
) -> tuple[M, dict[str, Any]]:
    """``(module, config)``: ``build(config)`` filled with the saved tensors, names and shapes checked.

    ``meta_check=False`` skips building on the meta device first, for builders that move their
    module to a device themselves (stable-baselines3's constructors); such a caller must bound
    the configuration's sizes before calling."""
    weights, _ = model_paths(path)
    config = read_model_config(weights, kind=kind)
    try:  # capped like an array archive: /dev/zero or a huge file stops at the limit
        tensors = load_tensors(read_input_bytes(weights, variable="SYMLEARN_MAX_ARRAY_MB", what="weights file"))
    except FileNotFoundError:
        raise ModelError("no weights file", file=weights) from None
    except (SafetensorError, ValueError, OSError) as exc:
        raise ModelError(f"not a readable safetensors file: {exc}", file=weights) from None
    # The configuration's layer sizes come from a file: build it first on the meta device
    # (shapes only, no memory), so a configuration asking for 10^12 weights is refused by the
    # comparison with the (size-capped) file's tensors below instead of being allocated.
    module = None if meta_check else _build(build, config, weights)
    expected = (_build(build, config, weights, device="meta") if module is None else module).state_dict()
    missing = sorted(set(expected) - set(tensors))
    unknown = sorted(set(tensors) - set(expected))
    if missing or unknown:
        parts = ([f"missing {', '.join(missing)}"] if missing else []) + \
                ([f"unknown {', '.join(unknown)}"] if unknown else [])
        raise ModelError(f"the weights do not fit the configured model: {'; '.join(parts)}", file=weights,
                         hint="the .json and .safetensors files must come from the same save")
    wrong = [f"{name} {tuple(tensors[name].shape)} {tensors[name].dtype} in the file, "
             f"{tuple(want.shape)} {want.dtype} in the model"
             for name, want in expected.items()
             if tuple(tensors[name].shape) != tuple(want.shape) or tensors[name].dtype != want.dtype]
    if wrong:
        raise ModelError(f"the weights do not fit the configured model: {'; '.join(wrong)}", file=weights,
                         hint="the .json and .safetensors files must come from the same save")
    if module is None:
        module = _build(build, config, weights)  # now no larger than the file's tensors
    module.load_state_dict(tensors, strict=True)
    return module, config


def _build(build: Callable[[dict[str, Any]], M], config: dict[str, Any], weights: Path, *,
           device: str | None = None) -> M:
    """``build(config)`` (on ``device``); a configuration that cannot build a module (a negative
    or fractional layer size, a wrong type) is a :class:`ModelError` naming the file."""
    try:
        # torch warns about layers of size 0 ("Initializing zero-element tensors is a no-op"); such
        # a configuration is refused below by the comparison with the file's tensors, in one line
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            if device is None:
                return build(config)
            with torch.device(device):
                return build(config)
    except ModelError as exc:  # torch's messages can carry its C++ stack: keep their first line
        raise ModelError(_first_line(exc.message), file=exc.file or str(weights.with_suffix(".json")),
                         hint=exc.hint) from None
    except (TypeError, ValueError, RuntimeError, OverflowError, KeyError, IndexError, AttributeError) as exc:
        raise ModelError(f"the configuration does not describe a model ({type(exc).__name__}: "
                         f"{_first_line(str(exc))})", file=weights.with_suffix(".json")) from None


def _first_line(text: str) -> str:
    lines = text.strip().splitlines()
    return lines[0].rstrip() + (" ..." if len(lines) > 1 else "") if lines else text
