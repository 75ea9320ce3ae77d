"""lambda = 1 in the primal domain is classic ARAP (Sorkine & Alexa 2007, spokes energy,
clamped cotangent weights): same positions and energies, step by step, as the small
dense solver in _reference.py."""

import numpy as np
import pytest

from _meshes import PLANE, SPOT, bend, diag, lift, load
from _reference import ClassicARAP
from _run import deformer

STEPS = (1, 2, 5, 20)


def _edits(V):
    # Out of the plane for the flat mesh (normal y): an in-plane edit of a flat mesh is
    # a symmetric saddle of ARAP, where round-off alone decides whether an iteration
    # buckles out of the plane, so two correct solvers may part ways there.
    flat = np.ptp(V[:, 1]) == 0
    return {"lift": lift(V, amount=0.15, static_frac=0.35, handle_frac=0.15,
                         direction=1 if flat else None),
            "bend": bend(V, degrees=40.0, static_frac=0.3, handle_frac=0.15,
                         about=2 if flat else None)}


@pytest.mark.parametrize("edit", ["lift", "bend"])
@pytest.mark.parametrize("name", [SPOT, PLANE])
def test_primal_lambda1_matches_classic_arap(name, edit):
    V, F = load(name)
    handles, static, targets = _edits(V)[edit]
    fixed = np.concatenate([handles, static])
    ref = ClassicARAP(V, F, fixed)
    assert len(ref.free) >= 200                      # "a few hundred" unknowns
    d = deformer(V, F, "primal", 1.0, handles, static)
    for k in STEPS:
        X_ref, E_ref = ref.solve(np.concatenate([targets, V[static]]), k)
        r = d.solve(targets, max_iterations=k, tolerance=0.0, warm_start=False,
                    acceleration="none")   # step by step: the plain iteration
        assert r.iterations == k
        np.testing.assert_allclose(r.positions, X_ref, rtol=0, atol=1e-9 * diag(V),
                                   err_msg=f"positions after {k} iterations")
        np.testing.assert_allclose(r.energies, E_ref, rtol=1e-7,
                                   err_msg=f"energies of {k} iterations")
    # The edit is not trivial: ARAP moved far from the naive solve.
    X1, _ = ref.solve(np.concatenate([targets, V[static]]), 1)
    assert np.abs(X_ref - X1).max() > 1e-3 * diag(V)


def test_energy_of_given_positions_is_classic_arap():
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.15)
    ref = ClassicARAP(V, F, np.concatenate([handles, static]))
    d = deformer(V, F, "primal", 1.0, handles, static)
    X = V + 0.02 * diag(V) * np.random.default_rng(0).standard_normal(V.shape)
    assert np.isclose(d.energy(X), ref.energy(X), rtol=1e-9)
