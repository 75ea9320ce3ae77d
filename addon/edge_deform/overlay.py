"""What the tools draw over one 3D viewport while they run: Live Deform's status and keys
as text, at the top left of the view under Blender's own text (the view's and the object's
name), clear of the redo panel at the bottom left; and the proportional radius as a
circle around each handle that moves, as Blender's transform draws its proportional size
around what it moves. The header and the status bar stay Blender's: a G/R/S inside Live
shows its typed value, axis and key hints there, and reports (a refused key) show in the
status bar as always."""

import math
import time

import blf
import bpy
from bpy_extras.view3d_utils import location_3d_to_region_2d


NOTE_SECONDS = 5.0   # how long a note (a refused key) stays on screen


def _redrawn(area):
    """Tag `area` for a redraw; the area, or None when it went away (a file load)."""
    try:
        if area is not None:
            area.tag_redraw()
        return area
    except ReferenceError:
        return None


class ViewportText:
    """Lines of text over `area`'s view until remove(). `drawn` holds the lines the last
    redraw showed (what the window tests read back)."""

    def __init__(self, area):
        self.area = area
        self.lines = []
        self.note, self.note_until = None, 0.0
        self.drawn = None
        self._note_ends = self._end_note   # (one bound method: the timer's identity)
        self.handle = bpy.types.SpaceView3D.draw_handler_add(
            self.draw, (), 'WINDOW', 'POST_PIXEL')

    def set(self, lines):
        if lines != self.lines:
            self.lines = list(lines)
            self.redraw()

    def tell(self, text):
        """A note under the lines for NOTE_SECONDS (why a key was refused). A timer
        redraws the view when it ends: nothing else may (a still view is not redrawn)."""
        self.note, self.note_until = text, time.monotonic() + NOTE_SECONDS
        self.redraw()
        if not bpy.app.timers.is_registered(self._note_ends):
            bpy.app.timers.register(self._note_ends, first_interval=NOTE_SECONDS)

    def _end_note(self):
        """The timer: redraw once the latest note's time is up (None: run no more)."""
        if self.handle is None:
            return None
        left = self.note_until - time.monotonic()
        if left > 0.0:          # a newer note came meanwhile
            return left + 0.01
        self.redraw()
        return None

    def redraw(self):
        self.area = _redrawn(self.area)

    def remove(self):
        if bpy.app.timers.is_registered(self._note_ends):
            bpy.app.timers.unregister(self._note_ends)
        if self.handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self.handle, 'WINDOW')
            self.handle = None
        self.redraw()

    def shown_lines(self):
        lines = list(self.lines)
        if self.note and time.monotonic() < self.note_until:
            lines.append(self.note)
        return lines

    def draw(self):
        context = bpy.context
        try:
            if context.area != self.area:
                return
        except ReferenceError:
            return
        scale = context.preferences.system.ui_scale
        size = round(12 * scale)
        font = 0
        try:
            blf.size(font, size)
        except TypeError:       # Blender 3.x still takes the dpi
            blf.size(font, size, 72)
        blf.enable(font, blf.SHADOW)
        blf.shadow(font, 3, 0.0, 0.0, 0.0, 0.9)
        x = 10 * scale
        for region in context.area.regions:   # right of the toolbar when it overlaps
            if region.type == 'TOOLS' and region.width > 1:
                x += region.width
        lines = self.shown_lines()
        step = size * 1.5
        top = context.region.height - 98 * scale   # under Blender's two lines of text
        for i, text in enumerate(lines):
            is_note = self.note is not None and text == self.note and i == len(lines) - 1
            blf.color(font, 1.0, 0.8 if is_note else 1.0, 0.4 if is_note else 1.0, 1.0)
            blf.position(font, x, top - i * step, 0)
            blf.draw(font, text)
        blf.disable(font, blf.SHADOW)
        self.drawn = lines


CIRCLE_SEGMENTS = 64
CIRCLE_COLOR = (1.0, 1.0, 1.0, 0.8)   # Blender's proportional circle is a light line too


class RadiusCircles:
    """Screen-space circles over `area`'s view until remove(): around the world points
    `where()` gives, each of its world radius projected there (the view's right-hand
    direction scaled by the radius). `where()` returns a list of (centre, radius) in world
    space, empty to draw nothing (proportional off). `drawn` holds [(x, y, radius)] in region
    pixels of the last draw, or None (what the window tests read back)."""

    def __init__(self, area, where):
        self.area = area
        self.where = where
        self.drawn = None
        self.handle = bpy.types.SpaceView3D.draw_handler_add(
            self.draw, (), 'WINDOW', 'POST_PIXEL')

    def remove(self):
        if self.handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self.handle, 'WINDOW')
            self.handle = None
        self.area = _redrawn(self.area)

    def draw(self):
        # (Imported here: the add-on also registers in background Blender, where drawing
        # is never called and gpu need not load.)
        import gpu
        from gpu_extras.batch import batch_for_shader
        context = bpy.context
        try:
            if context.area != self.area or context.region_data is None:
                return
            placed = self.where()
        except ReferenceError:
            return
        region, rv3d = context.region, context.region_data
        drawn = []
        for centre, radius in placed:
            right = rv3d.view_rotation @ centre.__class__((1.0, 0.0, 0.0))
            c = location_3d_to_region_2d(region, rv3d, centre)
            e = location_3d_to_region_2d(region, rv3d, centre + right * radius)
            if c is not None and e is not None:       # (None: behind the viewer)
                drawn.append((c.x, c.y, (e - c).length))
        # (The one name from 3.4, checked there, to 5.x; the "2D_" names went in 4.0.)
        shader = gpu.shader.from_builtin('UNIFORM_COLOR')
        gpu.state.blend_set('ALPHA')
        shader.bind()
        shader.uniform_float("color", CIRCLE_COLOR)
        for x, y, r in drawn:
            points = [(x + r * math.cos(t), y + r * math.sin(t))
                      for t in (2.0 * math.pi * i / CIRCLE_SEGMENTS
                                for i in range(CIRCLE_SEGMENTS + 1))]
            batch_for_shader(shader, 'LINE_STRIP', {"pos": points}).draw(shader)
        gpu.state.blend_set('NONE')
        self.drawn = drawn or None
