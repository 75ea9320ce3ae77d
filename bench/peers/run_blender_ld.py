"""Blender's Laplacian Deform modifier on one benchmark problem (child of
bench/bench_peers.py), run inside Blender:

    blender -b --factory-startup --python-exit-code 1 --python bench/peers/run_blender_ld.py \
        -- PROBLEM --edit lift|twist --out result.json [--frames 20]

The same anchors as the other methods: vertex group "anchors" = handles + static. A Hook
modifier (vertex group "handles", no falloff) moves the handles with an Empty at their
centroid, keyed at rest on frame 1 and at the edit on the last frame; Laplacian Deform
comes after it in the stack. Bound once; then every frame is timed as the Empty animates
(`scene.frame_set`: animation, hook, Laplacian Deform, depsgraph). The same frames with
the Laplacian Deform modifier switched off give the cost of everything else.
"""

import math
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from peers.common import child_args, max_rss_mb, write_result  # noqa: E402
from peers.problem import load_problem  # noqa: E402
from peers.trajectory import max_distance  # noqa: E402


def build_scene(p):
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    mesh = bpy.data.meshes.new("peer")
    mesh.from_pydata(p["V"].tolist(), [], p["F"].tolist())
    ob = bpy.data.objects.new("peer", mesh)
    bpy.context.scene.collection.objects.link(ob)
    ob.vertex_groups.new(name="handles").add(p["handles"].tolist(), 1.0, 'REPLACE')
    anchors = np.concatenate([p["handles"], p["static"]])
    ob.vertex_groups.new(name="anchors").add(anchors.tolist(), 1.0, 'REPLACE')
    pivot = p["V"][p["handles"]].mean(axis=0)
    empty = bpy.data.objects.new("controller", None)
    empty.location = pivot.tolist()
    bpy.context.scene.collection.objects.link(empty)
    bpy.context.view_layer.update()
    hook = ob.modifiers.new("Hook", 'HOOK')
    hook.object, hook.vertex_group, hook.falloff_type = empty, "handles", 'NONE'
    hook.center = pivot.tolist()
    hook.matrix_inverse = empty.matrix_world.inverted()   # identity at rest
    ld = ob.modifiers.new("LaplacianDeform", 'LAPLACIANDEFORM')
    ld.vertex_group, ld.iterations = "anchors", 1
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob, empty, ld


def animate(empty, p, edit, frames):
    """Rest on frame 1, the edit on frame `frames` (linear keys)."""
    V, h = p["V"], p["handles"]
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames
    scene.frame_set(1)
    empty.keyframe_insert("location", frame=1)
    empty.keyframe_insert("rotation_euler", frame=1)
    if edit == "lift":   # the targets are the handles shifted: move the Empty by that shift
        empty.location = (np.asarray(empty.location) + (p["targets"][0] - V[h[0]])).tolist()
    else:                # twist: turn the Empty about the height axis (it sits at the pivot)
        ax = int(p["up_axis"])
        rot = [0.0, 0.0, 0.0]
        rot[ax] = math.radians(float(p["twist_degrees"]))
        empty.rotation_euler = rot
    empty.keyframe_insert("location", frame=frames)
    empty.keyframe_insert("rotation_euler", frame=frames)
    for fc in empty.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = 'LINEAR'


def evaluated_positions(ob):
    ev = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    co = np.empty(len(ev.data.vertices) * 3)
    ev.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def frame_times(frames):
    """Wall ms of each frame after the first, and the median CPU ms (all threads)."""
    scene, times, cpu = bpy.context.scene, [], []
    for f in range(2, frames + 1):
        c0, t0 = time.process_time(), time.perf_counter()
        scene.frame_set(f)
        times.append((time.perf_counter() - t0) * 1e3)
        cpu.append((time.process_time() - c0) * 1e3)
    return times, float(np.median(cpu[1:]))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = child_args(__doc__.split("\n\n")[0], [
        (("--edit",), {"choices": ["lift", "twist"], "required": True}),
        (("--frames",), {"type": int, "default": 21})]).parse_args(argv)
    base_rss = max_rss_mb()
    p = load_problem(args.problem)
    ob, empty, ld = build_scene(p)
    animate(empty, p, args.edit, args.frames)
    bpy.context.scene.frame_set(1)

    t0 = time.perf_counter()
    with bpy.context.temp_override(object=ob, active_object=ob):
        result = bpy.ops.object.laplaciandeform_bind(modifier=ld.name)
    if result != {'FINISHED'}:
        raise RuntimeError(f"laplaciandeform_bind returned {result}")
    bpy.context.view_layer.update()          # the bind happens on this evaluation
    bind_ms = (time.perf_counter() - t0) * 1e3
    if not ld.is_bind:
        raise RuntimeError("Laplacian Deform did not bind")

    times, frame_cpu = frame_times(args.frames)   # the first builds and factors the system
    x = evaluated_positions(ob)
    anchor_error = max_distance(x[p["handles"]], p["targets"]) / p["diag"]
    static_error = max_distance(x[p["static"]], p["V"][p["static"]]) / p["diag"]
    moved = max_distance(x, p["V"]) / p["diag"]

    ld.show_viewport = False
    bpy.context.scene.frame_set(1)
    without, _ = frame_times(args.frames)
    frame_ms = float(np.median(times[1:]))
    write_result(args.out, {
        "method": "blender_laplacian_deform", "version": f"Blender {bpy.app.version_string}",
        "vertices": len(p["V"]), "threads": None,
        "precompute_ms": bind_ms + times[0], "bind_ms": bind_ms, "first_frame_ms": times[0],
        "frame_ms": frame_ms, "frame_ms_all": times[1:], "frame_cpu_ms": frame_cpu,
        "frame_ms_without_ld": float(np.median(without[1:])),
        "ld_ms": frame_ms - float(np.median(without[1:])),
        "anchor_error": anchor_error, "static_error": static_error, "max_move": moved,
        "base_rss_mb": base_rss, "frames": args.frames})


if __name__ == "__main__":
    main()
