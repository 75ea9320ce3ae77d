"""Hard constraints (docs/design.md §3): handles exactly on targets, static vertices and
vertices outside the region of interest exactly at rest."""

import numpy as np
import pytest

from _meshes import DINO, PLANE, PEAKS, diag, lift, load, up_axis
from _run import deformer


@pytest.mark.parametrize("lam", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("domain", ["edge", "primal"])
@pytest.mark.parametrize("name", [DINO, PLANE])
def test_handles_on_targets_static_at_rest(name, domain, lam):
    V, F = load(name)
    handles, static, targets = lift(V, amount=0.2)
    d = deformer(V, F, domain, lam, handles, static)
    r = d.solve(targets, max_iterations=10)
    X = np.asarray(r.positions)
    assert X.shape == V.shape and X.dtype == np.float64
    assert np.array_equal(X[handles], targets)        # exactly, not approximately
    assert np.array_equal(X[static], V[static])
    free = np.setdiff1d(np.arange(len(V)), np.concatenate([handles, static]))
    assert r.free_vertices == len(free)
    assert np.abs(X[free] - V[free]).max() > 0.01 * diag(V)


@pytest.mark.parametrize("domain", ["edge", "primal"])
@pytest.mark.parametrize("name", [DINO, PEAKS])
def test_outside_roi_stays_at_rest(name, domain):
    V, F = load(name)
    ax = up_axis(V)
    h = V[:, ax]
    # ROI: upper half; handles: top 10%; static: a band just inside the ROI's bottom.
    roi = np.flatnonzero(h >= np.quantile(h, 0.5))
    handles = np.flatnonzero(h >= np.quantile(h, 0.9))
    static = np.flatnonzero((h >= np.quantile(h, 0.5)) & (h < np.quantile(h, 0.55)))
    targets = V[handles] + np.eye(3)[ax] * 0.1 * diag(V)
    d = deformer(V, F, domain, 0.5, handles, static, roi=roi)
    r = d.solve(targets, max_iterations=10)
    X = np.asarray(r.positions)
    outside = np.setdiff1d(np.arange(len(V)), roi)
    assert np.array_equal(X[outside], V[outside])
    assert np.array_equal(X[handles], targets)
    assert np.array_equal(X[static], V[static])
    inside_free = np.setdiff1d(roi, np.concatenate([handles, static]))
    assert r.free_vertices == len(inside_free)
    assert np.abs(X[inside_free] - V[inside_free]).max() > 0.01 * diag(V)
    # only nodes whose terms touch a free vertex are assembled (docs/design.md §3, region of interest)
    assert 0 < r.active_nodes < d.n_nodes


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_roi_result_equals_static_outside(domain):
    """An ROI is the same problem as making everything outside it static."""
    V, F = load(PEAKS)
    ax = up_axis(V)
    h = V[:, ax]
    roi = np.flatnonzero(h >= np.quantile(h, 0.4))
    handles = np.flatnonzero(h >= np.quantile(h, 0.9))
    targets = V[handles] + 0.1 * diag(V) * np.eye(3)[(ax + 1) % 3]
    outside = np.setdiff1d(np.arange(len(V)), roi)
    a = deformer(V, F, domain, 0.5, handles, (), roi=roi).solve(targets, max_iterations=8,
                                                                 tolerance=0.0)
    b = deformer(V, F, domain, 0.5, handles, outside).solve(targets, max_iterations=8,
                                                             tolerance=0.0)
    np.testing.assert_allclose(a.positions, b.positions, rtol=0, atol=1e-9 * diag(V))
