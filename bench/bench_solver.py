#!/usr/bin/env python3
"""The solver's methods against each other, cold, to 1e-3 of the diagonal: the data of the
default rule ("auto": L-BFGS where λ = 1, Anderson below; docs/decisions/0070) and of its
targets: every cell converged and claimed within 2,000 iterations, each claim within twice
the tolerance of a tight reference.

Each row is one method on one cell (mesh, edit, λ; edge domain), solved from a fresh
Deformer (assembly and factorization included). Reported: wall time, global steps, L-BFGS's
extra line-search fits, accelerated and rejected steps, the claim and its estimate, and two
distances. "Run on": to where the same solve goes when continued to a residual of 1e-10 (the
claim's honesty: a claim is judged against the fixed point its own iteration reaches). "To
the default's": to the cell's reference, the default solve run to a residual of 1e-10
(bench_convergence.cached_reference); an edit can have several fixed points (the bent
cylinder at λ 1 has three, up to 6e-3 of the diagonal apart), and the energies tell which
is lower. Where a run does not reach a residual of 1e-8 the row says "no ref.".
"auto" is run only at λ = 1: below it it is Anderson, bit for bit
(tests/python/test_solver_methods.py).

The cells: bench_newton's set (record 0029: the lift on dino, head, Spot 11.5k and koala),
the held-out edits of record 0070 on the same meshes (bench/edits.py: side+, side-,
side_low+, side_low-, twist60, bend90), and a thin capped cylinder bent 90°; at λ 1 and 0.5.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_solver.py \\
        [--cells koala:lift:1,spot11k:side+:0.5] [--methods anderson,auto] [--json PATH]
    bench/bench_solver.py --plot-from bench/results/solver.json

Prints a table and writes the JSON (with the machine and its load) and, with matplotlib, a
plot beside it (each cell's time over Anderson's); bench/report.py puts both into
docs/benchmarks_solver.md.
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
from edits import EDITS, GENERATED, MESH_FILES, diagonal, edit, load_mesh  # noqa: E402
from machine import machine_info  # noqa: E402

MESHES = ("dino", "head", "spot11k", "koala")
HELD_OUT = ("side+", "side-", "side_low+", "side_low-", "twist60", "bend90")
LAMBDAS = (1.0, 0.5)
DEFAULT_CELLS = ",".join(
    [f"{m}:lift:{lam:g}" for lam in LAMBDAS for m in MESHES]
    + [f"{m}:{e}:{lam:g}" for lam in LAMBDAS for m in MESHES for e in HELD_OUT]
    + [f"cylinder:bend90:{lam:g}" for lam in LAMBDAS])
TOLERANCE = 1e-3
MAX_ITERATIONS = 2000
REFERENCE_RESIDUAL = 1e-8   # a reference whose residual is above this is none


def parse_cell(text):
    """"mesh:edit:λ"."""
    parts = text.split(":")
    if (len(parts) != 3 or parts[0] not in set(MESH_FILES) | set(GENERATED) or parts[1] not in EDITS):
        raise SystemExit(f"bad cell {text!r}: mesh:edit:lambda, mesh one of "
                         f"{', '.join(list(MESH_FILES) + list(GENERATED))}, edit one of {', '.join(EDITS)}")
    return parts[0], parts[1], float(parts[2])


def solve(ed, V, F, handles, static, lam, targets, method):
    """(the result, its wall time, where the same iteration goes when run on: positions and
    residual)."""
    start = time.perf_counter()
    d = ed.Deformer(V, F)
    d.set_constraints(handles, static)
    d.set_stiffness(lam)
    r = d.solve(targets, max_iterations=MAX_ITERATIONS, tolerance=TOLERANCE, acceleration=method)
    wall = time.perf_counter() - start
    on = d.solve(targets, max_iterations=4 * MAX_ITERATIONS, tolerance=1e-10, acceleration=method)
    return r, wall, np.asarray(on.positions), float(on.residuals[-1])


def run_cell(ed, cell, methods, log):
    name, edit_name, lam = parse_cell(cell)
    V, F = load_mesh(name)
    handles, static, targets = edit(V, edit_name)
    probe = ed.Deformer(V, F)
    probe.set_constraints(handles, static)
    probe.set_stiffness(lam)
    X_ref, ref_residual, ref_iterations = cached_reference(probe, name, edit_name, "edge", lam, targets, cap=8000)
    has_reference = ref_residual < REFERENCE_RESIDUAL
    dg = diagonal(V)
    rows = []
    for method in methods:
        if method == "auto" and lam < 1.0:
            continue  # Anderson's run, bit for bit
        r, wall, X_on, on_residual = solve(ed, V, F, handles, static, lam, targets, method)
        distance = float(np.linalg.norm(r.positions - X_ref, axis=1).max() / dg) if has_reference else None
        run_on = (float(np.linalg.norm(r.positions - X_on, axis=1).max() / dg)
                  if on_residual < REFERENCE_RESIDUAL else None)
        row = {"mesh": name, "edit": edit_name, "lambda": lam, "method": method, "ran": r.method,
               "vertices": len(V), "free": r.free_vertices, "wall_s": wall, "iterations": r.iterations,
               "line_search_fits": r.line_search_fits, "accelerated_steps": r.accelerated_steps,
               "rejected_steps": r.rejected_steps, "converged": bool(r.converged),
               "distance_estimate": float(r.distance_estimate), "energy": float(r.energies[-1]),
               "distance_to_reference": distance, "reference_residual": ref_residual,
               "reference_iterations": ref_iterations,
               "reference_energy": float(probe.energy(X_ref)) if has_reference else None,
               "distance_run_on": run_on, "run_on_residual": on_residual,
               "claim_within_2_tolerance": (run_on <= 2 * TOLERANCE) if (r.converged and run_on is not None)
               else None}
        rows.append(row)
        log(row)
    return rows


def ratios(rows):
    """{(mesh, edit, λ): wall of auto over Anderson's} where both ran."""
    by = {(r["mesh"], r["edit"], r["lambda"], r["method"]): r for r in rows}
    out = {}
    for (mesh, e, lam, method), r in by.items():
        base = by.get((mesh, e, lam, "anderson"))
        if method == "auto" and base:
            out[(mesh, e, lam)] = r["wall_s"] / base["wall_s"]
    return out


def markdown(result):
    rows = result["rows"]
    lines = [
        "Cold solves from a fresh Deformer (assembly and factorization included), edge domain, "
        f"tolerance {TOLERANCE:g}, at most {MAX_ITERATIONS} iterations. *auto* is the default (L-BFGS at λ 1, "
        "run only there: below it is Anderson's row). 'fits+' counts L-BFGS's local fits beyond one an "
        "iteration; 'rej.' Anderson's rejected steps or L-BFGS's failed line searches. Distances / diag: "
        "'run on' to where the same solve goes when continued to a residual of 1e-10 (a claim farther "
        "than twice the tolerance in bold), 'default's' to the default solve's tight result; 'E − E_ref' the "
        "energy over that result's, relative (λ 1: below 0, a lower minimum); 'no ref.' where a run did "
        "not reach a residual of 1e-8.",
        "",
        "| cell | free | method (ran) | wall s | × Anderson | iterations | fits+ | rej. | converged | "
        "estimate | run on | default's | E − E_ref |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    rat = ratios(rows)
    for r in rows:
        ratio = rat.get((r["mesh"], r["edit"], r["lambda"])) if r["method"] == "auto" else None
        on = r["distance_run_on"]
        if on is None:
            shown_on = "no ref."
        elif r["converged"] and on > 2 * TOLERANCE:
            shown_on = f"**{on:.1e}**"
        else:
            shown_on = f"{on:.1e}"
        dist = r["distance_to_reference"]
        ref_e = r["reference_energy"]
        energy = f"{(r['energy'] - ref_e) / abs(ref_e):+.1e}" if ref_e else ""
        lines.append(
            f"| {r['mesh']} {r['edit']} λ {r['lambda']:g} | {r['free']:,} | {r['method']} ({r['ran']}) | "
            f"{r['wall_s']:.1f} | {'' if ratio is None else f'{ratio:.2f}'} | {r['iterations']} | "
            f"{r['line_search_fits']} | {r['rejected_steps']} | {'yes' if r['converged'] else '**no**'} | "
            f"{r['distance_estimate']:.1e} | {shown_on} | {'no ref.' if dist is None else f'{dist:.1e}'} | "
            f"{energy} |")
    claimed = [r for r in rows if r["converged"]]
    judged = [r for r in claimed if r["claim_within_2_tolerance"] is not None]
    far = [r for r in judged if not r["claim_within_2_tolerance"]]
    for method in sorted({r["method"] for r in rows}):
        mine = [r for r in rows if r["method"] == method]
        lines.append("")
        lines.append(f"- {method}: {sum(r['converged'] for r in mine)} of {len(mine)} cells converged and claimed "
                     f"within {MAX_ITERATIONS} iterations"
                     + (f"; median time over Anderson's {np.median(list(rat.values())):.2f}"
                        if method == "auto" and rat else "") + ".")
    lines.append(f"- Claims judged against their own run on: {len(judged)}; farther than twice the tolerance: "
                 f"{len(far)}" + (" (" + ", ".join(f"{r['mesh']} {r['edit']} λ {r['lambda']:g} {r['method']}"
                                                  for r in far) + ")" if far else "") + ".")
    lines += ["", "![the default's time over Anderson's per cell at λ 1](../bench/results/solver.png)"]
    return "\n".join(lines)


def plot(result, path):
    """auto's wall time over Anderson's per λ-1 cell (log scale), when matplotlib is there."""
    try:
        import matplotlib
    except ImportError:
        return False
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rat = ratios(result["rows"])
    if not rat:
        return False
    cells = sorted(rat, key=lambda c: rat[c])
    fig, ax = plt.subplots(figsize=(8, 0.25 * len(cells) + 1.5))
    ax.barh([f"{m} {e}" for m, e, _ in cells], [rat[c] for c in cells], color="tab:blue")
    ax.axvline(1.0, color="k", lw=0.8)
    ax.axvline(1 / 3, color="tab:green", lw=0.8, ls="--", label="target on the koala lift: 1/3")
    ax.set_xscale("log")
    ax.set_xlabel("the default's (L-BFGS) wall time / Anderson's, cold to 1e-3, λ 1\n"
                  "(Anderson stopped at 2,000 iterations where it does not converge)")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return True


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS)
    ap.add_argument("--methods", default="anderson,auto")
    ap.add_argument("--json", default=str(HERE / "results" / "solver.json"))
    ap.add_argument("--plot-from", default=None, help="only write the plot from this JSON")
    args = ap.parse_args(argv)
    if args.plot_from:
        plot(json.loads(Path(args.plot_from).read_text()), Path(args.plot_from).with_suffix(".png"))
        return
    import edgedeform as ed
    start = machine_info()
    rows = []
    for cell in args.cells.split(","):
        rows += run_cell(ed, cell, args.methods.split(","), lambda row: print(json.dumps(row), flush=True))
    result = {"machine": start, "machine_end": machine_info(), "rows": rows,
              "command": "bench/bench_solver.py " + " ".join(argv if argv is not None else sys.argv[1:])}
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1))
    plot(result, out.with_suffix(".png"))
    print(markdown(result))


if __name__ == "__main__":
    main()
