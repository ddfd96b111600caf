"""What a demo pipeline is, and the list of them."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

# Modules that each define ``PIPELINE``; the demo runs them in this order.
PIPELINE_MODULES: tuple[str, ...] = (
    "symlearn.demo.demonstrations_pipeline",
    "symlearn.demo.gridworld_pipeline",
    "symlearn.demo.ltlf_pipeline",
    "symlearn.demo.spec_pipeline",
    "symlearn.demo.ilp_pipeline",
    "symlearn.demo.constraints_pipeline",
    "symlearn.demo.dnf_pipeline",
    "symlearn.demo.safenav_pipeline",
    "symlearn.demo.blockedpoint_pipeline",
    "symlearn.demo.blockworld_pipeline",
    "symlearn.demo.rm_pipeline",
)


@dataclass
class DemoContext:
    """Where a pipeline writes and how it draws random numbers."""

    out_dir: Path
    seed: int = 0
    quick: bool = False

    def rng(self) -> np.random.Generator:
        return np.random.default_rng(self.seed)

    def path(self, *parts: str) -> Path:
        target = self.out_dir.joinpath(*parts)
        target.parent.mkdir(parents=True, exist_ok=True)
        return target


@dataclass
class Section:
    """A pipeline's contribution to ``summary.md`` and ``summary.json``."""

    title: str
    markdown: str
    figures: dict[str, Any] = field(default_factory=dict)
    files: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Pipeline:
    name: str
    title: str
    run: Callable[[DemoContext], Section]


def pipelines() -> list[Pipeline]:
    return [importlib.import_module(name).PIPELINE for name in PIPELINE_MODULES]
