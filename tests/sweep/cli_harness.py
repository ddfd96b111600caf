"""``symlearn`` with the ``sweep`` command registered, whether or not ``cli/main.py`` lists it
yet: the tests call :func:`main` in-process, or run this file as a script in a subprocess."""

from __future__ import annotations

import sys

from symlearn.cli import main as cli_main

MODULE = "symlearn.cli.sweep_command"


def main(argv: list[str]) -> int:
    saved = cli_main.COMMAND_MODULES
    if MODULE not in saved:
        cli_main.COMMAND_MODULES = (*saved, MODULE)
    try:
        return cli_main.main(argv)
    finally:
        cli_main.COMMAND_MODULES = saved


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
