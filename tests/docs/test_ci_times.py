"""scripts/ci_times.py: docs/ci_times.md is what docs/ci_runs/ gives, and a scripts/test.sh
run's log and ctest's JUnit become a record. Pure Python, no build."""

import json
import re
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


def records_at(runs, kinds_and_dates):
    """Writes one record per (kind, date) into `runs`, copied from a committed one."""
    template = json.loads(next((ROOT / "docs" / "ci_runs").glob("*full*.json")).read_text(encoding="utf-8"))
    runs.mkdir(exist_ok=True)
    for kind, date in kinds_and_dates:
        rec = template | {"run": kind, "date": f"{date} 10:00 UTC"}
        (runs / f"{date}-{kind}.json").write_text(json.dumps(rec), encoding="utf-8")


def test_recording_keeps_the_newest_runs_and_the_newest_of_each_detailed_kind(tmp_path):
    """History is git's: a new record deletes those older than the newest KEEP, but keeps the
    newest quick run, which the page details and the README quotes, however old."""
    runs = tmp_path / "runs"
    records_at(runs, [("quick", "2027-01-01"), ("quick", "2027-01-02"), ("demo", "2027-01-03")]
               + [("full", f"2027-02-{day:02d}") for day in range(1, ci_times.KEEP + 2)])
    build = tmp_path / "build"
    (build / "ci_times").mkdir(parents=True)
    (build / "ci_times" / "full.txt").write_text(LOG.replace("2026-12-03", "2027-03-01"))
    assert ci_times.main(["--runs", str(runs), "--page", str(tmp_path / "page.md"),
                          "record", "--build", str(build), "--conditions", "quiet"]) == 0
    newest_full = [f"2027-02-{day:02d}-full.json" for day in range(ci_times.KEEP + 1, 2, -1)]
    assert sorted(p.name for p in runs.iterdir()) == sorted(
        ["2027-03-01-1705-full-abc1234.json", *newest_full, "2027-01-02-quick.json"])
    page = (tmp_path / "page.md").read_text()
    assert "## The fast tier (the newest measured run)" in page
    assert "`git log --stat -- docs/ci_runs`" in page


def test_the_page_stays_within_the_docs_length_rule():
    """The most the folder holds after a record (KEEP runs and an older quick one) fits the
    docs' 400-line rule; the committed folder holds no more than that."""
    committed = list((ROOT / "docs" / "ci_runs").glob("*.json"))
    assert len(committed) <= ci_times.KEEP + len(ci_times.FEATURED) - 1
    text = (ROOT / "docs" / "ci_times.md").read_text(encoding="utf-8")
    assert text.count("\n") <= 400


def readme_minutes():
    """The README's "the full run takes about N minutes and `--quick` about M minutes"."""
    text = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    m = re.search(r"full run takes about (\d+) minutes and `--quick` about (\d+) minutes", text)
    assert m, "README.md no longer states the test times in the words this test reads"
    return {"full": int(m.group(1)), "quick": int(m.group(2))}


def newest_with_windows_checks(runs):
    """The newest recorded full run that ran the `windows` label, as `.ci/run` does: the
    README's full time is "with the Windows checks under wine" (a Debian 13 root, or a
    run without wine, records a full run that is not what CI runs)."""
    return next(r for r in runs if r["run"] == "full"
                and any(label == "windows" for label, *_ in r.get("labels") or []))


def test_the_readme_states_the_recorded_times():
    """The README's rounded times are the newest recorded .ci/run's (the full run with the
    Windows checks) and the newest quick run's, within a minute."""
    runs = ci_times.load_runs(ROOT / "docs" / "ci_runs")
    newest = {"full": newest_with_windows_checks(runs), "quick": ci_times.newest_measured(runs, "quick")}
    for kind, minutes in readme_minutes().items():
        assert abs(newest[kind]["total_s"] / 60 - minutes) < 1, (kind, minutes, newest[kind]["file"])
