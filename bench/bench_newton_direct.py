#!/usr/bin/env python3
"""D1: Newton steps solved directly (a sparse factorization of the Newton matrix K) against
Anderson, cold, to 1e-3 and to 1e-6 of the diagonal.

Each row is one method on one cell (mesh, edit, λ), solved twice from a fresh Deformer
(assembly and factorization included): to a tolerance of 1e-3 and of 1e-6. Reported: wall
time, global steps (evaluations of G), Newton steps and factorizations of K, the final
energy, and the distance to the cell's reference (bench_convergence.cached_reference: a
default solve run to a residual of 1e-10).

Methods (the direct ones are acceleration="direct" with NewtonOptions):
- anderson: the default method;
- projected: K where it factors positive definite, else the per-node positive model
  (projection 1: every indefinite term made flat);
- ladder: only the terms whose generalized eigenvalue lies below a level projected, the level
  raised while K does not factor and lowered after a full step (direct_newton.h);
- ladder+plain: ... and a trial that fails its line search first corrected by a plain step;
- ladder+lift: ... and every trial lifted into the fit (the step's rotation and scale
  response exponentiated, then a global step: a turning part moves on its arc).
At λ < 1 every direct method is the same: K's LU, a line search on |A F|.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_newton_direct.py \\
        [--cells koala:lift:1,spot:lift:1] [--methods anderson,ladder+lift] [--tolerances 1e-3,1e-6] \\
        [--out bench/results/newton_direct.json]
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_convergence import cached_reference  # noqa: E402
from edits import diagonal, edit, mesh_path  # noqa: E402
from machine import machine_info  # noqa: E402

MESHES = {"koala": "koala.obj", "spot": "spot.obj", "dino": "cgal_dino.off", "head": "cgal_mannequin-devil.off"}
DEFAULT_CELLS = ("koala:lift:1,spot:lift:1,spot:lift:0.5,dino:lift:1,dino:lift:0.5,head:lift:1,head:lift:0.5,"
                 "koala:lift:0.5")
DIRECT = {
    "projected": dict(start_level=6, ladder=False),
    "ladder": dict(start_level=3),
    "ladder+plain": dict(start_level=3, correction=1),
    "ladder+lift": dict(start_level=3, correction=3),
}
METHODS = ("anderson",) + tuple(DIRECT)
MAX_ITERATIONS = 4000


def solve(ed, V, F, handles, static, lam, targets, method, tolerance):
    start = time.perf_counter()
    d = ed.Deformer(V, F)
    d.set_constraints(handles, static)
    d.set_stiffness(lam)
    if method == "anderson":
        r = d.solve(targets, max_iterations=MAX_ITERATIONS, tolerance=tolerance)
    else:
        r = d.solve(targets, max_iterations=MAX_ITERATIONS, tolerance=tolerance, acceleration="direct",
                    newton=ed.NewtonOptions(**DIRECT[method]))
    return r, time.perf_counter() - start


def run_cell(ed, cell, methods, tolerances, log):
    name, edit_name, lam = cell.split(":")
    lam = float(lam)
    from edgedeform.mesh_files import read_mesh
    V, F = read_mesh(mesh_path(MESHES[name]))
    handles, static, targets = edit(V, edit_name)
    probe = ed.Deformer(V, F)
    probe.set_constraints(handles, static)
    probe.set_stiffness(lam)
    X_ref, ref_residual, _ = cached_reference(probe, MESHES[name].split(".")[0], edit_name, "edge", lam, targets)
    E_ref = probe.energy(X_ref)
    dg = diagonal(V)
    rows = []
    for method in methods:
        if lam < 1.0 and method not in ("anderson", "ladder"):
            continue  # the same LU path at lambda < 1
        for tol in tolerances:
            r, wall = solve(ed, V, F, handles, static, lam, targets, method, tol)
            row = {"mesh": name, "edit": edit_name, "lambda": lam, "method": method if lam == 1.0 or method == "anderson"
                   else "direct (LU)", "tolerance": tol, "vertices": len(V), "free": r.free_vertices,
                   "wall_s": wall, "iterations": r.iterations, "newton_steps": r.newton_steps,
                   "factorizations": r.newton_factorizations, "assemble_s": r.assemble_ms / 1e3,
                   "newton_factor_s": r.newton_factor_ms / 1e3, "converged": bool(r.converged),
                   "distance_estimate": float(r.distance_estimate),
                   "energy": float(r.energies[-1]) if len(r.energies) else None, "reference_energy": float(E_ref),
                   "distance_to_reference": float(np.linalg.norm(r.positions - X_ref, axis=1).max() / dg),
                   "reference_residual": ref_residual}
            rows.append(row)
            log(row)
    return rows


def markdown(result):
    lines = ["| cell | method | tol | wall s | global steps | Newton steps | factorizations | converged | "
             "distance to reference | E − E_ref |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        dE = (r["energy"] - r["reference_energy"]) if r["energy"] is not None else float("nan")
        lines.append(f"| {r['mesh']} {r['edit']} λ {r['lambda']:g} | {r['method']} | {r['tolerance']:g} | "
                     f"{r['wall_s']:.1f} | {r['iterations']} | {r['newton_steps']} | {r['factorizations']} | "
                     f"{'yes' if r['converged'] else 'no'} | {r['distance_to_reference']:.1e} | {dE:+.1e} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS)
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--tolerances", default="1e-3,1e-6")
    ap.add_argument("--out", default=str(HERE / "results" / "newton_direct.json"))
    args = ap.parse_args(argv)
    import edgedeform as ed
    methods = [m for m in args.methods.split(",") if m]
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise SystemExit(f"unknown method(s) {', '.join(unknown)}: choose from {', '.join(METHODS)}")
    tolerances = [float(t) for t in args.tolerances.split(",")]
    result = {"machine": machine_info(), "rows": []}
    for cell in [c for c in args.cells.split(",") if c]:
        result["rows"] += run_cell(ed, cell, methods, tolerances, lambda row: print(json.dumps(row), flush=True))
        Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    result["machine_end"] = machine_info()
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(markdown(result))


if __name__ == "__main__":
    main()
