"""Small helpers shared by the operators: polls, error reports and Edit-Mode round trips."""

import contextlib
import functools
import traceback

import bpy

from . import compat, engine


def deformed_object(context):
    """The mesh a tool works on: the active mesh, or the mesh whose handle the active
    object controls (the artist picked a controller to move it). None when neither."""
    ob = context.active_object
    if ob is None:
        return None
    if ob.type == 'MESH':
        return ob
    for other in context.scene.objects:
        s = getattr(other, "edge_deform", None) if other.type == 'MESH' else None
        if s is not None and any(h.controller == ob for h in s.handles):
            return other
    return None


def poll_mesh(cls, context, modes=None, need_handles=False, follow_controller=False):
    """True for an active mesh object in one of `modes` (or, with follow_controller, the
    mesh of the active controller); explains itself otherwise."""
    ob = deformed_object(context) if follow_controller else context.active_object
    msg = None
    if ob is None or ob.type != 'MESH':
        msg = "Select a mesh object"
    elif modes is not None and ob.mode not in modes:
        msg = {"EDIT": "Enter Edit Mode first", "OBJECT": "Leave Edit Mode first"}.get(
            modes[0], "Not available in this mode")
    elif need_handles and not ob.edge_deform.handles:
        msg = "Add a handle first"
    if msg is not None:
        if hasattr(cls, "poll_message_set"):
            cls.poll_message_set(msg)
        return False
    return True


def error_text(exc):
    """The message an artist sees for an exception (a bug still says what it was)."""
    if isinstance(exc, engine.USER_ERRORS):
        return "Edge Deform: %s" % exc
    # Not a user error: keep the details on the console, never a raw traceback.
    print("Edge Deform internal error:", "".join(
        traceback.format_exception_only(type(exc), exc)).strip())
    return "Edge Deform: internal error (%s: %s); please report it" % (
        type(exc).__name__, exc)


# Callables (level, text) told of every message the add-on gives (the tests listen here).
listeners = []


def tell(op, level, text):
    """Every message to the user goes through here: the status bar via op.report."""
    for listen in listeners:
        listen(level, text)
    op.report({level}, text)


def _reported(op, call):
    try:
        return call()
    except Exception as exc:  # noqa: BLE001 - reported, never re-raised
        tell(op, 'ERROR', error_text(exc))
        return {'CANCELLED'}


def guarded(method):
    """Wrap an operator's execute(self, context) or invoke(self, context, event): no
    exception escapes, the user gets a report. (Blender checks the argument count, so
    each form gets a wrapper of its own shape.)"""
    if method.__code__.co_argcount == 3:
        @functools.wraps(method)
        def invoke(self, context, event):
            return _reported(self, lambda: method(self, context, event))
        return invoke

    @functools.wraps(method)
    def execute(self, context):
        return _reported(self, lambda: method(self, context))
    return execute


# Callables (kind, text, fraction) told of long work: 'begin', 'update' (a new stage or
# fraction), 'drawn' (the status bar showed `text`: the user saw it) and 'end'.
progress_listeners = []


def _progress(kind, text, fraction):
    for listen in progress_listeners:
        listen(kind, text, fraction)


def _show_status(workspace, text, fraction):
    def draw(layout):
        layout.label(text=text, icon='TIME')
        _progress('drawn', text, fraction)
    compat.status_bar(workspace, draw)


@contextlib.contextmanager
def busy(context, text):
    """Long work on the main thread (Bind, Solve, Bake): Blender's progress indicator and
    wait cursor, and what is happening in the status bar, until the work ends.
    Yields update(fraction, text=None): how far the work got, and what it does now."""
    wm, window, workspace = context.window_manager, context.window, context.workspace
    _progress('begin', text, 0.0)
    wm.progress_begin(0.0, 1.0)
    if window is not None:
        window.cursor_modal_set('WAIT')
    _show_status(workspace, text, 0.0)

    def update(fraction, stage=None):
        wm.progress_update(fraction)
        if stage is not None:
            _show_status(workspace, stage, fraction)
        _progress('update', stage or text, fraction)

    try:
        yield update
    finally:
        wm.progress_end()
        if window is not None:
            window.cursor_modal_restore()
        compat.status_bar(workspace, None)
        _progress('end', text, 1.0)


class Stages:
    """Long work written as a generator of (fraction, text) before each stage, run one
    stage per advance() call, with busy()'s progress, wait cursor and status text from
    the first call until the work ends. Between calls Blender redraws, so the user sees
    what the next stage does before it runs. stop() (idempotent) closes the generator
    early: work written that way touches no bpy data before its last stage."""

    def __init__(self, context, text, steps):
        self.steps, self.stage = steps, text
        self.busy = busy(context, text)
        self.update = self.busy.__enter__()

    def advance(self):
        """Run the next stage: (True, the work's result) when it ended (then stopped),
        else (False, None) with the next stage's text shown. An exception stops it."""
        try:
            fraction, self.stage = next(self.steps)
        except StopIteration as done:
            self.stop()
            return True, done.value
        except BaseException:
            self.stop()
            raise
        self.update(fraction, self.stage)
        return False, None

    def run_to_end(self):
        while True:
            done, result = self.advance()
            if done:
                return result

    def stop(self):
        steps, self.steps = self.steps, None
        if steps is not None:
            steps.close()
            self.busy.__exit__(None, None, None)


def run_steps(context, text, steps):
    """Run long work written as a generator of (fraction, what it does next) in one go
    (scripts, EXEC_DEFAULT), with the progress shown; returns the generator's result."""
    return Stages(context, text, steps).run_to_end()


class StepsJob:
    """Long work from the UI, one step per timer tick (an operator mix-in): between steps
    Blender redraws, so the status bar says what the next step does, the progress
    advances, and Esc cancels. `steps` yields (fraction, text) before each step and
    returns the result; nothing may be written to bpy data before its last step, so a
    cancel leaves the data as it was. The operator defines job_done(context, result) and
    job_cancelled(context)."""

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
            return _reported(self, lambda: self.job_done(context, result))
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


def set_header(area, text):
    """The area's header text (None: Blender's own); nothing if there is no area or the
    user closed it meanwhile."""
    try:
        if area is not None:
            area.header_text_set(text)
    except ReferenceError:
        pass


# Regions of the viewport that lie over its main region: a key there is theirs.
OVER_THE_VIEW = {'HUD', 'UI', 'TOOLS', 'HEADER', 'TOOL_HEADER', 'NAVIGATION_BAR',
                 'ASSET_SHELF', 'ASSET_SHELF_HEADER'}


def over_the_view(area, event):
    """Is the pointer over `area`'s 3D view itself (not a field of the sidebar, the redo
    panel or a header lying over it)? Keys elsewhere belong to what is under the pointer."""
    if area is None:
        return False
    x, y = event.mouse_x, event.mouse_y
    view = False
    for region in area.regions:
        inside = (region.width > 1 and region.height > 1
                  and region.x <= x < region.x + region.width
                  and region.y <= y < region.y + region.height)
        if inside and region.type in OVER_THE_VIEW:
            return False
        view = view or (inside and region.type == 'WINDOW')
    return view


def redraw_views(context):
    """Redraw every 3D viewport (its sidebar too): the panel shows state that changed
    without a redraw of its own (bound, a tool ended)."""
    wm = getattr(context, "window_manager", None)
    for window in (wm.windows if wm is not None else ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def report_lines(op, lines):
    for level, text in lines:
        tell(op, level, text)


@contextlib.contextmanager
def object_mode(ob):
    """Temporarily leave Edit Mode: VertexGroup.add/remove and foreach_set need it."""
    previous = ob.mode
    if previous != 'OBJECT':
        compat.mode_set(ob, 'OBJECT')
    try:
        yield
    finally:
        if previous != 'OBJECT' and ob.mode != previous:
            compat.mode_set(ob, previous)


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
        from . import cache_handlers, snapshot
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
        from . import cache_handlers
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
        from . import cache_handlers
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
