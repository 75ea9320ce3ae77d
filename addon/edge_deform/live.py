"""`live`: a modal tool that re-solves whenever a controller (or the object) moves.

Controllers are moved by anything (G/R/S, gizmos, drivers, scripts): every timer tick the
transforms and every setting Live reads are compared with the last solved ones. Live is a
state machine (modal_rules.Live): each tick observes Blender, acts, and moves on by
modal_rules.live_next. A tick that iterates spends a time budget, not a fixed count
(modal_rules.Settle), so slow redraws do not throttle the solve; the shape settles over the
following ticks, or Live stops after modal_rules.SETTLE_LIMIT iterations since the last change
and says so. Only this main-thread timer touches bpy.

What Live says goes in a text over the viewport (overlay.py) and the panel: the header
and the status bar stay Blender's, so a G/R/S inside Live shows its own value, axis and
hints, and a refused key's reason shows in the status bar and over the view.

Live starts from the shape shown (mesh_io.addon_shape): any solve that would start from
scratch (the first, or after a rebind) starts from it, and on a Grab edit no handle holds
Live solves nothing until something changes, saying so first (Live.HOLDING). With the mesh
active it makes the active handle's controller what G/R/S move; Esc gives back the
selection and every transform moved inside the session (Surroundings, at the end).

While the object is in another mode (the user entered Edit Mode) the tool pauses; back in
Object Mode it binds again (the topology may have changed). Undo or the object's deletion
end it cleanly.

A domain change (from the panel) needs a new graph, built and factored: seconds on a big
mesh. Live runs it as stages, one per tick (op_common.Stages): the status bar names each
stage before it runs, with the progress and the wait cursor; Esc between stages keeps the
previous domain and its graph, the mesh untouched (nothing is written until it is done).
"""

import bpy

from . import engine, lifecycle, mesh_io, modal, modal_rules, overlay, properties
from .modal import ModalTool
from .modal_rules import Live, LiveEvent, live_next
from .op_common import (Stages, deformed_object, error_text, guarded, over_the_view,
                        poll_mesh, select_only, tell)


LAMBDA_STEP = 0.05
# The settings Live reads, by what a change needs: a new read of the groups and a rebind,
# a new λ, a new graph, or only a new settle (read on every solve). Esc puts back every
# setting that shapes the result (the handles' groups and controllers too); where the
# result goes (Output, the key's name) stays as the artist typed it.
SHAPE_GROUPS = ("static_group", "roi_group", "stiffness_group")
# The radius and Connected Only while Proportional stays on need only new constraints
# (ObjectSolver.region_changed); turning Proportional on or off brings the Region group
# in or out: a rebind.
RADIUS_SETTINGS = ("proportional_radius", "proportional_connected")
REGION_SETTINGS = ("proportional",) + RADIUS_SETTINGS
OUTPUT_SETTINGS = ("output", "shape_key_name")
REBIND_SETTINGS = SHAPE_GROUPS + ("proportional",) + OUTPUT_SETTINGS
RESTORED_SETTINGS = SHAPE_GROUPS + REGION_SETTINGS + (
    "stiffness", "domain", "iterations", "tolerance", "acceleration")
WATCHED_SETTINGS = RESTORED_SETTINGS + OUTPUT_SETTINGS
def handle_settings(s):
    """The handles' groups and controllers, and whether each controller is still in a
    scene (X deletes it from every collection; the rebind then lets go of it)."""
    return tuple((h.vertex_group, h.controller,
                  h.controller is not None and bool(h.controller.users_collection))
                 for h in s.handles)


class EDGE_DEFORM_OT_live(ModalTool, bpy.types.Operator):
    """Deform the mesh while you move its controllers (select and move them as usual).
    Alt+[ ]: stiffness, O: proportional, Wheel/Page Up/Down: its radius, Enter over the
    view: keep, Esc: cancel"""
    bl_idname = "edge_deform.live"
    bl_label = "Live Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return context.window is not None and poll_mesh(
            cls, context, ('OBJECT',), need_handles=True, follow_controller=True) \
            and modal.idle(cls)

    @guarded
    def invoke(self, context, event):
        ob = deformed_object(context)
        s = ob.edge_deform
        self.solver = lifecycle.prepare(ob)          # refuses before anything changes
        self.saved_settings = {name: getattr(s, name) for name in RESTORED_SETTINGS}
        self.saved_handles = handle_settings(s)
        self.saved_controllers = [(g.controller, g.controller.matrix_world.copy())
                                  for g in self.solver.inputs.handle_groups if g.controller]
        self.surroundings = Surroundings(context.view_layer, ob)
        unheld = ob.data.edge_deform_state.unheld   # a Grab edit no handle holds
        self.state = Live.HOLDING if unheld else Live.SOLVING
        self.seen_settings = self.watched_settings(ob)
        self.seen_controllers = None
        self.switch = None          # while SWITCHING: the switch's stages (start_switch)
        self.refused_for = None     # what the user could fix, when the refusal came
        self.problem = None
        self.status_text = "no solve yet"
        self.status = "no solve yet"
        self.hint = None            # what G/R/S move, in words (what_g_moves)
        self.updates = 0
        self.settle = modal_rules.Settle()
        self.hinted = False         # the long-settle hint was given (once a session)
        self.keys_up, self.keys_down, self.keys_label = properties.stiffness_keys(context)
        self.start_modal(context, ob)
        self.text = overlay.ViewportText(self.area)
        self.circles = overlay.RadiusCircles(self.area, self.circles_where)
        self.hold_undo_steps(context)
        self.surroundings.select_controller(self.active_controller())
        self.hint = what_g_moves(context.view_layer, ob)
        for w in self.solver.warnings():
            tell(self, 'WARNING', w)
        if unheld:
            self.seen_controllers = engine.controller_state(ob, self.solver.inputs)
            self.show("holding your Grab edit (%d vertices no handle holds): move a "
                      "controller to deform" % unheld)
            self.say('WARNING', "%d vertices placed by Grab Deform are held by no handle: "
                                "moving a controller or changing a setting solves them with "
                                "the rest of the mesh (to keep them, make them a handle "
                                "first)" % unheld)
        self.update(context)
        return {'RUNNING_MODAL'}

    def active_controller(self):
        """The controller G/R/S should move: the active handle's, else the first one."""
        s = self.ob.edge_deform
        order = list(s.handles)
        if order:
            order.insert(0, order[min(s.active_handle, len(order) - 1)])
        return next((h.controller for h in order if h.controller is not None), None)

    def go(self, event):
        self.state = live_next(self.state, event)

    # ------------------------------------------------------------ per tick

    def watched_settings(self, ob):
        s = ob.edge_deform
        return ({name: getattr(s, name) for name in WATCHED_SETTINGS}, handle_settings(s))

    def update(self, context):
        """One tick: observe, act, and move on to the next state."""
        ob = self.ob
        if self.state == Live.SWITCHING:
            self.advance_switch()
            return
        if ob.mode != 'OBJECT':
            if self.state != Live.PAUSED:
                self.go(LiveEvent.MODE_LEFT)   # Blender's own tools own the mesh now
            self.show("paused: back to Object Mode to continue")
            return
        if self.state == Live.REFUSED:
            if self.refused_for == self.fixable():
                return                  # wait until the user changes something
            self.go(LiveEvent.RETRY)
        elif self.state == Live.PAUSED:
            self.go(LiveEvent.MODE_BACK)
        try:
            if self.state == Live.REBINDING:
                self.rebind()
            self.follow_changes(context)
            self.follow_selection(context)
            if self.state == Live.SWITCHING:
                return
            if self.state in (Live.AT_REST, Live.HOLDING):
                self.settle.rested()
                return
            # Nothing changed since it settled (a stopped domain switch comes back here
            # with the settle it had): say so, do not iterate.
            if self.settle.at_rest:
                self.go(LiveEvent.SETTLED)
                return
            targets = self.solver.targets()
            r = self.settle.tick(lambda n, check: self.solve(targets, n, check),
                                 moving=self.settle.iterations == 0,
                                 system=self.solver.binding.system)
            self.solver.write(r.positions)
        except Exception as exc:  # noqa: BLE001 - shown, and retried on the next change
            self.refuse(exc)
            return
        self.problem = None
        self.updates += 1
        self.go(LiveEvent.SETTLED if self.settle.at_rest else LiveEvent.ITERATED)
        self.show(modal_rules.describe(self.settle, "move a controller"))
        if self.settle.runs_long and not self.hinted and not self.ob.edge_deform.proportional:
            self.hinted = True
            self.say('INFO', modal.LONG_SETTLE_HINT)

    def solve(self, targets, iterations, check_claims):
        """More warm iterations; a solve that would start from scratch (the first, or after
        a new graph or new constraints) starts from the shape shown instead."""
        initial = (mesh_io.addon_shape(self.ob) if self.solver.binding.starts_cold
                   else None)
        return self.solver.solve(targets, iterations, self.ob.edge_deform.tolerance,
                                 initial=initial, check_claims=check_claims)

    def follow_selection(self, context):
        """The text over the view names what G/R/S move; the artist may pick another."""
        hint = what_g_moves(context.view_layer, self.ob)
        if hint != self.hint:
            self.hint = hint
            self.show(self.status)

    def follow_changes(self, context):
        """Compare what Live reads with what it last solved for; a change starts a new
        settle (after a rebind, a new λ or a domain switch, as the change needs)."""
        ob, s = self.ob, self.ob.edge_deform
        settings = self.watched_settings(ob)
        changed = settings != self.seen_settings
        if (lifecycle.output_settings(ob) != self.solver.output
                or settings[1] != self.seen_settings[1]
                or any(settings[0][n] != self.seen_settings[0][n] for n in REBIND_SETTINGS)):
            self.rebind()
            changed = True
        elif any(settings[0][n] != self.seen_settings[0][n] for n in RADIUS_SETTINGS):
            self.follow_radius()
        if s.domain != self.solver.binding.domain:
            self.start_switch(context)
            return
        if settings[0]["stiffness"] != self.seen_settings[0]["stiffness"]:
            self.solver.settings_changed()
        self.seen_settings = settings
        try:
            controllers = engine.controller_state(ob, self.solver.inputs)
        except ReferenceError:      # a controller was deleted: read the settings again
            self.rebind()
            controllers = engine.controller_state(ob, self.solver.inputs)
        if controllers != self.seen_controllers:
            self.seen_controllers = controllers
            changed = True
        if changed:
            self.settle.changed()
            self.go(LiveEvent.CHANGED)

    def refuse(self, exc):
        """A check or the solve failed: say so once, and wait for a fix."""
        self.refused_for = self.fixable()
        message = error_text(exc)
        if message != self.problem:
            tell(self, 'ERROR', message)
        self.problem = message
        self.go(LiveEvent.FAILED)
        self.show(message)

    def fixable(self):
        """What the user may change to fix a refusal (settings, groups, mode, a move)."""
        ob, s = self.ob, self.ob.edge_deform
        moves = tuple(tuple(map(tuple, h.controller.matrix_world)) for h in s.handles
                      if h.controller is not None)
        return (ob.mode, self.watched_settings(ob), tuple(g.name for g in ob.vertex_groups),
                ob.data.edge_deform_state.written, tuple(map(tuple, ob.matrix_world)), moves)

    def rebind(self):
        """Check and read everything again (Live.REBINDING): back from another mode, a
        refusal retried, a change of groups or Output, a deleted controller. A refusal
        leaves Live without a solver, in REFUSED, until the next retry binds again."""
        if self.state != Live.REBINDING:
            self.go(LiveEvent.REBIND)
        self.solver = None
        self.solver = lifecycle.prepare(self.ob)
        self.seen_settings = self.watched_settings(self.ob)
        self.seen_controllers = None
        for w in self.solver.warnings():
            tell(self, 'WARNING', w)
        self.go(LiveEvent.BOUND)

    # ------------------------------------------------------------ domain switch

    def start_switch(self, context):
        """Begin building the new domain's graph: this tick only shows what comes."""
        s = self.ob.edge_deform
        self.switch_from = self.solver.binding.domain
        inputs = engine.with_global_changes(self.solver.inputs, self.ob)
        self.switch = Stages(context, "Live Deform: switching to the %s graph…" % (
            "edge" if s.domain == 'EDGE' else "vertex"),
            lifecycle.prepare_steps(self.ob, inputs, what="Live Deform"))
        self.go(LiveEvent.SWITCH)
        self.show("%s  (Esc: keep the previous domain)" % self.switch.stage)

    def advance_switch(self):
        """One stage of the switch per tick; at its end Live solves with the new graph."""
        try:
            done, solver = self.switch.advance()
        except Exception as exc:  # noqa: BLE001 - the previous domain stays in use
            self.end_switch()
            tell(self, 'ERROR', error_text(exc) + " (the previous domain is kept)")
            return
        if not done:
            self.show("%s  (Esc: keep the previous domain)" % self.switch.stage)
            return
        self.switch = None
        self.solver = solver
        self.seen_settings = self.watched_settings(self.ob)
        self.seen_controllers = None
        self.settle.changed()
        self.go(LiveEvent.SWITCH_ENDED)
        self.show("new graph ready, solving…")

    def end_switch(self):
        """The switch stopped (failed or Esc): the previous domain and graph stay."""
        self.switch.stop()
        self.switch = None
        self.ob.edge_deform.domain = self.switch_from
        self.seen_settings = self.watched_settings(self.ob)
        self.go(LiveEvent.SWITCH_ENDED)
        self.show(self.status_text)

    def cancel_switch(self):
        """Esc during a switch: nothing was written."""
        self.end_switch()
        self.say('WARNING', "Domain switch cancelled: the %s graph is kept" % (
            "edge" if self.switch_from == 'EDGE' else "vertex"))

    def end_modal(self, context):
        if self.state == Live.SWITCHING:   # (any way out: the progress and cursor end too)
            self.switch.stop()
        for drawing in (getattr(self, "text", None), getattr(self, "circles", None)):
            if drawing is not None:
                drawing.remove()
        super().end_modal(context)

    # ------------------------------------------------------------ what the artist sees

    def show(self, status):
        """Live's state and its keys over the viewport (the panel says it runs)."""
        s = self.ob.edge_deform
        lam = ("painted (%s)" % s.stiffness_group if s.stiffness_group
               else "%.2f" % s.stiffness)
        self.status = status
        self.status_words = "%s | λ %s" % (status, lam)
        self.status_text = "Live Deform: " + self.status_words
        stiffness = ("stiffness: painted group" if s.stiffness_group
                     else "%s stiffness" % self.keys_label)
        self.text.set([self.status_text,
                       "Enter keep · Esc cancel · %s · %s" % (stiffness, self.hint),
                       "%s · %s" % (modal.describe_region(s, self.settle.runs_long),
                                    modal.KEYS)])

    def end_report(self):
        """What Enter kept, in one sentence."""
        if self.state == Live.HOLDING:
            return "Live Deform ended; nothing was solved: the mesh is as it was"
        if self.state in (Live.REFUSED, Live.PAUSED):
            return "Live Deform ended: " + self.status_words
        if self.settle.settled:
            return "Live Deform kept the shape: " + self.status_words
        return ("Live Deform kept the shape before it settled (%s): start Live again to "
                "let it settle" % self.status_words)

    def say(self, level, text):
        """A message where the artist looks: over the view, and as a report (the status
        bar and the Info log)."""
        self.text.tell(text)
        tell(self, level, text)

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
        if event.type == 'TIMER':
            self.update(context)
            return {'PASS_THROUGH'}
        in_view = over_the_view(self.area, event)
        if event.value == 'PRESS' and self.ob.mode == 'OBJECT' and in_view:
            for key, up in ((self.keys_up, True), (self.keys_down, False)):
                if properties.pressed(event, key):
                    self.change_stiffness(context, up)
                    return {'RUNNING_MODAL'}
            if event.type in {'RET', 'NUMPAD_ENTER'} and not (event.ctrl or event.alt):
                return self.finish(context)
            if self.region_key(context, event):
                return {'RUNNING_MODAL'}
            if starts_a_transform(context, event):
                EDGE_DEFORM_OT_live_transform_keys.follow(context)
        if event.value == 'PRESS' and event.type == 'Z' and (event.ctrl or event.oskey):
            self.say('WARNING', "Confirm or cancel Live Deform before undoing (Enter keeps, "
                                "Esc cancels)")
            return {'RUNNING_MODAL'}
        if event.value == 'PRESS' and event.type == 'ESC':
            if self.state == Live.SWITCHING:
                self.cancel_switch()
                return {'RUNNING_MODAL'}
            return self.cancel_and_restore(context)
        return {'PASS_THROUGH'}

    def region_key(self, context, event):
        """O, Alt+O, the wheel and Page Up/Down (pressed over the view in Object Mode):
        the proportional region. True when the key was taken (off, the wheel zooms)."""
        s = self.ob.edge_deform
        toggled = modal.toggle_key(event)
        if toggled is not None:
            self.change_region(context, toggled, not getattr(s, toggled))
            return True
        factor = modal.size_key(event)
        if factor is not None and s.proportional:
            self.change_region(context, "proportional_radius", modal.resized(s, factor))
            return True
        return False

    def change_stiffness(self, context, up):
        s = self.ob.edge_deform
        if s.stiffness_group:
            # The painted group decides λ: a hidden global value must not change.
            self.say('WARNING', "Stiffness comes from the painted group '%s': paint it, "
                                "or clear the group to use one value" % s.stiffness_group)
            return
        step = LAMBDA_STEP if up else -LAMBDA_STEP
        s.stiffness = min(1.0, max(0.0, round(s.stiffness + step, 4)))
        self.update(context)

    def change_region(self, context, name, value):
        """O, Alt+O, the wheel or Page Up/Down: the region now, or, when the new one frees
        no vertex, the previous one kept and the reason said (nothing else changes)."""
        s = self.ob.edge_deform
        before = getattr(s, name)
        setattr(s, name, value)
        if self.state not in (Live.SOLVING, Live.AT_REST, Live.HOLDING):
            return          # (a pause, refusal or switch reads it when it ends)
        try:
            self.follow_radius() if name in RADIUS_SETTINGS else self.rebind()
        except mesh_io.EdgeDeformError as exc:
            setattr(s, name, before)
            self.follow_radius() if name in RADIUS_SETTINGS else self.rebind()
            self.say('WARNING', modal.kept(exc, s))
        else:
            if name == "proportional" and not value:
                # Deliberately from the shape shown (record 0068): what the artist sees
                # goes on, where a fresh solve from the rest may settle elsewhere.
                self.text.tell(modal.OFF_CONTINUES)
        self.update(context)

    def follow_radius(self):
        """A new radius or Connected Only: new constraints only, when Proportional was on
        when Live last read the settings (else the Region group decided: a rebind). The
        next solve starts from the shape shown, as after a rebind."""
        if not self.ob.edge_deform.proportional or self.solver.inputs.roi_radius is None:
            self.rebind()
            return
        self.solver.region_changed()
        self.seen_settings = self.watched_settings(self.ob)
        self.seen_controllers = None

    def circles_where(self):
        """Where the radius circles go: around each handle that moves, where it is now
        (as Blender centres its circle on what it moves); before any moves, around each."""
        if self.solver is None:
            return []
        return modal.circles(self.ob, engine.moving_handles(
            self.solver.targets(), self.solver.binding.X, self.solver.inputs))

    def finish(self, context):
        while self.state == Live.SWITCHING:   # Enter during a domain switch: complete it
            self.advance_switch()
        self.update(context)   # the last controller move may not be solved yet
        self.end_modal(context)
        self.snapshot.discard()
        self.surroundings.give_back(cancelled=False)
        engine.start_cold(self.ob.data)
        tell(self, 'INFO', self.end_report())
        return {'FINISHED'}

    def cancel_and_restore(self, context):
        self.end_modal(context)
        s = self.ob.edge_deform
        why = self.restore(context)
        for name, value in self.saved_settings.items():
            if getattr(s, name) != value:
                setattr(s, name, value)
        self.restore_handles(s)
        for controller, matrix in self.saved_controllers:
            try:
                controller.matrix_world = matrix
            except ReferenceError:
                pass            # the controller was deleted meanwhile
        self.surroundings.give_back(cancelled=True)
        if why is not None:
            tell(self, 'WARNING', "Live Deform cancelled: " + why)
        return {'CANCELLED'}

    def restore_handles(self, s):
        """The handles' groups and controllers as they were (when the list kept its
        length: a handle added or removed during Live is the user's edit, not Live's)."""
        if len(s.handles) != len(self.saved_handles):
            return
        for h, (group, controller, _) in zip(s.handles, self.saved_handles):
            try:
                if h.vertex_group != group:
                    h.vertex_group = group
                if h.controller != controller and (controller is None
                                                   or controller.users_collection):
                    h.controller = controller     # (one deleted meanwhile stays let go)
            except ReferenceError:
                pass

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


# Blender's transforms, which the 3D View's keymap starts (G, R, S by default).
TRANSFORMS = {"transform.translate", "transform.rotate", "transform.resize"}
TRANSFORM_KEYMAPS = ("3D View", "Object Mode")
# The keys that end one (Transform Modal Map: confirm and cancel).
ENDS_A_TRANSFORM = {'LEFTMOUSE', 'RET', 'NUMPAD_ENTER', 'SPACE', 'RIGHTMOUSE', 'ESC'}


def starts_a_transform(context, event):
    """Does the 3D View's (or Object Mode's) keymap start one of Blender's transforms on
    `event`, as the artist has the keys set?"""
    keymaps = context.window_manager.keyconfigs.user.keymaps
    return any(item.active and item.idname in TRANSFORMS and item.type == event.type
               and item.value == event.value and bool(item.ctrl) == event.ctrl
               and bool(item.alt) == event.alt and bool(item.shift) == event.shift
               for name in TRANSFORM_KEYMAPS if keymaps.get(name) is not None
               for item in keymaps[name].keymap_items)


# Blender's transform takes every key while it runs: Live, under it, saw no O or wheel
# during a G (record 0066). This tool sits over the transform until it ends and gives those
# keys to Live; every other event passes through to the transform.
class EDGE_DEFORM_OT_live_transform_keys(bpy.types.Operator):
    """Proportional editing's keys for Live Deform while you move a controller with G, R
    or S: O and Alt+O toggle it, the wheel and Page Up/Down size it"""
    bl_idname = "edge_deform.live_transform_keys"
    bl_label = "Live Deform: Proportional Keys"
    bl_options = {'INTERNAL'}

    @staticmethod
    def follow(context):
        """Called on the key that starts the transform: once Blender has started it (the
        key's own handling), start this over it."""
        where = {"window": context.window, "area": context.area, "region": context.region}

        def start():
            try:
                with bpy.context.temp_override(**where):
                    bpy.ops.edge_deform.live_transform_keys('INVOKE_DEFAULT')
            except (ReferenceError, RuntimeError, TypeError):
                pass            # the window or the view went meanwhile
            return None
        bpy.app.timers.register(start, first_interval=0.0)

    def invoke(self, context, event):
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        live = modal.running_tool()
        if not isinstance(live, EDGE_DEFORM_OT_live):
            return {'CANCELLED', 'PASS_THROUGH'}
        if event.value == 'PRESS' and event.type in ENDS_A_TRANSFORM:
            return {'FINISHED', 'PASS_THROUGH'}      # the transform ends on it
        if (event.value == 'PRESS' and live.ob.mode == 'OBJECT'
                and over_the_view(live.area, event) and live.region_key(context, event)):
            return {'RUNNING_MODAL'}
        return {'PASS_THROUGH'}


CLASSES = (EDGE_DEFORM_OT_live, EDGE_DEFORM_OT_live_transform_keys)


# ----------------------------------------------------------- what Live changes around its mesh
# What Live Deform changes around its mesh, and gives back (docs/decisions/0042).
#
# - The selection. Started with the mesh active, Live makes the active handle's controller
#   the active, only selected object, so that G/R/S and the gizmos move the controller, not
#   the mesh object; the text over the view always names what G/R/S move now.
# - Every object's transform. Inside Live, G/R/S push no undo step of their own (Live's
#   one step holds the session), so Esc puts back the transform of every object moved
#   during the session, the mesh object's too: after Esc the next Ctrl+Z reaches only the
#   step before Live, never more.
# Esc gives both back. Enter keeps the transforms (Live's undo step holds them) and gives
# the selection back only if it is still the one Live made (the artist's own picks stay).

def what_g_moves(layer, ob):
    """The words for what G/R/S move now, Live running on `ob`."""
    active = layer.objects.active
    if active is not None and active != ob and any(
            h.controller == active for h in ob.edge_deform.handles):
        return "G/R/S move '%s'" % active.name
    if active == ob:
        return "G/R/S would move the object '%s' itself: click a controller" % ob.name
    return "click a controller to move it with G/R/S"


def _selectable(layer, ob):
    return (ob is not None and layer.objects.get(ob.name) == ob
            and ob.visible_get(view_layer=layer))


class Surroundings:
    """The selection and the transforms as Live found them, for Esc and Enter."""

    def __init__(self, layer, ob):
        self.layer, self.ob = layer, ob
        self.active = layer.objects.active
        self.selected = [o for o in layer.objects if o.select_get()]
        self.transforms = [(o, o.matrix_basis.copy()) for o in layer.objects]
        self.made = None   # the controller Live made the active, only selected object

    def select_controller(self, controller):
        """With the mesh active, make `controller` the active, only selected object.
        Returns it, or None when Live leaves the selection alone (started from a
        controller or another object; no controller that can be selected)."""
        if self.active != self.ob or not _selectable(self.layer, controller):
            return None
        select_only(self.layer, controller)
        self.made = controller
        return controller

    def give_back(self, cancelled):
        """Esc (cancelled): every moved transform and the selection as before Live. Enter:
        the selection as before, if it is still Live's own."""
        if cancelled:
            for ob, matrix in self.transforms:
                try:
                    if ob.matrix_basis != matrix:
                        ob.matrix_basis = matrix
                except ReferenceError:   # deleted meanwhile
                    pass
        if cancelled or self._still_made():
            self._select_as_before()

    def _still_made(self):
        layer = self.layer
        return (self.made is not None and layer.objects.active == self.made
                and [o for o in layer.objects if o.select_get()] == [self.made])

    def _select_as_before(self):
        keep = set()
        for ob in self.selected:
            try:
                keep.add(ob.name_full)
            except ReferenceError:   # deleted meanwhile
                pass
        try:
            for other in self.layer.objects:
                if other.select_get() != (other.name_full in keep):
                    other.select_set(other.name_full in keep)
            if self.active is not None and self.layer.objects.get(self.active.name) \
                    == self.active:
                self.layer.objects.active = self.active
        except (ReferenceError, RuntimeError):   # an object went, or left the view layer
            pass
