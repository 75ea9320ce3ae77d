"""No page in docs/ is longer than 400 lines: a longer one is split by topic. Checked here,
in the fast tier with the other documentation checks, so that a doc edit meets it where
people look after one (it sat in the benchmark pages' test, and a page one line over
reached CI)."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LIMIT = 400


def test_no_docs_page_is_longer_than_400_lines():
    long = {str(p.relative_to(ROOT)): n for p in sorted((ROOT / "docs").rglob("*.md"))
            if (n := p.read_text().count("\n")) > LIMIT}
    assert not long, f"pages over {LIMIT} lines: {long}"
