"""The benchmark edits, the benchmark meshes, and the solver's acceleration methods; shared
by every bench script, so that a row labelled "twist" is the same edit everywhere.

Regions by height (z, unless the mesh is flat in z, then the axis of largest extent):
the lowest 20 % is static, the top 10 % is the handle.
- "lift": the handle raised by a quarter of the bounding-box diagonal;
- "twist": the handle turned 90° about the height axis through its centroid;
- "bend": the handle turned 30° about the next axis (x after z) through its centroid.

Regions along the longest bounding-box axis instead (held-out edits of record 0070: a limb or
a head swung sideways; the lowest 20 % along that axis static, the top 10 % the handle, or
with "_low" the other way round):
- "side+", "side-", "side_low+", "side_low-": the handle moved by a quarter of the diagonal
  along the second-longest axis, + or -;
- "twist60": the handle turned 60° about the longest axis through its centroid;
- "bend90": the handle turned 90° about the second-longest axis through its centroid.
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
MESH_FILES = {"koala": "koala.obj", "koala5k": "koala_5k.obj", "koala12k": "koala_12k.obj", "spot11k": "spot.obj", "spot": "spot_low_resolution.obj",
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


def long_regions(V, low_handle=False):
    """(handles, static, axes by decreasing extent): along the longest axis, the top 10 % the
    handle and the lowest 20 % static, or the lowest 10 % and the top 20 % with low_handle."""
    order = np.argsort(-np.ptp(V, axis=0), kind="stable")
    h = V[:, order[0]] * (-1.0 if low_handle else 1.0)
    static = np.flatnonzero(h <= np.quantile(h, 0.2))
    handles = np.flatnonzero(h >= np.quantile(h, 0.9))
    return handles, static, order


def side_edit(V, sign, low_handle=False):
    handles, static, order = long_regions(V, low_handle)
    targets = V[handles].copy()
    targets[:, order[1]] += sign * 0.25 * diagonal(V)
    return handles, static, targets, order[0]


def long_turn_edit(V, which_axis, degrees):
    """The handle turned about long_regions' axis `which_axis` (0 longest) through its centroid."""
    handles, static, order = long_regions(V)
    pivot = V[handles].mean(axis=0)
    targets = (V[handles] - pivot) @ axis_rotation(order[which_axis], degrees).T + pivot
    return handles, static, targets, order[0]


EDITS = {"lift": lift_edit, "twist": twist_edit, "bend": bend_edit,
         "side+": lambda V: side_edit(V, 1.0), "side-": lambda V: side_edit(V, -1.0),
         "side_low+": lambda V: side_edit(V, 1.0, True), "side_low-": lambda V: side_edit(V, -1.0, True),
         "twist60": lambda V: long_turn_edit(V, 0, 60.0), "bend90": lambda V: long_turn_edit(V, 1, 90.0)}


def edit(V, name):
    """(handles, static, targets) of edit `name` on rest positions V."""
    handles, static, targets, _ = EDITS[name](V)
    return handles, static, targets


def capped_cylinder(radius=0.04, length=1.0, around=24, along=240):
    """A thin closed cylinder along z (record 0070's bent cylinder): `along` + 1 rings of
    `around` vertices from z = 0 to `length`, each end closed by a fan about a centre vertex."""
    t = 2 * np.pi * np.arange(around) / around
    z = np.linspace(0.0, length, along + 1)
    ring = np.column_stack([radius * np.cos(t), radius * np.sin(t)])
    V = np.column_stack([np.tile(ring, (along + 1, 1)), np.repeat(z, around)])
    V = np.vstack([V, [[0.0, 0.0, 0.0], [0.0, 0.0, length]]])
    k = np.arange(around)
    faces = []
    for j in range(along):
        a, b = j * around + k, j * around + (k + 1) % around
        faces += [np.column_stack([a, b, b + around]), np.column_stack([a, b + around, a + around])]
    bottom, top = len(V) - 2, len(V) - 1
    faces.append(np.column_stack([np.full(around, bottom), (k + 1) % around, k]))
    last = along * around
    faces.append(np.column_stack([np.full(around, top), last + k, last + (k + 1) % around]))
    return V, np.vstack(faces).astype(np.int64)


GENERATED = {"cylinder": capped_cylinder}


def load_mesh(short_name):
    """(V, F) of a benchmark mesh by its short name: a file of MESH_FILES, or a generated one."""
    if short_name in GENERATED:
        return GENERATED[short_name]()
    from edgedeform.mesh_files import read_mesh
    return read_mesh(mesh_path(MESH_FILES[short_name]))
