"""Screenshots of the Edge Deform sidebar for docs/addon.md (run under Xvfb, see
docs/addon.md): the bound plane with a handle, a static group and a painted stiffness
group, at the default sidebar width and dragged narrower, in Object Mode and in Weight
Paint. Images go to $EDGEDEFORM_TEST_OUT/panel_*.png (whole window; crop for the docs)."""

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
    print("sidebar width (default):", ui.width)
    screenshot("panel_default.png")
    # "Narrow": simulated drags of the region edge did not resize the sidebar under Xvfb,
    # and 3.4 cannot set a region's width from Python. Larger text in the same width
    # leaves each label the room it would have in a sidebar 13/11 = 1.18 times narrower.
    style = bpy.context.preferences.ui_styles[0]
    style.widget.points = style.widget_label.points = style.panel_title.points = 13
    for _ in range(5):
        yield
    print("text 13 pt instead of 11 pt in a sidebar of", sidebar().width, "px")
    screenshot("panel_narrow.png")


main(steps)
