"""What the modal tools (Live, Grab) share: one tool at a time, a timer, the header, one
undo step per session, noticing that undo or a deletion replaced the data they hold; the
operators greyed while a tool runs; proportional editing's keys and words; the snapshot
for a bit-exact cancel. Their states and settle policy are modal_rules.py's (no bpy)."""

import bpy
import numpy as np

from . import compat, engine, lifecycle, mesh_io
from .op_common import deformed_object, poll_mesh, redraw_views, set_header


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

    def start_modal(self, context, ob):
        self.ob = ob
        self.snapshot = Snapshot(ob)
        self.generation = lifecycle.generation()
        self.area = context.area
        self.workspace = context.workspace
        wm = context.window_manager
        self.timer = wm.event_timer_add(1.0 / 60.0, window=context.window)
        wm.modal_handler_add(self)
        self.object_name = ob.name_full
        _running[id(self)] = self

    def lost(self):
        """None while the tool's object is usable, else why not (for the report)."""
        if lifecycle.generation() != self.generation:
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
        if lifecycle.generation() != self.generation:
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


# ------------------------------------------------------------------ greyed while a tool runs
# While Live Deform or Grab Deform runs on a mesh it owns that mesh's shape: the
# operators that would rewrite or rebind it (Bind, Solve, Apply, Unbind, Bake) fail their
# poll, so Blender greys their buttons and menu entries and their tooltip says why, instead
# of looking enabled and then refusing (docs/decisions/0040, 0068).

def poll(cls, context, on_controller=True):
    """The poll of an Object-Mode operator that rewrites or rebinds a mesh: a mesh with
    handles (with `on_controller`, also the mesh of the active controller; else the active
    object, handles or not) on which no modal tool runs."""
    if not poll_mesh(cls, context, ('OBJECT',), need_handles=on_controller,
                     follow_controller=on_controller):
        return False
    return idle(cls, deformed_object(context) if on_controller else context.active_object)


def idle(cls, ob=None):
    """For an operator's poll: False while a modal tool runs on `ob` (on any mesh when `ob`
    is None: Live and Grab, one tool at a time; an enabled button whose click was refused
    opened an error report that swallowed the next Esc), with the reason as the poll
    message (the greyed button's tooltip; a script's error)."""
    tool = running_tool(ob)
    if tool is None:
        return True
    where = ("is running on '%s' and deforms it already" if ob is not None
             else "is already running on '%s'") % tool.object_name
    if hasattr(cls, "poll_message_set"):
        cls.poll_message_set("%s %s: press Enter over the view to keep its shape or Esc to "
                             "cancel" % (tool.bl_label, where))
    return False


# ------------------------------------------------------------------ proportional editing
# The proportional radius in the artist's terms: Blender's keys and steps for it, a first
# radius that fits the object, its words for the header and the text over the view, the
# circles drawn around what moves, and the plain refusal when it frees no vertex. No solver
# state: the radius lives on the object (properties.py), the region it picks in the core
# (Deformer.set_constraints(roi_radius=...), docs/decisions/0056 and 0066).

# Blender's transform (keymap "Transform Modal Map", transform.c): Page Up and the wheel
# pulled down grow the size by 1.1, Page Down and the wheel pushed up shrink it; with
# Shift by 1.01.
STEP, FINE_STEP = 1.1, 1.01
GROW = {'PAGE_UP', 'WHEELDOWNMOUSE'}
SHRINK = {'PAGE_DOWN', 'WHEELUPMOUSE'}
SMALLEST = 1e-6     # the property's minimum (Blender's T_PROP_SIZE_MIN)
KEYS = "Wheel/PgUp/PgDn: radius · O: proportional · Alt+O: connected"


def size_key(event):
    """The factor a wheel or Page key multiplies the radius by, or None (another key, or
    with Ctrl/Alt, which stay the view's and the stiffness keys')."""
    if event.ctrl or event.alt or event.oskey or event.value != 'PRESS':
        return None
    step = FINE_STEP if event.shift else STEP
    if event.type in GROW:
        return step
    if event.type in SHRINK:
        return 1.0 / step
    return None


def resized(settings, factor):
    """The radius after one step of `factor` (never below Blender's smallest size)."""
    return max(SMALLEST, settings.proportional_radius * factor)


def toggle_key(event):
    """'proportional' for O, 'proportional_connected' for Alt+O (Blender's keys), or None."""
    if event.type != 'O' or event.value != 'PRESS' or event.ctrl or event.shift:
        return None
    return "proportional_connected" if event.alt else "proportional"


def describe_region(settings, running_long=False):
    """What the header and the text over the view say about the region; with
    `running_long` (a whole-mesh settle has run long), that a radius would be quicker."""
    if not settings.proportional:
        return ("Proportional: off (O: a radius makes it local and quick)" if running_long
                else "Proportional: off (O: on)")
    return "Proportional: %s%s" % (engine.length(settings.proportional_radius),
                                   ", connected only" if settings.proportional_connected
                                   else "")


LONG_SETTLE_HINT = ("The whole mesh is still settling: Proportional (O) with a radius "
                    "(Wheel, Page Up/Down) makes the edit local and quick")
OFF_CONTINUES = ("Proportional off: the whole mesh settles on from the shape shown (a "
                 "Solve from the rest may settle on another shape)")


def kept(exc, settings):
    """A running tool's words for a radius or toggle that freed nothing: the reason and
    the radius kept (its keys are over the view or in the status bar)."""
    reason = exc.reason if isinstance(exc, engine.NothingFree) else str(exc)
    return "%s; kept %s" % (reason, describe_region(settings))


def short_kept(exc, settings):
    """kept() for a header: "Proportional: 4.77 cm kept (4.33 cm frees no vertex)"."""
    if not isinstance(exc, engine.NothingFree):
        return kept(exc, settings)
    return "%s kept (%s frees no vertex)" % (describe_region(settings),
                                             engine.length(exc.radius))


def held_within(X, sources, radius, held):
    """Do the vertices within `radius` of `sources` (rest positions X, straight distance),
    other than the sources, all belong to `held`, and is there one? Grab's refusal then
    blames what holds them, not the radius. Chunked: the error path of a big mesh."""
    lo, hi = X[sources].min(axis=0) - radius, X[sources].max(axis=0) + radius
    near = np.flatnonzero(np.all((X >= lo) & (X <= hi), axis=1))
    near = np.setdiff1d(near, sources)
    within = np.zeros(near.size, bool)
    for i in range(0, len(sources), 16):
        d = np.linalg.norm(X[near, None, :] - X[None, sources[i:i + 16], :], axis=2)
        within |= d.min(axis=1, initial=np.inf) <= radius
    inside = near[within]
    return inside.size > 0 and bool(np.isin(inside, held).all())


def pinned_refusal(radius, connected, names):
    """Grab's refusal when every vertex within the radius of the selection is held: by
    the rest of handles `names` (Grab holds a handle's unselected vertices where they
    are), or by Static."""
    held = ("the rest of handle%s %s" % ("s" if len(names) > 1 else "",
                                           ", ".join("'%s'" % n for n in names))
            if names else "Static")
    return engine.NothingFree(radius, connected, reason=(
        "No vertex can move within %s of the selection: %s holds every vertex there "
        "(Grab holds a handle's vertices you did not select)" % (engine.length(radius), held)))


def circles(ob, groups):
    """[(world centre, world radius)] of the circles drawn around `groups` ((k,3) object-
    space points each: the handles that move, where they are now), [] while proportional
    is off."""
    s = ob.edge_deform
    if not s.proportional:
        return []
    from mathutils import Vector
    scale = sum(abs(v) for v in ob.matrix_world.to_scale()) / 3.0
    return [(ob.matrix_world @ Vector(tuple(float(v) for v in points.mean(axis=0))),
             s.proportional_radius * scale) for points in groups if len(points)]


# ------------------------------------------------------------------ the snapshot
# Cancel's exact restore: a Snapshot of everything a modal tool may change, put back
# bit-exact on Esc (or when the tool's object was deleted under it).

class Snapshot:
    """Everything a modal tool may change, for a bit-exact cancel: the vertices, every
    shape key (positions, value, mute), the active key, the stored state and rest, and a
    full copy of the mesh for when the topology changed meanwhile (an edit during Live)."""

    def __init__(self, ob):
        mesh = ob.data
        self.mesh = mesh
        self.digest = mesh_io.topology_digest(mesh)
        self.co = mesh_io.read_positions32(mesh)
        keys = mesh.shape_keys
        self.keys = None if keys is None else [
            (kb.name, mesh_io.read_key(kb), kb.value, kb.mute) for kb in keys.key_blocks]
        self.active = ob.active_shape_key_index
        self.stored = mesh_io.stored_state(mesh)
        self.copy = mesh.copy()

    def _arrays_fit(self, mesh):
        if mesh_io.topology_digest(mesh) != self.digest:
            return False
        names = [] if mesh.shape_keys is None else mesh.shape_keys.key_blocks.keys()
        return self.keys is None or all(k[0] in names for k in self.keys)

    def restore(self, ob):
        """Put the mesh back as it was (the object must be in Object Mode, or deleted:
        ob None). Returns the mesh, which is a new datablock after a topology change."""
        mesh = self.mesh
        if not self._arrays_fit(mesh):
            name = mesh.name
            mesh.user_remap(self.copy)   # every object using the mesh gets the copy
            bpy.data.meshes.remove(mesh)
            self.copy.name = name
            self.mesh, self.copy = self.copy, None
            return self.mesh
        mesh_io.write_positions(mesh, self.co)
        with _any_object(ob, mesh) as owner:
            keys = mesh.shape_keys
            if self.keys is None:
                if keys is not None:
                    owner.shape_key_clear()
            else:
                names = [k[0] for k in self.keys]
                for kb in [kb for kb in keys.key_blocks if kb.name not in names]:
                    owner.shape_key_remove(kb)
                for name, co, value, mute in self.keys:
                    kb = keys.key_blocks[name]
                    mesh_io.write_key(kb, co)
                    kb.value, kb.mute = value, mute
                owner.active_shape_key_index = self.active
                keys.update_tag()
        mesh_io.restore_stored_state(mesh, self.stored)
        mesh.update()
        # The graph stays (a cancelled Live on an unbound mesh left it "Not bound" and the
        # next Live bound again: 4.5 s on a 44k mesh): the cache checks the topology and
        # the rest before it uses it. The next solve starts cold, not from the cancelled
        # shape.
        engine.start_cold(mesh)
        return mesh

    def discard(self):
        """Free the copy (the tool ended). Safe after undo removed it."""
        copy, self.copy = self.copy, None
        try:
            if copy is not None and copy.name in bpy.data.meshes \
                    and bpy.data.meshes[copy.name] == copy:
                bpy.data.meshes.remove(copy)
        except ReferenceError:
            pass


class _any_object:
    """An object using `mesh` for the Object-level shape-key calls: `ob`, or a temporary
    one when the object was deleted and only the mesh is left."""

    def __init__(self, ob, mesh):
        self.ob, self.mesh, self.temporary = ob, mesh, None

    def __enter__(self):
        if self.ob is not None and self.ob.data == self.mesh:
            return self.ob
        self.temporary = bpy.data.objects.new(".EdgeDeformRestore", self.mesh)
        return self.temporary

    def __exit__(self, *exc):
        if self.temporary is not None:
            bpy.data.objects.remove(self.temporary)
        return False
