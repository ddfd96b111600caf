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
