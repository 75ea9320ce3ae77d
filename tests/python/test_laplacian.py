"""The graph, its weights and its Laplacian against finite-element matrices that the
test assembles itself (docs/design.md §3 "Arcs and weights")."""

import numpy as np
import pytest
import scipy.sparse as sp

import edgedeform as ed
from _meshes import ALL, load, unique_edges
from _reference import cr_stiffness, p1_stiffness


def _csr(M):
    """laplacian()/node_matrix() return SciPy sparse when SciPy is present (it is here)."""
    assert sp.issparse(M), "SciPy is importable, so a scipy.sparse matrix is expected"
    return sp.csr_matrix(M)


def _close(A, B, rel=1e-9):
    scale = max(abs(A).max(), abs(B).max())
    return abs(A - B).max() <= rel * scale


def _face_count_per_edge(F, E):
    Ef = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    Ef.sort(axis=1)
    u, counts = np.unique(Ef, axis=0, return_counts=True)
    assert np.array_equal(u, E)
    return counts


@pytest.mark.parametrize("name", ALL)
def test_edge_graph_nodes_are_the_unique_edges(name):
    V, F = load(name)
    d = ed.Deformer(V, F, domain="edge")
    E = np.asarray(d.edges())
    assert E.shape[1] == 2 and np.all(E[:, 0] < E[:, 1])
    assert np.array_equal(np.unique(E, axis=0), unique_edges(F))
    assert d.n_nodes == len(E)
    assert np.array_equal(np.asarray(d.node_vertices()), E)
    # D: two entries 1/2 per row, at the edge's endpoints.
    D = _csr(d.node_matrix())
    expect = sp.csr_matrix((np.full(2 * len(E), 0.5),
                            (np.repeat(np.arange(len(E)), 2), E.reshape(-1))),
                           shape=(len(E), len(V)))
    assert abs(D - expect).max() == 0.0


@pytest.mark.parametrize("name", ALL)
def test_edge_graph_has_4_neighbours_inside_2_on_boundary(name):
    V, F = load(name)
    d = ed.Deformer(V, F, domain="edge", clamp_negative_weights=False)
    E = np.asarray(d.edges())
    A = np.asarray(d.arcs())
    assert np.all(A[:, 0] < A[:, 1])
    assert len(np.unique(A, axis=0)) == len(A), "arcs must be unique"
    valence = np.bincount(A.reshape(-1), minlength=len(E))
    faces = _face_count_per_edge(F, E)
    assert np.all(valence[faces == 2] == 4)
    assert np.all(valence[faces == 1] == 2)
    if name in ("cgal_plane.off", "cgal_three_peaks.off"):
        assert np.any(faces == 1)                     # the boundary case is exercised


@pytest.mark.parametrize("name", ALL)
def test_edge_laplacian_is_quarter_crouzeix_raviart(name):
    V, F = load(name)
    d = ed.Deformer(V, F, domain="edge", clamp_negative_weights=False)
    L = _csr(d.laplacian())
    assert L.shape == (d.n_nodes, d.n_nodes)
    assert abs(L - L.T).max() <= 1e-14 * abs(L).max()                  # symmetric
    assert np.abs(np.asarray(L.sum(axis=1))).max() <= 1e-12 * abs(L).max()  # rows sum 0
    K = cr_stiffness(V, F, np.asarray(d.edges()))
    assert _close(L, 0.25 * K)


@pytest.mark.parametrize("domain", ["edge", "primal"])
@pytest.mark.parametrize("name", ALL)
def test_clamping_keeps_only_positive_weights(name, domain):
    V, F = load(name)
    signed = ed.Deformer(V, F, domain=domain, clamp_negative_weights=False)
    clamped = ed.Deformer(V, F, domain=domain)     # default: clamp
    Ls, Lc = _csr(signed.laplacian()), _csr(clamped.laplacian())
    off_s = Ls - sp.diags(Ls.diagonal())
    off_c = Lc - sp.diags(Lc.diagonal())
    # off-diagonals are -w: clamping w to max(w, 0) is min(L_ij, 0)
    assert _close(off_c, off_s.minimum(0))
    assert np.allclose(Lc.diagonal(), -np.asarray(off_c.sum(axis=1)).ravel(),
                       rtol=1e-12, atol=1e-14 * abs(Lc).max())
    w = np.asarray(clamped.weights())
    assert np.all(w >= 0)
    # weights() and laplacian() describe the same arcs
    A = np.asarray(clamped.arcs())
    assert np.allclose(-np.asarray(Lc[A[:, 0], A[:, 1]]).ravel(), w, rtol=1e-12, atol=0)
    if name != "cgal_plane.off":
        # real meshes have obtuse angles, so clamping actually changes something
        assert off_s.max() > 0


@pytest.mark.parametrize("name", ALL)
def test_primal_laplacian_is_p1_cotangent_matrix(name):
    V, F = load(name)
    d = ed.Deformer(V, F, domain="primal", clamp_negative_weights=False)
    L = _csr(d.laplacian())
    assert _close(L, p1_stiffness(V, F))
    assert np.array_equal(np.asarray(d.node_vertices()).ravel(), np.arange(len(V)))


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_node_stiffness_is_mean_of_endpoints(domain):
    V, F = load("cgal_three_peaks.off")
    lam = np.random.default_rng(1).uniform(0, 1, len(V))
    d = ed.Deformer(V, F, domain=domain)
    d.set_stiffness(lam)
    nv = np.asarray(d.node_vertices())
    assert np.allclose(d.node_stiffness(), lam[nv].mean(axis=1), rtol=0, atol=1e-15)
    d.set_stiffness(0.3)
    assert np.allclose(d.node_stiffness(), 0.3, rtol=0, atol=1e-15)
