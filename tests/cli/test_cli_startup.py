"""The CLI imports only the command it runs, and large DFAs print without listing their edges."""

import json
import subprocess
import sys

from cli_runner import run
from symlearn.cli.main import COMMAND_MODULES, build_parser, command_name, requested_command


def test_the_command_on_the_line_picks_one_module():
    assert requested_command(["ltl", "dfa", "F a"]) == "symlearn.cli.ltl_command"
    assert requested_command(["--seed", "3", "--quiet", "automaton", "show", "x.json"]) == \
        "symlearn.cli.automaton_command"
    for line in (["--help"], [], ["--version"], ["no-such-command"], ["-q"]):
        assert requested_command(line) is None  # the full parser: help and usage list every command
    assert {command_name(m) for m in COMMAND_MODULES} >= {"ltl", "automaton", "learn", "data", "demo"}
    only = build_parser("symlearn.cli.ltl_command")
    assert only.parse_args(["ltl", "dfa", "F a"]).handler.__name__ == "_dfa"


def test_ltl_dfa_imports_no_learner_environment_numpy_or_lark():
    code = ("import sys\n"
            "from symlearn.cli.main import main\n"
            "assert main(['ltl', 'dfa', 'F a & G b']) == 0\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numpy', 'sympy', 'torch', 'lark') or "
            "m.startswith(('symlearn.envs', 'symlearn.learners', 'symlearn.rl'))))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_a_symbolic_dfa_is_summarised_not_listed(capsys):
    formula = " & ".join(f"F p{i}" for i in range(9))
    code, out, _ = run(capsys, "ltl", "dfa", formula)
    assert code == 0
    assert out.startswith("minimal DFA: 512 states, 19683 edges") and "kept symbolic" in out
    code, out, _ = run(capsys, "ltl", "dfa", formula, "--json")
    doc = json.loads(out)
    assert doc["symbolic"] is True and doc["transitions"] is None and doc["diagram_nodes"] > 0


def test_writing_too_many_edges_is_one_clear_error(tmp_path, capsys):
    formula = " & ".join(f"F p{i}" for i in range(13))  # 3^13 edges > 1,000,000
    code, out, err = run(capsys, "ltl", "dfa", formula, "--dot", tmp_path / "big.dot")
    assert code == 2 and "kept symbolic" in err and "Traceback" not in err
    assert not (tmp_path / "big.dot").exists()
