"""Makes bench/meshes/koala_5k.obj and koala_12k.obj: the koala at lower resolutions, for the
soft-mode scaling diagnostic (bench_soft_modes.py d1). Blender's Decimate modifier (Collapse,
triangulated) on the koala read as it is; the output keeps Blender's vertex order. The same
Blender gives the same file (checked on 3.4.1); the committed files are what 3.4.1 wrote.

    blender -b --factory-startup --python-exit-code 1 --python bench/decimate_koala.py -- \\
        bench/results/cache/meshes/koala.obj 0.1 koala_5k.obj
(then xz -9 into bench/meshes/; the decompressed koala comes from edits.mesh_path("koala.obj")).
"""
import sys

import bpy
import numpy as np


def read_obj(path):
    V, F = [], []
    for line in open(path):
        p = line.split()
        if p and p[0] == "v":
            V.append([float(x) for x in p[1:4]])
        elif p and p[0] == "f":
            F.append([int(x.split("/")[0]) - 1 for x in p[1:]])
    return V, F


def main(src, ratio, out):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    V, F = read_obj(src)
    mesh = bpy.data.meshes.new("koala")
    mesh.from_pydata(V, [], F)
    ob = bpy.data.objects.new("koala", mesh)
    bpy.context.scene.collection.objects.link(ob)
    mod = ob.modifiers.new("decimate", "DECIMATE")
    mod.decimate_type, mod.ratio, mod.use_collapse_triangulate = "COLLAPSE", ratio, True
    low = ob.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    low.calc_loop_triangles()
    co = np.empty(3 * len(low.vertices))
    low.vertices.foreach_get("co", co)
    tris = np.empty(3 * len(low.loop_triangles), dtype=np.int64)
    low.loop_triangles.foreach_get("vertices", tris)
    with open(out, "w") as f:
        f.write(f"# koala.obj (odedstein/meshes, Thingiverse 182225 by YahooJAPAN, CC BY 3.0) decimated by "
                f"Blender {bpy.app.version_string}: Decimate, Collapse, ratio {ratio:g}, triangulated\n")
        for v in co.reshape(-1, 3):
            f.write("v %.6f %.6f %.6f\n" % tuple(v))
        for t in tris.reshape(-1, 3) + 1:
            f.write("f %d %d %d\n" % tuple(t))


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:]
    main(args[0], float(args[1]), args[2])
