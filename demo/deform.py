"""The demo's deformations and measurements (NumPy + edgedeform; no Blender).

One sample gives 7 cells: λ ∈ {0, 0.5, 1} in the edge and the primal domain, and the painted
per-vertex stiffness in the edge domain. Every cell starts from the naive Laplacian (no warm
start), so that cells do not depend on each other's order.
"""
import time

import numpy as np

LAMBDAS = (0.0, 0.5, 1.0)


def cell_specs():
    """(key, domain, λ) in sheet order; λ None = the painted stiffness."""
    specs = [("edge_%g" % lam, "edge", lam) for lam in LAMBDAS]
    specs += [("primal_%g" % lam, "primal", lam) for lam in LAMBDAS]
    specs.append(("painted_edge", "edge", None))
    return specs


def run_cells(ed, V, F, setup, max_iterations=2000, tolerance=1e-3, repeat=1, log=print):
    """Solve every cell; returns a list of dicts (positions kept under "positions").
    ms is the best of `repeat` identical solves (the 2 cores here are shared; the best run
    is the least disturbed), each from a fresh factorization."""
    hidx, targets = setup["handle_index"], setup["targets"]
    cells, deformers = [], {}
    for key, domain, lam in cell_specs():
        d = deformers.get(domain)
        if d is None:
            d = deformers[domain] = ed.Deformer(V, F, domain=domain)
            d.set_constraints(handles=hidx, static=setup["static"], roi=None)
        times = []
        for _ in range(max(1, repeat)):
            d.set_stiffness(0.25)   # force the next solve to refactor, as a first solve does
            d.set_stiffness(setup["stiffness"] if lam is None else lam)
            t0 = time.perf_counter()
            r = d.solve(targets, max_iterations=max_iterations, tolerance=tolerance,
                        warm_start=False)
            times.append((time.perf_counter() - t0) * 1e3)
        ms = min(times)
        m = ed.metrics(V, F, r.positions, handles=hidx, targets=targets)
        cell = {
            "key": key, "domain": domain, "lambda": "painted" if lam is None else lam,
            "iterations": int(r.iterations), "converged": bool(r.converged),
            "ms": ms, "factor_ms": float(r.factor_ms),
            "energy": float(r.energies[-1]) if len(r.energies) else None,
            "warnings": list(r.warnings),
            **{k: float(v) for k, v in m.items()},
            "positions": np.asarray(r.positions),
        }
        log("  %-13s %4d it %s %8.1f ms  strain %.4f  dihedral %.4f  arap %.4g" % (
            key, cell["iterations"], "conv" if cell["converged"] else "NOT converged",
            ms, cell["mean_edge_strain"], cell["mean_dihedral_change"], cell["arap_energy"]))
        cells.append(cell)
    return cells


# ---------------------------------------------------------------- per-region measures

def mesh_edges(F):
    """Unique undirected edges (k,2) and, per edge, its two faces (-1 on the boundary)."""
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    face = np.tile(np.arange(len(F)), 3)
    key = np.sort(he, axis=1)
    edges, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    second = np.full(len(edges), -1)
    sorted_inv = inv[order]
    start = np.searchsorted(sorted_inv, np.arange(len(edges)))
    first = face[order[start]]
    has2 = np.append(sorted_inv[1:] == sorted_inv[:-1], False)[start]
    second[has2] = face[order[start[has2] + 1]]
    return edges, np.column_stack([first, second])


def _normals(X, F):
    n = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def region_metrics(V, F, X, mask, edges=None, faces=None):
    """Edge strain and bending inside a vertex region (edges with both ends in it):
    mean |l - l0| / l0, and mean change of the angle between the two face normals (rad)."""
    if edges is None:
        edges, faces = mesh_edges(F)
    inside = mask[edges[:, 0]] & mask[edges[:, 1]]
    l0 = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1)
    l1 = np.linalg.norm(X[edges[:, 0]] - X[edges[:, 1]], axis=1)
    strain = np.abs(l1 - l0) / l0
    interior = inside & (faces[:, 1] >= 0)
    f = faces[interior]

    def angle(P):
        n = _normals(P, F)
        c = np.clip(np.sum(n[f[:, 0]] * n[f[:, 1]], axis=1), -1, 1)
        return np.arccos(c)

    return {"edges": int(inside.sum()),
            "mean_edge_strain": float(strain[inside].mean()) if inside.any() else None,
            "mean_dihedral_change": float(np.abs(angle(X) - angle(V)).mean()) if f.size else None}


def painted_regions(V, F, cells, materials, free):
    """For each painted material (its free vertices only; `free` is a (n,) bool mask): its
    metrics in the painted cell and in the uniform edge-domain cells, the uniform λ whose local
    strain and bending are nearest, and the mean vertex distance to each uniform result."""
    edges, faces = mesh_edges(F)
    by_key = {c["key"]: c for c in cells}
    painted = by_key["painted_edge"]["positions"]
    out = []
    for label, mat in materials.items():
        mask = mat["mask"] & free
        if mask.sum() < 3:      # e.g. a material painted only on static vertices
            continue
        row = {"region": label, "lambda": mat["value"], "vertices": int(mask.sum()),
               "painted": region_metrics(V, F, painted, mask, edges, faces), "uniform": {},
               "distance_to_uniform": {}}
        for lam in LAMBDAS:
            X = by_key["edge_%g" % lam]["positions"]
            row["uniform"]["%g" % lam] = region_metrics(V, F, X, mask, edges, faces)
            row["distance_to_uniform"]["%g" % lam] = float(
                np.linalg.norm(painted[mask] - X[mask], axis=1).mean())
        p = row["painted"]
        if p["mean_edge_strain"] is not None and p["mean_dihedral_change"] is not None:
            def gap(lam):   # relative distance in (strain, bending) space
                u = row["uniform"]["%g" % lam]
                return (abs(u["mean_edge_strain"] - p["mean_edge_strain"]) /
                        max(p["mean_edge_strain"], 1e-12) +
                        abs(u["mean_dihedral_change"] - p["mean_dihedral_change"]) /
                        max(p["mean_dihedral_change"], 1e-12))
            row["nearest_uniform_by_local_shape"] = min(LAMBDAS, key=gap)
        row["nearest_uniform_by_position"] = float(min(
            LAMBDAS, key=lambda lam: row["distance_to_uniform"]["%g" % lam]))
        out.append(row)
    return out
