"""Writes solve_lift's input for a benchmark edit (bench/edits.py): the mesh, its handles,
static vertices and targets, and lambda, every number exact.

    make_lift_input.py MESH EDIT LAMBDA OUT      e.g. koala.obj lift 0.5 build/koala_lift.txt

Run with build/python on PYTHONPATH (edgedeform.mesh_files reads the mesh).
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import edits  # noqa: E402
from edgedeform.mesh_files import read_mesh  # noqa: E402


def main():
    mesh, edit, lam, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), Path(sys.argv[4])
    V, F = read_mesh(str(edits.mesh_path(mesh)))
    handles, static, targets = edits.edit(V, edit)
    lines = ["%d %d %d %d %r" % (len(V), len(F), len(handles), len(static), lam)]
    lines += ["%r %r %r" % tuple(map(float, v)) for v in V]
    lines += ["%d %d %d" % tuple(map(int, f)) for f in F]
    lines += [" ".join(str(int(i)) for i in handles), " ".join(str(int(i)) for i in static)]
    lines += ["%r %r %r" % tuple(map(float, t)) for t in targets]
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("%s: %s %s, lambda %g: %d vertices, %d handles, %d static; diagonal %.6g"
          % (out, mesh, edit, lam, len(V), len(handles), len(static), edits.diagonal(V)))


if __name__ == "__main__":
    np.seterr(all="raise")
    main()
