"""Live on a large mesh with a proportional radius, timed inside Blender.

The mesh is nefertiti_loop1.ply split once more into four (560,002 vertices, as in
bench_roi_scale.py); the handle is the disk of vertices within 2 % of the diagonal of the top
vertex, following an Empty; Proportional is on with the radius at 0.09 of the diagonal (about
21k free vertices), nothing static, λ = 0.5, edge domain. Measured with the add-on's own
calls (those of bench_live_update.py's updates, then the Live tool's rebind for a radius
step):

- bind: the Bind button (the Deformer of the whole mesh built, the region factored);
- one live update: targets, one warm iteration, the shape-key write; Blender's depsgraph
  evaluation apart;
- a radius step: the radius 1.1x larger (the wheel), the new constraints as Live takes
  them (ObjectSolver.region_changed), and the next update, started from the shape shown;
  then one step back.

    blender -b --factory-startup --python bench/bench_live_region.py -- \\
        [--mesh nefertiti_loop1.ply] [--splits 1] [--radius 0.09] [--updates 20] \\
        [--json bench/results/live_region.json]

Needs build/python and addon/ on the path (EDGEDEFORM_PYTHONPATH / EDGEDEFORM_ADDON_DIR, as
bench_live_update.py). Prints a table and writes the JSON; bench/report.py puts the table
into docs/benchmarks.md.
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_live_update import time_updates  # noqa: E402  (puts the package and add-on on the path)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import edge_deform  # noqa: E402
import edgedeform as ed  # noqa: E402
from edge_deform import lifecycle  # noqa: E402
from bench_roi_scale import handle_edit  # noqa: E402
from live_update_report import region_markdown as markdown  # noqa: E402
from machine import machine_info  # noqa: E402
from subdivide import subdivided  # noqa: E402

STEP = 1.1   # one wheel step (proportional.STEP)


def scene(mesh_name, splits, radius_fraction):
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    V, F, _ = subdivided(mesh_name, splits)
    handles, _, radius, step = handle_edit(V, radius_fraction)
    mesh = bpy.data.meshes.new("big")
    mesh.vertices.add(len(V))
    mesh.loops.add(F.size)
    mesh.polygons.add(len(F))
    mesh.vertices.foreach_set("co", V.astype(np.float32).ravel())
    mesh.loops.foreach_set("vertex_index", F.astype(np.int32).ravel())
    mesh.polygons.foreach_set("loop_start", np.arange(0, F.size, 3, dtype=np.int32))
    if bpy.app.version < (4, 0, 0):
        mesh.polygons.foreach_set("loop_total", np.full(len(F), 3, dtype=np.int32))
    mesh.update()
    ob = bpy.data.objects.new("big", mesh)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    ob.vertex_groups.new(name="H").add(handles.tolist(), 1.0, 'REPLACE')
    empty = bpy.data.objects.new("C", None)
    empty.location = tuple(V[handles].mean(axis=0))
    bpy.context.scene.collection.objects.link(empty)
    bpy.context.view_layer.update()
    s = ob.edge_deform
    item = s.handles.add()
    item.vertex_group, item.controller = "H", empty
    s.stiffness = 0.5
    s.proportional, s.proportional_radius = True, radius
    s.iterations, s.tolerance = 1, 0.0      # exactly one iteration per update
    return ob, empty, len(V), step, len(handles)


def radius_steps(ob, empty, step, rounds):
    """(grow ms, shrink ms, free vertices): medians of `rounds` wheel steps, each as Live
    takes it (ObjectSolver.region_changed, then one update started from the shape shown)."""
    from edge_deform import mesh_io
    s = ob.edge_deform
    bound = lifecycle.prepare(ob)
    times = {STEP: [], 1.0 / STEP: []}
    for _ in range(rounds):
        for factor in (STEP, 1.0 / STEP):
            t0 = time.perf_counter()
            s.proportional_radius *= factor
            bound.region_changed()
            empty.location = tuple(np.array(empty.location) + step)
            bpy.context.view_layer.update()
            initial = mesh_io.addon_shape(ob) if bound.binding.starts_cold else None
            r = bound.solve(bound.targets(), 1, 0.0, warm=True, initial=initial)
            bound.write(r.positions)
            times[factor].append((time.perf_counter() - t0) * 1e3)
    return float(np.median(times[STEP])), float(np.median(times[1.0 / STEP])), int(r.free_vertices)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesh", default="nefertiti_loop1.ply")
    ap.add_argument("--splits", type=int, default=1)
    ap.add_argument("--radius", type=float, default=0.09, help="a fraction of the diagonal")
    ap.add_argument("--updates", type=int, default=20)
    ap.add_argument("--json", default=str(HERE / "results" / "live_region.json"))
    args = ap.parse_args(argv)
    if not hasattr(bpy.types.Object, "edge_deform"):
        edge_deform.register()
    ob, empty, n, step, n_handles = scene(args.mesh, args.splits, args.radius)
    t0 = time.perf_counter()
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    bind_ms = (time.perf_counter() - t0) * 1e3
    _, t = time_updates(ob, empty, step, args.updates)
    med = np.median(t, axis=0)
    update = med[0] + med[1] + med[2]
    grow, shrink, free = radius_steps(ob, empty, step, 3)
    row = dict(mesh=f"{args.mesh} split {args.splits}×", vertices=n, radius_fraction=args.radius,
               handles=n_handles, free_vertices=free, bind_ms=bind_ms,
               targets_ms=med[0], solve_ms=med[1], write_ms=med[2], depsgraph_ms=med[3],
               update_ms=update, updates_per_s=1e3 / update, with_depsgraph_per_s=1e3 / (update + med[3]),
               radius_grow_ms=grow, radius_shrink_ms=shrink, updates=args.updates)
    info = machine_info()
    info.update(blender=bpy.app.version_string, build=ed.build_info())
    info["command"] = "blender -b --factory-startup --python bench/bench_live_region.py -- " + " ".join(argv)
    result = {"machine": info, "results": [row]}
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1))
    print(markdown(result))
    print("wrote", out)
    # bpy 4.5 as a Python module can hang at exit after this run, in its own exit handler
    # (gdb: GlobalState::~GlobalState waits on its delayed-close thread): the results are
    # written, so leave without running the exit handlers.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
