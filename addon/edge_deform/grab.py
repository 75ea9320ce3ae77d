"""`grab`: drag the selected vertices in the view plane, the rest of the mesh follows.

Like G in Edit Mode: the motion follows the pointer in screen pixels from where it was
when the tool started (started from the panel's button, from where the pointer first
enters the viewport), nothing moves before the pointer does, X/Y/Z constrain the motion to
a global axis (press again to free it), Enter/click confirms, Esc/right click restores.
The mesh is shown in Object Mode while dragging (bpy can only write whole arrays there) and
Edit Mode comes back at the end, showing the dragged shape: with Output Shape Key the
output key becomes the active key, the one Edit Mode shows and edits. The drag starts from
the shape shown (mesh_io.addon_shape: after Bake, the frame on screen). Other handle groups stay
where they are shown; static vertices and vertices outside the region stay at rest. No
handle is needed: the dragged vertices are the handle (record 0068). On confirm, a handle
whose vertices were dragged holds them where they are (mesh_io.hold_at); how many dragged
vertices no handle holds is noted, for Live to say before a solve moves them.

A state machine (modal_rules.Grab), with Live's settle policy (modal_rules.Settle).
"""

import bpy
import numpy as np
from bpy_extras.view3d_utils import region_2d_to_location_3d
from mathutils import Vector

from . import compat, engine, lifecycle, mesh_io, modal, modal_rules, overlay
from .modal import ModalTool
from .modal_rules import Grab, GrabEvent, grab_next
from .op_common import error_text, guarded, over_the_view, poll_mesh, tell


AXES = {'X': 0, 'Y': 1, 'Z': 2}
NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'TRACKPADPAN',
              'TRACKPADZOOM', 'NDOF_MOTION'}


def view_region(context):
    """The 3D view's main region the tool drags in (also when started from the sidebar,
    whose own region has another size and origin): (region, its RegionView3D)."""
    region = context.region
    if region is not None and region.type == 'WINDOW':
        return region, context.region_data
    windows = [r for r in context.area.regions if r.type == 'WINDOW']
    for r in windows:
        if r.data == context.region_data:
            return r, r.data
    r = max(windows, key=lambda r: r.width * r.height)
    return r, r.data


NOTHING_HOLDS = ("Nothing holds the rest of the mesh (no Static, Region or other handle): it "
                 "follows the drag as a whole. Set Static, or press O for a radius, to keep it")


class EDGE_DEFORM_OT_grab(ModalTool, bpy.types.Operator):
    """Drag the selected vertices; the mesh deforms around them. X/Y/Z: axis, O:
    proportional, Wheel/Page Up/Down: its radius, Enter/click: confirm, Esc/right click:
    cancel"""
    bl_idname = "edge_deform.grab"
    bl_label = "Grab Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return (context.region_data is not None and context.window is not None
                and context.area is not None and context.area.type == 'VIEW_3D'
                and poll_mesh(cls, context, ('EDIT',)) and modal.idle(cls))

    @guarded
    def invoke(self, context, event):
        ob = context.active_object
        moving = np.flatnonzero(mesh_io.read_selection(ob))
        solver = None
        try:
            if moving.size == 0:
                raise mesh_io.EdgeDeformError("Select the vertices to drag")
            inputs = engine.gather_inputs(ob, require_handles=False)
            moving = np.setdiff1d(moving, inputs.static)
            if inputs.roi is not None:
                moving = np.intersect1d(moving, inputs.roi)
            if moving.size == 0:
                raise mesh_io.EdgeDeformError("The selection is static or outside the region")
            compat.mode_set(ob, 'OBJECT')
            solver = lifecycle.prepare(ob, inputs)
            current = mesh_io.addon_shape(ob)
            pinned = np.setdiff1d(inputs.handles, moving)
            self.held = np.concatenate([moving, pinned])
            self.moving = moving        # (hold measures the radius from them)
            self.group_region = None
            try:
                self.hold(solver, ob)
            except engine.NothingFree as exc:
                raise self.why_nothing_is_free(exc, solver) from None
        except Exception:
            if solver is not None:
                solver.release_grab()   # the settings' constraints return on the next sync
            if ob.mode != 'EDIT':
                compat.mode_set(ob, 'EDIT')
            raise
        self.solver = solver
        self.current = current
        self.written = None         # the last shape written
        self.start = current[moving]
        self.pinned = current[pinned]
        self.n_moving = moving.size
        self.mw = mesh_io.matrix_to_numpy(ob.matrix_world)
        self.depth = ob.matrix_world @ Vector(self.start.mean(axis=0))
        self.region, self.rv3d = view_region(context)
        self.mouse = self.in_region(event)
        # Nothing is solved before the pointer moves (as G moves nothing before): a shape
        # that had not settled (a baked frame) would move under a still pointer. From the
        # panel's button the pointer is over the sidebar, which lies over the view: the
        # drag counts from where the pointer reaches the view itself.
        self.origin = self.mouse if over_the_view(context.area, event) else None
        self.state = Grab.WAITING
        self.axis = None
        self.first = True           # the first solve starts from what is shown
        self.delta = np.zeros(3)
        self.settle = modal_rules.Settle()
        self.stats = ""
        self.refused = None         # why the last radius change was refused, for the header
        self.start_modal(context, ob)
        self.circles = overlay.RadiusCircles(self.area, self.circles_where)
        self.status_drawn = None    # the key hints Blender last drew in the status bar
        compat.status_bar(self.workspace, self.draw_status)
        self.show()
        if not (inputs.static.size or pinned.size or inputs.roi is not None
                or ob.edge_deform.proportional):
            # The energy's minimum is then the whole mesh carried along, which surprised an
            # artist used to G moving the selection only (the walk-through of 2026-12-05).
            tell(self, 'INFO', NOTHING_HOLDS)
        return {'RUNNING_MODAL'}

    def draw_status(self, layout):
        """The keys in the status bar, as Blender's G lists its own."""
        s = self.ob.edge_deform
        hints = ["Enter/Click: confirm", "Esc/Right click: cancel", "X/Y/Z: axis",
                 "O: proportional %s" % ("off" if s.proportional else "on")]
        if s.proportional:
            hints += ["Wheel/PgUp/PgDn: radius", "Alt+O: connected only"]
        for hint in hints:
            layout.label(text=hint)
        self.status_drawn = hints

    def hold(self, solver, ob):
        """The Deformer holds the dragged and the pinned vertices, with the settings'
        static vertices and region: proportional on, the radius around the dragged
        vertices (Blender measures from what it moves, not from the pinned handles); off,
        the Region group."""
        radius, connected = engine.region_radius(ob.edge_deform)
        roi = None if radius is not None else self.region_vertices(solver, ob)
        solver.hold_grab(self.held, solver.inputs.static, roi, radius, connected,
                         roi_from=self.moving if radius is not None else None)

    def why_nothing_is_free(self, exc, solver):
        """At the start (the keys do nothing yet): when every vertex within the radius of
        the selection is held, by the rest of a handle it is part of or by Static, say so
        rather than blame the radius."""
        inputs = solver.inputs
        pinned = np.setdiff1d(self.held, self.moving)
        if not modal.held_within(solver.binding.X, self.moving, exc.radius,
                                        np.concatenate([pinned, inputs.static])):
            return exc
        names = [g.group for g in inputs.handle_groups if np.isin(g.indices, pinned).any()]
        return modal.pinned_refusal(exc.radius, exc.connected, names)

    def region_vertices(self, solver, ob):
        """The Region group's vertices (None: the whole mesh). With proportional on at the
        start the group was not read (record 0056): it is read when O turns it off."""
        if solver.inputs.roi is not None or not ob.edge_deform.roi_group:
            return solver.inputs.roi
        if self.group_region is None:
            self.group_region = engine.gather_inputs(ob, require_handles=False).roi
        return self.group_region

    def change_region(self, name, value):
        """O, Alt+O, the wheel or Page Up/Down: the new region, solved from the shape shown
        (the handles stay where the pointer put them); when it frees no vertex, the
        previous one is kept and the header says why."""
        s = self.ob.edge_deform
        before = getattr(s, name)
        setattr(s, name, value)
        self.refused = None
        try:
            self.hold(self.solver, self.ob)
        except mesh_io.EdgeDeformError as exc:
            setattr(s, name, before)
            self.hold(self.solver, self.ob)
            self.refused = modal.short_kept(exc, s)
            tell(self, 'WARNING', modal.kept(exc, s))
        if self.written is not None:
            self.current = self.written   # the next solve starts from the shape shown
        self.first = True
        if self.state != Grab.WAITING:
            self.go(GrabEvent.MOVED)
        self.show()

    def circles_where(self):
        """Around the dragged vertices where the pointer has put them."""
        return modal.circles(self.ob, [self.start + self.delta])

    def go(self, event):
        self.state = grab_next(self.state, event)

    def in_region(self, event):
        """The pointer in the view region's pixels (events from the sidebar count in
        the sidebar's)."""
        return (event.mouse_x - self.region.x, event.mouse_y - self.region.y)

    def offset(self):
        """Pointer motion since the origin, in the view plane through the dragged
        vertices, as an object-space vector."""
        p0 = region_2d_to_location_3d(self.region, self.rv3d, self.origin, self.depth)
        p1 = region_2d_to_location_3d(self.region, self.rv3d, self.mouse, self.depth)
        d = np.array(p1 - p0, np.float64)
        if self.axis is not None:
            keep = np.zeros(3)
            keep[self.axis] = 1.0
            d = d * keep
        return np.linalg.solve(self.mw[:3, :3], d)

    def update(self):
        """One tick of solving: the pointer's targets, iterated for the tick's budget."""
        s = self.ob.edge_deform
        moving = self.state == Grab.DRAGGING
        if moving:
            self.settle.changed()
        self.delta = self.offset()
        targets = np.concatenate([self.start + self.delta, self.pinned])

        def solve(n, check_claims):
            if self.first:
                # From the shape shown, first a few iterations where it holds the dragged
                # vertices, then on to the pointer (warm), as when Grab solved before the
                # pointer moved: a cold start straight at a far target can stall (the
                # plane, a 0.27 drag: 2,000 iterations unconverged; this way 1,660, settled).
                self.first = False
                self.solver.solve(self.current[self.held], modal_rules.LEAST_ITERATIONS,
                                  s.tolerance, warm=True, initial=self.current,
                                  check_claims=False)
            return self.solver.solve(targets, n, s.tolerance, warm=True,
                                     check_claims=check_claims)
        try:
            r = self.settle.tick(solve, moving, system=self.solver.binding.system)
            self.solver.write(r.positions)
            self.written = r.positions
        except Exception as exc:  # noqa: BLE001 - shown; the next move retries
            tell(self, 'ERROR', error_text(exc))
            self.go(GrabEvent.FAILED)
            return
        self.go(GrabEvent.SETTLED if self.settle.at_rest else GrabEvent.ITERATED)
        self.stats = modal_rules.describe(self.settle, "move the mouse")
        self.show()

    def show(self):
        """Blender's G way: the tool's state in the header while it runs, short enough for
        a narrow view (its keys are in the status bar, as G's are)."""
        s = self.ob.edge_deform
        region = self.refused or modal.describe_region(s, self.settle.runs_long)
        if self.state == Grab.WAITING:
            self.header("Grab Deform: %d vertices | move the pointer in the view to drag | %s"
                        % (self.n_moving, region))
            return
        axis = "along %s" % "XYZ"[self.axis] if self.axis is not None else "free"
        self.header("Grab Deform: %d vertices | D: %.4g %s | %s | %s"
                    % (self.n_moving, float(np.linalg.norm(self.mw[:3, :3] @ self.delta)),
                       axis, region, self.stats))

    def modal(self, context, event):
        try:
            why = self.lost()
            if why is not None:
                self.end_modal(context)
                self.snapshot.discard()
                tell(self, 'WARNING', "Grab Deform ended: " + why)
                return {'CANCELLED'}
            return self.handle(context, event)
        except Exception as exc:  # noqa: BLE001 - never leave a broken modal behind
            tell(self, 'ERROR', error_text(exc))
            return self.end(context, {'CANCELLED'}, restore=True)

    def handle(self, context, event):
        s = self.ob.edge_deform
        toggled = modal.toggle_key(event)
        factor = modal.size_key(event) if s.proportional else None
        if toggled is not None:
            self.change_region(toggled, not getattr(s, toggled))
        elif factor is not None:
            self.change_region("proportional_radius", modal.resized(s, factor))
        elif event.type == 'MOUSEMOVE':
            self.mouse = self.in_region(event)
            if self.state == Grab.WAITING:
                if over_the_view(self.area, event):
                    if self.origin is None:
                        self.origin = self.mouse
                    elif self.mouse != self.origin:
                        self.go(GrabEvent.STARTED)
                    self.show()
            else:
                self.refused = None     # (the refusal was reported; the drag goes on)
                self.go(GrabEvent.MOVED)
        elif event.type == 'TIMER':
            if self.state in (Grab.DRAGGING, Grab.SETTLING):
                self.update()
        elif event.type in AXES and event.value == 'PRESS':
            axis = AXES[event.type]
            self.axis = None if self.axis == axis else axis
            if self.state != Grab.WAITING:
                self.go(GrabEvent.MOVED)
            self.show()
        elif event.type in {'RET', 'NUMPAD_ENTER', 'LEFTMOUSE'} and event.value == 'PRESS':
            if self.state == Grab.DRAGGING:
                self.update()
            return self.end(context, {'FINISHED'})
        elif event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            return self.end(context, {'CANCELLED'}, restore=True)
        elif event.type in NAVIGATION:
            return {'PASS_THROUGH'}
        return {'RUNNING_MODAL'}

    def end(self, context, result, restore=False):
        self.circles.remove()
        compat.status_bar(self.workspace, None)
        self.end_modal(context)
        self.solver.release_grab()   # the settings' handles return on the next sync
        if restore:
            self.restore(context)
        else:
            self.snapshot.discard()
            self.keep_the_edit()
            self.show_output_in_edit_mode()
        if self.ob.mode != 'EDIT':
            with context.temp_override(object=self.ob, active_object=self.ob):
                compat.mode_set(self.ob, 'EDIT')
        return result

    def keep_the_edit(self):
        """Confirmed: handles whose vertices were dragged hold them where they are now;
        the dragged vertices no handle holds are counted (mesh_io.note_unheld_edit)."""
        if self.written is None or self.lost():
            return
        inputs, mesh = self.solver.inputs, self.ob.data
        rest = self.solver.binding.X
        for g in inputs.handle_groups:
            dragged = np.intersect1d(g.indices, self.moving)
            if dragged.size:
                motion = None if g.controller is None else np.array(
                    self.ob.matrix_world.inverted_safe() @ g.controller.matrix_world
                    @ g.rest_inverse)
                mesh_io.hold_at(mesh, rest, dragged, self.written[dragged], motion)
        mesh_io.note_unheld_edit(mesh, np.setdiff1d(self.moving, inputs.handles).size)

    def show_output_in_edit_mode(self):
        """Edit Mode shows (and edits) the active shape key: make it the output key, so
        the artist sees the mesh as dragged (Esc's snapshot keeps the previous one)."""
        kb = mesh_io.owned_key(self.ob.data)
        if self.ob.edge_deform.output == 'SHAPE_KEY' and kb is not None:
            index = self.ob.data.shape_keys.key_blocks.find(kb.name)
            if self.ob.active_shape_key_index != index:
                self.ob.active_shape_key_index = index

    def cancel(self, context):   # Blender closes the window or quits
        self.end(context, {'CANCELLED'}, restore=True)


CLASSES = (EDGE_DEFORM_OT_grab,)
