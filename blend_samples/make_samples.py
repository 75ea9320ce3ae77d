"""Build the sample .blend scenes from scenes.json (run inside Blender).

    blender -b --factory-startup --python-exit-code 1 --python blend_samples/make_samples.py \
        -- [--out DIR] [--only NAME ...]

Each scene: the mesh (normalised, vertex order as in the file), one vertex group per handle
("handle_<name>"), "static", "stiffness" (weight = painted λ on every vertex), an Empty
controller per handle already moved to the edit (its rest transform recorded on the handle;
keyed at rest on frame 1 and at the edit on frame 24, where the file opens with the mesh
solved: shape key EdgeDeform; frame 1 when the solver is missing),
the `ob.edge_deform` settings, a camera and Workbench lighting. Settings need the add-on's
properties: it is enabled if installed, else registered from the source tree (addon/).
"""
import argparse
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path[:0] = [HERE, os.path.join(REPO, "demo")]
import regions  # noqa: E402
import render   # noqa: E402

EDIT_FRAME = 24


def import_package_first():
    """Import the top-level `edgedeform` (build/python on PYTHONPATH) before the add-on is
    enabled, so that the add-on uses this copy (edge_deform/compat.py, native_package) instead of loading its
    bundled one: regions.scene_mesh reads the meshes with the top-level package, and a second
    copy of the compiled module cannot load into the same Python (pybind11: 'type
    "SolveResult" is already registered!'). With the add-on installed, as scripts/demo.sh
    step 3 leaves it, the sample step failed so on Debian 12 and 13 alike."""
    try:
        import edgedeform  # noqa: F401
    except ImportError:
        pass   # (then the add-on's copy, if any; a real mesh then fails to load, saying so)


def enable_addon():
    """Make `Object.edge_deform` exist; return how (for the log) or None."""
    if hasattr(bpy.types.Object, "edge_deform"):
        return "already registered"
    import_package_first()
    import addon_utils
    if any(m.__name__ == "edge_deform" for m in addon_utils.modules()):
        if addon_utils.enable("edge_deform", default_set=True) is not None:
            return "installed add-on"
    src = os.path.join(REPO, "addon")
    if os.path.exists(os.path.join(src, "edge_deform", "__init__.py")):
        sys.path.insert(0, src)
        import edge_deform
        edge_deform.register()
        return "source tree " + src
    return None


def add_group(ob, name, index, weight=1.0):
    g = ob.vertex_groups.new(name=name)
    if len(index):
        g.add(np.asarray(index).tolist(), weight, "REPLACE")
    return g


def add_stiffness_group(ob, lam):
    """Every vertex in the group (the add-on reads vertices outside it as λ = 0)."""
    g = ob.vertex_groups.new(name="stiffness")
    for value in np.unique(lam):         # a handful of bulk calls, one per painted value
        g.add(np.flatnonzero(lam == value).tolist(), float(value), "REPLACE")
    return g


def build_scene(scene):
    from mathutils import Matrix
    sc = render.reset_scene(scene["name"])
    V, F = regions.scene_mesh(scene)
    setup = regions.scene_setup(scene, V)
    colours = render.vertex_colours(len(V), setup["handle_index"], setup["static"],
                                    setup["stiffness"])
    ob = render.new_mesh_object(scene["name"], V, F, colours)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    add_group(ob, "static", setup["static"])
    add_stiffness_group(ob, setup["stiffness"])

    have_settings = hasattr(ob, "edge_deform")
    if have_settings:
        s = ob.edge_deform
        s.static_group, s.stiffness_group = "static", "stiffness"
        s.stiffness, s.domain = 0.5, "EDGE"
        # Solve runs until settled (tolerance: distance to the solution, 1e-3 of the diagonal);
        # Live warm-starts and continues the same iteration while the controllers stand still.
        s.iterations, s.tolerance = 500, 1e-3
        s.output = "SHAPE_KEY"
    for h in setup["handles"]:
        add_group(ob, "handle_" + h["name"], h["index"])
        ctrl = bpy.data.objects.new("ctrl_" + h["name"], None)
        ctrl.empty_display_type, ctrl.empty_display_size = "SPHERE", 0.06
        sc.collection.objects.link(ctrl)
        rest = np.eye(4)
        rest[:3, 3] = h["pivot"]
        if have_settings:
            item = s.handles.add()
            item.vertex_group, item.controller = "handle_" + h["name"], ctrl
            item.rest_matrix = Matrix(rest.tolist())   # as the add-on stores it
        # Keyed: rest at frame 1, the edit at EDIT_FRAME (the frame the file opens on), so
        # Bind at frame 1 (which records the rest) and the edit both stay reachable.
        for frame, M in ((1, rest), (EDIT_FRAME, h["matrix"])):
            ctrl.matrix_world = Matrix(M.tolist())
            for path in ("location", "rotation_euler", "scale"):
                ctrl.keyframe_insert(path, frame=frame)

    sc.frame_start, sc.frame_end = 1, EDIT_FRAME
    sc["edge_deform_edit_frame"] = EDIT_FRAME
    sc.frame_set(EDIT_FRAME)
    if have_settings:
        show_edit(ob, sc)
    render.setup_render(sc, 640, 480)
    render.add_camera(sc, np.vstack([V, setup["targets"]]), *scene["view"], aspect=640 / 480)
    sc["edge_deform_title"] = scene["title"]
    return ob, have_settings


def show_edit(ob, sc):
    """The file must open showing what it is about: bind at frame 1 (controllers at rest)
    and solve at the edit frame, so the mesh shows its deformation (shape key EdgeDeform)
    where the controllers are. Without the compiled solver, open at frame 1 instead: the
    mesh at rest and the controllers at rest. Returns the frame the file opens on."""
    from edge_deform import compat
    try:
        compat.native_package()
    except ImportError as exc:
        print("make_samples: %s; %s opens at frame 1 (at rest)" % (exc, ob.name))
        sc.frame_set(1)
        return 1
    bpy.context.view_layer.objects.active = ob
    sc.frame_set(1)
    assert bpy.ops.edge_deform.bind() == {"FINISHED"}
    sc.frame_set(EDIT_FRAME)
    assert bpy.ops.edge_deform.solve() == {"FINISHED"}
    return EDIT_FRAME


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=HERE, help="folder for the .blend files")
    ap.add_argument("--only", nargs="*", help="scene names (default: all)")
    args = ap.parse_args(argv)
    args.out = os.path.abspath(args.out)   # Blender refuses relative save paths
    os.makedirs(args.out, exist_ok=True)
    print("make_samples: add-on settings from", enable_addon() or "nowhere (add-on missing)")
    for scene in regions.load_scenes():
        if args.only and scene["name"] not in args.only:
            continue
        ob, have_settings = build_scene(scene)
        path = os.path.join(args.out, scene["name"] + ".blend")
        bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
        print("make_samples: wrote %s (%d vertices%s)" % (
            path, len(ob.data.vertices),
            "" if have_settings else "; add-on missing: no ob.edge_deform settings"))


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
