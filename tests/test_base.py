import pickle

from symlearn.atomic import write_text
from symlearn.errors import ParseError, SymlearnError
from symlearn.progress import progress, progress_bars, progress_enabled


def test_error_formats_location_and_hint():
    err = ParseError("unexpected ')'", file="task.las", line=3, column=14, hint="close the bracket")
    assert str(err) == "task.las:3:14: unexpected ')' (hint: close the bracket)"
    assert str(SymlearnError("plain")) == "plain"
    copy = pickle.loads(pickle.dumps(err))  # exceptions cross process pools intact (not a file format)
    assert (copy.file, copy.line, copy.column, copy.hint) == ("task.las", 3, 14, "close the bracket")


def test_write_text_replaces_atomically(tmp_path):
    target = tmp_path / "sub" / "out.txt"
    write_text(target, "one")
    write_text(target, "two")
    assert target.read_text() == "two"
    assert sorted(p.name for p in target.parent.iterdir()) == ["out.txt"]


def test_a_lone_surrogate_is_written_as_its_escape(tmp_path):
    """A file name that is not UTF-8 reaches Python as lone surrogates (b"d\\xff.npz" is
    "d\\udcff.npz"); a header naming it must not make the write fail."""
    import json

    name = b"d\xff.npz".decode("utf-8", "surrogateescape")
    write_text(tmp_path / "rules.dnf", f"# from {name}\nx > 1\n")
    assert (tmp_path / "rules.dnf").read_text(encoding="utf-8") == "# from d\\udcff.npz\nx > 1\n"
    write_text(tmp_path / "doc.json", json.dumps({"source": name}, ensure_ascii=False))
    assert json.loads((tmp_path / "doc.json").read_text(encoding="utf-8")) == {"source": name}


def test_a_learned_rule_file_names_a_demonstrations_file_that_is_not_utf8(tmp_path, capsys, monkeypatch):
    import numpy as np
    from cli_runner import run

    from symlearn.data import Demonstrations, Trajectory

    monkeypatch.chdir(tmp_path)
    name = b"d\xff.npz".decode("utf-8", "surrogateescape")
    Demonstrations([Trajectory(states=list(np.linspace(0, 1, 50)[:, None]), actions=[0] * 49)]).save(name)
    code, out, err = run(capsys, "learn", "dnf", "--demos", name, "-o", "rules.dnf")
    assert code == 0, err
    assert "d\\udcff.npz" in (tmp_path / "rules.dnf").read_text(encoding="utf-8").splitlines()[0]


def test_progress_is_silent_when_disabled(capsys):
    with progress_bars(False):
        assert not progress_enabled()
        assert list(progress(range(3), total=3, desc="x")) == [0, 1, 2]
    assert capsys.readouterr().err == ""
    with progress_bars(True):
        assert progress_enabled()
        assert list(progress(range(3), total=3)) == [0, 1, 2]


def test_progress_stays_quiet_in_ci(monkeypatch):
    monkeypatch.setenv("CI", "true")
    assert not progress_enabled()
