"""scripts/ci_times.py: docs/ci_times.md is what docs/ci_runs/ gives, and a scripts/test.sh
run's log and ctest's JUnit become a record. Pure Python, no build."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import ci_times  # noqa: E402

LOG = """kind full
started 2026-12-03 17:05 UTC
commit abc1234
load_start 1.50
phase install_deps 2100
phase configure 5300
phase build 300000
phase ctest 1200000
phase ctest_timing 15000
load_end 2.25
total 1522400
exit 1
"""

JUNIT = """<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="(empty)" tests="3">
 <testcase name="pytest_core" time="61.5" status="run">
  <properties><property name="cmake_labels" value="unit"/></properties></testcase>
 <testcase name="blender_bpy_4.5_venv" time="120.25" status="run">
  <properties><property name="cmake_labels" value="blender;bpy"/></properties>
  <failure message="Failed"/></testcase>
 <testcase name="demo_unit" time="2.0" status="notrun"><skipped message="skip"/></testcase>
</testsuite>
"""


def test_the_committed_page_is_up_to_date():
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "ci_times.py"), "--check"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_every_record_has_what_the_page_needs():
    for path in sorted((ROOT / "docs" / "ci_runs").glob("*.json")):
        rec = json.loads(path.read_text(encoding="utf-8"))
        for key in ("run", "what", "date", "commit", "machine", "conditions", "total_s", "source"):
            assert rec.get(key) is not None, (path.name, key)
        assert rec["run"] in ci_times.KINDS, path.name


def test_a_run_becomes_a_record_and_a_section(tmp_path, monkeypatch):
    build = tmp_path / "build"
    (build / "ci_times").mkdir(parents=True)
    (build / "ci_times" / "full.txt").write_text(LOG)
    (build / "ci_times" / "ctest.xml").write_text(JUNIT)
    runs = tmp_path / "runs"
    monkeypatch.setattr(ci_times, "RUNS", runs)
    path = ci_times.record(build, "full", "", "quiet")
    rec = json.loads(path.read_text())
    assert path.name == "2026-12-03-1705-full-abc1234.json"
    assert rec["total_s"] == 1522.4 and rec["exit"] == 1 and rec["load_1min"] == [1.5, 2.25]
    assert rec["phases"][2] == ["build", 300.0]
    assert rec["tests"] == {"entries": 3, "passed": 1, "failed": 1, "skipped": 1}
    assert ["bpy", 120.2, 1] in rec["labels"] and ["unit", 61.5, 1] in rec["labels"]
    assert rec["longest"][0] == ["blender_bpy_4.5_venv", 120.2, "failed"]
    page = ci_times.page(runs)
    assert "25 min 22 s" in page and "| build | 5 min 0 s | 20 % |" in page
    assert "1-minute load 1.5 at the start, 2.2 at the end" in page


def test_a_stale_page_is_caught(tmp_path):
    runs = tmp_path / "runs"
    shutil.copytree(ROOT / "docs" / "ci_runs", runs)
    page = tmp_path / "ci_times.md"
    assert ci_times.main(["--runs", str(runs), "--page", str(page)]) == 0
    assert ci_times.main(["--runs", str(runs), "--page", str(page), "--check"]) == 0
    next(runs.glob("*.json")).unlink()
    assert ci_times.main(["--runs", str(runs), "--page", str(page), "--check"]) == 1


def test_the_page_stays_within_the_docs_length_rule_however_many_runs_are_recorded(tmp_path):
    """Recording a run once pushed the page to 433 lines and failed the docs' 400-line rule."""
    runs = tmp_path / "runs"
    runs.mkdir()
    records = [json.loads(p.read_text(encoding="utf-8"))
               for p in sorted((ROOT / "docs" / "ci_runs").glob("*.json"))]
    for copy in range(6):
        for i, rec in enumerate(records):
            date = f"2027-{copy + 1:02d}-{i % 28 + 1:02d}T10:00:00Z"
            (runs / f"{copy}-{i}.json").write_text(json.dumps(rec | {"date": date}), encoding="utf-8")
    text = ci_times.page(runs)
    n_runs = 6 * len(records)
    assert text.count("\n") <= ci_times.PAGE_LINES
    assert f"{n_runs - ci_times.TABLE_ROWS} older runs: `docs/ci_runs/`." in text
    assert "## Earlier runs: pieces and notes" in text and "older records with pieces" in text
