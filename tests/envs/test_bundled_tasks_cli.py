"""The bundled tasks work out of the box from the command line."""

import json

import pytest

from symlearn.envs.ilp_tasks import DEFAULT_TASKS
from symlearn.envs.logic_domains import logic_domain
from symlearn.resources import background_kb_path

EXHAUSTIVE = {rel: name for rel, (name, recipe) in DEFAULT_TASKS.items() if recipe == "exhaustive"}


def test_learn_hanoi_from_the_command_line(run_cli):
    done = run_cli("ilp", "learn", background_kb_path("hanoi", "tasks", "hanoi.las"), "--json")
    assert done.returncode == 0, done.stderr
    document = json.loads(done.stdout)
    assert document["optimal"] is True and document["score"] == 2
    assert [r.replace(" ", "") for r in document["rules"]] in (
        [":-on(V1,V2),V1<V2."], [":-V1<V2,on(V1,V2)."], [":-on(V1,V2),V2>V1."])


@pytest.mark.parametrize("relative", sorted(EXHAUSTIVE))
def test_truth_files_cover_every_example_of_the_exhaustive_tasks(run_cli, relative):
    domain = logic_domain(EXHAUSTIVE[relative])
    done = run_cli("ilp", "check", background_kb_path(*relative.split("/")), domain.truth_path, "--json")
    assert done.returncode == 0, done.stderr
    document = json.loads(done.stdout)
    assert document["covered"] == document["total"] == len(domain.pairs())
