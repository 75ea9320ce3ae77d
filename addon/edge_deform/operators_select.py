"""Select Controller and Select Mesh: the panel's buttons that move the selection between a
deformed mesh and the controller of its active handle (ready for G/R/S or its gizmo)."""

import bpy

from .op_common import poll_mesh, tell


class EDGE_DEFORM_OT_select_controller(bpy.types.Operator):
    """Make the active handle's controller the active, only selected object, ready to move
    with G/R/S or its gizmo (the Edge Deform tab stays open)"""
    bl_idname = "edge_deform.select_controller"
    bl_label = "Select Controller"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    def execute(self, context):
        ob = context.active_object
        s = ob.edge_deform
        controller = s.handles[min(s.active_handle, len(s.handles) - 1)].controller
        if controller is None:
            tell(self, 'ERROR', "This handle has no controller")
            return {'CANCELLED'}
        if controller.name not in context.view_layer.objects:
            tell(self, 'ERROR', "The controller is not in this view layer")
            return {'CANCELLED'}
        for other in context.view_layer.objects:
            if other is not None and other != controller:
                other.select_set(False)
        controller.select_set(True)
        context.view_layer.objects.active = controller
        return {'FINISHED'}


class EDGE_DEFORM_OT_select_mesh(bpy.types.Operator):
    """Make the deformed mesh active again (after moving one of its controllers)"""
    bl_idname = "edge_deform.select_mesh"
    bl_label = "Select Mesh"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',))

    def execute(self, context):
        ob = context.active_object
        if ob.name not in context.view_layer.objects:
            return {'CANCELLED'}
        for other in context.view_layer.objects:
            if other is not None and other != ob:
                other.select_set(False)
        ob.select_set(True)
        context.view_layer.objects.active = ob
        return {'FINISHED'}


CLASSES = (EDGE_DEFORM_OT_select_controller, EDGE_DEFORM_OT_select_mesh)
