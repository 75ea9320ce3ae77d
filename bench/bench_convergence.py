#!/usr/bin/env python3
"""Convergence benchmark: iterations and core milliseconds to come within 1e-3 of the
bounding-box diagonal of the fixed point, plain local/global vs Anderson-accelerated.

Meshes: the samples in blend_samples/meshes. Edits (heights along z unless flat in z):
  lift   lowest 20% static, top 10% raised by 0.25 diag
  twist  lowest 20% (longest axis) static, top 10% turned 60 degrees about that axis
  bend   same groups, the top turned 30 degrees about the next axis
Reference: the fixed point, from the accelerated iteration run to a residual of 1e-10 diag
(tolerance 1e-9, at most 3000 iterations), then continued plainly (at most 1000 more)
until its residual is below 1e-10 diag; the JSON records the residual reached (both methods have the same fixed points; the tests check
that against the plain method alone). Each run takes one iteration per call
(warm solves with unchanged targets continue the same iteration) and stops as soon as every
vertex is within 1e-3 diag of the reference; ms = factorization + local + rhs + solve time
reported by the core (Python overhead excluded).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_convergence.py
        [--meshes dino,plane] [--budget 2000] [--koala | --koala-only] [--markdown docs/benchmarks.md]

Prints a table, writes bench/results/convergence.json and bench/results/convergence.png.
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

from machine import machine_info  # noqa: E402
from md_section import replace_section  # noqa: E402

SAMPLES = {"dino": "cgal_dino.off", "head": "cgal_mannequin-devil.off",
           "plane": "cgal_plane.off", "spot": "spot_low_resolution.obj"}
KOALA = ROOT.parent / "shared" / "meshes" / "koala.obj"
LAMBDAS = (0.0, 0.5, 1.0)
DOMAINS = ("edge", "primal")
GOAL = 1e-3
CHECKPOINTS = {1, 10, 25, 50, 100, 200, 400, 600, 800, 1000, 1200, 1500, 2000}


def diag(V):
    return float(np.linalg.norm(np.ptp(V, axis=0)))


def rotation(axis, degrees):
    a = np.zeros(3)
    a[axis] = 1.0
    t = np.radians(degrees)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * (K @ K)


def edit(V, name):
    ext = np.ptp(V, axis=0)
    if name == "lift":
        ax = 2 if ext[2] > 0.01 * np.linalg.norm(ext) else int(np.argmax(ext))
    else:
        ax = int(np.argmax(ext))
    h = V[:, ax]
    static = np.flatnonzero(h <= np.quantile(h, 0.2))
    handles = np.flatnonzero(h >= np.quantile(h, 0.9))
    if name == "lift":
        targets = V[handles].copy()
        targets[:, ax] += 0.25 * diag(V)
    else:
        about, deg = (ax, 60.0) if name == "twist" else ((ax + 1) % 3, 30.0)
        c = V[handles].mean(axis=0)
        targets = (V[handles] - c) @ rotation(about, deg).T + c
    return handles, static, targets


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


def run_cell(ed, V, F, name, edit_name, domain, lam, budget, log):
    handles, static, targets = edit(V, edit_name)
    dg = diag(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(lam)
    t0 = time.perf_counter()
    X_ref, ref_res, ref_its = reference(d, targets)
    ref_s = time.perf_counter() - t0
    plain = iterations_to_goal(d, targets, X_ref, dg, "none", budget, lam)
    fast = iterations_to_goal(d, targets, X_ref, dg, "anderson", budget, lam)
    refactor(d, lam)
    default = d.solve(targets, warm_start=False)       # what a user gets
    dist = float(np.linalg.norm(np.asarray(default.positions) - X_ref, axis=1).max() / dg)
    row = {"mesh": name, "vertices": len(V), "edit": edit_name, "domain": domain,
           "lambda": lam, "reference_residual": ref_res, "reference_iterations": ref_its,
           "plain_iterations": plain[0], "plain_ms": plain[1],
           "anderson_iterations": fast[0], "anderson_ms": fast[1],
           "ratio": (fast[0] / plain[0]) if plain[0] and fast[0] else None,
           "default_iterations": int(default.iterations),
           "default_converged": bool(default.converged),
           "default_distance": dist, "default_estimate": float(default.distance_estimate),
           "default_ms": core_ms(default)}
    log(fmt_row(row) + f"   (ref {ref_its} it, res {ref_res:.0e}, {ref_s:.0f} s)")
    return row


def fmt_its(its, budget):
    return f">{budget}" if its is None else str(its)


def fmt_row(r, budget=None):
    b = budget or 2000
    ratio = "-" if r["ratio"] is None else f"{r['ratio']:.2f}"
    return (f"{r['mesh']:6} {r['edit']:5} {r['domain']:6} {r['lambda']:4} | "
            f"{fmt_its(r['plain_iterations'], b):>6} {r['plain_ms']:9.0f} | "
            f"{fmt_its(r['anderson_iterations'], b):>6} {r['anderson_ms']:9.0f} | {ratio:>5} | "
            f"{r['default_iterations']:5} {'yes' if r['default_converged'] else 'NO':3} "
            f"{r['default_distance']:.1e}")


HEADER = ("mesh   edit  domain lam  |  plain it   ms     |  AA it     ms     | ratio | "
          "default it conv dist/diag")


def summary(rows, budget):
    ratios = []
    for r in rows:   # a run that missed the budget counts at the budget (conservative)
        p = r["plain_iterations"] or budget
        a = r["anderson_iterations"] or budget
        if r["plain_iterations"] or r["anderson_iterations"]:
            ratios.append(a / p)
    conv = [r for r in rows if r["default_converged"]]
    return {"median_ratio": float(np.median(ratios)) if ratios else None,
            "cells": len(rows), "cells_with_ratio": len(ratios),
            "default_converged": len(conv),
            "default_converged_max_iterations": max((r["default_iterations"] for r in conv),
                                                    default=None),
            "default_converged_max_distance": max((r["default_distance"] for r in conv),
                                                  default=None)}


def koala(ed, log, budget=1500, windows=()):
    """The 50k koala lift (edge, lambda 0.5): iterations and core ms to 1e-3 diag of the
    reference, with the true distance along the way; the default solve, timed."""
    from edgedeform.mesh_files import read_mesh
    V, F = read_mesh(KOALA)
    handles, static, targets = edit(V, "lift")
    dg = diag(V)
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(0.5)
    X_ref, res, its = cached_reference(d, "koala", "lift", "edge", 0.5, targets)
    out = {"mesh": "koala", "vertices": len(V), "reference_residual": res,
           "reference_iterations": its, "budget": budget}
    for acc in ("anderson", "none"):
        trace = []
        n, ms = iterations_to_goal(d, targets, X_ref, dg, acc, budget, 0.5, trace)
        out[acc] = {"iterations": n, "core_ms": ms, "trace": trace}
        log(f"koala {acc}: {n} iterations, {ms:.0f} ms; (iteration, residual, estimate, "
            f"distance): {trace}")
    for w in windows:       # other Anderson windows than the default
        trace = []
        n, ms = iterations_to_goal(d, targets, X_ref, dg, "anderson", budget, 0.5, trace, w)
        out[f"anderson_window_{w}"] = {"iterations": n, "core_ms": ms, "trace": trace}
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


def koala_markdown(k, machine):
    a, p, dflt = k["anderson"], k["none"], k["default"]
    b = k["budget"]
    rows = ["| iteration | residual | estimate | true distance |", "|---|---|---|---|"]
    rows += [f"| {i} | {r:.1e} | {e:.1e} | {t:.1e} |" for i, r, e, t in a["trace"]]
    return "\n".join([
        "### Koala, 50k vertices (target: 1e-3·diag in ≤ 1.5 s) (bench_convergence.py --koala)",
        "",
        f"Machine: {machine['cpu']}, {machine['cores']} cores shared with other jobs (load "
        f"{machine['load_1min']:.1f}), {machine['date']}, solver threads "
        f"{machine.get('threads', 'default')}. Lift, edge domain, λ = 0.5. "
        f"Reference: {k['reference_iterations']} iterations, residual {k['reference_residual']:.1e}.",
        "",
        f"- Anderson to 1e-3·diag of the reference: {fmt_its(a['iterations'], b)} iterations, "
        f"{a['core_ms']:.0f} core ms including the factorization; plain: "
        f"{fmt_its(p['iterations'], b)} iterations, {p['core_ms']:.0f} ms.",
        f"- Default solve: {dflt['iterations']} iterations, converged = {dflt['converged']} "
        f"(estimate {dflt['estimate']:.1e}), true distance {dflt['distance']:.1e}·diag, "
        f"{dflt['wall_ms'] / 1e3:.1f} s wall ({dflt['factor_ms']:.0f} ms factorization).",
        f"- Target 1e-3·diag in ≤ 1.5 s including the factorization: "
        f"{'met' if a['iterations'] and a['core_ms'] <= 1500 else '**not met**'}.",
        *[f"- Anderson, window {key.rsplit('_', 1)[1]}: {fmt_its(v['iterations'], b)} "
          f"iterations to 1e-3·diag; true distance " + ", ".join(
              f"{t:.1e} at {i}" for i, _, _, t in v["trace"] if i in (100, 400, 800, b))
          for key, v in k.items() if key.startswith("anderson_window_")],
        "",
        "The accelerated iteration (default, window 5) along the way:",
        "",
        *rows,
    ])


def plot(rows, path, budget):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 5))
    marks = {"lift": "o", "twist": "s", "bend": "^"}
    colours = {0.0: "tab:blue", 0.5: "tab:green", 1.0: "tab:red"}
    for r in rows:
        p = r["plain_iterations"] or budget
        a = r["anderson_iterations"] or budget
        ax.scatter(p, a, marker=marks[r["edit"]], c=colours[r["lambda"]],
                   edgecolors="k" if r["domain"] == "edge" else "none", s=40)
    lim = [1, budget * 1.3]
    ax.plot(lim, lim, "k:", lw=1, label="equal")
    ax.plot(lim, [x / 3 for x in lim], "k--", lw=1, label="1/3")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("plain iterations to 1e-3 diag")
    ax.set_ylabel("Anderson iterations to 1e-3 diag")
    for e, m in marks.items():
        ax.scatter([], [], marker=m, c="grey", label=e)
    for lam, c in colours.items():
        ax.scatter([], [], marker="o", c=c, label=f"λ={lam:g}")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"Iterations to 1e-3·diag (budget {budget}; edge = black outline)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def markdown(result, png_rel):
    b = result["budget"]
    s = result["summary"]
    m = result["machine"]
    lines = [
        "## Convergence: plain vs Anderson-accelerated (bench/bench_convergence.py)",
        "",
        f"Machine: {m['cpu']}, {m['cores']} cores shared with other jobs (load {m['load_1min']:.1f} "
        f"during the run), {m['date']}. Timings are noisy; iteration counts are exact.",
        "",
        "Iterations and core ms (factorization + local + rhs + solve) until every vertex is "
        "within 1e-3·diag of the fixed point (reference: see the script's docstring); "
        f"'>{b}' = not within the budget. 'default' = `solve(targets)` with the defaults "
        "(Anderson, tolerance 1e-3, max 2000 iterations): its iterations, whether it reports "
        "converged, and its true distance to the reference / diag.",
        "",
        "| mesh | edit | domain | λ | plain it | plain ms | AA it | AA ms | AA/plain | default it | converged | distance |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result["rows"]:
        ratio = "–" if r["ratio"] is None else f"{r['ratio']:.2f}"
        lines.append(
            f"| {r['mesh']} | {r['edit']} | {r['domain']} | {r['lambda']:g} | "
            f"{fmt_its(r['plain_iterations'], b)} | {r['plain_ms']:.0f} | "
            f"{fmt_its(r['anderson_iterations'], b)} | {r['anderson_ms']:.0f} | {ratio} | "
            f"{r['default_iterations']} | {'yes' if r['default_converged'] else '**no**'} | "
            f"{r['default_distance']:.1e} |")
    lines += ["", f"![iterations, plain vs Anderson]({png_rel})", "",
              f"Median Anderson/plain iteration ratio: {s['median_ratio']:.2f} over "
              f"{s['cells_with_ratio']} cells (a run that missed the budget counts as {b}). "
              f"Default cold solves reporting converged: {s['default_converged']} of {s['cells']}, "
              f"at most {s['default_converged_max_iterations']} iterations, largest true "
              f"distance {s['default_converged_max_distance']:.1e}·diag."]
    # Which cells to read closely, from this run's rows (not written by hand).
    said_no = [r for r in result["rows"] if not r["default_converged"]]
    far = [r for r in result["rows"] if r["default_converged"] and r["default_distance"] > 2e-3]
    cell = lambda r: f"{r['mesh']} {r['edit']} {r['domain']} λ = {r['lambda']:g}"
    lines += [
        "",
        "Reading the table (lists from this run's rows):",
        "- Default solves that end 'not converged' (with the warning, nothing claimed): "
        + (", ".join(cell(r) for r in said_no) or "none") + ".",
        "- Default solves that report converged but lie more than 2·tolerance (2e-3·diag) from "
        "the reference: " + (", ".join(f"{cell(r)} ({r['default_distance']:.1e})" for r in far) or "none")
        + ". Where that is the flat plane's in-plane bend (edge domain): the flat shape is an "
        "exact, unstable fixed point of the symmetric problem, where both methods sit with a "
        "round-off residual, and the long reference run leaves it out of plane only after "
        "hundreds of iterations of round-off growth; the estimate speaks about the fixed point "
        "the iteration is at and cannot know of another one. Elsewhere it is the estimate's "
        "known weakness with modes contracting by ~0.9995 per step (docs/deviations.md, "
        "item 8).",
    ]
    k = result.get("koala")
    if k:
        lines += ["", f"Koala ({k['vertices']} vertices) lift, edge, λ = 0.5: Anderson reaches "
                  f"1e-3·diag in {k['anderson']['iterations']} iterations, "
                  f"{k['anderson']['core_ms']:.0f} ms including factorization "
                  f"(plain: {k['none']['iterations']} iterations, {k['none']['core_ms']:.0f} ms); "
                  f"the default solve takes {k['default']['iterations']} iterations, "
                  f"{k['default']['wall_ms']:.0f} ms wall, converged = {k['default']['converged']}, "
                  f"true distance {k['default']['distance']:.1e}·diag."]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--meshes", default=",".join(SAMPLES))
    ap.add_argument("--edits", default="lift,twist,bend")
    ap.add_argument("--budget", type=int, default=2000)
    ap.add_argument("--koala", action="store_true", help="also the 50k koala lift")
    ap.add_argument("--koala-only", action="store_true", help="only the 50k koala lift")
    ap.add_argument("--koala-windows", default="",
                    help="koala: also these Anderson windows, e.g. 10,20")
    ap.add_argument("--markdown", default=None)
    ap.add_argument("--from-json", default=None)
    args = ap.parse_args(argv)
    out = HERE / "results"
    if args.from_json:
        result = json.loads(Path(args.from_json).read_text())
        write_outputs(result, out, args.markdown)
        return
    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh

    if args.koala_only:
        k = koala(ed, lambda s: print(s, flush=True),
                  windows=[int(w) for w in args.koala_windows.split(",") if w])
        out.mkdir(exist_ok=True)
        machine = dict(machine_info(), threads=os.environ.get("OMP_NUM_THREADS", "default"))
        (out / "convergence_koala.json").write_text(
            json.dumps({"machine": machine, "koala": k}, indent=1))
        if args.markdown:
            replace_section(args.markdown, "convergence-koala", koala_markdown(k, machine))
        return
    result = {"machine": machine_info(), "budget": args.budget, "goal": GOAL, "rows": []}
    print(HEADER, flush=True)
    for name in args.meshes.split(","):
        V, F = read_mesh(ROOT / "blend_samples" / "meshes" / SAMPLES[name])
        for e in args.edits.split(","):
            for domain in DOMAINS:
                for lam in LAMBDAS:
                    result["rows"].append(run_cell(ed, V, F, name, e, domain, lam, args.budget,
                                                   lambda s: print(s, flush=True)))
    result["summary"] = summary(result["rows"], args.budget)
    print(json.dumps(result["summary"]))
    if args.koala:
        result["koala"] = koala(ed, lambda s: print(s, flush=True),
                                windows=[int(w) for w in args.koala_windows.split(",") if w])
    out.mkdir(exist_ok=True)
    (out / "convergence.json").write_text(json.dumps(result, indent=1))
    write_outputs(result, out, args.markdown)


def write_outputs(result, out, markdown_path):
    plot(result["rows"], out / "convergence.png", result["budget"])
    if markdown_path:
        img = ROOT / "docs" / "img" / "convergence.png"
        img.write_bytes((out / "convergence.png").read_bytes())
        replace_section(markdown_path, "convergence", markdown(result, "img/convergence.png"))
        if result.get("koala"):
            replace_section(markdown_path, "convergence-koala",
                            koala_markdown(result["koala"], result["machine"]))


if __name__ == "__main__":
    main()
