"""Real-window test (Xvfb, --enable-event-simulate): proportional editing an artist trusts
(records 0066-0068), one section per finding of the walk-through that asked for it, each
on a fresh scene, each failing on the add-on before it (243555a); the tools are started as
an artist does (the panel's buttons, Blender's keys).

  1 no tick is sized from another system's speed: after O turns proportional off (a few
    vertices to the whole mesh) in Live and in Grab, the first whole-mesh solve call asks
    for no more than settle.LEAST_ITERATIONS (it measures first); before, it asked for
    hundreds sized from the small region's speed (the walk-through's 14-26 s freeze);
  3 the circle is drawn around each handle that moves (not at the centroid of all the
    handles); the first radius fits the object (a 125-unit plane: a fraction of its size,
    not 1 m), then is remembered; a change of radius or O after Live stopped restarts the
    settle and its text;
  4 a whole-mesh settle that runs long says once that a radius (O, wheel) makes the edit
    local and quick: Live in a report and over the view, Grab in its header;
  5 O off in Live says that the whole mesh settles on from the shape shown, and O's
    tooltip says the shape can depend on the way there;
  L3 inside Live, O and the wheel act during Blender's own G of the controller;
  L4 Grab's refusal of a radius within which only the rest of the handle lies names the
    handle, and no key of a tool that did not start;
  L5 Grab's header with proportional on fits the view's header (blf widths).
Screenshots: $EDGEDEFORM_TEST_OUT/walk_*.png.
"""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (Told, activate, add_group, add_handle, bpy, make_object, np,  # noqa: E402
                     positions, select_only, engine, visible)
from bpy_extras.view3d_utils import location_3d_to_region_2d  # noqa: E402
from mathutils import Vector  # noqa: E402
from window_harness import (at_rest, center, ctrl, dragged_at_rest, event, main,  # noqa: E402
                            override, plane, running, tap, until, view3d)
from window_ui import (grab_from_the_panel, live_from_the_panel, press_button,  # noqa: E402
                       sidebar_sections, ui_text_width, window_pixels)


def width(ob):
    return float(np.ptp(positions(ob.data)[:, 0]))


def grid(n):
    """An n x n grid in XZ as wide as the test plane (1.25), replacing the scene's objects:
    a handle 'H' (a small patch at the +x edge's middle, controller 'H_ctrl') and a static
    'S' (the -x column). Returns (object, handle indices)."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    t = np.linspace(-0.625, 0.625, n)
    x, z = np.meshgrid(t, t, indexing="ij")
    V = np.stack([x.ravel(), np.zeros(n * n), z.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    faces = np.stack([a, a + n, a + n + 1, a + 1], axis=1)
    ob = make_object("grid", V, faces)
    handle = np.flatnonzero((V[:, 0] > 0.6) & (np.abs(V[:, 2]) < 0.03))
    add_group(ob, "H", handle)
    add_group(ob, "S", np.flatnonzero(V[:, 0] < -0.62))
    ob.edge_deform.static_group = "S"
    add_handle(ob, "H", V[handle].mean(axis=0))
    activate(ob)
    with override():
        bpy.ops.view3d.view_all()
    return ob, handle


def live_text():
    return " / ".join(running().text.drawn or [])


def circles():
    """The circles the running tool drew last, as a list of (x, y, radius) in region
    pixels (the add-on before record 0066 drew one, `circle.drawn`, a tuple)."""
    tool = running()
    drawn = tool.circles.drawn if hasattr(tool, "circles") else tool.circle.drawn
    if drawn is None:
        return []
    return [drawn] if isinstance(drawn[0], float) else list(drawn)


class SolveCalls:
    """Every Binding.solve call while active: (free vertices, iterations asked, ms, claim
    checks, factoring ms)."""

    def __enter__(self):
        self.calls, self.original = [], engine.Binding.solve
        original, calls = self.original, self.calls

        def solve(binding, targets, iterations, *args, **kwargs):
            t0 = time.perf_counter()
            r = original(binding, targets, iterations, *args, **kwargs)
            calls.append((int(r.free_vertices), int(iterations),
                          (time.perf_counter() - t0) * 1e3, int(r.claim_checks),
                          float(r.factor_ms)))
            return r
        engine.Binding.solve = solve
        return self

    def __exit__(self, *exc):
        engine.Binding.solve = self.original
        return False

    def of_size(self, free):
        return [c for c in self.calls if c[0] == free]


def whole_mesh_calls_are_measured_first(calls, free, what):
    """The first call on the whole mesh asks for no more than LEAST_ITERATIONS; prints the
    calls' speed and the longest call (no time is asserted: a shared machine)."""
    from edge_deform import modal_rules
    whole = calls.of_size(free)
    assert whole, "%s: no whole-mesh solve (%d free) among %s" % (
        what, free, sorted({c[0] for c in calls.calls}))
    small = [c for c in calls.calls if c[0] < free]
    ms = np.median([c[2] / c[1] for c in whole])
    print("  %s: region calls %s; first whole-mesh call asked %d iterations (%.2f ms "
          "each on the whole mesh, so %.0f ms); longest call %.0f ms"
          % (what, [c[1] for c in small][-3:], whole[0][1], ms, whole[0][1] * ms,
             max(c[2] for c in whole)))
    print("  calls (iterations, ms, checks, factoring ms): %s" % [
        (c[1], round(c[2]), c[3], round(c[4])) for c in whole])
    assert whole[0][1] <= modal_rules.LEAST_ITERATIONS, (
        "%s: the first whole-mesh call asked for %d iterations, sized from the region's "
        "speed" % (what, whole[0][1]))


# ---------------------------------------------------------------------------- sections

def s1_no_tick_sized_from_the_region_after_o_off():
    """A 6,400-vertex grid, a radius of 2.5 grid steps (a few dozen free vertices):
    Live settles a lift, then O (whole mesh). Then Grab of the handle with the same
    radius, O during the drag. The first whole-mesh call measures."""
    n = 80
    ob, handle = grid(n)
    s = ob.edge_deform
    s.proportional = True
    s.proportional_radius = 2.5 * 1.25 / (n - 1)
    free = n * n - len(handle) - n                    # all but the handle and the static
    yield from live_from_the_panel(ob)
    ctrl().location.y += 0.05
    yield from until(lambda: at_rest() and running().settle.iterations > 0, 30)
    assert at_rest(), running().status_text
    with SolveCalls() as calls:
        tap('O', at=center())
        yield from until(lambda: calls.of_size(free) and at_rest(), 60)
        t0 = time.monotonic()
        tap('ESC', at=center())
        yield from until(lambda: running() is None, 60)
        print("  Esc after O off answered in %.2f s" % (time.monotonic() - t0))
    whole_mesh_calls_are_measured_first(calls, free, "Live")

    s.proportional = True
    select_only(ob.data, handle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 40))
    yield from until(dragged_at_rest, 30)
    with SolveCalls() as calls:
        tap('O', at=center(0, 40))
        yield from until(lambda: calls.of_size(free) and at_rest(), 60)
    whole_mesh_calls_are_measured_first(calls, free, "Grab")
    tap('ESC', at=center(0, 40))
    yield from until(lambda: running() is None)


def s3_circle_around_each_moving_handle():
    """Two handles at the plane's two ends (no static), proportional on: after a lift of
    one, the circle is around it, not at the centroid of both (where nothing is freed)."""
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    s.static_group = ""
    rest = positions(ob.data).astype(float)
    w = width(ob)
    other = np.flatnonzero(rest[:, 0] < rest[:, 0].min() + 0.1 * w)
    add_group(ob, "H2", other)
    add_handle(ob, "H2", rest[other].mean(axis=0))
    s.proportional = True
    s.proportional_radius = 0.2 * w
    yield from live_from_the_panel(ob)
    ctrl().location.y += 0.1 * w
    yield from until(lambda: at_rest() and running().settle.iterations > 0, 30)
    yield
    yield
    _, _, region = view3d()
    rv3d = region.data
    shown = visible(ob)

    def on_screen(points):
        p = location_3d_to_region_2d(region, rv3d, ob.matrix_world @ Vector(points.mean(axis=0)))
        return np.array([p.x, p.y])
    moving, still, both = (on_screen(shown[handle]), on_screen(shown[other]),
                           on_screen(shown[np.concatenate([handle, other])]))
    drawn = circles()
    window_pixels("walk_3_circles.png")
    print("  circles %s; the lifted handle at %s, the other at %s, their centroid at %s"
          % ([tuple(np.round(c)) for c in drawn], moving.round(), still.round(), both.round()))
    centres = [np.array(c[:2]) for c in drawn]
    assert any(np.linalg.norm(c - moving) < 3 for c in centres), \
        "no circle around the lifted handle"
    assert not any(np.linalg.norm(c - both) < 10 for c in centres), \
        "a circle at the centroid of both handles, where nothing is freed"
    assert not any(np.linalg.norm(c - still) < 3 for c in centres), \
        "a circle around the handle that did not move"


def s3b_first_radius_fits_the_object():
    """A plane 125 units wide: O in Live gives a radius that fits it (between 0.1 and 0.5
    of its size), not Blender's 1 m; the wheel's radius is kept through O off and on."""
    ob = plane()
    s = ob.edge_deform
    co = positions(ob.data) * 100.0
    ob.data.vertices.foreach_set("co", co.ravel())
    ob.data.update()
    ctrl().location = ctrl().location * 100.0
    bpy.context.view_layer.update()
    ob.edge_deform.handles[0].rest_matrix = ctrl().matrix_world.copy()
    with override():
        bpy.ops.view3d.view_all()
    size = float(np.ptp(co, axis=0).max())
    yield from live_from_the_panel(ob)
    tap('O', at=center())
    yield from until(lambda: s.proportional and at_rest(), 30)
    fitted = s.proportional_radius
    print("  first radius %.4g on a plane %.4g wide (%.3f of it)" % (fitted, size, fitted / size))
    assert 0.1 * size <= fitted <= 0.5 * size, "the first radius %.4g on a %.4g-unit object" % (
        fitted, size)
    tap('WHEELDOWNMOUSE', at=center())
    yield from until(lambda: abs(s.proportional_radius - 1.1 * fitted) < 1e-4 * fitted, 5)
    tap('O', at=center())
    yield from until(lambda: not s.proportional, 5)
    tap('O', at=center())
    yield from until(lambda: s.proportional, 5)
    assert abs(s.proportional_radius - 1.1 * fitted) < 1e-4 * fitted, \
        "the radius is remembered (%.4g, was %.4g)" % (s.proportional_radius, 1.1 * fitted)


def s3c_radius_change_restarts_the_settle_and_its_text():
    """A 3,600-vertex grid, tolerance 0 (it never settles), a 300-iteration limit, a radius
    of 2.5 grid steps: Live stops. O (the whole mesh), and after the same stop a radius of
    half the grid typed in the panel, each start a new settle: the text says so, not
    "stopped", when the mesh has changed (before, the first tick on the larger region ran
    to the limit at once: the walk-through's 13 % change under "stopped after 2000
    iterations")."""
    n = 60
    ob, handle = grid(n)
    s = ob.edge_deform
    s.tolerance = 0.0
    s.proportional = True
    small = s.proportional_radius = 2.5 * 1.25 / (n - 1)
    yield from live_from_the_panel(ob)
    running().settle._limit = 300
    changes = (("O", lambda: tap('O', at=center())),
               ("a typed radius", lambda: setattr(s, "proportional_radius", 0.6)))
    for what, change in changes:
        ctrl().location.y += 0.05
        yield from until(lambda: "stopped after 300 iterations" in live_text(), 30)
        assert "stopped after 300 iterations" in live_text(), live_text()
        shown = visible(ob)
        change()
        yield from until(lambda: np.abs(visible(ob) - shown).max() > 1e-6, 10)
        text, count = running().status_text, running().settle.iterations  # (as it is now)
        print("  after %s: %s iterations, %r" % (what, count, text.split(" / ")[0]))
        assert np.abs(visible(ob) - shown).max() > 1e-6, "%s: the mesh did not change" % what
        assert "stopped" not in text, "%s changed the mesh, the text still says %r" % (what,
                                                                                   text)
        s.proportional, s.proportional_radius = True, small


def s4_a_long_whole_mesh_settle_suggests_a_radius():
    """A 6,400-vertex grid, tolerance 1e-6, proportional off: Live's settle runs long and
    says once (a report and over the view) that a radius makes it local and quick; Grab
    says it in its header."""
    ob, handle = grid(80)
    s = ob.edge_deform
    s.tolerance = 1e-6
    with Told() as told:
        yield from live_from_the_panel(ob)
        ctrl().location.y += 0.1
        yield from until(lambda: told.has('INFO', "radius"), 30)
        hints = [m for m in told.messages if "radius" in m[1] and "Proportional" in m[1]]
        print("  Live's hint: %s" % hints)
        assert len(hints) == 1, told.messages
        assert "O" in hints[0][1], hints
        assert any("radius" in line for line in running().text.drawn or []), running().text.drawn
        ctrl().location.y += 0.05
        for _ in range(40):
            yield
        assert len([m for m in told.messages if "radius" in m[1]]) == 1, "said once"
    tap('ESC', at=center())
    yield from until(lambda: running() is None)
    select_only(ob.data, handle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 60))
    yield from until(lambda: "radius" in (running().header_text or ""), 30)
    print("  Grab's header: %s" % running().header_text)
    assert "radius" in running().header_text and "O" in running().header_text


def s5_o_off_says_it_continues_from_the_shape_shown():
    """O off in Live: the text says the whole mesh settles on from the shape shown, and
    O's tooltip (the Proportional setting's description) says the way there counts."""
    ob = plane()
    s = ob.edge_deform
    s.proportional = True
    s.proportional_radius = 0.3 * width(ob)
    yield from live_from_the_panel(ob)
    ctrl().location.y += 0.1
    yield from until(lambda: at_rest() and running().settle.iterations > 0, 30)
    tap('O', at=center())
    yield from until(lambda: not s.proportional, 5)
    yield
    assert "from the shape shown" in live_text(), live_text()
    tip = type(s).bl_rna.properties["proportional"].description
    assert "shape shown" in tip and "Solve" in tip, tip


def l3_o_and_wheel_inside_lives_g():
    """Live, G over the view (Blender's G moves the controller), O mid-move: Edge Deform's
    proportional turns on; the wheel grows its radius; Enter ends the G, Live goes on."""
    ob = plane()
    s = ob.edge_deform
    s.proportional_radius = r0 = 0.3 * width(ob)
    yield from live_from_the_panel(ob)
    yield from until(at_rest, 20)
    x0 = ctrl().location.x
    tap('G', at=center())
    yield
    event('MOUSEMOVE', at=center(40, 0))
    yield
    tap('O', at=center(40, 0))
    yield from until(lambda: s.proportional, 5)
    assert s.proportional, "O inside Live's G"
    assert not bpy.context.scene.tool_settings.use_proportional_edit_objects, \
        "Blender's own object proportional stays as it was"
    tap('WHEELDOWNMOUSE', at=center(40, 0))
    yield from until(lambda: abs(s.proportional_radius - 1.1 * r0) < 1e-5 * r0, 5)
    assert abs(s.proportional_radius - 1.1 * r0) < 1e-5 * r0, s.proportional_radius
    event('MOUSEMOVE', at=center(60, 0))
    yield
    tap('RET', at=center(60, 0))
    yield from until(lambda: at_rest() and running().settle.iterations > 0, 30)
    assert running() is not None, "Live goes on after the G"
    assert ctrl().location.x != x0, "the G moved the controller"
    assert circles(), "the circle is drawn"
    tap('O', at=center())
    yield from until(lambda: not s.proportional, 5)
    assert not s.proportional, "after the G, O is Live's again"


def l4_grab_refusal_names_the_handle():
    """One vertex in the middle of handle 'H' selected, a radius of a grid step: every
    vertex within it is the rest of the handle, which Grab pins. The refusal says so and
    names no key (Grab did not start)."""
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    inner = handle[np.argmin(np.linalg.norm(rest[handle] - rest[handle].mean(axis=0), axis=1))]
    s.proportional = True
    s.proportional_radius = 1.1 * 1.25 / 28
    select_only(ob.data, [inner])
    activate(ob)
    event('MOUSEMOVE', at=center())
    yield
    tap('TAB')
    yield from until(lambda: ob.mode == 'EDIT')
    with Told() as told:
        yield from press_button("bpy.ops.edge_deform.grab(")
        for _ in range(5):
            yield
    assert running() is None, "Grab must not start"
    errors = [m for lv, m in told.messages if lv == 'ERROR']
    print("  refusal: %s" % errors)
    assert errors and "'H'" in errors[0], errors
    assert "Wheel" not in errors[0] and "(O)" not in errors[0], \
        "names keys of a tool that did not start: %s" % errors[0]


def l5_grab_header_fits_the_view():
    """Grab with proportional on, dragged, refused a radius, stopped after 2,000
    iterations: each header's text is narrower than the view's header (Blender cuts it at
    the right)."""
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    s.proportional = True
    s.proportional_radius = 0.5 * width(ob)
    select_only(ob.data, handle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 60))
    yield from until(dragged_at_rest, 30)
    tap('X', at=center(0, 60))
    yield
    _, area, _ = view3d()
    header = [r for r in area.regions if r.type == 'HEADER'][0]
    texts = [running().header_text]
    for _ in range(80):          # shrink until a Page Down is refused
        if "kept" in running().header_text:
            break
        tap('PAGE_DOWN', at=center(0, 60))
        yield
    texts.append(running().header_text)
    window_pixels("walk_l5_grab_header.png")
    s.tolerance = 0.0                        # never settles: it stops, and says so
    running().settle._limit = 2000
    event('MOUSEMOVE', at=center(0, 70))
    yield from until(lambda: "stopped" in running().header_text, 60)
    texts.append(running().header_text)
    for text in texts:
        print("  header %.0f px of %d: %s" % (ui_text_width(text), header.width, text))
        assert ui_text_width(text) < header.width - 40, \
            "%.0f px of text in a %d px header" % (ui_text_width(text), header.width)


SECTIONS = [s1_no_tick_sized_from_the_region_after_o_off, s3_circle_around_each_moving_handle,
            s3b_first_radius_fits_the_object, s3c_radius_change_restarts_the_settle_and_its_text,
            s4_a_long_whole_mesh_settle_suggests_a_radius,
            s5_o_off_says_it_continues_from_the_shape_shown, l3_o_and_wheel_inside_lives_g,
            l4_grab_refusal_names_the_handle, l5_grab_header_fits_the_view]
HANDLE = [None]


main(sidebar_sections(SECTIONS, HANDLE), limit_s=900)
