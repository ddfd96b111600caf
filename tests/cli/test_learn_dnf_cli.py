"""``symlearn learn dnf``: a one-class tree from demonstrations, the DNF written and re-read."""

import json
import sys

import numpy as np

from cli_runner import run
from user_envs import SWAPPED_CART
from symlearn.data import Demonstrations, Trajectory
from symlearn.logic.dnf import load as load_dnf


def test_toy_expert_gives_the_thesis_rule(capsys, tmp_path):
    out_file = tmp_path / "toy.dnf"
    code, out, err = run(capsys, "learn", "dnf", "--env", "toy-navigation", "--n-demos", 20, "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert {"formula", "conjunctions", "leaves", "features", "seconds"} <= set(doc)
    assert doc["features"] == ["x", "y"] and len(doc["leaves"]) == 2
    formula = load_dnf(out_file)
    assert str(formula) == doc["formula"]
    # the corridor above the bottom leg is unsafe, both legs and the corner are safe
    points = np.array([[0.4, 0.6], [0.4, 0.2], [0.8, 0.5], [0.8, 0.2]])
    assert formula.evaluate(points, ["x", "y"]).tolist() == [True, False, False, False]


def test_vector_demonstrations_with_feature_names(capsys, tmp_path):
    rng = np.random.default_rng(0)
    trajectories = [Trajectory(states=rng.uniform(0, 1, (30, 2)) * [1, 0.2]) for _ in range(5)]
    path = tmp_path / "demos.npz"
    Demonstrations(trajectories).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "speed,gap", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == ["speed", "gap"] and any("gap > " in c for c in doc["conjunctions"])


def test_bad_input_is_one_line(capsys, tmp_path):
    path = tmp_path / "demos.npz"
    Demonstrations([Trajectory(states=np.ones((4, 2)))]).save(path)
    code, _, err = run(capsys, "learn", "dnf", "--demos", path, "--max-depth", 0)
    assert code == 2 and "max_depth" in err.replace("-", "_") and "Traceback" not in err
    code, _, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "a,b,c")
    assert code == 2 and len(err.strip().splitlines()) == 1
    code, _, err = run(capsys, "learn", "dnf", "--env", "hanoi")
    assert code == 2 and "has no expert" in err


def test_feature_names_the_file_carries_name_the_columns(capsys, tmp_path):
    path = tmp_path / "named.npz"
    rng = np.random.default_rng(0)
    Demonstrations([Trajectory(states=rng.uniform(0, 1, (30, 2))) for _ in range(3)],
                   metadata={"feature_names": ["speed", "gap"]}).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--json")
    assert code == 0, err
    assert json.loads(out)["features"] == ["speed", "gap"]
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "a,b", "--json")
    assert code == 0 and json.loads(out)["features"] == ["a", "b"]  # the flag wins


def test_inputs_keep_the_rules_to_the_named_features_and_train_reads_the_default_names(capsys, tmp_path):
    # positions spread over a box, velocities that barely vary: without --inputs the tree splits on
    # the velocities too (any other velocity is "unsafe"); with --inputs x0,x1 only positions count
    rng = np.random.default_rng(0)
    states = [np.column_stack([rng.uniform(-1, 0, 40), rng.uniform(-1, 1, 40), rng.normal(0, 0.01, (40, 2))])
              for _ in range(6)]
    path = tmp_path / "rover.npz"
    Demonstrations([Trajectory(states=s.astype(np.float32)) for s in states]).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--json")
    assert code == 0, err
    assert {"x2", "x3"} & {atom.split()[0] for c in json.loads(out)["conjunctions"] for atom in c.split(" & ")}
    rules = tmp_path / "rules.dnf"
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--inputs", "x0,x1", "--validation", 0.3,
                         "-o", rules, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == ["x0", "x1"] and any("x0 > " in c for c in doc["conjunctions"])
    assert set(load_dnf(rules).features) <= {"x0", "x1"}
    code, _, err = run(capsys, "learn", "dnf", "--demos", path, "--inputs", "x0,speed")
    assert code == 2 and "--inputs: no feature named 'speed'" in err and "x0, x1, x2, x3" in err
    # an environment that names nothing: train reads the formula's x0, x1 as learn dnf named them
    code, out, err = run(capsys, "train", "--env", "rover_env:Rover-v0", "--cost", rules, "--steps", 256,
                         "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "--json")
    assert code == 0, err
    assert json.loads(out)["cost_kind"] == "dnf"
    rules.write_text("x7 > 0\n")  # a column the rover's 4-entry observation does not have
    code, _, err = run(capsys, "train", "--env", "rover_env:Rover-v0", "--cost", rules, "--steps", 256)
    assert code == 2 and "names no features" in err


def test_demonstrations_recorded_in_another_environment_get_a_warning(capsys, tmp_path):
    """Two columns fit toy-navigation's x, y whatever they were: a file recorded in another
    environment is read (relabelling may be meant) with one warning line, which --quiet drops."""
    rng = np.random.default_rng(0)
    states = [rng.uniform(0, 1, (30, 2)) for _ in range(3)]
    elsewhere, here, unnamed = tmp_path / "elsewhere.npz", tmp_path / "here.npz", tmp_path / "unnamed.npz"
    Demonstrations([Trajectory(states=s) for s in states], metadata={"env": "PointRobot-v0"}).save(elsewhere)
    Demonstrations([Trajectory(states=s) for s in states], metadata={"env": "symlearn/toy-navigation-v0"}).save(here)
    # record() of an environment built without a spec stores its class name: too little to compare
    Demonstrations([Trajectory(states=s) for s in states], metadata={"env": "ToyNavigationEnv"}).save(unnamed)
    code, out, err = run(capsys, "learn", "dnf", "--env", "toy-navigation", "--demos", elsewhere, "--json")
    assert code == 0, err
    assert json.loads(out)["features"] == ["x", "y"]
    warning = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warning) == 1 and "PointRobot-v0" in warning[0] and "toy-navigation" in warning[0], err
    assert str(elsewhere) in warning[0]
    code, out, err = run(capsys, "learn", "dnf", "--env", "toy-navigation", "--demos", elsewhere, "--quiet")
    assert code == 0 and "warning" not in err, err
    for path in (here, unnamed):
        for env in ("toy-navigation", "symlearn/toy-navigation-v0"):
            code, out, err = run(capsys, "learn", "dnf", "--env", env, "--demos", path, "--json")
            assert code == 0 and "warning" not in err, (path, env, err)


def test_demonstrations_narrower_than_the_environment_are_refused(capsys, tmp_path):
    """Three columns are not CartPole's four: one line naming the file, not a formula over
    columns the environment does not have."""
    rng = np.random.default_rng(0)
    path = tmp_path / "pendulum.npz"
    Demonstrations([Trajectory(states=rng.uniform(-1, 1, (20, 3))) for _ in range(2)],
                   metadata={"env": "Pendulum-v1"}).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--env", "CartPole-v1", "--demos", path, "-o", tmp_path / "p.dnf")
    assert code == 2 and "3 columns" in err and "observation has 4" in err and str(path) in err, err
    assert not (tmp_path / "p.dnf").exists()


def test_names_of_info_features_are_not_put_on_observations_that_differ(capsys, tmp_path, monkeypatch):
    """record() stores the observation; where the environment's info["features"] (whose keys name
    the columns) are other numbers, learning would silently call the velocity "pos": refused in
    one line, and --features naming the observation's columns learns what train --cost reads."""
    import gymnasium

    from symlearn.data import record

    (tmp_path / "swapped_cart.py").write_text(SWAPPED_CART)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import swapped_cart  # noqa: F401 -- registers SwappedCart-v0

    try:
        record(gymnasium.make("SwappedCart-v0"), lambda o: np.array([1.0 if o[1] < 0.4 else -1.0], np.float32), 5,
               seed=0).save(tmp_path / "demos.npz")
        code, _, err = run(capsys, "learn", "dnf", "--env", "swapped_cart:SwappedCart-v0", "--demos", "demos.npz",
                           "-o", "cart.dnf")
        assert code == 2 and 'info["features"] (pos=' in err and "not its observation" in err, err
        assert len(err.strip().splitlines()) == 1 and not (tmp_path / "cart.dnf").exists()
        code, out, err = run(capsys, "learn", "dnf", "--env", "swapped_cart:SwappedCart-v0", "--demos", "demos.npz",
                             "--features", "vel,pos", "--inputs", "pos", "--json", "-o", "cart.dnf")
        assert code == 0, err
        assert any(c.startswith("pos >") for c in json.loads(out)["conjunctions"])
        code, _, err = run(capsys, "train", "--env", "swapped_cart:SwappedCart-v0", "--cost", "cart.dnf", "--steps",
                           256, "--eval-episodes", 1)
        assert code == 0, err
    finally:
        sys.modules.pop("swapped_cart", None)
        gymnasium.registry.pop("SwappedCart-v0", None)


def test_validation_names_a_shallower_depth_when_the_tree_does_not_generalise(capsys, tmp_path):
    """Six features of random walks: depth 5 boxes are tight in every direction at once and call
    many held-out expert states unsafe; the warning names the shallower depth measured to call
    fewer of the same states unsafe, and the note without --validation points to it."""
    rng = np.random.default_rng(3)
    walks = [np.cumsum(rng.normal(0, 0.1, (60, 6)), axis=0) + rng.uniform(-1, 1, 6) for _ in range(20)]
    path = tmp_path / "walks.npz"
    Demonstrations([Trajectory(states=w.astype(np.float32)) for w in walks]).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--validation", 0.25, "--json")
    assert code == 0, err
    doc = json.loads(out)
    shallower = doc["validation"]["shallower"]
    assert [o["max_depth"] for o in shallower] == [4, 3, 2, 1]
    advice = [w for w in doc["warnings"] if "--max-depth" in w]
    assert len(advice) == 1, doc["warnings"]
    depth = int(advice[0].split("--max-depth ")[1].split()[0])
    chosen = next(o for o in shallower if o["max_depth"] == depth)
    assert chosen["held_out_share"] <= doc["validation"]["share"] / 2 or chosen["held_out_share"] <= 0.05
    code, out, err = run(capsys, "learn", "dnf", "--demos", path)
    assert code == 0 and "note: --validation 0.2" in out, out


def test_no_depth_advice_where_the_formula_already_generalises():
    from symlearn.learners.trees.depth_advice import DepthOption, advised

    options = [DepthOption(4, 0.01, 0.6, 9), DepthOption(3, 0.0, 0.5, 5), DepthOption(2, 0.0, 0.4, 3)]
    assert advised(options, 0.03) is None          # within the acceptable share already
    assert advised(options, 0.4).max_depth == 4    # the deepest one within it
    worse = [DepthOption(4, 0.35, 0.9, 9), DepthOption(3, 0.3, 0.8, 5)]
    assert advised(worse, 0.4) is None             # nothing halves it
    assert advised(worse, 0.7).max_depth == 3


def test_a_corridor_of_demonstrations_lists_the_formula_over_each_feature_alone(capsys, tmp_path):
    """One swing of an arm in (theta, omega) -- theta rising to 0.9 while omega rises and falls --
    covers a thin curve of the plane: most of the box is unsafe, and the note lists the formula
    over each feature alone for --inputs (issue 24); a box the demonstrations fill lists nothing."""
    t = np.linspace(0, 1, 30)
    rise = np.stack([0.9 * np.sin(np.pi / 2 * t), 2 * np.sin(np.pi * t)], 1)   # then held at 0.9, at rest
    swing = [Trajectory(states=np.concatenate([rise, np.tile([0.9, 0.0], (40, 1))]) + [0.002 * k, 0.0])
             for k in range(6)]
    path = tmp_path / "swing.npz"
    Demonstrations(swing).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "theta,omega", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["unsafe_share"] > 0.5
    assert [o["inputs"] for o in doc["inputs_options"]] == ["theta", "omega"]
    theta = doc["inputs_options"][0]["conjunctions"]
    assert any(c.startswith("theta > 0.9") for c in theta) and all("omega" not in c for c in theta)
    note = next(n for n in doc["notes"] if "--inputs" in n)
    assert "--inputs theta: theta <" in note and "--inputs omega: omega <" in note
    # --inputs given, or a box the demonstrations fill: nothing listed
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "theta,omega", "--inputs", "theta",
                         "--json")
    assert code == 0 and "inputs_options" not in json.loads(out)
    rng = np.random.default_rng(0)
    filled = tmp_path / "filled.npz"
    Demonstrations([Trajectory(states=rng.uniform(0, 1, (60, 2))) for _ in range(6)]).save(filled)
    code, out, err = run(capsys, "learn", "dnf", "--demos", filled, "--features", "a,b", "--json")
    assert code == 0 and "inputs_options" not in json.loads(out)


def test_pictures_as_states_are_warned_about_and_their_box_does_not_overflow(capsys, tmp_path):
    """A user's camera module's demonstrations: each state an 8 x 8 x 3 picture, learned as 192
    columns, so every rule bounds single pixels (said once); the lattice count of whole-number
    pixel values multiplied 192 extents in a float, which overflowed with a numpy warning."""
    import warnings

    import numpy as np

    from symlearn.data import Demonstrations, Trajectory

    rng = np.random.default_rng(0)
    pictures = [Trajectory(states=rng.integers(0, 255, size=(6, 8, 8, 3)).astype(np.uint8),
                           actions=np.zeros(5, dtype=int)) for _ in range(4)]
    Demonstrations(pictures).save(tmp_path / "pics.npz")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        code, out, err = run(capsys, "--json", "learn", "dnf", "--demos", tmp_path / "pics.npz",
                             "-o", tmp_path / "pics.dnf")
    assert code == 0, err
    doc = json.loads(out)
    assert any("arrays of shape (8, 8, 3), read as 192 separate columns" in w for w in doc["warnings"])
    code, out, err = run(capsys, "--json", "learn", "dnf", "--demos", tmp_path / "pics.npz", "--inputs", "x0,x1",
                         "-o", tmp_path / "two.dnf")
    assert code == 0, err
    assert not any("separate columns" in w for w in json.loads(out)["warnings"])


def test_the_validation_line_learn_dnf_writes_is_the_floor_train_reads(capsys, tmp_path):
    """The rule file's validation line is read back (rule_file_validation) with the numbers the
    JSON reports: the held-out demonstrations' unsafe states per demonstration."""
    from symlearn.learners.validation import rule_file_validation

    out_file = tmp_path / "toy.dnf"
    code, out, err = run(capsys, "learn", "dnf", "--env", "toy-navigation", "--n-demos", 10, "--validation", 0.3,
                         "-o", out_file, "--json")
    assert code == 0, err
    doc = json.loads(out)["validation"]
    recorded = rule_file_validation(out_file.read_text())
    assert recorded is not None
    assert (recorded.forbidden, recorded.steps, recorded.n_held_out, recorded.n_train) \
        == (doc["forbidden"], doc["steps"], doc["n_held_out"], doc["n_train"])
    assert recorded.per_demonstration == doc["per_demonstration"] == doc["forbidden"] / doc["n_held_out"]
