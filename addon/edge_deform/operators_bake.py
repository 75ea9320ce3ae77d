"""Animation: a frame-change handler that deforms on every frame, and `bake`, which stores
a frame range as shape keys keyed over time (one key per frame, weight 1 on its frame and
0 on its neighbours, so playback interpolates linearly between solved frames)."""

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, IntProperty

from . import engine, mesh_io
from .op_common import poll_mesh

_state = {"baking": False, "errors": {}}


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
            engine.deform(ob, warm=True, reuse_inputs=playing)
            _state["errors"].pop(ob.name_full, None)
        except engine.USER_ERRORS as exc:
            if _state["errors"].get(ob.name_full) != str(exc):   # say it once
                _state["errors"][ob.name_full] = str(exc)
                print("Edge Deform (%s, frame %d): %s" % (ob.name, scene.frame_current, exc))


def bake_key_name(s, frame):
    return "%s.%04d" % (s.shape_key_name, frame)


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

    def execute(self, context):
        ob, scene = context.active_object, context.scene
        s = ob.edge_deform
        start, end = ((scene.frame_start, scene.frame_end) if self.use_scene_range
                      else (self.frame_start, self.frame_end))
        if end < start:
            self.report({'ERROR'}, "Edge Deform: the frame range is empty")
            return {'CANCELLED'}
        frames = list(range(start, end + 1, self.frame_step))
        frame0 = scene.frame_current
        _state["baking"] = True
        made = []
        try:
            inputs = engine.gather_inputs(ob)
            binding = engine.ensure_binding(ob, inputs)
            binding.last = None   # frame `start` solves from scratch
            results = []
            for f in frames:   # solve everything first: on error nothing is written
                scene.frame_set(f)
                targets = engine.handle_targets(ob, binding, inputs)
                results.append(engine.solve(binding, targets, self.iterations,
                                            s.tolerance, acceleration=s.acceleration).positions)
        except engine.USER_ERRORS as exc:
            self.report({'ERROR'}, "Edge Deform: %s" % exc)
            return {'CANCELLED'}
        finally:
            scene.frame_set(frame0)
            _state["baking"] = False
        for f in frames:   # a re-bake replaces the previous keys
            mesh_io.remove_shape_key(ob, bake_key_name(s, f))
        for f, X in zip(frames, results):
            name = bake_key_name(s, f)
            mesh_io.write_output(ob, 'SHAPE_KEY', name, X)
            kb = ob.data.shape_keys.key_blocks[name]
            for frame, value in ((f - self.frame_step, 0.0), (f, 1.0),
                                 (f + self.frame_step, 0.0)):
                kb.value = value
                kb.keyframe_insert("value", frame=frame)
            made.append(name)
        live = ob.data.shape_keys.key_blocks.get(s.shape_key_name)
        if live is not None:
            live.value = 0.0   # the baked keys replace the live result
        s.animate = False
        scene.frame_set(frame0)
        self.report({'INFO'}, "Baked %d frames (%d-%d) into shape keys '%s.####'"
                    % (len(made), frames[0], frames[-1], s.shape_key_name))
        return {'FINISHED'}


def register_handlers():
    if on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(on_frame_change)


def unregister_handlers():
    if on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(on_frame_change)


CLASSES = (EDGE_DEFORM_OT_bake,)
