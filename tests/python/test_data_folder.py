"""tests/data is the one copy of the repository's small real meshes: its SOURCES.md has a row
for each file and a file for each row, and no mesh is committed twice (the sample scenes and
the benchmarks read these files, they do not carry copies)."""

import hashlib
import lzma
import subprocess
from pathlib import Path

import pytest

from edgedeform.mesh_files import read_mesh
from _meshes import DATA, source_counts

ROOT = DATA.parents[1]
MESH_SUFFIXES = (".obj", ".off", ".ply")


def test_sources_lists_each_mesh_with_its_counts():
    files = sorted(p.name for p in DATA.iterdir() if p.suffix in MESH_SUFFIXES)
    rows = source_counts()
    assert sorted(rows) == files
    for name, counts in rows.items():
        V, F = read_mesh(DATA / name)
        assert (len(V), len(F)) == counts, name


def committed_meshes():
    """The mesh files git holds (compressed ones as NAME.xz)."""
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True,
                             check=True).stdout.decode()
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout: which files are committed is not known")
    return [p for p in out.split("\0") if p.removesuffix(".xz").endswith(MESH_SUFFIXES)]


def duplicates(paths, root=ROOT):
    """Groups of paths whose mesh bytes are equal (an .xz file compared by its content)."""
    by_hash = {}
    for rel in paths:
        data = (root / rel).read_bytes()
        if rel.endswith(".xz"):
            data = lzma.decompress(data)
        by_hash.setdefault(hashlib.sha256(data).hexdigest(), []).append(rel)
    return sorted(group for group in by_hash.values() if len(group) > 1)


def test_each_mesh_is_committed_once():
    paths = committed_meshes()
    assert "tests/data/cgal_dino.off" in paths
    assert duplicates(paths) == []


def test_the_check_finds_a_copy(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "m.off").write_bytes(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    (tmp_path / "b.off.xz").write_bytes(lzma.compress((tmp_path / "a" / "m.off").read_bytes()))
    (tmp_path / "c.obj").write_bytes(b"v 0 0 0\n")
    assert duplicates(["a/m.off", "b.off.xz", "c.obj"], tmp_path) == [["a/m.off", "b.off.xz"]]
