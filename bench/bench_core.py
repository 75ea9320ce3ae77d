#!/usr/bin/env python3
"""Core solver benchmark: precompute and per-iteration cost, iterations to converge.

For meshes of about 1k, 10k, 50k and 140k vertices, both domains, lambda in {0, 0.5, 1},
on a "lift" edit: the lowest 20% of the height static, the top 10% raised by a quarter of
the bounding-box diagonal. Height is the z coordinate, unless the mesh is flat in z
(extent below 1% of the diagonal), then the axis of largest extent. (None of the meshes
below is flat in z, so all of them are lifted along z.)

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_core.py [--sizes 1k,10k]
        [--max-iterations 300] [--busy] [--roi] [--json PATH]

Besides precompute and iterations, every row measures the incremental paths: a change of λ
(numeric refactorization) and a handle group added and removed, each against a fresh
Deformer, with the largest position difference between the two. --busy runs a busy loop
in a second process for the whole run (one core kept busy); --roi measures a region of
interest on the 140k mesh against a whole mesh of the same vertex count instead.

Prints a table and merges its rows into bench/results/core.json (rows of other sizes are
kept, so sizes can be run one at a time); bench/report.py puts the table into
docs/benchmarks.md.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from edits import lift_edit, mesh_path, up_axis  # noqa: E402
from machine import machine_info  # noqa: E402

MESHES = None  # --meshes: a folder holding them all; by default edits.mesh_path() finds them
SIZES = {
    "1k": "spot_low_resolution.obj",
    "10k": "blub_fish.obj",
    "50k": "koala.obj",
    "140k": "nefertiti_loop1.ply",
}
ROI_REFERENCE = "cgal_dino.off"  # 3,916 vertices: the whole mesh the region is compared with
LAMBDAS = (0.0, 0.5, 1.0)
DOMAINS = ("edge", "primal")


def belt_group(V, ax):
    """A new handle group: the 2 % band of vertices around 55 % of the height, pinned
    where they are (a user pinning a waist)."""
    h = V[:, ax]
    lo, hi = np.quantile(h, [0.54, 0.56])
    return np.flatnonzero((h >= lo) & (h <= hi))


def timed_constraints(d, handles, static, roi=None):
    """Wall ms of set_constraints plus the next solve's assembly and factorization."""
    t0 = time.perf_counter()
    d.set_constraints(handles=handles, static=static, roi=roi)
    set_ms = (time.perf_counter() - t0) * 1e3
    return set_ms


def relative_difference(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


def run_changes(ed, V, F, edit, domain, lam, repeat):
    """λ change and handle-group change, each against a fresh Deformer given the final
    state directly. The fast path must reproduce the fresh positions (same 5 iterations,
    cold start) to 1e-9 relative."""
    handles, static, targets, ax = edit
    belt = belt_group(V, ax)
    belt = belt[~np.isin(belt, handles) & ~np.isin(belt, static)]
    more = np.concatenate([handles, belt])
    more_targets = np.vstack([targets, V[belt]])
    lam2 = 0.25 if lam != 0.25 else 0.75
    out = {"belt_vertices": int(len(belt))}
    stiff, stiff_again, add, remove, fresh_add, fresh_remove, fresh_pre = [], [], [], [], [], [], []
    diff_stiff = diff_add = diff_remove = 0.0
    for _ in range(repeat):
        d = ed.Deformer(V, F, domain=domain)
        d.set_constraints(handles=handles, static=static)
        d.set_stiffness(lam)
        d.solve(targets, max_iterations=1)
        # λ change: the live slider
        d.set_stiffness(lam2)
        r = d.solve(targets, max_iterations=5, tolerance=0.0, warm_start=False)
        stiff.append(float(r.factor_ms))
        t0 = time.perf_counter()
        f = ed.Deformer(V, F, domain=domain)
        f.set_constraints(handles=handles, static=static)
        f.set_stiffness(lam2)
        construct_ms = (time.perf_counter() - t0) * 1e3
        rf = f.solve(targets, max_iterations=5, tolerance=0.0, warm_start=False)
        fresh_pre.append(construct_ms + float(rf.factor_ms))
        diff_stiff = max(diff_stiff, relative_difference(r.positions, rf.positions))
        # The slider back and forth again: from λ = 1 the first change had to order the
        # Laplacian's pattern; the second finds that order kept.
        d.set_stiffness(lam)
        d.solve(targets, max_iterations=1)
        d.set_stiffness(lam2)
        r = d.solve(targets, max_iterations=5, tolerance=0.0, warm_start=False)
        stiff_again.append(float(r.factor_ms))
        diff_stiff = max(diff_stiff, relative_difference(r.positions, rf.positions))
        # a handle group added, then removed again
        for group, tg, times, fresh_times, key in ((more, more_targets, add, fresh_add, "add"),
                                                   (handles, targets, remove, fresh_remove, "remove")):
            set_ms = timed_constraints(d, group, static)
            r = d.solve(tg, max_iterations=5, tolerance=0.0, warm_start=False)
            times.append(set_ms + float(r.factor_ms))
            f = ed.Deformer(V, F, domain=domain)
            f.set_stiffness(lam2)
            set_ms = timed_constraints(f, group, static)
            rf = f.solve(tg, max_iterations=5, tolerance=0.0, warm_start=False)
            fresh_times.append(set_ms + float(rf.factor_ms))
            diff = relative_difference(r.positions, rf.positions)
            if key == "add":
                diff_add = max(diff_add, diff)
            else:
                diff_remove = max(diff_remove, diff)
    out.update({"stiffness_change_ms": min(stiff), "stiffness_change_again_ms": min(stiff_again),
                "new_lambda": lam2,
                "fresh_precompute_new_lambda_ms": min(fresh_pre), "handle_add_ms": min(add),
                "handle_remove_ms": min(remove), "fresh_factor_add_ms": min(fresh_add),
                "fresh_factor_remove_ms": min(fresh_remove),
                "stiffness_change_diff": diff_stiff, "handle_add_diff": diff_add,
                "handle_remove_diff": diff_remove})
    return out


def run_one(ed, V, F, edit, domain, lam, max_iterations, tolerance, repeat, changes=True):
    """One (mesh, domain, lambda) cell. The machine is shared, so every timing is the
    minimum over `repeat` runs; the iteration count comes from one full lift solve."""
    handles, static, targets, _ = edit
    construct, factor, pre_cpu = [], [], []
    for _ in range(repeat):
        c0 = time.process_time()
        t0 = time.perf_counter()
        d = ed.Deformer(V, F, domain=domain)
        d.set_constraints(handles=handles, static=static, roi=None)
        d.set_stiffness(lam)
        construct.append((time.perf_counter() - t0) * 1e3)
        r = d.solve(targets, max_iterations=1, tolerance=tolerance)
        factor.append(float(r.factor_ms))
        # CPU time of all threads (includes the one iteration): insensitive to other load
        pre_cpu.append((time.process_time() - c0) * 1e3)
    t0 = time.perf_counter()
    r = d.solve(targets, max_iterations=max_iterations, tolerance=tolerance, warm_start=False)
    wall_ms = (time.perf_counter() - t0) * 1e3
    its = int(r.iterations)
    row = {
        "domain": domain, "lambda": lam, "nodes": int(d.n_nodes),
        "free_vertices": int(r.free_vertices), "active_nodes": int(r.active_nodes),
        "construct_ms": min(construct), "factor_ms": min(factor),
        "precompute_ms": min(construct) + min(factor),
        "precompute_cpu_ms": min(pre_cpu),
        "iterations": its, "converged": bool(r.converged),
        "lift_wall_ms": wall_ms,
        "final_energy": float(r.energies[-1]),
        "finite": bool(np.all(np.isfinite(r.positions))),
    }
    # Per-iteration split: fixed 10-iteration warm-started runs, best of `repeat`.
    k = 10
    best, cpu, totals = None, [], []
    for _ in range(repeat):
        c0 = time.process_time()
        rk = d.solve(targets, max_iterations=k, tolerance=0.0, warm_start=True)
        cpu.append((time.process_time() - c0) * 1e3 / rk.iterations)
        parts = (float(rk.local_ms) / rk.iterations, float(rk.rhs_ms) / rk.iterations,
                 float(rk.solve_ms) / rk.iterations)
        totals.append(sum(parts))
        if best is None or sum(parts) < sum(best):
            best = parts
    row["local_ms_per_it"], row["rhs_ms_per_it"], row["solve_ms_per_it"] = best
    row["ms_per_it"] = sum(best)
    row["ms_per_it_median"] = float(np.median(totals))
    row["cpu_ms_per_it"] = min(cpu)   # CPU time of all threads per iteration
    row["repeat"] = repeat
    row["load_1min"] = os.getloadavg()[0]
    # Numeric refactorization when only lambda changes (symbolic analysis kept).
    d.set_stiffness(0.25 if lam != 0.25 else 0.75)
    r2 = d.solve(targets, max_iterations=1, tolerance=tolerance)
    row["refactor_ms"] = float(r2.factor_ms)
    if changes:
        row.update(run_changes(ed, V, F, edit, domain, lam, repeat))
    row["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return row


def grow_region(F, seed, count):
    """`count` vertices around `seed`, by breadth-first growth over the mesh edges."""
    n = int(F.max()) + 1
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E = np.vstack([E, E[:, ::-1]])
    order = np.argsort(E[:, 0], kind="stable")
    E = E[order]
    starts = np.searchsorted(E[:, 0], np.arange(n + 1))
    seen = np.zeros(n, bool)
    seen[seed] = True
    region, frontier = [seed], [seed]
    while frontier and len(region) < count:
        nxt = []
        for v in frontier:
            for u in E[starts[v]:starts[v + 1], 1]:
                if not seen[u]:
                    seen[u] = True
                    nxt.append(int(u))
        region.extend(nxt)
        frontier = nxt
    return np.array(region[:count])


def roi_edit(V, region, ax):
    """Inside the region: its top 10 % by height are handles, raised by a quarter of the
    region's diagonal; the rest of the mesh is held by the region boundary."""
    h = V[region, ax]
    handles = region[h >= np.quantile(h, 0.9)]
    targets = V[handles].copy()
    targets[:, ax] += 0.25 * float(np.linalg.norm(np.ptp(V[region], axis=0)))
    return handles, targets


PEAK_SCRIPT = """
import resource, sys
sys.path.insert(0, {here!r})
import edgedeform as ed
from edgedeform.mesh_files import read_mesh
from bench_core import lift_edit
V, F = read_mesh({path!r})
handles, static, targets, _ = lift_edit(V)
d = ed.Deformer(V, F, domain={domain!r})
d.set_constraints(handles=handles, static=static)
d.set_stiffness({lam!r})
r = d.solve(targets, max_iterations=10, tolerance=0.0, acceleration={method!r})
print(r.method, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""


ITERATION_SCRIPT = """
import sys, numpy as np
sys.path.insert(0, {here!r})
import edgedeform as ed
from edgedeform.mesh_files import read_mesh
from bench_core import lift_edit
V, F = read_mesh({path!r})
handles, static, targets, _ = lift_edit(V)
d = ed.Deformer(V, F, domain="edge")
d.set_constraints(handles=handles, static=static)
d.set_stiffness(0.5)
d.solve(targets, max_iterations=1)
per_it = []
for _ in range(5):
    r = d.solve(targets, max_iterations=10, tolerance=0.0)
    per_it.append((r.local_ms + r.rhs_ms + r.solve_ms) / r.iterations)
print(np.median(per_it))
"""


def busy_ab(sizes, rounds):
    """With one core kept busy: 1 and 2 threads in alternating fresh processes, `rounds`
    each, so that both see the same stretch of the machine's other load. Median ms per
    iteration (edge, λ = 0.5, median of 5 runs of 10 iterations in each process)."""
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    rows = []
    try:
        for size in sizes:
            code = ITERATION_SCRIPT.format(here=str(HERE), path=str(mesh_path(SIZES[size], MESHES)))
            times = {1: [], 2: []}
            for _ in range(rounds):
                for threads in (1, 2):
                    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
                    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                         text=True, check=True)
                    times[threads].append(float(out.stdout.split()[-1]))
            rows.append({"size": size, "mesh": SIZES[size], "rounds": rounds,
                         "ms_per_it_1": float(np.median(times[1])),
                         "ms_per_it_2": float(np.median(times[2])),
                         "all_1": times[1], "all_2": times[2], "load_1min": os.getloadavg()[0]})
            print(rows[-1], flush=True)
    finally:
        busy.kill()
    return rows


def peak_memory(size, domain, lam, method="anderson"):
    """Peak resident set (MB) of a fresh process that reads the mesh, builds one Deformer,
    factors and runs 10 iterations of `method`: the memory one live session needs.
    The row (result["peak_memory"]): size, domain, lambda, method (asked), ran (the method
    that ran: "auto" and "lbfgs" run Anderson below λ 1), peak_mb."""
    code = PEAK_SCRIPT.format(here=str(HERE), path=str(mesh_path(SIZES[size], MESHES)), domain=domain, lam=lam,
                              method=method)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    ran, peak = out.stdout.split()[-2:]
    return {"size": size, "domain": domain, "lambda": lam, "method": method, "ran": ran, "peak_mb": float(peak)}


def run_roi(ed, repeat, domain="edge", lam=0.5):
    """A region of interest of a whole small mesh's vertex count on the 140k mesh, against
    that whole small mesh (lowest 20 % static as in the lift): precompute without the
    Deformer construction (done once per mesh), and per iteration."""
    from edgedeform.mesh_files import read_mesh
    rows = []
    Vs, Fs = read_mesh(str(mesh_path(ROI_REFERENCE, MESHES)))
    Vb, Fb = read_mesh(str(mesh_path(SIZES['140k'], MESHES)))
    ax = up_axis(Vb)
    seed = int(np.argmax(Vb[:, ax]))
    region = grow_region(Fb, seed, len(Vs))
    hs, ss, ts, _ = lift_edit(Vs)
    hb, tb = roi_edit(Vb, region, ax)
    for name, V, F, handles, static, targets, roi in (
            (ROI_REFERENCE, Vs, Fs, hs, ss, ts, None),
            (SIZES["140k"] + " ROI", Vb, Fb, hb, np.array([], int), tb, region)):
        t0 = time.perf_counter()
        d = ed.Deformer(V, F, domain=domain)
        construct_ms = (time.perf_counter() - t0) * 1e3
        d.set_stiffness(lam)
        pre, its = [], []
        for _ in range(repeat):
            set_ms = timed_constraints(d, handles, static, roi)
            r = d.solve(targets, max_iterations=1)
            pre.append(set_ms + float(r.factor_ms))
            r = d.solve(targets, max_iterations=10, tolerance=0.0)
            its.append((float(r.local_ms) + float(r.rhs_ms) + float(r.solve_ms)) / r.iterations)
        rows.append({"mesh": name, "vertices": len(V), "region": len(region) if roi is not None else len(V),
                     "free_vertices": int(r.free_vertices), "active_nodes": int(r.active_nodes),
                     "construct_ms": construct_ms, "precompute_ms": min(pre),
                     "ms_per_it": min(its), "domain": domain, "lambda": lam})
        print(rows[-1], flush=True)
    return rows


def changes(r):
    """The λ-change and handle-change cells (rows from older runs lack them)."""
    if "stiffness_change_ms" not in r:
        return f"{r['refactor_ms']:.0f} | –"
    pct = lambda a, b: f"{100 * a / b:.0f} %"
    new = (f" / {pct(r['stiffness_change_ms'], r['fresh_precompute_new_lambda_ms'])}"
           if "fresh_precompute_new_lambda_ms" in r else "")
    return (f"{r['stiffness_change_ms']:.0f} ({pct(r['stiffness_change_ms'], r['precompute_ms'])}{new}) "
            f"| {r['handle_add_ms']:.0f} / {r['handle_remove_ms']:.0f} "
            f"({pct(r['handle_add_ms'], r['fresh_factor_add_ms'])} / "
            f"{pct(r['handle_remove_ms'], r['fresh_factor_remove_ms'])})")


def table(rows):
    head = ("| size | mesh | vertices | domain | λ | threads | busy | nodes | precompute ms (CPU) "
            "| λ change ms (% pre / % pre at new λ) | handle add / remove ms (% fresh) "
            "| local ms/it | rhs ms/it | solve ms/it | ms/it | CPU ms/it | iterations | peak MB | load |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        its = f"{r['iterations']}" + ("" if r["converged"] else " (not conv.)")
        lines.append(
            f"| {r['size']} | {r['mesh']} | {r['vertices']:,} | {r['domain']} | {r['lambda']:g} "
            f"| {r.get('threads', '?')} | {'yes' if r.get('busy') else 'no'} "
            f"| {r['nodes']:,} | {r['precompute_ms']:.0f} ({r['precompute_cpu_ms']:.0f}) "
            f"| {changes(r)} "
            f"| {r['local_ms_per_it']:.2f} | {r['rhs_ms_per_it']:.2f} "
            f"| {r['solve_ms_per_it']:.2f} | {r['ms_per_it']:.2f} | {r['cpu_ms_per_it']:.2f} "
            f"| {its} | {r.get('peak_rss_mb', float('nan')):.0f} | {r['load_1min']:.1f} |")
    return "\n".join(lines)


def targets(rows, peaks=()):
    """The speed targets (record 0013), each with what this run measured."""
    out = []
    anderson = {(q["size"], q["domain"], q["lambda"]): q["peak_mb"] for q in peaks
                if q.get("method", "anderson") == "anderson"}
    for q in peaks:
        method = q.get("method", "anderson")
        line = (f"- Peak memory of one Deformer, {q['size']} {q['domain']} λ = {q['lambda']:g}, {method} "
                f"(fresh process: mesh read, construction, factorization, 10 iterations): "
                f"{q['peak_mb']:.0f} MB")
        if q["size"] == "140k" and method == "anderson":
            line += f" (≤ 1536: {'met' if q['peak_mb'] <= 1536 else '**missed**'})"
        base = anderson.get((q["size"], q["domain"], q["lambda"]))
        if method != "anderson" and base:
            line += f" ({q.get('ran', method)}: {q['peak_mb'] / base:.2f}× Anderson's)"
        out.append(line + ".")
    for t in rows:
        if not (t["size"] == "140k" and t["domain"] == "edge" and t["lambda"] == 0.5):
            continue
        met = lambda ok: "met" if ok else "**missed**"
        out.append(
            f"- 140k edge λ = 0.5, threads {t.get('threads')}, busy core {'yes' if t.get('busy') else 'no'}: "
            f"{t['ms_per_it']:.1f} ms per iteration (≤ 70: {met(t['ms_per_it'] <= 70)}), "
            f"precompute {t['precompute_ms'] / 1e3:.2f} s wall, {t['precompute_cpu_ms'] / 1e3:.2f} s CPU "
            f"(≤ 2.5: wall {met(t['precompute_ms'] <= 2500)}, CPU {met(t['precompute_cpu_ms'] <= 2500)}), "
            f"{t['cpu_ms_per_it']:.1f} ms CPU per iteration over both threads; load {t['load_1min']:.1f}.")
    for t in rows:
        if "stiffness_change_ms" not in t or t.get("busy"):
            continue
        lam = t["stiffness_change_ms"] / t["precompute_ms"]
        # The change replaces building a Deformer at the new λ; across λ = 1 the two
        # precomputes differ (λ = 1 alone has no Laplacian pattern), so both are quoted.
        lam_new = t["stiffness_change_ms"] / t.get("fresh_precompute_new_lambda_ms", t["precompute_ms"])
        add = t["handle_add_ms"] / t["fresh_factor_add_ms"]
        rem = t["handle_remove_ms"] / t["fresh_factor_remove_ms"]
        worst = max(t["stiffness_change_diff"], t["handle_add_diff"], t["handle_remove_diff"])
        out.append(
            f"- {t['size']} {t['domain']} λ = {t['lambda']:g} (threads {t.get('threads')}): λ change "
            f"to {t.get('new_lambda', 0.25):g}: {100 * lam:.0f} % of this λ's precompute, {100 * lam_new:.0f} % "
            f"of a fresh precompute at the new λ (≤ 40 %: {'met' if max(lam, lam_new) <= 0.4 else '**missed**'})"
            + (f", again after going back: {100 * t['stiffness_change_again_ms'] / t['precompute_ms']:.0f} % / "
               f"{100 * t['stiffness_change_again_ms'] / t['fresh_precompute_new_lambda_ms']:.0f} %"
               if "stiffness_change_again_ms" in t else "") + "; "
            f"belt of {t['belt_vertices']} vertices added {100 * add:.0f} % / removed {100 * rem:.0f} % "
            f"of a fresh Deformer's set_constraints + factorization (≤ 30 %: "
            f"{'met' if max(add, rem) <= 0.3 else '**missed**'}); largest position difference "
            f"to the fresh Deformer {worst:.1e} relative.")
    busy = {}
    for t in rows:
        if t.get("busy") and t["domain"] == "edge" and t["lambda"] == 0.5:
            busy.setdefault(t["size"], {})[t.get("threads")] = t["ms_per_it"]
    for size, by in busy.items():
        if 1 in by and 2 in by:
            out.append(f"- {size} edge λ = 0.5 with one core busy: {by[2]:.2f} ms per iteration on 2 "
                       f"threads vs {by[1]:.2f} on 1 ({'not slower' if by[2] <= by[1] else '**slower**'}).")
    return "\n".join(out)


def busy_ab_table(result):
    rows = result.get("busy_ab")
    if not rows:
        return ""
    lines = ["| size | mesh | rounds | 1 thread ms/it (median) | 2 threads ms/it (median) | 2 / 1 | load |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['size']} | {r['mesh']} | {r['rounds']} | {r['ms_per_it_1']:.2f} "
                     f"| {r['ms_per_it_2']:.2f} | {r['ms_per_it_2'] / r['ms_per_it_1']:.2f} "
                     f"| {r['load_1min']:.1f} |")
    return ("\nOne core kept busy (`--busy-ab`): 1 and 2 threads in alternating fresh processes "
            "(edge, λ = 0.5, lift; each process the median of 5 × 10 iterations), medians over "
            "the rounds:\n\n" + "\n".join(lines) + "\n")


def roi_table(result):
    rows = result.get("roi")
    if not rows:
        return ""
    lines = ["| mesh | vertices | region | free | active nodes | construct ms (once per mesh) "
             "| precompute ms | ms/it |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['mesh']} | {r['vertices']:,} | {r['region']:,} | {r['free_vertices']:,} "
                     f"| {r['active_nodes']:,} | {r['construct_ms']:.0f} | {r['precompute_ms']:.1f} "
                     f"| {r['ms_per_it']:.2f} |")
    whole, roi = rows[0], rows[1]
    return ("\nRegion of interest (`--roi`): a region grown breadth-first from the top vertex of "
            f"{SIZES['140k']} to the vertex count of {ROI_REFERENCE}, its top 10 % raised, against "
            f"the whole {ROI_REFERENCE} (lift). Edge domain, λ = 0.5. Precompute here = set_constraints "
            "+ assembly + factorization (the Deformer's construction is once per mesh and listed "
            "apart). Ratios: precompute "
            f"{roi['precompute_ms'] / whole['precompute_ms']:.2f}×, per iteration "
            f"{roi['ms_per_it'] / whole['ms_per_it']:.2f}× (target ≤ 3×).\n\n" + "\n".join(lines) + "\n")


def markdown(result):
    bi = result.get("build_info", {})
    rows = sorted(result["rows"], key=row_order)
    return f"""Build: solver `{bi.get('solver', '?')}`, threads {bi.get('threads', '?')} (the core's own
worker pool). Rows are merged across the commands above; each row keeps its own load.

Edit "lift": lowest 20 % of the height static, top 10 % raised by ¼ of the bounding-box
diagonal; height = z (no mesh here is flat in z). Tolerance {result['tolerance']:g} (the
estimated largest vertex distance to the fixed point, as a fraction of the bounding-box
diagonal), at most {result['max_iterations']} iterations, naive-Laplacian start.
Precompute = Deformer construction (graph, weights) + the first solve's assembly and
factorization. λ change = set_stiffness to another λ (0.25; 0.75 from 0.25), then the next
solve's update and numeric refactorization, as a share of this row's precompute and of a fresh
Deformer's precompute at the new λ (what the change saves; from λ = 1 the matrix gains the
Laplacian's pattern, so that change also orders it anew, by AMD alone). Handle change = a "belt" (the 2 % band of
vertices around 55 % of the height) added as pinned handles, then removed again:
set_constraints + the next solve's assembly and factorization, as a share of the same on a
fresh Deformer (which has to order the matrix). ms/it = local step + right-hand side +
back-substitution per iteration (10 warm-started iterations), wall clock, best of
{result.get('repeat', 1)}. With the other sessions' load the wall times are inflated by up to
the load / 2; "CPU" = the process's CPU time over all its threads. busy = a second process
spinning (`--busy`) for the whole row. Peak MB = the benchmark process's peak resident set
(it holds up to three Deformers of the mesh at once for the comparisons; one Deformer's peak
is measured apart with `--peak`).

{table(rows)}

Speed targets (per iteration, precompute, memory, λ and handle changes), as measured in these rows:

{targets(rows, result.get("peak_memory", ()))}
{busy_ab_table(result)}{roi_table(result)}"""


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", default=",".join(SIZES), help="comma list of " + ",".join(SIZES))
    p.add_argument("--domains", default=",".join(DOMAINS))
    p.add_argument("--lambdas", default=",".join(map(str, LAMBDAS)))
    p.add_argument("--max-iterations", type=int, default=300)
    p.add_argument("--tolerance", type=float, default=1e-3)
    p.add_argument("--repeat", type=int, default=3, help="timings: best of this many runs")
    p.add_argument("--threads", type=int, default=None,
                   help="OpenMP threads (sets OMP_NUM_THREADS before the core loads)")
    p.add_argument("--busy", action="store_true",
                   help="keep one core busy with a second process during the run")
    p.add_argument("--skip-changes", action="store_true",
                   help="leave out the λ-change and handle-change measurements")
    p.add_argument("--busy-ab", type=int, default=0, metavar="ROUNDS",
                   help="only: 1 vs 2 threads with one core busy, alternating fresh processes")
    p.add_argument("--peak", action="store_true",
                   help="only the peak memory of one Deformer per size/domain/λ, each in a fresh process")
    p.add_argument("--peak-methods", default="anderson",
                   help="with --peak: the accelerations to measure (comma-separated: anderson,lbfgs)")
    p.add_argument("--roi", action="store_true",
                   help="only the region-of-interest comparison (results under 'roi')")
    p.add_argument("--meshes", default=None,
                   help="folder of the benchmark meshes (default: bench/meshes, tests/data, blend_samples/meshes)")
    p.add_argument("--json", default=str(HERE / "results" / "core.json"))
    args = p.parse_args(argv)
    if args.busy and args.busy_ab:
        p.error("--busy-ab keeps one core busy itself; with --busy both cores would be")
    global MESHES
    MESHES = args.meshes

    if args.threads:
        os.environ["OMP_NUM_THREADS"] = str(args.threads)
    import edgedeform as ed
    threads = int(ed.build_info().get("threads", 0)) if args.threads is None else args.threads

    sizes = [s for s in args.sizes.split(",") if s]
    for s in sizes:
        if s not in SIZES:
            p.error(f"unknown size {s!r}")
    out = Path(args.json)
    result = json.loads(out.read_text()) if out.exists() else {"rows": []}
    result.update({"machine": machine_info(), "build_info": dict(ed.build_info()),
                   "tolerance": args.tolerance, "max_iterations": args.max_iterations,
                   "repeat": args.repeat})
    # Every invocation that contributed rows
    cmd = "bench/bench_core.py " + " ".join(argv or sys.argv[1:])
    result["commands"] = [c for c in result.get("commands", []) if c != cmd] + [cmd]
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if args.busy else None
    try:
        if args.roi:
            result["roi"] = run_roi(ed, args.repeat)
            out.write_text(json.dumps(result, indent=1))
        elif args.busy_ab:
            result["busy_ab"] = busy_ab(sizes, args.busy_ab)
            out.write_text(json.dumps(result, indent=1))
        elif args.peak:
            peaks = [peak_memory(size, domain, float(lam), method) for size in sizes
                     for domain in args.domains.split(",") for lam in args.lambdas.split(",")
                     for method in args.peak_methods.split(",")]

            def key(q):
                return q["size"], q["domain"], q["lambda"], q.get("method", "anderson")
            keys = {key(q) for q in peaks}
            result["peak_memory"] = [q for q in result.get("peak_memory", []) if key(q) not in keys] + peaks
            print(peaks)
            out.write_text(json.dumps(result, indent=1))
        else:
            measure_sizes(ed, args, sizes, threads, result, out)
    finally:
        if busy:
            busy.kill()
    print()
    print(table(sorted(result["rows"], key=row_order)))


def row_order(r):
    return (-r.get("threads", 0), r.get("busy", False), list(SIZES).index(r["size"]),
            DOMAINS.index(r["domain"]), r["lambda"])


def measure_sizes(ed, args, sizes, threads, result, out):
    from edgedeform.mesh_files import read_mesh
    for size in sizes:
        V, F = read_mesh(str(mesh_path(SIZES[size], MESHES)))
        edit = lift_edit(V)
        for domain in args.domains.split(","):
            for lam in map(float, args.lambdas.split(",")):
                row = run_one(ed, V, F, edit, domain, lam, args.max_iterations, args.tolerance,
                              args.repeat, changes=not args.skip_changes)
                row.update({"size": size, "mesh": SIZES[size], "vertices": len(V),
                            "faces": len(F), "up_axis": "xyz"[edit[3]], "threads": threads,
                            "busy": args.busy})
                key = (size, domain, lam, threads, args.busy)
                result["rows"] = [r for r in result["rows"]
                                  if (r["size"], r["domain"], r["lambda"], r.get("threads"),
                                      r.get("busy", False)) != key] + [row]
                print(table([row]).splitlines()[-1], flush=True)
                out.parent.mkdir(parents=True, exist_ok=True)
                out.write_text(json.dumps(result, indent=1))   # keep partial results


if __name__ == "__main__":
    main()
