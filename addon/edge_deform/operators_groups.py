"""Operators that turn a vertex selection into handle, static, region and stiffness groups,
and the panel's buttons that move the selection between a mesh and a controller.

Selections come from any tool (box, lasso, circle, select linked, ...): the operators only
read the selection state, in Edit Mode or from Weight Paint's vertex mask.
"""

import bpy
import numpy as np
from bpy.props import EnumProperty, FloatProperty, StringProperty
from mathutils import Matrix, Vector

from . import compat, engine, mesh_io
from .op_common import object_mode, poll_mesh, select_only, tell


PRESETS = {'SOFT': 0.0, 'MEDIUM': 0.5, 'RIGID': 1.0}
# Short enough to read in full in the panel's fields at the default sidebar width.
STATIC_DEFAULT = "ED_Static"
ROI_DEFAULT = "ED_Region"
STIFFNESS_DEFAULT = "ED_Stiffness"


def _selected(op, ob):
    idx = np.flatnonzero(mesh_io.read_selection(ob))
    if idx.size == 0:
        tell(op, 'ERROR', "No vertices selected")
    return idx


class _OnMesh:
    """An operator on the active mesh, one undo step; its poll wants one of `modes` (None:
    any) and, with `need_handles`, a handle."""
    bl_options = {'REGISTER', 'UNDO'}
    modes = None
    need_handles = False

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, cls.modes, need_handles=cls.need_handles)


class _OnSelection(_OnMesh):
    """An operator on the vertices selected in Edit Mode: refused with a message when none
    is; else `on_selection(context, ob, indices)` does the work."""
    modes = ('EDIT',)

    def execute(self, context):
        ob = context.active_object
        idx = _selected(self, ob)
        if idx.size == 0:
            return {'CANCELLED'}
        return self.on_selection(context, ob, idx)


class EDGE_DEFORM_OT_add_handle(_OnSelection, bpy.types.Operator):
    """Make the selected vertices a new handle, moved by a new Empty at their centroid; it
    holds them where they are shown"""
    bl_idname = "edge_deform.add_handle"
    bl_label = "Add Handle"

    name: StringProperty(name="Name", default="Handle",
                         description="Name of the new vertex group (and its controller)")

    def on_selection(self, context, ob, idx):
        s = ob.edge_deform
        with object_mode(ob):
            # Where the artist sees the vertices (on a deformed mesh: the shape shown, not
            # the rest): the Empty goes there, and the handle holds them there.
            X = mesh_io.addon_shape(ob)
            centroid = ob.matrix_world @ Vector(X[idx].mean(axis=0))
            size = float(np.ptp(X, axis=0).max()) * 0.08 or 0.1
            # A vertex follows one handle: take the selection out of the other groups.
            for other in [h.vertex_group for h in s.handles] + [s.static_group]:
                if other and other in ob.vertex_groups:
                    ob.vertex_groups[other].remove(idx.tolist())
            vg = ob.vertex_groups.new(name=self.name or "Handle")   # unique: "Handle.001"
            mesh_io.assign_group(ob, vg.name, idx)
            # Named after the object and the group: "Handle_Controller" of every mesh
            # crept to "Handle_Controller.004".
            empty = bpy.data.objects.new("%s_%s" % (ob.name, vg.name), None)
            empty.empty_display_type = 'SPHERE'
            empty.empty_display_size = size
            empty.matrix_world = Matrix.Translation(centroid)
            (ob.users_collection[0] if ob.users_collection
             else context.scene.collection).objects.link(empty)
            item = s.handles.add()
            item.vertex_group = vg.name
            item.controller = empty
            item.rest_matrix = engine.controller_rest(ob, empty)
            s.active_handle = len(s.handles) - 1
            hold_where_shown(ob, idx, X[idx])
        tell(self, 'INFO', "Handle '%s': %d vertices, controller '%s'"
                    % (vg.name, idx.size, empty.name))
        return {'FINISHED'}


def hold_where_shown(ob, idx, where):
    """The new handle holds its vertices where they are shown (mesh_io.hold_at). Without
    a readable rest (a broken Mesh output) it holds the rest: the next solve says why."""
    try:
        rest = mesh_io.rest_shape(ob.data)
    except mesh_io.EdgeDeformError:
        return
    mesh_io.hold_at(ob.data, rest, idx, where)


class EDGE_DEFORM_OT_remove_handle(_OnMesh, bpy.types.Operator):
    """Remove the active handle (its vertex group and controller are kept)"""
    bl_idname = "edge_deform.remove_handle"
    bl_label = "Remove Handle"
    need_handles = True

    def execute(self, context):
        ob = context.active_object
        s = ob.edge_deform
        group = s.handles[min(s.active_handle, len(s.handles) - 1)].vertex_group
        if group in ob.vertex_groups:   # its vertices are held at their rest again
            with object_mode(ob):
                weights = mesh_io.read_group_weights(ob, [group])[group]
                mesh_io.release_holds(ob.data, np.flatnonzero(weights > 0.0))
        s.handles.remove(min(s.active_handle, len(s.handles) - 1))
        s.active_handle = max(0, min(s.active_handle, len(s.handles) - 1))
        return {'FINISHED'}


class _SetGroup(_OnSelection):
    field = ""
    default = ""
    takes_from_handles = False   # Static: a vertex cannot be pinned and moved at once

    def on_selection(self, context, ob, idx):
        name = getattr(ob.edge_deform, self.field) or self.default
        with object_mode(ob):
            if self.takes_from_handles:   # as Add Handle takes them out of Static
                for handle in ob.edge_deform.handles:
                    if handle.vertex_group in ob.vertex_groups:
                        ob.vertex_groups[handle.vertex_group].remove(idx.tolist())
            vg = mesh_io.assign_group(ob, name, idx, 1.0, replace_all=True)
        setattr(ob.edge_deform, self.field, vg.name)
        tell(self, 'INFO', "%s group '%s': %d vertices" % (self.bl_label.split()[-1],
                                                                 vg.name, idx.size))
        return {'FINISHED'}


class EDGE_DEFORM_OT_set_static(_SetGroup, bpy.types.Operator):
    """Pin the selected vertices: they never move (and stop being handles)"""
    bl_idname = "edge_deform.set_static"
    bl_label = "Set Static"
    field, default = "static_group", STATIC_DEFAULT
    takes_from_handles = True


class EDGE_DEFORM_OT_set_roi(_SetGroup, bpy.types.Operator):
    """Only the selected vertices may move; the rest of the mesh stays put"""
    bl_idname = "edge_deform.set_roi"
    bl_label = "Set Region"
    field, default = "roi_group", ROI_DEFAULT


def ensure_stiffness_group(ob):
    """The stiffness group, created filled with the global λ so unpainted areas keep it."""
    s = ob.edge_deform
    name = s.stiffness_group or STIFFNESS_DEFAULT
    if name not in ob.vertex_groups:
        with object_mode(ob):
            vg = mesh_io.assign_group(ob, name, np.arange(len(ob.data.vertices)),
                                      s.stiffness)
        name = vg.name
    s.stiffness_group = name
    return ob.vertex_groups[name]


def _stiffness_targets(op, ob):
    """The vertices Assign Stiffness acts on, as Blender's Set Weight chooses them: in
    Weight Paint the masked vertices when a selection mask is on, else every vertex (never
    a selection left over from Edit Mode, which Weight Paint does not show); in Edit Mode
    the selection."""
    me = ob.data
    if ob.mode != 'WEIGHT_PAINT':
        return _selected(op, ob)
    if me.use_paint_mask_vertex:
        return _selected(op, ob)
    if me.use_paint_mask:   # face mask: the vertices of the selected faces
        idx = mesh_io.selected_face_vertices(me)
        if idx.size == 0:
            tell(op, 'ERROR', "No faces selected")
        return idx
    return np.arange(len(me.vertices))


class EDGE_DEFORM_OT_assign_stiffness(_OnMesh, bpy.types.Operator):
    """Set the stiffness of the selected vertices (Weight Paint: the masked vertices, or
    the whole mesh without a mask), like Set Weight"""
    bl_idname = "edge_deform.assign_stiffness"
    bl_label = "Assign Stiffness"
    modes = ('EDIT', 'WEIGHT_PAINT')

    preset: EnumProperty(
        name="Preset", default='VALUE',
        items=[('VALUE', "Value", "Use the value below"),
               ('SOFT', "Soft", "λ = 0: bends smoothly like rubber (blue)"),
               ('MEDIUM', "Medium", "λ = 0.5: in between (green)"),
               ('RIGID', "Rigid", "λ = 1: keeps its shape (red)")],
        description="The stiffness to give")
    value: FloatProperty(name="λ", default=1.0, min=0.0, max=1.0,
                         description="Stiffness for Value: 1 rigid, 0 soft")

    def execute(self, context):
        ob = context.active_object
        idx = _stiffness_targets(self, ob)
        if idx.size == 0:
            return {'CANCELLED'}
        lam = PRESETS.get(self.preset, self.value)
        vg = ensure_stiffness_group(ob)
        with object_mode(ob):
            mesh_io.assign_group(ob, vg.name, idx, lam)
        tell(self, 'INFO', "λ = %.2f on %d vertices (group '%s')" % (lam, idx.size, vg.name))
        return {'FINISHED'}


class EDGE_DEFORM_OT_paint_stiffness(_OnMesh, bpy.types.Operator):
    """Paint the stiffness in Weight Paint (red = rigid, blue = soft)"""
    bl_idname = "edge_deform.paint_stiffness"
    bl_label = "Paint Stiffness"

    def execute(self, context):
        ob = context.active_object
        vg = ensure_stiffness_group(ob)
        ob.vertex_groups.active_index = vg.index
        if ob.mode != 'WEIGHT_PAINT':
            compat.mode_set(ob, 'WEIGHT_PAINT')
        return {'FINISHED'}


# ------------------------------------------------------------------ selection
# Select Controller and Select Mesh: the panel's buttons that move the selection between a
# deformed mesh and the controller of its active handle (ready for G/R/S or its gizmo).

class EDGE_DEFORM_OT_select_controller(_OnMesh, bpy.types.Operator):
    """Make the active handle's controller the active, only selected object, ready to move
    with G/R/S or its gizmo (the Edge Deform tab stays open)"""
    bl_idname = "edge_deform.select_controller"
    bl_label = "Select Controller"
    modes = ('OBJECT',)
    need_handles = True

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
        select_only(context.view_layer, controller)
        return {'FINISHED'}


class EDGE_DEFORM_OT_select_mesh(_OnMesh, bpy.types.Operator):
    """Make the deformed mesh active again (after moving one of its controllers)"""
    bl_idname = "edge_deform.select_mesh"
    bl_label = "Select Mesh"
    modes = ('OBJECT',)

    def execute(self, context):
        ob = context.active_object
        if ob.name not in context.view_layer.objects:
            return {'CANCELLED'}
        select_only(context.view_layer, ob)
        return {'FINISHED'}


CLASSES = (EDGE_DEFORM_OT_add_handle, EDGE_DEFORM_OT_remove_handle, EDGE_DEFORM_OT_set_static,
           EDGE_DEFORM_OT_set_roi, EDGE_DEFORM_OT_assign_stiffness,
           EDGE_DEFORM_OT_paint_stiffness, EDGE_DEFORM_OT_select_controller,
           EDGE_DEFORM_OT_select_mesh,)
