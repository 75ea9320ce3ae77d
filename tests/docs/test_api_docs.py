"""docs/api.md's generated blocks are what the code gives (scripts/api_docs.py): the
synopsis and member tables from help(), the command line's tables from its parser and
report fields. Needs the built package (PYTHONPATH=build/python)."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import api_docs  # noqa: E402
import edgedeform as ed  # noqa: E402


def test_the_committed_page_is_up_to_date():
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "api_docs.py"), "--check"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_a_stale_block_is_caught(tmp_path):
    page = tmp_path / "api.md"
    text = api_docs.PAGE.read_text(encoding="utf-8")
    page.write_text(text.replace("max_iterations=2000", "max_iterations=1000"), encoding="utf-8")
    assert api_docs.main(["--page", str(page), "--check"]) == 1
    assert api_docs.main(["--page", str(page)]) == 0
    assert page.read_text(encoding="utf-8") == text


def test_a_missing_block_is_an_error(tmp_path):
    page = tmp_path / "api.md"
    page.write_text(api_docs.PAGE.read_text(encoding="utf-8").replace(
        api_docs.END.format(name="cli-report"), ""), encoding="utf-8")
    with pytest.raises(SystemExit, match="cli-report"):
        api_docs.main(["--page", str(page), "--check"])


def test_every_public_name_is_on_the_page():
    """Every name the package exports, every Deformer, SolveResult and Welding member, and
    every key of the command line's report appear in docs/api.md."""
    text = api_docs.PAGE.read_text(encoding="utf-8")
    names = list(ed.__all__)
    for cls in (ed.Deformer, ed.SolveResult, ed.Welding):
        names += api_docs.public(cls)
    from edgedeform import cli
    names += list(cli.REPORT_FIELDS)
    missing = [n for n in names if f"`{n}" not in text and f"{n}(" not in text and f".{n}" not in text]
    assert not missing, missing


def test_the_synopsis_shows_every_solve_default():
    block = api_docs.synopsis(ed)
    for name, value in ed.SOLVE_DEFAULTS.items():
        assert f"{name}={value!r}" in block, name
