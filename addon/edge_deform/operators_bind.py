"""The non-interactive operators (scripts use these): Bind, Solve, Apply, Unbind and Bake,
and deforming on every frame. They translate between the user and lifecycle.py, which does
the work. Long work started from the UI runs as a modal job (StepsJob): one stage per timer
tick, so Blender redraws between stages and Esc cancels."""

import contextlib
import time

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, IntProperty

from . import engine, lifecycle, mesh_io, modal, op_common
from .op_common import (Stages, call_reporting_errors, deformed_object, error_text, guarded,
                        redraw_views, report_lines, run_steps, set_header, tell)


class StepsJob:
    """Long work from the UI, one step per timer tick (an operator mix-in): between steps
    Blender redraws, so the status bar says what the next step does, the progress
    advances, and Esc cancels. `steps` yields (fraction, text) before each step and
    returns the result; nothing may be written to bpy data before its last step, so a
    cancel leaves the data as it was. The operator defines job_done(context, result) and
    job_cancelled(context)."""

    def job_object(self, context):
        """The mesh the job works on; the clock of the artist's wait starts now."""
        ob = deformed_object(context)
        self.object_name, self.t0 = ob.name, time.perf_counter()
        return ob

    def start_job(self, context, text, steps):
        self.job = Stages(context, text, steps)
        self.job_area = context.area
        wm = context.window_manager
        self.job_timer = wm.event_timer_add(0.01, window=context.window)
        wm.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC' and event.value == 'PRESS':
            self.stop_job(context)
            self.job_cancelled(context)
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}   # the rest of the UI waits for the work
        try:
            done, result = self.job.advance()
        except Exception as exc:  # noqa: BLE001 - reported; nothing written before the end
            self.stop_job(context)
            tell(self, 'ERROR', error_text(exc))
            return {'CANCELLED'}
        if done:
            self.stop_job(context)
            return call_reporting_errors(self, lambda: self.job_done(context, result))
        self._job_header("%s  (Esc: cancel)" % self.job.stage)
        return {'RUNNING_MODAL'}

    def _job_header(self, text):
        set_header(self.job_area, text)

    def stop_job(self, context):
        context.window_manager.event_timer_remove(self.job_timer)
        self._job_header(None)
        self.job.stop()

    def cancel(self, context):   # the window closes or a file loads
        self.stop_job(context)


# ------------------------------------------------------------------ bind, solve, apply, unbind

class RewritesTheMesh:
    """Bind, Solve, Apply, Unbind and Bake (a mix-in): one undo step each, and greyed while
    a modal tool runs on the mesh, the tooltip saying why (modal.poll). `on_controller`:
    also the mesh of the active controller."""
    bl_options = {'REGISTER', 'UNDO'}
    on_controller = True

    @classmethod
    def poll(cls, context):
        return modal.poll(cls, context, on_controller=cls.on_controller)


class EDGE_DEFORM_OT_bind(RewritesTheMesh, StepsJob, bpy.types.Operator):
    """Get the mesh ready to deform: the mesh and controllers as they are now become the
    rest pose. Takes a moment on big meshes; every later update is quick"""
    bl_idname = "edge_deform.bind"
    bl_label = "Bind"
    def text(self, ob):
        return "Binding '%s' (%d vertices)…" % (ob.name, len(ob.data.vertices))

    @guarded
    def execute(self, context):
        ob = self.job_object(context)
        return self.job_done(context, run_steps(context, self.text(ob), lifecycle.bind_steps(ob)))

    @guarded
    def invoke(self, context, event):
        """From the UI: one stage per timer tick, so the status bar says what happens
        (reading, building the graph, factoring) and Esc cancels between stages."""
        ob = self.job_object(context)
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


class EDGE_DEFORM_OT_solve(RewritesTheMesh, StepsJob, bpy.types.Operator):
    """Deform the mesh once to follow where the controllers are now"""
    bl_idname = "edge_deform.solve"
    bl_label = "Solve"

    warm_start: BoolProperty(
        name="Warm Start", default=False,
        description="Continue from the last result (faster); off gives the same shape "
                    "every time for the same controllers")

    @guarded
    def execute(self, context):
        ob = self.job_object(context)
        with op_common.showing_progress(context, "Deforming '%s'…" % ob.name):
            bound, r = lifecycle.deform(ob, warm=self.warm_start)
        return self.job_done(context, (bound, r, r.iterations))

    @guarded
    def invoke(self, context, event):
        """From the UI: the iterations run in chunks of about 0.1 s, one per timer tick,
        so the progress advances and Esc stops the solve with the mesh as it was."""
        if self.warm_start:
            return self.execute(context)
        ob = self.job_object(context)
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


class EDGE_DEFORM_OT_apply(RewritesTheMesh, bpy.types.Operator):
    """Make the shape you see the base mesh and the new rest shape (other shape keys
    keep their offsets)"""
    bl_idname = "edge_deform.apply"
    bl_label = "Apply"
    @guarded
    def execute(self, context):
        ob = deformed_object(context)
        lifecycle.apply(ob)
        tell(self, 'INFO', "Applied to the base mesh; it is the new rest shape")
        redraw_views(context)
        return {'FINISHED'}


class EDGE_DEFORM_OT_unbind(RewritesTheMesh, bpy.types.Operator):
    """Release the mesh: the next Bind or Solve takes the mesh as it is now as its rest
    pose. The mesh and its shape key stay as they are"""
    bl_idname = "edge_deform.unbind"
    bl_label = "Unbind"
    on_controller = False   # the active object itself, bound or not

    @guarded
    def execute(self, context):
        was = lifecycle.unbind(context.active_object)
        tell(self, 'INFO', "Unbound" if was else "Was not bound")
        redraw_views(context)
        return {'FINISHED'}


# ------------------------------------------------------------------ bake
# `bake`: stores a frame range as shape keys keyed over time (one key per frame, weight 1
# on its frame and 0 on its neighbours, so playback interpolates linearly between solved
# frames). Deforming on every frame without baking is the frame handler's (below).

class EDGE_DEFORM_OT_bake(RewritesTheMesh, StepsJob, bpy.types.Operator):
    """Solve every frame of a range and store the results as shape keys keyed over time"""
    bl_idname = "edge_deform.bake"
    bl_label = "Bake Frames"

    use_scene_range: BoolProperty(name="Scene Range", default=True,
                                  description="Bake the scene's frame range")
    frame_start: IntProperty(name="Start", default=1, description="First frame to bake")
    frame_end: IntProperty(name="End", default=250, description="Last frame to bake")
    frame_step: IntProperty(name="Step", default=1, min=1,
                            description="Bake every n-th frame; playback blends between")
    iterations: IntProperty(name="Refinement per Frame", default=10, min=1,
                            description="Refinement passes on each frame (more: closer to "
                                        "the stiffness, slower)")

    def frames(self, scene):
        start, end = ((scene.frame_start, scene.frame_end) if self.use_scene_range
                      else (self.frame_start, self.frame_end))
        if end < start:
            raise mesh_io.EdgeDeformError("the frame range is empty")
        return list(range(start, end + 1, self.frame_step))

    def begin(self, context):
        """Check and bind; nothing is written before every frame is solved."""
        self.ob, self.scene = deformed_object(context), context.scene
        self.todo = self.frames(self.scene)
        self.frame0 = self.scene.frame_current
        self.results = []
        self.solver = lifecycle.prepare(self.ob)
        engine.start_cold(self.ob.data)   # the first frame solves from scratch

    def solve_next(self):
        """Solve the next frame (the frame handler is held off meanwhile)."""
        with held_off():
            try:
                self.scene.frame_set(self.todo[len(self.results)])
                self.results.append(self.solver.solve(
                    self.solver.targets(), self.iterations,
                    self.ob.edge_deform.tolerance).positions)
            finally:
                self.scene.frame_set(self.frame0)

    def steps(self):
        """Solve every frame, one per step; the keys are written only after the last."""
        n = len(self.todo)
        while len(self.results) < n:
            yield len(self.results) / n, "Baking: frame %d/%d" % (len(self.results) + 1, n)
            self.solve_next()
        return None

    def job_done(self, context, _):
        ob, s = self.ob, self.ob.edge_deform
        made = mesh_io.write_baked(ob, self.todo, self.results, self.frame_step)
        s.animate = False
        self.scene.frame_set(self.frame0)
        tell(self, 'INFO', "Baked %d frames (%d-%d) into shape keys '%s.####'"
             % (len(made), self.todo[0], self.todo[-1], s.shape_key_name))
        return {'FINISHED'}

    def job_cancelled(self, context):
        tell(self, 'WARNING', "Bake cancelled after %d of %d frames; nothing was "
                              "written" % (len(self.results), len(self.todo)))

    @guarded
    def execute(self, context):
        self.begin(context)
        return self.job_done(context, run_steps(context, "Baking %d frames…" % len(self.todo),
                                                self.steps()))

    @guarded
    def invoke(self, context, event):
        """From the UI: one frame per timer tick, so the window redraws, shows
        "Frame 12/24" and Esc cancels with the data as before."""
        self.begin(context)
        return self.start_job(context, "Baking %d frames…" % len(self.todo), self.steps())


# ------------------------------------------------------------------ deform on every frame
# Deform on every frame: a frame-change handler re-solves the objects whose Animation >
# Every Frame is on (warm-started from the last frame) and keeps each object's last problem
# for the panel. Bake holds it off while it steps through its frames (`held_off`).

# The handler's own state: its last problem per object (name_full: text) and whether Bake
# holds it off. Only this module changes them.
_problems = {}
_holds = [0]


def frame_problem(ob):
    """The last error of the frame handler for `ob` (shown in the panel), or None."""
    return _problems.get(ob.name_full)


@contextlib.contextmanager
def held_off():
    """The handler does nothing meanwhile (Bake sets frames and solves them itself)."""
    _holds[0] += 1
    try:
        yield
    finally:
        _holds[0] -= 1


@persistent
def on_frame_change(scene, depsgraph=None):
    """Re-solve objects with 'Deform on Frame Change' (warm-started from the last frame)."""
    if _holds[0]:
        return
    # A render job may call this off the main thread; bpy data must not be written then.
    if hasattr(bpy.app, "is_job_running") and bpy.app.is_job_running('RENDER'):
        return
    # During playback the groups cannot change: skip re-reading them every frame.
    screen = getattr(bpy.context, "screen", None)
    playing = bool(screen is not None and screen.is_animation_playing)
    # A mesh a modal tool deforms is left alone: Live follows animated controllers itself.
    for ob in scene.objects:
        s = getattr(ob, "edge_deform", None)
        if ob.type != 'MESH' or s is None or not s.animate or not s.handles \
                or ob.mode != 'OBJECT' or modal.running_tool(ob) is not None:
            continue
        try:
            solver, _ = lifecycle.deform(ob, warm=True, reuse_inputs=playing)
            problem = "; ".join(solver.warnings()) or None
        except Exception as exc:  # noqa: BLE001 - a handler must never raise
            problem = error_text(exc)
        if problem is None:
            _problems.pop(ob.name_full, None)
        elif _problems.get(ob.name_full) != problem:   # say it once
            _problems[ob.name_full] = problem
            print("Edge Deform (%s, frame %d): %s" % (ob.name, scene.frame_current, problem))


def register_handlers():
    if on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(on_frame_change)


def unregister_handlers():
    if on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(on_frame_change)


CLASSES = (EDGE_DEFORM_OT_bind, EDGE_DEFORM_OT_solve, EDGE_DEFORM_OT_apply,
           EDGE_DEFORM_OT_unbind, EDGE_DEFORM_OT_bake,)
