"""docs/design.md's "Where is…" table points at files and names that exist: each row's files
are in the repository and each name it says to look for is written in one of them (as a
C++'s `Deformer::solve` as written, Python's `Binding.sync` as a class with that method). A rename that
forgets the table fails here."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DESIGN = ROOT / "docs" / "design.md"
FIRST_QUESTIONS = 20   # the issue asked for the twenty things a newcomer asks first


def where_is_rows():
    text = DESIGN.read_text()
    start = text.index("**Where is…**")
    rows = []
    for line in text[start:].splitlines()[1:]:
        if rows and not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) != 3 or cells[0] in ("where is…", "---"):
            continue
        rows.append((cells[0], re.findall(r"`([^`]+)`", cells[1]), re.findall(r"`([^`]+)`", cells[2])))
    return rows


def test_the_table_answers_the_first_questions():
    rows = where_is_rows()
    assert len(rows) >= FIRST_QUESTIONS, [q for q, _, _ in rows]
    assert all(files and names for _, files, names in rows), rows


@pytest.mark.parametrize("question,files,names", where_is_rows(), ids=lambda v: v if isinstance(v, str) else None)
def test_each_name_is_in_its_files(question, files, names):
    missing_files = [f for f in files if not (ROOT / f).is_file()]
    assert not missing_files, f"{question}: no such file {missing_files}"
    text = "\n".join((ROOT / f).read_text() for f in files)
    for name in names:
        assert re.search(pattern(name), text), f"{question}: {name} is not in {', '.join(files)}"


def pattern(name):
    """C++'s `Class::member` as written; Python's `Class.method` as a class with that
    method defined; anything else as a whole word (a file name, a function, a constant)."""
    if "::" in name or re.search(r"\.(sh|py|cmake)$", name):
        return re.escape(name)
    if "." in name:
        owner, member = name.split(".")
        return rf"class {owner}\b[\s\S]*def {member}\b"
    return r"(?<![\w.])" + re.escape(name) + r"(?!\w)"
