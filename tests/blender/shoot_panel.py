"""Screenshots of the Edge Deform sidebar for docs/addon.md: the bound plane with a handle,
a static group and a painted stiffness group, at the default sidebar width and dragged
60 px narrower. Run it under Xvfb with the window tests' environment and command line
(tests/blender/CMakeLists.txt), this file in place of test_<name>.py. Images go to
$EDGEDEFORM_TEST_OUT/panel_*.png (whole window; crop for the docs)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import add_group, bpy, np  # noqa: E402
from window_harness import event, main, override, screenshot, setup, tap, view3d  # noqa: E402,F401


def sidebar():
    _, area, _ = view3d()
    return [r for r in area.regions if r.type == 'UI'][0]


def steps():
    tap('ESC')
    yield
    setup()
    ob = bpy.data.objects["plane"]
    add_group(ob, "Stiffness", np.arange(len(ob.data.vertices)), 0.8)
    ob.edge_deform.stiffness_group = "Stiffness"
    # Two handles named as Add Handle names them ("Handle", "Handle.001"): the list must
    # show both names in full at both widths.
    co = np.array([v.co[:] for v in ob.data.vertices])
    add_group(ob, "Handle", np.flatnonzero(co[:, 0] > co[:, 0].max() - 0.1 * np.ptp(co[:, 0])))
    add_group(ob, "Handle.001", np.flatnonzero(np.abs(co[:, 0]) < 0.05 * np.ptp(co[:, 0])))
    ob.edge_deform.handles[0].vertex_group = "Handle"
    second = ob.edge_deform.handles.add()
    second.vertex_group = "Handle.001"
    second.controller = bpy.data.objects["H_ctrl"].copy()
    bpy.context.scene.collection.objects.link(second.controller)
    with override():
        assert bpy.ops.edge_deform.bind('EXEC_DEFAULT', True) == {'FINISHED'}
    for _ in range(5):
        yield
    ui = sidebar()
    # Open the Edge Deform tab: a click on its tab (the 4th, below Item, Tool, View; the
    # tab strip is at the sidebar's right edge. 3.4 has no Python access to the tab.)
    top = ui.y + ui.height
    event('MOUSEMOVE', at=(ui.x + ui.width - 10, top - 225))
    yield
    tap('LEFTMOUSE', at=(ui.x + ui.width - 10, top - 225))
    for _ in range(3):
        yield
    default = ui.width
    print("sidebar width (default):", default)
    screenshot("panel_default.png")
    # Narrow: drag the sidebar's edge (its resize zone starts a few pixels inside the
    # region: a press at the very edge misses it) 60 px to the right.
    x, y = ui.x + 6, ui.y + ui.height // 2
    event('MOUSEMOVE', at=(x, y))
    yield
    event('LEFTMOUSE', 'PRESS', at=(x, y))
    yield
    for k in range(1, 6):
        event('MOUSEMOVE', at=(x + 12 * k, y))
        yield
    event('LEFTMOUSE', 'RELEASE', at=(x + 60, y))
    for _ in range(5):
        yield
    width = sidebar().width
    assert width < default - 40, "the sidebar did not get narrower (%d px)" % width
    print("sidebar width (narrow):", width)
    screenshot("panel_narrow.png")
    # The rest of the panel: scroll the sidebar down.
    ui = sidebar()
    at = (ui.x + ui.width // 2, ui.y + ui.height // 2)
    event('MOUSEMOVE', at=at)
    yield
    for _ in range(12):
        tap('WHEELDOWNMOUSE', at=at)
        yield
    screenshot("panel_narrow_lower.png")


main(steps)
