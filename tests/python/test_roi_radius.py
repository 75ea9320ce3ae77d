"""set_constraints(roi_radius=..., roi_connected=...): the region of interest picked by
distance from the handles, as Blender's proportional editing picks it; checked against
distances computed here (NumPy; SciPy's Dijkstra along the edges bounds the distance over the
surface from above, the straight line from below) and against the same region given as roi."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

import edgedeform as ed
from _meshes import DINO, PLANE, diag, load, unique_edges, up_axis
from _run import deformer, max_dev


def straight_line_region(V, handles, radius):
    d2 = ((V[:, None, :] - V[None, handles, :]) ** 2).sum(axis=2).min(axis=1)
    return np.flatnonzero(d2 <= radius * radius)


def along_edges_region(V, F, handles, radius):
    E = unique_edges(F)
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    G = sp.coo_matrix((length, (E[:, 0], E[:, 1])), shape=(len(V), len(V))).tocsr()
    dist = dijkstra(G, directed=False, indices=handles, min_only=True)
    return np.flatnonzero(dist <= radius)


def assert_over_surface(free, V, F, handles, static, radius):
    """Connected Only's free vertices: at least those within the radius along the edges, at
    most those within it in a straight line (a distance over the surface lies between)."""
    assert set(expected_free(along_edges_region(V, F, handles, radius), handles, static)) <= set(free)
    assert set(free) <= set(expected_free(straight_line_region(V, handles, radius), handles, static))


def expected_free(region, handles, static):
    return np.setdiff1d(region, np.concatenate([handles, static]))


def dino_case():
    V, F = load(DINO)
    h = V[:, up_axis(V)]
    handles = np.flatnonzero(h >= np.quantile(h, 0.95))
    static = np.flatnonzero((h >= np.quantile(h, 0.85)) & (h < np.quantile(h, 0.87)))
    targets = V[handles] + 0.1 * diag(V) * np.eye(3)[up_axis(V)]
    return V, F, handles, static, targets


@pytest.mark.parametrize("connected", [False, True])
def test_radius_equals_the_same_roi_bit_for_bit(connected):
    V, F, handles, static, targets = dino_case()
    radius = 0.25 * diag(V)
    by_radius = ed.Deformer(V, F)
    by_radius.set_constraints(handles, static, roi_radius=radius, roi_connected=connected)
    if connected:
        assert_over_surface(by_radius.free_vertices, V, F, handles, static, radius)
        region = np.union1d(by_radius.free_vertices, handles)
    else:
        region = straight_line_region(V, handles, radius)
        np.testing.assert_array_equal(by_radius.free_vertices, expected_free(region, handles, static))
    by_roi = ed.Deformer(V, F)
    by_roi.set_constraints(handles, static, roi=region)
    a = by_radius.solve(targets, max_iterations=10, tolerance=0.0)
    b = by_roi.solve(targets, max_iterations=10, tolerance=0.0)
    assert np.array_equal(a.positions, b.positions)
    X = np.asarray(a.positions)
    outside = np.setdiff1d(np.arange(len(V)), np.union1d(region, static))
    assert outside.size > 0 and np.array_equal(X[outside], V[outside])
    assert np.array_equal(X[static], V[static])       # statics inside the radius stay static
    moved = by_radius.free_vertices
    assert np.abs(X[moved] - V[moved]).max() > 0.01 * diag(V)


def test_connected_leaves_out_a_second_sheet_the_straight_line_reaches():
    V0, F0 = load(PLANE)
    gap = 0.02 * diag(V0)
    normal = int(np.argmin(np.ptp(V0, axis=0)))              # a flat sheet: its thin axis
    V = np.vstack([V0, V0 + gap * np.eye(3)[normal]])
    F = np.vstack([F0, F0 + len(V0)])
    centre = int(np.argmin(np.linalg.norm(V0 - V0.mean(axis=0), axis=1)))
    handles = np.array([centre])
    radius = 0.23 * diag(V0)
    d = ed.Deformer(V, F)
    d.set_constraints(handles, roi_radius=radius)
    straight = np.asarray(d.free_vertices)
    d.set_constraints(handles, roi_radius=radius, roi_connected=True)
    along = np.asarray(d.free_vertices)
    assert (straight >= len(V0)).any()                 # the other sheet is 2 % of the diagonal away
    assert not (along >= len(V0)).any()
    np.testing.assert_array_equal(straight, expected_free(straight_line_region(V, handles, radius), handles, []))
    # Over a flat sheet the distance across its faces is the straight line's, farther than the
    # path along its edges reaches.
    np.testing.assert_array_equal(along, expected_free(straight_line_region(V0, handles, radius), handles, []))
    assert len(along) > len(expected_free(along_edges_region(V, F, handles, radius), handles, []))


def strip(k):
    """A ladder of unit squares: vertex 2 i at (i, 0, 0), 2 i + 1 at (i, 1, 0)."""
    V = np.array([[i, y, 0.0] for i in range(k + 1) for y in (0, 1)])
    F = np.array([f for i in range(k) for f in ((2 * i, 2 * i + 2, 2 * i + 3), (2 * i, 2 * i + 3, 2 * i + 1))])
    return V, F


@pytest.mark.parametrize("connected", [False, True])
def test_a_vertex_exactly_at_the_radius_is_inside(connected):
    V, F = strip(6)
    d = ed.Deformer(V, F)
    d.set_constraints([0], roi_radius=3.0, roi_connected=connected)
    assert 6 in d.free_vertices and 8 not in d.free_vertices     # (3, 0) is 3 away; (4, 0) is 4
    d.set_constraints([0], roi_radius=np.nextafter(3.0, 0.0), roi_connected=connected)
    assert 6 not in d.free_vertices


def test_weld_passes_the_radius_through():
    V, F, handles, static, targets = dino_case()
    a = ed.Deformer(V, F, weld=True)
    a.set_constraints(handles, static, roi_radius=0.2 * diag(V))
    b = deformer(V, F, "edge", 0.5, handles, static, roi=straight_line_region(V, handles, 0.2 * diag(V)))
    assert max_dev(a.solve(targets, max_iterations=5).positions, b.solve(targets, max_iterations=5).positions) == 0.0


@pytest.mark.parametrize("kwargs, words", [
    (dict(roi_radius=0.0), r"roi_radius must be a finite distance > 0, got 0"),
    (dict(roi_radius=-1.0), r"roi_radius must be a finite distance > 0, got -1"),
    (dict(roi_radius=float("nan")), r"roi_radius must be a finite distance > 0, got nan"),
    (dict(roi_radius=float("inf")), r"roi_radius must be a finite distance > 0, got inf"),
    (dict(roi_radius=1.0, roi=np.arange(10)), r"roi and roi_radius both given"),
    (dict(roi_connected=True), r"roi_connected needs roi_radius"),
    (dict(roi_radius=1e-9), r"no free vertex within roi_radius 1e-09 of the handles: increase the radius"),
    (dict(roi_radius=1e-9, roi_connected=True),
     r"no free vertex within roi_radius 1e-09 over the surface of the handles: increase the radius"),
], ids=["zero", "negative", "nan", "inf", "with_roi", "connected_alone", "too_small", "too_small_connected"])
def test_bad_radius_rejected_and_deformer_unchanged(kwargs, words):
    V, F, handles, static, targets = dino_case()
    d = deformer(V, F, "edge", 0.5, handles, static)
    before = np.asarray(d.solve(targets, max_iterations=5, warm_start=False).positions).copy()
    free = list(d.free_vertices)
    with pytest.raises(ValueError, match=words):
        d.set_constraints(handles, static, **kwargs)
    assert d.free_vertices == free
    after = d.solve(targets, max_iterations=5, warm_start=False)
    assert np.array_equal(after.positions, before)


@pytest.mark.parametrize("connected", [False, True])
def test_roi_from_measures_from_the_given_vertices(connected):
    """roi_from: the radius is measured from those vertices, not from every handle (Grab
    pins other handles where they are shown; Blender measures from what it moves)."""
    V, F, handles, static, targets = dino_case()
    far = np.flatnonzero(V[:, up_axis(V)] <= np.quantile(V[:, up_axis(V)], 0.02))  # pinned, far below
    held = np.concatenate([handles, far])
    radius = 0.2 * diag(V)
    d = ed.Deformer(V, F)
    d.set_constraints(held, static, roi_radius=radius, roi_connected=connected, roi_from=handles)
    if connected:
        assert_over_surface(d.free_vertices, V, F, handles, np.union1d(held, static), radius)
    else:
        region = straight_line_region(V, handles, radius)
        np.testing.assert_array_equal(d.free_vertices, expected_free(region, held, static))
    everywhere = ed.Deformer(V, F)
    everywhere.set_constraints(held, static, roi_radius=radius, roi_connected=connected)
    assert len(everywhere.free_vertices) > len(d.free_vertices)   # the far pins grew a region of their own


def test_roi_from_refusals_leave_the_deformer_as_it_was():
    V, F, handles, static, targets = dino_case()
    d = ed.Deformer(V, F)
    d.set_constraints(handles, static, roi_radius=0.2 * diag(V))
    before = np.array(d.free_vertices)
    for kwargs, words in ((dict(roi_from=handles), "roi_from needs roi_radius"),
                          (dict(roi_radius=0.2 * diag(V), roi_from=[]), "roi_from is empty"),
                          (dict(roi_radius=1e-9 * diag(V), roi_from=static), "of roi_from")):
        with pytest.raises(ValueError, match=words):
            d.set_constraints(handles, static, **kwargs)
        np.testing.assert_array_equal(d.free_vertices, before)
    with pytest.raises(IndexError):
        d.set_constraints(handles, static, roi_radius=1.0, roi_from=[len(V)])


def test_a_region_builds_only_its_own_graph_and_matches_the_whole_one():
    # The Deformer builds the graph of the region's faces (record 0058); one whose whole
    # graph an inspection call built must give the same positions, bit for bit, and the
    # inspection calls must still describe the whole mesh.
    V, F, handles, static, targets = dino_case()
    lam = np.where(np.arange(len(V)) % 4 == 0, 0.9, 0.3)
    results = []
    for inspect_first in (False, True):
        d = ed.Deformer(V, F)
        n_nodes = d.n_nodes
        if inspect_first:
            assert len(d.edges()) == n_nodes == len(unique_edges(F))
        d.set_stiffness(lam)
        d.set_constraints(handles, static, roi_radius=0.2 * diag(V))
        results.append(np.asarray(d.solve(targets, max_iterations=8, tolerance=0.0).positions))
        assert d._whole_graph_built == inspect_first
    assert np.array_equal(results[0], results[1])
    assert np.allclose(d.node_stiffness(), lam[d.node_vertices()].mean(axis=1), rtol=0, atol=1e-15)
