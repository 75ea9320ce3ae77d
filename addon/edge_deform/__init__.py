"""Edge Deform: edge-based graph mesh deformation (register only; see the modules)."""

bl_info = {
    "name": "Edge Deform",
    "author": "edgedeform contributors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Edge Deform",
    "description": "Deform meshes with handles and painted stiffness "
                   "(Triangular Mesh Deformation via Edge-Based Graph)",
    "category": "Mesh",
}

import bpy

from . import (cache_handlers, menus, operators_bake, operators_bind, operators_grab,
               operators_groups, operators_live, properties, session, ui)

# Where things are: lifecycle.py owns the rest shape, the output and their invalidation;
# engine.py turns settings into solver inputs; mesh_arrays.py moves bpy data to NumPy;
# session.py is the in-memory solver cache; operators_*.py talk to the user.

_register, _unregister = bpy.utils.register_classes_factory(
    properties.CLASSES + operators_groups.CLASSES + operators_bind.CLASSES
    + operators_live.CLASSES + operators_grab.CLASSES + operators_bake.CLASSES
    + ui.CLASSES + menus.CLASSES)


def register():
    _register()
    properties.register_props()
    operators_bake.register_handlers()
    cache_handlers.register_handlers()
    menus.register_menus()


def unregister():
    menus.unregister_menus()
    cache_handlers.unregister_handlers()
    operators_bake.unregister_handlers()
    properties.unregister_props()
    _unregister()
    session.clear()
