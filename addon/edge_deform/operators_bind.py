"""Bind, solve, apply and unbind: the non-interactive operators (scripts use these).
They only translate between the user and lifecycle.py, which does the work."""

import time

import bpy
from bpy.props import BoolProperty

from . import engine, lifecycle
from .op_common import guarded, poll_mesh, report_lines, tell


class EDGE_DEFORM_OT_bind(bpy.types.Operator):
    """Triangulate, build the graph and factor the system; current controller transforms
    and the current mesh become the rest"""
    bl_idname = "edge_deform.bind"
    bl_label = "Bind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def execute(self, context):
        binding = lifecycle.bind(context.active_object)
        d = binding.deformer
        tell(self, 'INFO', "Bound %d vertices, %d nodes (%s), %.1f ms"
                    % (d.n_vertices, d.n_nodes, binding.domain.lower(), binding.bind_ms))
        return {'FINISHED'}


class EDGE_DEFORM_OT_solve(bpy.types.Operator):
    """Deform once from the current controller transforms"""
    bl_idname = "edge_deform.solve"
    bl_label = "Solve"
    bl_options = {'REGISTER', 'UNDO'}

    warm_start: BoolProperty(
        name="Warm Start", default=False,
        description="Start from the previous result (else from the naive Laplacian solve, "
                    "repeatable for the same inputs)")

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def execute(self, context):
        t0 = time.perf_counter()
        bound, r = lifecycle.deform(context.active_object, warm=self.warm_start)
        lines, text, _ = engine.status(r, (time.perf_counter() - t0) * 1e3)
        report_lines(self, [('WARNING', w) for w in bound.warnings()] + lines)
        tell(self, 'INFO', "Solved: " + text)
        return {'FINISHED'}


class EDGE_DEFORM_OT_apply(bpy.types.Operator):
    """Make the shape you see the base mesh and the new rest shape (other shape keys
    keep their offsets)"""
    bl_idname = "edge_deform.apply"
    bl_label = "Apply"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def execute(self, context):
        lifecycle.apply(context.active_object)
        tell(self, 'INFO', "Applied to the base mesh; it is the new rest shape")
        return {'FINISHED'}


class EDGE_DEFORM_OT_unbind(bpy.types.Operator):
    """Forget the binding (cached factorization and stored rest shape); the mesh and the
    shape key are left as they are"""
    bl_idname = "edge_deform.unbind"
    bl_label = "Unbind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',))

    @guarded
    def execute(self, context):
        was = lifecycle.unbind(context.active_object)
        tell(self, 'INFO', "Unbound" if was else "Was not bound")
        return {'FINISHED'}


CLASSES = (EDGE_DEFORM_OT_bind, EDGE_DEFORM_OT_solve, EDGE_DEFORM_OT_apply,
           EDGE_DEFORM_OT_unbind)
