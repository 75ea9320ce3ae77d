"""What every operator shares: polls, error texts and reports (every message to the user
goes through `tell`), and small view helpers (headers, redraws, the pointer over the view,
Edit-Mode round trips), and long work's progress (the progress indicator, the wait cursor,
the status bar). Timer-driven jobs are operators_bind.StepsJob, the modal tools' base
modal.ModalTool."""

import contextlib
import functools
import traceback

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


def call_reporting_errors(op, call):
    """call(); an exception becomes an error report (never re-raised)."""
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
            return call_reporting_errors(self, lambda: method(self, context, event))
        return invoke

    @functools.wraps(method)
    def execute(self, context):
        return call_reporting_errors(self, lambda: method(self, context))
    return execute


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


def select_only(layer, ob):
    """Make `ob` the active and only selected object of the view layer `layer`."""
    for other in layer.objects:
        if other is not None and other != ob:   # (None right after objects were removed)
            other.select_set(False)
    ob.select_set(True)
    layer.objects.active = ob


def redraw_views(context):
    """Redraw every 3D viewport (its sidebar too): the panel shows state that changed
    without a redraw of its own (bound, a tool ended)."""
    wm = getattr(context, "window_manager", None)
    for window in (wm.windows if wm is not None else ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()
                # Blender 4.3 redraws the sidebar only when its own region is tagged: the
                # panel kept saying Bind after Bind until the pointer crossed it.
                for region in area.regions:
                    region.tag_redraw()


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


# ------------------------------------------------------------------ long work's progress
# Long work on the main thread (Bind, Solve, Bake, Live's domain switch): Blender's
# progress indicator, the wait cursor and what happens in the status bar, while a generator
# of stages runs. The tests listen to `progress_listeners`.

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
def showing_progress(context, text):
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
        self.busy = showing_progress(context, text)
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
