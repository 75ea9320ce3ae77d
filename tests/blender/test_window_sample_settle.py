"""Real-window test (Xvfb, --enable-event-simulate): how long Live Deform takes to settle
after a move on the largest sample scene (blend_samples' head: 12,977 vertices, painted
stiffness 0 / 0.5 / 1), done as an artist does it: the scene as make_samples.py builds it
(bound at frame 1, solved at its edit frame), Live Deform from the panel's button, G on the
controller Live selects, a drag, Enter; then the wall time from that Enter until Live says
"settled". Three moves; each time and Live's own figures are printed, with their median.

No speed is asserted here (the machine is shared and noisy; docs/addon-tests.md records
the figures with date, machine and load). The test fails if Live does not settle within
its own limit, if the mesh does not follow the controller, or if anything escapes.
"""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import ROOT, bpy, np, register  # noqa: E402
from window_harness import center, g_drag, main, override, tap, until, view3d  # noqa: E402
from window_ui import open_tab, press_button  # noqa: E402

SAMPLE = "head"
MOVES = ((40, 0), (0, 40), (-40, -40))   # pixels, one G drag each


def build_sample():
    """The sample scene as make_samples.py builds it (its functions, in this session)."""
    sys.path.insert(0, os.path.join(ROOT, "blend_samples"))
    import make_samples
    import regions
    scene = next(s for s in regions.load_scenes() if s["name"] == SAMPLE)
    ob, have_settings = make_samples.build_scene(scene)
    assert have_settings, "the add-on's settings are missing"
    return ob


def running():
    from edge_deform import op_common
    return op_common.running_tool()


def status():
    tool = running()
    return (getattr(tool, "status_text", "") or "") if tool is not None else ""


def steps():
    tap('ESC')   # dismiss the splash screen
    yield
    register()
    t0 = time.perf_counter()
    ob = build_sample()
    print("  %s built, bound and solved in %.1f s: %d vertices, acceleration %s"
          % (SAMPLE, time.perf_counter() - t0, len(ob.data.vertices),
             ob.edge_deform.acceleration))
    _, area, _ = view3d()
    area.spaces.active.show_region_ui = True
    with override():
        bpy.ops.view3d.view_all()
    for _ in range(5):
        yield
    yield from open_tab()
    for other in bpy.context.view_layer.objects:
        other.select_set(other == ob)
    bpy.context.view_layer.objects.active = ob
    yield from press_button("bpy.ops.edge_deform.live(")
    yield from until(lambda: "settled" in status(), 300)
    assert "settled" in status(), "Live did not settle on the solved sample: %s" % status()
    controller = bpy.context.view_layer.objects.active
    assert controller != ob, "Live selects a controller for G"
    times = []
    for dx, dy in MOVES:
        c0 = controller.matrix_world.translation.copy()
        yield from g_drag((dx // 2, dy // 2), (dx, dy))
        confirmed = time.perf_counter()
        yield from until(lambda: (controller.matrix_world.translation - c0).length > 1e-3
                         and "settling" in status(), 60)
        yield from until(lambda: "settled" in status() or "stopped after" in status(), 600)
        waited = time.perf_counter() - confirmed
        text = status()
        assert "settled" in text, "Live did not settle after a move: %s" % text
        moved = (controller.matrix_world.translation - c0).length
        times.append(waited)
        print("  SETTLE %s, %d vertices, controller moved %.3f: %.1f s from Enter to "
              "'settled' (Live: %s)" % (SAMPLE, len(ob.data.vertices), moved, waited, text))
    print("  SETTLE median %.1f s over %d moves (%s)" % (
        float(np.median(times)), len(times), ", ".join("%.1f" % t for t in times)))
    event_at = center(0, -150)
    tap('ESC', at=event_at)
    yield from until(lambda: running() is None)
    assert running() is None


main(steps, limit_s=1500)
