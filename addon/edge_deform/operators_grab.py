"""`grab`: drag the selected vertices in the view plane, the rest of the mesh follows.

Like G in Edit Mode: X/Y/Z constrain the motion to a global axis (press again to free it),
Enter/click confirms, Esc/right click restores. The mesh is shown in Object Mode while
dragging (bpy can only write whole arrays there) and Edit Mode comes back at the end.
Other handle groups stay where they are shown; static vertices and vertices outside the
region stay at rest.
"""

import time

import bpy
import numpy as np
from bpy_extras.view3d_utils import region_2d_to_location_3d
from mathutils import Vector

from . import engine, mesh_io
from .op_common import poll_mesh
from .operators_live import TICK

AXES = {'X': 0, 'Y': 1, 'Z': 2}
NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'TRACKPADPAN',
              'TRACKPADZOOM', 'NDOF_MOTION'}


class EDGE_DEFORM_OT_grab(bpy.types.Operator):
    """Drag the selected vertices; the mesh deforms around them. X/Y/Z: axis,
    Enter/click: confirm, Esc/right click: cancel"""
    bl_idname = "edge_deform.grab"
    bl_label = "Grab Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return (context.region_data is not None and context.window is not None
                and poll_mesh(cls, context, ('EDIT',)))

    def invoke(self, context, event):
        ob = context.active_object
        s = ob.edge_deform
        moving = np.flatnonzero(mesh_io.read_selection(ob))
        try:
            if moving.size == 0:
                raise engine.EdgeDeformError("Select the vertices to drag")
            inputs = engine.gather_inputs(ob, require_handles=False)
            moving = np.setdiff1d(moving, inputs.static)
            if inputs.roi is not None:
                moving = np.intersect1d(moving, inputs.roi)
            if moving.size == 0:
                raise engine.EdgeDeformError("The selection is static or outside the region")
            bpy.ops.object.mode_set(mode='OBJECT')
            self.ob = ob
            binding = engine.ensure_binding(ob, inputs)
            current = mesh_io.read_output(ob, s.output, s.shape_key_name)
            pinned = np.setdiff1d(inputs.handles, moving)
            binding.use_constraints(np.concatenate([moving, pinned]), inputs.static,
                                    inputs.roi)
        except engine.USER_ERRORS as exc:
            if ob.mode != 'EDIT':
                bpy.ops.object.mode_set(mode='EDIT')
            self.report({'ERROR'}, "Edge Deform: %s" % exc)
            return {'CANCELLED'}
        self.binding = binding
        self.snapshot = mesh_io.OutputSnapshot(ob, s.shape_key_name)
        self.current = current
        self.start = current[moving]
        self.pinned = current[pinned]
        self.n_moving = moving.size
        self.mw = mesh_io.matrix_to_numpy(ob.matrix_world)
        self.depth = ob.matrix_world @ Vector(self.start.mean(axis=0))
        self.mouse0 = (event.mouse_region_x, event.mouse_region_y)
        self.mouse = self.mouse0
        self.axis = None
        self.dirty, self.converged, self.first = True, False, True
        self.stats = ""
        self.budget = engine.IterationBudget()
        self.region, self.rv3d, self.area = context.region, context.region_data, context.area
        wm = context.window_manager
        self.timer = wm.event_timer_add(TICK, window=context.window)
        wm.modal_handler_add(self)
        self.header()
        return {'RUNNING_MODAL'}

    def offset(self):
        """Mouse motion since the start, in the view plane through the dragged vertices,
        as an object-space vector."""
        p0 = region_2d_to_location_3d(self.region, self.rv3d, self.mouse0, self.depth)
        p1 = region_2d_to_location_3d(self.region, self.rv3d, self.mouse, self.depth)
        d = np.array(p1 - p0, np.float64)
        if self.axis is not None:
            keep = np.zeros(3)
            keep[self.axis] = 1.0
            d = d * keep
        return np.linalg.solve(self.mw[:3, :3], d)

    def update(self):
        s = self.ob.edge_deform
        t0 = time.perf_counter()
        self.delta = self.offset()
        targets = np.concatenate([self.start + self.delta, self.pinned])
        iterations = self.budget.iterations(s.iterations)
        try:
            if self.first:   # start from what is shown, not from the rest shape
                r = self.binding.deformer.solve(targets, max_iterations=iterations,
                                                tolerance=s.tolerance, warm_start=False,
                                                initial=self.current,
                                                acceleration=s.acceleration.lower())
            else:
                r = self.binding.deformer.solve(targets, max_iterations=iterations,
                                                tolerance=s.tolerance, warm_start=True,
                                                acceleration=s.acceleration.lower())
            self.budget.record(r, (time.perf_counter() - t0) * 1e3)
        except engine.USER_ERRORS as exc:
            self.report({'ERROR'}, "Edge Deform: %s" % exc)
            self.dirty, self.converged = False, True
            return
        self.first = False
        self.binding.last = r
        engine.write(self.ob, self.binding, r.positions)
        self.dirty, self.converged = False, r.converged
        self.stats = "%d it, %.1f ms, %s" % (r.iterations, (time.perf_counter() - t0) * 1e3,
                                             "settled" if r.converged else "settling")
        self.header()

    def header(self):
        axis = "XYZ"[self.axis] if self.axis is not None else "free"
        self.area.header_text_set(
            "Edge Deform grab: %d vertices | X/Y/Z: axis (%s) | Enter/Click: confirm | "
            "Esc/Right click: cancel | %s" % (self.n_moving, axis, self.stats))

    def modal(self, context, event):
        if event.type == 'MOUSEMOVE':
            self.mouse = (event.mouse_region_x, event.mouse_region_y)
            self.dirty = True
        elif event.type == 'TIMER':
            if self.dirty or not self.converged:
                self.update()
        elif event.type in AXES and event.value == 'PRESS':
            axis = AXES[event.type]
            self.axis = None if self.axis == axis else axis
            self.dirty = True
            self.header()
        elif event.type in {'RET', 'NUMPAD_ENTER', 'LEFTMOUSE'} and event.value == 'PRESS':
            if self.dirty:
                self.update()
            return self.end(context, {'FINISHED'})
        elif event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            self.snapshot.restore(self.ob)
            return self.end(context, {'CANCELLED'})
        elif event.type in NAVIGATION:
            return {'PASS_THROUGH'}
        return {'RUNNING_MODAL'}

    def end(self, context, result):
        context.window_manager.event_timer_remove(self.timer)
        self.area.header_text_set(None)
        self.binding.constraint_key = None   # the settings' handles return on next sync
        self.binding.last = None
        if self.ob.mode != 'EDIT':
            bpy.ops.object.mode_set(mode='EDIT')
        return result

    def cancel(self, context):
        self.snapshot.restore(self.ob)
        self.end(context, {'CANCELLED'})


CLASSES = (EDGE_DEFORM_OT_grab,)
