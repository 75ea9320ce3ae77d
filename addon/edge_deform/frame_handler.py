"""Deform on every frame: a frame-change handler re-solves the objects whose Animation >
Every Frame is on (warm-started from the last frame) and keeps each object's last problem
for the panel. Bake holds it off while it steps through its frames (`held_off`)."""

import contextlib

import bpy
from bpy.app.handlers import persistent

from . import lifecycle, tool_guard
from .op_common import error_text

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
    for ob in scene.objects:
        s = getattr(ob, "edge_deform", None)
        if ob.type != 'MESH' or s is None or not s.animate or not s.handles \
                or ob.mode != 'OBJECT' or tool_guard.busy(ob):
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
