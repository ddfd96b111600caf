"""``import symlearn.logic`` stays light: no deep-learning, RL or scientific stack, no learner.

Checked at run time in a fresh interpreter, so transitive imports count too (tests/test_layers.py
checks the import statements themselves).
"""

import json
import subprocess
import sys

PACKAGES = ["symlearn.logic", "symlearn.logic.ltlf", "symlearn.logic.automata", "symlearn.logic.asp",
            "symlearn.logic.ilp"]
HEAVY = ["torch", "gymnasium", "sklearn", "scipy", "sympy", "networkx", "z3", "pandas", "matplotlib",
         "symlearn.learners", "symlearn.envs", "symlearn.backends", "symlearn.rl"]


def test_importing_the_logic_core_loads_nothing_heavy():
    code = (f"import importlib, json, sys\n"
            f"for name in {PACKAGES!r}:\n"
            f"    importlib.import_module(name)\n"
            f"print(json.dumps(sorted(sys.modules)))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    loaded = json.loads(done.stdout)
    heavy = sorted({m for m in loaded for h in HEAVY if m == h or m.startswith(h + ".")})
    assert not heavy, f"importing {', '.join(PACKAGES)} loaded {heavy}"
