"""Shared setup for the Blender tests: paths, the add-on, real meshes, a tiny runner.

Environment (set by tests/blender/CMakeLists.txt):
  EDGEDEFORM_PYTHONPATH  folder holding the built `edgedeform` package (build/python)
  EDGEDEFORM_ADDON_DIR   folder holding the `edge_deform` add-on package (addon/)
  EDGEDEFORM_TEST_DATA   tests/data
  EDGEDEFORM_TEST_OUT    a writable folder under the build tree (screenshots)
"""

import os
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
for var, default in (("EDGEDEFORM_PYTHONPATH", os.path.join(ROOT, "build", "python")),
                     ("EDGEDEFORM_ADDON_DIR", os.path.join(ROOT, "addon"))):
    path = os.environ.get(var, default)
    if path not in sys.path:
        sys.path.insert(0, path)
DATA = os.environ.get("EDGEDEFORM_TEST_DATA", os.path.join(ROOT, "tests", "data"))
OUT = os.environ.get("EDGEDEFORM_TEST_OUT", os.path.join(ROOT, "build", "tests", "blender"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

import edgedeform as ed  # noqa: E402
import edgedeform.mesh_files  # noqa: E402,F401  (ed.mesh_files)
import edge_deform  # noqa: E402
from edge_deform import engine  # noqa: E402


def register():
    if not hasattr(bpy.types.Object, "edge_deform"):
        edge_deform.register()


# ------------------------------------------------------------------ meshes

def load(name):
    """(V, F) of a mesh in tests/data, read by the package (file vertex order)."""
    return ed.mesh_files.read_mesh(os.path.join(DATA, name))


def make_object(name, V, faces):
    """A mesh object from vertex and face arrays (faces: list of index lists)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(np.asarray(V).tolist(), [], [list(map(int, f)) for f in faces])
    mesh.update()
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    activate(ob)
    return ob


def activate(ob):
    for other in bpy.context.view_layer.objects:
        if other is not None:   # (None right after objects were removed)
            other.select_set(False)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)


def select_only(mesh, idx):
    """Select exactly the vertices `idx` (no edges or faces) in Object Mode data."""
    sel = np.zeros(len(mesh.vertices), bool)
    sel[idx] = True
    mesh.vertices.foreach_set("select", sel)
    clear_edge_face_selection(mesh)   # else Edit Mode flushes them back


def clear_edge_face_selection(mesh):
    """Deselect every edge and face (the vertex selection is the caller's)."""
    stored = [mesh.attributes[n] for n in (".select_edge", ".select_poly")
              if n in getattr(mesh, "attributes", ())]
    if stored:
        # Blender 3.5+ keeps the selection in attributes, and a missing one means "nothing
        # selected". Removing them also avoids a crash of Blender 5.0.1 when writing the
        # edge selection of a mesh made by from_pydata.
        for attribute in stored:
            mesh.attributes.remove(attribute)
        return
    for items in (mesh.edges, mesh.polygons):
        items.foreach_set("select", np.zeros(len(items), bool))


def add_group(ob, name, idx, weight=1.0):
    vg = ob.vertex_groups.get(name) or ob.vertex_groups.new(name=name)
    vg.add(np.asarray(idx).tolist(), weight, 'REPLACE')
    return vg


def add_handle(ob, group, controller_location=(0, 0, 0)):
    """A handle driven by a new Empty (rest = its current transform)."""
    empty = bpy.data.objects.new(group + "_ctrl", None)
    bpy.context.scene.collection.objects.link(empty)
    empty.location = controller_location
    bpy.context.view_layer.update()
    h = ob.edge_deform.handles.add()
    h.vertex_group = group
    h.controller = empty
    h.rest_matrix = empty.matrix_world.copy()
    return empty


def plane_with_end_groups():
    """The test plane with group "H" (the +x tenth) and static group "S" (the -x tenth)
    and a handle on H: (object, controller, handle indices, static indices)."""
    V, F = load("cgal_plane.off")
    ob = make_object("plane", V, F)
    x = V[:, 0]
    handle = np.flatnonzero(x > x.max() - 0.1 * np.ptp(x))
    static = np.flatnonzero(x < x.min() + 0.1 * np.ptp(x))
    add_group(ob, "H", handle)
    add_group(ob, "S", static)
    ob.edge_deform.static_group = "S"
    ctrl = add_handle(ob, "H", V[handle].mean(axis=0))
    return ob, ctrl, handle, static


def positions(mesh):
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def key_positions(ob, name="EdgeDeform"):
    kb = ob.data.shape_keys.key_blocks[name]
    co = np.empty(len(kb.data) * 3, np.float32)
    kb.data.foreach_get("co", co)
    return co.reshape(-1, 3)


def loop_triangles(mesh):
    mesh.calc_loop_triangles()
    t = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("vertices", t)
    return t.reshape(-1, 3)


def transform(M, P):
    M = np.array(M, float)
    return P @ M[:3, :3].T + M[:3, 3]


def reset_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    engine.forget_all()
    bpy.context.scene.frame_set(1)


def expect_error(op, fragment="", **kw):
    """Run an operator that must refuse: in background mode an ERROR report raises."""
    try:
        result = op(**kw)
    except RuntimeError as exc:
        assert fragment.lower() in str(exc).lower(), (fragment, str(exc))
        print("  expected error:", str(exc).strip())
        return str(exc)
    name = op.idname_py() if hasattr(op, "idname_py") else repr(op)
    raise AssertionError("%s returned %s instead of an error" % (name, result))


class Told:
    """Records every message the add-on gives the user (op_common.tell) while active."""

    def __enter__(self):
        from edge_deform import op_common
        self.messages = []
        self._listen = lambda level, text: self.messages.append((level, text))
        op_common.listeners.append(self._listen)
        return self

    def __exit__(self, *exc):
        from edge_deform import op_common
        op_common.listeners.remove(self._listen)
        return False

    def has(self, level, fragment):
        return any(lv == level and fragment.lower() in text.lower()
                   for lv, text in self.messages)


def visible(ob):
    """Positions as the user sees them (shape keys mixed; modifiers off for the count)."""
    bpy.context.view_layer.update()
    shown = [(m, m.show_viewport) for m in ob.modifiers]
    for m, _ in shown:
        m.show_viewport = False
    try:
        ev = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
        me = ev.to_mesh()
        try:
            return positions(me).astype(np.float64)
        finally:
            ev.to_mesh_clear()
    finally:
        for m, state in shown:
            m.show_viewport = state
        bpy.context.view_layer.update()


def key_offsets(ob):
    """{name: key - the key it is relative to} for every non-reference shape key."""
    keys = ob.data.shape_keys
    return {kb.name: key_positions(ob, kb.name).astype(np.float64)
            - key_positions(ob, kb.relative_key.name).astype(np.float64)
            for kb in keys.key_blocks if kb != keys.reference_key}


def mesh_fingerprint(ob):
    """Everything a refused operation must leave bit-identical: vertices, every key's
    positions, value and mute, the stored state, the rest attribute and the settings."""
    me = ob.data
    keys = None if me.shape_keys is None else [
        (kb.name, key_positions(ob, kb.name).tobytes(), kb.value, kb.mute)
        for kb in me.shape_keys.key_blocks]
    st = me.edge_deform_state
    rest = me.attributes.get(".edge_deform_rest")
    rest_bytes = None
    if rest is not None:
        r = np.empty(len(me.vertices) * 3, np.float32)
        rest.data.foreach_get("vector", r)
        rest_bytes = r.tobytes()
    s = ob.edge_deform
    settings = (s.static_group, s.roi_group, s.stiffness_group, s.stiffness, s.domain,
                s.output, s.shape_key_name,
                tuple((h.vertex_group, h.controller.name if h.controller else None,
                       tuple(map(tuple, h.rest_matrix))) for h in s.handles))
    return (positions(me).tobytes(), keys,
            tuple(getattr(st, f) for f in ("output", "output_key", "made_key_datablock",
                                          "topology", "written", "base", "baked_keys")),
            rest_bytes, settings)


def refused(op, fragment, ob):
    """The operator refuses with a message containing `fragment` and changes nothing."""
    before = mesh_fingerprint(ob)
    msg = expect_error(op, fragment)
    assert mesh_fingerprint(ob) == before, "a refused operation changed the data"
    return msg


# ------------------------------------------------------------------ runner

def run(tests):
    """Run each test on a clean scene; fail the Blender process if any fails."""
    register()
    failed = []
    for test in tests:
        reset_scene()
        try:
            test()
            print("PASS", test.__name__)
        except Exception:
            traceback.print_exc()
            print("FAIL", test.__name__)
            failed.append(test.__name__)
    print("%d passed, %d failed" % (len(tests) - len(failed), len(failed)))
    if failed:
        raise SystemExit("failed: " + ", ".join(failed))
