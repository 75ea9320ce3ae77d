"""One live update of the Edge Deform add-on, timed inside Blender.

A live update is what the `live` tool does on a timer tick after a controller moved:
read the controllers and compute the handle targets, run one warm-started local/global
iteration, write the shape key, update the mesh; the depsgraph evaluation that Blender
then runs before drawing is timed in its own column. The edit is a drag: the top 10 % of
the height follows an Empty that moves a little every update, the lowest 20 % is static,
λ = 0.5. Meshes: ~10k (blub_fish.obj) and ~50k (koala.obj) vertices.

    blender -b --factory-startup --python bench/bench_live_update.py -- \
        [--sizes 10k,50k] [--updates 30] [--json bench/results/live_update.json]

Needs build/python (the package) and addon/ (the add-on) on the path: set
EDGEDEFORM_PYTHONPATH / EDGEDEFORM_ADDON_DIR or run from the repository root. Prints a
table and writes bench/results/live_update.json; bench/report.py puts the table into
docs/benchmarks.md.
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
for var, default in (("EDGEDEFORM_PYTHONPATH", ROOT / "build" / "python"),
                     ("EDGEDEFORM_ADDON_DIR", ROOT / "addon")):
    sys.path.insert(0, os.environ.get(var, str(default)))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import edge_deform  # noqa: E402
import edgedeform as ed  # noqa: E402
from edgedeform.mesh_files import read_mesh  # noqa: E402
from edge_deform import lifecycle  # noqa: E402
from edits import diagonal, mesh_path, regions  # noqa: E402
from machine import machine_info  # noqa: E402

SIZES = {"1k": "spot_low_resolution.obj", "10k": "blub_fish.obj", "50k": "koala.obj"}  # 1k: the smoke test
DOMAINS = ("EDGE", "PRIMAL")


def scene_for(meshes, name):
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    V, F = read_mesh(mesh_path(name, meshes))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(V.tolist(), [], F.tolist())
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    handles, static, ax = regions(V)
    ob.vertex_groups.new(name="H").add(handles.tolist(), 1.0, 'REPLACE')
    ob.vertex_groups.new(name="S").add(static.tolist(), 1.0, 'REPLACE')
    empty = bpy.data.objects.new("C", None)
    bpy.context.scene.collection.objects.link(empty)
    bpy.context.view_layer.update()
    s = ob.edge_deform
    item = s.handles.add()
    item.vertex_group, item.controller = "H", empty
    s.static_group, s.stiffness = "S", 0.5
    s.iterations, s.tolerance = 1, 0.0      # exactly one iteration per update
    step = np.zeros(3)
    step[ax] = 0.005 * diagonal(V)   # a drag: small moves, 60 a second
    return ob, empty, len(V), step


def time_updates(ob, empty, step, updates):
    """The live tool's update, timed in its parts (ms): same lifecycle calls as `live`."""
    bound = lifecycle.prepare(ob)
    binding = bound.binding
    s = ob.edge_deform
    rows = []
    for k in range(updates + 3):          # the first three warm up caches and the solver
        empty.location = tuple(np.array(empty.location) + step)
        bpy.context.view_layer.update()   # the transform system has done this for us live
        t0 = time.perf_counter()
        targets = bound.targets()
        t1 = time.perf_counter()
        r = bound.solve(targets, s.iterations, s.tolerance, warm=True)
        t2 = time.perf_counter()
        bound.write(r.positions)
        t3 = time.perf_counter()
        bpy.context.view_layer.update()   # depsgraph: shape key -> evaluated mesh
        t4 = time.perf_counter()
        if k >= 3:
            rows.append([(t1 - t0) * 1e3, (t2 - t1) * 1e3, (t3 - t2) * 1e3,
                         (t4 - t3) * 1e3, r.local_ms, r.rhs_ms, r.solve_ms])
    return binding, np.array(rows)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="10k,50k", help="comma list of " + ",".join(SIZES))
    ap.add_argument("--updates", type=int, default=30)
    ap.add_argument("--meshes", default=None,
                    help="folder of the benchmark meshes (default: bench/meshes and the test data)")
    ap.add_argument("--json", default=str(HERE / "results" / "live_update.json"))
    args = ap.parse_args(argv)
    if not hasattr(bpy.types.Object, "edge_deform"):
        edge_deform.register()

    results = []
    for size in args.sizes.split(","):
        name = SIZES[size]
        ob, empty, n, step = scene_for(args.meshes, name)
        for domain in DOMAINS:
            ob.edge_deform.domain = domain
            t0 = time.perf_counter()
            assert bpy.ops.edge_deform.bind() == {'FINISHED'}
            bind_ms = (time.perf_counter() - t0) * 1e3
            binding, t = time_updates(ob, empty, step, args.updates)
            med = np.median(t, axis=0)
            update = med[0] + med[1] + med[2]
            row = dict(size=size, mesh=name, vertices=n, nodes=binding.deformer.n_nodes,
                       domain=domain.lower(), bind_ms=bind_ms, targets_ms=med[0],
                       solve_ms=med[1], write_ms=med[2], depsgraph_ms=med[3],
                       update_ms=update, updates_per_s=1e3 / update,
                       with_depsgraph_per_s=1e3 / (update + med[3]),
                       local_ms=med[4], rhs_ms=med[5], backsub_ms=med[6],
                       updates=args.updates)
            results.append(row)
            print("%-4s %-6s %6d v  bind %7.0f ms | update %6.1f ms (targets %.2f, "
                  "solve %.1f [local %.1f rhs %.1f back-sub %.1f], write %.1f) = %5.1f/s | "
                  "+ depsgraph %.1f ms = %5.1f/s" % (
                      size, domain.lower(), n, bind_ms, update, med[0], med[1], med[4],
                      med[5], med[6], med[2], 1e3 / update, med[3],
                      1e3 / (update + med[3])))

    info = machine_info()
    info.update(blender=bpy.app.version_string, build=ed.build_info())
    info["command"] = "blender -b --factory-startup --python bench/bench_live_update.py -- " + " ".join(argv)
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": info, "results": results}, indent=1))
    print("wrote", out)


if __name__ == "__main__":
    main()
