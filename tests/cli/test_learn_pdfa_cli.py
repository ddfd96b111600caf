"""``symlearn learn pdfa``: sub-goals, PDFA and plan from a frame archive or the block world; bad input."""

import json

import numpy as np
import pytest

from cli_runner import run
from symlearn.cli import learn_command
from symlearn.data.frame_archive import save_frames
from symlearn.envs.block_world import Demonstrator, place_task

MODULE = "symlearn.cli.learn_pdfa_command"


@pytest.fixture(autouse=True)
def registered(monkeypatch):
    """The subcommand, whether or not learn_command lists it yet."""
    if MODULE not in learn_command.LEARN_SUBCOMMANDS:
        monkeypatch.setattr(learn_command, "LEARN_SUBCOMMANDS", (*learn_command.LEARN_SUBCOMMANDS, MODULE))


@pytest.fixture(scope="module")
def archive(tmp_path_factory):
    task = place_task(3)
    runs, _ = Demonstrator(task, seed=4, drop=0.1).demonstrations(80)
    path = tmp_path_factory.mktemp("pdfa") / "blocks.npz"
    save_frames(path, runs, task.feature_names())
    return path, task


def test_frame_archive_to_plan_json_dot_and_automaton_show(capsys, tmp_path, archive):
    path, task = archive
    plan, dot = tmp_path / "plan.json", tmp_path / "plan.dot"
    code, out, err = run(capsys, "learn", "pdfa", "--demos", path, "--subsets", "red=0,1,2;green=3,4,5;blue=6,7,8",
                         "-o", plan, "--dot", dot, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert {"subgoals", "states", "edges", "words", "plan", "seconds"} <= set(doc)
    assert sorted(doc["subgoals"]) == ["blue_0", "green_0", "red_0"] and doc["plan"] == ["red_0", "green_0", "blue_0"]
    assert len(doc["states"]) == 8 and len(doc["edges"]) == 12 and sum(w["count"] for w in doc["words"]) == 80
    assert np.allclose(doc["subgoals"]["red_0"]["centre"], task.placements[0].place, atol=0.01)
    written = json.loads(plan.read_text())
    assert written["kind"] == "pdfa" and written["plan"] == doc["plan"] and "red_0" in written["subgoals"]
    assert "red_0\\n" in dot.read_text() and "penwidth" in dot.read_text()
    code, out, err = run(capsys, "automaton", "show", plan, "--json")
    assert code == 0, err
    assert json.loads(out)["states"] == 8


def test_feature_names_work_in_subsets(capsys, archive):
    path, _ = archive
    code, out, err = run(capsys, "learn", "pdfa", "--demos", path, "--subsets", "red=red_x,red_y,red_z", "--json")
    assert code == 0, err
    assert list(json.loads(out)["subgoals"]) == ["red_0"]


def test_block_world_env_is_scored_against_the_truth(capsys):
    code, out, err = run(capsys, "learn", "pdfa", "--env", "blocks-place-3", "--n-demos", 150, "--json")
    assert code == 0, err
    truth = json.loads(out)["truth"]
    assert truth == {"subgoals": 3, "matched_within_1cm": 3, "extra": 0, "language_equivalent": True,
                     "plan_is_preferred": True}
    code, out, err = run(capsys, "learn", "pdfa", "--env", "blocks-place-3", "--n-demos", 30)
    assert code == 0 and out.startswith("3 sub-goals") and "plan: red_0 -> green_0 -> blue_0" in out


@pytest.mark.parametrize("extra, message", [
    (["--subsets", "red=0,1,12"], "column 12 is out of range; the states have 9 features"),
    (["--subsets", "red"], "expected name=c,c"),
    (["--min-samples", "1e9"], "no sub-goal found"),
    (["--eps", "-2"], "eps must be a positive number"),
    (["-o", "plan.txt"], "must end in .json"),
    (["--dot", "plan.svg"], "must end in .dot"),
])
def test_bad_options_are_one_line(capsys, archive, extra, message):
    path, _ = archive
    code, _, err = run(capsys, "learn", "pdfa", "--demos", path, *extra)
    assert code == 2 and message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_all_nan_frames_and_bad_archives(capsys, tmp_path):
    nan = tmp_path / "nan.npz"
    save_frames(nan, [np.full((5, 3), np.nan)] * 4)
    code, _, err = run(capsys, "learn", "pdfa", "--demos", nan)
    assert code == 2 and "every frame is unobserved" in err
    bad = tmp_path / "bad.npz"
    np.savez(bad, states=np.zeros((5, 3)), lengths=np.array([2, 2]))
    code, _, err = run(capsys, "learn", "pdfa", "--demos", bad)
    assert code == 2 and "sum to the 5 rows" in err and "bad.npz" in err
    inf = tmp_path / "inf.npz"
    np.savez(inf, states=np.array([[0.0], [np.inf]]), lengths=np.array([1, 1]))
    code, _, err = run(capsys, "learn", "pdfa", "--demos", inf)
    assert code == 2 and "demonstration 1 has an infinite feature value" in err
    code, _, err = run(capsys, "learn", "pdfa", "--demos", tmp_path / "missing.npz")
    assert code == 2 and "missing.npz" in err
    code, _, err = run(capsys, "learn", "pdfa", "--env", "blocks-place-9")
    assert code == 2 and "unknown sub-goal task 'blocks-place-9'" in err and "blocks-place-6" in err


def test_thesis_probabilities_print_and_refuse_an_unloadable_file(capsys, tmp_path, archive):
    path, _ = archive
    code, out, err = run(capsys, "learn", "pdfa", "--demos", path, "--subsets", "red=0,1,2;green=3,4,5;blue=6,7,8",
                         "--probabilities", "thesis", "--json", "-o", tmp_path / "t.json")
    # every word completes all three sub-goals: the thesis' values form a proper PDFA here
    assert code == 0, err
    assert json.loads(out)["probabilities"] == "thesis" and (tmp_path / "t.json").exists()


def test_thesis_probabilities_that_do_not_sum_to_one_are_not_written(capsys, tmp_path):
    task = place_task(3)
    demonstrator = Demonstrator(task, seed=1)
    # some demonstrations stop after two blocks: {red, green} is accepting and has an edge out
    runs = [demonstrator.demonstration(order)[0] for order in [[0, 1, 2]] * 40 + [[0, 1]] * 20 + [[1, 0, 2]] * 20]
    path = tmp_path / "partial.npz"
    save_frames(path, runs, task.feature_names())
    args = ["learn", "pdfa", "--demos", path, "--subsets", task.subsets_text(), "--probabilities", "thesis"]
    code, out, err = run(capsys, *args, "--json")
    assert code == 0, err
    doc = json.loads(out)
    stops = {s["name"]: s["termination"] for s in doc["states"] if s["accepting"]}
    # eq. 6.3: entries into each accepting state over all entries into accepting states
    assert stops == pytest.approx({"{red_0,green_0}": 80 / 140, "{red_0,green_0,blue_0}": 60 / 140})
    code, _, err = run(capsys, *args, "-o", tmp_path / "p.json")
    assert code == 2 and "could not be read back as a PDFA" in err and not (tmp_path / "p.json").exists()
    code, out, err = run(capsys, *args[:-2], "--json", "-o", tmp_path / "p.json")
    assert code == 0 and (tmp_path / "p.json").exists()


def test_fast_walkers_at_the_defaults(capsys, tmp_path):
    # a cook walking 0.3 per step between three stations, dwelling with noise 0.05 (the tours of
    # benchmarks/fresh_domains.py); before: eps 0.45 from the dwelling noise chained the stations
    # and the start, "no sub-goal found"
    from symlearn.data import Demonstrations, Trajectory

    rng = np.random.default_rng(2)
    stations = np.array([(0.0, 0.0), (5.0, 0.0), (2.5, 4.0)])
    tours = []
    for k in range(40):
        pos, states = np.array([2.5, -2.0]), []
        for j in (0, 1, 2) if k % 4 else (1, 0, 2):
            while np.linalg.norm(stations[j] - pos) > 0.3:
                pos = pos + 0.3 * (stations[j] - pos) / np.linalg.norm(stations[j] - pos) + rng.normal(0, 0.05, 2)
                states.append([*pos, float(j)])
            states += [[*(stations[j] + rng.normal(0, 0.05, 2)), float(j)] for _ in range(int(rng.integers(6, 11)))]
        tours.append(Trajectory(states=np.array(states)))
    path = tmp_path / "tours.jsonl"
    Demonstrations(tours).save(path)
    code, out, err = run(capsys, "learn", "pdfa", "--demos", path, "--features", "x,y,station", "--subsets",
                         "cook=0,1", "--json")
    assert code == 0, err
    doc = json.loads(out)
    (clusters,) = doc["clusters"]
    assert clusters["eps_source"] == "half the travel step" and clusters["eps"] < 0.16 and not doc["warnings"]
    centres = [doc["subgoals"][name]["centre"] for name in doc["plan"]]
    assert len(doc["subgoals"]) == 3 and np.allclose(centres, stations, atol=0.1)  # fridge, stove, table
    code, out, err = run(capsys, "learn", "pdfa", "--demos", path, "--features", "x,y,station", "--subsets",
                         "cook=0,1", "--eps", "0.45", "--json")
    assert code == 2 and "no sub-goal found" in err  # an explicit --eps is used as given
