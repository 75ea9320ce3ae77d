"""The "Edge Deform" tab in the 3D Viewport sidebar: a main panel with the actions and
collapsible sub-panels (Handles, Groups, Stiffness, Solver, Animation), like Blender's own
tools, and the menu entries (at the end). Labels sit above fields whose values are long
(vertex group names), so everything stays readable at the default sidebar width.

The panel also shows while a controller of a deformed mesh is active (the artist picked it
in the viewport or the Outliner to move it): it then works on that mesh, and its buttons
get the mesh as their `active_object` (layout.context_pointer_set).
"""

import bpy

from . import compat, lifecycle, modal, op_common, operators_bind


# (Kept here too: the panel and its tests speak of it.)
deformed_object = op_common.deformed_object


def target(layout, context):
    """The deformed mesh; the layout's operators act on it (even from a controller)."""
    ob = deformed_object(context)
    layout.context_pointer_set("active_object", ob)
    layout.context_pointer_set("object", ob)
    return ob


def drawn_for(panel, context):
    """(the panel's layout, the mesh it works on, the mesh's settings); see target()."""
    ob = target(panel.layout, context)
    return panel.layout, ob, ob.edge_deform


def narrow(context):
    """Is the sidebar narrower than its default (about 230 px at 100 % scale)? Rows of
    three buttons stack then."""
    region = context.region
    return region is not None and region.width < 200 * context.preferences.system.ui_scale


def group_field(layout, label, operator, icon, ob, field):
    """A vertex group setting: its label with the operator that fills it beside it (the
    group's name gets the whole row below)."""
    row = layout.row()
    row.label(text=label)
    row.operator(operator, text="", icon=icon)
    layout.prop_search(ob.edge_deform, field, ob, "vertex_groups", text="")


class _Panel:
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Edge Deform"

    @classmethod
    def poll(cls, context):
        return deformed_object(context) is not None


class EDGE_DEFORM_UL_handles(bpy.types.UIList):
    """Handle rows: the vertex group's name and its controller's, as plain text (fields
    would shrink to a letter each); the active handle's fields are edited below the list."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_prop):
        # The group's name, and an icon for its controller (its name is in the field
        # below the list): "group → controller" was cut at the default sidebar width.
        # In a narrow sidebar the name gets the whole row (with two icons and the list's
        # buttons beside it, "Handle" and "Handle.001" were both cut to "Ha…" at 170 px):
        # an icon only for a missing controller.
        name = item.vertex_group or "(no group)"
        if narrow(context):
            layout.label(text=name, icon='NONE' if item.controller else 'ERROR')
            return
        row = layout.row(align=True)
        row.label(text=name, icon='GROUP_VERTEX')
        row.label(text="", icon='EMPTY_AXIS' if item.controller else 'ERROR')


class EDGE_DEFORM_PT_main(_Panel, bpy.types.Panel):
    bl_label = "Edge Deform"

    def draw_header(self, context):
        ob = deformed_object(context)
        if ob is not None and operators_bind.frame_problem(ob):
            self.layout.label(text="", icon='ERROR')

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        bound = lifecycle.is_bound(ob.data)
        active = context.active_object
        if active != ob:   # (short labels: each reads in full in a 170 px sidebar)
            layout.label(text="Controller of")
            row = layout.row()
            row.label(text=ob.name, icon='OUTLINER_OB_MESH')
            row.operator("edge_deform.select_mesh", text="", icon='RESTRICT_SELECT_OFF')

        running = modal.running_tool(ob)
        if running:
            col = layout.column(align=True)
            col.label(text="%s on" % running.bl_label, icon='REC')
            col.label(text="Enter keeps")
            col.label(text="Esc cancels")
        elif not s.handles:
            col = layout.column(align=True)
            col.label(text="No handles yet", icon='INFO')
            col.label(text="Edit Mode: select")
            col.label(text="vertices, then +")
        elif bound:
            layout.label(text="Bound", icon='LINKED')   # (the graph: Solver sub-panel)
        else:
            layout.label(text="Not bound", icon='UNLINKED')

        col = layout.column(align=True)
        col.scale_y = 1.3
        if ob.mode == 'EDIT':
            col.operator("edge_deform.grab", icon='VIEW_PAN')
        else:
            col.operator("edge_deform.live", icon='PLAY')
        col = layout.column(align=True)
        # Bind and Unbind swap, as in Laplacian Deform: one of them at a time, on a row of
        # its own ("Unbind" beside "Solve" was cut to "Unb…" in a narrow sidebar).
        if bound:
            col.operator("edge_deform.unbind", icon='UNLINKED')
        else:
            col.operator("edge_deform.bind", icon='LINKED')
        row = col.row(align=True)
        row.operator("edge_deform.solve", icon='FILE_REFRESH')
        row.operator("edge_deform.apply", icon='CHECKMARK')
        problem = operators_bind.frame_problem(ob) if s.animate else None
        if problem:
            layout.label(text=problem, icon='ERROR')


class _SubPanel(_Panel):
    bl_parent_id = "EDGE_DEFORM_PT_main"


class EDGE_DEFORM_PT_handles(_SubPanel, bpy.types.Panel):
    bl_label = "Handles"

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        # The list's buttons beside it, or under it in a narrow sidebar (the list is the
        # only place the handles' names are listed: it gets the whole width there).
        if narrow(context):
            layout.template_list("EDGE_DEFORM_UL_handles", "", s, "handles", s,
                                 "active_handle", rows=3)
            buttons = layout.row(align=True)
        else:
            row = layout.row()
            row.template_list("EDGE_DEFORM_UL_handles", "", s, "handles", s,
                              "active_handle", rows=3)
            buttons = row.column(align=True)
        buttons.operator("edge_deform.add_handle", text="", icon='ADD')
        buttons.operator("edge_deform.remove_handle", text="", icon='REMOVE')
        buttons.separator()
        buttons.operator("edge_deform.select_controller", text="", icon='RESTRICT_SELECT_OFF')
        if s.handles:
            item = s.handles[min(s.active_handle, len(s.handles) - 1)]
            col = layout.column()
            col.label(text="Vertex Group")
            col.prop_search(item, "vertex_group", ob, "vertex_groups", text="")
            col.label(text="Controller")
            col.prop(item, "controller", text="")


class EDGE_DEFORM_PT_groups(_SubPanel, bpy.types.Panel):
    bl_label = "Static and Region"

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        for field, op, label in (("static_group", "edge_deform.set_static", "Static"),
                                 ("roi_group", "edge_deform.set_roi", "Region")):
            # The button beside the label: the group's name gets the whole row. (An
            # empty Region is the whole mesh; "Region (optional)" was cut at 170 px.)
            col = layout.column()
            # Proportional picks the region while on: the Region group is not read.
            col.active = field != "roi_group" or not s.proportional
            group_field(col, label, op, 'ADD', ob, field)
        layout.prop(s, "proportional")
        col = layout.column()
        col.active = s.proportional
        col.prop(s, "proportional_radius")
        # "Connected Only" (its tooltip's name) was cut off at 170 px by Blender 4.3's font.
        col.prop(s, "proportional_connected", text="Connected")


class EDGE_DEFORM_PT_stiffness(_SubPanel, bpy.types.Panel):
    bl_label = "Stiffness"

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        row = layout.row()
        row.active = not s.stiffness_group   # a group overrides the global value
        row.prop(s, "stiffness", slider=True, text="λ")
        # (The sub-panel says it is stiffness.)
        group_field(layout, "Painted Group", "edge_deform.paint_stiffness", 'BRUSH_DATA', ob,
                    "stiffness_group")
        if s.stiffness_group:
            layout.label(text="Group sets λ", icon='INFO')
        # Side by side, or stacked in a narrow sidebar (else cut to "Med…" and "Rig…").
        row = layout.column(align=True) if narrow(context) else layout.row(align=True)
        row.enabled = ob.mode in {'EDIT', 'WEIGHT_PAINT'}
        for preset in ("SOFT", "MEDIUM", "RIGID"):
            row.operator("edge_deform.assign_stiffness", text=preset.title()).preset = preset
        # What the weight colours mean (Weight Paint: red = weight 1, blue = 0). Two short
        # items: three were cut to "Ri…" in a narrow sidebar.
        legend = layout.column(align=True) if narrow(context) else layout.row(align=True)
        legend.scale_y = 0.8
        legend.label(text="Rigid 1", icon=compat.icon('STRIP_COLOR_01', 'SEQUENCE_COLOR_01'))
        legend.label(text="Soft 0", icon=compat.icon('STRIP_COLOR_05', 'SEQUENCE_COLOR_05'))


class EDGE_DEFORM_PT_solver(_SubPanel, bpy.types.Panel):
    bl_label = "Solver"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        # Side by side, or stacked in a narrow sidebar (else cut to "Vertex Gr…").
        (layout.column() if narrow(context) else layout.row()).prop(s, "domain", expand=True)
        if s.domain == 'PRIMAL' and not s.stiffness_group and s.stiffness < 0.1:
            # Measured: the primal graph with lambda ~ 0 can drift and inflate (docs/benchmarks.md).
            col = layout.column(align=True)
            col.label(text="Vertex graph with λ near 0", icon='ERROR')
            col.label(text="may inflate: use Edge Graph")
        # Labels above their fields: "Tolerance" was cut to "Tole" in a narrow sidebar.
        for name in ("iterations", "tolerance", "acceleration"):
            layout.label(text=s.bl_rna.properties[name].name)
            layout.prop(s, name, text="")
        layout.label(text="Output")
        # Side by side, or stacked in a narrow sidebar: Blender 4.3's UI font (Inter) cut
        # "Shape Key" to "Shape K…" at 176 px (Debian 13, ui_scale 1.04; 3.4's DejaVu fits).
        (layout.column() if narrow(context) else layout.row()).prop(s, "output", expand=True)
        if s.output == 'SHAPE_KEY':
            layout.prop(s, "shape_key_name", text="Key")


class EDGE_DEFORM_PT_animation(_SubPanel, bpy.types.Panel):
    bl_label = "Animation"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout, ob, s = drawn_for(self, context)
        layout.prop(s, "animate", text="Every Frame")   # (the full name: the tooltip)
        problem = operators_bind.frame_problem(ob) if s.animate else None
        if problem:
            layout.label(text=problem, icon='ERROR')
        layout.operator("edge_deform.bake", icon='REC')


# ------------------------------------------------------------------ menu entries
# Menu entries where artists look for a deform tool (and where F3 search finds them):
# Object > Edge Deform, Edit Mode's Vertex menu and Weight Paint's Weights menu.

class EDGE_DEFORM_MT_object(bpy.types.Menu):
    bl_label = "Edge Deform"
    bl_idname = "EDGE_DEFORM_MT_object"

    def draw(self, context):
        layout = self.layout
        layout.operator("edge_deform.bind", icon='LINKED')
        layout.operator("edge_deform.live", icon='PLAY')
        layout.operator("edge_deform.solve", icon='FILE_REFRESH')
        layout.operator("edge_deform.apply", icon='CHECKMARK')
        layout.operator("edge_deform.bake", icon='REC')
        layout.separator()
        layout.operator("edge_deform.unbind", icon='UNLINKED')


def _object_menu(self, context):
    self.layout.separator()
    self.layout.menu(EDGE_DEFORM_MT_object.bl_idname)


def _edit_vertex_menu(self, context):
    layout = self.layout
    layout.separator()
    layout.operator("edge_deform.grab", text="Grab Deform", icon='VIEW_PAN')
    layout.operator("edge_deform.add_handle", text="Add Edge Deform Handle")
    layout.operator("edge_deform.set_static", text="Set Edge Deform Static")
    layout.operator("edge_deform.set_roi", text="Set Edge Deform Region")
    layout.operator_menu_enum("edge_deform.assign_stiffness", "preset",
                              text="Assign Edge Deform Stiffness")


def _weight_menu(self, context):
    layout = self.layout
    layout.separator()
    layout.operator_menu_enum("edge_deform.assign_stiffness", "preset",
                              text="Assign Edge Deform Stiffness")


# (menu class name, draw function): appended on register, removed on unregister.
ENTRIES = (("VIEW3D_MT_object", _object_menu),
           ("VIEW3D_MT_edit_mesh_vertices", _edit_vertex_menu),
           ("VIEW3D_MT_paint_weight", _weight_menu))


def register_menus():
    for menu, draw in ENTRIES:
        getattr(bpy.types, menu).append(draw)


def unregister_menus():
    for menu, draw in ENTRIES:
        getattr(bpy.types, menu).remove(draw)


CLASSES = (EDGE_DEFORM_UL_handles, EDGE_DEFORM_PT_main, EDGE_DEFORM_PT_handles,
           EDGE_DEFORM_PT_groups, EDGE_DEFORM_PT_stiffness, EDGE_DEFORM_PT_solver,
           EDGE_DEFORM_PT_animation, EDGE_DEFORM_MT_object,)
