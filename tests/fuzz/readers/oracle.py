"""What every mesh-file input must give, fuzzed or kept: a MeshFormatError that names the
file, or a mesh that is what it says (finite positions, polygons of 3+ corners, fan
triangles inside the vertex range) and that reads back as the same mesh after it is written,
in its own format and in the two others. Any other exception, or a failed assertion, is a
finding."""

import numpy as np

from edgedeform.mesh_files import SUPPORTED, MeshFormatError, parse_mesh


def check(data, ext):
    """'read' or 'refused' for the bytes `data` of a file with extension `ext`."""
    name = "input" + ext
    try:
        mesh = parse_mesh(data, ext, name)
    except MeshFormatError as exc:
        assert str(exc).startswith(name + ": "), f"the error does not name the file: {exc}"
        return "refused"
    V, sizes, corners, T = mesh.vertices, mesh.face_sizes, mesh.face_corners, mesh.triangles
    assert V.ndim == 2 and V.shape[1] == 3 and len(V) > 0 and np.isfinite(V).all()
    assert len(sizes) > 0 and (sizes >= 3).all() and int(sizes.sum()) == len(corners)
    assert T.shape == (int((sizes - 2).sum()), 3) and T.min() >= 0 and T.max() < len(V)
    for out in SUPPORTED:
        content, _ = mesh.encode(out, V)
        again = parse_mesh(content, out, "again" + out)
        assert np.array_equal(again.vertices, V), f"{ext} -> {out}: positions changed"
        assert np.array_equal(again.face_sizes, sizes) and np.array_equal(again.face_corners, corners), \
            f"{ext} -> {out}: faces changed"
    return "read"
