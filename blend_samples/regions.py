"""Sample-scene geometry without Blender: meshes (read by edgedeform.mesh_files), region
selection, handle edits.

Shared by make_samples.py (inside Blender) and the demo (inside or outside Blender), so the
scenes and the demo select exactly the same vertices. NumPy only; no per-vertex loops.

A scene (one entry of scenes.json) is plain data:
  mesh       file under tests/data/ (".off", ".obj"; the one copy of the real meshes) or
             "procedural:bar"
  frame      [[axis permutation / sign]] via "up": which mesh axis points up ("x","y","z","-y",...)
  handles    [{name, region, edit}], static region, stiffness {default, regions:[{region, value}]}
Coordinates are normalised: bounding-box centre at the origin, longest side 2, up = +Z.
"""
import json
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES_JSON = os.path.join(HERE, "scenes.json")
# The real meshes the samples use live once, with the tests' (sources and licences in
# tests/data/SOURCES.md).
MESHES = os.path.join(os.path.dirname(HERE), "tests", "data")


def load_scenes(path=SCENES_JSON):
    with open(path) as f:
        return json.load(f)["scenes"]


# ---------------------------------------------------------------- mesh input

def make_bar(length=8.0, radius=0.5, rings=48, segments=16):
    """A closed, triangulated cylinder along X (caps as triangle fans around a centre vertex)."""
    x = np.linspace(-length / 2, length / 2, rings)
    a = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    X = np.repeat(x, segments)
    Y = np.tile(np.cos(a), rings) * radius
    Z = np.tile(np.sin(a), rings) * radius
    V = np.column_stack([X, Y, Z])
    r = np.arange(rings - 1)[:, None] * segments
    s = np.arange(segments)[None, :]
    a0, a1 = r + s, r + (s + 1) % segments
    b0, b1 = a0 + segments, a1 + segments
    side = np.concatenate([np.stack([a0, a1, b1], -1).reshape(-1, 3),
                           np.stack([a0, b1, b0], -1).reshape(-1, 3)])
    c0, c1 = len(V), len(V) + 1
    V = np.vstack([V, [[-length / 2, 0, 0], [length / 2, 0, 0]]])
    s1 = np.arange(segments)
    last = (rings - 1) * segments
    cap0 = np.column_stack([np.full(segments, c0), (s1 + 1) % segments, s1])
    cap1 = np.column_stack([np.full(segments, c1), last + s1, last + (s1 + 1) % segments])
    return V, np.vstack([side, cap0, cap1]).astype(np.int64)


_AXES = {"x": 0, "y": 1, "z": 2}


def _up_matrix(up):
    """Rotation taking the mesh axis named by `up` (e.g. "y", "-z") to +Z, keeping handedness."""
    sign = -1.0 if up.startswith("-") else 1.0
    k = _AXES[up[-1]]
    M = np.zeros((3, 3))
    # cyclic permutation keeps det = +1: axis k -> z, k+1 -> x, k+2 -> y
    M[2, k] = sign
    M[0, (k + 1) % 3] = 1.0
    M[1, (k + 2) % 3] = sign
    return M


def normalise(V, up="z"):
    V = V @ _up_matrix(up).T
    lo, hi = V.min(0), V.max(0)
    return (V - (lo + hi) / 2) * (2.0 / (hi - lo).max())


def scene_mesh(scene):
    """(V, F) of a scene in normalised coordinates, vertex order as in the file."""
    src = scene["mesh"]
    if src == "procedural:bar":
        V, F = make_bar()
    else:  # the package's reader: OBJ/OFF/PLY, file vertex order kept
        from edgedeform.mesh_files import read_mesh
        V, F = read_mesh(os.path.join(MESHES, src))
    return normalise(V, scene.get("up", "z")), F


# ---------------------------------------------------------------- regions

def select(region, V):
    """Boolean mask of the vertices in `region`, a dict with exactly one shape key:
    box {min, max} (null = unbounded), sphere {center, radius}, halfspace {normal, offset}
    (n.x >= offset), all/none, or the set operations any [...], every [...], not {...},
    minus [a, b...] (a without the others)."""
    if region in ("all", None) or region == {}:
        return np.ones(len(V), bool) if region == "all" else np.zeros(len(V), bool)
    (kind, arg), = region.items()
    if kind == "box":
        lo = np.array([-np.inf if v is None else v for v in arg["min"]])
        hi = np.array([np.inf if v is None else v for v in arg["max"]])
        return np.all((V >= lo) & (V <= hi), axis=1)
    if kind == "sphere":
        return np.linalg.norm(V - np.asarray(arg["center"]), axis=1) <= arg["radius"]
    if kind == "halfspace":
        return V @ np.asarray(arg["normal"], float) >= arg["offset"]
    if kind == "any":
        return np.any([select(r, V) for r in arg], axis=0)
    if kind == "every":
        return np.all([select(r, V) for r in arg], axis=0)
    if kind == "not":
        return ~select(arg, V)
    if kind == "minus":
        out = select(arg[0], V)
        for r in arg[1:]:
            out &= ~select(r, V)
        return out
    raise ValueError(f"unknown region kind {kind!r}")


def rotation(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    t = np.radians(degrees)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def edit_matrix(edit, pivot):
    """4x4 world matrix of a controller Empty that sat at `pivot` (identity rotation) and was
    then scaled, rotated (list of [axis, degrees], applied in order) and moved by `translate`."""
    R = np.eye(3)
    for axis, deg in edit.get("rotate", []):
        R = rotation(axis, deg) @ R
    S = np.diag(np.broadcast_to(np.asarray(edit.get("scale", 1.0), float), 3))
    M = np.eye(4)
    M[:3, :3] = R @ S
    M[:3, 3] = np.asarray(pivot) + np.asarray(edit.get("translate", [0, 0, 0]), float)
    return M


def scene_setup(scene, V):
    """Everything a deformation needs, from the scene data and normalised rest positions V:
    {"handles": [{name, index, pivot, matrix}], "handle_index", "targets", "static", "stiffness"}.
    Handle targets are matrix @ inverse(rest matrix) applied to rest positions, exactly as the
    add-on maps a controller's motion onto its handle."""
    handles, taken = [], np.zeros(len(V), bool)
    for h in scene["handles"]:
        mask = select(h["region"], V) & ~taken   # a vertex belongs to one handle only
        taken |= mask
        idx = np.flatnonzero(mask)
        pivot = V[idx].mean(0)
        handles.append({"name": h["name"], "index": idx, "pivot": pivot,
                        "matrix": edit_matrix(h["edit"], pivot)})
    static = np.flatnonzero(select(scene["static"], V) & ~taken)
    hidx = np.concatenate([h["index"] for h in handles])
    targets = np.concatenate([
        (V[h["index"]] - h["pivot"]) @ h["matrix"][:3, :3].T + h["matrix"][:3, 3]
        for h in handles])
    lam = np.full(len(V), float(scene["stiffness"]["default"]))
    for r in scene["stiffness"].get("regions", []):   # later regions paint over earlier ones
        lam[select(r["region"], V)] = r["value"]
    return {"handles": handles, "handle_index": hidx, "targets": targets,
            "static": static, "stiffness": lam}


def material_regions(scene, V):
    """{label: vertex mask} of the painted materials (for per-region metrics), painting order."""
    out = {}
    lam = np.full(len(V), float(scene["stiffness"]["default"]))
    masks = [(None, select("all", V), scene["stiffness"]["default"])]
    for r in scene["stiffness"].get("regions", []):
        masks.append((r.get("label"), select(r["region"], V), r["value"]))
    for label, m, value in masks:
        lam[m] = value
    for label, m, value in masks:
        key = label or "elsewhere (default)"
        out[key] = {"mask": m & (lam == value), "value": value}
    return out
