"""`live`: a modal tool that re-solves whenever a controller (or the object) moves.

Controllers are moved by anything (G/R/S, gizmos, drivers, scripts): every timer tick the
transforms are compared with the last solved ones; a change (or an unconverged previous
solve) triggers one warm-started solve and a write through lifecycle.py. Each tick runs at
most the settings' iterations and no more than fit in ~40 ms, so big meshes stay responsive
and converge over the following ticks. Only this main-thread timer touches bpy.

While the object is in another mode (the user entered Edit Mode from the menu) the tool
pauses; back in Object Mode it binds again (the topology may have changed). Undo or the
object's deletion end it cleanly.
"""

import time

import bpy

from . import engine, lifecycle
from .op_common import ModalTool, error_text, guarded, poll_mesh, tell

LAMBDA_STEP = 0.05
KEYS_UP = {'WHEELUPMOUSE', 'NUMPAD_PLUS', 'PLUS', 'EQUAL'}
KEYS_DOWN = {'WHEELDOWNMOUSE', 'NUMPAD_MINUS', 'MINUS'}


def in_region(area, event, region_type='WINDOW'):
    """Is the mouse over the given region of `area`? (panels and headers stay usable)"""
    if area is None:
        return False
    for region in area.regions:
        if region.type == region_type:
            return (region.x <= event.mouse_x < region.x + region.width
                    and region.y <= event.mouse_y < region.y + region.height)
    return False


class EDGE_DEFORM_OT_live(ModalTool, bpy.types.Operator):
    """Deform live while controllers move. Wheel/+/-: λ, Tab: domain,
    Enter/click: confirm, Esc/right click: cancel"""
    bl_idname = "edge_deform.live"
    bl_label = "Live Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return context.window is not None and poll_mesh(
            cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def invoke(self, context, event):
        ob = context.active_object
        s = ob.edge_deform
        self.bound = lifecycle.prepare(ob)          # refuses before anything changes
        self.saved_settings = (s.stiffness, s.domain)
        self.saved_controllers = [(g.controller, g.controller.matrix_world.copy())
                                  for g in self.bound.inputs.handle_groups if g.controller]
        self.settings_state = self.saved_settings
        self.controllers_state = None
        self.converged = False
        self.paused = False
        self.problem = None
        self.refused_for = None
        self.stats = "no solve yet"
        self.updates = 0
        self.budget = engine.IterationBudget()
        self.start_modal(context, ob)
        for w in self.bound.warnings():
            tell(self, 'WARNING', w)
        self.update(context)
        return {'RUNNING_MODAL'}

    # ------------------------------------------------------------ per tick

    def update(self, context):
        ob, s = self.ob, self.ob.edge_deform
        if ob.mode != 'OBJECT':
            self.paused = True          # Blender's own tools own the mesh now
            self.show("paused: back to Object Mode to continue")
            return
        if self.bound is None and self.refused_for == self.settings_key():
            return                      # refused: wait until the user changes something
        try:
            if (self.paused or self.bound is None
                    or lifecycle.output_settings(ob) != self.bound.output):
                self.rebind()
            settings_state = (s.stiffness, s.domain)
            if settings_state != self.settings_state:
                self.bound.settings_changed()
                self.settings_state = settings_state
                self.converged = False
            try:
                state = engine.controller_state(ob, self.bound.inputs)
            except ReferenceError:      # a controller was deleted: read the settings again
                self.rebind()
                state = engine.controller_state(ob, self.bound.inputs)
            if state == self.controllers_state and self.converged:
                return
            self.controllers_state = state
            t0 = time.perf_counter()
            r = self.bound.solve(self.bound.targets(), self.budget.iterations(s.iterations),
                                 s.tolerance, warm=True)
            self.budget.record(r, (time.perf_counter() - t0) * 1e3)
            self.bound.write(r.positions)
        except Exception as exc:  # noqa: BLE001 - shown, and retried on the next change
            if self.bound is None:
                self.refused_for = self.settings_key()
            message = error_text(exc)
            if message != self.problem:
                tell(self, 'ERROR', message)
            self.problem = message
            self.converged = True
            self.show(message)
            return
        self.problem = None
        _, text, self.converged = engine.status(r, (time.perf_counter() - t0) * 1e3)
        self.updates += 1
        self.stats = text
        self.show(self.stats)

    def settings_key(self):
        """What the user may change to fix a refusal (settings, groups, mode)."""
        ob, s = self.ob, self.ob.edge_deform
        return (ob.mode, s.output, s.shape_key_name, s.static_group, s.roi_group,
                s.stiffness_group, s.domain, tuple(h.vertex_group for h in s.handles),
                tuple(g.name for g in ob.vertex_groups), ob.data.edge_deform_state.written)

    def rebind(self):
        """After a mode switch, an Output change or a deleted controller: check and read
        everything again."""
        self.paused = False
        self.bound = None
        self.bound = lifecycle.prepare(self.ob)
        self.settings_state = (self.ob.edge_deform.stiffness, self.ob.edge_deform.domain)
        self.controllers_state = None
        self.converged = False
        for w in self.bound.warnings():
            tell(self, 'WARNING', w)

    def show(self, stats):
        s = self.ob.edge_deform
        lam = "group" if s.stiffness_group else "%.2f" % s.stiffness
        self.header("Edge Deform live | move controllers: G/R/S, gizmo | Wheel/+/-: λ %s | "
                    "Tab: domain %s | Enter/Click: confirm | Esc/Right click: cancel | %s"
                    % (lam, s.domain.title(), stats))

    # ------------------------------------------------------------ events

    def modal(self, context, event):
        try:
            why = self.lost()
            if why is not None:
                return self.abandon(context, why)
            return self.handle(context, event)
        except Exception as exc:  # noqa: BLE001 - never leave a broken modal behind
            tell(self, 'ERROR', error_text(exc))
            self.end_modal(context)
            return {'CANCELLED'}

    def handle(self, context, event):
        s = self.ob.edge_deform
        if event.type == 'TIMER':
            self.update(context)
            return {'PASS_THROUGH'}
        if event.value == 'PRESS' and self.ob.mode == 'OBJECT':
            if event.type in KEYS_UP | KEYS_DOWN and not (event.ctrl or event.alt):
                step = LAMBDA_STEP if event.type in KEYS_UP else -LAMBDA_STEP
                s.stiffness = min(1.0, max(0.0, round(s.stiffness + step, 4)))
                self.update(context)
                return {'RUNNING_MODAL'}
            if event.type == 'TAB':
                s.domain = 'PRIMAL' if s.domain == 'EDGE' else 'EDGE'
                self.update(context)
                return {'RUNNING_MODAL'}
            if event.type in {'RET', 'NUMPAD_ENTER'}:
                return self.finish(context)
            if event.type == 'Z' and (event.ctrl or event.oskey):
                tell(self, 'WARNING', "Confirm or cancel Live Deform before undoing")
                return {'RUNNING_MODAL'}
        if event.value == 'PRESS' and event.type in {'ESC', 'RIGHTMOUSE'}:
            return self.cancel_and_restore(context)
        if (event.type == 'LEFTMOUSE' and event.value == 'CLICK' and self.ob.mode == 'OBJECT'
                and in_region(self.area, event)):
            return self.finish(context)
        return {'PASS_THROUGH'}

    def finish(self, context):
        self.update(context)   # the last controller move may not be solved yet
        self.end_modal(context)
        self.snapshot.discard()
        lifecycle.forget_cache(self.ob.data)
        tell(self, 'INFO', "Live Deform: %d updates, %s" % (self.updates, self.stats))
        return {'FINISHED'}

    def cancel_and_restore(self, context):
        self.end_modal(context)
        s = self.ob.edge_deform
        why = self.restore(context)
        s.stiffness, s.domain = self.saved_settings
        for controller, matrix in self.saved_controllers:
            try:
                controller.matrix_world = matrix
            except ReferenceError:
                pass            # the controller was deleted meanwhile
        if why is not None:
            tell(self, 'WARNING', "Live Deform cancelled: " + why)
        return {'CANCELLED'}

    def abandon(self, context, why):
        """The object or the scene data went away under the tool: end without writing."""
        self.end_modal(context)
        if "deleted" in why:
            self.restore(context)   # the mesh may still exist: put it back as it was
        else:
            self.snapshot.discard()
        tell(self, 'WARNING', "Live Deform ended: " + why)
        return {'CANCELLED'}

    def cancel(self, context):   # Blender closes the window, quits or loads a file
        self.end_modal(context)
        self.snapshot.discard()


CLASSES = (EDGE_DEFORM_OT_live,)
