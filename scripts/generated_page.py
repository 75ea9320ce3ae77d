"""Write a generated page, or (check) say whether the committed one is what its source gives:
the one rule of scripts/api_docs.py and scripts/ci_times.py (bench/report.py keeps its own)."""

from pathlib import Path


def write_or_check(path, text, check, remedy):
    """0 when written, or when checking and up to date; 1 (and what to run) when stale."""
    path = Path(path)
    if check:
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            print(f"{path} is out of date: run {remedy}")
            return 1
        return 0
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path} ({text.count(chr(10))} lines)")
    return 0
