#!/usr/bin/env python3
"""Convergence benchmark: iterations and core milliseconds to come within 1e-3 of the
bounding-box diagonal of the fixed point, for each acceleration method the build accepts
("none" is the plain local/global iteration).

Meshes: the samples in blend_samples/meshes. Edits: lift, twist and bend of bench/edits.py.
Reference: the fixed point, from the accelerated iteration run to a residual of 1e-10 diag
(tolerance 1e-9, at most 3000 iterations), then continued plainly (at most 1000 more)
until its residual is below 1e-10 diag; the JSON records the residual reached (both methods have the same fixed points; the tests check
that against the plain method alone). Each run takes one iteration per call
(warm solves with unchanged targets continue the same iteration) and stops as soon as every
vertex is within 1e-3 diag of the reference; ms = factorization + local + rhs + solve time
reported by the core (Python overhead excluded).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_convergence.py
        [--meshes dino,plane] [--edits lift] [--methods anderson,none] [--budget 2000]
        [--koala | --koala-only] [--json PATH]

Prints a table, writes bench/results/convergence.json (convergence_koala.json with
--koala-only) and bench/results/convergence.png; bench/report.py puts the tables into
docs/benchmarks.md.
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

from edits import MESH_FILES, diagonal, edit, mesh_path, method_list  # noqa: E402
from machine import machine_info  # noqa: E402

SAMPLES = {name: MESH_FILES[name] for name in ("dino", "head", "plane", "spot")}   # the default --meshes
LAMBDAS = (0.0, 0.5, 1.0)
DOMAINS = ("edge", "primal")
GOAL = 1e-3
CHECKPOINTS = {1, 10, 25, 50, 100, 200, 400, 600, 800, 1000, 1200, 1500, 2000}


def core_ms(r):
    return float(r.factor_ms + r.local_ms + r.rhs_ms + r.solve_ms)


def reference(d, targets, chunk=500, cap=3000):
    r = d.solve(targets, max_iterations=cap, tolerance=1e-9, warm_start=False)
    total = r.iterations
    while r.residuals[-1] >= 1e-10 and total < cap + 1000:
        r = d.solve(targets, max_iterations=chunk, tolerance=0.0, acceleration="none")
        total += r.iterations
    return np.asarray(r.positions), float(r.residuals[-1]), total


def cached_reference(d, mesh, edit_name, domain, lam, targets, cap=4000):
    """reference(), kept in bench/results/cache/ (not committed): on the 50k koala it takes
    thousands of iterations. Reused for the same targets while still_fixed() holds."""
    cache = HERE / "results" / "cache" / f"reference_{mesh}_{edit_name}_{domain}_{lam:g}.npz"
    if cache.exists():
        z = np.load(cache)
        if np.array_equal(z["targets"], targets) and still_fixed(d, targets, z):
            return z["X"], float(z["residual"]), int(z["iterations"])
    X, res, its = reference(d, targets, cap=cap)
    cache.parent.mkdir(parents=True, exist_ok=True)
    np.savez(cache, X=X, targets=targets, residual=res, iterations=its)
    return X, res, its


def still_fixed(d, targets, cached):
    """Whether a cached reference is still what today's build would compute: one plain step
    from it must move no more than a few times its recorded residual (a change to the solver
    since the cache was written shows up there; the cache key holds only the targets)."""
    X = cached["X"]
    step = d.solve(targets, max_iterations=1, tolerance=0.0, warm_start=False, initial=X,
                   acceleration="none")
    return float(step.residuals[-1]) <= max(5.0 * float(cached["residual"]), 1e-9)


def refactor(d, lam):
    """Make the next solve factorize again, as a first solve does."""
    d.set_stiffness(0.25 if lam != 0.25 else 0.3)
    d.set_stiffness(lam)


def iterations_to_goal(d, targets, X_ref, dg, acceleration, budget, lam, trace=None, window=5):
    """(iterations, ms) until within GOAL*diag of X_ref, or (None, ms) after budget.
    `trace`, a list, gets (iteration, residual, estimate, true distance) at checkpoints."""
    refactor(d, lam)
    r = d.solve(targets, max_iterations=1, tolerance=0.0, warm_start=False,
                acceleration=acceleration, anderson_window=window)
    ms, its = core_ms(r), 1
    while True:
        dist = np.linalg.norm(np.asarray(r.positions) - X_ref, axis=1).max() / dg
        if trace is not None and (its in CHECKPOINTS or dist <= GOAL):
            trace.append((its, float(r.residuals[-1]), float(r.distance_estimate), float(dist)))
        if dist <= GOAL:
            return its, ms
        if its >= budget or not np.all(np.isfinite(r.positions)):
            return None, ms
        r = d.solve(targets, max_iterations=1, tolerance=0.0, acceleration=acceleration,
                    anderson_window=window)
        ms += core_ms(r)
        its += 1


def run_cell(ed, V, F, name, edit_name, domain, lam, budget, methods, log):
    handles, static, targets = edit(V, edit_name)
    dg = diagonal(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(lam)
    t0 = time.perf_counter()
    X_ref, ref_res, ref_its = reference(d, targets)
    ref_s = time.perf_counter() - t0
    runs = {}
    for m in methods:
        its, ms = iterations_to_goal(d, targets, X_ref, dg, m, budget, lam)
        runs[m] = {"iterations": its, "ms": ms}
    refactor(d, lam)
    default = d.solve(targets, warm_start=False)       # what a user gets
    dist = float(np.linalg.norm(np.asarray(default.positions) - X_ref, axis=1).max() / dg)
    row = {"mesh": name, "vertices": len(V), "edit": edit_name, "domain": domain,
           "lambda": lam, "reference_residual": ref_res, "reference_iterations": ref_its,
           "methods": runs,
           "default_iterations": int(default.iterations),
           "default_converged": bool(default.converged),
           "default_distance": dist, "default_estimate": float(default.distance_estimate),
           "default_ms": core_ms(default)}
    log(fmt_row(row, budget) + f"   (ref {ref_its} it, res {ref_res:.0e}, {ref_s:.0f} s)")
    return row


def fmt_its(its, budget):
    return f">{budget}" if its is None else str(its)


def fmt_row(r, budget):
    runs = " | ".join(f"{m} {fmt_its(v['iterations'], budget)} it {v['ms']:.0f} ms"
                      for m, v in r["methods"].items())
    return (f"{r['mesh']:6} {r['edit']:5} {r['domain']:6} {r['lambda']:4} | {runs} | default "
            f"{r['default_iterations']} it, converged {r['default_converged']}, "
            f"{r['default_distance']:.1e}")


def ratio(row, method, budget):
    """Iterations of `method` over the plain iteration's; a run that missed the budget counts
    at the budget (conservative), None when both missed it."""
    p = row["methods"]["none"]["iterations"]
    a = row["methods"][method]["iterations"]
    if not (p or a):
        return None
    return (a or budget) / (p or budget)


def summary(rows, budget):
    methods = list(rows[0]["methods"]) if rows else []
    medians = {}
    if "none" in methods:
        for m in methods:
            if m != "none":
                rs = [x for x in (ratio(r, m, budget) for r in rows) if x is not None]
                medians[m] = float(np.median(rs)) if rs else None
    conv = [r for r in rows if r["default_converged"]]
    return {"median_ratio_to_plain": medians, "cells": len(rows),
            "default_converged": len(conv),
            "default_converged_max_iterations": max((r["default_iterations"] for r in conv),
                                                    default=None),
            "default_converged_max_distance": max((r["default_distance"] for r in conv),
                                                  default=None)}


def koala(ed, log, methods, budget=1500, windows=()):
    """The 50k koala lift (edge, lambda 0.5): iterations and core ms to 1e-3 diag of the
    reference, with the true distance along the way; the default solve, timed."""
    from edgedeform.mesh_files import read_mesh
    V, F = read_mesh(mesh_path("koala.obj"))
    handles, static, targets = edit(V, "lift")
    dg = diagonal(V)
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(0.5)
    X_ref, res, its = cached_reference(d, "koala", "lift", "edge", 0.5, targets)
    out = {"mesh": "koala", "vertices": len(V), "reference_residual": res,
           "reference_iterations": its, "budget": budget, "methods": {}}
    for acc in methods:
        trace = []
        n, ms = iterations_to_goal(d, targets, X_ref, dg, acc, budget, 0.5, trace)
        out["methods"][acc] = {"iterations": n, "core_ms": ms, "trace": trace}
        log(f"koala {acc}: {n} iterations, {ms:.0f} ms; (iteration, residual, estimate, "
            f"distance): {trace}")
    for w in windows:       # other Anderson windows than the default
        trace = []
        n, ms = iterations_to_goal(d, targets, X_ref, dg, "anderson", budget, 0.5, trace, w)
        out["methods"][f"anderson_window_{w}"] = {"iterations": n, "core_ms": ms, "trace": trace}
        log(f"koala anderson window {w}: {n} iterations; {trace}")
    refactor(d, 0.5)
    t0, c0 = time.perf_counter(), time.process_time()
    r = d.solve(targets, warm_start=False)
    out["default"] = {"iterations": int(r.iterations), "converged": bool(r.converged),
                      "estimate": float(r.distance_estimate),
                      "wall_ms": (time.perf_counter() - t0) * 1e3,
                      "cpu_ms": (time.process_time() - c0) * 1e3, "core_ms": core_ms(r),
                      "factor_ms": float(r.factor_ms),
                      "distance": float(np.linalg.norm(np.asarray(r.positions) - X_ref,
                                                       axis=1).max() / dg)}
    log(f"koala default solve: {out['default']}")
    return out


def koala_markdown(result):
    k, machine = result["koala"], result["machine"]
    b, dflt = k["budget"], k["default"]
    lines = [
        "Lift, edge domain, λ = 0.5, 49,999 vertices (target: 1e-3·diag in ≤ 1.5 s including "
        f"the factorization). Reference: {k['reference_iterations']} iterations, residual "
        f"{k['reference_residual']:.1e}. Solver threads: {machine.get('threads', 'default')}.",
        "",
        "| method | iterations to 1e-3·diag | core ms | target |",
        "|---|---|---|---|",
    ]
    # (older results keep each method under its own key)
    methods = k.get("methods") or {m: k[m] for m in ("anderson", "none") if m in k}
    for m, v in methods.items():
        met = v["iterations"] is not None and v["core_ms"] <= 1500
        lines.append(f"| {m} | {fmt_its(v['iterations'], b)} | {v['core_ms']:.0f} | "
                     f"{'met' if met else 'not met'} |")
    lines += ["", f"Default solve: {dflt['iterations']} iterations, converged = "
              f"{dflt['converged']} (estimate {dflt['estimate']:.1e}), true distance "
              f"{dflt['distance']:.1e}·diag, {dflt['wall_ms'] / 1e3:.1f} s wall "
              f"({dflt['factor_ms']:.0f} ms factorization)."]
    return "\n".join(lines)


def plot(rows, path, budget):
    """Iterations of each accelerated method against the plain iteration's, when matplotlib
    is installed (bench/setup_peers.sh installs it); False when no plot was written."""
    try:
        import matplotlib
    except ImportError:
        print("no matplotlib: convergence plot not written", flush=True)
        return False
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    accelerated = [m for m in rows[0]["methods"] if m != "none"]
    if "none" not in rows[0]["methods"] or not accelerated:
        return False
    fig, axes = plt.subplots(1, len(accelerated), figsize=(6 * len(accelerated), 5), squeeze=False)
    marks = {"lift": "o", "twist": "s", "bend": "^"}
    colours = {0.0: "tab:blue", 0.5: "tab:green", 1.0: "tab:red"}
    for ax, method in zip(axes[0], accelerated):
        for r in rows:
            p = r["methods"]["none"]["iterations"] or budget
            a = r["methods"][method]["iterations"] or budget
            ax.scatter(p, a, marker=marks.get(r["edit"], "x"), c=colours.get(r["lambda"], "k"),
                       edgecolors="k" if r["domain"] == "edge" else "none", s=40)
        lim = [1, budget * 1.3]
        ax.plot(lim, lim, "k:", lw=1, label="equal")
        ax.plot(lim, [x / 3 for x in lim], "k--", lw=1, label="1/3")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("plain iterations to 1e-3 diag")
        ax.set_ylabel(f"{method} iterations to 1e-3 diag")
        for e, m in marks.items():
            ax.scatter([], [], marker=m, c="grey", label=e)
        for lam, c in colours.items():
            ax.scatter([], [], marker="o", c=c, label=f"λ={lam:g}")
        ax.legend(fontsize=8, loc="upper left")
        ax.set_title(f"{method} vs plain (budget {budget}; edge = black outline)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return True


def markdown(result, png_rel=None):
    b = result["budget"]
    s = result["summary"]
    methods = list(result["rows"][0]["methods"]) if result["rows"] else []
    accelerated = [m for m in methods if m != "none" and "none" in methods]
    lines = [
        "Iterations and core ms (factorization + local + rhs + solve) until every vertex is "
        "within 1e-3·diag of the fixed point (reference: see the script's docstring); "
        f"'>{b}' = not within the budget; 'none' is the plain local/global iteration. "
        "'default' = `solve(targets)` with the defaults of the build in the JSON: its "
        "iterations, whether it reports converged, and its true distance to the reference / diag.",
        "",
        "| mesh | edit | domain | λ | " + " | ".join(f"{m} it | {m} ms" for m in methods)
        + "".join(f" | {m}/plain" for m in accelerated)
        + " | default it | converged | distance |",
        "|---" * (4 + 2 * len(methods) + len(accelerated) + 3) + "|",
    ]
    for r in result["rows"]:
        runs = " | ".join(f"{fmt_its(r['methods'][m]['iterations'], b)} | {r['methods'][m]['ms']:.0f}"
                          for m in methods)
        ratios = "".join(" | " + ("–" if ratio(r, m, b) is None else f"{ratio(r, m, b):.2f}")
                         for m in accelerated)
        lines.append(
            f"| {r['mesh']} | {r['edit']} | {r['domain']} | {r['lambda']:g} | {runs}{ratios} | "
            f"{r['default_iterations']} | {'yes' if r['default_converged'] else '**no**'} | "
            f"{r['default_distance']:.1e} |")
    if png_rel:
        lines += ["", f"![iterations of each method against the plain iteration's]({png_rel})"]
    medians = ", ".join(f"{m} {v:.2f}" for m, v in s["median_ratio_to_plain"].items() if v is not None)
    lines += ["", f"Median iteration ratio to the plain iteration: {medians or 'none measured'} "
              f"(a run that missed the budget counts as {b}). Default cold solves reporting "
              f"converged: {s['default_converged']} of {s['cells']}, at most "
              f"{s['default_converged_max_iterations']} iterations, largest true distance "
              + (f"{s['default_converged_max_distance']:.1e}·diag."
                 if s["default_converged_max_distance"] is not None else "–.")]
    said_no = [r for r in result["rows"] if not r["default_converged"]]
    far = [r for r in result["rows"] if r["default_converged"] and r["default_distance"] > 2e-3]
    cell = lambda r: f"{r['mesh']} {r['edit']} {r['domain']} λ = {r['lambda']:g}"
    lines += [
        "",
        "- Default solves that end 'not converged' (with the warning, nothing claimed): "
        + (", ".join(cell(r) for r in said_no) or "none") + ".",
        "- Default solves that report converged but lie more than 2·tolerance (2e-3·diag) from "
        "the reference: " + (", ".join(f"{cell(r)} ({r['default_distance']:.1e})" for r in far) or "none")
        + " (why these can happen: docs/decisions/0008-convergence-estimate.md).",
    ]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--meshes", default=",".join(SAMPLES))
    ap.add_argument("--edits", default="lift,twist,bend")
    ap.add_argument("--methods", default="",
                    help="comma list of acceleration methods (default: every one the build accepts)")
    ap.add_argument("--lambdas", default=",".join(map(str, LAMBDAS)))
    ap.add_argument("--domains", default=",".join(DOMAINS))
    ap.add_argument("--budget", type=int, default=2000)
    ap.add_argument("--koala", action="store_true", help="also the 50k koala lift")
    ap.add_argument("--koala-only", action="store_true", help="only the 50k koala lift")
    ap.add_argument("--koala-windows", default="",
                    help="koala: also these Anderson windows, e.g. 10,20")
    ap.add_argument("--json", default=None, help="where to write the result (default: "
                    "bench/results/convergence.json, or convergence_koala.json with --koala-only)")
    args = ap.parse_args(argv)
    out = HERE / "results"
    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh
    methods = method_list(ed, args.methods)
    windows = [int(w) for w in args.koala_windows.split(",") if w]
    log = lambda s: print(s, flush=True)  # noqa: E731
    machine = dict(machine_info(), threads=os.environ.get("OMP_NUM_THREADS", "default"))
    if args.koala_only:
        k = koala(ed, log, methods, windows=windows)
        path = Path(args.json or out / "convergence_koala.json")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"machine": machine, "build_info": ed.build_info(),
                                    "koala": k}, indent=1))
        return
    result = {"machine": machine, "build_info": ed.build_info(), "budget": args.budget,
              "goal": GOAL, "command": " ".join(["bench/bench_convergence.py"] + (argv or sys.argv[1:])),
              "rows": []}
    path = Path(args.json or out / "convergence.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = out / "cache" / (path.stem + ".partial.json")   # what a long run has so far
    partial.parent.mkdir(parents=True, exist_ok=True)
    for name in args.meshes.split(","):
        V, F = read_mesh(mesh_path(SAMPLES[name]))
        for e in args.edits.split(","):
            for domain in args.domains.split(","):
                for lam in (float(x) for x in args.lambdas.split(",")):
                    result["rows"].append(run_cell(ed, V, F, name, e, domain, lam, args.budget,
                                                   methods, log))
                    partial.write_text(json.dumps(result, indent=1))
    # the machine as the run ends (its load is what the run shared), and when it started
    result["machine"] = dict(machine_info(), threads=machine["threads"], started=machine["date"])
    result["summary"] = summary(result["rows"], args.budget)
    print(json.dumps(result["summary"]))
    if args.koala:
        result["koala"] = koala(ed, log, methods, windows=windows)
    path.write_text(json.dumps(result, indent=1))
    partial.unlink()
    plot(result["rows"], path.with_suffix(".png"), result["budget"])


if __name__ == "__main__":
    main()
