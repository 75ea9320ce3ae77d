"""Settings stored on the object (`ob.edge_deform`): the scripting contract (docs/addon.md,
"Scripting contract"); the mesh's stored state group (written by mesh_io.py); and the
add-on's preferences (its keys, the manual)."""

import pathlib

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       FloatVectorProperty, IntProperty, PointerProperty, StringProperty)

from . import engine


# The core's defaults that two settings start from. The package loads lazily (the add-on
# registers without it and says why at the first solve), so they cannot be read from it
# here; test_manual_defaults.py checks them against the package.
CORE_TOLERANCE = 1e-3   # edgedeform.SOLVE_DEFAULTS["tolerance"]
CORE_STIFFNESS = 0.5    # a new Deformer's λ, before set_stiffness

IDENTITY = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0),
            (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0))


# (identifier, name, description, number): the number is what a file stores (2 was Newton,
# retired in record 0070: a file that stored it reads as Automatic, engine.acceleration).
# A method is listed only when this build of the package solves with it
# (engine.offered_accelerations). Automatic, the default, names no method: the package's
# rule picks one (engine.AUTOMATIC).
_AUTOMATIC_ITEM = (engine.AUTOMATIC, "Automatic", "The package's measured rule: "
                   "quasi-Newton steps where Stiffness is 1 everywhere, else Anderson", 3)
_ACCELERATION_ITEMS = {
    "anderson": ('ANDERSON', "Anderson", "Anderson-accelerated steps at any stiffness "
                 "(Automatic's choice below Stiffness 1)", 0),
    "none": ('NONE', "Plain", "One plain pass at a time: slower, for comparison", 1)}


def _acceleration_items(self, context):
    # (A module-level list: Blender keeps pointers to the strings an items callback gives.)
    _acceleration_items.cache[:] = [_AUTOMATIC_ITEM] + [
        _ACCELERATION_ITEMS[name] for name in engine.offered_accelerations()]
    return _acceleration_items.cache


_acceleration_items.cache = []


def _fit_radius(settings, _context):
    """Proportional on with no radius chosen yet (0): one that fits the object, kept from
    then on (a fixed 1 m tore a 229-unit figure and fell outside a 2 cm one; record 0066).
    (An update callback: it runs for the panel, the keys and scripts alike.)"""
    if settings.proportional and settings.proportional_radius == 0.0:
        settings.proportional_radius = engine.fitted_radius(settings.id_data)


class EdgeDeformHandle(bpy.types.PropertyGroup):
    vertex_group: StringProperty(
        name="Vertex Group", description="Vertices moved by this handle")
    controller: PointerProperty(
        name="Controller", type=bpy.types.Object,
        description="Object whose motion since its rest transform moves the handle")
    # The controller's transform in the deformed object's space (ob.matrix_world⁻¹ @
    # controller.matrix_world) when the handle was added or the object bound; the handle
    # moves by (ob.matrix_world⁻¹ @ controller.matrix_world) @ rest_matrix⁻¹.
    rest_matrix: FloatVectorProperty(
        name="Rest Matrix", size=(4, 4), subtype='MATRIX', default=IDENTITY,
        description="Where the controller was, relative to the mesh, at Bind",
        options={'HIDDEN'})


class EdgeDeformSettings(bpy.types.PropertyGroup):
    handles: CollectionProperty(
        type=EdgeDeformHandle, name="Handles",
        description="Groups of vertices that follow a controller object")
    active_handle: IntProperty(name="Active Handle", default=0, min=0,
                               description="The handle selected in the list")
    static_group: StringProperty(
        name="Static", description="Vertex group that never moves (empty: none)")
    roi_group: StringProperty(
        name="Region", description="Only these vertices may move (empty: whole mesh)")
    proportional: BoolProperty(
        name="Proportional", default=False, update=_fit_radius,
        description="Only the vertices within the radius of the handles may move, as in "
                    "Blender's proportional editing; the rest stays at rest. Overrides the "
                    "Region group while on (O toggles it in Live and Grab Deform). Live "
                    "goes on from the shape shown when it is toggled, so the same pose can "
                    "settle a little differently than a Solve from the rest")
    proportional_radius: FloatProperty(
        name="Radius", default=0.0, min=0.0, soft_max=100.0, subtype='DISTANCE',
        unit='LENGTH', precision=3, update=_fit_radius,
        description="How far from the handles vertices may move, in the mesh's units "
                    "(Wheel or Page Up/Page Down change it in Live and Grab Deform; 0: a "
                    "quarter of the object's size, set when Proportional turns on)")
    proportional_connected: BoolProperty(
        name="Connected Only", default=False,
        description="Measure the radius over the mesh's surface, so parts that are near "
                    "but not connected stay at rest (Alt+O in Live and Grab Deform)")
    stiffness_group: StringProperty(
        name="Stiffness Group",
        description="Paintable stiffness: each vertex's weight is its λ (red 1 rigid, blue "
                    "0 soft). Overrides the λ slider; vertices outside the group are soft")
    stiffness: FloatProperty(
        name="Stiffness λ", default=CORE_STIFFNESS, min=0.0, max=1.0,
        description="How stiff the whole mesh is: 1 = rigid, keeps its shape and edge "
                    "lengths; 0 = soft, bends smoothly like rubber")
    domain: EnumProperty(
        name="Domain", default='EDGE',
        description="How the mesh is modelled while it deforms",
        items=[('EDGE', "Edge Graph", "Even bending that follows the stiffness closely "
                "(recommended)"),
               ('PRIMAL', "Vertex Graph", "A lighter model on the vertices: faster to "
                "bind, bends less evenly; can inflate when very soft")])
    iterations: IntProperty(
        name="Iterations", default=4, min=1, max=1000,
        description="Refinement passes per update: more passes match the stiffness more "
                    "closely but take longer")
    tolerance: FloatProperty(
        name="Tolerance", default=CORE_TOLERANCE, min=0.0, max=1.0, precision=6,
        description="How close to the final shape counts as settled, as a fraction of the "
                    "object's size (smaller: more accurate, slower)")
    acceleration: EnumProperty(
        name="Acceleration", default=_AUTOMATIC_ITEM[3],
        description="How updates approach the final shape",
        items=_acceleration_items)
    output: EnumProperty(
        name="Output", default='SHAPE_KEY',
        description="Where the deformed shape goes",
        items=[('SHAPE_KEY', "Shape Key", "Write into the shape key 'EdgeDeform'; "
                "the base mesh stays untouched"),
               ('MESH', "Mesh", "Write into the base mesh")])
    shape_key_name: StringProperty(
        name="Shape Key", default="EdgeDeform",
        description="Name of the shape key that shows the deformation (made by Edge "
                    "Deform; not the Basis or one of your own keys)")
    animate: BoolProperty(
        name="Deform on Frame Change", default=False,
        description="Follow animated controllers: deform again on every frame change")


class EdgeDeformMeshState(bpy.types.PropertyGroup):
    """What Edge Deform last did to this mesh; written only by mesh_io.py (docs/design.md,
    "Who owns what state"). Kept on the Mesh so that undo, save and reload carry it with
    the vertices."""
    output: EnumProperty(
        name="Output Held", default='NONE',
        items=[('NONE', "None", "The base mesh is the rest shape"),
               ('SHAPE_KEY', "Shape Key", "The add-on's shape key holds the last result"),
               ('MESH', "Mesh", "The base mesh holds the last result; the rest is stored")])
    output_key: StringProperty(name="Output Key", description="The shape key the add-on made")
    made_key_datablock: BoolProperty(
        name="Made Shape Keys", description="The add-on added the Basis (Apply removes it)")
    topology: StringProperty(name="Topology", description="Topology digest at the last write")
    written: StringProperty(name="Written", description="Hash of the output last written")
    base: StringProperty(name="Base", description="Hash of the base mesh at the last write")
    baked_keys: StringProperty(name="Baked Keys", description="Keys made by Bake, one a line")
    unheld: IntProperty(
        name="Unheld Edit", min=0,
        description="Vertices the last Grab Deform placed that no handle holds (0 after "
                    "any solve)")


def register_props():
    bpy.types.Object.edge_deform = PointerProperty(type=EdgeDeformSettings)
    bpy.types.Mesh.edge_deform_state = PointerProperty(type=EdgeDeformMeshState,
                                                       options={'HIDDEN'})


def unregister_props():
    del bpy.types.Mesh.edge_deform_state
    del bpy.types.Object.edge_deform


# ------------------------------------------------------------------ the add-on's preferences
# Preferences > Add-ons > Edge Deform: a "Manual" button that opens the manual shipped
# inside the add-on. A 4.2+ extension has no bl_info (Blender drops it), so this button is
# its documentation link; the legacy add-on also gets bl_info["doc_url"] (__init__.py).

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


CLASSES = (EdgeDeformHandle, EdgeDeformSettings, EdgeDeformMeshState,
           EDGE_DEFORM_AP_preferences,)
