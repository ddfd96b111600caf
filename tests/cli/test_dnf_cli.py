"""``symlearn dnf eval`` / ``symlearn dnf show``: DNF rule files evaluated on NPZ points."""

import json

import numpy as np
from cli_runner import run

RULES = "# unsafe: too fast, or in the corner\nv > 1.46\nx0 > 0.1 & x0 < 0.7 & x1 > 0.3\n"
POINTS = np.array([[0.0, 0.5, 0.5], [2.0, 0.0, 0.0], [0.0, 0.9, 0.5], [1.46, 0.1, 0.31]])


def _files(tmp_path):
    rules = tmp_path / "rules.dnf"
    rules.write_text(RULES)
    np.savez(tmp_path / "points.npz", points=POINTS)
    np.savez(tmp_path / "named.npz", x1=POINTS[:, 2], v=POINTS[:, 0], x0=POINTS[:, 1], extra=np.zeros(4))
    np.savez(tmp_path / "self_named.npz", points=POINTS, features=np.array(["v", "x0", "x1"]))
    return rules


def test_eval_points_array_and_named_columns(capsys, tmp_path):
    rules = _files(tmp_path)
    code, out, err = run(capsys, "dnf", "eval", rules, "--points", tmp_path / "points.npz", "--features", "v,x0,x1",
                         "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["unsafe"] == [True, True, False, False]
    assert (doc["n_points"], doc["unsafe_count"], doc["conjunction_hits"]) == (4, 2, [1, 1])
    for archive in ("named.npz", "self_named.npz"):
        code, out, err = run(capsys, "dnf", "eval", rules, "--points", tmp_path / archive, "--json",
                             "--per-conjunction")
        assert code == 0, err
        doc = json.loads(out)
        assert doc["unsafe"] == [True, True, False, False] and doc["holding"] == [[1], [0], [], []]
    code, out, err = run(capsys, "dnf", "eval", rules, "--points", tmp_path / "named.npz")
    assert code == 0 and "2 of 4 points unsafe" in out and "unsafe points: 0, 1" in out


def test_eval_json_rules_and_true_false(capsys, tmp_path):
    _files(tmp_path)
    from symlearn.logic.dnf import FALSE, TRUE, parse

    parse(RULES).save(tmp_path / "rules.json")
    TRUE.save(tmp_path / "true.dnf")
    FALSE.save(tmp_path / "false.dnf")
    for name, want in (("rules.json", [True, True, False, False]), ("true.dnf", [True] * 4),
                       ("false.dnf", [False] * 4)):
        code, out, err = run(capsys, "dnf", "eval", tmp_path / name, "--points", tmp_path / "named.npz", "--json")
        assert code == 0, err
        assert json.loads(out)["unsafe"] == want


def test_eval_errors_are_one_line(capsys, tmp_path):
    rules = _files(tmp_path)

    def fails(*args, words):
        code, out, err = run(capsys, "dnf", "eval", *args)
        assert code == 2 and out == "", (code, out, err)
        assert len(err.strip().splitlines()) == 1 and words in err and "Traceback" not in err, err
        return err

    err = fails(rules, "--points", tmp_path / "points.npz", "--features", "v,a,b", words="features x0, x1")
    assert "points.npz" in err and "they have: v, a, b" in err
    fails(rules, "--points", tmp_path / "points.npz", words="--features")
    fails(rules, "--points", tmp_path / "points.npz", "--features", "v,x0", words="3 columns")
    fails(rules, "--points", tmp_path / "named.npz", "--features", "v,x0,x1", words="one array per feature")
    bad = tmp_path / "bad.dnf"
    bad.write_text("v > 1\nx0 >> 2\n")
    err = fails(bad, "--points", tmp_path / "named.npz", words="bad.dnf:2:5")
    nan = POINTS.copy()
    nan[2, 1] = np.nan
    np.savez(tmp_path / "nan.npz", points=nan)
    fails(rules, "--points", tmp_path / "nan.npz", "--features", "v,x0,x1", words="x0 is NaN in point 2")
    np.savez(tmp_path / "objects.npz", points=np.array([[1, "a"]], dtype=object))
    fails(rules, "--points", tmp_path / "objects.npz", "--features", "v,x0", words="objects.npz")
    (tmp_path / "junk.npz").write_bytes(b"not an archive")
    fails(rules, "--points", tmp_path / "junk.npz", words="not a readable NPZ")
    fails(rules, "--points", tmp_path / "missing.npz", words="missing.npz")
    np.savez(tmp_path / "ragged.npz", v=np.zeros(3), x0=np.zeros(4), x1=np.zeros(4))
    fails(rules, "--points", tmp_path / "ragged.npz", words="different lengths")


def test_show_and_simplify(capsys, tmp_path):
    rules = tmp_path / "rules.dnf"
    rules.write_text("x > 0 & x < 1 & y > 0\nx >= 1 & x < 2 & y > 0\nx > 0.5 & x < 0.7 & y > 3\n")
    code, out, err = run(capsys, "dnf", "show", rules, "--simplify", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["simplified"] == "x > 0 & x < 2 & y > 0" and doc["equivalent"] is True
    assert (doc["conjunctions"], doc["simplified_conjunctions"]) == (3, 1)
    code, out, err = run(capsys, "dnf", "show", rules, "--style", "unicode")
    assert code == 0 and out.splitlines()[0] == "x > 0 ∧ x < 1 ∧ y > 0" and "3 conjunctions, 9 atoms" in out


def test_eval_refuses_a_compressed_bomb_before_decompressing(capsys, tmp_path, monkeypatch):
    rules = _files(tmp_path)
    # 8 MB of zeros compress to a few KB; the header declares the size, so a 1 MB cap refuses it
    np.savez_compressed(tmp_path / "bomb.npz", points=np.zeros((1 << 20, 1)))
    monkeypatch.setenv("SYMLEARN_MAX_ARRAY_MB", "1")
    code, out, err = run(capsys, "dnf", "eval", rules, "--points", tmp_path / "bomb.npz", "--features", "v")
    assert code == 2 and "bomb.npz" in err and "limit" in err and "Traceback" not in err


def test_rule_file_that_is_not_utf8_is_located(capsys, tmp_path):
    _files(tmp_path)
    bad = tmp_path / "bad.dnf"
    bad.write_bytes(b"v > 1\nx0 > \xff0.1\n")
    code, out, err = run(capsys, "dnf", "show", bad)
    assert code == 2 and "bad.dnf:2:" in err and "UTF-8" in err


def test_a_conjunction_that_can_never_hold_is_warned_about(capsys, tmp_path):
    """``x < 1 & x > 2`` forbids nothing: in a hand-edited file that is a comparison the wrong way
    round, said once for the file with its lines (``==``/``!=`` expansions included). The CLI
    prints a warning as one ``warning:`` line; in-process, pytest records it."""
    import warnings

    path = tmp_path / "edited.dnf"
    path.write_text("x < 1 & x > 2\ny > 3\nx >= 0.5 & x <= 0.5\nz == 1 & z != 1\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code, out, err = run(capsys, "dnf", "show", path)
    assert code == 0 and "y > 3" in out
    warned = [str(w.message) for w in caught if "can never hold" in str(w.message)]
    assert len(warned) == 1, warned
    assert f"{path}: 3 conjunctions can never hold" in warned[0] and "lines 1, 4;" in warned[0]
    assert "x < 1 & x > 2 leaves no value of x" in warned[0]
    path.write_text("x < 3 & x > 2\nx >= 0.5 & x <= 0.5\n")   # narrow, but each holds somewhere
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code, out, err = run(capsys, "dnf", "show", path)
    assert code == 0 and not [w for w in caught if "can never hold" in str(w.message)]
    assert "# 2 conjunctions, 4 atoms" in out
