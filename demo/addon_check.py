"""Cross-check: the add-on, driven as a script user would (open the sample .blend, bind, solve),
must give the package's painted edge-domain result.

As a module: AddonCheck(...).run(scene_def, expected) starts a separate Blender on the
sample file (so the demo's own scenes stay untouched) and compares. As a Blender script:
    blender -b SAMPLE.blend --python addon_check.py -- OUT.npy MAX_ITERATIONS TOLERANCE
writes the deformed positions (shape key or mesh) to OUT.npy.
"""
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


class AddonCheck:
    def __init__(self, samples_dir, out, max_iterations=3000, tolerance=1e-3):
        self.samples_dir = samples_dir or os.path.join(REPO, "blend_samples")
        self.work = os.path.join(out, "addon_check")
        self.max_iterations, self.tolerance = max_iterations, tolerance

    def _blend(self, name):
        path = os.path.join(self.samples_dir, name + ".blend")
        if os.path.exists(path):
            return path
        os.makedirs(self.work, exist_ok=True)
        subprocess.run([bpy_binary(), "-b", "--factory-startup", "--python-exit-code", "1",
                        "--python", os.path.join(REPO, "blend_samples", "make_samples.py"),
                        "--", "--out", self.work, "--only", name],
                       check=True, capture_output=True, text=True)
        return os.path.join(self.work, name + ".blend")

    def run(self, scene_def, expected):
        import numpy as np
        try:
            blend = self._blend(scene_def["name"])
        except subprocess.CalledProcessError as exc:
            return {"ok": False, "message": "make_samples failed: " + exc.stderr[-300:]}
        os.makedirs(self.work, exist_ok=True)
        npy = os.path.join(self.work, scene_def["name"] + "_addon.npy")
        if os.path.exists(npy):
            os.remove(npy)
        env = dict(os.environ, EDGEDEFORM_MODULE_PATH=os.path.join(REPO, "build", "python"))
        proc = subprocess.run(
            [bpy_binary(), "-b", "--factory-startup", blend, "--python-exit-code", "1",
             "--python", os.path.abspath(__file__), "--", npy, str(self.max_iterations),
             str(self.tolerance)], capture_output=True, text=True, env=env)
        if proc.returncode != 0 or not os.path.exists(npy):
            tail = [ln for ln in (proc.stdout + proc.stderr).splitlines()
                    if "EGL" not in ln][-6:]
            return {"ok": False, "message": "add-on run failed: " + " | ".join(tail)}
        got = np.load(npy)
        diff = float(np.abs(got - expected).max())
        moved = float(np.abs(got - np.load(npy.replace("_addon.npy", "_rest.npy"))).max())
        # float32 in Blender; the stop test may fire one iteration apart: allow 1e-3 of size 2
        return {"ok": diff < 1e-3 and moved > 0, "max_difference": diff, "max_displacement": moved}


def bpy_binary():
    import bpy
    return bpy.app.binary_path or "blender"


# ---------------------------------------------------------------- inside Blender

def _enable_addon():
    import addon_utils
    import bpy
    if hasattr(bpy.types.Object, "edge_deform"):
        return
    if any(m.__name__ == "edge_deform" for m in addon_utils.modules()):   # installed
        addon_utils.enable("edge_deform", default_set=True)
    if not hasattr(bpy.types.Object, "edge_deform"):     # development tree
        sys.path[:0] = [os.environ.get("EDGEDEFORM_MODULE_PATH", ""), os.path.join(REPO, "addon")]
        import edge_deform
        edge_deform.register()


def _script(argv):
    import bpy
    import numpy as np
    npy, max_iterations, tolerance = argv[0], int(argv[1]), float(argv[2])
    _enable_addon()
    ob = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    s = ob.edge_deform
    s.iterations, s.tolerance, s.output = max_iterations, tolerance, "SHAPE_KEY"
    rest = np.empty(len(ob.data.vertices) * 3, np.float32)
    ob.data.vertices.foreach_get("co", rest)
    np.save(npy.replace("_addon.npy", "_rest.npy"), rest.reshape(-1, 3).astype(np.float64))
    # As the sample README says: Bind at frame 1 (controllers at rest), Solve at the edit.
    edit_frame = bpy.context.scene.get("edge_deform_edit_frame",
                                       bpy.context.scene.frame_current)
    bpy.context.scene.frame_set(1)
    if bpy.ops.edge_deform.bind() != {"FINISHED"}:
        raise SystemExit("addon_check: bind did not finish")
    bpy.context.scene.frame_set(edit_frame)
    if bpy.ops.edge_deform.solve() != {"FINISHED"}:
        raise SystemExit("addon_check: solve did not finish")
    key = ob.data.shape_keys.key_blocks.get(s.shape_key_name) if ob.data.shape_keys else None
    data = key.data if key is not None else ob.data.vertices
    co = np.empty(len(ob.data.vertices) * 3, np.float32)
    data.foreach_get("co", co)
    np.save(npy, co.reshape(-1, 3).astype(np.float64))


if __name__ == "__main__" and "--" in sys.argv:
    _script(sys.argv[sys.argv.index("--") + 1:])
