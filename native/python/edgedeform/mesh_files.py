"""Mesh files (OBJ, OFF, PLY) in and out, keeping everything but the positions.

    mesh = read_mesh_file("in.obj")        # mesh.vertices (n,3), mesh.triangles (m,3)
    notes = mesh.write("out.obj", X)       # only the positions change

The solver needs triangles; the file keeps its own faces. `triangles` is a fan of every
polygon from its first corner, with the file's vertex indices unchanged. Writing to the
same format rewrites the input with new positions: quads and n-gons, texture coordinates,
colours, groups, materials, comments and the storage format stay as they were, and normals
are recomputed from the deformed faces (the returned notes say so). Writing to another
format keeps positions and polygons; the notes name what that format cannot carry.
Files appear atomically: a failed or interrupted write leaves no partial file.

The parsers are this package's own (obj_format, off_format, ply_format; record 0060 says
why). They trust no declared count, read a leading UTF-8 byte-order mark (and write it
back), and refuse a bad file with MeshFormatError naming the file, the line and the
problem (docs/robustness.md).
"""

import os
import tempfile

import numpy as np

from . import obj_format, off_format, ply_format
from .format_error import MeshFormatError
from .polygons import fan_triangles

SUPPORTED = (".obj", ".off", ".ply")
_FORMATS = {".obj": obj_format, ".off": off_format, ".ply": ply_format}
BOM = b"\xef\xbb\xbf"   # UTF-8's byte-order mark, which some Windows tools write first

__all__ = ["MeshFile", "MeshFormatError", "SUPPORTED", "check_extension", "parse_mesh", "read_mesh",
           "read_mesh_file", "write_mesh"]


def check_extension(path):
    """The lower-case extension of `path`; MeshFormatError if it is not a supported format."""
    ext = os.path.splitext(str(path))[1].lower()
    if ext not in SUPPORTED:
        raise MeshFormatError(
            f"{path}: unsupported mesh format '{ext or '(none)'}' "
            f"(supported: {', '.join(SUPPORTED)})")
    return ext


class MeshFile:
    """A mesh as read from a file: positions, polygons, and the file to write back."""

    def __init__(self, path, ext, source, vertices, bom=b""):
        self.path, self.ext, self._source = path, ext, source
        self._bom = bom                                         # written back in front
        self.vertices = vertices                                # (n,3) float64, file order
        self.face_sizes = source.sizes                          # (k,) corners per face
        self.face_corners = source.corners                      # (sum sizes,) vertex indices
        self.triangles = fan_triangles(source.sizes, source.corners)  # (m,3) int64

    def write(self, path, positions):
        """Write `positions` (n,3) with this file's faces and data. Returns notes (list of
        str) on what was recomputed or could not be carried into the output format."""
        path = str(path)
        content, notes = self.encode(check_extension(path), positions)
        _write_atomically(path, content)
        return notes

    def encode(self, ext, positions):
        """(the bytes of a file of format `ext` with `positions`, notes) without writing it."""
        X = np.asarray(positions, dtype=np.float64)
        if X.shape != self.vertices.shape:
            raise MeshFormatError(f"write: positions {X.shape}, the mesh has {self.vertices.shape}")
        if ext == self.ext:
            content, notes = self._source.rewrite(X)
            return self._bom + _bytes(content), notes
        lost = sorted(self._source.has)
        notes = [f"{self.ext} -> {ext}: positions and faces written; not carried over: "
                 f"{', '.join(lost)}"] if lost else []
        return _bytes(_FORMATS[ext].write_plain(X, self.face_sizes, self.face_corners)), notes


def read_mesh_file(path):
    """Read OBJ, OFF (text) or PLY (ASCII or binary).

    @raise MeshFormatError (a ValueError) naming the file, the line and the problem,
           FileNotFoundError when the file is missing.
    """
    path = str(path)
    ext = check_extension(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such file")
    with open(path, "rb") as fh:
        return parse_mesh(fh.read(), ext, path)


def parse_mesh(data, ext, path):
    """A MeshFile from the bytes `data` of a file with extension `ext` (".obj", ".off",
    ".ply"); `path` names it in errors and is where it was read from. MeshFormatError as
    read_mesh_file."""
    bom = BOM if data.startswith(BOM) else b""
    data = data[len(bom):]
    try:
        # Latin-1 maps each byte to one character: text formats round-trip byte for byte.
        source, V = _FORMATS[ext].read(data if ext == ".ply" else data.decode("latin-1"))
    except MeshFormatError as exc:
        raise MeshFormatError(f"{path}: {ext[1:].upper()} {exc}") from None
    if len(V) == 0:
        raise MeshFormatError(f"{path}: no vertices")
    if len(source.sizes) == 0:
        raise MeshFormatError(f"{path}: no faces")
    c = source.corners
    if c.min() < 0 or c.max() >= len(V):
        raise MeshFormatError(f"{path}: face index out of range [0, {len(V)}) "
                              f"(min {c.min()}, max {c.max()})")
    finite = np.isfinite(V).all(axis=1)
    if not finite.all():
        k = int(np.argmin(finite))
        raise MeshFormatError(f"{path}: vertex {k} (0-based, in file order) has a coordinate that is "
                              f"not finite: {tuple(float(x) for x in V[k])}")
    return MeshFile(path, ext, source, np.ascontiguousarray(V, dtype=np.float64), bom)


def read_mesh(path):
    """(V (n,3) float64 in file order, F (m,3) int64 fan triangles) of a mesh file."""
    mesh = read_mesh_file(path)
    return mesh.vertices, mesh.triangles


def write_mesh(path, V, F):
    """Write a new triangle mesh V (n,3), F (m,3), vertex order unchanged, atomically."""
    path = str(path)
    ext = check_extension(path)
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    if V.ndim != 2 or V.shape[1] != 3 or F.ndim != 2 or F.shape[1] != 3:
        raise MeshFormatError(f"write_mesh: need V (n,3) and F (m,3), got {V.shape}, {F.shape}")
    _write_atomically(path, _FORMATS[ext].write_plain(V, np.full(len(F), 3), F.reshape(-1)))


def _bytes(content):
    return content if isinstance(content, bytes) else content.encode("latin-1")


def _write_atomically(path, content):
    """Write to a temporary file next to `path`, then rename it into place. An OSError
    names `path`, never the temporary file."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{path}: folder {folder} does not exist")
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(suffix=os.path.splitext(path)[1], prefix=".edgedeform-", dir=folder)
        with os.fdopen(fd, "wb") as fh:
            fh.write(_bytes(content))
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except OSError as exc:
        # OSError(errno, ...) is the errno's own subclass (PermissionError, ...)
        raise OSError(exc.errno, f"cannot write {path}: {exc.strerror}") from None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.remove(tmp)
