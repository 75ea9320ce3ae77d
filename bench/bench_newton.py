#!/usr/bin/env python3
"""Newton against Anderson, cold, to 1e-3 and 1e-6 of the diagonal: the data of the default
rule (edgedeform's automatic method) and of the diagnostic D1 that chose the Newton method
(docs/decisions/0029).

Each row is one method on one cell (mesh, edit, domain, λ), solved from a fresh Deformer
(assembly and factorization included) to each tolerance. Reported: wall time, global steps
(evaluations of G), Newton steps, factorizations of the Newton matrix K, the final energy
and the distance to the cell's reference (bench_convergence.cached_reference: a default solve
run to a residual of 1e-10).

Methods:
- anderson: Anderson-accelerated local/global;
- newton: acceleration="newton" as shipped (an Anderson lead-in, then projected Newton);
- d1-full: D1 as first planned: no lead-in; K itself where it factors, else every
  indefinite term projected (the per-node positive model); straight line search;
- d1-ladder: no lead-in; only the terms below a level that factors projected; straight;
- d1-lifted: no lead-in; the ladder, and the trials lifted into the fit.
Newton steps are taken only at λ = 1 (record 0029): below it every method here runs Anderson,
so the cells at λ < 1 in bench/results/newton.json keep the retired LU Newton's rows of the
run that decided it.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_newton.py \\
        [--cells koala:lift:1,spot11k:lift:0.5] [--methods anderson,newton] [--tolerances 1e-3,1e-6] \\
        [--max-iterations 4000] [--out bench/results/newton.json]
    bench/bench_newton.py --plot-from bench/results/newton.json   # only the plot, from a JSON

Prints a table and writes the JSON (with the machine and its load) and, with matplotlib, a
plot next to it (.png: each method's time over Anderson's per cell); bench/report.py puts
the table and the plot into docs/benchmarks_solver.md.
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
from edits import MESH_FILES, diagonal, edit, mesh_path  # noqa: E402
from machine import machine_info  # noqa: E402

# λ 1 only: below it every method here is Anderson. A run writes a fresh JSON: the retired
# LU rows at λ 0.5 in bench/results/newton.json are then kept by git and record 0029.
DEFAULT_CELLS = "dino:lift:1,head:lift:1,spot11k:lift:1,koala:lift:1"
METHODS = {
    "anderson": None,
    "newton": {},
    "d1-full": {"lead_in": 0, "projection": "full", "lifted": False},
    "d1-ladder": {"lead_in": 0, "lifted": False},
    "d1-lifted": {"lead_in": 0},
}
MAX_ITERATIONS = 4000


def parse_cell(text):
    """"mesh:edit:λ" or "mesh:edit:domain:λ" (domain edge by default)."""
    parts = text.split(":")
    if len(parts) == 3:
        parts.insert(2, "edge")
    if len(parts) != 4 or parts[0] not in MESH_FILES:
        raise SystemExit(f"bad cell {text!r}: mesh:edit[:domain]:lambda, mesh one of {', '.join(MESH_FILES)}")
    return parts[0], parts[1], parts[2], float(parts[3])


def solve(ed, V, F, handles, static, domain, lam, targets, method, tolerance, max_iterations):
    start = time.perf_counter()
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(handles, static)
    d.set_stiffness(lam)
    if method == "anderson":
        r = d.solve(targets, max_iterations=max_iterations, tolerance=tolerance, acceleration="anderson")
    else:
        r = d.solve(targets, max_iterations=max_iterations, tolerance=tolerance, acceleration="newton",
                    newton=ed.NewtonOptions(**METHODS[method]))
    return r, time.perf_counter() - start


def run_cell(ed, cell, methods, tolerances, max_iterations, log):
    from edgedeform.mesh_files import read_mesh
    name, edit_name, domain, lam = parse_cell(cell)
    V, F = read_mesh(mesh_path(MESH_FILES[name]))
    handles, static, targets = edit(V, edit_name)
    probe = ed.Deformer(V, F, domain=domain)
    probe.set_constraints(handles, static)
    probe.set_stiffness(lam)
    X_ref, ref_residual, _ = cached_reference(probe, MESH_FILES[name].split(".")[0], edit_name, domain, lam, targets)
    E_ref = probe.energy(X_ref)
    dg = diagonal(V)
    rows = []
    for method in methods:
        if lam < 1.0 and method.startswith("d1"):
            continue  # Newton steps only at lambda 1: below it these are Anderson (record 0029)
        for tol in tolerances:
            r, wall = solve(ed, V, F, handles, static, domain, lam, targets, method, tol, max_iterations)
            row = {"mesh": name, "edit": edit_name, "domain": domain, "lambda": lam, "method": method,
                   "tolerance": tol, "vertices": len(V), "free": r.free_vertices, "wall_s": wall,
                   "iterations": r.iterations, "newton_steps": r.newton_steps,
                   "factorizations": r.newton_factorizations, "newton_fallbacks": r.newton_fallbacks,
                   "assemble_s": r.assemble_ms / 1e3, "newton_factor_s": r.newton_factor_ms / 1e3,
                   "converged": bool(r.converged), "distance_estimate": float(r.distance_estimate),
                   "energy": float(r.energies[-1]) if len(r.energies) else None, "reference_energy": float(E_ref),
                   "distance_to_reference": float(np.linalg.norm(r.positions - X_ref, axis=1).max() / dg),
                   "reference_residual": ref_residual}
            rows.append(row)
            log(row)
    return rows


def plot(result, path):
    """Each method's wall time over Anderson's, per cell and tolerance (log scale), when
    matplotlib is installed; False when no plot was written."""
    try:
        import matplotlib
    except ImportError:
        print("no matplotlib: newton plot not written", flush=True)
        return False
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    anderson = {(r["mesh"], r["lambda"], r["tolerance"]): r["wall_s"] for r in result["rows"] if r["method"] == "anderson"}
    keys = sorted({(r["mesh"], r["lambda"]) for r in result["rows"]}, key=lambda k: (k[1], k[0]))
    methods = [m for m in dict.fromkeys(r["method"] for r in result["rows"]) if m != "anderson"]
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), sharey=True)
    width = 0.8 / max(1, len(methods))
    for ax, tol in zip(axes, (1e-3, 1e-6)):
        for j, method in enumerate(methods):
            xs, ys, hatches = [], [], []
            for i, (mesh, lam) in enumerate(keys):
                row = next((r for r in result["rows"] if (r["mesh"], r["lambda"], r["tolerance"], r["method"]) ==
                            (mesh, lam, tol, method)), None)
                if row is None or (mesh, lam, tol) not in anderson:
                    continue
                xs.append(i + (j - (len(methods) - 1) / 2) * width)
                ys.append(row["wall_s"] / anderson[(mesh, lam, tol)])
                hatches.append("" if row["converged"] else "xx")
            bars = ax.bar(xs, ys, width, label=method)
            for bar, hatch in zip(bars, hatches):
                bar.set_hatch(hatch)
        ax.axhline(1.0, color="k", lw=1, ls=":")
        ax.set_yscale("log")
        ax.set_xticks(range(len(keys)))
        ax.set_xticklabels([f"{m}\nλ {lam:g}" for m, lam in keys], fontsize=8)
        ax.set_title(f"to {tol:g} of the diagonal (hatched: not converged)")
    axes[0].set_ylabel("wall time / Anderson's (same run)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    return True


def markdown(result, png_rel="../bench/results/newton.png"):
    """One row per cell, method and tolerance; the time relative to Anderson's in the same run."""
    anderson = {(r["mesh"], r["edit"], r["domain"], r["lambda"], r["tolerance"]): r["wall_s"]
                for r in result["rows"] if r["method"] == "anderson"}
    lines = ["| cell | free | method | tolerance | wall s | × Anderson | global steps | Newton steps | "
             "factorizations | converged | distance to reference | E − E_ref |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        key = (r["mesh"], r["edit"], r["domain"], r["lambda"], r["tolerance"])
        ratio = f"{r['wall_s'] / anderson[key]:.2f}" if key in anderson else "–"
        dE = (r["energy"] - r["reference_energy"]) if r["energy"] is not None else float("nan")
        lines.append(f"| {r['mesh']} {r['edit']} {r['domain']} λ {r['lambda']:g} | {r['free']} | {r['method']} | "
                     f"{r['tolerance']:g} | {r['wall_s']:.1f} | {ratio} | {r['iterations']} | {r['newton_steps']} | "
                     f"{r['factorizations']} | {'yes' if r['converged'] else 'no'} | "
                     f"{r['distance_to_reference']:.1e} | {dE:+.1e} |")
    if result.get("note"):
        lines += ["", result["note"]]
    if png_rel:
        lines += ["", f"![each method's time over Anderson's, per cell]({png_rel})"]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS)
    ap.add_argument("--methods", default="anderson,newton")
    ap.add_argument("--tolerances", default="1e-3,1e-6")
    ap.add_argument("--max-iterations", type=int, default=MAX_ITERATIONS)
    ap.add_argument("--out", default=str(HERE / "results" / "newton.json"))
    ap.add_argument("--plot-from", help="write only the plot of this JSON (next to it, .png)")
    args = ap.parse_args(argv)
    if args.plot_from:
        plot(json.loads(Path(args.plot_from).read_text()), Path(args.plot_from).with_suffix(".png"))
        return
    import edgedeform as ed
    methods = [m for m in args.methods.split(",") if m]
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise SystemExit(f"unknown method(s) {', '.join(unknown)}: choose from {', '.join(METHODS)}")
    cells = [c for c in args.cells.split(",") if c]
    for c in cells:
        parse_cell(c)
    tolerances = [float(t) for t in args.tolerances.split(",")]
    result = {"machine": machine_info(), "command": "bench/bench_newton.py " + " ".join(argv or sys.argv[1:]),
              "rows": []}
    for cell in cells:
        result["rows"] += run_cell(ed, cell, methods, tolerances, args.max_iterations,
                                   lambda row: print(json.dumps(row), flush=True))
        Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    result["machine_end"] = machine_info()
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    plot(result, Path(args.out).with_suffix(".png"))
    print(markdown(result, png_rel=None))


if __name__ == "__main__":
    main()
