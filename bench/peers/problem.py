"""One benchmark problem on disk, readable by every peer: the mesh as OFF (vertex order
kept), the constraints as .npz (Python peers) and as plain text (the CGAL program).

Handles move to `targets`; static vertices stay at rest; every vertex is in the region of
interest. `drag` is the per-update handle move of the live-update measurement.
NumPy only: this module is imported by the system Python, the libigl venv and Blender.
"""

from pathlib import Path

import numpy as np


def write_problem(folder, V, F, handles, static, targets, drag, **meta):
    """`meta`: numbers the peers may need to rebuild the edit (e.g. up_axis, twist_degrees)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    diag = float(np.linalg.norm(np.ptp(V, axis=0)))
    with open(folder / "mesh.off", "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.17g")
        np.savetxt(f, np.column_stack([np.full(len(F), 3), F]), fmt="%d")
    np.savez(folder / "problem.npz", V=V, F=F, handles=handles, static=static,
             targets=targets, drag=np.asarray(drag, float), diag=diag, **meta)
    with open(folder / "constraints.txt", "w") as f:
        f.write(f"diag {diag:.17g}\nhandles {len(handles)}\n")
        np.savetxt(f, np.column_stack([handles, targets]), fmt=["%d", "%.17g", "%.17g", "%.17g"])
        f.write(f"static {len(static)}\n")
        np.savetxt(f, static, fmt="%d")
    return folder


def load_problem(folder):
    with np.load(Path(folder) / "problem.npz") as z:
        p = {k: z[k] for k in z.files}
    p["diag"] = float(p["diag"])
    return p
