"""Set the ``#const name = value.`` defaults of a background program to other values.

The bundled background knowledge states its sizes (grid size, number of disks) as clingo
constants; a model of another size rewrites them instead of keeping a second copy of the file.

>>> set_constants("#const size = 5.\\ncol(1..size).", {"size": 7})
'#const size = 7.\\ncol(1..size).'
"""

from __future__ import annotations

import re
from collections.abc import Mapping

from symlearn.errors import ModelError


def set_constants(program: str, values: Mapping[str, int]) -> str:
    """``program`` with each ``#const NAME = ...`` line of ``values`` set to the new value."""
    for name, value in values.items():
        pattern = re.compile(rf"^#const\s+{re.escape(name)}\s*=\s*[^.]+\.", re.MULTILINE)
        program, count = pattern.subn(f"#const {name} = {int(value)}.", program)
        if count != 1:
            raise ModelError(f"the background program defines #const {name} {count} times, expected once")
    return program
