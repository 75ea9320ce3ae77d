"""The proportional radius in the artist's terms: Blender's keys and steps for it, a first
radius that fits the object, its words for the header and the text over the view, the
circles drawn around what moves, and the plain refusal when it frees no vertex. No solver
state: the radius lives on the object (properties.py), the region it picks in the core
(Deformer.set_constraints(roi_radius=...), docs/decisions/0056 and 0066)."""

import bpy
import numpy as np

from . import engine

# Blender's transform (keymap "Transform Modal Map", transform.c): Page Up and the wheel
# pulled down grow the size by 1.1, Page Down and the wheel pushed up shrink it; with
# Shift by 1.01.
STEP, FINE_STEP = 1.1, 1.01
GROW = {'PAGE_UP', 'WHEELDOWNMOUSE'}
SHRINK = {'PAGE_DOWN', 'WHEELUPMOUSE'}
SMALLEST = 1e-6     # the property's minimum (Blender's T_PROP_SIZE_MIN)
KEYS = "Wheel/PgUp/PgDn: radius · O: proportional · Alt+O: connected"
SHORT_KEYS = "Wheel/PgUp/PgDn, O"   # (Grab's header; its status bar lists them in full)
WHERE_TO_CHANGE = "the Edge Deform panel, Static and Region"


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


def describe(settings, running_long=False):
    """What the header and the text over the view say about the region; with
    `running_long` (a whole-mesh settle has run long), that a radius would be quicker."""
    if not settings.proportional:
        return ("Proportional: off (O: a radius makes it local and quick)" if running_long
                else "Proportional: off (O: on)")
    return "Proportional: %s%s" % (length(settings.proportional_radius),
                                   ", connected only" if settings.proportional_connected
                                   else "")


LONG_SETTLE_HINT = ("The whole mesh is still settling: Proportional (O) with a radius "
                    "(Wheel, Page Up/Down) makes the edit local and quick")
OFF_CONTINUES = ("Proportional off: the whole mesh settles on from the shape shown (a "
                 "Solve from the rest may settle on another shape)")


class NothingFree(engine.EdgeDeformError):
    """The core's NoFreeVertexError, in plain words, with what was tried.
    Its text is for a tool that is not running: the panel is where the radius changes."""

    def __init__(self, radius, connected, reason=None):
        self.radius, self.connected = radius, connected
        self.reason = reason or ("No vertex can move within %s of the handles%s (they are "
                                 "too far, or Static holds them)" % (
                                     length(radius), " along the mesh" if connected else ""))
        super().__init__("%s: make the Radius larger or turn Proportional off (%s)"
                         % (self.reason, WHERE_TO_CHANGE))


def kept(exc, settings):
    """A running tool's words for a radius or toggle that freed nothing: the reason and
    the radius kept (its keys are over the view or in the status bar)."""
    reason = exc.reason if isinstance(exc, NothingFree) else str(exc)
    return "%s; kept %s" % (reason, describe(settings))


def short_kept(exc, settings):
    """kept() for a header: "Proportional: 4.77 cm kept (4.33 cm frees no vertex)"."""
    if not isinstance(exc, NothingFree):
        return kept(exc, settings)
    return "%s kept (%s frees no vertex)" % (describe(settings), length(exc.radius))


def held_within(X, sources, radius, held):
    """Do the vertices within `radius` of `sources` (rest positions X, straight distance),
    other than the sources, all belong to `held`, and is there one? Grab's refusal then
    blames what holds them, not the radius. Chunked: the error path of a big mesh."""
    lo, hi = X[sources].min(axis=0) - radius, X[sources].max(axis=0) + radius
    near = np.flatnonzero(np.all((X >= lo) & (X <= hi), axis=1))
    near = np.setdiff1d(near, sources)
    within = np.zeros(near.size, bool)
    for i in range(0, len(sources), 16):
        d = np.linalg.norm(X[near, None, :] - X[None, sources[i:i + 16], :], axis=2)
        within |= d.min(axis=1, initial=np.inf) <= radius
    inside = near[within]
    return inside.size > 0 and bool(np.isin(inside, held).all())


def pinned_refusal(radius, connected, names):
    """Grab's refusal when every vertex within the radius of the selection is held: by
    the rest of handles `names` (Grab holds a handle's unselected vertices where they
    are), or by Static."""
    held = ("the rest of handle%s %s" % ("s" if len(names) > 1 else "",
                                           ", ".join("'%s'" % n for n in names))
            if names else "Static")
    return NothingFree(radius, connected, reason=(
        "No vertex can move within %s of the selection: %s holds every vertex there "
        "(Grab holds a handle's vertices you did not select)" % (length(radius), held)))


def circles(ob, groups):
    """[(world centre, world radius)] of the circles drawn around `groups` ((k,3) object-
    space points each: the handles that move, where they are now), [] while proportional
    is off."""
    s = ob.edge_deform
    if not s.proportional:
        return []
    from mathutils import Vector
    scale = sum(abs(v) for v in ob.matrix_world.to_scale()) / 3.0
    return [(ob.matrix_world @ Vector(tuple(float(v) for v in points.mean(axis=0))),
             s.proportional_radius * scale) for points in groups if len(points)]
