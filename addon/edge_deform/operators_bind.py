"""Bind, solve, apply and unbind: the non-interactive operators (scripts use these)."""

import time

import bpy
from bpy.props import BoolProperty

from . import engine, mesh_io, session
from .op_common import poll_mesh


def _report_error(op, exc):
    op.report({'ERROR'}, "Edge Deform: %s" % exc)
    return {'CANCELLED'}


class EDGE_DEFORM_OT_bind(bpy.types.Operator):
    """Triangulate, build the graph and factor the system; current controller transforms
    and the current mesh become the rest"""
    bl_idname = "edge_deform.bind"
    bl_label = "Bind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    def execute(self, context):
        ob = context.active_object
        saved = [h.rest_matrix.copy() for h in ob.edge_deform.handles]
        saved_digest = ob.data.get(mesh_io.TOPOLOGY_PROP)
        rest_attr = mesh_io.read_rest(ob.data, saved_digest)
        try:
            engine.record_rest_transforms(ob)
            inputs = engine.gather_inputs(ob)
            binding = engine.ensure_binding(ob, inputs, fresh=True)
        except engine.USER_ERRORS as exc:
            for h, m in zip(ob.edge_deform.handles, saved):   # leave everything as it was
                h.rest_matrix = m
            if rest_attr is not None:
                mesh_io.store_rest(ob.data, rest_attr, saved_digest or "")
            session.drop(ob.data.as_pointer())
            return _report_error(self, exc)
        d = binding.deformer
        self.report({'INFO'}, "Bound %d vertices, %d nodes (%s), %.1f ms"
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

    def execute(self, context):
        ob = context.active_object
        t0 = time.perf_counter()
        try:
            _, r = engine.deform(ob, warm=self.warm_start)
        except engine.USER_ERRORS as exc:
            return _report_error(self, exc)
        for w in r.warnings:
            self.report({'WARNING'}, w)
        self.report({'INFO'}, "Solved: %d iterations%s, %.1f ms"
                    % (r.iterations, "" if r.converged else " (not converged)",
                       (time.perf_counter() - t0) * 1e3))
        return {'FINISHED'}


class EDGE_DEFORM_OT_apply(bpy.types.Operator):
    """Bake the deformation into the base mesh; it becomes the new rest shape"""
    bl_idname = "edge_deform.apply"
    bl_label = "Apply"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    def execute(self, context):
        ob = context.active_object
        s = ob.edge_deform
        mesh = ob.data
        keys = mesh.shape_keys
        shown = (s.output == 'SHAPE_KEY' and keys is not None
                 and s.shape_key_name in keys.key_blocks) or \
            (s.output == 'MESH' and mesh_io.has_rest(mesh))
        try:
            if shown:   # apply what the user sees
                X = mesh_io.read_output(ob, s.output, s.shape_key_name)
            else:
                X = engine.deform(ob)[1].positions
        except engine.USER_ERRORS as exc:
            return _report_error(self, exc)
        mesh_io.remove_shape_key(ob, s.shape_key_name)
        if mesh.shape_keys is not None and len(mesh.shape_keys.key_blocks) == 1:
            ob.shape_key_clear()   # only the Basis we added is left
        mesh_io.write_output(ob, 'MESH', s.shape_key_name, X)
        mesh_io.clear_rest(mesh)
        engine.record_rest_transforms(ob)
        session.drop(mesh.as_pointer())
        self.report({'INFO'}, "Applied to the base mesh; it is the new rest shape")
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

    def execute(self, context):
        mesh = context.active_object.data
        was = session.get(mesh.as_pointer()) is not None or mesh_io.has_rest(mesh)
        session.drop(mesh.as_pointer())
        mesh_io.clear_rest(mesh)
        self.report({'INFO'}, "Unbound" if was else "Was not bound")
        return {'FINISHED'}


CLASSES = (EDGE_DEFORM_OT_bind, EDGE_DEFORM_OT_solve, EDGE_DEFORM_OT_apply,
           EDGE_DEFORM_OT_unbind)
