"""Real-window test (Xvfb, --enable-event-simulate): how long Live Deform takes to settle
after a move on the largest sample scene (blend_samples' head: 12,977 vertices, painted
stiffness 0 / 0.5 / 1), done as an artist does it: the scene as make_samples.py builds it
(bound at frame 1, solved at its edit frame), Live Deform from the panel's button, G on the
controller Live selects, a drag, Enter; then the wall time from that Enter until Live is
at rest: "settled", or "stopped after 2000 iterations, not converged" (its give-up limit).
Small nudges and one larger move; each time and Live's own words are printed.

Neither speed nor convergence is asserted here (the machine is shared and noisy, and
whether a move converges is the solver's matter: docs/addon-tests.md records what was
seen, with date, machine and load). The test fails if Live does not come to rest, if the
handle does not follow its controller, or if anything escapes.
"""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import ROOT, bpy, np, register  # noqa: E402
from window_harness import (center, g_drag, main, override, screenshot, tap,  # noqa: E402
                            until, view3d)
from window_ui import open_tab, press_button  # noqa: E402

SAMPLE = "head"
MOVES = ((10, 0), (0, 10), (-10, -10), (40, 0))   # pixels, one G drag each


def build_sample():
    """The sample scene as make_samples.py builds it (its functions, in this session)."""
    sys.path.insert(0, os.path.join(ROOT, "blend_samples"))
    import make_samples
    import regions
    scene = next(s for s in regions.load_scenes() if s["name"] == SAMPLE)
    ob, have_settings = make_samples.build_scene(scene)
    assert have_settings, "the add-on's settings are missing"
    return ob


def shown(ob):
    from edge_deform import mesh_io
    return mesh_io.addon_shape(ob)


def group_weights(ob, group):
    from edge_deform import mesh_io
    return mesh_io.read_group_weights(ob, [group])[group]


def running():
    from edge_deform import modal
    return modal.running_tool()


def status():
    tool = running()
    return (getattr(tool, "status_text", "") or "") if tool is not None else ""


def steps():
    tap('ESC')   # dismiss the splash screen
    yield
    register()
    t0 = time.perf_counter()
    ob = build_sample()
    print("  %s built, bound and solved in %.1f s: %d vertices, acceleration %s; load "
          "average %.1f" % (SAMPLE, time.perf_counter() - t0, len(ob.data.vertices),
                            ob.edge_deform.acceleration, os.getloadavg()[0]))
    _, area, _ = view3d()
    area.spaces.active.show_region_ui = True
    for other in bpy.context.view_layer.objects:
        other.select_set(other == ob)
    bpy.context.view_layer.objects.active = ob
    with override():
        bpy.ops.view3d.view_selected()   # the head fills the view (View > Frame Selected)
    for _ in range(5):
        yield
    yield from open_tab()
    yield from press_button("bpy.ops.edge_deform.live(")
    yield from until(lambda: "settled" in status(), 300)
    assert "settled" in status(), "Live did not settle on the solved sample: %s" % status()
    controller = bpy.context.view_layer.objects.active
    assert controller != ob, "Live selects a controller for G"
    group = next(h.vertex_group for h in ob.edge_deform.handles if h.controller == controller)
    handle = np.flatnonzero(group_weights(ob, group) > 0)
    settled = []
    for dx, dy in MOVES:
        c0 = controller.matrix_world.translation.copy()
        h0 = shown(ob)[handle].mean(axis=0)
        yield from g_drag((dx // 2, dy // 2), (dx, dy))
        confirmed = time.perf_counter()
        yield from until(lambda: (controller.matrix_world.translation - c0).length > 1e-4
                         and "settling" in status(), 60)
        yield from until(lambda: "settled" in status() or "stopped after" in status(), 900)
        waited = time.perf_counter() - confirmed
        text = status()
        assert "settled" in text or "stopped after" in text, "Live is not at rest: %s" % text
        moved = np.array(controller.matrix_world.translation - c0)
        followed = shown(ob)[handle].mean(axis=0) - h0
        assert np.abs(followed - moved).max() < 1e-3, (followed, moved)
        if "settled" in text:
            settled.append(waited)
        print("  SETTLE %s, %d vertices, a %d px drag moved the controller %.4f: %.1f s "
              "from Enter to rest (Live: %s)" % (SAMPLE, len(ob.data.vertices),
                                                  max(abs(dx), abs(dy)),
                                                  float(np.linalg.norm(moved)), waited, text))
    if settled:
        print("  SETTLE median %.1f s over the %d moves that settled; load average %.1f" % (
            float(np.median(settled)), len(settled), os.getloadavg()[0]))
    screenshot("sample_settle_%s.png" % SAMPLE)
    event_at = center(0, -150)
    tap('ESC', at=event_at)
    yield from until(lambda: running() is None)
    assert running() is None


main(steps, limit_s=1500)
