"""Run by ctest after `install_addon` in private user folders: Blender starts with the
user's preferences, the add-on is enabled, its bundled native module loads, the sidebar
tab exists and a solve works."""

import os
import sys

import addon_utils
import bpy
import numpy as np

scripts = os.path.realpath(os.environ["BLENDER_USER_SCRIPTS"])
loaded_default, loaded_state = addon_utils.check("edge_deform")
assert loaded_default and loaded_state, "edge_deform is not enabled in the saved preferences"
import edge_deform  # noqa: E402
from edge_deform import compat  # noqa: E402

assert os.path.realpath(edge_deform.__file__).startswith(scripts), edge_deform.__file__
module = compat.native_package()
assert os.path.realpath(module.__file__).startswith(
    os.path.join(scripts, "addons", "edge_deform", "edgedeform")), module.__file__
assert "edgedeform" not in sys.modules or sys.modules["edgedeform"] is module
panel = bpy.types.EDGE_DEFORM_PT_main
assert panel.bl_category == "Edge Deform" and panel.bl_space_type == 'VIEW_3D'

bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10)
ob = bpy.context.active_object
co = np.empty(len(ob.data.vertices) * 3, np.float32)
ob.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
top = np.flatnonzero(co[:, 0] > 0.99)
ob.vertex_groups.new(name="H").add(top.tolist(), 1.0, 'REPLACE')
ob.vertex_groups.new(name="S").add(np.flatnonzero(co[:, 0] < -0.99).tolist(), 1.0, 'REPLACE')
empty = bpy.data.objects.new("C", None)
bpy.context.scene.collection.objects.link(empty)
h = ob.edge_deform.handles.add()
h.vertex_group, h.controller = "H", empty
ob.edge_deform.static_group = "S"
empty.location.z = 0.5
bpy.context.view_layer.update()
assert bpy.ops.edge_deform.solve() == {'FINISHED'}
key = ob.data.shape_keys.key_blocks["EdgeDeform"]
out = np.empty(len(co) * 3, np.float32)
key.data.foreach_get("co", out)
assert np.allclose(out.reshape(-1, 3)[top, 2], 0.5, atol=1e-5)
print("installed add-on OK:", edge_deform.__file__, module.__file__)
