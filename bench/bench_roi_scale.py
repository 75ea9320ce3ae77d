#!/usr/bin/env python3
"""Does a region picked by radius cost what the region costs, whatever the mesh around it?

The big mesh is nefertiti_loop1.ply split once more into four (560,002 vertices). The handle
is the disk of vertices within 2 % of the diagonal of the top vertex; the region is every
vertex within `--radius` (a fraction of the diagonal) of it: set_constraints(handles=...,
roi_radius=r). The reference is the same region cut out as a whole mesh of its own (the faces
that touch a free vertex or a handle; the cut's outer vertices static): the same free vertices, the same
energy terms, no mesh around them. Edge domain, λ = 0.5. Both are measured in one run:

- construct: ed.Deformer(V, F), once per mesh (the big mesh's graph is built whole);
- bind: set_constraints + the first factorization, on a fresh Deformer;
- per iteration: a 10-iteration solve, the solver's own timers and the wall clock;
- tick: the wall time of one warm iteration while the handle moves a little each call
  (what Live runs per update; Blender's write and redraw come on top);
- radius change (big mesh): set_constraints with the radius 1.1× larger (a new base set:
  assembled and factored anew) or back to r (a subset: restricted), then one iteration;
- peak memory: a fresh process each, reading the mesh from a cache, binding and iterating;
  the mesh's own arrays (V and F) are listed apart;
- outside: the positions of every vertex outside the region equal the rest positions, bit
  for bit (np.array_equal), checked after every solve.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_roi_scale.py \\
        [--mesh nefertiti_loop1.ply] [--splits 1] [--radius 0.09] [--repeat 3] \\
        [--out bench/results/roi_scale.json]

Prints a table and writes the JSON; bench/report.py puts the table into docs/benchmarks.md.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from edits import UNPACKED, diagonal, up_axis  # noqa: E402
from machine import machine_info  # noqa: E402
from subdivide import subdivided  # noqa: E402

HANDLE_RADIUS = 0.02   # of the diagonal: the handle disk around the top vertex
LAMBDA = 0.5
TICKS = 20
DRAG_STEP = 2e-4       # of the diagonal, per tick: a slow drag
RADIUS_GROWTH = 1.1    # one wheel step of Blender's proportional size


def handle_edit(V, radius_fraction):
    """Handles (the disk at the top), their targets (raised by a quarter of the region's
    radius), the radius in mesh units and the drag's step per tick."""
    ax, diag = up_axis(V), diagonal(V)
    top = V[int(np.argmax(V[:, ax]))]
    handles = np.flatnonzero(np.linalg.norm(V - top, axis=1) <= HANDLE_RADIUS * diag)
    step = np.zeros(3)
    step[ax] = DRAG_STEP * diag
    targets = V[handles] + 0.25 * radius_fraction * diag * step / np.linalg.norm(step)
    return handles, targets, radius_fraction * diag, step


def cut_out(V, F, free, handles):
    """The region as a mesh of its own: the faces touching a free vertex or a handle, the
    vertices they use renumbered; those neither free nor handles become static. Returns
    (V, F, handles, static)."""
    moving = np.zeros(len(V), bool)
    moving[free] = True
    moving[handles] = True
    faces = F[moving[F].any(axis=1)]
    used = np.unique(faces)
    new_id = np.full(len(V), -1)
    new_id[used] = np.arange(len(used))
    static = new_id[used[~moving[used]]]
    return V[used], new_id[faces], new_id[handles], static


def outside_at_rest(V, positions, moving):
    """Every vertex but the `moving` ones (free vertices and handles) at rest, bit for bit."""
    outside = np.ones(len(V), bool)
    outside[moving] = False
    return bool(np.array_equal(positions[outside], V[outside]))


def time_case(ed, V, F, constraints, targets, step, repeat, check_outside):
    """Medians over `repeat` fresh Deformers, after one more that warms the caches and thread
    pools and is not counted: construct, bind, per iteration, tick (ms)."""
    for rep in range(repeat + 1):
        if rep <= 1:
            binds, inner, wall, ticks, construct = [], [], [], [], []
        t0 = time.perf_counter()
        d = ed.Deformer(V, F)
        construct.append((time.perf_counter() - t0) * 1e3)
        d.set_stiffness(LAMBDA)
        t0 = time.perf_counter()
        d.set_constraints(**constraints)
        set_ms = (time.perf_counter() - t0) * 1e3
        r = d.solve(targets, max_iterations=1)
        binds.append(set_ms + float(r.factor_ms))
        t0 = time.perf_counter()
        r = d.solve(targets, max_iterations=10, tolerance=0.0)
        wall.append((time.perf_counter() - t0) * 1e3 / r.iterations)
        inner.append((float(r.local_ms) + float(r.rhs_ms) + float(r.solve_ms)) / r.iterations)
        check_outside(r.positions, d.free_vertices)
        moved = targets.copy()
        for _ in range(TICKS):
            moved += step
            t0 = time.perf_counter()
            r = d.solve(moved, max_iterations=1, tolerance=0.0)
            ticks.append((time.perf_counter() - t0) * 1e3)
        check_outside(r.positions, d.free_vertices)
    med = lambda xs: float(np.median(xs))
    return d, {"construct_ms": med(construct), "bind_ms": med(binds), "ms_per_it": med(inner),
               "wall_ms_per_it": med(wall), "tick_ms": med(ticks), "free_vertices": int(r.free_vertices),
               "active_nodes": int(r.active_nodes)}


def radius_change(ed, d, handles, targets, radius, repeat, check_outside):
    """Next update after the radius grows by RADIUS_GROWTH, and after it shrinks back (ms)."""
    grow, shrink = [], []
    for _ in range(repeat):
        for r_new, into in ((radius * RADIUS_GROWTH, grow), (radius, shrink)):
            t0 = time.perf_counter()
            d.set_constraints(handles=handles, roi_radius=r_new)
            r = d.solve(targets, max_iterations=1, tolerance=0.0)
            into.append((time.perf_counter() - t0) * 1e3)
            check_outside(r.positions, d.free_vertices)
    return {"radius_grow_ms": float(np.median(grow)), "radius_shrink_ms": float(np.median(shrink))}


# VmHWM, not ru_maxrss: a child's ru_maxrss keeps the forking parent's high-water mark.
CHILD = """
import numpy as np
import edgedeform as ed
def status_mb(key):
    for line in open("/proc/self/status"):
        if line.startswith(key + ":"):
            return float(line.split()[1]) / 1024
with np.load({path!r}) as z:
    V, F, handles, static, targets, radius = (z[k] for k in ("V", "F", "handles", "static", "targets", "radius"))
loaded = status_mb("VmRSS")
d = ed.Deformer(V, F)
d.set_stiffness({lam!r})
kw = dict(roi_radius=float(radius)) if radius > 0 else dict(static=static)
d.set_constraints(handles=handles, **kw)
d.solve(targets, max_iterations=10, tolerance=0.0)
print(loaded, status_mb("VmHWM"))
"""


def peak_memory(case_path):
    """(MB after loading the mesh, peak MB) of a fresh process binding and iterating the case."""
    out = subprocess.run([sys.executable, "-c", CHILD.format(path=str(case_path), lam=LAMBDA)],
                         capture_output=True, text=True, check=True)
    loaded, peak = (float(x) for x in out.stdout.split()[-2:])
    return loaded, peak


def run(ed, mesh, splits, radius_fraction, repeat):
    V, F, _ = subdivided(mesh, splits)
    handles, targets, radius, step = handle_edit(V, radius_fraction)

    outside_checks = []   # one per solve of the big mesh: every vertex outside at rest, bit for bit

    def check_outside_big(positions, free):
        outside_checks.append(outside_at_rest(V, positions, np.concatenate([free, handles])))

    big_d, big = time_case(ed, V, F, dict(handles=handles, roi_radius=radius), targets, step, repeat,
                           check_outside_big)
    big.update(radius_change(ed, big_d, handles, targets, radius, repeat, check_outside_big))
    free = np.array(big_d.free_vertices)
    del big_d
    Vs, Fs, hs, ss = cut_out(V, F, free, handles)

    def check_outside_small(positions, free_small):
        if not outside_at_rest(Vs, positions, np.concatenate([free_small, hs])):
            raise SystemExit("a static vertex of the cut-out moved")

    _, small = time_case(ed, Vs, Fs, dict(handles=hs, static=ss), targets, step, repeat, check_outside_small)
    if small["free_vertices"] != big["free_vertices"]:
        raise SystemExit(f"the cut-out frees {small['free_vertices']} vertices, the region {big['free_vertices']}")

    cases = {}
    for name, arrays in (("big", (V, F, handles, np.array([], int), targets, radius)),
                         ("small", (Vs, Fs, hs, ss, targets, 0.0))):
        path = UNPACKED / f"roi_scale_{name}.npz"
        np.savez(path, **dict(zip(("V", "F", "handles", "static", "targets", "radius"), arrays)))
        cases[name] = peak_memory(path)
        path.unlink()
    for row, (loaded, peak), (Vx, Fx) in ((big, cases["big"], (V, F)), (small, cases["small"], (Vs, Fs))):
        row.update(peak_mb=peak, loaded_mb=loaded, mesh_arrays_mb=(Vx.nbytes + Fx.nbytes) / 2**20,
                   vertices=len(Vx), faces=len(Fx))
    return {"mesh": f"{mesh} split {splits}×", "radius_fraction": radius_fraction, "radius": radius,
            "handles": len(handles), "lambda": LAMBDA, "region": big, "cut_out": small,
            "outside_bit_equal": bool(outside_checks) and all(outside_checks),
            "outside_checked_solves": len(outside_checks)}


def markdown(result):
    r = result["rows"][0]
    big, small = r["region"], r["cut_out"]
    ratio = lambda key: big[key] / small[key]
    lines = [f"{r['mesh']} ({big['vertices']:,} vertices), the region within {r['radius_fraction']:g} of the "
             f"diagonal of a {r['handles']}-vertex handle disk: {big['free_vertices']:,} free vertices, "
             f"{big['active_nodes']:,} energy terms; against that region cut out as a mesh of its own "
             f"({small['vertices']:,} vertices). Edge domain, λ {r['lambda']:g}; medians of the runs. Outside "
             f"the region every vertex stayed at rest bit for bit after each of "
             f"{r.get('outside_checked_solves', 'the')} solves: "
             f"{'yes' if r['outside_bit_equal'] else 'no'}.", "",
             "| | region in the big mesh | the region as its own mesh | ratio |", "|---|---|---|---|"]
    for label, key, fmt in (("construct (once per mesh), ms", "construct_ms", "{:.0f}"),
                            ("bind (set_constraints + factor), ms", "bind_ms", "{:.0f}"),
                            ("per iteration, solver's timers, ms", "ms_per_it", "{:.2f}"),
                            ("per iteration, wall, ms", "wall_ms_per_it", "{:.2f}"),
                            ("one warm iteration while dragging (Live's tick, core only), ms", "tick_ms", "{:.1f}"),
                            ("peak memory, MB", "peak_mb", "{:.0f}"),
                            ("of which the mesh's V and F, MB", "mesh_arrays_mb", "{:.0f}")):
        lines.append(f"| {label} | {fmt.format(big[key])} | {fmt.format(small[key])} | {ratio(key):.2f} |")
    lines.append(f"| peak memory less the big mesh's V and F, MB | "
                 f"{big['peak_mb'] - big['mesh_arrays_mb']:.0f} | {small['peak_mb']:.0f} | "
                 f"{(big['peak_mb'] - big['mesh_arrays_mb']) / small['peak_mb']:.2f} |")
    lines += ["", f"Radius changed during the drag (the next update: set_constraints, then one iteration): "
                  f"grown {RADIUS_GROWTH:g}× {big['radius_grow_ms']:.0f} ms, shrunk back "
                  f"{big['radius_shrink_ms']:.0f} ms."]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesh", default="nefertiti_loop1.ply", help="a benchmark mesh file name")
    ap.add_argument("--splits", type=int, default=1, help="times each triangle is split into four")
    ap.add_argument("--radius", type=float, default=0.09, help="the region's radius, a fraction of the diagonal")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=str(HERE / "results" / "roi_scale.json"))
    args = ap.parse_args(argv)
    import edgedeform as ed
    result = {"machine": machine_info(), "command": "bench/bench_roi_scale.py " + " ".join(argv or sys.argv[1:]),
              "rows": [run(ed, args.mesh, args.splits, args.radius, args.repeat)]}
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(markdown(result))


if __name__ == "__main__":
    main()
