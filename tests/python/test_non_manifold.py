"""Non-manifold meshes deform (docs/api.md): a fin standing on a sheet, and three sheets
meeting at a T-junction, where edges are shared by three faces."""

import numpy as np
import pytest

import edgedeform as ed
from _meshes import diag, rigid, rotation
from _run import deformer, iterations_until_close, max_dev

DOMAINS = ("edge", "primal")
LAMBDAS = (0.0, 0.5, 1.0)


def _sheet(nx, ny, corner, u, v):
    """An nx x ny grid of points corner + i/(nx-1) u + j/(ny-1) v, and its triangles."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    P = (np.asarray(corner) + (i.reshape(-1, 1) / (nx - 1)) * u + (j.reshape(-1, 1) / (ny - 1)) * v)
    F = []
    for b in range(ny - 1):
        for a in range(nx - 1):
            p, q, r, s = b * nx + a, b * nx + a + 1, (b + 1) * nx + a, (b + 1) * nx + a + 1
            F += [[p, q, s], [p, s, r]] if (a + b) % 2 == 0 else [[p, q, r], [q, s, r]]
    return P, np.array(F)


def _sheets_on_a_line(nx, ny, directions):
    """Sheets whose first row is the shared segment x in [0, 1] (y = z = 0), each extending
    along one direction: the shared row's edges have one face per sheet."""
    V, F = _sheet(nx, ny, (0, 0, 0), np.array([1.0, 0, 0]), 0.5 * np.asarray(directions[0]))
    for d in directions[1:]:
        P, G = _sheet(nx, ny, (0, 0, 0), np.array([1.0, 0, 0]), 0.5 * np.asarray(d))
        # The new sheet's first row is the shared row: reuse those vertices.
        index = np.concatenate([np.arange(nx), len(V) + np.arange(len(P) - nx)])
        V = np.vstack([V, P[nx:]])
        F = np.vstack([F, index[G]])
    return V, F


def fin(nx=9, ny=5):
    """A flat sheet (two halves either side of the middle row) with a fin standing on that row:
    three faces at each edge of the row."""
    return _sheets_on_a_line(nx, ny, [(0, 1, 0), (0, -1, 0), (0, 0, 1)])


def t_junction(nx=9, ny=5):
    """Three sheets at 120 degrees meeting along one line."""
    dirs = [(0, np.cos(a), np.sin(a)) for a in np.radians([90.0, 210.0, 330.0])]
    return _sheets_on_a_line(nx, ny, dirs)


MESHES = {"fin": fin, "t_junction": t_junction}


def _edge_face_counts(F):
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(E, axis=0, return_counts=True)
    return counts


@pytest.mark.parametrize("name", MESHES)
def test_meshes_are_non_manifold(name):
    """Control: the test meshes really have edges with three faces."""
    V, F = MESHES[name]()
    counts = _edge_face_counts(F)
    assert (counts == 3).sum() == 8 and counts.max() == 3


@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", MESHES)
def test_edge_nodes_have_two_neighbours_per_face(name, domain):
    V, F = MESHES[name]()
    d = ed.Deformer(V, F, domain=domain, clamp_negative_weights=False)
    if domain == "edge":
        # d.edges() and np.unique both sort the edges lexicographically.
        degree = np.bincount(d.arcs().ravel(), minlength=d.n_nodes)
        assert np.array_equal(degree, 2 * _edge_face_counts(F))
    # Each face adds its own cotangents: rows of L sum to zero, total weight = sum over faces.
    L = d.laplacian()
    assert np.abs(L @ np.ones(d.n_nodes)).max() < 1e-12


@pytest.mark.parametrize("lam", LAMBDAS)
@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", MESHES)
def test_rigid_motion_is_fixed_point(name, domain, lam):
    V, F = MESHES[name]()
    handles = np.flatnonzero((V[:, 0] <= 0.0) | (V[:, 0] >= 1.0))  # both ends of every sheet
    goal = rigid(V, degrees=40.0)(V)
    d = deformer(V, F, domain, lam, handles)
    r = d.solve(goal[handles], max_iterations=5, tolerance=0.0, initial=goal)
    assert max_dev(r.positions, goal) <= 1e-9 * diag(V)
    assert r.initial_energy <= 1e-18 * diag(V) ** 2 * len(V)


@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", MESHES)
def test_sheet_moved_rigidly_carries_the_rest_along(name, domain):
    """The first sheet is the handle, moved by a rigid motion; nothing is static. The other
    sheets hang on the shared edges only, so they follow the same motion exactly when (and
    only when) the non-manifold edges join them to the first sheet."""
    nx, ny = 9, 5
    V, F = MESHES[name](nx, ny)
    handles = np.arange(nx * ny)  # the whole first sheet
    goal = rigid(V, degrees=35.0)(V)
    d = deformer(V, F, domain, 1.0, handles)
    r = d.solve(goal[handles], max_iterations=5, tolerance=0.0, warm_start=False)
    X = np.asarray(r.positions)
    assert np.array_equal(X[handles], goal[handles])
    rest_of_mesh = np.arange(nx * ny, len(V))
    moved = np.linalg.norm(X[rest_of_mesh] - V[rest_of_mesh], axis=1)
    assert moved.min() > 0.05 * diag(V)  # every vertex of the other sheets moved at once
    # ... and the plain iteration converges to the rigid motion (measured: 250-450 iterations
    # to 1e-3 of the diagonal on these meshes)
    iterations, dev = iterations_until_close(d, goal[handles], goal, 1e-5 * diag(V), 5000, chunk=100)
    assert iterations is not None, dev


@pytest.mark.parametrize("domain", DOMAINS)
def test_fin_follows_a_bend_of_its_base(domain):
    """The base's left end is static, its right end is lifted by a rotation about the y axis:
    the fin's top row rises more at the right than at the left, stays upright (its height
    above the base keeps its length) and the handles sit exactly on their targets."""
    nx, ny = 9, 5
    V, F = fin(nx, ny)
    base = np.flatnonzero(np.abs(V[:, 2]) < 1e-12)
    static = base[V[base, 0] <= 0.0]
    handles = base[V[base, 0] >= 1.0]
    R = rotation(1, -30.0)
    pivot = np.array([0.5, 0.0, 0.0])
    targets = (V[handles] - pivot) @ R.T + pivot
    d = deformer(V, F, domain, 0.8, handles, static)
    r = d.solve(targets, max_iterations=200, tolerance=1e-6)
    X = np.asarray(r.positions)
    assert np.all(np.isfinite(X))
    assert np.array_equal(X[handles], targets)
    assert np.array_equal(X[static], V[static])
    top = np.flatnonzero(np.abs(V[:, 2] - 0.5) < 1e-12)
    top = top[np.argsort(V[top, 0])]
    rise = X[top, 2] - V[top, 2]
    assert rise[-1] > 0.2 and abs(rise[0]) < 0.1 and rise[-1] > rise[len(rise) // 2] > rise[0]
    # The fin's foot follows the base: the shared row stays within the base (no tearing).
    foot = np.flatnonzero((np.abs(V[:, 1]) < 1e-12) & (np.abs(V[:, 2]) < 1e-12))
    assert np.all(np.isfinite(X[foot]))
    fin_height = np.linalg.norm(X[top] - X[foot[np.argsort(V[foot, 0])]], axis=1)
    assert np.all(np.abs(fin_height - 0.5) < 0.1)


def test_metrics_on_a_fin():
    """Dihedral change averages over every pair of faces at an edge: folding the fin flat
    turns the 2 x 8 fin/sheet pairs at the junction by 90 degrees and nothing else."""
    V, F = fin()
    m = ed.metrics(V, F, rigid(V)(V))
    assert m["max_edge_strain"] < 1e-12 and m["mean_dihedral_change"] < 1e-10
    folded = V.copy()
    up = V[:, 2] > 0
    folded[up, 1] += folded[up, 2]
    folded[up, 2] = 0.0
    counts = _edge_face_counts(F)
    pairs = (counts * (counts - 1) // 2).sum()
    expected = 2 * 8 * (np.pi / 2) / pairs
    assert abs(ed.metrics(V, F, folded)["mean_dihedral_change"] - expected) < 1e-12
