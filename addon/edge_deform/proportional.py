"""The proportional radius in the artist's terms: Blender's keys and steps for it, its
words for the header and the text over the view, and the plain refusal when it frees no
vertex. No solver state: the radius lives on the object (properties.py), the region it
picks in the core (Deformer.set_constraints(roi_radius=...), docs/decisions/0056)."""

import bpy

# Blender's transform (keymap "Transform Modal Map", transform.c): Page Up and the wheel
# pulled down grow the size by 1.1, Page Down and the wheel pushed up shrink it; with
# Shift by 1.01.
STEP, FINE_STEP = 1.1, 1.01
GROW = {'PAGE_UP', 'WHEELDOWNMOUSE'}
SHRINK = {'PAGE_DOWN', 'WHEELUPMOUSE'}
SMALLEST = 1e-6     # the property's minimum (Blender's T_PROP_SIZE_MIN)
KEYS = "Wheel/PgUp/PgDn: radius · O: proportional · Alt+O: connected"
SHORT_KEYS = "Wheel/PgUp/PgDn, O"   # (Grab's header; its status bar lists them in full)


def size_key(event):
    """The factor a wheel or Page key multiplies the radius by, or None (another key, or
    with Ctrl/Alt, which stay the view's and the stiffness keys')."""
    if event.ctrl or event.alt or event.oskey or event.value != 'PRESS':
        return None
    step = FINE_STEP if event.shift else STEP
    if event.type in GROW:
        return step
    if event.type in SHRINK:
        return 1.0 / step
    return None


def resized(settings, factor):
    """The radius after one step of `factor` (never below Blender's smallest size)."""
    return max(SMALLEST, settings.proportional_radius * factor)


def toggle_key(event):
    """'proportional' for O, 'proportional_connected' for Alt+O (Blender's keys), or None."""
    if event.type != 'O' or event.value != 'PRESS' or event.ctrl or event.shift:
        return None
    return "proportional_connected" if event.alt else "proportional"


def length(value):
    """A length in the scene's units, as Blender's fields write it ("0.35 m")."""
    units = bpy.context.scene.unit_settings
    try:
        return bpy.utils.units.to_string(units.system, 'LENGTH',
                                         value * units.scale_length, precision=3)
    except (AttributeError, TypeError, ValueError):
        return "%.3g" % value


def describe(settings):
    """What the header and the text over the view say about the region."""
    if not settings.proportional:
        return "Proportional: off (O: on)"
    return "Proportional: %s%s" % (length(settings.proportional_radius),
                                   ", connected only" if settings.proportional_connected
                                   else "")


def refusal(radius, connected):
    """The plain words for the core's NoFreeVertexError."""
    return ("No vertex can move within %s of the handles%s (they are too far, or Static "
            "holds them): make the radius larger (Wheel, Page Up) or turn Proportional off "
            "(O)" % (length(radius), " along the mesh" if connected else ""))


def circle(ob, points):
    """(world centre, world radius) of the circle drawn around `points` ((k,3) object
    space, the handles where they are now), or None while proportional is off."""
    s = ob.edge_deform
    if not s.proportional or points is None or len(points) == 0:
        return None
    from mathutils import Vector
    centre = ob.matrix_world @ Vector(tuple(float(v) for v in points.mean(axis=0)))
    scale = sum(abs(v) for v in ob.matrix_world.to_scale()) / 3.0
    return centre, s.proportional_radius * scale
