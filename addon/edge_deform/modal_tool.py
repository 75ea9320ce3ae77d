"""What the modal tools (Live, Grab) share: one tool at a time, a timer, the header, the
snapshot for a bit-exact cancel, one undo step per session, and noticing that undo or a
deletion replaced the data they hold."""

import bpy

from . import cache_handlers, compat, engine, snapshot
from .op_common import redraw_views, set_header


# The modal tools running now: {id(tool): tool}. One at a time: a second Live or Grab
# would write the same output and its cancel would throw away the first's.
_running = {}


def running_tool(ob=None):
    """The tool running (on `ob`, when given), or None."""
    for tool in _running.values():
        if ob is None or tool.object_name == ob.name_full:
            return tool
    return None


class ModalTool:
    """What Live and Grab share: a timer, the header, the snapshot for a bit-exact cancel,
    and noticing that undo or a deletion replaced the data they hold (then they end
    cleanly instead of touching a removed object)."""

    @staticmethod
    def refuse_if_running():
        """Before anything changes: a second session is refused, the first goes on."""
        for tool in _running.values():
            raise engine.EdgeDeformError(
                "%s is already running on '%s': confirm it (Enter) or cancel it (Esc) "
                "first" % (tool.bl_label, tool.object_name))

    def start_modal(self, context, ob):
        self.ob = ob
        self.snapshot = snapshot.Snapshot(ob)
        self.generation = cache_handlers.generation()
        self.area = context.area
        self.workspace = context.workspace
        wm = context.window_manager
        self.timer = wm.event_timer_add(1.0 / 60.0, window=context.window)
        wm.modal_handler_add(self)
        self.object_name = ob.name_full
        _running[id(self)] = self

    def lost(self):
        """None while the tool's object is usable, else why not (for the report)."""
        if cache_handlers.generation() != self.generation:
            return "Undo (or a file load) replaced the scene data"
        try:
            name = self.ob.name_full
        except ReferenceError:
            return "the object was deleted"
        if bpy.data.objects.get(name) != self.ob:
            return "the object was deleted"
        return None

    def header(self, text):
        self.header_text = text   # (what the window tests read back)
        set_header(self.area, text)

    def hold_undo_steps(self, context):
        """One undo step per session: while the tool runs, the G/R/S moves inside it push
        no undo steps of their own (Global Undo off), so the step the tool pushes when it
        ends holds the whole session. end_modal puts the preference back on every exit
        path, before that step is pushed."""
        edit = context.preferences.edit
        self.global_undo = edit.use_global_undo
        edit.use_global_undo = False

    def end_modal(self, context):
        _running.pop(id(self), None)
        if getattr(self, "global_undo", None) is not None:
            context.preferences.edit.use_global_undo = self.global_undo
            self.global_undo = None
        try:
            context.window_manager.event_timer_remove(self.timer)
        except (ReferenceError, ValueError):
            pass
        if getattr(self, "header_text", None) is not None:
            self.header(None)   # (Live never sets it: the header stays Blender's)
        redraw_views(context)   # the panel stops saying the tool runs

    def restore(self, context):
        """Esc: the mesh back bit-exact (leaving Edit Mode first if the user entered it).
        After an undo the scene is Blender's restored step: nothing is written then.
        Returns a message when nothing could be restored, else None."""
        if cache_handlers.generation() != self.generation:
            self.snapshot.discard()
            return "Undo restored an earlier state; it is kept"
        ob = None if self.lost() else self.ob
        if ob is not None and ob.mode != 'OBJECT':
            with context.temp_override(object=ob, active_object=ob):
                compat.mode_set(ob, 'OBJECT')
        try:
            self.snapshot.restore(ob)
        except ReferenceError:
            return "the mesh was removed; nothing to restore"
        finally:
            self.snapshot.discard()
        return None
