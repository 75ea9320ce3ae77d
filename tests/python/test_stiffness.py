"""Per-vertex stiffness (paper section 3.2.4): lambda = 1 on one half of a mesh and 0
on the other; each half's mean edge-length strain lies between the two uniform
results."""

import numpy as np
import pytest

from _meshes import DINO, PLANE, edge_strain, lift, load, up_axis
from _run import deformer


def _split(V):
    """Halves across an axis other than the lift direction, so both halves carry the
    same edit."""
    ax = up_axis(V)
    ext = np.ptp(V, axis=0)
    ext[ax] = -1
    side = int(np.argmax(ext))
    return V[:, side] < np.median(V[:, side])


@pytest.mark.parametrize("domain", ["edge", "primal"])
@pytest.mark.parametrize("name", [DINO, PLANE])
def test_half_stiff_half_soft_strain_between_uniform(name, domain):
    V, F = load(name)
    handles, static, targets = lift(V, amount=0.2)
    stiff_half = _split(V)
    lam_mixed = np.where(stiff_half, 1.0, 0.0)
    results = {}
    for key, lam in (("soft", 0.0), ("stiff", 1.0), ("mixed", lam_mixed)):
        d = deformer(V, F, domain, lam, handles, static)
        r = d.solve(targets, max_iterations=200, tolerance=1e-5)
        assert np.all(np.isfinite(r.positions))
        results[key] = np.asarray(r.positions)
    for half in (stiff_half, ~stiff_half):
        means = {}
        for key, X in results.items():
            s, E = edge_strain(V, X, F)
            inside = half[E[:, 0]] & half[E[:, 1]]
            means[key] = s[inside].mean()
        lo, hi = sorted((means["soft"], means["stiff"]))
        assert hi > 1.05 * lo, f"uniform results too close to tell apart: {means}"
        assert lo <= means["mixed"] <= hi, f"half strain outside the uniform range: {means}"
