"""J_G's soft modes, for the diagnostics that choose how the solver reaches the fixed point
(bench/bench_soft_modes.py, docs/decisions/0070): the global step's matrix A, the largest
eigenpairs of the one-step map's Jacobian J_G = A^-1 D at a point, and how much of an error
lies in their span, all over the free vertices and from the package's analytic derivative
(Deformer._jacobian).

Inner product: A's. At lambda = 1 J_G is self-adjoint in it (A and D symmetric), its
eigenvectors are A-orthogonal and the A-orthogonal projection onto the top p of them is the
spectral projector; the A norm is the energy norm of an error. At lambda < 1 J_G is nearly
self-adjoint in A (record 0028 measured the asymmetry): the span is still its invariant
subspace, projected A-orthogonally.

Vectors over the free vertices: (#free, 3) arrays in Deformer.free_vertices order; flat
vectors hold all x, then all y, then all z (to_flat). A acts on each coordinate alike.
"""

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

EIGEN_TOL = 1e-6      # ARPACK's relative tolerance on the Ritz values
IDENTITY_CHECKS = 3   # random vectors the A identity K v = A (v - J v) is checked on


def to_flat(M):
    return np.asarray(M).T.ravel()


def to_points(v, nf):
    return np.ascontiguousarray(np.asarray(v).reshape(3, nf).T)


def coo_matrix(t):
    rows, cols, vals, shape = t
    return sp.csr_matrix((vals, (rows, cols)), shape=tuple(shape))


def system_matrix(d, lam):
    """A over the free vertices on one coordinate, at a uniform lambda, edge domain: the
    1-form arcs 2 lambda (N^T L N)_ff plus the Laplacian rows (1 - lambda) ((L N)^T (L N))_ff.
    Checked against the core (identity_error) before anything is measured with it."""
    free = np.asarray(d.free_vertices)
    N = coo_matrix(d._node_matrix_coo())
    L = coo_matrix(d._laplacian_coo())
    A = 2.0 * lam * (N.T @ L @ N)
    if lam != 1.0:
        LN = L @ N
        A = A + (1.0 - lam) * (LN.T @ LN)
    return A.tocsr()[free][:, free].tocsc()


class Linearization:
    """J_G and A at the full positions X (n, 3) of a Deformer whose constraints are set."""

    def __init__(self, d, X, lam):
        self.d, self.X, self.lam = d, np.ascontiguousarray(X, dtype=float), lam
        self.nf = len(d.free_vertices)
        self.A = system_matrix(d, lam)
        self._solve_A = spla.factorized(self.A)
        self.products = 0
        err = self.identity_error(np.random.default_rng(1))
        if err > 1e-8:
            raise RuntimeError(f"A does not match the core's K = A (I - J): relative error {err:.1e}")

    def J(self, P):
        """J_G P for P (#free, 3)."""
        self.products += 1
        return np.asarray(self.d._jacobian(self.X, np.ascontiguousarray(P)))

    def K(self, P):
        """K P = A (P - J_G P), the core's Newton operator (no back-substitution)."""
        self.products += 1
        return np.asarray(self.d._jacobian(self.X, np.ascontiguousarray(P), True))

    def apply_A(self, P):
        return np.asarray(self.A @ P)

    def solve_A(self, P):
        return np.column_stack([self._solve_A(np.ascontiguousarray(P[:, c])) for c in range(3)])

    def identity_error(self, rng):
        worst = 0.0
        for _ in range(IDENTITY_CHECKS):
            P = rng.standard_normal((self.nf, 3))
            Kp = self.K(P)
            worst = max(worst, float(np.linalg.norm(Kp - self.apply_A(P - self.J(P))) / np.linalg.norm(Kp)))
        return worst

    def a_inner(self, U, W):
        return float(np.sum(U * self.apply_A(W)))


def a_orthonormal(lin, vectors):
    """An A-orthonormal basis (k, #free, 3) of the span of `vectors` (k, #free, 3), in their
    order (Gram-Schmidt, twice), so that its first j vectors span the first j given; a vector
    dependent on those before it (a complex pair's second part, say) is dropped."""
    basis, A_basis = [], []
    for v in vectors:
        w = np.array(v, dtype=float)
        norm0 = np.sqrt(lin.a_inner(w, w))
        for _ in range(2):
            for b, Ab in zip(basis, A_basis):
                w -= float(np.sum(w * Ab)) * b
        norm = np.sqrt(lin.a_inner(w, w))
        if norm > 1e-8 * norm0:
            basis.append(w / norm)
            A_basis.append(lin.apply_A(basis[-1]))
    return np.stack(basis)


def top_modes(lin, p, seed=0):
    """The p largest eigenvalues of J_G and an A-orthonormal basis of their eigenvectors,
    largest first, and a row (products, seconds, converged pairs). lambda = 1: the symmetric
    generalized problem D v = mu A v (ARPACK's mode 2, D = A - K, largest algebraic);
    lambda < 1: J_G itself (largest modulus), the span A-orthonormalized."""
    nf, n = lin.nf, 3 * lin.nf
    before, t0 = lin.products, time.perf_counter()
    v0 = np.random.default_rng(seed).standard_normal(n)
    ncv = min(n - 1, max(2 * p + 1, p + 40))
    if lin.lam == 1.0:
        def D(v):
            P = to_points(v, nf)
            return to_flat(lin.apply_A(P) - lin.K(P))
        A3 = sp.block_diag([lin.A] * 3, format="csr")
        op = spla.LinearOperator((n, n), matvec=D, dtype=float)
        inv = spla.LinearOperator((n, n), matvec=lambda v: to_flat(lin.solve_A(to_points(v, nf))), dtype=float)
        try:
            mu, vecs = spla.eigsh(op, k=p, M=A3, Minv=inv, which="LA", tol=EIGEN_TOL, v0=v0, ncv=ncv)
        except spla.ArpackNoConvergence as e:
            mu, vecs = e.eigenvalues, e.eigenvectors
        order = np.argsort(-mu)
        mu, vecs = mu[order], vecs[:, order]
        basis = np.stack([to_points(vecs[:, j], nf) for j in range(len(mu))])
        basis = basis / np.sqrt([lin.a_inner(b, b) for b in basis])[:, None, None]
    else:
        op = spla.LinearOperator((n, n), matvec=lambda v: to_flat(lin.J(to_points(np.real(v), nf))), dtype=float)
        try:
            mu, vecs = spla.eigs(op, k=p, which="LM", tol=EIGEN_TOL, v0=v0, ncv=ncv)
        except spla.ArpackNoConvergence as e:
            mu, vecs = e.eigenvalues, e.eigenvectors
        order = np.argsort(-np.abs(mu))
        mu, vecs = mu[order], vecs[:, order]
        parts = []
        for j in range(len(mu)):   # a complex pair spans its vectors' real and imaginary parts
            parts.append(to_points(vecs[:, j].real, nf))
            if abs(mu[j].imag) > 0:
                parts.append(to_points(vecs[:, j].imag, nf))
        basis = a_orthonormal(lin, np.stack(parts))
    row = {"requested": p, "found": int(len(mu)), "products": lin.products - before,
           "seconds": time.perf_counter() - t0}
    return mu, basis, row


def captured_fraction(lin, basis, e):
    """The fraction (A norm) of the error e (#free, 3) in the span of an A-orthonormal basis:
    |P e|_A / |e|_A, with P the A-orthogonal projection."""
    coeffs = np.einsum("kij,ij->k", basis, lin.apply_A(e))
    return float(np.linalg.norm(coeffs) / np.sqrt(lin.a_inner(e, e)))
