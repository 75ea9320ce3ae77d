"""The soft part of the one-step map's second difference, for bench_spectrum.py --split.

At the fixed point x* the Newton step for F(x) = x - G(x) solves (I - J) delta = -F, so
from x* + e it leaves the error -1/2 (I - J)^-1 G''[e, e] (to second order): a component of
the second-order term along a mode of eigenvalue mu comes back multiplied by 1/(1 - mu),
large on the soft modes (mu near 1), about 1 on the stiff ones. This module splits a second
difference s into its part along the soft modes and the rest, and applies (I - J)^-1:

- the soft modes: the k largest eigenpairs of the analytic J_G at x* (ARPACK, through
  newton_model.spectrum: converged to 1e-6, where the script's own 100-step
  finite-difference Arnoldi resolves only the first few of the koala's cluster of
  eigenvalues above 0.99);
- the projection (SoftProjection): at lambda = 1, J_G = A^-1 D with A and D symmetric, so J
  is self-adjoint in the A inner product <u, w>_A = u^T A w, its eigenvectors are
  A-orthogonal, and the A-orthogonal projection onto the soft eigenvectors is the spectral
  projector: the rest has no component along any soft mode, and (I - J) maps each part into
  itself. At lambda < 1, D is not symmetric, but J stays nearly self-adjoint in A's inner
  product (A carries the mesh's ill-conditioning; the script measures the asymmetry per
  cell), so the A-orthogonal split stays close to spectral; how close is measured per mode
  (the commutator figure of bench_spectrum.SoftSplit). A Euclidean least-squares split is
  far from spectral even at lambda = 1 (its two parts, each multiplied by (I - J)^-1, come
  out several times larger than their sum: they cancel; record 0028), so it is only
  measured beside, for the slowest mode. A comes from the graph
  (newton_model.system_matrix) and is checked against the core's
  K v = A (I - J) v before use;
- (I - J)^-1 by GMRES on (I - J) w = y with the analytic J products (each a back-substitution
  with A's factor, so the system is A-preconditioned), in the A inner product at lambda = 1
  (where I - J is self-adjoint: GMRES is then MINRES; at lambda < 1 nearly so), to a relative
  residual of SOLVE_TOLERANCE; the true residual is measured after the solve.

Vectors over the free vertices are (#free, 3) arrays, in the order of Deformer.free_vertices
(which is increasing, the order of bench_spectrum's free mask: checked).
"""

import numpy as np

# Eigenpairs of J_G asked of ARPACK: the soft subspace is spanned by them (complex pairs by
# the real and imaginary parts of their vectors).
SOFT_COUNT = 50
SOLVE_TOLERANCE = 1e-8
SOLVE_ITERATIONS = 1500


def frobenius(a, b):
    return float(np.sum(a * b))


class SoftProjection:
    """P: the projection onto span(basis) along the complement orthogonal to it in the inner
    product of `A` (an (n, n) sparse symmetric positive matrix acting on each coordinate) or,
    with A None, the Euclidean one (least squares). basis: (k, #free, 3)."""

    def __init__(self, basis, A=None):
        self.A = A
        flat = basis.reshape(len(basis), -1)
        # An orthonormal (Euclidean) basis of the span first: a complex pair's conjugate
        # members give the same real and imaginary parts; drop what is dependent.
        u, sigma, vt = np.linalg.svd(flat, full_matrices=False)
        keep = sigma > 1e-10 * sigma[0]
        self.basis = vt[keep].reshape((-1,) + basis.shape[1:])
        self.rank = int(keep.sum())
        self.A_basis = np.stack([self.apply_A(b) for b in self.basis])
        gram = np.einsum("kij,lij->kl", self.basis, self.A_basis)
        self.gram_inverse = np.linalg.inv(gram)

    def apply_A(self, w):
        return w if self.A is None else np.asarray(self.A @ w)

    def inner(self, u, w):
        return frobenius(u, self.apply_A(w))

    def coefficients(self, s):
        return self.gram_inverse @ np.einsum("kij,ij->k", self.A_basis, s)

    def soft(self, s):
        """P s: s's part along the soft subspace."""
        return np.einsum("k,kij->ij", self.coefficients(s), self.basis)

    def split(self, s):
        """(P s, s - P s): the two parts add up to s exactly."""
        soft = self.soft(s)
        return soft, s - soft


def gmres(apply, b, metric, tolerance=SOLVE_TOLERANCE, max_iterations=SOLVE_ITERATIONS):
    """Solves apply(w) = b (arrays of b's shape) by unrestarted GMRES in the inner product
    <u, w> = u . metric(w) (classical Gram-Schmidt twice, Givens rotations; the basis is kept
    with its metric images, so one metric product per iteration). Returns (w, iterations,
    residual estimate relative to |b|)."""
    shape, b = b.shape, b.ravel()
    Mb = metric(b.reshape(shape)).ravel()
    beta = np.sqrt(b @ Mb)
    if beta == 0.0:
        return np.zeros(shape), 0, 0.0
    Q = np.empty((max_iterations + 1, b.size))   # pages are committed only as used
    MQ = np.empty_like(Q)
    Q[0], MQ[0] = b / beta, Mb / beta
    H = np.zeros((max_iterations + 1, max_iterations))
    cs, sn = np.zeros(max_iterations), np.zeros(max_iterations)
    g = np.zeros(max_iterations + 1)
    g[0] = beta
    k = 0
    for k in range(max_iterations):
        w = apply(Q[k].reshape(shape)).ravel()
        for _ in range(2):
            h = MQ[:k + 1] @ w
            H[:k + 1, k] += h
            w = w - h @ Q[:k + 1]
        Mw = metric(w.reshape(shape)).ravel()
        H[k + 1, k] = np.sqrt(max(w @ Mw, 0.0))
        for j in range(k):  # earlier rotations on the new column
            H[j, k], H[j + 1, k] = (cs[j] * H[j, k] + sn[j] * H[j + 1, k],
                                    -sn[j] * H[j, k] + cs[j] * H[j + 1, k])
        r = np.hypot(H[k, k], H[k + 1, k])
        next_norm = H[k + 1, k]
        cs[k], sn[k] = H[k, k] / r, H[k + 1, k] / r
        H[k, k], H[k + 1, k] = r, 0.0
        g[k + 1], g[k] = -sn[k] * g[k], cs[k] * g[k]
        if abs(g[k + 1]) <= tolerance * beta or next_norm == 0.0:
            break
        Q[k + 1], MQ[k + 1] = w / next_norm, Mw / next_norm
    n = k + 1
    y = np.linalg.solve(np.triu(H[:n, :n]), g[:n])
    return (y @ Q[:n]).reshape(shape), n, float(abs(g[n]) / beta)


class NewtonSolve:
    """w = (I - J)^-1 y at X, J the core's analytic J_G (Deformer._jacobian), by GMRES in the
    inner product of `projection` (A's)."""

    def __init__(self, d, X, projection):
        self.d, self.X, self.projection = d, X, projection
        self.products = 0

    def operator(self, w):
        self.products += 1
        return w - np.asarray(self.d._jacobian(self.X, np.ascontiguousarray(w)))

    def __call__(self, y):
        inner = self.projection.inner
        w, iterations, _ = gmres(self.operator, y, self.projection.apply_A)
        r = y - self.operator(w)  # the true residual, not GMRES's estimate
        norm = np.sqrt(inner(y, y))
        residual = float(np.sqrt(inner(r, r)) / norm) if norm > 0 else 0.0
        return w, {"iterations": iterations, "residual": residual}


def soft_eigenpairs(d, X, count, log):
    """The `count` largest eigenpairs of the analytic J_G at X (ARPACK; complex pairs as
    ARPACK returns them), vectors as (count, #free, 3), each turned so that its largest entry
    is real and positive (ARPACK's sign is arbitrary; a step along +v is then the same step
    in every run), and the spectrum's summary row."""
    from newton_model import spectrum, to_points  # SciPy's ARPACK: only when measuring
    nf = len(d.free_vertices)
    mu, vecs, row = spectrum(d, X, nf, count, log)
    largest = vecs[np.abs(vecs).argmax(axis=0), np.arange(vecs.shape[1])]
    vecs = vecs * (np.abs(largest) / largest)
    vectors = np.stack([to_points(vecs[:, j].real, nf) + 1j * to_points(vecs[:, j].imag, nf)
                        for j in range(len(mu))])
    return mu, vectors, row


def projection_at(d, X, lam, vectors, rng_seed=0):
    """The A-orthogonal SoftProjection onto the span of `vectors` (see the module's
    docstring), after A (newton_model.system_matrix at this uniform lambda) is
    checked against the core's K v = A (v - J v); and how far J is from self-adjoint in A's
    inner product, |<u, J w>_A - <J u, w>_A| / (|J u|_A |w|_A) on random u, w (0 to round-off
    at lambda = 1)."""
    basis = np.concatenate([vectors.real, vectors.imag[np.abs(vectors.imag).max(axis=(1, 2)) > 0]])
    from newton_model import a_identity_error, system_matrix
    fv = np.asarray(d.free_vertices)
    A3, A = system_matrix(d, fv, lam)
    rng = np.random.default_rng(rng_seed)
    error = a_identity_error(d, X, A3, len(fv), rng)
    if error > 1e-10:
        raise SystemExit(f"A is not the matrix the core uses at lambda {lam:g} (K v against "
                         f"A (v - J v): {error:.1e}): the A-orthogonal split would be wrong")
    projection = SoftProjection(basis, A.tocsr())
    u, w = rng.standard_normal((2,) + vectors.shape[1:])
    Ju, Jw = (np.asarray(d._jacobian(X, z)) for z in (u, w))
    inner = projection.inner
    asymmetry = abs(inner(u, Jw) - inner(Ju, w)) / np.sqrt(inner(Ju, Ju) * inner(w, w))
    return projection, basis, {"a_identity_error": error, "asymmetry": float(asymmetry)}
