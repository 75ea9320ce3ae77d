"""Blender's UI operated as an artist does, for the real-window tests (window_harness.py
runs them): the Edge Deform tab, a panel's buttons, F3 search, the window's keyboard focus
and what the status bar shows.

- A panel button is found by hovering: Ctrl+C over an operator button copies its Python
  command to the clipboard (Blender's own UI handler), so a column of the sidebar is probed
  until the clipboard names the operator; then a real click presses it. (While probing,
  Ctrl+C outside a button would copy the selected objects: those keymap items are off.)
- Focus: on a desktop the window manager gives Blender's window the keyboard focus, and
  only a focused window shows reports in its status bar (Blender 3.4 animates its report
  banner with a timer on the active window; under Xvfb, which has no window manager, there
  is none, and neither Blender's own reports nor the add-on's showed). focus_window() sets
  the X input focus on Blender's window, as a window manager does.
Every function that needs Blender's event loop between events is a generator (yield from).
"""

import ctypes
import ctypes.util
import os

from helpers import OUT, activate, bpy, np
from window_harness import (center, event, run_sections, running, screenshot, setup, tap, until,
                            view3d)

COPY_KEYMAP_ITEMS = {"view3d.copybuffer", "view3d.pastebuffer"}


# ------------------------------------------------------------------ focus

class _XWindowAttributes(ctypes.Structure):
    _fields_ = [("x", ctypes.c_int), ("y", ctypes.c_int), ("width", ctypes.c_int),
                ("height", ctypes.c_int), ("border_width", ctypes.c_int),
                ("depth", ctypes.c_int), ("visual", ctypes.c_void_p),
                ("root", ctypes.c_ulong), ("class_", ctypes.c_int),
                ("bit_gravity", ctypes.c_int), ("win_gravity", ctypes.c_int),
                ("backing_store", ctypes.c_int), ("backing_planes", ctypes.c_ulong),
                ("backing_pixel", ctypes.c_ulong), ("save_under", ctypes.c_int),
                ("colormap", ctypes.c_ulong), ("map_installed", ctypes.c_int),
                ("map_state", ctypes.c_int), ("all_event_masks", ctypes.c_long),
                ("your_event_mask", ctypes.c_long), ("do_not_propagate_mask", ctypes.c_long),
                ("override_redirect", ctypes.c_int), ("screen", ctypes.c_void_p)]


def focus_window():
    """Give the largest mapped top-level X window (Blender's) the keyboard focus, as a
    desktop's window manager does. Returns what was done (for the log)."""
    x11 = ctypes.cdll.LoadLibrary(ctypes.util.find_library("X11") or "libX11.so.6")
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XDefaultRootWindow.restype = ctypes.c_ulong
    x11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
    x11.XQueryTree.argtypes = [ctypes.c_void_p, ctypes.c_ulong,
                               ctypes.POINTER(ctypes.c_ulong), ctypes.POINTER(ctypes.c_ulong),
                               ctypes.POINTER(ctypes.POINTER(ctypes.c_ulong)),
                               ctypes.POINTER(ctypes.c_uint)]
    x11.XGetWindowAttributes.argtypes = [ctypes.c_void_p, ctypes.c_ulong,
                                         ctypes.POINTER(_XWindowAttributes)]
    x11.XSetInputFocus.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int,
                                   ctypes.c_ulong]
    x11.XFlush.argtypes = x11.XCloseDisplay.argtypes = x11.XFree.argtypes = [ctypes.c_void_p]
    display = x11.XOpenDisplay(os.environ.get("DISPLAY", "").encode() or None)
    assert display, "no X display to focus a window on"
    try:
        root, parent = ctypes.c_ulong(), ctypes.c_ulong()
        children, count = ctypes.POINTER(ctypes.c_ulong)(), ctypes.c_uint()
        x11.XQueryTree(display, x11.XDefaultRootWindow(display), ctypes.byref(root),
                       ctypes.byref(parent), ctypes.byref(children), ctypes.byref(count))
        best, area = None, 0
        for i in range(count.value):
            attributes = _XWindowAttributes()
            x11.XGetWindowAttributes(display, children[i], ctypes.byref(attributes))
            if attributes.map_state == 2 and attributes.width * attributes.height > area:
                best, area = children[i], attributes.width * attributes.height
        if children:
            x11.XFree(children)
        assert best is not None, "no mapped window to focus"
        x11.XSetInputFocus(display, best, 2, 0)   # RevertToParent, CurrentTime
        x11.XFlush(display)
        return "X input focus on window 0x%x" % best
    finally:
        x11.XCloseDisplay(display)


# ------------------------------------------------------------------ the sidebar

def sidebar():
    _, area, _ = view3d()
    return [r for r in area.regions if r.type == 'UI'][0]


def open_tab():
    """Click the sidebar's Edge Deform tab (the 4th, below Item, Tool and View; 3.4 has no
    Python access to the active tab)."""
    ui = sidebar()
    at = (ui.x + ui.width - 10, ui.y + ui.height - 225)
    event('MOUSEMOVE', at=at)
    yield
    tap('LEFTMOUSE', at=at)
    for _ in range(3):
        yield


def grab_from_the_panel(ob):
    """Tab into Edit Mode on `ob` and start Grab Deform from the panel's button on the
    selected vertices, as an artist starts it; the pointer rests at the view's centre."""
    activate(ob)
    event('MOUSEMOVE', at=center())
    yield
    tap('TAB')
    yield from until(lambda: ob.mode == 'EDIT')
    yield from press_button("bpy.ops.edge_deform.grab(")
    yield from until(lambda: running() is not None)
    assert running() is not None, "the panel's Grab Deform did not start Grab"
    event('MOUSEMOVE', at=center())
    yield
    yield


def live_from_the_panel(ob):
    """Make `ob` active and start Live Deform from the panel's button, as an artist does;
    the pointer then rests at the view's centre."""
    activate(ob)
    event('MOUSEMOVE', at=center())
    yield
    yield from press_button("bpy.ops.edge_deform.live(")
    yield from until(lambda: running() is not None, 60)
    assert running() is not None, "the panel's Live Deform did not start Live"
    event('MOUSEMOVE', at=center())
    yield


def solve_and_bake(frames):
    """The panel's Solve, then F3 "bake frames" (the scene's range, `frames` frames), each
    waited for until it reports."""
    from helpers import Told
    with Told() as told:
        yield from press_button("bpy.ops.edge_deform.solve(", columns=(LEFT,))
        yield from until(lambda: told.has('INFO', "Solved"), 60)
        yield from f3("bake frames")
        yield from until(lambda: told.has('INFO', "Baked %d frames" % frames), 120)
    assert told.has('INFO', "Baked %d frames" % frames), told.messages


def sidebar_sections(sections, handle, after_setup=lambda: None):
    """The steps of a window test made of sections: each runs on a fresh scene (setup(),
    its handle's indices put in `handle[0]`, then `after_setup()`) with the Edge Deform tab
    open. EDGEDEFORM_SECTIONS=s1,s4 runs a few by hand."""
    def steps():
        tap('ESC')   # dismiss the splash screen
        yield
        only = os.environ.get("EDGEDEFORM_SECTIONS", "").split(",")
        chosen = [s for s in sections if only == [""] or s.__name__.split("_")[0] in only]
        tab = []

        def fresh_scene(_section):
            handle[0], _ = setup()
            if not tab:
                yield from open_tab()
                tab.append(True)
            after_setup()
            yield
        yield from run_sections(chosen, fresh_scene)
    return steps


def _copy_keys(active):
    for keymap in bpy.context.window_manager.keyconfigs.active.keymaps:
        for item in keymap.keymap_items:
            if item.idname in COPY_KEYMAP_ITEMS:
                item.active = active


# Where the last find_button found its button (window pixels), or None; what else it saw.
FOUND = [None]
SEEN = []

# Columns of the sidebar to probe, as fractions of its width without the tab strip:
# buttons that fill a row or its left half; a row's right half; the icon column (three
# probes: an icon button is narrow).
LEFT, RIGHT, ICONS = 0.3, 0.7, (0.8, 0.85, 0.9)


def find_button(command, columns=(LEFT, RIGHT), step=8):
    """Probe the sidebar from its top for the button whose Python command starts with
    `command` (e.g. "bpy.ops.edge_deform.solve("); FOUND[0] is its position, or None."""
    ui = sidebar()
    wm = bpy.context.window_manager
    FOUND[0] = None
    SEEN.clear()
    _copy_keys(False)
    try:
        for fraction in columns:
            x = ui.x + int(fraction * (ui.width - 24))
            for y in range(ui.y + ui.height - 30, ui.y + 10, -step):
                wm.clipboard = ""
                event('MOUSEMOVE', at=(x, y))
                yield
                tap('C', at=(x, y), ctrl=True)
                yield
                if wm.clipboard.startswith(command):
                    FOUND[0] = (x, y)
                    return
                if wm.clipboard and wm.clipboard not in SEEN:
                    SEEN.append(wm.clipboard)
    finally:
        _copy_keys(True)


def press_button(command, columns=(LEFT, RIGHT)):
    """Find the panel's button for `command` and click it, as an artist does."""
    yield from find_button(command, columns)
    ui = sidebar()
    assert FOUND[0] is not None, "no button for %s in the sidebar (x %d, width %d; found %s)" % (
        command, ui.x, ui.width, SEEN)
    event('MOUSEMOVE', at=FOUND[0])
    yield
    tap('LEFTMOUSE', at=FOUND[0])
    yield


def f3(text):
    """F3 over the view (Blender 3.x: menu search), type `text`, Enter: the first match."""
    win = bpy.context.window_manager.windows[0]
    at = center()
    event('MOUSEMOVE', at=at)
    yield
    tap('F3', at=at)
    yield
    for ch in text:
        kind = 'SPACE' if ch == ' ' else ch.upper()
        win.event_simulate(type=kind, value='PRESS', unicode=ch, x=at[0], y=at[1])
        win.event_simulate(type=kind, value='RELEASE', x=at[0], y=at[1])
    yield
    yield
    tap('RET', at=at)
    yield


# ------------------------------------------------------------------ pixels

def window_pixels(name, x_screen=False):
    """A screenshot of the window as an (h, w, 3) array, row 0 at the bottom (Blender's
    region coordinates). x_screen: captured from the X screen (`xwd`), leaving Blender's
    state alone (its screenshot operator stops the status bar's report banner)."""
    if x_screen:
        import screen_capture
        os.makedirs(OUT, exist_ok=True)
        screen_capture._capture_x_screen(os.path.join(OUT, name))
        print("screenshot:", os.path.join(OUT, name), "- xwd -root")
    else:
        screenshot(name)
    image = bpy.data.images.load(os.path.join(OUT, name))
    try:
        w, h = image.size
        px = np.empty(w * h * 4, np.float32)
        image.pixels.foreach_get(px)
        return px.reshape(h, w, 4)[:, :, :3]
    finally:
        bpy.data.images.remove(image)


def status_bar(px):
    """The status bar's pixels in a window screenshot: the rows below the screen's areas
    (the status bar is a global area of the window, not one of `screen.areas`)."""
    win = bpy.context.window_manager.windows[0]
    bottom = min(a.y for a in win.screen.areas)
    assert bottom > 10, "no status bar below the areas (%d px)" % bottom
    return px[:bottom]


def changed_columns(before, after, least=0.08, narrowest_banner=100):
    """The x range (first, last) of a report banner that `after` shows and `before` did not,
    or None. A banner is a filled box, so its columns change without a break (Blender 3.4
    draws it right of the middle, 4.3 centred); the key hints at the left and the icons at
    the right change too, but a word or an icon at a time: runs under 100 px (at most 40
    seen) are not a banner."""
    diff = np.abs(after - before).max(axis=(0, 2)) > least
    cols = np.flatnonzero(diff)
    if cols.size == 0:
        return None
    longest = max(np.split(cols, np.flatnonzero(np.diff(cols) > 1) + 1), key=len)
    return (int(longest[0]), int(longest[-1])) if len(longest) >= narrowest_banner else None


def ui_text_width(text):
    """`text`'s width in Blender's UI font at the UI's size (what a label takes)."""
    import blf
    scale = bpy.context.preferences.system.ui_scale or 1.0
    font = 0
    try:
        blf.size(font, 11 * scale)
    except TypeError:
        blf.size(font, 11 * scale, 72)
    return blf.dimensions(font, text)[0]
