"""`bake`: stores a frame range as shape keys keyed over time (one key per frame, weight 1
on its frame and 0 on its neighbours, so playback interpolates linearly between solved
frames). Deforming on every frame without baking is frame_handler.py's."""

import bpy
from bpy.props import BoolProperty, IntProperty

from . import engine, frame_handler, lifecycle, output, solver_cache, tool_guard
from .jobs import StepsJob
from .op_common import deformed_object, guarded, tell
from .progress import run_steps

class EDGE_DEFORM_OT_bake(StepsJob, bpy.types.Operator):
    """Solve every frame of a range and store the results as shape keys keyed over time"""
    bl_idname = "edge_deform.bake"
    bl_label = "Bake Frames"
    bl_options = {'REGISTER', 'UNDO'}

    use_scene_range: BoolProperty(name="Scene Range", default=True,
                                  description="Bake the scene's frame range")
    frame_start: IntProperty(name="Start", default=1, description="First frame to bake")
    frame_end: IntProperty(name="End", default=250, description="Last frame to bake")
    frame_step: IntProperty(name="Step", default=1, min=1,
                            description="Bake every n-th frame; playback blends between")
    iterations: IntProperty(name="Refinement per Frame", default=10, min=1,
                            description="Refinement passes on each frame (more: closer to "
                                        "the stiffness, slower)")

    @classmethod
    def poll(cls, context):
        return tool_guard.poll(cls, context)

    def frames(self, scene):
        start, end = ((scene.frame_start, scene.frame_end) if self.use_scene_range
                      else (self.frame_start, self.frame_end))
        if end < start:
            raise engine.EdgeDeformError("the frame range is empty")
        return list(range(start, end + 1, self.frame_step))

    def begin(self, context):
        """Check and bind; nothing is written before every frame is solved."""
        self.ob, self.scene = deformed_object(context), context.scene
        self.todo = self.frames(self.scene)
        self.frame0 = self.scene.frame_current
        self.results = []
        self.solver = lifecycle.prepare(self.ob)
        solver_cache.start_cold(self.ob.data)   # the first frame solves from scratch

    def solve_next(self):
        """Solve the next frame (the frame handler is held off meanwhile)."""
        with frame_handler.held_off():
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
        made = output.write_baked(ob, self.todo, self.results, self.frame_step)
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


CLASSES = (EDGE_DEFORM_OT_bake,)
