"""Reading sweep files: cells, and every mistake located in the file."""

from __future__ import annotations

import pytest

from symlearn.errors import DataError, ParseError
from symlearn.sweep.spec import cell_id, read_spec
from sweep_helpers import CELLS, sweep_text


def write(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_cells_are_the_product_of_grid_cases_and_seeds(tmp_path):
    text = sweep_text("square", {"x": [1, 2, 3]}, seeds=[5, 7]) + "[[cases]]\ndelay = 0.0\n[[cases]]\ndelay = 0.001\n"
    spec = read_spec(write(tmp_path, text))
    cells = spec.cells()
    assert len(cells) == 2 * 3 * 2
    assert [c.seed for c in cells[:4]] == [5, 7, 5, 7]
    assert cells[0].params == {"delay": 0.0, "x": 1}
    assert cells[-1].params == {"delay": 0.001, "x": 3}
    assert len({c.id for c in cells}) == len(cells)
    # ids depend on what is computed only: the same in another file, another order of keys
    assert cells[0].id == cell_id(spec.target, {"x": 1, "delay": 0.0}, 5, None)


def test_seeds_count_means_zero_to_n_minus_one(tmp_path):
    spec = read_spec(write(tmp_path, sweep_text("square", {"x": [1]}, seeds=3)))
    assert spec.seeds == [0, 1, 2]


def test_fingerprint_ignores_retries_and_report_but_not_the_grid(tmp_path):
    base = read_spec(write(tmp_path, sweep_text("square", {"x": [1, 2]}), "a.toml"))
    tuned = read_spec(write(tmp_path, sweep_text("square", {"x": [1, 2]}, extra="retries = 5\ntimeout = 9"),
                            "b.toml"))
    grown = read_spec(write(tmp_path, sweep_text("square", {"x": [1, 2, 3]}), "c.toml"))
    assert base.fingerprint() == tuned.fingerprint()
    assert base.fingerprint() != grown.fingerprint()


def test_unknown_parameter_is_located(tmp_path):
    path = write(tmp_path, sweep_text("square", {"x": [1], "y": [2]}))
    with pytest.raises(DataError) as error:
        read_spec(path)
    assert "unknown parameter 'y'" in error.value.message
    assert error.value.file == str(path)
    assert path.read_text().splitlines()[error.value.line - 1].startswith("y =")


def test_missing_required_parameter(tmp_path):
    with pytest.raises(DataError, match="needs parameter x"):
        read_spec(write(tmp_path, sweep_text("square", {"delay": [0.0]})))


def test_function_without_seed_is_refused(tmp_path):
    with pytest.raises(DataError, match="unknown parameter 'seed'") as error:
        read_spec(write(tmp_path, sweep_text("no_seed", {"x": [1]})))
    assert "seed" in error.value.hint


@pytest.mark.parametrize("grid, seeds, what", [
    ({"x": []}, 2, "empty list: the grid has 0 cells"),
    ({"x": [1]}, 0, "the grid has 0 cells"),
    ({"x": [1]}, [], "empty list: the grid has 0 cells"),
])
def test_a_grid_of_zero_cells_is_refused(tmp_path, grid, seeds, what):
    path = write(tmp_path, sweep_text("square", grid, seeds=seeds))
    with pytest.raises(DataError, match=what) as error:
        read_spec(path)
    assert error.value.line is not None


@pytest.mark.parametrize("text, message", [
    ("[sweep]\nfunction = 'm:f'\n[gird]\nx = [1]\n", "unknown section [gird]"),
    ("[sweep]\nfunction = 'm:f'\nseed = 3\n", "unknown key 'seed' in [sweep]"),
    ("[sweep]\nseeds = 2\n", "exactly one of function"),
    ("[sweep]\nfunction = 'nocolon'\n", "must be \"module:function\""),
    ("[sweep]\nfunction = 'm:f'\nretries = -1\n", "retries must be"),
    ("[sweep]\nfunction = 'm:f'\ntimeout = 0\n", "timeout must be a positive number"),
    ("[sweep]\nfunction = 'm:f'\n[grid]\nx = 3\n", "must be a list"),
    ("[sweep]\nfunction = 'm:f'\n[grid]\nx = [1, 1]\n", "lists a value twice"),
    ("[sweep]\nfunction = 'm:f'\n[fixed]\nseed = 1\n", "'seed' is set per cell"),
    ("[sweep]\nfunction = 'm:f'\n[fixed]\nx = 1\n[grid]\nx = [1, 2]\n", "both in [fixed] and in [grid]"),
])
def test_mistakes_in_the_file(tmp_path, text, message):
    with pytest.raises(DataError) as error:
        read_spec(write(tmp_path, text), check_target=False)
    assert message in error.value.message


def test_toml_syntax_error_has_line_and_column(tmp_path):
    with pytest.raises(ParseError) as error:
        read_spec(write(tmp_path, "[sweep]\nfunction = 'm:f'\nseeds = [1,\n"))
    assert error.value.line is not None and error.value.column is not None


def test_function_that_does_not_load(tmp_path):
    with pytest.raises(DataError, match="cannot load function") as error:
        read_spec(write(tmp_path, f'[sweep]\nfunction = "{CELLS}:nothing_here"\n'))
    assert error.value.line == 2


def test_command_placeholders_are_checked(tmp_path):
    ok = '[sweep]\ncommand = ["symlearn", "x", "{n}", "--seed", "{seed}"]\n[grid]\nn = [1, 2]\n'
    assert len(read_spec(write(tmp_path, ok, "a.toml")).cells()) == 2
    unused = '[sweep]\ncommand = ["symlearn", "x"]\n[grid]\nn = [1, 2]\n'
    with pytest.raises(DataError, match="no {n} placeholder"):
        read_spec(write(tmp_path, unused, "b.toml"))
    unknown = '[sweep]\ncommand = ["symlearn", "{m}"]\n'
    with pytest.raises(DataError, match="placeholder {m}"):
        read_spec(write(tmp_path, unknown, "c.toml"))


def test_keeping_other_metrics_makes_other_cells(tmp_path):
    every = read_spec(write(tmp_path, sweep_text("square", {"x": [1]}), "a.toml")).cells()
    some = read_spec(write(tmp_path, sweep_text("square", {"x": [1]}, extra='metrics = ["value"]'), "b.toml")).cells()
    assert [c.id for c in every] != [c.id for c in some]
