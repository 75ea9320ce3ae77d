"""Preferences > Add-ons > Edge Deform: a "Manual" button that opens the manual shipped
inside the add-on. A 4.2+ extension has no bl_info (Blender drops it), so this button is
its documentation link; the legacy add-on also gets bl_info["doc_url"] (__init__.py)."""

import pathlib

import bpy
from bpy.props import EnumProperty

# Live Deform's stiffness keys: (type, ctrl, alt, shift) for up and down. The default pair
# is bound to nothing in Object Mode's 3D viewport (Blender 3.4.1's default keyconfig, read
# in a window on 2026-12-02, has no Alt+[ or Alt+] item at all; no test checks this, and
# test_window_artist's finding 13 only checks that [ / ] and Ctrl+Wheel keep Blender's
# meaning); the others shadow a Blender key while Live runs.
STIFFNESS_KEYS = {
    'ALT_BRACKETS': (('RIGHT_BRACKET', False, True, False), ('LEFT_BRACKET', False, True, False),
                     "Alt+[ ]"),
    'BRACKETS': (('RIGHT_BRACKET', False, False, False), ('LEFT_BRACKET', False, False, False),
                 "[ ]"),
    'CTRL_WHEEL': (('WHEELUPMOUSE', True, False, False), ('WHEELDOWNMOUSE', True, False, False),
                   "Ctrl+Wheel"),
}


def pressed(event, key):
    """Is `event` the press of `key` (type, ctrl, alt, shift)?"""
    kind, ctrl, alt, shift = key
    return (event.value == 'PRESS' and event.type == kind and bool(event.ctrl) == ctrl
            and bool(event.alt) == alt and bool(event.shift) == shift)
DEFAULT_STIFFNESS_KEYS = 'ALT_BRACKETS'


def stiffness_keys(context):
    """(the key raising λ, the key lowering it, their label) as the preferences choose."""
    addon = context.preferences.addons.get(__package__)
    choice = getattr(addon.preferences, "stiffness_keys", None) if addon else None
    return STIFFNESS_KEYS.get(choice or DEFAULT_STIFFNESS_KEYS,
                              STIFFNESS_KEYS[DEFAULT_STIFFNESS_KEYS])


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

    stiffness_keys: EnumProperty(
        name="Live Stiffness Keys", default=DEFAULT_STIFFNESS_KEYS,
        description="The keys that change λ while Live Deform runs",
        items=[('ALT_BRACKETS', "Alt+[ / Alt+]", "Free in Object Mode (recommended)"),
               ('BRACKETS', "[ / ]", "Shadows Select Hierarchy while Live runs"),
               ('CTRL_WHEEL', "Ctrl+Wheel", "Shadows horizontal panning while Live runs")])

    def draw(self, context):
        self.layout.prop(self, "stiffness_keys")
        url = manual_url()
        row = self.layout.row()
        if url:
            row.operator("wm.url_open", text="Manual", icon='HELP').url = url
        else:
            row.label(text="The manual (docs/addon.md) is missing from this install", icon='ERROR')


CLASSES = (EDGE_DEFORM_AP_preferences,)
