"""Every sample scene, built by make_samples.py, binds and solves through the add-on's
operators as its README says (Bind at frame 1, Solve at the edit frame). Run in Blender:
    blender -b --factory-startup --python-exit-code 1 --python tests/demo/test_samples_addon.py \
        -- OUT_DIR BUILD_PYTHON_DIR
Asserts: the file opens at the edit frame showing the solved deformation; groups and
settings as the scene data says; handles reach their targets; static
vertices do not move; other vertices do; the saved .blend reopens with its settings."""
import os
import sys
import traceback

import bpy
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
out, module_path = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path[:0] = [module_path, os.path.join(REPO, "blend_samples"), os.path.join(REPO, "demo")]
import make_samples  # noqa: E402
import regions       # noqa: E402


def read_key(ob):
    key = ob.data.shape_keys.key_blocks[ob.edge_deform.shape_key_name]
    co = np.empty(len(ob.data.vertices) * 3, np.float32)
    key.data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def positions(ob):
    co = np.empty(len(ob.data.vertices) * 3, np.float32)
    ob.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def group_weights(ob, name):
    """(n,) weights of a vertex group (0 outside), through the add-on's bulk reader."""
    from edge_deform import mesh_io
    return mesh_io.read_group_weights(ob, [name])[name].astype(np.float64)


def check_scene(scene):
    ob, have_settings = make_samples.build_scene(scene)
    assert have_settings, "the add-on's settings are missing"
    path = os.path.join(out, scene["name"] + ".blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
    bpy.ops.wm.open_mainfile(filepath=path)            # what a user opens
    ob = bpy.data.objects[scene["name"]]
    V, _ = regions.scene_mesh(scene)
    setup = regions.scene_setup(scene, V)
    s = ob.edge_deform
    assert [h.vertex_group for h in s.handles] == ["handle_" + h["name"] for h in scene["handles"]]
    assert s.static_group == "static" and s.stiffness_group == "stiffness" and s.domain == "EDGE"
    lam = group_weights(ob, "stiffness")
    assert np.allclose(lam, setup["stiffness"], atol=1e-6), "stiffness group != painted λ"
    assert np.array_equal(np.flatnonzero(group_weights(ob, "static") > 0),
                          np.sort(setup["static"]))

    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    sc = bpy.context.scene
    # It opens where the mesh already shows its deformation: the edit frame, the key shown
    # in full, handles at the controllers' targets, static vertices at rest.
    assert sc.frame_current == make_samples.EDIT_FRAME
    key = ob.data.shape_keys.key_blocks.get(s.shape_key_name) if ob.data.shape_keys else None
    assert key is not None and key.value == 1.0 and not key.mute, "opens without its edit"
    shown, rest = read_key(ob), positions(ob)
    assert np.abs(shown[setup["handle_index"]] - setup["targets"]).max() < 1e-3, \
        "the shown deformation does not reach the controllers"
    assert np.array_equal(shown[setup["static"]], rest[setup["static"]])
    sc.frame_set(1)
    assert bpy.ops.edge_deform.bind() == {"FINISHED"}
    sc.frame_set(make_samples.EDIT_FRAME)
    s.iterations = 30
    assert bpy.ops.edge_deform.solve() == {"FINISHED"}
    X = read_key(ob)
    err = np.abs(X[setup["handle_index"]] - setup["targets"]).max()
    assert err < 1e-4, "handles off their targets by %g" % err
    assert np.abs(X[setup["static"]] - rest[setup["static"]]).max() == 0.0
    free = np.setdiff1d(np.arange(len(V)), np.concatenate([setup["handle_index"], setup["static"]]))
    assert np.abs(X[free] - rest[free]).max() > 1e-2, "free vertices did not move"
    return err


def main():
    os.makedirs(out, exist_ok=True)
    how = make_samples.enable_addon()
    print("add-on from", how)
    passed = failed = 0
    for scene in regions.load_scenes():
        try:
            err = check_scene(scene)
            if not hasattr(bpy.types.Object, "edge_deform"):
                raise AssertionError("add-on lost")
            print("PASS %s (handle error %.1e)" % (scene["name"], err))
            passed += 1
        except Exception:
            traceback.print_exc()
            print("FAIL %s" % scene["name"])
            failed += 1
    print("%d passed, %d failed" % (passed, failed))
    if failed:
        sys.exit(1)


main()
