"""Cross-check: the add-on, driven as a script user would (open the sample .blend, bind, solve),
must reach a fixed point of the package's painted edge-domain iteration.

Like with like: the add-on solves to CHECK_TOLERANCE (a distance to the fixed point, as a
fraction of the diagonal; Solve pressed again with Warm Start until it settles, as its
Iterations are capped), then the package continues from the add-on's result with its default
method and must stop at once, converged, within the tolerance's reach of it (package_verdict).
Comparing against the package's own solve from rest instead does not work on soft samples:
the head's fixed point moves by 1e-4 of the diagonal when its input is rounded to float32
(as Blender stores it) or another method walks to it, so two solves each converged to 1e-6
lie 1e-4 apart; and with the demo's 1e-3 two solves may lie 2e-3 apart, which is what failed
on Debian 13, where round-off made the head take 1,301 iterations instead of 736 and the
add-on stop at its cap of 1,000.

As a module: AddonCheck(...).run(scene_def, ed, V, F, setup) starts a separate Blender on
the sample file (so the demo's own scenes stay untouched) and compares. As a Blender script:
    blender -b SAMPLE.blend --python addon_check.py -- OUT.npy TOLERANCE
writes the deformed positions (shape key or mesh) to OUT.npy.
"""
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


# Tight: the slack of two converged ends (4 tolerances) stays far below a wrong result.
CHECK_TOLERANCE = 1e-6
# The add-on's result reaches us in float32 (2^-24 relative, ~3e-8 of the head's diagonal);
# continuing from it moved the head 1.5e-7 of the diagonal (measured): allowance, in units
# of the diagonal, on top of the 4 tolerances two converged ends may lie apart.
FLOAT32_SLACK = 1e-6
# Solve presses (Warm Start: continue) until one changes the mesh by less than this many
# tolerances: the add-on runs at most its Iterations' hard maximum per press.
SETTLED_STEP = 4


class AddonCheck:
    def __init__(self, samples_dir, out, module_path=None, tolerance=CHECK_TOLERANCE,
                 max_iterations=3000):
        self.samples_dir = samples_dir or os.path.join(REPO, "blend_samples")
        self.work = os.path.join(out, "addon_check")
        self.module_path = module_path or os.path.join(REPO, "build", "python")
        self.tolerance, self.max_iterations = tolerance, max_iterations

    def _blend(self, name):
        path = os.path.join(self.samples_dir, name + ".blend")
        if os.path.exists(path):
            return path
        os.makedirs(self.work, exist_ok=True)
        # --python-use-system-env: Blender 4.x ignores PYTHONPATH otherwise.
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            p for p in (self.module_path, os.environ.get("PYTHONPATH")) if p))
        subprocess.run([bpy_binary(), "-b", "--factory-startup", "--python-use-system-env",
                        "--python-exit-code", "1",
                        "--python", os.path.join(REPO, "blend_samples", "make_samples.py"),
                        "--", "--out", self.work, "--only", name],
                       check=True, capture_output=True, text=True, env=env)
        return os.path.join(self.work, name + ".blend")

    def run(self, scene_def, ed, V, F, setup):
        import numpy as np
        try:
            blend = self._blend(scene_def["name"])
        except subprocess.CalledProcessError as exc:
            return {"ok": False, "message": "make_samples failed: " + exc.stderr[-300:]}
        os.makedirs(self.work, exist_ok=True)
        npy = os.path.join(self.work, scene_def["name"] + "_addon.npy")
        if os.path.exists(npy):
            os.remove(npy)
        env = dict(os.environ, EDGEDEFORM_MODULE_PATH=self.module_path)
        proc = subprocess.run(
            [bpy_binary(), "-b", "--factory-startup", blend, "--python-exit-code", "1",
             "--python", os.path.abspath(__file__), "--", npy, str(self.tolerance)],
            capture_output=True, text=True, env=env)
        if proc.returncode != 0 or not os.path.exists(npy):
            tail = [ln for ln in (proc.stdout + proc.stderr).splitlines()
                    if "EGL" not in ln][-6:]
            return {"ok": False, "message": "add-on run failed: " + " | ".join(tail)}
        got = np.load(npy)
        moved = float(np.abs(got - np.load(npy.replace("_addon.npy", "_rest.npy"))).max())
        verdict = package_verdict(ed, V, F, setup, got, self.tolerance, self.max_iterations)
        verdict["ok"] = verdict["ok"] and moved > 0
        verdict["max_displacement"] = moved
        return verdict


def package_verdict(ed, V, F, setup, got, tolerance, max_iterations=3000):
    """Does the package accept `got` as its fixed point? It continues from `got` with its own
    default method and must stop, converged, within 4 tolerances (plus float32 round-off) of it.

    Not plain steps: a fixed point may repel them. The dino's painted edit has one (its soft
    tail end, growth 1.6 per step; docs/decisions/0023): Anderson, in the add-on and the
    package alike, converges to it (|G(x) - x| = 1e-9 of the diagonal there), and plain steps
    from it walk 2e-3 of the diagonal away to another fixed point, which attracts them."""
    import numpy as np
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=setup["handle_index"], static=setup["static"], roi=None)
    d.set_stiffness(setup["stiffness"])
    r = d.solve(setup["targets"], initial=got, max_iterations=max_iterations,
                tolerance=tolerance, warm_start=False)
    diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    diff = float(np.abs(np.asarray(r.positions) - got).max())
    limit = (4 * tolerance + FLOAT32_SLACK) * diag
    return {"ok": bool(r.converged) and diff < limit,
            "max_difference": diff, "limit": limit, "tolerance": tolerance,
            "package_converged": bool(r.converged), "package_iterations": int(r.iterations)}


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


def _read(ob):
    import numpy as np
    s = ob.edge_deform
    key = ob.data.shape_keys.key_blocks.get(s.shape_key_name) if ob.data.shape_keys else None
    data = key.data if key is not None else ob.data.vertices
    co = np.empty(len(ob.data.vertices) * 3, np.float32)
    data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def _script(argv):
    import bpy
    import numpy as np
    npy, tolerance = argv[0], float(argv[1])
    _enable_addon()
    ob = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    s = ob.edge_deform
    # Iterations is capped (its hard maximum): a larger value would silently become it.
    s.iterations = type(s).bl_rna.properties["iterations"].hard_max
    s.tolerance, s.output = tolerance, "SHAPE_KEY"
    rest = np.empty(len(ob.data.vertices) * 3, np.float32)
    ob.data.vertices.foreach_get("co", rest)
    rest = rest.reshape(-1, 3).astype(np.float64)
    np.save(npy.replace("_addon.npy", "_rest.npy"), rest)
    diag = float(np.linalg.norm(rest.max(axis=0) - rest.min(axis=0)))
    # As the sample README says: Bind at frame 1 (controllers at rest), Solve at the edit.
    edit_frame = bpy.context.scene.get("edge_deform_edit_frame",
                                       bpy.context.scene.frame_current)
    bpy.context.scene.frame_set(1)
    if bpy.ops.edge_deform.bind() != {"FINISHED"}:
        raise SystemExit("addon_check: bind did not finish")
    bpy.context.scene.frame_set(edit_frame)
    if bpy.ops.edge_deform.solve() != {"FINISHED"}:
        raise SystemExit("addon_check: solve did not finish")
    X = _read(ob)
    for presses in range(2, 100):
        if bpy.ops.edge_deform.solve(warm_start=True) != {"FINISHED"}:
            raise SystemExit("addon_check: solve did not finish")
        new = _read(ob)
        step, X = float(np.abs(new - X).max()), new
        if step < SETTLED_STEP * tolerance * diag:
            break
    else:
        raise SystemExit("addon_check: still moving by %g after %d Solves" % (step, presses))
    print("addon_check: settled after %d Solves (last moved %.2g)" % (presses, step))
    np.save(npy, X)


if __name__ == "__main__" and "--" in sys.argv:
    _script(sys.argv[sys.argv.index("--") + 1:])
