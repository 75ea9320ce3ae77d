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
    # Set by register() to a file:// URL of the manual shipped with the add-on
    # (docs/addon.md): there is no public web page, and bl_info must be a literal here.
    "doc_url": "",
}

import bpy

from . import (cache_handlers, frame_handler, menus, operators_bake, operators_bind,
               operators_grab, operators_groups, operators_live, operators_select,
               preferences, properties, solver_cache, ui)

# Where things are: lifecycle.py owns the rest shape, the output and their invalidation
# (checks in output_checks.py, writes in output.py); engine.py turns settings into solver
# inputs; mesh_arrays.py moves bpy data to NumPy; solver_cache.py owns the in-memory
# solver cache (session.py); operators_*.py talk to the user, ui.py draws the panel.

_register, _unregister = bpy.utils.register_classes_factory(
    properties.CLASSES + operators_groups.CLASSES + operators_bind.CLASSES
    + operators_live.CLASSES + operators_grab.CLASSES + operators_bake.CLASSES
    + operators_select.CLASSES + ui.CLASSES + menus.CLASSES + preferences.CLASSES)


def _link_manual():
    """Preferences > Add-ons shows a "Documentation" button for bl_info["doc_url"], read
    from the copy of bl_info that addon_utils parsed from this file (a literal, which
    cannot know where the add-on is installed): give both copies the manual's URL."""
    info = globals().get("bl_info")
    if info is None:   # a 4.2+ extension: Blender drops bl_info; its manifest speaks for it
        return
    import addon_utils
    url = preferences.manual_url()
    info["doc_url"] = url
    addon_utils.modules(refresh=False)   # (parses bl_info once, as the Preferences do)
    fake = addon_utils.addons_fake_modules.get(__name__)
    if fake is not None:
        addon_utils.module_bl_info(fake)["doc_url"] = url


def register():
    _link_manual()
    _register()
    properties.register_props()
    frame_handler.register_handlers()
    cache_handlers.register_handlers()
    menus.register_menus()


def unregister():
    menus.unregister_menus()
    cache_handlers.unregister_handlers()
    frame_handler.unregister_handlers()
    properties.unregister_props()
    _unregister()
    solver_cache.forget_all()
