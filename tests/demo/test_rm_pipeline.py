"""Demo ``rm``: Stack-2 machine from images, drawn with prototypes, and a short DQRM run (quick settings)."""

from symlearn.demo.registry import DemoContext
from symlearn.demo.rm_pipeline import PIPELINE


def test_rm_pipeline_infers_draws_and_trains(tmp_path):
    section = PIPELINE.run(DemoContext(tmp_path, seed=0, quick=True))
    assert section.figures["isomorphic_to_truth"] and section.figures["states"] == 2
    assert len(section.figures["dqrm_curve"]) == 2
    for name in ("rm/stack2.json", "rm/stack2.dot", "rm/stack2.md", "rm/stack2.prototypes.png",
                 "rm/stack2.labeling.json", "rm/stack2.prototypes/u0.png", "rm/stack2.prototypes/u1.png"):
        assert name in section.files and (tmp_path / name).exists()
    assert "![prototypes](rm/stack2.prototypes.png)" in section.markdown
