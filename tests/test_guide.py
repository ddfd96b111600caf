"""docs/GUIDE.md cannot rot: its marked code blocks run, in order, in a copy of docs/guide/.

A block is marked by the comment on the line before its fence: ``<!-- guide-test -->`` (runs in
the default suite) or ``<!-- guide-test slow -->`` (left to ``-m slow``; no block needs it
today: every route, training included, runs at the cut-down budgets below). ``bash`` blocks run under ``bash -e`` with ``symlearn`` and
``python`` meaning this interpreter; ``python`` blocks run as scripts. Training budgets are cut
down (``--steps``, ``--iterations``) so the commands are checked, not the agents' quality.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
GUIDE = ROOT / "docs" / "GUIDE.md"
FILES = ROOT / "docs" / "guide"
BLOCK = re.compile(r"<!-- guide-test(?P<tags>[a-z ]*)-->\n```(?P<lang>bash|python)\n(?P<code>.*?)\n```", re.S)
SMALL = [(re.compile(r"--steps \d+"), "--steps 1024"), (re.compile(r"--ppo-steps \d+"), "--ppo-steps 4096"),
         (re.compile(r"--iterations \d+"), "--iterations 1")]


def blocks(*, slow: bool) -> list[tuple[str, str, set[str]]]:
    found = []
    for match in BLOCK.finditer(GUIDE.read_text()):
        tags = set(match["tags"].split())
        if "slow" in tags and not slow:
            continue
        code = match["code"]
        for pattern, replacement in SMALL:
            code = pattern.sub(replacement, code)
        found.append((match["lang"], code, tags))
    return found


def run_blocks(selected, folder: Path) -> None:
    shutil.copytree(FILES, folder, ignore=shutil.ignore_patterns("__pycache__"))
    env = dict(os.environ, SYMLEARN_QUIET="1", SYMLEARN_QUICK="1", MPLBACKEND="Agg")
    prelude = f'symlearn() {{ "{sys.executable}" -m symlearn "$@"; }}\npython() {{ "{sys.executable}" "$@"; }}\n'
    for number, (lang, code, _) in enumerate(selected):
        if lang == "bash":
            command = ["bash", "-e", "-c", prelude + code]
        else:
            script = folder / f"guide_block_{number}.py"
            script.write_text(code + "\n")
            command = [sys.executable, script.name]
        done = subprocess.run(command, cwd=folder, env=env, capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, f"guide block {number} ({lang}) failed:\n{code}\n--- output\n{done.stdout}{done.stderr}"


def test_every_command_block_is_marked():
    text = GUIDE.read_text()
    unmarked = [m.group(0) for m in re.finditer(r"(?<!-->\n)```bash\n(.*?)\n```", text, re.S) if "symlearn" in m[1]]
    assert not unmarked, f"bash blocks with symlearn commands but no guide-test mark: {unmarked}"
    assert len(blocks(slow=True)) >= 15


def test_guide_commands(tmp_path):
    """Every route of the guide, record -> learn -> edit -> re-check -> train, in order."""
    run_blocks(blocks(slow=False), tmp_path / "guide")


@pytest.mark.slow
def test_guide_slow_commands(tmp_path):
    run_blocks(blocks(slow=True), tmp_path / "guide")
