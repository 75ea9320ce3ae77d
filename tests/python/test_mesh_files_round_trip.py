"""Only positions change (docs/api.md, "Command line"): faces (quads, n-gons), texture coordinates, colours,
groups, materials, comments and the storage format survive a write with new positions;
normals are recomputed from the deformed faces. OBJ, OFF, PLY ASCII and binary."""

import numpy as np
import pytest

from edgedeform.mesh_files import read_mesh_file
from _meshes import rotation

R = rotation((1.0, 2.0, 0.5), 40.0)
SHIFT = np.array([0.3, -1.25, 2.0])


def _mesh(nx=4, ny=3):
    """A flat (z = 0) grid of nx x ny vertices as quads, and a pentagon on its +x side; all
    faces counter-clockwise seen from +z."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    V = np.stack([i.ravel() / (nx - 1), j.ravel() / (ny - 1), np.zeros(nx * ny)], axis=1)
    quads = [[b * nx + a, b * nx + a + 1, (b + 1) * nx + a + 1, (b + 1) * nx + a]
             for b in range(ny - 1) for a in range(nx - 1)]
    n = len(V)
    V = np.vstack([V, [[1.5, 0.25, 0.0], [1.75, 0.5, 0.0], [1.5, 0.75, 0.0]]])
    pentagon = [nx - 1, n, n + 1, n + 2, 2 * nx - 1]  # (1,0) .. (1,0.5)
    return V, quads + [pentagon]


def _moved(V):
    return V @ R.T + SHIFT


def _lines_except(text, keys):
    return [ln for ln in text.splitlines() if not ln.split() or ln.split()[0] not in keys]


# ---- OBJ ------------------------------------------------------------------------------

def _obj_text(V, faces):
    out = ["# made by the test\n", "mtllib test.mtl\n", "o thing\n"]
    out += [f"v {float(x)!r} {float(y)!r} {float(z)!r} 0.5 0.25 1\n" for x, y, z in V]   # with vertex colours
    out += [f"vt {float(u)!r} {float(v)!r}\n" for u, v, _ in V]
    out += ["vn 0 0 1\n", "vn 0 0 1\n"]           # one shared by the quads, one by the pentagon
    out += ["g quads\n", "usemtl red\n", "s 1\n"]
    for f in faces[:-1]:
        out.append("f " + " ".join(f"{k + 1}/{k + 1}/1" for k in f) + "\n")
    out += ["g pentagon\n", "usemtl blue\n", "s off\n"]
    out.append("f " + " ".join(f"{k + 1}/{k + 1}/2" for k in faces[-1]) + "\n")
    out.append("l 1 2\n")
    return "".join(out)


def test_obj_keeps_everything_but_positions_and_normals(tmp_path):
    V, faces = _mesh()
    src = tmp_path / "in.obj"
    src.write_text(_obj_text(V, faces))
    mesh = read_mesh_file(src)
    assert mesh.face_sizes.tolist() == [4] * 6 + [5]
    assert len(mesh.triangles) == 6 * 2 + 3
    X = _moved(V)
    notes = mesh.write(tmp_path / "out.obj", X)
    assert notes == ["normals (vn) recomputed from the deformed faces"]
    before, after = src.read_text(), (tmp_path / "out.obj").read_text()
    assert _lines_except(after, ("v", "vn")) == _lines_except(before, ("v", "vn"))
    v_lines = [ln.split() for ln in after.splitlines() if ln.startswith("v ")]
    np.testing.assert_array_equal(np.array([[float(t) for t in ln[1:4]] for ln in v_lines]), X)
    assert all(ln[4:] == ["0.5", "0.25", "1"] for ln in v_lines)
    vn = np.array([[float(t) for t in ln.split()[1:4]] for ln in after.splitlines()
                   if ln.startswith("vn ")])
    np.testing.assert_allclose(vn, np.tile(R @ [0.0, 0.0, 1.0], (2, 1)), atol=1e-12)
    again = read_mesh_file(tmp_path / "out.obj")
    np.testing.assert_array_equal(again.vertices, X)
    np.testing.assert_array_equal(again.face_corners, mesh.face_corners)


def test_obj_split_normals_stay_split(tmp_path):
    """Two faces with their own vn (a hard edge) fold apart: each vn follows its face."""
    src = tmp_path / "hinge.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 -1 0\nvn 0 0 1\nvn 0 0 1\n"
                   "f 1//1 2//1 3//1\nf 1//2 4//2 2//2\n")
    mesh = read_mesh_file(src)
    X = mesh.vertices.copy()
    X[3] = [0.0, 0.0, -1.0]  # fold the second face down: its normal turns from +z to -y
    mesh.write(tmp_path / "out.obj", X)
    vn = [ln.split()[1:] for ln in (tmp_path / "out.obj").read_text().splitlines()
          if ln.startswith("vn")]
    np.testing.assert_allclose(np.array(vn, dtype=float), [[0, 0, 1], [0, -1, 0]], atol=1e-12)


# ---- OFF ------------------------------------------------------------------------------

def test_off_keeps_polygons_colours_and_comments(tmp_path):
    V, faces = _mesh()
    lines = ["COFF\n", "# a comment\n", f"{len(V)} {len(faces)} 0\n"]
    lines += [f"{float(x)!r} {float(y)!r} {float(z)!r} 255 128 0 255\n" for x, y, z in V]
    lines += [f"{len(f)} " + " ".join(map(str, f)) + " 0.1 0.2 0.3\n" for f in faces]
    src = tmp_path / "in.off"
    src.write_text("".join(lines))
    mesh = read_mesh_file(src)
    X = _moved(V)
    assert mesh.write(tmp_path / "out.off", X) == []
    out = (tmp_path / "out.off").read_text().splitlines(keepends=True)
    assert out[:3] == lines[:3] and out[3 + len(V):] == lines[3 + len(V):]
    vertex = [ln.split() for ln in out[3:3 + len(V)]]
    np.testing.assert_array_equal(np.array([t[:3] for t in vertex], dtype=float), X)
    assert all(t[3:] == ["255", "128", "0", "255"] for t in vertex)


def test_noff_normals_recomputed(tmp_path):
    V, faces = _mesh()
    lines = ["NOFF\n", f"{len(V)} {len(faces)} 0\n"]
    lines += [f"{float(x)!r} {float(y)!r} {float(z)!r} 0 0 1\n" for x, y, z in V]
    lines += [f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces]
    src = tmp_path / "in.off"
    src.write_text("".join(lines))
    X = _moved(V)
    notes = read_mesh_file(src).write(tmp_path / "out.off", X)
    assert notes == ["vertex normals (NOFF) recomputed from the deformed faces"]
    rows = np.array([ln.split() for ln in (tmp_path / "out.off").read_text().splitlines()[2:2 + len(V)]],
                    dtype=float)
    np.testing.assert_array_equal(rows[:, :3], X)
    np.testing.assert_allclose(rows[:, 3:], np.tile(R @ [0.0, 0.0, 1.0], (len(V), 1)), atol=1e-12)


# ---- PLY ------------------------------------------------------------------------------

def _ply_bytes(V, faces, fmt, xyz="float"):
    """Vertex x y z (xyz type), nx ny nz, uchar colour, float u v; polygon faces with a uchar
    flag each; and an extra element after the faces."""
    header = (f"ply\nformat {fmt} 1.0\ncomment test mesh\n"
              f"element vertex {len(V)}\nproperty {xyz} x\nproperty {xyz} y\nproperty {xyz} z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              "property float u\nproperty float v\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
              "element material 1\nproperty float shine\nend_header\n").encode()
    colour = np.array([[10 * k % 256, 20, 30] for k in range(len(V))])
    if fmt == "ascii":
        body = "".join(f"{float(x)!r} {float(y)!r} {float(z)!r} 0 0 1 {r} {g} {b} {float(x)!r} {float(y)!r}\n"
                       for (x, y, z), (r, g, b) in zip(V, colour))
        body += "".join(f"{len(f)} " + " ".join(map(str, f)) + f" {k}\n" for k, f in enumerate(faces))
        body += "0.75\n"
        return header + body.encode()
    o = "<" if fmt == "binary_little_endian" else ">"
    t = {"float": "f4", "double": "f8"}[xyz]
    rows = np.zeros(len(V), dtype=[("x", o + t), ("y", o + t), ("z", o + t), ("nx", o + "f4"),
                                   ("ny", o + "f4"), ("nz", o + "f4"), ("red", "u1"), ("green", "u1"),
                                   ("blue", "u1"), ("u", o + "f4"), ("v", o + "f4")])
    for k, n in enumerate("xyz"):
        rows[n] = V[:, k]
    rows["nz"] = 1.0
    rows["red"], rows["green"], rows["blue"] = colour.T
    rows["u"], rows["v"] = V[:, 0], V[:, 1]
    body = rows.tobytes()
    for k, f in enumerate(faces):
        body += np.array([len(f)], "u1").tobytes() + np.array(f, o + "i4").tobytes() + bytes([k])
    return header + body + np.array([0.75], o + "f4").tobytes()


@pytest.mark.parametrize("fmt, xyz", [("ascii", "float"), ("binary_little_endian", "float"),
                                      ("binary_big_endian", "double"),
                                      ("binary_little_endian", "double")])
def test_ply_keeps_format_properties_faces_and_elements(tmp_path, fmt, xyz):
    V, faces = _mesh()
    src = tmp_path / "in.ply"
    src.write_bytes(_ply_bytes(V, faces, fmt, xyz))
    mesh = read_mesh_file(src)
    assert mesh.face_sizes.tolist() == [4] * 6 + [5]
    X = _moved(V)
    notes = mesh.write(tmp_path / "out.ply", X)
    assert "vertex normals (nx, ny, nz) recomputed from the deformed faces" in notes
    assert ("positions stored as float32, the input's type" in notes) == (xyz == "float" and fmt != "ascii")
    # Expected: the same file written with the new positions and rotated normals.
    out = (tmp_path / "out.ply").read_bytes()
    again = read_mesh_file(tmp_path / "out.ply")
    tol = 1e-6 if xyz == "float" and fmt != "ascii" else 0.0
    np.testing.assert_allclose(again.vertices, X, atol=tol, rtol=0)
    np.testing.assert_array_equal(again.face_corners, mesh.face_corners)
    expected = _ply_bytes(X, faces, fmt, xyz)
    header_end = expected.index(b"end_header\n") + len(b"end_header\n")
    assert out[:header_end] == src.read_bytes()[:header_end]
    if fmt != "ascii":
        # byte-identical outside x, y, z, nx, ny, nz
        o = "<" if fmt == "binary_little_endian" else ">"
        dt = np.dtype([(n, o + ("f8" if xyz == "double" else "f4")) for n in "xyz"] +
                      [(n, o + "f4") for n in ("nx", "ny", "nz")] +
                      [("rgb", "u1", (3,)), ("uv", o + "f4", (2,))])
        got = np.frombuffer(out, dt, len(V), header_end)
        ref = np.frombuffer(src.read_bytes(), dt, len(V), header_end)
        np.testing.assert_array_equal(got["rgb"], ref["rgb"])
        np.testing.assert_array_equal(got["uv"], ref["uv"])
        normals = np.stack([got[n] for n in ("nx", "ny", "nz")], axis=1)
        tail = header_end + len(V) * dt.itemsize
        assert out[tail:] == src.read_bytes()[tail:]  # faces with flags, the material element
    else:
        rows = [ln.split() for ln in out[header_end:].decode().splitlines()]
        ref = [ln.split() for ln in src.read_bytes()[header_end:].decode().splitlines()]
        assert [r[6:] for r in rows[:len(V)]] == [r[6:] for r in ref[:len(V)]]
        assert rows[len(V):] == ref[len(V):]
        normals = np.array([r[3:6] for r in rows[:len(V)]], dtype=float)
    np.testing.assert_allclose(normals, np.tile(R @ [0.0, 0.0, 1.0], (len(V), 1)), atol=1e-6)


# ---- across formats ---------------------------------------------------------------------

def test_other_format_keeps_polygons_and_names_what_is_dropped(tmp_path):
    V, faces = _mesh()
    src = tmp_path / "in.obj"
    src.write_text(_obj_text(V, faces))
    X = _moved(V)
    notes = read_mesh_file(src).write(tmp_path / "out.ply", X)
    assert len(notes) == 1 and notes[0].startswith(".obj -> .ply: positions and faces written")
    for lost in ("texture coordinates (vt)", "normals (vn)", "materials", "groups"):
        assert lost in notes[0]
    again = read_mesh_file(tmp_path / "out.ply")
    np.testing.assert_array_equal(again.vertices, X)
    assert again.face_sizes.tolist() == [4] * 6 + [5]
