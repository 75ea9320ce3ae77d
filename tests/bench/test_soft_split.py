"""bench/soft_split.py and bench_spectrum.py --split: the split of a second difference into its
part along the soft modes and the rest adds up to the whole, finds a soft part that was put
there (on a synthetic self-adjoint map, where the answer is known, and on the package's own
J_G at a Spot fixed point), and (I - J)^-1 multiplies a soft mode by 1/(1 - mu)."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

import bench_spectrum  # noqa: E402
import soft_split  # noqa: E402

sp = pytest.importorskip("scipy.sparse")


def synthetic(n=40, soft=4, seed=3):
    """J = A^-1 D with A, D symmetric (A positive): the lambda = 1 structure. Returns A (sparse),
    J (dense), its eigenvalues (largest first) and A-orthonormal eigenvectors (columns)."""
    import scipy.linalg
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    A = M @ M.T + n * np.eye(n)
    # D = A V diag(mu) V^T A for an A-orthonormal V: J's eigenvalues are mu, soft ones near 1.
    mu = np.concatenate([1.0 - np.geomspace(1e-3, 1e-2, soft), rng.uniform(-0.5, 0.8, n - soft)])
    mu = np.sort(mu)[::-1]
    V = scipy.linalg.eigh(rng.standard_normal((n, n)) + n * np.eye(n), A)[1]  # A-orthonormal
    D = A @ V @ np.diag(mu) @ V.T @ A
    J = np.linalg.solve(A, D)
    return sp.csr_matrix(A), J, mu, V


def as_points(columns, c=0):
    """Vectors (n, k) -> (k, n, 3) arrays with the vector in coordinate c."""
    out = np.zeros((columns.shape[1], columns.shape[0], 3))
    out[:, :, c] = columns.T
    return out


def test_synthetic_split_is_spectral_and_adds_up():
    A, J, mu, V = synthetic()
    soft = 4
    basis = as_points(V[:, :soft] * np.arange(1, soft + 1))  # any scaling of the eigenvectors
    P = soft_split.SoftProjection(basis, A)
    alpha = np.array([0.3, -1.0, 0.0, 2.0])
    beta = np.random.default_rng(0).standard_normal(V.shape[0] - soft)
    known_soft = as_points(V[:, :soft] @ alpha[:, None])[0]
    known_rest = as_points(V[:, soft:] @ beta[:, None])[0]
    s = known_soft + known_rest
    part, rest = P.split(s)
    assert np.abs(part + rest - s).max() <= 1e-14 * np.abs(s).max()  # they add up to the whole
    assert np.abs(part - known_soft).max() < 1e-10 * np.abs(s).max()
    assert np.abs(rest - known_rest).max() < 1e-10 * np.abs(s).max()
    assert abs(P.inner(part, rest)) < 1e-10 * P.inner(s, s)  # A-orthogonal
    assert np.abs(P.soft(part) - part).max() < 1e-12 * np.abs(s).max()  # a projection

    # (I - J)^-1 by GMRES in the A inner product: the soft part comes back divided by 1 - mu.
    def operator(w):
        return w - J @ w
    w, iterations, estimate = soft_split.gmres(operator, s, P.apply_A, tolerance=1e-12)
    assert np.abs(w - np.linalg.solve(np.eye(len(mu)) - J, s)).max() < 1e-8 * np.abs(w).max()
    assert iterations <= len(mu) and estimate < 1e-11
    amplified = as_points(V[:, :soft] @ (alpha / (1 - mu[:soft]))[:, None])[0]
    assert np.abs(P.soft(w) - amplified).max() < 1e-8 * np.abs(amplified).max()

    # A Euclidean least-squares split does not find the soft part of a non-normal J.
    ls = soft_split.SoftProjection(basis)
    assert np.abs(ls.soft(s) - known_soft).max() > 0.01 * np.abs(known_soft).max()


def test_dependent_vectors_span_once():
    """A complex pair gives its real and imaginary parts once each: conjugate members add
    nothing to the span."""
    A, _, _, V = synthetic()
    pair = as_points(V[:, :2])
    basis = np.concatenate([pair, pair, 2.0 * pair[:1]])
    assert soft_split.SoftProjection(basis, A).rank == 2


@pytest.fixture(scope="module")
def spot():
    import edgedeform as ed
    d, targets, free, dg = bench_spectrum.problem(ed, ("spot", "lift", "edge", 1.0))
    X, *_ = bench_spectrum.reference(d, targets)
    split = bench_spectrum.SoftSplit(d, X, free, 1.0, 12, lambda s: None)
    return d, targets, free, dg, X, split


def test_split_of_the_packages_map(spot):
    """At a Spot fixed point (lambda 1): A is the core's (checked), J is self-adjoint in its
    inner product, a second difference's parts add up to it and are A-orthogonal, a soft
    part put into a vector is found, and (I - J)^-1 divides a soft eigenvector by 1 - mu."""
    d, targets, free, dg, X, split = spot
    assert split.summary["a_identity_error"] < 1e-12 and split.summary["asymmetry"] < 1e-10
    assert split.summary["rank"] == 12 and split.summary["ritz_residual_max"] < 1e-5
    P = split.projection
    v = split.vectors[0].real
    v = v * (dg / np.linalg.norm(v, axis=1).max())
    G = bench_spectrum.one_step_map(d, targets)
    s = bench_spectrum.second_difference(G, X, free, v, 1e-3, G(X))
    part, rest = P.split(s)
    assert np.abs(part + rest - s).max() <= 1e-14 * np.abs(s).max()
    assert abs(P.inner(part, rest)) < 1e-9 * P.inner(s, s)
    assert 0.0 < P.inner(part, part) < P.inner(s, s)

    other = np.random.default_rng(4).standard_normal(v.shape)
    other -= P.soft(other)  # no soft part
    planted = 0.3 * v + other
    assert np.abs(P.soft(planted) - 0.3 * v).max() < 1e-8 * np.abs(v).max()

    w, stats = split.solve(v)
    mu = split.mu[0].real
    assert stats["residual"] < 1e-7
    assert np.abs(w - v / (1 - mu)).max() < 1e-5 * np.abs(w).max()


def test_split_option_writes_its_table(tmp_path):
    """--split: c_soft is a constant over the two steps, the split at lambda 1 is spectral
    (the commutator is round-off), a Newton step from 3e-4 of the diagonal along the slowest
    mode lands quadratically close, and the Markdown tables carry the rows."""
    out = tmp_path / "split.json"
    bench_spectrum.main(["--cells", "spot:lift:edge:1", "--steps", "40", "--radius", "2",
                         "--split", "20", "--json", str(out)])
    result = json.loads(out.read_text())
    row = result["rows"][0]
    assert row["soft"]["count"] == 20 and len(row["model_radius"]) == 2
    first = row["model_radius"][0]["split"]
    c_small, c_large = first["soft"]["curvature"]
    assert c_small > 0 and abs(c_large / c_small - 1) < 0.1
    assert first["amplified"]["commutator"] < 1e-6
    assert first["amplified"]["solve_residual"] < 1e-7
    near = [n for n in row["newton_steps"] if n["h"] == min(bench_spectrum.NEWTON_FROM)]
    assert all(n["after"] < 0.05 * n["before"] for n in near), near
    table = bench_spectrum.split_markdown(result)
    assert f"| spot lift edge λ 1 | {row['model_radius'][0]['modulus']:.5f} |" in table
    assert "| spot lift edge λ 1 | valley |" in table
