"""Preferences > Add-ons > Edge Deform: a "Manual" button that opens the manual shipped
inside the add-on. A 4.2+ extension has no bl_info (Blender drops it), so this button is
its documentation link; the legacy add-on also gets bl_info["doc_url"] (__init__.py)."""

import pathlib

import bpy


def manual_url():
    """file:// URL of the manual: the copy bundled in an installed add-on
    (edge_deform/docs/addon.md), else the checkout's docs/addon.md (a development run)."""
    here = pathlib.Path(__file__).resolve().parent
    for path in (here / "docs" / "addon.md", here.parent.parent / "docs" / "addon.md"):
        if path.is_file():
            return path.as_uri()
    return ""


class EDGE_DEFORM_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    def draw(self, context):
        url = manual_url()
        row = self.layout.row()
        if url:
            row.operator("wm.url_open", text="Manual", icon='HELP').url = url
        else:
            row.label(text="The manual (docs/addon.md) is missing from this install", icon='ERROR')


CLASSES = (EDGE_DEFORM_AP_preferences,)
