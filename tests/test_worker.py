"""The bounded worker process (``symlearn/worker.py``): results, errors and limits.

Functions run in the worker must be importable by name in a fresh interpreter, so these tests
use builtins and library functions, not functions defined here.
"""

import time

import pytest

from symlearn.errors import LimitExceededError, ParseError, SymlearnError
from symlearn.worker import WorkerCrash, memory_limit_mb, run_limited, seconds_limit


def test_result_and_user_errors_come_back_unchanged():
    from symlearn.logic.asp import clingo_adapter as cl
    from symlearn.logic.asp.program import Program
    from symlearn.logic.ilp import parse_task

    outcome = run_limited(cl.solve, Program.from_text("{a}. b :- not a."), seconds=30, memory_mb=512)
    assert sorted(sorted(map(str, m)) for m in outcome.models) == [["a"], ["b"]]  # symbols crossed processes
    with pytest.raises(ParseError) as info:
        run_limited(parse_task, "#modeb(1, p(var(t)).\n", source="t.las", seconds=30)
    assert info.value.file == "t.las" and info.value.line == 1


def test_time_limit_kills_the_worker_and_names_the_limit():
    start = time.monotonic()
    with pytest.raises(LimitExceededError, match=r"time limit of 1 s reached while sleeping") as info:
        run_limited(time.sleep, 30, seconds=1, what="sleeping", time_hint="raise --timeout")
    assert time.monotonic() - start < 1 + 0.2 + 0.02 + 1.0 and info.value.hint == "raise --timeout"


def test_memory_limit_stops_an_allocation_with_a_clear_error():
    with pytest.raises(LimitExceededError, match="memory limit of 300 MB reached while allocating"):
        run_limited(bytearray, 2**31, seconds=30, memory_mb=300, what="allocating")


def test_a_bug_in_the_worker_is_not_a_user_error():
    with pytest.raises(WorkerCrash, match="ValueError") as info:
        run_limited(int, "not a number", seconds=30)
    assert not isinstance(info.value, SymlearnError) and "ValueError" in info.value.child_traceback


def test_in_process_switch(monkeypatch):
    monkeypatch.setenv("SYMLEARN_WORKER", "off")
    assert run_limited(sum, [1, 2], seconds=0.001) == 3  # no worker, no limit


@pytest.mark.parametrize("text, seconds", [("5", 5.0), ("0.5", 0.5), ("inf", None), ("1e10", None),
                                           ("1e308", None), (None, None)])
def test_seconds_limit_accepts(text, seconds):
    assert seconds_limit(text) == seconds


@pytest.mark.parametrize("text", ["0", "-1", "nan", "-inf", "soon"])
def test_seconds_limit_refuses(text):
    with pytest.raises(SymlearnError, match="--timeout must be a"):
        seconds_limit(text, name="--timeout")


def test_memory_limit_from_flag_environment_and_default(monkeypatch):
    monkeypatch.delenv("SYMLEARN_MAX_MEMORY_MB", raising=False)
    assert memory_limit_mb() == 1024 and memory_limit_mb("300") == 300 and memory_limit_mb("0") is None
    monkeypatch.setenv("SYMLEARN_MAX_MEMORY_MB", "2048")
    assert memory_limit_mb() == 2048 and memory_limit_mb("500") == 500
    monkeypatch.setenv("SYMLEARN_MAX_MEMORY_MB", "none")
    assert memory_limit_mb() is None
    for bad in ("-5", "nan", "lots", "10"):
        with pytest.raises(SymlearnError, match="--max-memory"):
            memory_limit_mb(bad, name="--max-memory")
