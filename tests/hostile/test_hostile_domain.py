"""A domain folder's background is a user's program: unbounded grounding stops at the limit."""

import sys
from pathlib import Path

from hostile import check

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
import warehouse_domain as wh  # noqa: E402


def test_recursive_background_in_a_domain_folder_stops_at_the_memory_limit(tmp_path):
    folder = wh.write_warehouse(tmp_path / "warehouse")
    background = folder / "bk.lp"
    background.write_text(background.read_text() + "\n% a typo that never ends\nn(1).\nn(X+1) :- n(X).\n")
    check(["domain", "check", folder, "--max-memory", "300"], cwd=tmp_path, timeout=60, memory_mb=1024,
          contains=["memory limit of 300 MB reached", "--max-memory"], max_rss_mb=600)


def _recursive_warehouse(tmp_path):
    folder = wh.write_warehouse(tmp_path / "warehouse", alarm_prob=0.0)
    background = folder / "bk.lp"
    background.write_text(background.read_text() + "\nn(1).\nn(X+1) :- n(X).\n")
    wh.expert_demonstrations(2, seed=0, alarm_prob=0.0).save(tmp_path / "demos.jsonl")
    return folder


def test_learn_spec_reads_a_domain_folder_within_the_memory_limit(tmp_path):
    folder = _recursive_warehouse(tmp_path)
    check(["learn", "spec", "--domain", folder, "--demos", "demos.jsonl", "--max-memory", "300"], cwd=tmp_path,
          timeout=60, memory_mb=1024, contains=["memory limit of 300 MB reached", "--max-memory"], max_rss_mb=600)


def test_learn_dnf_reads_a_domain_folder_within_the_memory_limit(tmp_path):
    folder = _recursive_warehouse(tmp_path)
    check(["learn", "dnf", "--domain", folder, "--demos", "demos.jsonl", "--max-memory", "300"], cwd=tmp_path,
          timeout=60, memory_mb=1024, contains=["memory limit of 300 MB reached", "--max-memory"], max_rss_mb=600)
