"""The benchmark edits and where the benchmark meshes live; shared by every bench script.

Regions by height (z, unless the mesh is flat in z, then the axis of largest extent):
the lowest 20 % is static, the top 10 % is the handle.
- "lift": the handle raised by a quarter of the bounding-box diagonal;
- "twist": the handle turned 90° about the height axis through its centroid.
"""

from pathlib import Path

import numpy as np

# ../shared relative to the checkout: the meshes are read in place, not copied.
SHARED_MESHES = Path(__file__).resolve().parents[2] / "shared" / "meshes"
TWIST_DEGREES = 90.0


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


def twist_edit(V, degrees=TWIST_DEGREES):
    handles, static, ax = regions(V)
    pivot = V[handles].mean(axis=0)
    targets = (V[handles] - pivot) @ axis_rotation(ax, degrees).T + pivot
    return handles, static, targets, ax


EDITS = {"lift": lift_edit, "twist": twist_edit}
