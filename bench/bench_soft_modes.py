#!/usr/bin/env python3
"""The soft-mode diagnostics that chose how the solver reaches the fixed point
(docs/decisions/0070; background: ../shared/research/soft-modes.md). Each writes a JSON in
bench/results/ and prints its table; bench/report.py puts the tables into
docs/benchmarks_solver.md.

d1  scaling: the largest eigenvalue mu of J_G at the λ 1 solution of one edit at several
    resolutions of one shape (Spot 829 split once and twice into four, which keeps the surface;
    the koala decimated to 5k and 12k, and whole), and (1 - mu) times the free vertices; and how
    far the λ 1 results at two resolutions of one shape lie apart (each fine vertex against the
    coarse result at its nearest coarse vertex's place, / diag).
d2  deflation capture: the share (A norm) of an iterate's error that lies in the span of J_G's
    top p eigenvectors (p = 10, 25, 50, 100), eigenvectors taken at the solution and at the
    iterate; iterates: a cold Anderson solve after 100 iterations, and Live's shape when the
    mouse stops (bench_live_settle's drag). The deflation plan needed >= 0.9 with p <= 100.
d3  arcs: Anderson on positions as the core does it, damped (1/2, 1/4 tried before the plain
    step), on the rotations (Lie algebra about a base; windows 5 and 20), judged after a plain
    step, and L-BFGS on E (the same harness: bench/arc_anderson.py); global steps to 1e-3 of
    the diagonal from the reference, rejected steps.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_soft_modes.py d1 [--shapes spot] [--levels 2] [--json PATH]
    PYTHONPATH=build/python /usr/bin/python3 bench/bench_soft_modes.py d2 [--cells koala:lift] [--p 100]
    PYTHONPATH=build/python /usr/bin/python3 bench/bench_soft_modes.py d3 [--cells spot11k:side+]
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
from edits import diagonal, edit, load_mesh  # noqa: E402
from machine import machine_info  # noqa: E402
from soft_modes import Linearization, captured_fraction, top_modes  # noqa: E402
from subdivide import split_in_four  # noqa: E402

SPANS = (10, 25, 50, 100)
# d1: (shape, [(label, mesh or (mesh, splits)), ...]) coarse to fine.
RESOLUTIONS = {
    "spot": [("spot 829", ("spot", 0)), ("spot split once", ("spot", 1)), ("spot split twice", ("spot", 2))],
    "koala": [("koala 5k", ("koala5k", 0)), ("koala 12k", ("koala12k", 0)), ("koala 50k", ("koala", 0))],
}


def prepared(ed, V, F, edit_name, lam, cache_name):
    """(deformer, targets, reference positions, residual, free indices) of a cell."""
    handles, static, targets = edit(V, edit_name)
    d = ed.Deformer(V, F)
    d.set_constraints(handles, static)
    d.set_stiffness(lam)
    X, residual, _ = cached_reference(d, cache_name, edit_name, "edge", lam, targets, cap=8000)
    return d, handles, static, targets, X, residual


def mesh_at(spec):
    name, splits = spec
    V, F = load_mesh(name)
    for _ in range(splits):
        V, F = split_in_four(V, F)
    return V, F


def d1(ed, args, log):
    rows, apart = [], []
    for shape in args.shapes.split(","):
        results = []
        for label, spec in RESOLUTIONS[shape][:args.levels]:
            V, F = mesh_at(spec)
            cache = f"{spec[0]}_split{spec[1]}" if spec[1] else spec[0]
            d, h, s, t, X, residual = prepared(ed, V, F, "lift", 1.0, cache)
            lin = Linearization(d, X, 1.0)
            mu, _, row = top_modes(lin, args.p1)
            n = len(d.free_vertices)
            rows.append({"shape": shape, "mesh": label, "vertices": len(V), "free": n, "mu": float(mu[0]),
                         "one_minus_mu_times_free": float((1 - mu[0]) * n), "reference_residual": residual,
                         "products": row["products"], "seconds": row["seconds"]})
            log(rows[-1])
            results.append((label, V, X))
        for (la, Va, Xa), (lb, Vb, Xb) in zip(results, results[1:]):
            apart.append({"shape": shape, "coarse": la, "fine": lb,
                          "distance": float(result_distance(Va, Xa, Vb, Xb) / diagonal(Vb))})
            log(apart[-1])
    return {"rows": rows, "apart": apart}


def result_distance(Vc, Xc, Vf, Xf):
    """Largest distance between the fine result and the coarse one carried to the fine
    vertices (each fine vertex moved by its nearest coarse vertex's displacement)."""
    from scipy.spatial import cKDTree
    _, nearest = cKDTree(Vc).query(Vf)
    return np.linalg.norm(Xf - (Vf + (Xc - Vc)[nearest]), axis=1).max()


def spans(lin, basis, e):
    return {p: captured_fraction(lin, basis[:p], e) for p in SPANS if p <= len(basis)}


def d2(ed, args, log):
    rows = []
    for cell in args.cells.split(","):
        name, edit_name = cell.split(":")
        V, F = load_mesh(name)
        d, h, s, t, X, residual = prepared(ed, V, F, edit_name, 1.0, name)
        free = np.asarray(d.free_vertices)
        lin = Linearization(d, X, 1.0)
        mu, basis, row = top_modes(lin, args.p)
        log({"cell": cell, "modes at the solution": row, "mu": [float(m) for m in mu[:5]]})
        for kind, Y in iterates(ed, V, F, h, s, t, name, edit_name):
            e = (Y - X)[free]
            here = Linearization(d, Y, 1.0)
            mu_i, basis_i, row_i = top_modes(here, args.p)
            rows.append({"cell": cell, "iterate": kind, "free": len(free),
                         "distance": float(np.linalg.norm(e, axis=1).max() / diagonal(V)),
                         "mu_at_solution": [float(m) for m in mu[:3]],
                         "mu_at_iterate": [float(m) for m in mu_i[:3]],
                         "share_solution_modes": spans(lin, basis, e), "share_iterate_modes": spans(lin, basis_i, e),
                         "products": row["products"] + row_i["products"]})
            log(rows[-1])
    return {"rows": rows, "p": args.p}


def iterates(ed, V, F, h, s, t, name, edit_name):
    """(kind, positions): a cold Anderson solve after 100 iterations; for the lift, Live's
    shape when the mouse stops (bench_live_settle's drag of 30 ticks, the add-on's policy)."""
    d = ed.Deformer(V, F)
    d.set_constraints(h, s)
    d.set_stiffness(1.0)
    yield "cold Anderson, 100 iterations", np.asarray(
        d.solve(t, max_iterations=100, tolerance=0.0, acceleration="anderson").positions)
    if edit_name == "lift":
        import bench_live_settle as live
        d = ed.Deformer(V, F)
        d.set_constraints(h, s)
        d.set_stiffness(1.0)
        budget = live.settle.Settle(limit=10 ** 9)
        d.solve(V[h], max_iterations=1, warm_start=False, acceleration="anderson")
        r = None
        for k in range(1, 31):
            r, _ = live.tick(d, V[h] + (k / 30) * (t - V[h]), budget, True, "anderson")
        yield "Live (Anderson) when the mouse stops", np.asarray(r.positions)


def d3(ed, args, log):
    import arc_anderson as arcs
    rows = []
    variants = [("positions", 5), ("damped", 5), ("rotations", 5), ("rotations", 20), ("judged after a plain step", 5),
                ("lbfgs", 5)]
    for cell in args.cells.split(","):
        name, edit_name = cell.split(":")
        V, F = load_mesh(name)
        d, h, s, t, X, residual = prepared(ed, V, F, edit_name, 1.0, name)
        for variant, window in variants:
            t0 = time.perf_counter()
            steps, stats = arcs.run(variant, d, V, h, t, X, window, args.budget)
            rows.append({"cell": cell, "variant": variant, "window": window, "global_steps": steps,
                         "budget": args.budget, "stats": stats, "seconds": time.perf_counter() - t0})
            log(rows[-1])
    return {"rows": rows}


def markdown_d1(result):
    lines = ["The largest eigenvalue μ of J_G at the λ 1 lift's solution (ARPACK on the analytic J_G, "
             "symmetric in A's inner product), against the free vertices n. Constant (1 − μ)·n means 1 − μ ∝ 1/n: "
             "bending modes whose stiffness vanishes with refinement.", "",
             "| shape | mesh | vertices | free n | μ | (1 − μ)·n |", "|---|---|---|---|---|---|"]
    for r in result["rows"]:
        lines.append(f"| {r['shape']} | {r['mesh']} | {r['vertices']:,} | {r['free']:,} | {r['mu']:.5f} | "
                     f"{r['one_minus_mu_times_free']:.1f} |")
    lines += ["", "How far the λ 1 results at two resolutions lie apart (largest vertex distance / diag):", "",
              "| shape | coarse | fine | apart |", "|---|---|---|---|"]
    for a in result["apart"]:
        lines.append(f"| {a['shape']} | {a['coarse']} | {a['fine']} | {a['distance']:.1e} |")
    return "\n".join(lines)


def markdown_d2(result):
    lines = ["The share (A norm) of an iterate's error, against a tight reference, in the span of J_G's top p "
             "eigenvectors, taken at the solution and at the iterate itself. Deflating the soft subspace "
             f"needed ≥ 0.9 with p ≤ {SPANS[-1]}.", "",
             "| cell | iterate | distance | μ at the iterate | p | share, modes at the solution | "
             "share, modes at the iterate |", "|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        for p in r["share_solution_modes"]:
            lines.append(f"| {r['cell']} | {r['iterate']} | {r['distance']:.1e} | "
                         f"{', '.join(f'{m:.5f}' for m in r['mu_at_iterate'])} | {p} | "
                         f"{r['share_solution_modes'][p]:.2f} | {r['share_iterate_modes'].get(p, float('nan')):.2f} |")
    return "\n".join(lines)


def markdown_d3(result):
    lines = ["Global steps (evaluations of G) until within 1e-3 of the diagonal of the reference, λ 1, from a "
             "cold start, in one Python harness (bench/arc_anderson.py) so that the variants compare alike; "
             "'—' where the budget ran out.", "",
             "| cell | variant | window | global steps | accelerated / kept | rejected |", "|---|---|---|---|---|---|"]
    for r in result["rows"]:
        st = r["stats"]
        lines.append(f"| {r['cell']} | {r['variant']} | {r['window']} | "
                     f"{r['global_steps'] if r['global_steps'] else '— (' + str(r['budget']) + ')'} | "
                     f"{st.get('accepted', 0)} | {st.get('rejected', 0)} |")
    return "\n".join(lines)


def markdown(result):
    return {"d1": markdown_d1, "d2": markdown_d2, "d3": markdown_d3}[result["diagnostic"]](result)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("diagnostic", choices=("d1", "d2", "d3"))
    ap.add_argument("--cells", default=None, help="d2: koala:lift,spot11k:side+ ; d3: spot11k:side+,dino:side+")
    ap.add_argument("--p", type=int, default=100, help="d2: eigenvectors computed")
    ap.add_argument("--p1", type=int, default=4, help="d1: eigenvalues computed (the largest is reported)")
    ap.add_argument("--shapes", default=",".join(RESOLUTIONS), help="d1: " + ", ".join(RESOLUTIONS))
    ap.add_argument("--levels", type=int, default=3, help="d1: resolutions of each shape, coarse first")
    ap.add_argument("--budget", type=int, default=2000, help="d3: global steps")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    args.cells = args.cells or {"d1": "", "d2": "koala:lift,spot11k:side+", "d3": "spot11k:side+,dino:side+"}[
        args.diagnostic]
    import edgedeform as ed
    run = {"d1": d1, "d2": d2, "d3": d3}[args.diagnostic]
    result = {"diagnostic": args.diagnostic, "machine": machine_info(),
              "command": "bench/bench_soft_modes.py " + " ".join(argv if argv is not None else sys.argv[1:])}
    result.update(run(ed, args, lambda row: print(json.dumps(row), flush=True)))
    out = Path(args.json or HERE / "results" / f"soft_modes_{args.diagnostic}.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1))
    print(markdown(result))


if __name__ == "__main__":
    main()
