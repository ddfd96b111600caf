"""symlearn.rl.training_log: CSV rows written as training goes, and the refusals."""

from __future__ import annotations

import csv
import math

import pytest

from symlearn.errors import SymlearnError
from symlearn.rl.training_log import TrainingLog, flat_row


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_flat_row_spreads_sequences_and_blanks_non_finite_numbers():
    assert flat_row({"a": (1.0, 2.0), "b": math.nan, "c": True, "d": 3}) == \
        {"a_0": 1.0, "a_1": 2.0, "b": None, "c": 1, "d": 3}


def test_rows_are_on_disk_after_every_write_and_a_new_column_widens_the_header(tmp_path):
    path = tmp_path / "run.csv"
    log = TrainingLog(path)
    assert path.exists() and path.read_text() == ""  # created before any training
    log.write({"iteration": 1, "mean_cost": ()})
    assert _rows(path) == [{"iteration": "1"}]
    log.write({"iteration": 2, "mean_cost": (0.5,)})   # the first cost arrives: a new column
    log.write({"iteration": 3, "mean_cost": (0.25,)})
    assert _rows(path) == [{"iteration": "1", "mean_cost_0": ""}, {"iteration": "2", "mean_cost_0": "0.5"},
                           {"iteration": "3", "mean_cost_0": "0.25"}]
    assert not list(tmp_path.glob(".*.tmp"))


def test_a_directory_and_a_missing_tensorboard_are_refused_before_training(tmp_path):
    with pytest.raises(SymlearnError, match="is a directory"):
        TrainingLog(tmp_path)
    try:
        import tensorboard  # noqa: F401
    except ImportError:
        with pytest.raises(SymlearnError, match="needs the tensorboard package"):
            TrainingLog(tensorboard=tmp_path / "tb")
