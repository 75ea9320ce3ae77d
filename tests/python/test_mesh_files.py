"""edgedeform.mesh_files: file vertex order kept, polygons fan-triangulated, clear errors."""

import os

import numpy as np
import pytest

from edgedeform.mesh_files import MeshFormatError, read_mesh, write_mesh
from _meshes import ALL, DATA, HEAD, source_counts

COUNTS = source_counts()


def _first_vertex_lines(path, k):
    """The first k vertex coordinates, parsed by hand from the file."""
    out = []
    with open(path) as fh:
        lines = [ln.split() for ln in fh if ln.strip() and not ln.startswith("#")]
    if path.suffix == ".obj":
        out = [list(map(float, ln[1:4])) for ln in lines if ln[0] == "v"][:k]
    else:  # OFF: header, counts, vertices
        out = [list(map(float, ln[:3])) for ln in lines[2:2 + k]]
    return np.array(out)


@pytest.mark.parametrize("name", ALL + (HEAD,))
def test_reads_test_meshes_in_file_order(name):
    V, F = read_mesh(DATA / name)
    assert (len(V), len(F)) == COUNTS[name]
    assert V.dtype == np.float64 and V.shape[1] == 3 and F.shape[1] == 3
    assert F.min() == 0 and F.max() == len(V) - 1
    np.testing.assert_array_equal(V[:50], _first_vertex_lines(DATA / name, 50))


@pytest.mark.parametrize("ext", [".obj", ".off", ".ply"])
def test_write_read_round_trip_is_exact(tmp_path, ext):
    V, F = read_mesh(DATA / "cgal_three_peaks.off")
    X = V * 1.0001 + 1e-7
    write_mesh(tmp_path / f"m{ext}", X, F)
    X2, F2 = read_mesh(tmp_path / f"m{ext}")
    np.testing.assert_array_equal(X2, X)
    np.testing.assert_array_equal(F2, F)
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"m{ext}"]   # no temp left
    umask = os.umask(0)
    os.umask(umask)
    assert (tmp_path / f"m{ext}").stat().st_mode & 0o777 == 0o666 & ~umask


def test_quads_and_polygons_fan_triangulated(tmp_path):
    p = tmp_path / "q.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nvt 0 0\n"
                 "f 1/1 2/1 3/1 4/1\nf 2 5 3\n")
    V, F = read_mesh(p)
    assert len(V) == 5
    assert sorted(map(tuple, F.tolist())) == [(0, 1, 2), (0, 2, 3), (1, 4, 2)]
    q = tmp_path / "p.off"
    q.write_text("OFF\n# pentagon\n5 1 0\n0 0 0\n1 0 0\n1.5 1 0\n0.5 1.5 0\n-0.5 1 0\n"
                 "5 0 1 2 3 4\n")
    V, F = read_mesh(q)
    assert F.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]]


@pytest.mark.parametrize("content, words", [
    ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "out of range"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n", "out of range"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "at least 3 corners"),
    ("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1: a vertex needs 3 coordinates"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//4 2 3\n", "normal index 4 out of range"),
])
def test_bad_obj_rejected(tmp_path, content, words):
    p = tmp_path / "bad.obj"
    p.write_text(content)
    with pytest.raises(MeshFormatError, match=words):
        read_mesh(p)


def test_relative_obj_indices_resolve(tmp_path):
    p = tmp_path / "rel.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf 2 -1 3\n")
    V, F = read_mesh(p)
    assert F.tolist() == [[0, 1, 2], [1, 3, 2]]


def test_bad_paths(tmp_path):
    with pytest.raises(MeshFormatError, match="unsupported"):
        read_mesh(tmp_path / "mesh.stl")
    with pytest.raises(FileNotFoundError):
        read_mesh(tmp_path / "missing.obj")
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(MeshFormatError):
        read_mesh(bad)
