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

from . import engine, grab, lifecycle, live, operators_bind, operators_groups, properties, ui

# Where things are: docs/design.md, "The add-on", lists each module's job.

_register, _unregister = bpy.utils.register_classes_factory(
    properties.CLASSES + operators_groups.CLASSES + operators_bind.CLASSES
    + live.CLASSES + grab.CLASSES + ui.CLASSES)


def _link_manual():
    """Preferences > Add-ons shows a "Documentation" button for bl_info["doc_url"], read
    from the copy of bl_info that addon_utils parsed from this file (a literal, which
    cannot know where the add-on is installed): give both copies the manual's URL."""
    info = globals().get("bl_info")
    if info is None:   # a 4.2+ extension: Blender drops bl_info; its manifest speaks for it
        return
    import addon_utils
    url = properties.manual_url()
    info["doc_url"] = url
    addon_utils.modules(refresh=False)   # (parses bl_info once, as the Preferences do)
    fake = addon_utils.addons_fake_modules.get(__name__)
    if fake is not None:
        addon_utils.module_bl_info(fake)["doc_url"] = url


def register():
    _link_manual()
    _register()
    properties.register_props()
    operators_bind.register_handlers()
    lifecycle.register_handlers()
    ui.register_menus()


def unregister():
    ui.unregister_menus()
    lifecycle.unregister_handlers()
    operators_bind.unregister_handlers()
    properties.unregister_props()
    _unregister()
    engine.forget_all()
