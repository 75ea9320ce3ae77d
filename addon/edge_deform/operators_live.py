"""`live`: a modal tool that re-solves whenever a controller moves.

Controllers are moved by anything (G/R/S, gizmos, drivers, scripts): every timer tick the
controllers' world matrices are compared with the last solved ones; a change (or an
unconverged previous solve) triggers one warm-started solve and a write of the output.
Each tick runs at most the settings' iterations and no more than fit in ~40 ms, so big
meshes stay responsive and converge over the following ticks.
Only this main-thread timer touches bpy.
"""

import time

import bpy

from . import engine, mesh_io
from .op_common import poll_mesh

TICK = 1.0 / 60.0
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


class EDGE_DEFORM_OT_live(bpy.types.Operator):
    """Deform live while controllers move. Wheel/+/-: λ, Tab: domain,
    Enter/click: confirm, Esc/right click: cancel"""
    bl_idname = "edge_deform.live"
    bl_label = "Live Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return context.window is not None and poll_mesh(
            cls, context, ('OBJECT',), need_handles=True)

    def invoke(self, context, event):
        ob = context.active_object
        s = ob.edge_deform
        try:
            self.inputs = engine.gather_inputs(ob)
            self.binding = engine.ensure_binding(ob, self.inputs)
        except engine.USER_ERRORS as exc:
            self.report({'ERROR'}, "Edge Deform: %s" % exc)
            return {'CANCELLED'}
        self.ob = ob
        self.snapshot = mesh_io.OutputSnapshot(ob, s.shape_key_name)
        self.saved_settings = (s.stiffness, s.domain)
        self.saved_controllers = [(g.controller, g.controller.matrix_world.copy())
                                  for g in self.inputs.handle_groups if g.controller]
        self.settings_state = self.saved_settings
        self.controllers_state = None
        self.converged = False
        self.stats = "no solve yet"
        self.area = context.area
        self.updates = 0
        self.budget = engine.IterationBudget()
        wm = context.window_manager
        self.timer = wm.event_timer_add(TICK, window=context.window)
        wm.modal_handler_add(self)
        self.update(context)
        return {'RUNNING_MODAL'}

    # ------------------------------------------------------------ per tick

    def update(self, context):
        ob, s = self.ob, self.ob.edge_deform
        settings_state = (s.stiffness, s.domain)
        try:
            if settings_state != self.settings_state:
                self.inputs = engine.with_global_changes(self.inputs, ob)
                self.binding = engine.ensure_binding(ob, self.inputs, check=False)
                self.settings_state = settings_state
                self.converged = False
            state = engine.controller_state(self.inputs)
            if state == self.controllers_state and self.converged:
                return
            t0 = time.perf_counter()
            targets = engine.handle_targets(ob, self.binding, self.inputs)
            r = engine.solve(self.binding, targets, self.budget.iterations(s.iterations),
                             s.tolerance, warm=True, acceleration=s.acceleration)
            self.budget.record(r, (time.perf_counter() - t0) * 1e3)
            engine.write(ob, self.binding, r.positions)
        except engine.USER_ERRORS as exc:
            self.report({'ERROR'}, "Edge Deform: %s" % exc)
            self.converged = True   # don't retry every tick; a new move retries
            self.controllers_state = engine.controller_state(self.inputs)
            return
        self.controllers_state = state
        self.converged = r.converged
        self.updates += 1
        self.stats = "%d it, %.1f ms, %s" % (r.iterations, (time.perf_counter() - t0) * 1e3,
                                             "settled" if r.converged else "settling")
        self.header(context)

    def header(self, context):
        s = self.ob.edge_deform
        lam = "group" if s.stiffness_group else "%.2f" % s.stiffness
        text = ("Edge Deform live | move controllers: G/R/S, gizmo | Wheel/+/-: λ %s | "
                "Tab: domain %s | Enter/Click: confirm | Esc/Right click: cancel | %s"
                % (lam, s.domain.title(), self.stats))
        if self.area is not None:
            self.area.header_text_set(text)

    # ------------------------------------------------------------ events

    def modal(self, context, event):
        s = self.ob.edge_deform
        if event.type == 'TIMER':
            self.update(context)
            return {'PASS_THROUGH'}
        if event.value == 'PRESS':
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
            if event.type in {'ESC', 'RIGHTMOUSE'}:
                return self.cancel_and_restore(context)
            if event.type == 'Z' and (event.ctrl or event.oskey):
                self.report({'WARNING'}, "Confirm or cancel Live Deform before undoing")
                return {'RUNNING_MODAL'}
        if (event.type == 'LEFTMOUSE' and event.value == 'CLICK'
                and in_region(self.area, event)):
            return self.finish(context)
        return {'PASS_THROUGH'}

    def _end(self, context):
        context.window_manager.event_timer_remove(self.timer)
        if self.area is not None:
            self.area.header_text_set(None)

    def finish(self, context):
        self.update(context)   # the last controller move may not be solved yet
        self._end(context)
        self.report({'INFO'}, "Live Deform: %d updates, %s" % (self.updates, self.stats))
        return {'FINISHED'}

    def cancel_and_restore(self, context):
        self._end(context)
        s = self.ob.edge_deform
        self.snapshot.restore(self.ob)
        s.stiffness, s.domain = self.saved_settings
        for controller, matrix in self.saved_controllers:
            controller.matrix_world = matrix
        self.binding.last = None
        return {'CANCELLED'}

    def cancel(self, context):   # Blender closes the window or quits
        self._end(context)


CLASSES = (EDGE_DEFORM_OT_live,)
