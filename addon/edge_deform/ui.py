"""The "Edge Deform" tab in the 3D Viewport sidebar."""

import bpy

from . import operators_bake


class EDGE_DEFORM_UL_handles(bpy.types.UIList):
    def draw_item(self, context, layout, data, item, icon, active_data, active_prop):
        ob = data.id_data
        row = layout.row(align=True)
        row.prop_search(item, "vertex_group", ob, "vertex_groups", text="", icon='GROUP_VERTEX')
        row.prop(item, "controller", text="", icon='EMPTY_AXIS')


class EDGE_DEFORM_OT_select_controller(bpy.types.Operator):
    """Select the active handle's controller (to move it with G/R/S or its gizmo)"""
    bl_idname = "edge_deform.select_controller"
    bl_label = "Select Controller"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return ob is not None and ob.type == 'MESH' and len(ob.edge_deform.handles) > 0

    def execute(self, context):
        ob = context.active_object
        s = ob.edge_deform
        controller = s.handles[min(s.active_handle, len(s.handles) - 1)].controller
        if controller is None:
            self.report({'ERROR'}, "This handle has no controller")
            return {'CANCELLED'}
        controller.select_set(True)
        return {'FINISHED'}


class EDGE_DEFORM_PT_main(bpy.types.Panel):
    bl_label = "Edge Deform"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Edge Deform"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == 'MESH'

    def draw(self, context):
        layout = self.layout
        ob = context.active_object
        s = ob.edge_deform
        edit = ob.mode == 'EDIT'

        box = layout.box()
        box.label(text="Handles", icon='EMPTY_AXIS')
        row = box.row()
        row.template_list("EDGE_DEFORM_UL_handles", "", s, "handles", s, "active_handle",
                          rows=2)
        col = row.column(align=True)
        col.operator("edge_deform.add_handle", text="", icon='ADD')
        col.operator("edge_deform.remove_handle", text="", icon='REMOVE')
        col.operator("edge_deform.select_controller", text="", icon='RESTRICT_SELECT_OFF')

        box = layout.box()
        box.label(text="Groups", icon='GROUP_VERTEX')
        for field, op in (("static_group", "edge_deform.set_static"),
                          ("roi_group", "edge_deform.set_roi")):
            row = box.row(align=True)
            row.prop_search(s, field, ob, "vertex_groups")
            row.operator(op, text="", icon='ADD')

        box = layout.box()
        box.label(text="Stiffness (λ: 1 rigid, 0 smooth)", icon='MOD_PHYSICS')
        box.prop(s, "stiffness", slider=True)
        row = box.row(align=True)
        row.prop_search(s, "stiffness_group", ob, "vertex_groups", text="Group")
        row.operator("edge_deform.paint_stiffness", text="", icon='BRUSH_DATA')
        row = box.row(align=True)
        row.enabled = ob.mode in {'EDIT', 'WEIGHT_PAINT'}
        for preset in ("SOFT", "MEDIUM", "RIGID"):
            row.operator("edge_deform.assign_stiffness", text=preset.title()).preset = preset
        op = box.operator("edge_deform.assign_stiffness", text="Assign λ to Selection")
        op.preset, op.value = 'VALUE', s.stiffness

        box = layout.box()
        box.label(text="Solver", icon='SETTINGS')
        box.prop(s, "domain", expand=True)
        if s.domain == 'PRIMAL' and not s.stiffness_group and s.stiffness < 0.1:
            # Measured: the primal graph with lambda ~ 0 can drift and inflate (docs/benchmarks.md).
            box.label(text="Primal with λ near 0 may inflate: use Edge Graph or λ ≥ 0.1",
                      icon='ERROR')
        row = box.row(align=True)
        row.prop(s, "iterations")
        row.prop(s, "tolerance")
        box.prop(s, "output", expand=True)
        if s.output == 'SHAPE_KEY':
            box.prop(s, "shape_key_name")

        col = layout.column(align=True)
        col.scale_y = 1.2
        if edit:
            col.operator("edge_deform.grab", icon='VIEW_PAN')
        else:
            col.operator("edge_deform.live", icon='PLAY')
        row = col.row(align=True)
        row.operator("edge_deform.bind")
        row.operator("edge_deform.solve")
        row = col.row(align=True)
        row.operator("edge_deform.apply")
        row.operator("edge_deform.unbind")

        box = layout.box()
        box.label(text="Animation", icon='ANIM')
        box.prop(s, "animate")
        problem = operators_bake.frame_problem(ob) if s.animate else None
        if problem:
            box.label(text=problem, icon='ERROR')
        box.operator("edge_deform.bake")


CLASSES = (EDGE_DEFORM_UL_handles, EDGE_DEFORM_OT_select_controller, EDGE_DEFORM_PT_main)
