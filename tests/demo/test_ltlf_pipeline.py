from symlearn.demo.ltlf_pipeline import PIPELINE
from symlearn.demo.registry import DemoContext, pipelines


def test_ltlf_pipeline_checks_translates_and_explains(tmp_path):
    assert "ltlf" in [p.name for p in pipelines()]
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    fig = section.figures
    assert fig["vectorised_agrees_with_reference"] and fig["dfa_agrees_with_evaluator"]
    assert fig["dfa_states"] == 3 and fig["identical_to_mona"] in (True, None)
    assert fig["spec_satisfaction"]["expert"] > fig["spec_satisfaction"]["random"]
    assert fig["edited_spec_satisfaction"]["expert"] <= fig["spec_satisfaction"]["expert"]
    for name in section.files:
        assert (tmp_path / name).is_file(), name
    assert (tmp_path / "ltlf" / "spec.ltl").read_text().strip().endswith("G(!hole) & F goal")
    assert "shortest fix" in section.markdown
    assert (tmp_path / "ltlf" / "spec_dfa.dot").read_text().startswith("digraph")
