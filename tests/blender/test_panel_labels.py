"""Background test: every label of the Edge Deform sidebar reads in full at the default
sidebar width (229 px) and dragged narrower (170 px), as docs/addon.md promises. The
panels draw into a layout that keeps their rows and columns; each text is
measured with the UI's font (blf, the widget size at this UI scale) against the room the
layout gives it.

The room follows the sidebar's geometry measured on the panel screenshots
(tests/blender/shoot_panel.py, Blender 3.4.1): panel content = sidebar width - 54 px; an
icon takes 26 px before its text; a row shares its width among its items, an icon-only
button taking 26 px; the handle list leaves 40 px to its side buttons. At 229 px the
walk-through found "Add a handl…de, select, +", "Live Deform…, Esc cancels",
"Handle → Handle…" and "EdgeDeform_St…"; at 170 px "Controll…", "Tole" and
"Deform on Fra…": this model flags each of them on the old panel (before commit a515a04).
It holds on Blender 4.3.2 (Debian 13) too, whose UI font is wider: it said "Shape Key" in
the Solver panel's Output row had 54 px for 55 px of text at 170 px, and a window under
Xvfb (UI scale 1.04) showed "Shape K…" at 176 px and the full text at 185 px.
Group-name fields are checked at the default width only (a value may shorten, in
Blender's usual way, in a narrow sidebar; a label may not). The handle list's names are
checked at both widths: the list is the only place the handles are listed (at 170 px the
walk-through found "Handle" and "Handle.001" both cut to "Ha…").
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blf  # noqa: E402
from helpers import add_group, bpy, edge_deform, plane_with_end_groups, run  # noqa: E402

CONTENT = 54      # sidebar width - panel content width
ICON = 26         # an icon before a label's text (a button's: 21)
ICON_IN_BUTTON = 21
ICON_BUTTON = 26  # a button with an icon only, with the gap before it
PAD = 6           # text padding of a label (a button's: 4)
BUTTON_PAD = 4
LIST_SIDE = 40    # the handle list's column of buttons and its frame
LIST_FRAME = 14   # the handle list's frame alone (its buttons under it)
NUMBER_SIDES = 40 # a number field's arrows and the gap between its label and value


FONT = []


def ui_font():
    """The UI font, loaded (background mode loads no font): DejaVu Sans in Blender 3.x,
    Inter in 4.x. Inter is wider: "Deform on Frame Change" at 11 px measures 127 px in
    DejaVu Sans (3.4.1) and 136 px in Inter (4.3.2)."""
    if not FONT:
        fonts = bpy.utils.system_resource('DATAFILES', path="fonts")
        paths = [os.path.join(fonts, name) for name in ("DejaVuSans.woff2", "Inter.woff2")]
        FONT.append(next((blf.load(p) for p in paths if os.path.isfile(p)), 0))
    return FONT[0]


def text_width(text):
    # (Background mode reports a UI scale of 0: the default, 1, is what the model measured.)
    font, scale = ui_font(), bpy.context.preferences.system.ui_scale or 1.0
    try:
        blf.size(font, 11 * scale)
    except TypeError:
        blf.size(font, 11 * scale, 72)
    width = blf.dimensions(font, text)[0]
    assert width > 0 or not text, "no font to measure with (%r, %r, %r)" % (font, text, scale)
    return width


class Item:
    def __init__(self, kind, text, icon=False, check=True):
        self.kind, self.text, self.icon, self.check = kind, text, icon, check


class Layout:
    """Records the panel's items in rows and columns; room() gives each its width."""

    def __init__(self, horizontal=False):
        self.horizontal, self.items = horizontal, []
        self.active = self.enabled = True
        self.scale_y = 1.0

    def row(self, **_):
        child = Layout(True)
        self.items.append(child)
        return child

    def column(self, **_):
        child = Layout(False)
        self.items.append(child)
        return child

    box = column

    def separator(self, **_):
        pass

    def context_pointer_set(self, *_):
        pass

    def label(self, text="", icon='NONE', **_):
        self.items.append(Item("label", text, icon != 'NONE'))

    def operator(self, idname, text=None, icon='NONE', **_):
        if text is None:
            category, name = idname.split(".")
            text = getattr(getattr(bpy.ops, category), name).get_rna_type().name
        self.items.append(Item("button", text, icon != 'NONE'))

        class Props:
            pass
        return Props()

    def prop(self, data, name, text=None, icon='NONE', expand=False, **_):
        prop = data.bl_rna.properties[name]
        if expand and prop.type == 'ENUM':   # side by side in a row, stacked in a column
            row = self.row() if self.horizontal else self.column()
            for item in prop.enum_items:
                row.items.append(Item("button", item.name))
            return
        label = prop.name if text is None else text
        if prop.type == 'BOOLEAN':
            self.items.append(Item("label", label, True))
        elif prop.type in ('INT', 'FLOAT') and label:
            value = ("%d" % getattr(data, name) if prop.type == 'INT'
                     else "%.*f" % (prop.precision, getattr(data, name)))
            self.items.append(Item("field", "%s  %s" % (label, value)))
        elif prop.type == 'ENUM' and not label:
            self.items.append(Item("field", dict((i.identifier, i.name)
                                                 for i in prop.enum_items)
                                   .get(getattr(data, name), ""), True))
        elif label:
            self.items.append(Item("label", label))

    def prop_search(self, data, name, *_args, text=None, **_):
        value = getattr(data, name)
        # A group's name in its field: an icon before it, the clear button after it.
        self.items.append(Item("value", value, True) if value else Item("value", ""))
        if text:
            self.items.append(Item("label", text))

    def template_list(self, list_type, _id, data, prop, active_data, active_prop, **_):
        self.items.append(("list", getattr(bpy.types, list_type), data, prop))

    def room(self, width, out, values, in_list=False):
        """(text, room, kind) for every text, in a layout `width` pixels wide. In the
        handle list the texts are names (values)."""
        lists = [i for i in self.items if isinstance(i, tuple)]
        beside = self.horizontal and len(self.items) > 1
        if lists:   # the list beside its column of icon buttons, or with them under it
            _, ui_list, data, prop = lists[0]
            for entry in getattr(data, prop):
                row = Layout(True)
                ui_list.draw_item(ui_list, bpy.context, row, data, entry, 0, data, prop)
                row.room(width - (LIST_SIDE if beside else LIST_FRAME), out, values,
                         in_list=True)
            if beside:
                return
        items = [i for i in self.items if not isinstance(i, tuple)]
        if self.horizontal:
            fixed = [i for i in items if isinstance(i, Item) and not i.text]
            share = (width - ICON_BUTTON * len(fixed)) / max(1, len(items) - len(fixed))
        else:
            share = width
        for item in items:
            if isinstance(item, Layout):
                item.room(share, out, values, in_list)
            elif item.text:
                if item.kind == "button":
                    room = share - BUTTON_PAD - (ICON_IN_BUTTON if item.icon else 0)
                elif item.kind == "field":
                    room = share - NUMBER_SIDES
                else:
                    room = share - PAD - (ICON if item.icon else 0)
                if in_list:   # (names in the list: checked at every width)
                    out.append((item.text, room, "value"))
                elif item.kind == "value":
                    room -= ICON_BUTTON          # the field's clear button
                    if values:
                        out.append((item.text, room, item.kind))
                else:
                    out.append((item.text, room, item.kind))


def panels():
    from edge_deform import ui
    return [ui.EDGE_DEFORM_PT_main, ui.EDGE_DEFORM_PT_handles, ui.EDGE_DEFORM_PT_groups,
            ui.EDGE_DEFORM_PT_stiffness, ui.EDGE_DEFORM_PT_solver, ui.EDGE_DEFORM_PT_animation]


def cut_labels(sidebar_width, values):
    from edge_deform import ui
    ui.narrow = lambda context: sidebar_width < 200   # (no region in background mode)
    cut = []
    for panel in panels():
        layout = Layout()
        panel.draw(type("P", (), {"layout": layout})(), bpy.context)
        out = []
        layout.room(sidebar_width - CONTENT, out, values)
        cut += ["%s: %r (%.0f px in %.0f)" % (panel.__name__, text, text_width(text), room)
                for text, room, _ in out if text_width(text) > room]
    return cut


def scene_states():
    """The panel in the states the walk-through saw: no handles; a bound plane with a
    painted group made by the add-on; a running Live; a controller active."""
    from edge_deform import modal, operators_groups
    ob, ctrl, handle, static = plane_with_end_groups()
    s = ob.edge_deform
    saved = list(s.handles)
    yield "with handles"
    add_group(ob, operators_groups.STIFFNESS_DEFAULT, range(len(ob.data.vertices)), 0.5)
    s.stiffness_group = operators_groups.STIFFNESS_DEFAULT
    h = s.handles[0]
    h.vertex_group = "Handle"       # the names Add Handle gives
    ctrl.name = "Handle_Controller"
    add_group(ob, "Handle", handle)
    second = s.handles.add()
    second.vertex_group, second.controller = "Handle.001", ctrl
    add_group(ob, "Handle.001", static)
    yield "painted, Add Handle's names"

    class Running:
        bl_label = "Live Deform"
        object_name = ob.name_full
    modal._running[0] = Running()
    try:
        yield "Live running"
    finally:
        modal._running.pop(0)
    bpy.context.view_layer.objects.active = ctrl
    yield "a controller active"
    bpy.context.view_layer.objects.active = ob
    s.handles.clear()
    yield "no handles"
    del saved


def test_labels_read_in_full():
    found = []
    for state in scene_states():
        for width, values in ((229, True), (170, False)):
            found += ["%s at %d px: %s" % (state, width, c) for c in cut_labels(width, values)]
    assert not found, "cut off:\n  " + "\n  ".join(found)


def test_the_model_sees_a_long_label():
    """The measurement can fail: a long text in the main panel is cut at 170 px."""
    layout = Layout()
    layout.label(text="Deform on Frame Change, every frame", icon='INFO')
    out = []
    layout.room(170 - CONTENT, out, False)
    [(text, room, _)] = out
    assert text_width(text) > room


if __name__ == "__main__":
    run([test_the_model_sees_a_long_label, test_labels_read_in_full])
