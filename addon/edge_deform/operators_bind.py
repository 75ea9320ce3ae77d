"""Bind, solve, apply and unbind: the non-interactive operators (scripts use these).
They only translate between the user and lifecycle.py, which does the work."""

import time

import bpy
from bpy.props import BoolProperty

from . import engine, lifecycle, tool_guard
from .jobs import StepsJob
from .op_common import deformed_object, guarded, redraw_views, report_lines, tell
from .progress import busy, run_steps


class EDGE_DEFORM_OT_bind(StepsJob, bpy.types.Operator):
    """Get the mesh ready to deform: the mesh and controllers as they are now become the
    rest pose. Takes a moment on big meshes; every later update is quick"""
    bl_idname = "edge_deform.bind"
    bl_label = "Bind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return tool_guard.poll(cls, context)

    def text(self, ob):
        return "Binding '%s' (%d vertices)…" % (ob.name, len(ob.data.vertices))

    @guarded
    def execute(self, context):
        ob = deformed_object(context)
        self.t0 = time.perf_counter()
        return self.job_done(context, run_steps(context, self.text(ob), lifecycle.bind_steps(ob)))

    @guarded
    def invoke(self, context, event):
        """From the UI: one stage per timer tick, so the status bar says what happens
        (reading, building the graph, factoring) and Esc cancels between stages."""
        ob = deformed_object(context)
        self.object_name, self.t0 = ob.name, time.perf_counter()
        return self.start_job(context, self.text(ob), lifecycle.bind_steps(ob))

    def job_done(self, context, binding):
        d = binding.deformer
        # The time the artist waited (the redraws between the stages included); the
        # compute time alone goes to the Info log.
        tell(self, 'INFO', "Bound %d vertices, %d nodes (%s) in %.1f s"
             % (d.n_vertices, d.n_nodes, binding.domain.lower(), time.perf_counter() - self.t0))
        tell(self, 'INFO', "Bind details: building and factoring the graph took %.0f ms"
             % binding.bind_ms)
        redraw_views(context)   # the panel's Bind becomes Unbind now, not on a hover
        return {'FINISHED'}

    def job_cancelled(self, context):
        tell(self, 'WARNING', "Bind of '%s' cancelled; nothing changed" % self.object_name)


class EDGE_DEFORM_OT_solve(StepsJob, bpy.types.Operator):
    """Deform the mesh once to follow where the controllers are now"""
    bl_idname = "edge_deform.solve"
    bl_label = "Solve"
    bl_options = {'REGISTER', 'UNDO'}

    warm_start: BoolProperty(
        name="Warm Start", default=False,
        description="Continue from the last result (faster); off gives the same shape "
                    "every time for the same controllers")

    @classmethod
    def poll(cls, context):
        return tool_guard.poll(cls, context)

    @guarded
    def execute(self, context):
        ob = deformed_object(context)
        self.t0 = time.perf_counter()
        with busy(context, "Deforming '%s'…" % ob.name):
            bound, r = lifecycle.deform(ob, warm=self.warm_start)
        return self.job_done(context, (bound, r, r.iterations))

    @guarded
    def invoke(self, context, event):
        """From the UI: the iterations run in chunks of about 0.1 s, one per timer tick,
        so the progress advances and Esc stops the solve with the mesh as it was."""
        if self.warm_start:
            return self.execute(context)
        ob = deformed_object(context)
        self.object_name, self.t0 = ob.name, time.perf_counter()
        return self.start_job(context, "Deforming '%s'…" % ob.name,
                              lifecycle.deform_steps(ob))

    def job_done(self, context, result):
        solver, r, iterations = result
        details, summary = engine.solve_report(r, time.perf_counter() - self.t0, iterations)
        report_lines(self, [('WARNING', w) for w in solver.warnings()] + details)
        tell(self, 'INFO', summary)
        redraw_views(context)
        return {'FINISHED'}

    def job_cancelled(self, context):
        tell(self, 'WARNING', "Solve of '%s' cancelled; the mesh is as it was"
             % self.object_name)


class EDGE_DEFORM_OT_apply(bpy.types.Operator):
    """Make the shape you see the base mesh and the new rest shape (other shape keys
    keep their offsets)"""
    bl_idname = "edge_deform.apply"
    bl_label = "Apply"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return tool_guard.poll(cls, context)

    @guarded
    def execute(self, context):
        ob = deformed_object(context)
        lifecycle.apply(ob)
        tell(self, 'INFO', "Applied to the base mesh; it is the new rest shape")
        redraw_views(context)
        return {'FINISHED'}


class EDGE_DEFORM_OT_unbind(bpy.types.Operator):
    """Release the mesh: the next Bind or Solve takes the mesh as it is now as its rest
    pose. The mesh and its shape key stay as they are"""
    bl_idname = "edge_deform.unbind"
    bl_label = "Unbind"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return tool_guard.poll(cls, context, on_controller=False)

    @guarded
    def execute(self, context):
        was = lifecycle.unbind(context.active_object)
        tell(self, 'INFO', "Unbound" if was else "Was not bound")
        redraw_views(context)
        return {'FINISHED'}


CLASSES = (EDGE_DEFORM_OT_bind, EDGE_DEFORM_OT_solve, EDGE_DEFORM_OT_apply,
           EDGE_DEFORM_OT_unbind)
