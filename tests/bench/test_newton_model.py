"""bench/newton_model.py on the 829-vertex Spot lift: A is the core's at each lambda (and a
wrong lambda is caught), and the spectrum's pairs are J_G's largest, largest first,
resolved, as J_G built column by column gives them."""

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

import bench_spectrum  # noqa: E402

newton_model = pytest.importorskip("newton_model")  # needs SciPy


def test_system_matrix_below_lambda_one():
    """The A at lambda < 1 is the core's: 2 lambda N^T L N + (1 - lambda) (LN)^T LN."""
    import edgedeform as ed
    d, targets, free, _ = bench_spectrum.problem(ed, ("spot", "lift", "edge", 0.5))
    X = np.asarray(d.solve(targets, max_iterations=20).positions)
    fv = np.asarray(d.free_vertices)
    A3, _ = newton_model.system_matrix(d, fv, 0.5)
    assert newton_model.a_identity_error(d, X, A3, len(fv), np.random.default_rng(0)) < 1e-12
    A3, _ = newton_model.system_matrix(d, fv, 1.0)  # the wrong lambda is caught
    assert newton_model.a_identity_error(d, X, A3, len(fv), np.random.default_rng(0)) > 1e-3


def test_spectrum_is_the_largest_of_the_dense_jacobian():
    import edgedeform as ed
    d, targets, free, _ = bench_spectrum.problem(ed, ("spot", "lift", "edge", 1.0))
    X, *_ = bench_spectrum.reference(d, targets)
    nf = len(d.free_vertices)
    mu, vecs, row = newton_model.spectrum(d, X, nf, 8, lambda s: None)
    mod = np.abs(mu)
    assert row["found"] == 8 == len(mu) == vecs.shape[1] and row["products"] > 0
    assert (np.diff(mod) <= 1e-12).all()              # largest first
    assert 0.5 < mod[0] < 1.0                          # a stable fixed point: contracting
    assert max(row["ritz_residuals"]) < 1e-6

    def column(j):
        e = np.zeros(3 * nf)
        e[j] = 1.0
        return newton_model.to_flat(d._jacobian(X, newton_model.to_points(e, nf)))
    dense = np.sort(np.abs(np.linalg.eigvals(np.column_stack([column(j) for j in range(3 * nf)]))))[::-1]
    assert np.abs(mod[:4] - dense[:4]).max() < 1e-6
