"""Shared pytest hooks: report the recorded iteration counts after the run."""

import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _record  # noqa: E402


def pytest_configure(config):
    # Wall-clock bounds: ctest runs them apart (pytest_timing, label `timing`), after the
    # other tests and alone, so that a loaded machine does not fail the functional tiers.
    config.addinivalue_line("markers", "timing: asserts a wall-clock bound (ctest label timing)")


def pytest_terminal_summary(terminalreporter):
    if not _record.COUNTS:
        return
    tr = terminalreporter
    tr.section("iteration counts")
    tr.write_line(f"{'test':<22} {'mesh':<24} {'domain':<7} {'lambda':>6} {'iters':>6}  note")
    for c in _record.COUNTS:
        tr.write_line(f"{c['test']:<22} {c['mesh']:<24} {c['domain']:<7} {c['lambda']:>6} "
                      f"{str(c['iterations']):>6}  {c['note']}")
    out = os.environ.get("EDGEDEFORM_COUNTS_JSON")
    if out:
        Path(out).write_text(json.dumps(_record.COUNTS, indent=1))
