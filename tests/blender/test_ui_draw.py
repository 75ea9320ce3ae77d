"""Background test of the add-on's UI code against this Blender's API.

The `bpy` module (4.5, 5.0) has no window, so panels are never drawn there. Here every
Panel and UIList of the add-on draws into a recording layout that checks each call against
this Blender's RNA: the layout method and its keyword arguments exist, icons are valid
names, `prop` names a real property, `operator` a registered operator whose properties are
the ones set. A renamed icon or removed argument in a new Blender fails here, not in the
user's sidebar.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (add_group, add_handle, bpy, edge_deform, load, make_object,  # noqa: E402
                     np, run)

LAYOUT = bpy.types.UILayout.bl_rna
ICONS = set(LAYOUT.functions["label"].parameters["icon"].enum_items.keys())


class OperatorStub:
    """What `layout.operator()` returns: only the operator's own properties may be set."""

    def __init__(self, idname):
        category, name = idname.split(".")
        op = getattr(getattr(bpy.ops, category), name)
        object.__setattr__(self, "_props", set(op.get_rna_type().properties.keys()))
        object.__setattr__(self, "_idname", idname)

    def __setattr__(self, key, value):
        assert key in self._props, "%s has no property %r" % (self._idname, key)


class RecordingLayout:
    def __init__(self, calls):
        object.__setattr__(self, "_calls", calls)

    def __setattr__(self, key, value):
        assert key in LAYOUT.properties, "UILayout has no attribute %r" % key

    def __getattr__(self, name):
        assert name in LAYOUT.functions, "UILayout has no method %r" % name
        params = LAYOUT.functions[name].parameters

        def call(*args, **kw):
            for key, value in kw.items():
                assert key in params, "UILayout.%s has no argument %r" % (name, key)
            if "icon" in kw:
                assert kw["icon"] in ICONS, "unknown icon %r" % kw["icon"]
            self._calls.append(name)
            if name in ("prop", "prop_search", "props_enum", "prop_enum", "prop_menu_enum"):
                data, prop = args[0], args[1]
                assert prop in data.bl_rna.properties, "%s has no property %r" % (data, prop)
            if name == "prop_search":
                assert args[3] in args[2].bl_rna.properties, args[3]
            if name == "template_list":
                assert hasattr(bpy.types, args[0]), "UIList %s is not registered" % args[0]
                for data, prop in ((args[2], args[3]), (args[4], args[5])):
                    assert prop in data.bl_rna.properties, prop
            if name == "operator":
                return OperatorStub(args[0] if args else kw["operator"])
            return RecordingLayout(self._calls)
        return call


def addon_classes(base):
    prefix = edge_deform.__name__
    return [c for c in base.__subclasses__() if c.__module__.startswith(prefix)]


def draw_everything(context):
    calls = []
    panels = addon_classes(bpy.types.Panel)
    assert panels, "the add-on registers no panel"
    for panel in panels:
        if hasattr(panel, "poll") and not panel.poll(context):
            continue
        stub = type("PanelStub", (), {"layout": RecordingLayout(calls)})()
        for method in ("draw_header", "draw"):
            if hasattr(panel, method):
                getattr(panel, method)(stub, context)
    for ui_list in addon_classes(bpy.types.UIList):
        from edge_deform import ui
        ob = ui.deformed_object(context)
        for item in ob.edge_deform.handles:
            ui_list.draw_item(ui_list, context, RecordingLayout(calls), ob.edge_deform, item,
                              0, ob.edge_deform, "active_handle")
    return calls


def test_panels_draw_with_this_blenders_api():
    V, F = load("cgal_plane.off")
    ob = make_object("plane", V, F)
    x = V[:, 0]
    add_group(ob, "H", np.flatnonzero(x > x.max() - 0.1 * np.ptp(x)))
    add_group(ob, "S", np.flatnonzero(x < x.min() + 0.1 * np.ptp(x)))
    ob.edge_deform.static_group = "S"
    context = bpy.context
    seen = set()
    # Several states, so that the panels' branches draw: no handle, a handle, bound and
    # solved, the other output and domain.
    seen.update(draw_everything(context))
    ctrl = add_handle(ob, "H")
    seen.update(draw_everything(context))
    # A controller active (picked to move it): the panels draw for its mesh.
    bpy.context.view_layer.objects.active = ctrl
    calls = draw_everything(context)
    assert "template_list" in calls, "the panels must draw for a controller"
    seen.update(calls)
    bpy.context.view_layer.objects.active = ob
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    ob.edge_deform.output, ob.edge_deform.domain = 'MESH', 'PRIMAL'
    seen.update(draw_everything(context))
    assert {"prop", "operator", "label"} <= seen, seen
    print("  layout calls checked:", ", ".join(sorted(seen)))


if __name__ == "__main__":
    run([test_panels_draw_with_this_blenders_api])
