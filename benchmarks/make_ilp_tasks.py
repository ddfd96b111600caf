"""Regenerate the bundled ILP task files under background_kb/<domain>/tasks/.

    python benchmarks/make_ilp_tasks.py            # write them
    python benchmarks/make_ilp_tasks.py --check    # exit 1 if a bundled file is out of date
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from symlearn.envs.ilp_tasks import DEFAULT_TASKS, default_task_text, write_default_tasks

ROOT = Path(__file__).resolve().parent.parent / "background_kb"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only compare, write nothing")
    args = parser.parse_args()
    if args.check:
        stale = [rel for rel in DEFAULT_TASKS
                 if not (ROOT / rel).is_file() or (ROOT / rel).read_text(encoding="utf-8") != default_task_text(rel)]
        for rel in stale:
            print(f"out of date: background_kb/{rel}")
        return 1 if stale else 0
    for path in write_default_tasks(ROOT):
        print(f"wrote {path.relative_to(ROOT.parent)} ({path.stat().st_size} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
