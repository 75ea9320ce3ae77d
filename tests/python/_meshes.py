"""Test meshes from tests/data and the edits the tests apply to them."""

from functools import lru_cache
from pathlib import Path

import numpy as np

from edgedeform.mesh_files import read_mesh

DATA = Path(__file__).resolve().parents[1] / "data"

PLANE = "cgal_plane.off"              # flat, one boundary loop
SPOT = "spot_low_resolution.obj"      # closed, 829 vertices
DINO = "cgal_dino.off"                # closed, the paper's Fig. 5 stand-in
PEAKS = "cgal_three_peaks.off"        # bumpy, one boundary loop
ALL = (PLANE, SPOT, DINO, PEAKS)
HEAD = "cgal_mannequin-devil.off"     # open face mask, 12,977 vertices: the head sample (not in ALL: large)


def source_counts():
    """{file: (vertices, faces)} as tests/data/SOURCES.md's table states them."""
    rows = {}
    for line in (DATA / "SOURCES.md").read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) > 3 and cells[2].replace(",", "").isdigit():
            rows[cells[0]] = (int(cells[2].replace(",", "")), int(cells[3].replace(",", "")))
    return rows


@lru_cache(maxsize=None)
def _load(name):
    V, F = read_mesh(DATA / name)
    V.setflags(write=False)
    F.setflags(write=False)
    return V, F


def load(name):
    """(V, F) copies, so a test may modify them."""
    V, F = _load(name)
    return V.copy(), F.copy()


def diag(V):
    return float(np.linalg.norm(np.ptp(V, axis=0)))


def up_axis(V):
    """z, unless the mesh is flat in z (then the axis of largest extent)."""
    ext = np.ptp(V, axis=0)
    return 2 if ext[2] > 0.01 * np.linalg.norm(ext) else int(np.argmax(ext))


def long_axis(V):
    return int(np.argmax(np.ptp(V, axis=0)))


def lift(V, amount=0.25, static_frac=0.2, handle_frac=0.1, direction=None):
    """The benchmark's "lift": lowest static_frac of the height static, top handle_frac
    raised by amount * bbox diagonal (along the height, or along axis `direction`).
    Returns handles, static, targets."""
    ax = up_axis(V)
    h = V[:, ax]
    static = np.flatnonzero(h <= np.quantile(h, static_frac))
    handles = np.flatnonzero(h >= np.quantile(h, 1.0 - handle_frac))
    targets = V[handles].copy()
    targets[:, ax if direction is None else direction] += amount * diag(V)
    return handles, static, targets


def bend(V, degrees=20.0, static_frac=0.2, handle_frac=0.1, about=None):
    """Static at one end of the longest axis, the other end rotated about its own
    centroid around axis `about` (default: the next coordinate axis)."""
    ax = long_axis(V)
    h = V[:, ax]
    static = np.flatnonzero(h <= np.quantile(h, static_frac))
    handles = np.flatnonzero(h >= np.quantile(h, 1.0 - handle_frac))
    c = V[handles].mean(axis=0)
    R = rotation((ax + 1) % 3 if about is None else about, degrees)
    targets = (V[handles] - c) @ R.T + c
    return handles, static, targets


def two_ends(V, frac=0.1):
    """Two handle groups at opposite ends of the longest axis."""
    ax = long_axis(V)
    h = V[:, ax]
    lo = np.flatnonzero(h <= np.quantile(h, frac))
    hi = np.flatnonzero(h >= np.quantile(h, 1.0 - frac))
    return np.concatenate([lo, hi])


def rotation(axis, degrees):
    """Rotation matrix about a coordinate axis (0, 1, 2) or a 3-vector."""
    a = np.zeros(3)
    if np.ndim(axis) == 0:
        a[int(axis)] = 1.0
    else:
        a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    t = np.radians(degrees)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * (K @ K)


def rigid(V, degrees=30.0, axis=(1.0, 2.0, 0.5), shift=(0.3, -0.2, 0.1)):
    """A rigid motion x -> R (x - c) + c + shift * diag, about the centroid c."""
    R = rotation(axis, degrees)
    c = V.mean(axis=0)
    t = np.asarray(shift) * diag(V)
    return lambda X: (X - c) @ R.T + c + t


def unique_edges(F):
    """Sorted unique undirected edges (a < b), computed here, not by the core."""
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E.sort(axis=1)
    return np.unique(E, axis=0)


def edge_strain(V0, X, F):
    """Per-edge |l - l0| / l0 and the edges, for the test's own strain measures."""
    E = unique_edges(F)
    l0 = np.linalg.norm(V0[E[:, 0]] - V0[E[:, 1]], axis=1)
    l = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1)
    return np.abs(l - l0) / l0, E
