"""Newton-Krylov against Anderson and the plain method on the large benchmark meshes.

Each cell is a cold default solve (a fresh Deformer: assembly and factorization included)
to a tolerance of 1e-3 of the diagonal, timed by the wall clock, and its distance to the
cell's reference (a solve run to a residual of 1e-10, cached in bench/results/cache/ and
checked before reuse, as bench_convergence.py does).

    python bench/bench_newton.py [--meshes koala.obj] [--lambdas 0.5,1] [--methods newton,anderson,none]
                                 [--newton-coarse 200:0,200:16] [--krylov-iterations 30]
                                 [--max-iterations 2000] [--out bench/results/newton.json]

--newton-coarse runs Newton once per coarse space, P:S = P patches blended by S smoothing
steps (coarse_space.h); a row names its space.

Prints a table and writes the JSON (with the machine and its load) and a PNG beside it.
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
from edits import diagonal, edit, mesh_path, method_list  # noqa: E402
from machine import machine_info  # noqa: E402


def runs(methods, newton_coarse):
    """(method, solve keywords) per row: Newton once per coarse space."""
    out = []
    for m in methods:
        if m == "newton":
            out += [(m, {"coarse_patches": p, "coarse_blend": s}) for p, s in newton_coarse]
        else:
            out.append((m, {}))
    return out


def cell(ed, V, F, mesh, edit_name, domain, lam, methods, max_iterations, tolerance, newton_coarse=((200, 0),),
         krylov_iterations=30, newton_max_iterations=None):
    handles, static, targets = edit(V, edit_name)
    probe = ed.Deformer(V, F, domain=domain)
    probe.set_constraints(handles, static)
    probe.set_stiffness(lam)
    X_ref, ref_residual, ref_iterations = cached_reference(probe, mesh.split(".")[0], edit_name, domain, lam, targets)
    rows = []
    for method, coarse in runs(methods, newton_coarse):
        start = time.perf_counter()
        d = ed.Deformer(V, F, domain=domain)
        d.set_constraints(handles, static)
        d.set_stiffness(lam)
        extra = dict(coarse, krylov_iterations=krylov_iterations) if method == "newton" else {}
        cap = newton_max_iterations if method == "newton" and newton_max_iterations else max_iterations
        r = d.solve(targets, max_iterations=cap, tolerance=tolerance, acceleration=method, **extra)
        wall = time.perf_counter() - start
        dist = float(np.linalg.norm(r.positions - X_ref, axis=1).max() / diagonal(V))
        rows.append({
            "mesh": mesh, "edit": edit_name, "domain": domain, "lambda": lam, "method": method,
            "vertices": len(V), "max_iterations": cap, "wall_s": wall, "factor_ms": r.factor_ms, "iterations": r.iterations,
            "newton_steps": r.newton_steps, "krylov_iterations": r.krylov_iterations,
            "coarse_dimension": r.coarse_dimension, "line_search_failures": r.line_search_failures,
            "coarse_patches": coarse.get("coarse_patches"), "coarse_blend": coarse.get("coarse_blend"),
            "coarse_ms": r.coarse_ms, "krylov_ms": r.krylov_ms,
            "converged": bool(r.converged), "distance_estimate": float(r.distance_estimate),
            "distance_to_reference": dist, "within_tolerance": dist <= tolerance,
            "reference_residual": ref_residual, "reference_iterations": ref_iterations,
        })
        label = method + (f" {coarse['coarse_patches']}:{coarse['coarse_blend']}" if coarse else "")
        print(f"{mesh:>12} {edit_name:>5} {domain:>6} {lam:4.2f} {label:>14} {wall:8.2f} s {r.iterations:6d} it "
              f"{r.newton_steps:3d} N {r.krylov_iterations:4d} K  conv={r.converged!s:5} dist={dist:.1e}", flush=True)
    return rows


def row_label(r):
    """The method, with Newton's coarse space (patches:blend steps) when it has one."""
    if r.get("coarse_patches") is None:
        return r["method"]
    return f"{r['method']} ({r['coarse_patches']}:{r['coarse_blend']})"


def plot(rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    labels = sorted({(r["mesh"], r["edit"], r["domain"], r["lambda"]) for r in rows})
    methods = list(dict.fromkeys(row_label(r) for r in rows))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    width = 0.8 / max(len(methods), 1)
    for k, m in enumerate(methods):
        ys = [next((r["wall_s"] for r in rows if (r["mesh"], r["edit"], r["domain"], r["lambda"]) == lab and row_label(r) == m), 0)
              for lab in labels]
        ax.bar([i + k * width for i in range(len(labels))], ys, width, label=m)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(labels))])
    ax.set_xticklabels([f"{a.split('.')[0]} {b}\n{c} λ={d:g}" for a, b, c, d in labels], fontsize=8)
    ax.set_ylabel("cold solve, wall (s)\n(to 1e-3 diag or its cap: see the table)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return path


def markdown(result):
    """The benchmark page's section: one row per cell and method (bench/report.py heads it
    with the run's date, machine and command)."""
    lines = [f"Cold solves (factorization included) to {result['tolerance']:g} of the "
             "diagonal; distance to a reference run to a residual of 1e-10.", "",
             "| mesh | edit | domain | λ | method | wall (s) | iterations | Newton steps | Krylov products | "
             "converged | distance to reference |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        lines.append(f"| {r['mesh'].split('.')[0]} | {r['edit']} | {r['domain']} | {r['lambda']:g} | {row_label(r)} | "
                     f"{r['wall_s']:.2f} | {r['iterations']} | {r['newton_steps']} | {r['krylov_iterations']} | "
                     f"{'yes' if r['converged'] else 'no, stopped at ' + str(r.get('max_iterations', r['iterations']))} | "
                     f"{r['distance_to_reference']:.1e} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--meshes", default="koala.obj")
    p.add_argument("--edits", default="lift")
    p.add_argument("--domains", default="edge")
    p.add_argument("--lambdas", default="0.5,1")
    p.add_argument("--methods", default=None, help="comma-separated; default: every method the module offers")
    p.add_argument("--newton-coarse", default="200:0", help="Newton's coarse spaces, P:S (patches:blend steps)")
    p.add_argument("--krylov-iterations", type=int, default=30)
    p.add_argument("--newton-max-iterations", type=int, default=None,
                   help="Newton's own cap (default: --max-iterations), for meshes where it is slow")
    p.add_argument("--max-iterations", type=int, default=2000)
    p.add_argument("--tolerance", type=float, default=1e-3)
    p.add_argument("--out", default=str(HERE / "results" / "newton.json"))
    a = p.parse_args(argv)
    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh
    methods = method_list(ed, a.methods)
    newton_coarse = [tuple(int(x) for x in (k + ":0").split(":")[:2]) for k in a.newton_coarse.split(",") if k]
    rows = []
    for mesh in a.meshes.split(","):
        V, F = read_mesh(mesh_path(mesh))[:2]
        for edit_name in a.edits.split(","):
            for domain in a.domains.split(","):
                for lam in (float(x) for x in a.lambdas.split(",")):
                    rows += cell(ed, V, F, mesh, edit_name, domain, lam, methods, a.max_iterations, a.tolerance,
                                 newton_coarse, a.krylov_iterations, a.newton_max_iterations)
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    picture = plot(rows, out.with_suffix(".png"))
    shown = [in_repo(arg) for arg in (argv or sys.argv[1:])]
    out.write_text(json.dumps({"machine": machine_info(), "command": " ".join(["bench/bench_newton.py"] + shown),
                               "tolerance": a.tolerance, "rows": rows, "plot": picture and Path(picture).name}, indent=1))
    print(f"wrote {out}")


def in_repo(arg):
    """An absolute path inside the repository as a path from its root (the recorded command
    then names no directory of the machine it ran on); any other argument unchanged."""
    path = Path(arg)
    if not path.is_absolute():
        return arg
    try:
        return str(path.resolve().relative_to(HERE.parent))
    except ValueError:
        return arg


if __name__ == "__main__":
    main()
