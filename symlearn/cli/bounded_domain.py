"""Reading a user's domain folder within a time and memory limit, for the commands that use a
folder only as a world to learn in (``learn dnf --domain``, ``learn spec --domain``).

A domain folder's background program and state facts are the user's ASP: grounding them can take
any time and memory (``n(X+1) :- n(X).``), and clingo cannot be interrupted. ``domain check``,
``ilp`` and ``learn constraints --domain`` run their whole work in the bounded worker
(:mod:`symlearn.worker`). Here only reading and grounding the folder does: the worker returns the
loaded :class:`~symlearn.grounding.Domain` (plain arrays and names), and learning -- minutes of
tabular or PPO updates with live progress notes -- happens in this process, where a memory
limit sized for grounding would not fit torch.
"""

from __future__ import annotations

import argparse


def add_domain_limits(parser: argparse.ArgumentParser, work: str = "reading and grounding the folder") -> None:
    """``--timeout`` and ``--max-memory`` for the ``work`` done with the folder given with ``--domain``."""
    parser.add_argument("--timeout", default="600", metavar="S",
                        help=f"--domain: seconds for {work}, in a worker process ('inf': no limit; default 600)")
    parser.add_argument("--max-memory", default=None, metavar="MB",
                        help=f"--domain: memory limit of the worker ({work}; default SYMLEARN_MAX_MEMORY_MB or "
                             "1024; 0: none)")


def run_on_domain(function, /, *arguments, args: argparse.Namespace, what: str):
    """``function(*arguments)`` in the bounded worker under the limits of ``args.timeout`` and
    ``args.max_memory``; ``what`` names the work in the message when a limit is reached."""
    from symlearn.worker import memory_limit_mb, run_limited, seconds_limit

    seconds = seconds_limit(getattr(args, "timeout", None), name="--timeout")
    memory = memory_limit_mb(getattr(args, "max_memory", None), name="--max-memory")
    return run_limited(function, *arguments, seconds=seconds, memory_mb=memory, what=what,
                       time_hint="raise --timeout",
                       memory_hint="raise --max-memory (or SYMLEARN_MAX_MEMORY_MB; 0: no limit) if the "
                                   "domain is meant to be this large")


def load_domain(args: argparse.Namespace):
    """The folder ``args.domain`` read and grounded in the bounded worker; one
    :class:`~symlearn.errors.SymlearnError` line when it is malformed or grounds past a limit."""
    return run_on_domain(_read, args.domain, bool(getattr(args, "allow_outside", False)), args=args,
                         what=f"reading and grounding the domain {args.domain}")


def _read(folder: str, allow_outside: bool):
    from symlearn.grounding import Domain

    return Domain.from_folder(folder, allow_outside=allow_outside)
