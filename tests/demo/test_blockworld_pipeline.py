"""The block-world demo pipeline: learned sub-goals and PDFA match the truth, replanning succeeds."""

import json

from symlearn.demo.blockworld_pipeline import PIPELINE
from symlearn.demo.registry import DemoContext


def test_blockworld_pipeline_learns_plans_and_replans(tmp_path):
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    fig = section.figures
    assert fig["subgoals"] == fig["matched_within_1cm"] == 4 and fig["words_match_orderings"]
    # the learned automaton is Algorithm 6.2's on the true orderings; the truth's when all 24 were shown
    assert fig["equals_automaton_of_true_orderings"]
    assert fig["language_equivalent"] or not fig["all_orderings_shown"]
    assert fig["plan"] == fig["preferred"] == ["red_at_0", "green_at_0", "blue_at_0", "yellow_at_0"]
    assert fig["execution"]["success"] and fig["task_done"] and fig["execution"]["replans"]
    assert fig["execution"]["achieved"][0] != "red_0"  # red was hidden: something else went first
    for name in section.files:
        assert (tmp_path / name).is_file(), name
    assert json.loads((tmp_path / "blockworld" / "plan.json").read_text())["kind"] == "pdfa"
    assert "Greedy plan" in section.markdown
