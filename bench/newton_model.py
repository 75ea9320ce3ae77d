"""The linear model of the one-step map G at a point, for the bench scripts that study it
(bench_spectrum.py --split through soft_split.py): J_G's products, the global step's
matrix A at a uniform lambda, and J_G's largest eigenpairs, all over the free coordinates
and all from the package's analytic derivative (Deformer._jacobian).

A flat vector over the free coordinates holds all x, then all y, then all z (to_flat);
the package takes and returns (#free, 3) arrays (to_points). The core's Newton operator is
K v = A (v - J v) (Deformer._jacobian(X, v, True)); a_identity_error checks A against it,
so a wrong A (another lambda, a missing term) is caught before anything is measured with it.
"""

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

ARPACK_TOL = 1e-6
RANDOM_CHECKS = 3   # random vectors the A identity is checked on


def to_flat(M):
    return np.asarray(M).T.ravel()


def to_points(v, nf):
    return np.ascontiguousarray(v.reshape(3, nf).T)


def coo_matrix(t):
    rows, cols, vals, shape = t
    return sp.csr_matrix((vals, (rows, cols)), shape=tuple(shape))


def system_matrix(d, free, lam=1.0):
    """(A3, A): A at a uniform lambda over the free vertices, on one coordinate, and A3 its
    copy on each of the three. The edge domain's A (no similarity share): the 1-form arcs
    2 lambda (N^T L N)_ff plus the Laplacian rows (1 - lambda) ((L N)^T (L N))_ff."""
    N = coo_matrix(d._node_matrix_coo())
    L = coo_matrix(d._laplacian_coo())
    A = 2.0 * lam * (N.T @ L @ N)
    if lam != 1.0:
        LN = L @ N
        A = A + (1.0 - lam) * (LN.T @ LN)
    A = A.tocsr()[free][:, free]
    return sp.block_diag([A, A, A], format="csr"), A


def a_identity_error(d, X, A3, nf, rng):
    """max over random v of |K v - A (v - J v)| / |K v|: 0 to round-off when A is right."""
    worst = 0.0
    for _ in range(RANDOM_CHECKS):
        v = rng.standard_normal(3 * nf)
        P = to_points(v, nf)
        Kv = to_flat(d._jacobian(X, P, True))
        Jv = to_flat(d._jacobian(X, P))
        worst = max(worst, float(np.linalg.norm(Kv - A3 @ (v - Jv)) / np.linalg.norm(Kv)))
    return worst


def spectrum(d, X, nf, k, log):
    """The k largest-modulus eigenpairs of J_G at X (ARPACK on J products; the pairs that
    converged when not all did), largest first, and a row: how many were found, the J
    products and seconds they took, and each pair's residual |J v - mu v| / |v|."""
    n = 3 * nf
    count = [0]

    def J(v):
        count[0] += 1
        return to_flat(d._jacobian(X, to_points(np.real(v).astype(float), nf)))

    op = spla.LinearOperator((n, n), matvec=J, dtype=float)
    t0 = time.perf_counter()
    v0 = np.random.default_rng(0).standard_normal(n)
    try:
        mu, vecs = spla.eigs(op, k=k, which="LM", tol=ARPACK_TOL, v0=v0,
                             ncv=min(n - 1, max(2 * k + 1, k + 40)), maxiter=60)
    except spla.ArpackNoConvergence as e:
        mu, vecs = e.eigenvalues, e.eigenvectors
    seconds = time.perf_counter() - t0
    order = np.argsort(-np.abs(mu))
    mu, vecs = mu[order], vecs[:, order]
    residuals = []
    for j in range(len(mu)):  # J applied to the real and imaginary parts
        v = vecs[:, j]
        Jv = J(v.real) + 1j * J(v.imag)
        residuals.append(float(np.linalg.norm(Jv - mu[j] * v) / np.linalg.norm(v)))
    mod = np.abs(mu)
    log(f"  spectrum: {len(mu)} Ritz pairs in {count[0]} products, {seconds:.0f} s; largest "
        f"{', '.join(f'{m:.5f}' for m in mod[:5])}")
    row = {"requested": k, "found": int(len(mu)), "products": count[0], "seconds": seconds,
           "ritz_residuals": residuals}
    return mu, vecs, row
