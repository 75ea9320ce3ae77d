"""Independent reference computations for the tests (no edgedeform code used).

Everything here starts from finite-element gradients rather than cotangent formulas, so
that an error in the core's cotangents cannot hide in the reference as well.
"""

import numpy as np
import scipy.linalg
import scipy.sparse as sp


def barycentric_gradients(V, F):
    """grad lambda_k on every triangle: (m,3,3) [triangle, corner, xyz], and areas (m,)."""
    x = V[F]                                            # (m,3,3)
    n = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    dbl = np.linalg.norm(n, axis=1)                     # 2 * area
    nh = n / dbl[:, None]
    G = np.empty_like(x)
    for k in range(3):
        # grad lambda_k is perpendicular to the opposite edge, in the plane, |.| = 1/h_k
        e = x[:, (k + 2) % 3] - x[:, (k + 1) % 3]
        G[:, k] = np.cross(nh, e) / dbl[:, None]
    return G, dbl / 2


def p1_stiffness(V, F):
    """K_ij = sum_t area_t grad phi_i . grad phi_j (hat functions), sparse (n,n)."""
    G, A = barycentric_gradients(V, F)
    rows, cols, vals = [], [], []
    for i in range(3):
        for j in range(3):
            rows.append(F[:, i])
            cols.append(F[:, j])
            vals.append(A * np.einsum("md,md->m", G[:, i], G[:, j]))
    n = len(V)
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n))


def cr_stiffness(V, F, edges):
    """Crouzeix-Raviart stiffness, nodes = `edges` (row order given by the caller).

    The nonconforming basis function of the edge opposite corner k of a triangle is
    phi = 1 - 2 lambda_k, so grad phi = -2 grad lambda_k.
    """
    index = {(int(a), int(b)): i for i, (a, b) in enumerate(edges)}
    G, A = barycentric_gradients(V, F)
    m = len(F)
    node = np.empty((m, 3), dtype=np.int64)             # node of the edge opposite corner k
    for t in range(m):
        for k in range(3):
            a, b = F[t, (k + 1) % 3], F[t, (k + 2) % 3]
            node[t, k] = index[(min(a, b), max(a, b))]
    rows, cols, vals = [], [], []
    for i in range(3):
        for j in range(3):
            rows.append(node[:, i])
            cols.append(node[:, j])
            vals.append(4.0 * A * np.einsum("md,md->m", G[:, i], G[:, j]))
    ne = len(edges)
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(ne, ne))


def closest_rotations(S):
    """R_k maximising tr(R_k S_k) for a stack S (k,3,3), reflections fixed."""
    U, _, Vt = np.linalg.svd(S)
    R = np.einsum("kji,klj->kil", Vt, U)               # V U^T
    bad = np.linalg.det(R) < 0
    if np.any(bad):
        U = U.copy()
        U[bad, :, 2] *= -1                              # column of the smallest singular value
        R[bad] = np.einsum("kji,klj->kil", Vt[bad], U[bad])
    return R


class ClassicARAP:
    """Sorkine & Alexa 2007 as-rigid-as-possible, spokes energy, clamped cotangent
    weights w_ij = max(0, 1/2 (cot a + cot b)), hard constraints, dense Cholesky."""

    def __init__(self, V0, F, fixed):
        self.V0 = np.asarray(V0, dtype=float)
        n = len(V0)
        K = p1_stiffness(self.V0, F).toarray()
        W = np.maximum(-K, 0.0)                          # off-diagonal weights, clamped
        np.fill_diagonal(W, 0.0)
        self.W = W
        L = np.diag(W.sum(axis=1)) - W
        self.fixed = np.asarray(fixed)
        mask = np.ones(n, dtype=bool)
        mask[self.fixed] = False
        self.free = np.flatnonzero(mask)
        self.L_fc = L[np.ix_(self.free, self.fixed)]
        self.chol = scipy.linalg.cho_factor(L[np.ix_(self.free, self.free)])
        i, j = np.nonzero(np.triu(W, 1))
        self.i, self.j, self.w = i, j, W[i, j]
        self.e0 = self.V0[i] - self.V0[j]

    def fit_rotations(self, X):
        e = X[self.i] - X[self.j]
        outer = self.w[:, None, None] * self.e0[:, :, None] * e[:, None, :]
        S = np.zeros((len(X), 3, 3))
        np.add.at(S, self.i, outer)                     # arc seen from i ...
        np.add.at(S, self.j, outer)                     # ... and from j (both signs flip)
        return closest_rotations(S)

    def energy(self, X, R=None):
        """sum_i sum_{j in N(i)} w_ij |(x_i - x_j) - R_i (x0_i - x0_j)|^2."""
        R = self.fit_rotations(X) if R is None else R
        e = X[self.i] - X[self.j]
        ri = np.einsum("kab,kb->ka", R[self.i], self.e0)
        rj = np.einsum("kab,kb->ka", R[self.j], self.e0)
        return float(np.sum(self.w * (np.sum((e - ri) ** 2, 1) + np.sum((e - rj) ** 2, 1))))

    def global_step(self, X_fixed, R):
        # d/dx_i: sum_j w_ij [(x_i - x_j) - 1/2 (R_i + R_j)(x0_i - x0_j)] = 0
        rhs_arc = 0.5 * self.w[:, None] * np.einsum(
            "kab,kb->ka", R[self.i] + R[self.j], self.e0)
        b = np.zeros_like(self.V0)
        np.add.at(b, self.i, rhs_arc)
        np.add.at(b, self.j, -rhs_arc)
        X = np.zeros_like(self.V0)
        X[self.fixed] = X_fixed
        X[self.free] = scipy.linalg.cho_solve(
            self.chol, b[self.free] - self.L_fc @ X_fixed)
        return X

    def solve(self, X_fixed, iterations):
        """`iterations` global steps from R = I; returns positions and the energy after
        each step (with rotations fitted to that step's result)."""
        R = np.broadcast_to(np.eye(3), (len(self.V0), 3, 3)).copy()
        energies = []
        for _ in range(iterations):
            X = self.global_step(X_fixed, R)
            R = self.fit_rotations(X)
            energies.append(self.energy(X, R))
        return X, np.array(energies)
