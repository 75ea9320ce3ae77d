"""`live`: a modal tool that re-solves whenever a controller (or the object) moves.

Controllers are moved by anything (G/R/S, gizmos, drivers, scripts): every timer tick the
transforms are compared with the last solved ones; a change (or an unconverged previous
solve) triggers one warm-started solve and a write through lifecycle.py. Each tick runs at
most the settings' iterations and no more than fit in ~40 ms, so big meshes stay responsive
and converge over the following ticks, or stop after engine.SETTLE_LIMIT iterations since
the last change and say so. Only this main-thread timer touches bpy.

While the object is in another mode (the user entered Edit Mode from the menu) the tool
pauses; back in Object Mode it binds again (the topology may have changed). Undo or the
object's deletion end it cleanly.

A domain change (from the panel) needs a new graph, built and factored: seconds on a big
mesh. Live runs it as stages, one per tick (op_common.Stages): the status bar names each
stage before it runs, with the progress and the wait cursor; Esc between stages keeps the
previous domain and its graph, the mesh untouched (nothing is written until it is done).
"""

import time

import bpy

from . import compat, engine, lifecycle
from .op_common import ModalTool, Stages, error_text, guarded, poll_mesh, tell

LAMBDA_STEP = 0.05
# λ keys that shadow no navigation: ] / [ and Ctrl+wheel (the plain wheel and numpad +/-
# zoom, Tab switches modes, clicks select: Live passes all of them on).
KEYS_UP = {'RIGHT_BRACKET', 'WHEELUPMOUSE'}
KEYS_DOWN = {'LEFT_BRACKET', 'WHEELDOWNMOUSE'}
WHEEL = {'WHEELUPMOUSE', 'WHEELDOWNMOUSE'}


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
    """Deform the mesh while you move its controllers (select and move them as usual).
    [ ] or Ctrl+Wheel: stiffness, Enter: keep, Esc: cancel"""
    bl_idname = "edge_deform.live"
    bl_label = "Live Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return context.window is not None and poll_mesh(
            cls, context, ('OBJECT',), need_handles=True)

    @guarded
    def invoke(self, context, event):
        self.refuse_if_running()
        ob = context.active_object
        s = ob.edge_deform
        self.bound = lifecycle.prepare(ob)          # refuses before anything changes
        self.saved_settings = (s.stiffness, s.domain)
        self.saved_controllers = [(g.controller, g.controller.matrix_world.copy())
                                  for g in self.bound.inputs.handle_groups if g.controller]
        self.settings_state = self.saved_settings
        self.controllers_state = None
        self.at_rest = False        # converged, or gave up settling: idle until a change
        self.paused = False
        self.problem = None
        self.switch = None          # a domain switch in progress (Stages), see start_switch
        self.refused_for = None
        self.stats = "no solve yet"
        self.updates = 0
        self.settle_iterations, self.settle_ms = 0, 0.0   # since the last change
        self.budget = engine.IterationBudget()
        self.start_modal(context, ob)
        self.hold_undo_steps(context)
        for w in self.bound.warnings():
            tell(self, 'WARNING', w)
        self.update(context)
        return {'RUNNING_MODAL'}

    # ------------------------------------------------------------ per tick

    def update(self, context):
        ob, s = self.ob, self.ob.edge_deform
        if self.switch is not None:
            self.advance_switch()
            return
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
            if s.domain != self.bound.binding.domain:
                self.start_switch(context)
                return
            if settings_state != self.settings_state:
                self.bound.settings_changed()
                self.settings_state = settings_state
                self.at_rest = False
                self.settle_iterations, self.settle_ms = 0, 0.0
            try:
                state = engine.controller_state(ob, self.bound.inputs)
            except ReferenceError:      # a controller was deleted: read the settings again
                self.rebind()
                state = engine.controller_state(ob, self.bound.inputs)
            if state == self.controllers_state and self.at_rest:
                return
            if state != self.controllers_state:
                self.settle_iterations, self.settle_ms = 0, 0.0
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
            self.at_rest = True
            self.show(message)
            return
        self.problem = None
        self.settle_iterations += r.iterations
        self.settle_ms += (time.perf_counter() - t0) * 1e3
        text, self.at_rest = engine.settle_status(r, self.settle_ms, self.settle_iterations,
                                                  "move a controller")
        self.updates += 1
        self.stats = text
        self.show(self.stats)

    # ------------------------------------------------------------ domain switch

    def start_switch(self, context):
        """Begin building the new domain's graph: this tick only shows what comes."""
        s = self.ob.edge_deform
        self.switch_from = self.bound.binding.domain
        self.switch_to = (s.stiffness, s.domain)
        inputs = engine.with_global_changes(self.bound.inputs, self.ob)
        self.switch = Stages(context, "Live Deform: switching to the %s graph…" % (
            "edge" if s.domain == 'EDGE' else "vertex"),
            lifecycle.prepare_steps(self.ob, inputs, what="Live Deform"))
        self.header("%s  (Esc: keep the previous domain)" % self.switch.stage)

    def advance_switch(self):
        """One stage of the switch per tick; at its end Live solves with the new graph."""
        try:
            done, bound = self.switch.advance()
        except Exception as exc:  # noqa: BLE001 - the previous domain stays in use
            self.switch = None
            self.ob.edge_deform.domain = self.switch_from
            tell(self, 'ERROR', error_text(exc) + " (the previous domain is kept)")
            self.show(self.stats)
            return
        if not done:
            self.header("%s  (Esc: keep the previous domain)" % self.switch.stage)
            return
        self.switch = None
        self.bound, self.settings_state = bound, self.switch_to
        self.controllers_state, self.at_rest = None, False
        self.settle_iterations, self.settle_ms = 0, 0.0
        self.budget = engine.IterationBudget()   # the new graph has its own speed
        self.show("new graph ready, solving…")

    def cancel_switch(self):
        """Esc during a switch: the previous domain and graph stay; nothing was written."""
        self.switch.stop()
        self.switch = None
        self.ob.edge_deform.domain = self.switch_from
        tell(self, 'WARNING', "Domain switch cancelled: the %s graph is kept" % (
            "edge" if self.switch_from == 'EDGE' else "vertex"))
        self.show(self.stats)

    def end_modal(self, context):
        if self.switch is not None:   # (any way out: the progress and cursor end too)
            self.switch.stop()
            self.switch = None
        super().end_modal(context)

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
        self.at_rest = False
        for w in self.bound.warnings():
            tell(self, 'WARNING', w)

    def show(self, stats):
        """A short header (what is happening) and the keys in the status bar."""
        s = self.ob.edge_deform
        lam = ("painted (%s)" % s.stiffness_group if s.stiffness_group
               else "%.2f" % s.stiffness)
        self.header("Live Deform: %s | λ %s" % (stats, lam))
        # Drawn later by Blender, maybe after undo replaced the object: plain values only.
        self.painted = s.stiffness_group
        compat.status_bar(self.workspace, self.draw_keys)

    def draw_keys(self, layout):
        """Key hints the way Blender's G shows them (icons from 3.4 to 5.0)."""
        layout.label(text="Keep", icon='EVENT_RETURN')
        layout.label(text="Cancel", icon='EVENT_ESC')
        layout.label(text="Move controllers: G / R / S or gizmo", icon='MOUSE_LMB')
        if self.painted:
            layout.label(text="Stiffness: painted group", icon='BRUSH_DATA')
        else:
            layout.label(text="[ ]  Stiffness", icon='NONE')
            layout.label(text="", icon='EVENT_CTRL')
            layout.label(text="Stiffness", icon='MOUSE_MMB')

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
            wheel = event.type in WHEEL
            if (event.type in KEYS_UP | KEYS_DOWN and wheel == event.ctrl
                    and not (event.alt or event.shift) and in_region(self.area, event)):
                self.change_stiffness(context, event.type in KEYS_UP)
                return {'RUNNING_MODAL'}
            if event.type in {'RET', 'NUMPAD_ENTER'}:
                return self.finish(context)
            if event.type == 'Z' and (event.ctrl or event.oskey):
                tell(self, 'WARNING', "Confirm or cancel Live Deform before undoing")
                return {'RUNNING_MODAL'}
        if event.value == 'PRESS' and event.type == 'ESC':
            if self.switch is not None:
                self.cancel_switch()
                return {'RUNNING_MODAL'}
            return self.cancel_and_restore(context)
        return {'PASS_THROUGH'}

    def change_stiffness(self, context, up):
        s = self.ob.edge_deform
        if s.stiffness_group:
            # The painted group decides λ: a hidden global value must not change.
            tell(self, 'WARNING', "Stiffness comes from the painted group '%s': paint it, "
                                  "or clear the group to use one value" % s.stiffness_group)
            return
        step = LAMBDA_STEP if up else -LAMBDA_STEP
        s.stiffness = min(1.0, max(0.0, round(s.stiffness + step, 4)))
        self.update(context)

    def finish(self, context):
        while self.switch is not None:   # Enter during a domain switch: complete it
            self.advance_switch()
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
