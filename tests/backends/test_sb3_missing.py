"""Without stable-baselines3 the SB3 glue says how to install it (runs whether or not it is installed)."""

import pytest

from symlearn import optional
from symlearn.backends import sb3
from symlearn.errors import MissingDependencyError


def test_missing_stable_baselines3_is_reported_with_the_extra_to_install(monkeypatch):
    monkeypatch.setattr(optional, "available", lambda name: False)
    with pytest.raises(MissingDependencyError, match="needs sb3") as info:
        sb3.counterfactual_callback()
    assert "symlearn[sb3]" in info.value.hint


def test_the_engines_are_registered():
    assert {"sb3", "sb3_contrib"} <= set(optional.ENGINES)
    assert all(".venv/bin/pip install -e '.[sb3]'" in optional.ENGINES[name].install_hint
               and "symlearn[sb3]" in optional.ENGINES[name].install_hint for name in ("sb3", "sb3_contrib"))


def test_training_and_loading_on_stable_baselines3_name_the_extra(monkeypatch):
    monkeypatch.setattr(optional, "available", lambda name: False)
    for call in (lambda: sb3.algorithm_class("ppo"), lambda: sb3.lagrangian_callback(None),
                 lambda: sb3.load_policy("agent.safetensors", None)):
        with pytest.raises(MissingDependencyError) as info:
            call()
        assert "symlearn[sb3]" in info.value.hint
