"""``symlearn demo``: the bundled end-to-end pipelines, run one after another into a report.

Each capability contributes a :class:`~symlearn.demo.registry.Pipeline` in its own module and
lists it in :data:`~symlearn.demo.registry.PIPELINE_MODULES`.
"""

from symlearn.demo.registry import DemoContext, Pipeline, Section
from symlearn.demo.runner import run_demo

__all__ = ["DemoContext", "Pipeline", "Section", "run_demo"]
