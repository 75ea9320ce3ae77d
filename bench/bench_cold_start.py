#!/usr/bin/env python3
"""A candidate cold start, measured against the naive-Laplacian start .

Candidate: each handle group's rigid motion (Kabsch fit of rest -> targets) propagated over the
mesh by a harmonic field phi (L phi = 0, phi = 1 on the handles, 0 on the static vertices):
vertex v gets the rotation slerp(I, R, phi_v) about the handle centroid and phi_v of its
translation. The solver starts from that shape (`initial=`: a local step fits rotations and
scales to it, then the global step). Compared: iterations of the default solve (Anderson,
tolerance 1e-3) from either start, and how far apart the two converged results are.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_cold_start.py [--markdown docs/benchmarks.md]
Writes bench/results/cold_start.json (and its section of the Markdown file).
"""
import json
import sys
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spl
from scipy.spatial.transform import Rotation, Slerp

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from bench_convergence import diag, edit  # noqa: E402
from machine import machine_info  # noqa: E402
from md_section import replace_section  # noqa: E402

MESHES = ("spot_low_resolution.obj", "cgal_dino.off", "cgal_three_peaks.off")


def kabsch(P, Q):
    cp, cq = P.mean(0), Q.mean(0)
    U, _, Vt = np.linalg.svd((P - cp).T @ (Q - cq))
    D = np.diag([1, 1, np.sign(np.linalg.det(Vt.T @ U.T))])
    return Vt.T @ D @ U.T, cp, cq


def propagated_start(ed, V, F, handles, static, targets):
    L = ed.Deformer(V, F, domain="primal").laplacian().tocsr()
    fixed = np.concatenate([handles, static])
    free = np.setdiff1d(np.arange(len(V)), fixed)
    phi = np.zeros(len(V))
    phi[handles] = 1.0
    phi[free] = spl.spsolve(L[free][:, free].tocsc(), -L[free][:, fixed] @ phi[fixed])
    R, cp, cq = kabsch(V[handles], targets)
    Rv = Slerp([0, 1], Rotation.from_matrix(np.stack([np.eye(3), R])))(np.clip(phi, 0, 1)).as_matrix()
    X = np.einsum("vij,vj->vi", Rv, V - cp) + cp + phi[:, None] * (cq - cp)
    X[handles], X[static] = targets, V[static]
    return X


def markdown(rows, ratio, machine):
    worse = sum(r["propagated"] > r["naive"] for r in rows)
    better = sum(r["propagated"] < r["naive"] for r in rows)
    return "\n".join([
        "### A better cold start? (bench/bench_cold_start.py)",
        "",
        "Candidate: the handles' rigid motion propagated by a harmonic field (slerp of the "
        "Kabsch rotation by the field, about the handle centroid), then the usual iteration "
        "from that shape. Default solves (Anderson, tolerance 1e-3) on the test meshes "
        f"(Spot, dino, three peaks) × lift/twist/bend × both domains × λ ∈ {{0.5, 1}}: median "
        f"iterations propagated/naive = {ratio:.2f}; fewer iterations in {better} of "
        f"{len(rows)} cases, more in {worse} (up to "
        f"{max(r['propagated'] / r['naive'] for r in rows):.1f}×). Not adopted: the naive-"
        f"Laplacian start stays the default. {machine['date']}."])


def main(argv=None):
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--markdown", default=None)
    args = ap.parse_args(argv)
    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh
    rows = []
    for name in MESHES:
        V, F = read_mesh(HERE.parent / "tests" / "data" / name)
        for e in ("lift", "twist", "bend"):
            h, s, T = edit(V, e)
            X0 = propagated_start(ed, V, F, h, s, T)
            for domain in ("edge", "primal"):
                for lam in (0.5, 1.0):
                    d = ed.Deformer(V, F, domain=domain)
                    d.set_constraints(handles=h, static=s)
                    d.set_stiffness(lam)
                    a = d.solve(T, warm_start=False)
                    b = d.solve(T, warm_start=False, initial=X0)
                    apart = np.linalg.norm(np.asarray(a.positions) - np.asarray(b.positions),
                                           axis=1).max() / diag(V)
                    row = {"mesh": name, "edit": e, "domain": domain, "lambda": lam,
                           "naive": int(a.iterations), "naive_converged": bool(a.converged),
                           "propagated": int(b.iterations),
                           "propagated_converged": bool(b.converged), "apart": float(apart)}
                    rows.append(row)
                    print(f"{name[:10]:10} {e:5} {domain:6} {lam}: naive {a.iterations:4} | "
                          f"propagated {b.iterations:4} | apart {apart:.1e}", flush=True)
    ratio = float(np.median([r["propagated"] / r["naive"] for r in rows]))
    print(f"median propagated/naive iterations: {ratio:.2f}")
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "cold_start.json").write_text(
        json.dumps({"rows": rows, "median_ratio": ratio, "machine": machine_info()}, indent=1))
    if args.markdown:
        replace_section(args.markdown, "cold-start", markdown(rows, ratio, machine_info()))


if __name__ == "__main__":
    main()
