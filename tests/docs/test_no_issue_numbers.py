"""Code comments and docs point to decision records (docs/decisions/), not to issue numbers:
an issue is closed and gone for the next engineer, a record stays beside the code. The
records themselves may say which issue they came from. Pure Python, no build."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("addon", "bench", "blend_samples", "cmake", "demo", "docs", "native", "scripts", "tests")
SUFFIXES = {".py", ".cpp", ".h", ".md", ".txt", ".cmake", ".sh", ".toml"}
ISSUE = re.compile(r"\bissues? #?\d+", re.I)


def files():
    yield from (ROOT / name for name in ("README.md", "CMakeLists.txt", "pyproject.toml"))
    for folder in FOLDERS:
        for path in (ROOT / folder).rglob("*"):
            rel = path.relative_to(ROOT).as_posix()
            if path.suffix in SUFFIXES and path.is_file() and not rel.startswith("docs/decisions/"):
                yield path


def test_no_issue_numbers_outside_the_decision_records():
    found = [f"{p.relative_to(ROOT)}:{n}: {line.strip()[:90]}"
             for p in files()
             for n, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
             if ISSUE.search(line)]
    assert not found, "point to a decision record instead:\n" + "\n".join(found)
