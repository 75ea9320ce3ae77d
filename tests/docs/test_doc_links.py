"""Every relative link in the repository's Markdown pages reaches a file or folder in the
repository, and every #anchor a heading on the page it names (GitHub's heading slugs).
Links to web pages (http:, https:, mailto:) are not followed. Every repository path a page
names in `code` (`bench/report.py`, `tests/cpp/test_<file>.cpp`) exists too; a file that has
since gone (the decision records name many) is named with where git keeps it, a
`git show <commit>:<path>` on the same page, which must resolve. The shared folder beside
the checkout (meshes, the paper, the research notes) is named `../shared/...`, never by an
absolute path or as if it were in the repository, and must exist where it is present. Pure
Python: no build (git for the history, when the checkout has it)."""

import functools
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# README.md, docs/ (the decision records included) and the pages beside the data they describe.
PAGES = sorted({ROOT / "README.md", *ROOT.glob("docs/**/*.md"), *ROOT.glob("blend_samples/*.md"),
                *ROOT.glob("bench/meshes/*.md"), *ROOT.glob("tests/data/*.md"),
                *ROOT.glob("demo/*.md")})

# [text](target) and ![alt](target), an optional "title" after the target; [name]: target
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$", re.M)
FENCE = re.compile(r"^(```|~~~).*?^\1", re.M | re.S)
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1", re.S)


def links(text):
    """The link targets of a Markdown text, code blocks and code spans left out."""
    text = CODE_SPAN.sub("", FENCE.sub("", text))
    return INLINE.findall(text) + REFERENCE.findall(text)


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    heading = re.sub(r"`|\*\*|__|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip()).lower()
    return re.sub(r"[^\w\- ]", "", heading).replace(" ", "-")


def anchors(page):
    """The anchors a page's headings give, numbered as GitHub numbers repeated ones."""
    seen, out = {}, set()
    for line in FENCE.sub("", page.read_text(encoding="utf-8")).splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            base = slug(m.group(1))
            n = seen.get(base, 0)
            seen[base] = n + 1
            out.add(base if n == 0 else f"{base}-{n}")
    out.update(re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", page.read_text(encoding="utf-8")))
    return out


def dead_links(page):
    """(target, reason) for each link of the page that does not resolve."""
    dead = []
    for target in links(page.read_text(encoding="utf-8")):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        resolved = (page.parent / path).resolve() if path else page
        if path.startswith("/"):
            dead.append((target, "absolute path: link relative to the page"))
        elif ROOT not in resolved.parents and resolved != ROOT:
            dead.append((target, "points outside the repository"))
        elif not resolved.exists():
            dead.append((target, "no such file or folder"))
        elif anchor and resolved.suffix == ".md" and anchor not in anchors(resolved):
            dead.append((target, f"no heading with anchor #{anchor} in {resolved.relative_to(ROOT)}"))
    return dead


# A path from the repository root, as pages write them in `code`.
REPO_PATH = re.compile(r"(?<![\w/.~-])((?:addon|bench|blend_samples|cmake|demo|docs|native|scripts|tests|\.ci|\.github)/"
                       r"[\w./<>*-]*[\w>*/])")
# What the repository makes but does not commit (.gitignore): named, never present in a clone.
MADE_NOT_COMMITTED = (re.compile(r"^bench/results/cache/"), re.compile(r"^blend_samples/[^/]+\.blend$"))


# Where a page says git keeps a file: `git show 8dba812:bench/bench_cold_start.py`.
GIT_SHOW = re.compile(r"git show ([0-9a-f]{7,40}):([\w./-]*\w)")
# A path into the shared folder, however written: ../shared/x, shared/x, /abs/shared/x.
SHARED = re.compile(r"(?<![\w.~/:-])((?:[\w.~-]*/)*shared/[\w./-]*[\w/])")


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)


@functools.lru_cache(maxsize=None)
def in_history(commit, path):
    """Whether git holds `path` at `commit`; True when it cannot tell (no git, or a shallow
    clone without that commit), so that only a checkout with the history judges."""
    if git("cat-file", "-e", f"{commit}:{path}").returncode == 0:
        return True
    known = git("cat-file", "-e", f"{commit}^{{commit}}").returncode == 0
    shallow = git("rev-parse", "--is-shallow-repository").stdout.strip() != "false"
    return not known and shallow


def shared_path_problem(path):
    """Why a path into the shared folder is written wrong or missing (None when fine)."""
    if not path.startswith("../shared/"):
        return "outside the repository: write it ../shared/... (relative to the checkout)"
    if (ROOT.parent / "shared").is_dir() and not (ROOT / path).exists():
        return "no such file in ../shared"
    return None


def missing_paths(page):
    """The repository paths the page names in code spans that match no file or folder
    (a <placeholder> or * matches any name) and that the page does not say git keeps; the
    `git show` lines that do not resolve; and each path into the shared folder written
    other than ../shared/... or missing there (anywhere on the page, code or not)."""
    text = page.read_text(encoding="utf-8")
    kept = {path for _, path in GIT_SHOW.findall(text)}
    missing = [f"{path} ({why})" for path in SHARED.findall(text)
               if (why := shared_path_problem(path))]
    for span in re.findall(r"`([^`\n]+)`", FENCE.sub("", text)):
        missing += [f"{commit}:{path}" for commit, path in GIT_SHOW.findall(span)
                    if not in_history(commit, path)]
        for path in REPO_PATH.findall(GIT_SHOW.sub("", span)):
            if path in kept or any(p.search(path) for p in MADE_NOT_COMMITTED):
                continue
            pattern = re.sub(r"<[^>]*>", "*", path).rstrip("/")
            found = any(ROOT.glob(pattern)) if "*" in pattern else (ROOT / pattern).exists()
            if not found:
                missing.append(path)
    return missing


def test_the_pages_are_found():
    names = {p.relative_to(ROOT).as_posix() for p in PAGES}
    assert {"README.md", "docs/design.md", "docs/addon.md", "docs/decisions/README.md"} <= names


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_relative_links_resolve(page):
    dead = dead_links(page)
    assert not dead, f"{page.relative_to(ROOT)}: " + "; ".join(f"({t}) {why}" for t, why in dead)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_named_repository_paths_exist(page):
    missing = missing_paths(page)
    assert not missing, f"{page.relative_to(ROOT)} names what the repository does not hold: {missing}"


def test_the_check_finds_a_dead_link(tmp_path, monkeypatch):
    """The checker itself: a missing file, a missing anchor and a way out are each reported;
    a good link, a web link and a link inside a code span are not."""
    docs = ROOT / "docs"
    page = docs / "design.md"
    text = ("[ok](addon.md) [ok2](decisions/README.md) [web](https://example.org/x.md) "
            "`[code](nowhere.md)` [gone](no_such_page.md) [anchor](addon.md#no-such-heading) "
            "[out](../../elsewhere/DESIGN.md)\n")
    monkeypatch.setattr(Path, "read_text", lambda self, **kw: text if self == page else
                        Path.read_bytes(self).decode("utf-8"))
    found = [t for t, _ in dead_links(page)]
    assert found == ["no_such_page.md", "addon.md#no-such-heading", "../../elsewhere/DESIGN.md"]


def test_the_check_finds_a_path_that_is_gone(monkeypatch):
    """A named path that is not there is reported; one that is, a placeholder that matches
    files, and what the repository makes but does not commit are not."""
    page = ROOT / "docs" / "design.md"
    text = ("`bench/report.py`, `tests/cpp/test_<file>.cpp`, `bench/results/cache/meshes/`, "
            "`PYTHONPATH=build/python python3 bench/no_such_script.py`, `docs/gone/`, "
            "`bash .ci/run`, `.github/workflows/no_such.yml`\n")
    monkeypatch.setattr(Path, "read_text", lambda self, **kw: text if self == page else
                        Path.read_bytes(self).decode("utf-8"))
    assert missing_paths(page) == ["bench/no_such_script.py", "docs/gone/", ".github/workflows/no_such.yml"]


def history_has(commit):
    return git("cat-file", "-e", f"{commit}^{{commit}}").returncode == 0


@pytest.mark.skipif(not history_has("8dba812"), reason="the checkout has no git history")
def test_the_check_wants_a_gone_file_kept_in_git(monkeypatch):
    """A file that has gone may be named only with the `git show` that brings it back, and
    that `git show` must resolve in the history."""
    page = ROOT / "docs" / "decisions" / "README.md"
    text = ("`bench/bench_cold_start.py` removed (`git show 8dba812:bench/bench_cold_start.py`); "
            "`bench/bench_live_modes.py` gone; `git show 8dba812:bench/no_such_script.py`\n")
    monkeypatch.setattr(Path, "read_text", lambda self, **kw: text if self == page else
                        Path.read_bytes(self).decode("utf-8"))
    assert missing_paths(page) == ["bench/bench_live_modes.py", "8dba812:bench/no_such_script.py"]


@pytest.mark.parametrize("shared_there", [True, False])
def test_the_check_wants_the_shared_folder_written_relative(tmp_path, monkeypatch, shared_there):
    """The research path record 0029 once cited as if in the repository
    (`shared/research/direct-newton.md`) and an absolute one are reported; ../shared/... is
    checked where ../shared is beside the checkout, and trusted where it is not; a web
    address with /shared/ in it is not a path."""
    checkout = tmp_path / "checkout"
    (checkout / "docs").mkdir(parents=True)
    if shared_there:
        (tmp_path / "shared" / "research").mkdir(parents=True)
        (tmp_path / "shared" / "research" / "direct-newton.md").write_text("notes")
    page = checkout / "docs" / "x.md"
    page.write_text("The plan (DESIGN §2, `shared/research/direct-newton.md`); see "
                    "`../shared/research/direct-newton.md`, /work/shared/DESIGN.md, "
                    "`../shared/no_such.md` and https://example.org/shared/page.\n")
    monkeypatch.setattr(sys.modules[__name__], "ROOT", checkout)
    found = [m.split(" (")[0] for m in missing_paths(page)]
    assert found == ["shared/research/direct-newton.md", "/work/shared/DESIGN.md"] + (
        ["../shared/no_such.md"] if shared_there else [])


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
