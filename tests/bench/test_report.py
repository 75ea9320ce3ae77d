"""bench/report.py: the benchmark pages are what bench/results gives, and each section
says when, where and how it was measured."""

import json
import re
import shutil
import subprocess
import sys

from _bench import BENCH

sys.path.insert(0, str(BENCH))
import report  # noqa: E402


def test_the_committed_pages_are_up_to_date():
    proc = subprocess.run([sys.executable, str(BENCH / "report.py"), "--check"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_every_section_has_date_machine_command_and_a_table():
    for name in report.PAGES:
        text = report.page(name, BENCH / "results")
        sections = re.split(r"^## ", text, flags=re.M)[1:]
        assert len(sections) == len(report.PAGES[name][1])
        for s in sections:
            assert "Not measured" not in s, s[:200]
            assert re.search(r"\*Date \d{4}-\d\d-\d\d \d\d:\d\d UTC; machine .+Command: ", s), s[:300]
            assert "\n|---" in s, s[:200]
        assert text.count("\n") < 400, f"{name}: {text.count(chr(10))} lines"


def test_a_missing_result_is_said_and_a_stale_page_is_caught(tmp_path):
    results = tmp_path / "results"
    shutil.copytree(BENCH / "results", results)
    (results / "soft_modes_d3.json").unlink()
    docs = tmp_path / "docs"
    docs.mkdir()
    assert report.main(["--results", str(results), "--docs", str(docs)]) == 0
    text = (docs / "benchmarks_solver.md").read_text()
    assert "Not measured: `bench/results/soft_modes_d3.json` is missing" in text
    assert report.main(["--results", str(BENCH / "results"), "--docs", str(docs), "--check"]) == 1

