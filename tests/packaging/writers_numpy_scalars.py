"""The mesh writers on NumPy scalars: every file they write reads back to the same doubles.

    python writers_numpy_scalars.py     (needs `edgedeform` importable; no pytest needed, so
                                         it also runs inside the wheel's bare venvs)

Under NumPy 2 `repr(np.float64(x))` is "np.float64(x)": writers that formatted coordinates
with `!r` wrote OBJ/OFF files no reader could open. `LoudFloat` has such a repr on any
NumPy, so these checks fail on that bug even where NumPy 1.x is installed.
"""

import os
import sys
import tempfile

import numpy as np

from edgedeform import mesh_files


class LoudFloat(float):
    def __repr__(self):
        return "LoudFloat(%s)" % float.__repr__(self)


# Values whose shortest text has many digits: the round trip must be exact, not "close".
V = np.array([[0.1, 0.2, 0.30000000000000004], [1.0 / 3.0, -2.5e-17, 7.0],
              [123456.789, 0.0, -1.0 / 7.0], [np.pi, np.e, 1e300]])
F = np.array([[0, 1, 2], [0, 2, 3]])


def check_write_mesh(folder):
    """write_mesh with a float64 array (NumPy scalars when iterated), every format."""
    for ext in ("obj", "off", "ply"):
        path = os.path.join(folder, "plain." + ext)
        mesh_files.write_mesh(path, V, F)
        text = open(path, "rb").read()
        assert b"np." not in text and b"float64" not in text, (ext, text[:200])
        V2, F2 = mesh_files.read_mesh(path)
        assert np.array_equal(V2, V), (ext, V2)
        assert np.array_equal(F2, F), (ext, F2)


def check_rewrite(folder):
    """The CLI's path: read a file, write it back with new positions (keeping its other
    lines). MeshFile.write hands the format a float64 array (NumPy scalars row by row); the
    format's rewrite itself also gets rows of floats with a NumPy-2-like repr."""
    moved = V * 2.0 + 0.1
    loud = [[LoudFloat(x) for x in row] for row in moved]
    for ext in ("obj", "off", "ply"):
        src = os.path.join(folder, "src." + ext)
        mesh_files.write_mesh(src, V, F)
        mesh = mesh_files.read_mesh_file(src)
        out = os.path.join(folder, "moved." + ext)
        mesh.write(out, moved)
        outputs = [open(out, "rb").read()]
        if ext != "ply":   # PLY's rewrite takes arrays only (binary files pack them)
            text, _ = mesh._source.rewrite(loud)
            outputs.append(text.encode("latin-1"))
        for data in outputs:
            assert b"LoudFloat" not in data and b"np." not in data, (ext, data[:200])
            with open(out, "wb") as fh:
                fh.write(data)
            V2, F2 = mesh_files.read_mesh(out)
            assert np.array_equal(V2, moved), (ext, V2)
            assert np.array_equal(F2, F), ext


def check_plain_writers_on_loud_floats():
    """The plain writers themselves (write_mesh converts to float64 first)."""
    from edgedeform import obj_format, off_format
    loud = [[LoudFloat(x) for x in row] for row in V]
    for module in (obj_format, off_format):
        text = module.write_plain(loud, np.full(len(F), 3), F.reshape(-1))
        assert "LoudFloat" not in text, (module.__name__, text[:200])


def main():
    print("numpy", np.__version__, "- repr(np.float64(0.5)) =", repr(np.float64(0.5)))
    with tempfile.TemporaryDirectory() as folder:
        check_write_mesh(folder)
        check_rewrite(folder)
    check_plain_writers_on_loud_floats()
    print("writers OK on NumPy scalars")


if __name__ == "__main__":
    sys.exit(main())
