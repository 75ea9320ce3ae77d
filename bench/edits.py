"""The benchmark edits, the benchmark meshes, and the solver's acceleration methods; shared
by every bench script, so that a row labelled "twist" is the same edit everywhere.

Regions by height (z, unless the mesh is flat in z, then the axis of largest extent):
the lowest 20 % is static, the top 10 % is the handle.
- "lift": the handle raised by a quarter of the bounding-box diagonal;
- "twist": the handle turned 90° about the height axis through its centroid;
- "bend": the handle turned 30° about the next axis (x after z) through its centroid.
(bench_convergence.py once had its own twist, 60° about the longest axis, and its bend about
the axis after that one: docs/decisions/0009-one-definition-per-edit.md.)
"""

import lzma
import re
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
# Where mesh_path() looks, in order: the benchmark meshes (xz-compressed), then the small
# real meshes the tests and the sample scenes share (their one copy).
MESH_FOLDERS = (HERE / "meshes", ROOT / "tests" / "data")
UNPACKED = HERE / "results" / "cache" / "meshes"   # not committed (.gitignore)
# The benchmark meshes' short names, one table for every script's --mesh/--cells/--meshes.
MESH_FILES = {"koala": "koala.obj", "spot11k": "spot.obj", "spot": "spot_low_resolution.obj",
              "dino": "cgal_dino.off", "head": "cgal_mannequin-devil.off", "plane": "cgal_plane.off"}
TWIST_DEGREES = 90.0
BEND_DEGREES = 30.0


def mesh_path(name, folder=None):
    """The path of benchmark mesh `name` ("koala.obj"): in `folder` if one is given (a
    script's --meshes), else the first of MESH_FOLDERS that has it, decompressed once into
    bench/results/cache/meshes/ when the repository holds it as NAME.xz."""
    if folder:
        path = Path(folder) / name
        if not path.is_file():
            raise SystemExit(f"mesh {name} is not in {folder}")
        return path
    for where in MESH_FOLDERS:
        if (where / name).is_file():
            return where / name
        packed = where / (name + ".xz")
        if packed.is_file():
            out = UNPACKED / name
            if not out.is_file() or out.stat().st_mtime < packed.stat().st_mtime:
                out.parent.mkdir(parents=True, exist_ok=True)
                tmp = out.with_suffix(out.suffix + ".part")
                tmp.write_bytes(lzma.decompress(packed.read_bytes()))
                tmp.replace(out)   # whole or absent, also when two benchmarks race
            return out
    raise SystemExit(f"mesh {name} is in none of " + ", ".join(str(w) for w in MESH_FOLDERS))


def accelerations(ed):
    """The acceleration methods this build's solve() accepts, as the core lists them
    (edgedeform.ACCELERATIONS, e.g. ["newton", "anderson", "none"]). A build older than
    that export (same_positions.py compares against old builds) is asked through the error
    message of solve(acceleration="?"), which names every method."""
    if hasattr(ed, "ACCELERATIONS"):
        return list(ed.ACCELERATIONS)
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    d = ed.Deformer(V, F)
    d.set_constraints(handles=[3], static=[0])
    try:
        d.solve(V[[3]], max_iterations=1, acceleration="?")
    except ValueError as e:
        names = re.findall(r'"([a-z_]+)"', str(e))
        if names:
            return [n for n in names if n != "?"]
        raise
    raise RuntimeError('solve(acceleration="?") was accepted: cannot list the methods')


def method_list(ed, text):
    """--methods: a comma list checked against accelerations(ed); empty = all of them."""
    known = accelerations(ed)
    chosen = [m for m in text.split(",") if m] if text else known
    unknown = [m for m in chosen if m not in known]
    if unknown:
        raise SystemExit(f"unknown method(s) {', '.join(unknown)}: this build has {', '.join(known)}")
    return chosen


def up_axis(V):
    ext = np.ptp(V, axis=0)
    return 2 if ext[2] > 0.01 * np.linalg.norm(ext) else int(np.argmax(ext))


def diagonal(V):
    return float(np.linalg.norm(np.ptp(V, axis=0)))


def regions(V):
    """(handles, static, up axis): top 10 % and lowest 20 % of the height."""
    ax = up_axis(V)
    h = V[:, ax]
    static = np.flatnonzero(h <= np.quantile(h, 0.2))
    handles = np.flatnonzero(h >= np.quantile(h, 0.9))
    return handles, static, ax


def lift_edit(V):
    handles, static, ax = regions(V)
    targets = V[handles].copy()
    targets[:, ax] += 0.25 * diagonal(V)
    return handles, static, targets, ax


def axis_rotation(axis, degrees):
    """3x3 rotation by `degrees` about coordinate axis `axis` (0, 1, 2)."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R = np.eye(3)
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def turn_edit(V, about, degrees):
    """The handle turned by `degrees` about axis up + `about` (mod 3) through its centroid."""
    handles, static, ax = regions(V)
    pivot = V[handles].mean(axis=0)
    targets = (V[handles] - pivot) @ axis_rotation((ax + about) % 3, degrees).T + pivot
    return handles, static, targets, ax


def twist_edit(V, degrees=TWIST_DEGREES):
    return turn_edit(V, 0, degrees)


def bend_edit(V, degrees=BEND_DEGREES):
    return turn_edit(V, 1, degrees)


EDITS = {"lift": lift_edit, "twist": twist_edit, "bend": bend_edit}


def edit(V, name):
    """(handles, static, targets) of edit `name` on rest positions V."""
    handles, static, targets, _ = EDITS[name](V)
    return handles, static, targets
