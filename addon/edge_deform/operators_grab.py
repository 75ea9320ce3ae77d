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

from . import engine, lifecycle, mesh_arrays
from .op_common import ModalTool, error_text, guarded, poll_mesh, tell

AXES = {'X': 0, 'Y': 1, 'Z': 2}
NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'TRACKPADPAN',
              'TRACKPADZOOM', 'NDOF_MOTION'}


class EDGE_DEFORM_OT_grab(ModalTool, bpy.types.Operator):
    """Drag the selected vertices; the mesh deforms around them. X/Y/Z: axis,
    Enter/click: confirm, Esc/right click: cancel"""
    bl_idname = "edge_deform.grab"
    bl_label = "Grab Deform"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return (context.region_data is not None and context.window is not None
                and poll_mesh(cls, context, ('EDIT',)))

    @guarded
    def invoke(self, context, event):
        self.refuse_if_running()
        ob = context.active_object
        moving = np.flatnonzero(mesh_arrays.read_selection(ob))
        bound = None
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
            bound = lifecycle.prepare(ob, inputs)
            current = lifecycle.shown_positions(ob)
            pinned = np.setdiff1d(inputs.handles, moving)
            bound.use_constraints(np.concatenate([moving, pinned]), inputs.static, inputs.roi)
        except Exception:
            if bound is not None:
                bound.release()   # the settings' constraints return on the next sync
            if ob.mode != 'EDIT':
                bpy.ops.object.mode_set(mode='EDIT')
            raise
        self.bound = bound
        self.current = current
        self.start = current[moving]
        self.pinned = current[pinned]
        self.n_moving = moving.size
        self.mw = mesh_arrays.matrix_to_numpy(ob.matrix_world)
        self.depth = ob.matrix_world @ Vector(self.start.mean(axis=0))
        self.mouse0 = (event.mouse_region_x, event.mouse_region_y)
        self.mouse = self.mouse0
        self.axis = None
        self.dirty, self.at_rest, self.first = True, False, True
        self.settle_iterations, self.settle_ms = 0, 0.0     # since the mouse last moved
        self.stats = ""
        self.budget = engine.IterationBudget()
        self.region, self.rv3d = context.region, context.region_data
        self.start_modal(context, ob)
        self.show()
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
        if self.dirty:
            self.settle_iterations, self.settle_ms = 0, 0.0
        try:
            # The first solve starts from what is shown, not from the rest shape.
            r = self.bound.solve(targets, iterations, s.tolerance, warm=True,
                                 initial=self.current if self.first else None)
            self.budget.record(r, (time.perf_counter() - t0) * 1e3)
            self.bound.write(r.positions)
        except Exception as exc:  # noqa: BLE001 - shown; the next move retries
            tell(self, 'ERROR', error_text(exc))
            self.dirty, self.at_rest = False, True
            return
        self.first = False
        self.dirty = False
        self.settle_iterations += r.iterations
        self.settle_ms += (time.perf_counter() - t0) * 1e3
        self.stats, self.at_rest = engine.settle_status(r, self.settle_ms, self.settle_iterations,
                                                        "move the mouse")
        self.show()

    def show(self):
        axis = "XYZ"[self.axis] if self.axis is not None else "free"
        self.header("Edge Deform grab: %d vertices | X/Y/Z: axis (%s) | Enter/Click: confirm "
                    "| Esc/Right click: cancel | %s" % (self.n_moving, axis, self.stats))

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
        if event.type == 'MOUSEMOVE':
            self.mouse = (event.mouse_region_x, event.mouse_region_y)
            self.dirty = True
        elif event.type == 'TIMER':
            if self.dirty or not self.at_rest:
                self.update()
        elif event.type in AXES and event.value == 'PRESS':
            axis = AXES[event.type]
            self.axis = None if self.axis == axis else axis
            self.dirty = True
            self.show()
        elif event.type in {'RET', 'NUMPAD_ENTER', 'LEFTMOUSE'} and event.value == 'PRESS':
            if self.dirty:
                self.update()
            return self.end(context, {'FINISHED'})
        elif event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
            return self.end(context, {'CANCELLED'}, restore=True)
        elif event.type in NAVIGATION:
            return {'PASS_THROUGH'}
        return {'RUNNING_MODAL'}

    def end(self, context, result, restore=False):
        self.end_modal(context)
        self.bound.release()   # the settings' handles return on the next sync
        if restore:
            self.restore(context)
        else:
            self.snapshot.discard()
        if self.ob.mode != 'EDIT':
            with context.temp_override(object=self.ob, active_object=self.ob):
                bpy.ops.object.mode_set(mode='EDIT')
        return result

    def cancel(self, context):   # Blender closes the window or quits
        self.end(context, {'CANCELLED'}, restore=True)


CLASSES = (EDGE_DEFORM_OT_grab,)
