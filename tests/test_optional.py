import shutil

import pytest

from symlearn import optional
from symlearn.errors import MissingDependencyError


def test_spot_is_detected_or_reported_with_a_hint():
    try:
        import spot  # noqa: F401
        present = True
    except ImportError:
        present = False
    assert optional.available("spot") is present
    if not present:
        with pytest.raises(MissingDependencyError, match="needs spot") as info:
            optional.require("spot")
        assert "conda-forge" in info.value.hint


def test_programs_count_too():
    assert optional.available("graphviz") is (shutil.which("dot") is not None)


def test_unknown_engine_is_a_programming_error():
    with pytest.raises(ValueError, match="unknown optional engine"):
        optional.available("nonsense")


def test_doctor_command(run_cli):
    import json

    result = run_cli("doctor", "--json")
    assert result.returncode == 0
    names = {row["name"] for row in json.loads(result.stdout)["engines"]}
    assert {"spot", "mona", "sumo"} <= names
