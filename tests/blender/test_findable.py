"""Background test of what makes the add-on findable and predictable:
menu entries where artists look, descriptions on every operator and property, Set Static
taking vertices out of handles, the stiffness buttons following Weight Paint's masks like
Set Weight, and the panel following a controller of a deformed mesh."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (bpy, clear_edge_face_selection, edge_deform, load,  # noqa: E402
                     make_object, np, plane_with_end_groups, run)


class MenuRecorder:
    """Records the operators (and enum menus) a menu's draw function adds."""

    def __init__(self):
        self.operators = []
        self.menus = []

    def operator(self, idname, **kw):
        self.operators.append(idname)
        return type("Props", (), {})()

    def operator_menu_enum(self, idname, prop, **kw):
        self.operators.append(idname)

    def menu(self, idname, **kw):
        self.menus.append(idname)

    def separator(self, **kw):
        pass


def draw_appended(menu_name):
    """What the add-on's draw functions append to one of Blender's menus."""
    from edge_deform import ui
    rec = MenuRecorder()
    holder = type("MenuStub", (), {"layout": rec})()
    for name, draw in ui.ENTRIES:
        if name == menu_name:
            assert draw in getattr(bpy.types, name)._dyn_ui_initialize(), \
                "%s is not appended to %s" % (draw.__name__, name)
            draw(holder, bpy.context)
    return rec


def test_menus_hold_the_operators():
    rec = draw_appended("VIEW3D_MT_object")
    assert rec.menus == ["EDGE_DEFORM_MT_object"], rec.menus
    sub = MenuRecorder()
    bpy.types.EDGE_DEFORM_MT_object.draw(type("M", (), {"layout": sub})(), bpy.context)
    for op in ("bind", "live", "solve", "apply", "bake"):
        assert "edge_deform." + op in sub.operators, (op, sub.operators)
    rec = draw_appended("VIEW3D_MT_edit_mesh_vertices")
    # Grab Deform and Set Region too (they were in no menu once, so F3 missed them).
    assert rec.operators == ["edge_deform.grab", "edge_deform.add_handle",
                             "edge_deform.set_static", "edge_deform.set_roi",
                             "edge_deform.assign_stiffness"], rec.operators
    rec = draw_appended("VIEW3D_MT_paint_weight")
    assert rec.operators == ["edge_deform.assign_stiffness"], rec.operators


JARGON = ("paper", "local/global", "factor", "laplacian", "arap", "primal")


def addon_operators():
    return [c for c in bpy.types.Operator.__subclasses__()
            if c.__module__.startswith(edge_deform.__name__)]


def test_every_operator_and_property_is_described():
    ops = addon_operators()
    assert len(ops) >= 15, [c.bl_idname for c in ops]
    missing = []
    for cls in ops:
        category, name = cls.bl_idname.split(".")
        rna = getattr(getattr(bpy.ops, category), name).get_rna_type()
        if not rna.description.strip():
            missing.append(cls.bl_idname)
        text = rna.description.lower()
        assert not any(w in text for w in JARGON), (cls.bl_idname, rna.description)
        for prop in rna.properties:
            if prop.identifier != "rna_type" and not prop.description.strip():
                missing.append("%s.%s" % (cls.bl_idname, prop.identifier))
    from edge_deform import properties
    for group in ("EdgeDeformSettings", "EdgeDeformHandle"):
        for prop in getattr(properties, group).bl_rna.properties:
            if prop.identifier in ("rna_type", "name"):
                continue
            if not prop.description.strip():
                missing.append("%s.%s" % (group, prop.identifier))
            text = prop.description.lower()
            assert not any(w in text for w in JARGON), (prop.identifier, prop.description)
            for item in getattr(prop, "enum_items", ()):
                assert item.description and not any(w in item.description.lower()
                                                     for w in JARGON), item.identifier
    assert not missing, "no description: " + ", ".join(missing)


def select(ob, idx):
    sel = np.zeros(len(ob.data.vertices), bool)
    sel[idx] = True
    ob.data.vertices.foreach_set("select", sel)
    clear_edge_face_selection(ob.data)


def members(ob, group):
    vg = ob.vertex_groups[group]
    return {v.index for v in ob.data.vertices if any(g.group == vg.index for g in v.groups)}


def weights(ob, group):
    vg = ob.vertex_groups[group]
    out = np.full(len(ob.data.vertices), -1.0)
    for v in ob.data.vertices:
        for g in v.groups:
            if g.group == vg.index:
                out[v.index] = g.weight
    return out


def test_set_static_takes_vertices_out_of_handles():
    ob, _, handle, static = plane_with_end_groups()
    pinned = handle[: len(handle) // 2]
    select(ob, pinned)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.edge_deform.set_static() == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    assert set(pinned.tolist()) <= members(ob, ob.edge_deform.static_group)
    assert not set(pinned.tolist()) & members(ob, "H"), "still in the handle"
    assert members(ob, "H") == set(handle.tolist()) - set(pinned.tolist())
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}, "no clash left for Bind"


def test_stiffness_buttons_follow_weight_paint_masks():
    V, F = load("cgal_plane.off")
    ob = make_object("plane", V, F)
    n = len(V)
    left = np.flatnonzero(V[:, 0] < np.median(V[:, 0]))
    select(ob, left)   # a selection left over from Edit Mode
    bpy.ops.object.mode_set(mode='WEIGHT_PAINT')
    me = ob.data
    me.use_paint_mask_vertex = False
    me.use_paint_mask = False
    # No mask: the whole mesh, not the invisible selection.
    assert bpy.ops.edge_deform.assign_stiffness(preset='RIGID') == {'FINISHED'}
    w = weights(ob, ob.edge_deform.stiffness_group)
    assert np.all(w == 1.0), "without a mask every vertex gets λ"
    # Vertex mask: only the masked vertices.
    me.use_paint_mask_vertex = True
    assert bpy.ops.edge_deform.assign_stiffness(preset='SOFT') == {'FINISHED'}
    w = weights(ob, ob.edge_deform.stiffness_group)
    assert np.all(w[left] == 0.0) and np.all(np.delete(w, left) == 1.0), \
        "the vertex mask limits the buttons"
    # Face mask: the vertices of the selected faces.
    me.use_paint_mask_vertex = False
    me.use_paint_mask = True
    on = set(me.polygons[0].vertices)   # (read first: 4.x invalidates the reference)
    sel = np.zeros(len(me.polygons), bool)
    sel[0] = True
    me.polygons.foreach_set("select", sel)
    assert bpy.ops.edge_deform.assign_stiffness(preset='MEDIUM') == {'FINISHED'}
    w = weights(ob, ob.edge_deform.stiffness_group)
    assert all(w[i] == 0.5 for i in on)
    assert sum(1 for i in range(n) if w[i] == 0.5) == len(on), "only the masked face"
    bpy.ops.object.mode_set(mode='OBJECT')


def test_panel_follows_a_controller_and_swaps_bind():
    from edge_deform import lifecycle, ui
    ob, ctrl, _, _ = plane_with_end_groups()
    assert ui.deformed_object(bpy.context) == ob
    bpy.context.view_layer.objects.active = ctrl
    assert ui.deformed_object(bpy.context) == ob, "a controller keeps the panel"
    assert ui.EDGE_DEFORM_PT_main.poll(bpy.context)
    other = bpy.data.objects.new("unrelated", None)
    bpy.context.scene.collection.objects.link(other)
    bpy.context.view_layer.objects.active = other
    assert not ui.EDGE_DEFORM_PT_main.poll(bpy.context)
    bpy.context.view_layer.objects.active = ob
    assert not lifecycle.is_bound(ob.data)
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    assert lifecycle.is_bound(ob.data)
    assert bpy.ops.edge_deform.unbind() == {'FINISHED'}
    assert not lifecycle.is_bound(ob.data)
    # Select Controller makes the controller the active object (G then moves it).
    assert bpy.ops.edge_deform.select_controller() == {'FINISHED'}
    assert bpy.context.view_layer.objects.active == ctrl and not ob.select_get()


def doc_file(url):
    """The file a file:// documentation link opens (asserts it is one that exists)."""
    from urllib.parse import urlparse
    from urllib.request import url2pathname
    parts = urlparse(url)
    assert parts.scheme == "file", url
    path = url2pathname(parts.path)
    assert os.path.isfile(path), "the documentation link opens no file: %s" % url
    return path


class _RecordingLayout:
    """Stands in for a UILayout: records the operators a draw() puts on it."""

    def __init__(self):
        self.operators = []

    def row(self, **_):
        return self

    def label(self, **kw):
        self.operators.append(("label", kw.get("text"), None))

    def prop(self, data, name, **_):
        self.props = getattr(self, "props", []) + [name]

    def operator(self, idname, **kw):
        class Props:
            url = None
        props = Props()
        self.operators.append((idname, kw.get("text"), props))
        return props


def test_info_links_the_manual():
    from edge_deform import properties
    path = doc_file(properties.manual_url())
    # The copy installed with the add-on (the 4.2+ suites install the extension), else,
    # from a checkout, its docs/addon.md.
    bundled = os.path.join(os.path.dirname(edge_deform.__file__), "docs", "addon.md")
    checkout = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))), "docs", "addon.md")
    expected = bundled if os.path.isfile(bundled) else checkout
    assert os.path.samefile(path, expected), (path, expected)
    with open(path, encoding="utf-8") as f:
        assert f.readline().startswith("# Edge Deform"), path
    # Preferences > Add-ons > Edge Deform: a Manual button opening it (the only link a
    # 4.2+ extension has: Blender drops its bl_info) ...
    cls = properties.EDGE_DEFORM_AP_preferences
    assert cls.is_registered and cls.bl_idname == edge_deform.__name__
    layout = _RecordingLayout()
    cls.draw(type("Prefs", (), {"layout": layout})(), bpy.context)
    [(idname, text, props)] = layout.operators
    assert idname == "wm.url_open" and text == "Manual", layout.operators
    assert layout.props == ["stiffness_keys"], layout.props   # Live's λ keys
    assert os.path.samefile(doc_file(props.url), path)
    # ... and the legacy add-on's "Documentation" link (bl_info["doc_url"]) the same page.
    info = getattr(edge_deform, "bl_info", None)
    if info is not None:
        assert os.path.samefile(doc_file(info["doc_url"]), path)


if __name__ == "__main__":
    run([test_info_links_the_manual, test_menus_hold_the_operators, test_every_operator_and_property_is_described,
         test_set_static_takes_vertices_out_of_handles,
         test_stiffness_buttons_follow_weight_paint_masks,
         test_panel_follows_a_controller_and_swaps_bind])

