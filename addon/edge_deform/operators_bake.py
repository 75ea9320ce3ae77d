"""Animation: a frame-change handler that deforms on every frame, and `bake`, which stores
a frame range as shape keys keyed over time (one key per frame, weight 1 on its frame and
0 on its neighbours, so playback interpolates linearly between solved frames)."""

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, IntProperty

from . import engine, lifecycle
from .op_common import error_text, guarded, poll_mesh, tell

_state = {"baking": False, "errors": {}}


def frame_problem(ob):
    """The last error of the frame handler for `ob` (shown in the panel), or None."""
    return _state["errors"].get(ob.name_full)


@persistent
def on_frame_change(scene, depsgraph=None):
    """Re-solve objects with 'Deform on Frame Change' (warm-started from the last frame)."""
    if _state["baking"]:
        return
    # A render job may call this off the main thread; bpy data must not be written then.
    if hasattr(bpy.app, "is_job_running") and bpy.app.is_job_running('RENDER'):
        return
    # During playback the groups cannot change: skip re-reading them every frame.
    screen = getattr(bpy.context, "screen", None)
    playing = bool(screen is not None and screen.is_animation_playing)
    for ob in scene.objects:
        s = getattr(ob, "edge_deform", None)
        if ob.type != 'MESH' or s is None or not s.animate or not s.handles \
                or ob.mode != 'OBJECT':
            continue
        try:
            bound, _ = lifecycle.deform(ob, warm=True, reuse_inputs=playing)
            problem = "; ".join(bound.warnings()) or None
        except Exception as exc:  # noqa: BLE001 - a handler must never raise
            problem = error_text(exc)
        if problem is None:
            _state["errors"].pop(ob.name_full, None)
        elif _state["errors"].get(ob.name_full) != problem:   # say it once
            _state["errors"][ob.name_full] = problem
            print("Edge Deform (%s, frame %d): %s" % (ob.name, scene.frame_current, problem))


class EDGE_DEFORM_OT_bake(bpy.types.Operator):
    """Solve every frame of a range and store the results as shape keys keyed over time"""
    bl_idname = "edge_deform.bake"
    bl_label = "Bake Frames"
    bl_options = {'REGISTER', 'UNDO'}

    use_scene_range: BoolProperty(name="Scene Range", default=True)
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=250)
    frame_step: IntProperty(name="Step", default=1, min=1)
    iterations: IntProperty(name="Iterations per Frame", default=10, min=1)

    @classmethod
    def poll(cls, context):
        return poll_mesh(cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def execute(self, context):
        ob, scene = context.active_object, context.scene
        s = ob.edge_deform
        start, end = ((scene.frame_start, scene.frame_end) if self.use_scene_range
                      else (self.frame_start, self.frame_end))
        if end < start:
            raise engine.EdgeDeformError("the frame range is empty")
        frames = list(range(start, end + 1, self.frame_step))
        frame0 = scene.frame_current
        _state["baking"] = True
        try:
            bound = lifecycle.prepare(ob)
            bound.binding.last = None   # frame `start` solves from scratch
            results = []
            for f in frames:   # solve everything first: on error nothing is written
                scene.frame_set(f)
                results.append(bound.solve(bound.targets(), self.iterations,
                                           s.tolerance).positions)
        finally:
            scene.frame_set(frame0)
            _state["baking"] = False
        made = lifecycle.write_baked(ob, frames, results, self.frame_step)
        s.animate = False
        scene.frame_set(frame0)
        tell(self, 'INFO', "Baked %d frames (%d-%d) into shape keys '%s.####'"
                    % (len(made), frames[0], frames[-1], s.shape_key_name))
        return {'FINISHED'}


def register_handlers():
    if on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(on_frame_change)


def unregister_handlers():
    if on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(on_frame_change)


CLASSES = (EDGE_DEFORM_OT_bake,)
