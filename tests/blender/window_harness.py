"""The real-window test harness (Xvfb with --enable-event-simulate): simulated events,
a generator of steps run from a bpy.app timer so that Blender's event loop handles each
event between steps, a watchdog, and a check that no exception escaped from an operator,
a modal tick or a handler (sys.excepthook, which Blender calls when it prints one)."""

import os
import sys
import threading
import time
import traceback

from mathutils import Euler

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import OUT, bpy, key_positions, np, plane_with_end_groups, register  # noqa: E402

STEP = 0.1  # seconds between steps: several 60 Hz ticks of the tools' timers


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == 'VIEW_3D'),
               key=lambda a: a.width * a.height)
    region = [r for r in area.regions if r.type == 'WINDOW'][0]
    return win, area, region


def override():
    win, area, region = view3d()
    return bpy.context.temp_override(window=win, area=area, region=region,
                                     screen=win.screen)


def center(dx=0, dy=0):
    _, _, region = view3d()
    return region.x + region.width // 2 + dx, region.y + region.height // 2 + dy


def event(kind, value='PRESS', at=None, **mods):
    win = view3d()[0]
    x, y = at or center()
    if kind == 'MOUSEMOVE':
        value = 'NOTHING'
    win.event_simulate(type=kind, value=value, x=x, y=y, **mods)


def tap(kind, at=None, **mods):
    event(kind, 'PRESS', at, **mods)
    event(kind, 'RELEASE', at, **mods)


def screenshot(name):
    """A real picture or an exception (screen_capture: Blender 4.3 + llvmpipe saves black)."""
    import screen_capture
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, name)

    def take():
        with override():
            bpy.ops.screen.screenshot(filepath=path)
    print("screenshot:", path, "-", screen_capture.save(path, take))


def g_drag(*offsets, confirm=True):
    """Blender's own G in the viewport: the pointer to the view's centre, G, then one mouse
    move per offset (pixels from the centre), a step after each; with `confirm`, Enter at
    the last offset (no step after it: the caller waits for what it expects)."""
    event('MOUSEMOVE', at=center())
    yield
    tap('G', at=center())
    yield
    for dx, dy in offsets:
        event('MOUSEMOVE', at=center(dx, dy))
        yield
    if confirm:
        tap('RET', at=center(*offsets[-1]))


def grab_until_moved(ob, handle, rest, dy=70, least=0.01):
    """Start Grab Deform over the viewport and drag the pointer `dy` pixels down until every
    handle vertex of the output key has moved more than `least`."""
    event('MOUSEMOVE', at=center())
    yield
    with override():
        assert bpy.ops.edge_deform.grab('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    event('MOUSEMOVE', at=center(0, dy))
    yield from until(lambda: ob.data.shape_keys is not None and np.linalg.norm(
        key_positions(ob)[handle] - rest[handle], axis=1).min() > least)


def until(predicate, seconds=10.0):
    """Yield to the event loop until `predicate()` holds (a loaded machine may be slow)."""
    start = time.time()
    while time.time() - start < seconds:
        try:
            if predicate():
                return
        except (KeyError, AttributeError, ReferenceError):
            pass
        yield


def plane():
    """The plane setup() makes."""
    return bpy.data.objects["plane"]


def ctrl():
    """Its handle's controller."""
    return bpy.data.objects["H_ctrl"]


def running():
    """The Edge Deform tool running now, or None."""
    from edge_deform import modal
    return modal.running_tool()


def at_rest():
    """The running tool has settled or stopped (nothing to do until something changes)."""
    return running() is not None and running().settle.at_rest


def dragged_at_rest():
    """Grab at rest after the pointer moved (not on the press's position)."""
    return (at_rest() and running().settle.iterations > 0
            and np.abs(running().delta).max() > 0)


def keyed_lift(controller, dz, last):
    """Key `controller` where it is on frame 1 and lifted by `dz` on frame `last`; the
    scene plays frames 1 to `last`. Returns its height on frame 1."""
    z0 = controller.location.z
    controller.keyframe_insert("location", frame=1)
    controller.location.z = z0 + dz
    controller.keyframe_insert("location", frame=last)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, last
    return z0


def setup():
    register()
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    ob, _, handle, static = plane_with_end_groups()
    # A three-quarter view (the plane lies in XZ) with the add-on's sidebar tab open.
    win, area, region = view3d()
    space = area.spaces.active
    space.show_region_ui = True
    space.region_3d.view_perspective = 'PERSP'
    space.region_3d.view_rotation = Euler((1.2, 0.0, 0.5)).to_quaternion()
    try:
        [r for r in area.regions if r.type == 'UI'][0].active_panel_category = "Edge Deform"
    except (AttributeError, TypeError):
        pass
    with override():
        bpy.ops.view3d.view_all()
    return handle, static


def watchdog(seconds=240):
    """If the event loop itself stalls, timers never run: end the process from a thread
    (no bpy here) so the test fails instead of hanging."""
    def fire():
        print("WINDOW TEST STALLED after %d s (last step: %s)" % (seconds, LAST[0]))
        sys.stdout.flush()
        os._exit(2)
    timer = threading.Timer(seconds, fire)
    timer.daemon = True
    timer.start()


def run_sections(sections, prepare):
    """Run each section (a generator function) on the scene `prepare(section)` (a
    generator) makes: a failed section is reported and the next one runs; what a section
    left running is ended (Esc) and Object Mode restored. Fails at the end, naming the
    failed sections."""
    failed = []
    for section in sections:
        yield from prepare(section)
        with override():
            bpy.ops.ed.undo_push(message=section.__name__)
        try:
            yield from section()
            print("PASS", section.__name__)
        except Exception:  # noqa: BLE001 - reported; the next section runs
            traceback.print_exc()
            print("FAIL", section.__name__)
            failed.append(section.__name__)
        for _ in range(3):    # end whatever the section left running
            if running() is None:
                break
            tap('ESC', at=center(0, -150))
            yield from until(lambda: running() is None, 5)
        ob = bpy.context.active_object
        if ob is not None and ob.mode != 'OBJECT':
            with override():
                bpy.ops.object.mode_set(mode='OBJECT')
        yield
    print("sections failed: %s" % (", ".join(failed) or "none"))
    assert not failed, failed


LAST = ["start"]


ESCAPED = []


def _excepthook(kind, value, tb):
    ESCAPED.append("%s: %s" % (kind.__name__, value))
    sys.__excepthook__(kind, value, tb)


def main(steps, limit_s=400):
    """Run the generator function `steps`; exit 0 only if it finished and no exception
    escaped anywhere meanwhile, within `limit_s` seconds."""
    sys.excepthook = _excepthook
    watchdog(max(240, limit_s - 160))
    gen = steps()
    started = time.time()

    def tick():
        try:
            frame = gen.gi_frame
            LAST[0] = "line %d" % frame.f_lineno if frame is not None else "start"
            next(gen)
        except StopIteration:
            if ESCAPED:
                print("AN EXCEPTION ESCAPED:", ESCAPED)
                print("WINDOW TEST FAILED")
                sys.stdout.flush()
                os._exit(1)
            print("ALL WINDOW TESTS PASSED")
            sys.stdout.flush()
            os._exit(0)
        except Exception:
            traceback.print_exc()
            print("WINDOW TEST FAILED")
            sys.stdout.flush()
            os._exit(1)
        if time.time() - started > limit_s:   # a loaded 2-core machine is slow; ctest: 600
            print("WINDOW TEST TIMED OUT")
            sys.stdout.flush()
            os._exit(1)
        return STEP

    bpy.app.timers.register(tick, first_interval=1.0)

