"""Triangle meshes from and to OBJ, OFF and PLY files, keeping the file's vertex order.

Reading goes through meshio (Debian python3-meshio 5.0). Two gaps of that version are
bridged here rather than worked around by the caller:
- its OBJ reader rejects files whose `vt`/`vn` counts differ from the `v` count (e.g.
  Spot); texture and normal lines carry nothing we need, so they are dropped before parsing;
- its OFF reader accepts only a bare `OFF` header (no COFF colours, no polygons); for
  those files a small OFF parser below takes over.
Quads and polygons are split into triangles by a fan from their first corner; vertex
indices never change. Point and line cells are ignored; any other cell type is an error.
"""

import io
import os
import tempfile

import numpy as np

SUPPORTED = (".obj", ".off", ".ply")


class MeshFormatError(ValueError):
    """The file cannot be read or written as a triangle mesh."""


def _ext(path):
    ext = os.path.splitext(str(path))[1].lower()
    if ext not in SUPPORTED:
        raise MeshFormatError(
            f"{path}: unsupported mesh format '{ext or '(none)'}' "
            f"(supported: {', '.join(SUPPORTED)})")
    return ext


def _fan(cells):
    """(k, s) polygons -> (k*(s-2), 3) triangles (v0, vi, vi+1)."""
    cells = np.asarray(cells, dtype=np.int64)
    s = cells.shape[1]
    if s < 3:
        raise MeshFormatError(f"a face has {s} corners")
    parts = [np.stack([cells[:, 0], cells[:, i], cells[:, i + 1]], axis=1)
             for i in range(1, s - 1)]
    # Keep polygon order: all triangles of polygon 0, then of polygon 1, ...
    return np.stack(parts, axis=1).reshape(-1, 3)


def _faces_from_cells(path, cell_blocks):
    tris = []
    for ctype, data in cell_blocks:
        if ctype in ("vertex", "line"):
            continue
        if ctype == "triangle":
            tris.append(np.asarray(data, dtype=np.int64).reshape(-1, 3))
        elif ctype in ("quad", "polygon") or ctype.startswith("polygon"):
            tris.append(_fan(data))
        else:
            raise MeshFormatError(
                f"{path}: cell type '{ctype}' is not a surface polygon")
    if not tris:
        raise MeshFormatError(f"{path}: no faces")
    return np.concatenate(tris, axis=0)


def _check(path, V, F):
    V = np.asarray(V, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] < 3:
        raise MeshFormatError(f"{path}: vertices need 3 coordinates, got shape {V.shape}")
    V = np.ascontiguousarray(V[:, :3])
    if len(V) == 0:
        raise MeshFormatError(f"{path}: no vertices")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise MeshFormatError(
            f"{path}: face index out of range [0, {len(V)}) "
            f"(min {F.min()}, max {F.max()}; relative OBJ indices are not supported)")
    return V, np.ascontiguousarray(F, dtype=np.int64)


def _read_obj(path):
    from meshio.obj import _obj  # read_buffer is not re-exported
    keep = []
    with open(path, "r", encoding="utf-8", errors="replace") as fh:
        for line in fh:
            head = line.lstrip()[:3]
            if head.startswith(("vt", "vn", "vp")):
                continue
            keep.append(line)
    try:
        mesh = _obj.read_buffer(io.StringIO("".join(keep)))
    except (ValueError, IndexError) as exc:
        raise MeshFormatError(f"{path}: cannot parse OBJ ({exc})") from None
    return mesh.points, [(c.type, c.data) for c in mesh.cells]


def _read_off_text(path):
    """OFF / COFF / NOFF / CNOFF with comments, colours and polygons."""
    with open(path, "r", encoding="utf-8", errors="replace") as fh:
        lines = [ln.split("#", 1)[0].split() for ln in fh]
    tokens = [t for t in lines if t]
    if not tokens or not tokens[0][0].upper().endswith("OFF"):
        raise MeshFormatError(f"{path}: missing OFF header")
    head = tokens[0][1:]
    rows = tokens[1:]
    if not head:  # counts on their own line
        if not rows:
            raise MeshFormatError(f"{path}: missing vertex/face counts")
        head, rows = rows[0], rows[1:]
    try:
        nv, nf = int(head[0]), int(head[1])
        if len(rows) < nv + nf:
            raise MeshFormatError(f"{path}: expected {nv} vertices and {nf} faces, "
                                  f"file has {len(rows)} data lines")
        V = np.array([[float(x) for x in r[:3]] for r in rows[:nv]])
        groups = {}
        for r in rows[nv:nv + nf]:
            k = int(r[0])
            groups.setdefault(k, []).append([int(x) for x in r[1:1 + k]])
    except (ValueError, IndexError) as exc:
        raise MeshFormatError(f"{path}: cannot parse OFF ({exc})") from None
    if V.shape != (nv, 3):
        raise MeshFormatError(f"{path}: a vertex line has fewer than 3 coordinates")
    blocks = []
    for k, faces in groups.items():
        if any(len(f) != k for f in faces):
            raise MeshFormatError(f"{path}: a face line is shorter than its corner count")
        blocks.append(("triangle" if k == 3 else "polygon", np.array(faces).reshape(-1, k)))
    # Order of faces across groups is irrelevant to the deformation; vertices keep theirs.
    return V, blocks


def _read_off(path):
    from meshio import off  # the format's reader itself: meshio.read prints its errors
    try:
        mesh = off.read(path)
        return mesh.points, [(c.type, c.data) for c in mesh.cells]
    except Exception:  # meshio 5.0 refuses COFF, polygons, odd spacing: parse it here
        return _read_off_text(path)


def _read_ply(path):
    from meshio import ply
    try:
        mesh = ply.read(path)
    except Exception as exc:
        raise MeshFormatError(f"{path}: cannot parse PLY ({exc})") from None
    return mesh.points, [(c.type, c.data) for c in mesh.cells]


def read_mesh(path):
    """Read a triangle mesh.

    @return V (n,3) float64 in file order, F (m,3) int64 (polygons fan-triangulated).
    @raise MeshFormatError (a ValueError) for unsupported or malformed files,
           FileNotFoundError when the file is missing.
    """
    path = str(path)
    ext = _ext(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such file")
    points, blocks = {".obj": _read_obj, ".off": _read_off, ".ply": _read_ply}[ext](path)
    F = _faces_from_cells(path, blocks)
    return _check(path, points, F)


def write_mesh(path, V, F):
    """Write V (n,3), F (m,3) with the vertex order unchanged.

    The file appears atomically: written to a temporary file next to it, then renamed,
    so that a failure never leaves a partial mesh behind.
    """
    import meshio
    path = str(path)
    ext = _ext(path)
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    if V.ndim != 2 or V.shape[1] != 3 or F.ndim != 2 or F.shape[1] != 3:
        raise MeshFormatError(f"write_mesh: need V (n,3) and F (m,3), got {V.shape}, {F.shape}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{path}: folder {folder} does not exist")
    fd, tmp = tempfile.mkstemp(suffix=ext, prefix=".edgedeform-", dir=folder)
    os.close(fd)
    try:
        # PLY has no 64-bit integers (meshio would warn and cast)
        cells = F.astype(np.int32) if ext == ".ply" else F
        meshio.write(tmp, meshio.Mesh(V, [("triangle", cells)]), file_format=ext[1:])
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
