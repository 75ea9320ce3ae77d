#!/usr/bin/env python3
"""Diagnostics for the Newton-Krylov solver (record 0020), all measured with the
package's analytic derivative of the one-step map G (Deformer._jacobian).

Per cell (mesh, edit, domain; the lambda = 1 solution is the reference):
1. spectrum: the largest moduli of J_G at the reference (ARPACK eigs on J_G over the 3 nf
   free coordinates, ordered all x, then all y, then all z, as the coarse basis's rows
   v + nf c); counts above 0.9 / 0.99 / 0.999 / 1 and the band's density (how many lie
   within 1e-3, 1e-2, 1e-1 of 1), and each Ritz pair's residual |J v - mu v| / |v|;
2. capture: for each affine-patch coarse space U (Deformer._coarse_basis_coo; "P:S" is P
   patches blended into a partition of unity by S smoothing steps), the part of
   each top eigenvector that U misses, |(I - P_U) v| / |v|, in the Euclidean norm, in the A
   norm (A = the global step's matrix over the free vertices; at lambda = 1 it is
   2 (N^T L N) restricted to the free vertices, an identity the script checks against
   K v = A (I - J_G) v on every run) and in the K norm (K = A (I - J_G), the Hessian at
   lambda = 1; its coarse block U^T K U is the core's own, _coarse_operator_coo). A complex
   pair counts as the plane of its real and imaginary parts (Frobenius norm). A decimated
   mesh coarse space is not built here;
3. safeguard: Anderson from rest at lambda 0.5 and 1, rejected / accelerated steps per 100
   iterations (run as warm-started chunks of 100, which continue one iteration; the chunked
   end point is compared to one uninterrupted run);
4. monotonicity: the plain iteration's energies at lambda 0.5, how often and by how much
   they rise;
5. Hessian: K assembled by probing (one K product per colour of columns that share no row;
   the pattern comes from the graph's node stencils and is checked against K products on
   random vectors), then its numeric factorization timed with SciPy's SuperLU, beside the
   same factorization of A (3 copies of the n x n matrix) for scale. This is the exact
   Hessian, not a Gauss-Newton model; the two share a pattern.

    PYTHONPATH=build/python nice /usr/bin/python3 bench/bench_newton_diagnostics.py
        [--cells koala.obj:lift:edge,spot.obj:lift:edge] [--eigenvalues 50]
        [--patches 100,200,400,200:16] [--json bench/results/newton_diagnostics.json]
    .../bench_newton_diagnostics.py --plot-only bench/results/newton_diagnostics.json
Writes the JSON and a PNG beside it (matplotlib here, or in --plot-python's interpreter).
"""
import argparse
import json
import multiprocessing
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

DEFAULT_CELLS = "koala.obj:lift:edge,spot.obj:lift:edge"
REFERENCE = {"acceleration": "anderson", "tolerance": 1e-9, "max_iterations": 6000}
ARPACK_TOL = 1e-6
RANDOM_CHECKS = 3   # random vectors the probed K and the A identity are checked on


# ---- the problem -----------------------------------------------------------------------

def load_cell(ed, cell):
    from edgedeform.mesh_files import read_mesh
    from edits import diagonal, edit, mesh_path
    mesh, edit_name, domain = cell.split(":")
    V, F = read_mesh(mesh_path(mesh))
    handles, static, targets = edit(V, edit_name)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(handles=handles, static=static)
    return {"mesh": mesh, "edit": edit_name, "domain": domain, "d": d, "targets": targets,
            "V": V, "diag": diagonal(V), "free": np.asarray(d.free_vertices)}


def solve_row(r, seconds):
    return {"converged": bool(r.converged), "iterations": int(r.iterations),
            "residual": float(r.residuals[-1]) if len(r.residuals) else None,
            "distance_estimate": float(r.distance_estimate), "seconds": seconds}


def reference(p, method):
    """The lambda = 1 solution the spectrum is taken at, and how well it was reached."""
    d = p["d"]
    d.set_stiffness(1.0)
    t0 = time.perf_counter()
    r = d.solve(p["targets"], warm_start=False, **dict(REFERENCE, acceleration=method))
    row = solve_row(r, time.perf_counter() - t0)
    X = np.asarray(r.positions)
    row["method"] = method
    row["one_step_residual"] = float(np.abs(d._one_step(X) - X[p["free"]]).max() / p["diag"])
    return X, row


# ---- vectors over the free coordinates: all x, then all y, then all z ------------------

def to_flat(M):
    return np.asarray(M).T.ravel()


def to_points(v, nf):
    return np.ascontiguousarray(v.reshape(3, nf).T)


def coo_matrix(t):
    rows, cols, vals, shape = t
    return sp.csr_matrix((vals, (rows, cols)), shape=tuple(shape))


def system_matrix(d, free, lam=1.0):
    """A at a uniform lambda over the free coordinates, on each coordinate: the 1-form arcs
    2 lambda (N^T L N)_ff plus the Laplacian rows (1 - lambda) ((L N)^T (L N))_ff (edge domain,
    where no similarity share is added; a_identity_error checks it against the core's K)."""
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


# ---- 1. the spectrum -------------------------------------------------------------------

def spectrum(d, X, nf, k, log):
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
        converged = k
    except spla.ArpackNoConvergence as e:  # keep the pairs that did converge
        mu, vecs = e.eigenvalues, e.eigenvectors
        converged = len(mu)
    seconds = time.perf_counter() - t0
    order = np.argsort(-np.abs(mu))
    mu, vecs = mu[order], vecs[:, order]
    residuals = []
    for j in range(len(mu)):  # |J v - mu v| / |v| with J applied to re and im parts
        v = vecs[:, j]
        Jv = J(v.real) + 1j * J(v.imag)
        residuals.append(float(np.linalg.norm(Jv - mu[j] * v) / np.linalg.norm(v)))
    mod = np.abs(mu)
    gap = 1.0 - mod
    row = {"requested": k, "found": int(len(mu)), "arpack_converged": converged,
           "products": count[0], "seconds": seconds,
           "moduli": [float(m) for m in mod], "real": [float(m) for m in mu.real],
           "imag": [float(m) for m in mu.imag], "ritz_residuals": residuals,
           "above_0.9": int((mod > 0.9).sum()), "above_0.99": int((mod > 0.99).sum()),
           "above_0.999": int((mod > 0.999).sum()), "above_1": int((mod > 1.0 + 1e-9).sum()),
           "within_1e-3_of_1": int((np.abs(gap) <= 1e-3).sum()),
           "within_1e-2_of_1": int((np.abs(gap) <= 1e-2).sum()),
           "within_1e-1_of_1": int((np.abs(gap) <= 1e-1).sum()),
           "complex_pairs": int((mu.imag > 1e-12).sum())}
    row["participation"], row["top1pct_share"] = localization(vecs, nf)
    log(f"  spectrum: {len(mu)} Ritz pairs in {count[0]} products, {seconds:.0f} s; largest "
        f"{', '.join(f'{m:.5f}' for m in mod[:5])}")
    return mu, vecs, row


def localization(vecs, nf):
    """Per eigenvector: the participation ratio (sum |v_i|^2)^2 / (nf sum |v_i|^4) over the free
    vertices (1: spread evenly, 1/nf: one vertex) and the share of |v|^2 on the 1% of
    vertices where it is largest. Localized modes are what no coarse space of large patches
    can carry."""
    ratio, top_share = [], []
    for j in range(vecs.shape[1]):
        w = (np.abs(vecs[:, j]) ** 2).reshape(3, nf).sum(axis=0)
        ratio.append(float(w.sum() ** 2 / (nf * np.sum(w ** 2))))
        k = max(1, nf // 100)
        top_share.append(float(np.sort(w)[-k:].sum() / w.sum()))
    return ratio, top_share


def eigen_planes(mu, vecs):
    """Per eigenvalue, the real vectors it stands for: [v] if real, [Re v, Im v] if not."""
    out = []
    for j in range(len(mu)):
        v = vecs[:, j]
        out.append(v.real[:, None] if abs(mu[j].imag) <= 1e-12 else np.column_stack([v.real, v.imag]))
    return out


# ---- 2. capture by a coarse space -----------------------------------------------------

def orthonormal_coefficients(U):
    """(T, rank, blocks): with Q = U T the columns of Q are orthonormal; T is block-diagonal
    over the blocks of U^T U (disjoint patches: small blocks; blended ones overlap into one
    large block). Q itself is never formed (for a blended basis it would be dense).
    Directions with singular value below 1e-10 of their block's largest (all-constrained or
    flat patches) are dropped."""
    G = (U.T @ U).tocsr()
    n_blocks, label = csgraph.connected_components(G, directed=False)
    T = np.zeros((U.shape[1], U.shape[1]))
    kept = 0
    members = np.argsort(label, kind="stable")
    starts = np.searchsorted(label[members], np.arange(n_blocks + 1))
    for b in range(n_blocks):
        idx = members[starts[b]:starts[b + 1]]
        w, E = np.linalg.eigh(G[idx][:, idx].toarray())
        keep = w > 1e-20 * max(w.max(), 1e-300)   # singular values > 1e-10 of the largest
        T[np.ix_(idx, np.arange(kept, kept + keep.sum()))] = E[:, keep] / np.sqrt(w[keep])
        kept += int(keep.sum())
    return T[:, :kept], kept, n_blocks


def coarse_operator_error(d, X, U, C, rng=None):
    """max over random coarse vectors c of |U^T K (U c) - C c| / |C c|: whether the core's
    coarse operator C is U^T K U for this U (K by products, as everywhere here)."""
    rng = rng or np.random.default_rng(4)
    nf = U.shape[0] // 3
    worst = 0.0
    for _ in range(RANDOM_CHECKS):
        c = rng.standard_normal(U.shape[1])
        KUc = to_flat(d._jacobian(X, to_points(U @ c, nf), True))
        worst = max(worst, float(np.linalg.norm(U.T @ KUc - C @ c) / np.linalg.norm(C @ c)))
    return worst


class CoarseSpace:
    """The affine-patch space U of `patches` patches (blended by `blend` steps), and the
    share of a vector it misses in the Euclidean, A and K inner products: with M one of
    them, |W - P_M W|_M^2 = W^T M W - g^T (Q^T M Q)^-1 g, g = Q^T M W, Q = U T orthonormal."""

    def __init__(self, d, X, A3, patches, blend=0):
        U = coo_matrix(d._coarse_basis_coo(patches, blend)).tocsc()
        self.T, self.rank, self.gram_blocks = orthonormal_coefficients(U)
        self.U, self.columns, self.A3 = U, int(U.shape[1]), A3
        QA = self.T.T @ (U.T @ (A3 @ U)).toarray() @ self.T
        self.QA_inv = np.linalg.pinv(0.5 * (QA + QA.T), rcond=1e-13, hermitian=True)
        C = coo_matrix(d._coarse_operator_coo(X, patches, blend))  # the core's U^T K U
        self.operator_check = coarse_operator_error(d, X, U, C)
        QK = self.T.T @ C.toarray() @ self.T
        self.asymmetry = float(np.abs(QK - QK.T).max() / np.abs(QK).max())
        QK = 0.5 * (QK + QK.T)
        self.min_eigenvalue_rel = float(np.linalg.eigvalsh(QK)[0] / np.abs(QK).max())
        self.QK_inv = np.linalg.pinv(QK, rcond=1e-12, hermitian=True)

    def _miss(self, W, MW, inverse):
        g = self.T.T @ (self.U.T @ MW)
        whole = float(np.sum(W * MW))
        rest = whole - float(np.sum(g * (inverse @ g)))
        return float(np.sqrt(max(rest, 0.0) / whole)) if whole > 0 else float("nan")

    def miss_euclidean(self, W):
        return self._miss(W, W, np.eye(self.rank))

    def miss_A(self, W):
        return self._miss(W, self.A3 @ W, self.QA_inv)

    def miss_K(self, W, KW):
        """K symmetric at lambda = 1: no K product beyond KW."""
        return self._miss(W, KW, self.QK_inv)


def capture(space, planes, K_planes, patches, log, blend=0):
    t0 = time.perf_counter()
    row = {"patches_requested": patches, "blend": blend, "basis_columns": space.columns,
           "rank": int(space.rank), "gram_blocks": int(space.gram_blocks),
           "coarse_operator_check": space.operator_check, "coarse_asymmetry": space.asymmetry, "coarse_min_eigenvalue_rel": space.min_eigenvalue_rel}
    fractions = {"euclidean": [space.miss_euclidean(W) for W in planes],
                 "A": [space.miss_A(W) for W in planes],
                 "K": [space.miss_K(W, KW) for W, KW in zip(planes, K_planes)]}
    row["seconds"] = time.perf_counter() - t0
    row["miss"] = fractions
    for name, f in fractions.items():
        f = np.asarray(f)
        for top in (10, 50):
            row[f"{name}_top{top}_median"] = float(np.median(f[:top]))
            row[f"{name}_top{top}_max"] = float(np.max(f[:top]))
    log(f"  capture {patches} patches, blend {blend} ({row['rank']} columns): miss median/max top 10: Euclidean "
        f"{row['euclidean_top10_median']:.3f}/{row['euclidean_top10_max']:.3f}, A "
        f"{row['A_top10_median']:.3f}/{row['A_top10_max']:.3f}, K {row['K_top10_median']:.3f}/"
        f"{row['K_top10_max']:.3f}")
    return row


# ---- 3. safeguard rejections, 4. energy monotonicity -----------------------------------

def safeguard(p, lam, iterations, compare_whole, chunk=100):
    d = p["d"]
    d.set_stiffness(lam)
    per_chunk = []
    t0 = time.perf_counter()
    for k in range(0, iterations, chunk):
        r = d.solve(p["targets"], acceleration="anderson", tolerance=0.0,
                    max_iterations=min(chunk, iterations - k), warm_start=k > 0)
        per_chunk.append({"iterations": int(r.iterations), "rejected": int(r.rejected_steps),
                          "accelerated": int(r.accelerated_steps),
                          "residual": float(r.residuals[-1])})
    seconds = time.perf_counter() - t0
    row = {"lambda": lam, "iterations": iterations, "chunks": per_chunk, "seconds": seconds,
           "rejected": sum(c["rejected"] for c in per_chunk),
           "accelerated": sum(c["accelerated"] for c in per_chunk)}
    if compare_whole:  # the chunks continue one iteration: the same end as one call
        whole = d.solve(p["targets"], acceleration="anderson", tolerance=0.0,
                        max_iterations=iterations, warm_start=False)
        row.update(whole_run_rejected=int(whole.rejected_steps),
                   whole_run_accelerated=int(whole.accelerated_steps),
                   chunked_vs_whole=float(np.abs(np.asarray(r.positions) - np.asarray(whole.positions)).max()
                                          / p["diag"]))
    return row


def monotonicity(p, lam, iterations):
    d = p["d"]
    d.set_stiffness(lam)
    r = d.solve(p["targets"], acceleration="none", tolerance=0.0, max_iterations=iterations,
                warm_start=False)
    e = np.asarray(r.energies, float)
    rise = np.diff(e) / np.abs(e[:-1])
    up = rise > 0
    return {"lambda": lam, "iterations": int(r.iterations), "energies": len(e),
            "first_energy": float(e[0]), "last_energy": float(e[-1]),
            "increases": int(up.sum()),
            "largest_relative_increase": float(rise.max()) if up.any() else 0.0,
            "first_increase_at": int(np.flatnonzero(up)[0]) + 1 if up.any() else None,
            "last_residual": float(r.residuals[-1])}


# ---- 5. the Hessian K, probed and factored ---------------------------------------------

def k_pattern(d, free, n_vertices):
    """Vertex pairs K can couple: both in the vertices of one node's stencil (the node and
    its arc neighbours), restricted to the free vertices."""
    nv = np.asarray(d.node_vertices())
    arcs = np.asarray(d.arcs())
    n_nodes = nv.shape[0]
    S = sp.coo_matrix((np.ones(2 * len(arcs) + n_nodes),
                       (np.r_[arcs[:, 0], arcs[:, 1], np.arange(n_nodes)],
                        np.r_[arcs[:, 1], arcs[:, 0], np.arange(n_nodes)])),
                      shape=(n_nodes, n_nodes)).tocsr()
    NV = sp.coo_matrix((np.ones(nv.size), (np.repeat(np.arange(n_nodes), nv.shape[1]), nv.ravel())),
                       shape=(n_nodes, n_vertices)).tocsr()
    B = (S @ NV).tocsc()[:, free]               # stencil t -> its vertices (free ones)
    P = (B.T @ B).tocsr()
    P.data[:] = 1.0
    return P


def greedy_colours(conflict):
    n = conflict.shape[0]
    colour = np.full(n, -1)
    ip, ix = conflict.indptr, conflict.indices
    for v in range(n):
        used = set(colour[ix[ip[v]:ip[v + 1]]].tolist())
        c = 0
        while c in used:
            c += 1
        colour[v] = c
    return colour


def probed_hessian(d, X, free, n_vertices, log):
    nf = len(free)
    P = k_pattern(d, free, n_vertices)
    conflict = (P @ P).tocsr()              # columns that share a row of K
    colour = greedy_colours(conflict)
    n_colours = int(colour.max()) + 1
    Pc = P.tocoo()
    rows, cols, vals = [], [], []
    t0 = time.perf_counter()
    for c in range(3):
        for k in range(n_colours):
            dX = np.zeros((nf, 3))
            dX[colour == k, c] = 1.0
            KdX = d._jacobian(X, dX, True)          # (nf, 3): rows u of every coordinate
            # entry (u, c') of column (v, c) for v of colour k next to u: read it back
            mask = colour[Pc.col] == k
            u, v = Pc.row[mask], Pc.col[mask]
            for c2 in range(3):
                rows.append(u + nf * c2)
                cols.append(v + nf * c)
                vals.append(KdX[u, c2])
    seconds = time.perf_counter() - t0
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(3 * nf, 3 * nf))
    K.eliminate_zeros()
    rng = np.random.default_rng(2)
    err = 0.0
    for _ in range(RANDOM_CHECKS):
        v = rng.standard_normal(3 * nf)
        Kv = to_flat(d._jacobian(X, to_points(v, nf), True))
        err = max(err, float(np.linalg.norm(K @ v - Kv) / np.linalg.norm(Kv)))
    log(f"  K probed: {n_colours} colours x 3 = {3 * n_colours} products, {seconds:.0f} s, "
        f"{K.nnz:,} nonzeros, product check {err:.1e}")
    return K, {"colours": n_colours, "products": 3 * n_colours, "probe_seconds": seconds,
               "nonzeros": int(K.nnz), "probe_check": err,
               "asymmetry": float(abs(K - K.T).max() / abs(K).max())}


def dense_hessian(d, X, nf):
    """K column by column (3 nf products): only for small meshes, to check the probing."""
    cols = []
    for j in range(3 * nf):
        e = np.zeros(3 * nf)
        e[j] = 1.0
        cols.append(to_flat(d._jacobian(X, to_points(e, nf), True)))
    return np.column_stack(cols)


def _superlu_child(M, repeats, out):
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        lu = spla.splu(M, permc_spec="MMD_AT_PLUS_A")
        best = min(best, time.perf_counter() - t0)
    out.put({"seconds": best, "factor_nonzeros": int(lu.L.nnz + lu.U.nnz)})


def factor_time(M, timeout):
    """Best of two SuperLU factorizations (one above 20,000 rows) and the factors' nonzeros;
    the time covers ordering, symbolic and numeric work together (SciPy's SuperLU does not
    split them). Run in a child process that is ended after `timeout` s: then the result
    says only that it took longer."""
    ctx = multiprocessing.get_context("fork")
    out = ctx.Queue()
    child = ctx.Process(target=_superlu_child, args=(M.tocsc(), 2 if M.shape[0] <= 20000 else 1, out))
    t0 = time.perf_counter()
    child.start()
    child.join(timeout)
    if child.is_alive():
        child.terminate()
        child.join()
        return {"seconds": None, "unfinished_after_s": time.perf_counter() - t0}
    return out.get(timeout=10)


def factor_text(f):
    if f["seconds"] is None:
        return f"not finished after {f['unfinished_after_s']:.0f} s"
    return f"{f['seconds']:.2f} s ({f['factor_nonzeros']:,} in L+U)"


def hessian(p, X, A3, dense_check, timeout, log):
    d, free = p["d"], p["free"]
    K, row = probed_hessian(d, X, free, len(p["V"]), log)
    if dense_check:
        Kd = dense_hessian(d, X, len(free))
        row["dense_check"] = float(np.abs(K.toarray() - Kd).max() / np.abs(Kd).max())
    Ks = (0.5 * (K + K.T)).tocsc()
    row["K_superlu"] = factor_time(Ks, timeout)
    row["A_superlu"] = factor_time(A3, timeout)
    row["size"] = int(K.shape[0])
    log(f"  factorization (SuperLU): K {factor_text(row['K_superlu'])}, A {factor_text(row['A_superlu'])}")
    return row


# ---- one cell --------------------------------------------------------------------------

def run_cell(ed, cell, args, log):
    p = load_cell(ed, cell)
    d, nf = p["d"], len(p["free"])
    row = {"mesh": p["mesh"], "edit": p["edit"], "domain": p["domain"],
           "vertices": int(len(p["V"])), "free": nf}
    log(f"{cell}: {row['vertices']:,} vertices, {nf:,} free")
    X, row["reference"] = reference(p, args.reference_method)
    ref = row["reference"]
    log(f"  reference ({ref['method']}): converged {ref['converged']}, {ref['iterations']} its, "
        f"residual {ref['residual']:.1e}, |G(X) - X| {ref['one_step_residual']:.1e} diag, "
        f"{ref['seconds']:.0f} s")
    A3, _ = system_matrix(d, p["free"])
    row["a_identity_error"] = a_identity_error(d, X, A3, nf, np.random.default_rng(1))
    if row["a_identity_error"] > 1e-8:
        raise SystemExit(f"{cell}: A != 2 (N^T L N)_ff at lambda 1 (error "
                         f"{row['a_identity_error']:.1e}): the A norm below would be wrong")
    mu, vecs, row["spectrum"] = spectrum(d, X, nf, min(args.eigenvalues, 3 * nf - 2), log)
    planes = eigen_planes(mu, vecs)
    K_planes = [np.column_stack([to_flat(d._jacobian(X, to_points(W[:, c], nf), True))
                                 for c in range(W.shape[1])]) for W in planes]
    row["capture"] = [capture(CoarseSpace(d, X, A3, k, blend), planes, K_planes, k, log, blend)
                      for k, blend in args.patches]
    if args.safeguard_iterations:
        row["safeguard"] = [safeguard(p, lam, args.safeguard_iterations, nf <= args.dense_check_max_free)
                           for lam in (0.5, 1.0)]
        for s in row["safeguard"]:
            log(f"  anderson lambda {s['lambda']:g}: rejected/accelerated per 100 its "
                + " ".join(f"{c['rejected']}/{c['accelerated']}" for c in s["chunks"]))
    if args.monotone_iterations:
        row["monotonicity"] = monotonicity(p, 0.5, args.monotone_iterations)
        m = row["monotonicity"]
        log(f"  plain lambda 0.5: {m['increases']} energy increases in {m['energies']}, largest "
            f"relative {m['largest_relative_increase']:.1e}")
    if nf <= args.hessian_max_free:
        d.set_stiffness(1.0)
        row["hessian"] = hessian(p, X, A3, nf <= args.dense_check_max_free, args.factor_timeout, log)
    else:
        row["hessian"] = {"skipped": f"{nf} free vertices > --hessian-max-free {args.hessian_max_free}"}
    return row


# ---- output ----------------------------------------------------------------------------

def table(result):
    lines = ["| cell | reference (its, residual, conv.) | top moduli | > 0.9 / 0.99 / 0.999 / 1 "
             "| within 1e-3 / 1e-2 / 1e-1 of 1 | worst Ritz residual | top 10: participation / share on 1% of vertices (median) |",
             "|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        s, ref = r["spectrum"], r["reference"]
        lines.append(
            f"| {r['mesh']} {r['edit']} {r['domain']} λ 1 | {ref['iterations']}, {ref['residual']:.0e}, "
            f"{'yes' if ref['converged'] else 'no'} | {', '.join(f'{m:.4f}' for m in s['moduli'][:4])} | "
            f"{s['above_0.9']} / {s['above_0.99']} / {s['above_0.999']} / {s['above_1']} of {s['found']} | "
            f"{s['within_1e-3_of_1']} / {s['within_1e-2_of_1']} / {s['within_1e-1_of_1']} | "
            f"{max(s['ritz_residuals']):.0e} | "
            + (f"{np.median(s['participation'][:10]):.2f} / {np.median(s['top1pct_share'][:10]):.2f} |" if "participation" in s else "– |"))
    lines += ["", "| cell | patches, blend steps (rank) | miss, top 10 median / max: Euclidean | A | K | "
              "top 50: Euclidean | A | K |", "|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        for c in r["capture"]:
            f = lambda n, t: f"{c[f'{n}_top{t}_median']:.3f} / {c[f'{n}_top{t}_max']:.3f}"  # noqa: E731
            lines.append(f"| {r['mesh']} | {c['patches_requested']}, {c.get('blend', 0)} ({c['rank']}) | {f('euclidean', 10)} | "
                         f"{f('A', 10)} | {f('K', 10)} | {f('euclidean', 50)} | {f('A', 50)} | {f('K', 50)} |")
    lines += ["", "| cell | Anderson λ: rejected / accelerated per 100 its | plain λ 0.5: energy "
              "increases, largest relative | K probe (products, check) | SuperLU of K / of A |",
              "|---|---|---|---|---|"]
    for r in result["rows"]:
        sg = "; ".join(f"{s['lambda']:g}: " + " ".join(f"{c['rejected']}/{c['accelerated']}"
                                                         for c in s["chunks"])
                       for s in r.get("safeguard", []))
        m = r.get("monotonicity")
        mono = f"{m['increases']} of {m['energies'] - 1}, {m['largest_relative_increase']:.1e}" if m else "–"
        h = r["hessian"]
        if "skipped" in h:
            hs, fs = "skipped", h["skipped"]
        else:
            hs = f"{h['products']}, {h['probe_check']:.0e}"
            fs = f"{factor_text(h['K_superlu'])} / {factor_text(h['A_superlu'])}"
        lines.append(f"| {r['mesh']} | {sg or '–'} | {mono} | {hs} | {fs} |")
    return "\n".join(lines)


def plot(result, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for r in result["rows"]:
        mod = np.asarray(r["spectrum"]["moduli"])
        a.semilogy(np.arange(1, len(mod) + 1), 1.0 - mod, "o-", ms=3, label=f"{r['mesh']} ({r['free']:,} free)")
        for c in r["capture"]:
            b.semilogy(np.arange(1, len(c["miss"]["A"]) + 1), np.maximum(c["miss"]["A"], 1e-6), ".-",
                       label=f"{r['mesh']}, {c['patches_requested']} patches, blend {c.get('blend', 0)}")
    a.set_xlabel("rank of |μ|")
    a.set_ylabel("1 − |μ| (J_G at the λ = 1 solution)")
    a.legend(fontsize=8)
    b.set_xlabel("rank of |μ|")
    b.set_ylabel("|(I − Π_U) v|_A / |v|_A")
    b.legend(fontsize=7)
    fig.suptitle(f"Newton diagnostics, {result['machine']['date']}", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def write_plot(result, json_path, png, plot_python, log):
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        if plot_python and Path(plot_python).is_file():
            done = subprocess.run([plot_python, __file__, "--plot-only", str(json_path),
                                   "--png", str(png)]).returncode == 0
            log(f"plot {'written' if done else 'NOT written (see above)'} by {plot_python}: {png}")
        else:
            log("no matplotlib (and no --plot-python): plot not written")
        return
    plot(result, png)
    log(f"plot: {png}")


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS, help="mesh:edit:domain,...")
    ap.add_argument("--eigenvalues", type=int, default=50)
    ap.add_argument("--patches", default="100,200,400,200:8,200:16",
                    help="coarse spaces to compare: P (disjoint patches) or P:S (blended by S steps)")
    ap.add_argument("--reference-method", default=REFERENCE["acceleration"],
                    help="acceleration of the reference solve (tolerance 1e-9, 6000 its)")
    ap.add_argument("--safeguard-iterations", type=int, default=600)
    ap.add_argument("--monotone-iterations", type=int, default=300)
    ap.add_argument("--hessian-max-free", type=int, default=100000,
                    help="probe and factor K only up to this many free vertices")
    ap.add_argument("--dense-check-max-free", type=int, default=1000,
                    help="up to this size also build K column by column and run Anderson "
                         "uncut, to check the probing and the chunked runs")
    ap.add_argument("--factor-timeout", type=float, default=900,
                    help="seconds one SuperLU factorization may take before it is given up")
    ap.add_argument("--json", default=str(HERE / "results" / "newton_diagnostics.json"))
    ap.add_argument("--png", default=None, help="default: the JSON's path with .png")
    build = Path(os.environ.get("EDGEDEFORM_BUILD_DIR", HERE.parent / "build-diag"))
    ap.add_argument("--plot-python", default=str(build / "plot-venv" / "bin" / "python"),
                    help="a Python with matplotlib, used when this one has none")
    ap.add_argument("--plot-only", default=None, help="only draw the plot of this JSON")
    args = ap.parse_args(argv)
    args.patches = [tuple(int(x) for x in (k + ":0").split(":")[:2]) for k in args.patches.split(",") if k]
    return args


def main(argv=None):
    args = parse(argv)
    if args.plot_only:
        result = json.loads(Path(args.plot_only).read_text())
        plot(result, args.png or str(Path(args.plot_only).with_suffix(".png")))
        return
    import edgedeform as ed
    from machine import machine_info
    log = lambda s: print(s, flush=True)  # noqa: E731
    result = {"machine": machine_info(), "load_start": list(os.getloadavg()),
              "command": " ".join([Path(sys.argv[0]).name] + (sys.argv[1:] if argv is None else argv)),
              "reference": dict(REFERENCE, acceleration=args.reference_method),
              "arpack_tol": ARPACK_TOL, "rows": []}
    t0 = time.perf_counter()
    json_path = Path(args.json)
    json_path.parent.mkdir(parents=True, exist_ok=True)
    for cell in args.cells.split(","):
        result["rows"].append(run_cell(ed, cell, args, log))
        result["load_end"] = list(os.getloadavg())
        result["seconds"] = time.perf_counter() - t0
        json_path.write_text(json.dumps(result, indent=1))   # after each cell: hours of work
    print(table(result))
    print(f"load (1, 5, 15 min) at start {result['load_start']}, at end {result['load_end']}")
    write_plot(result, json_path, args.png or json_path.with_suffix(".png"), args.plot_python, log)

if __name__ == "__main__":
    main()
