"""Real-window test (Xvfb, --enable-event-simulate): proportional editing inside Live
Deform and Grab Deform, driven as an artist does (the panel's buttons, Blender's keys:
O, Alt+O, the wheel, Page Up/Down; record 0056). One section per behaviour, each on a
fresh scene:

  1 Live: O turns proportional on (the circle is drawn, measured in the screenshot's
    pixels), the wheel and Page Up/Down change the radius by Blender's 1.1 (the text over
    the view says it), O turns it off and the wheel zooms again;
  2 Live: the radius shrinks while the controller is lifted: the handles stay on their
    controller, every vertex beyond the new radius is back at rest, a further lift is
    followed; Esc puts the radius back with Live's other settings;
  3 Live: a Page Down that would free no vertex is refused, the radius kept and said;
    Live started with such a radius is refused with the reason;
  4 Grab: the header and the status bar say the radius and its keys, the wheel and Page Down change it during the drag,
    the circle is drawn, the drag goes on (the dragged vertices follow the pointer, the
    rest beyond the radius at rest); a refused Page Down keeps the radius; O turns it off;
  5 Grab with a Region group: the radius picks the region while on, the group once O
    turns it off in the drag.
Screenshots: $EDGEDEFORM_TEST_OUT/proportional_*.png.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import Told, activate, bpy, key_positions, np, positions, select_only, visible  # noqa: E402
from window_harness import (at_rest, center, ctrl, event, main, plane,  # noqa: E402
                            running, tap, until, view3d)
from window_ui import (grab_from_the_panel, live_from_the_panel, press_button,  # noqa: E402
                       sidebar_sections, window_pixels)


def distance_to(V, idx):
    return np.linalg.norm(V[:, None, :] - V[None, idx, :], axis=2).min(axis=1)


def width(ob):
    return float(np.ptp(positions(ob.data)[:, 0]))


def region_text():
    """What Live's text over the view drew last, one string."""
    return " / ".join(running().text.drawn or [])


def ring_brightening(before, after):
    """The fraction of points on the circle the tool last drew that are brighter in
    `after` than in `before` (window pixels, within a pixel of the ring)."""
    _, _, region = view3d()
    cx, cy, r = running().circles.drawn[0]
    hits = total = 0
    for t in np.linspace(0, 2 * np.pi, 48, endpoint=False):
        x = int(round(region.x + cx + r * np.cos(t)))
        y = int(round(region.y + cy + r * np.sin(t)))
        if not (region.x + 2 < x < region.x + region.width - 2
                and region.y + 2 < y < region.y + region.height - 2):
            continue
        total += 1
        a = after[y - 1:y + 2, x - 1:x + 2].mean(axis=2).max()
        b = before[y - 1:y + 2, x - 1:x + 2].mean(axis=2).max()
        hits += a > b + 0.1
    assert total >= 12, "the circle is mostly off the view (%d points on it)" % total
    return hits / total


def start_live():
    yield from live_from_the_panel(plane())


# ---------------------------------------------------------------------------- sections

def s1_live_keys_and_circle():
    ob = plane()
    s = ob.edge_deform
    s.proportional_radius = r0 = 0.3 * width(ob)
    yield from start_live()
    yield from until(at_rest, 20)
    assert "Proportional: off" in region_text(), region_text()
    before = window_pixels("proportional_live_off.png")
    tap('O', at=center())
    yield from until(lambda: running().circles.drawn is not None, 5)
    assert s.proportional, "O turned proportional on"
    yield from until(at_rest, 20)
    yield
    after = window_pixels("proportional_live_on.png")
    share = ring_brightening(before, after)
    print("  circle of %.0f px: %.0f%% of its points brighter" % (
        running().circles.drawn[0][2], 100 * share))
    assert share > 0.6, share
    r_px = running().circles.drawn[0][2]

    tap('WHEELDOWNMOUSE', at=center())
    yield from until(lambda: abs(s.proportional_radius - 1.1 * r0) < 1e-6 * r0, 5)
    assert abs(s.proportional_radius - 1.1 * r0) < 1e-6 * r0, s.proportional_radius
    yield from until(lambda: running().circles.drawn[0][2] > 1.05 * r_px, 5)
    assert running().circles.drawn[0][2] > 1.05 * r_px, "the circle grew"
    tap('PAGE_UP', at=center())
    yield from until(lambda: abs(s.proportional_radius - 1.21 * r0) < 1e-5 * r0, 5)
    assert abs(s.proportional_radius - 1.21 * r0) < 1e-5 * r0, s.proportional_radius
    for key in ('PAGE_DOWN', 'WHEELUPMOUSE'):
        tap(key, at=center())
        yield
        yield
    yield from until(lambda: abs(s.proportional_radius - r0) < 1e-5 * r0, 5)
    assert abs(s.proportional_radius - r0) < 1e-5 * r0, s.proportional_radius
    from edge_deform import engine
    yield from until(lambda: engine.length(r0) in region_text(), 5)
    assert "Proportional: %s" % engine.length(r0) in region_text(), region_text()
    assert "Wheel/PgUp/PgDn" in region_text(), region_text()
    tap('O', at=center(), alt=True)
    yield from until(lambda: "connected only" in region_text(), 5)
    assert s.proportional_connected, "Alt+O: Connected Only"

    tap('O', at=center())
    yield from until(lambda: "Proportional: off" in region_text(), 5)
    assert not s.proportional
    yield from until(lambda: running().circles.drawn is None, 5)
    assert running().circles.drawn is None, "no circle when off"
    rv3d = view3d()[1].spaces.active.region_3d
    distance = rv3d.view_distance
    tap('WHEELUPMOUSE', at=center())
    yield from until(lambda: rv3d.view_distance != distance, 5)
    assert rv3d.view_distance < distance, "off: the wheel zooms as always"
    assert abs(s.proportional_radius - r0) < 1e-5 * r0


def s2_live_resize_while_lifted():
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    w = width(ob)
    s.proportional = True
    s.proportional_radius = 0.5 * w
    yield from start_live()
    dz = 0.15 * w
    ctrl().location.z += dz

    def followed(lift):
        return at_rest() and np.abs(visible(ob)[handle, 2] - rest[handle, 2] - lift).max() < 1e-3 * w
    yield from until(lambda: followed(dz), 30)
    assert followed(dz), "Live follows the lift"
    for _ in range(5):
        tap('PAGE_DOWN', at=center())
        yield
    r = 0.5 * w / 1.1 ** 5
    yield from until(lambda: abs(s.proportional_radius - r) < 1e-5 * w, 5)
    assert abs(s.proportional_radius - r) < 1e-5 * w, s.proportional_radius
    yield from until(lambda: followed(dz) and running().settle.iterations > 0, 30)
    shown = visible(ob)
    outside = distance_to(rest, handle) > r * 1.0001
    assert np.abs(shown[handle, 2] - rest[handle, 2] - dz).max() < 1e-3 * w, \
        "the handles stay on their controller through the resize"
    assert np.abs(shown[outside] - rest[outside]).max() < 1e-6 * w, \
        "beyond the new radius: at rest"
    assert np.abs(shown[~outside] - rest[~outside]).max() > 0.01 * w, "inside: deformed"
    ctrl().location.z += dz
    yield from until(lambda: followed(2 * dz), 30)
    assert followed(2 * dz), "a further lift is followed"
    assert np.abs(visible(ob)[outside] - rest[outside]).max() < 1e-6 * w
    tap('ESC', at=center())
    yield from until(lambda: running() is None)
    assert running() is None
    assert abs(s.proportional_radius - 0.5 * w) < 1e-6 * w, "Esc puts the radius back"


def s3_live_refuses_a_radius_that_frees_nothing():
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    d = distance_to(rest, handle)
    nearest = d[d > 0].min()
    s.proportional = True
    s.proportional_radius = 1e-3 * nearest
    with Told() as told:
        yield from start_live_refused()
    assert told.has('ERROR', "No vertex can move within"), told.messages
    s.proportional_radius = 1.05 * nearest
    r = s.proportional_radius     # (stored as float32)
    yield from start_live()
    tap('PAGE_DOWN', at=center())
    yield from until(lambda: "kept" in region_text(), 5)
    assert "No vertex can move" in region_text() and "kept" in region_text(), region_text()
    assert s.proportional_radius == r, "the previous radius is kept"
    assert running() is not None, "Live goes on"


def start_live_refused():
    activate(plane())
    event('MOUSEMOVE', at=center())
    yield
    yield from press_button("bpy.ops.edge_deform.live(")
    for _ in range(5):
        yield
    assert running() is None, "Live with a radius that frees nothing must not start"


def s4_grab_keys_header_and_resize():
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    w = width(ob)
    s.proportional = True
    s.proportional_radius = r0 = 0.5 * w
    select_only(ob.data, handle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 60))

    def settled_drag():
        return (ob.data.shape_keys is not None and running() is not None
                and running().settle.at_rest and running().settle.iterations > 0
                and np.abs(running().delta).max() > 0)
    yield from until(settled_drag, 30)
    from edge_deform import engine
    header = running().header_text
    assert "Proportional: %s" % engine.length(r0) in header, header
    drawn = running().status_drawn or []
    assert "Wheel/PgUp/PgDn: radius" in drawn and "O: proportional off" in drawn, drawn
    lifted = key_positions(ob)[handle].astype(float) - rest[handle]
    assert np.abs(lifted).max() > 0.01 * w, "the drag moved the handle"

    before = window_pixels("proportional_grab_before.png")
    tap('WHEELDOWNMOUSE', at=center(0, 60))
    yield from until(lambda: abs(s.proportional_radius - 1.1 * r0) < 1e-5 * r0, 5)
    assert "Proportional: %s" % engine.length(1.1 * r0) in running().header_text
    yield from until(settled_drag, 30)
    yield
    after = window_pixels("proportional_grab_wheel.png")
    assert running().circles.drawn is not None
    share = ring_brightening(before, after)   # (the circle grew by 10 %: a new ring)
    print("  Grab circle of %.0f px: %.0f%% brighter" % (running().circles.drawn[0][2], 100 * share))
    assert share > 0.5, share

    for _ in range(6):
        tap('PAGE_DOWN', at=center(0, 60))
        yield
    r = 1.1 * r0 / 1.1 ** 6
    yield from until(lambda: abs(s.proportional_radius - r) < 1e-5 * r0, 5)
    event('MOUSEMOVE', at=center(0, 90))
    yield
    yield from until(settled_drag, 30)
    shown = key_positions(ob).astype(float)
    outside = distance_to(rest, handle) > r * 1.0001
    assert np.abs(shown[handle] - rest[handle]).max() > np.abs(lifted).max() * 1.2, \
        "the dragged vertices follow the pointer further"
    assert np.abs(shown[outside] - rest[outside]).max() < 1e-6 * w, "beyond: at rest"

    d = distance_to(rest, handle)
    s_r = s.proportional_radius
    for _ in range(80):          # shrink until a Page Down is refused
        if "kept" in running().header_text:
            break
        tap('PAGE_DOWN', at=center(0, 90))
        yield
    assert "frees no vertex" in running().header_text, running().header_text
    assert s.proportional_radius >= d[d > 0].min(), "the radius that freed vertices is kept"
    assert s.proportional_radius < s_r
    tap('O', at=center(0, 90))
    yield from until(lambda: "Proportional: off" in running().header_text, 5)
    assert not s.proportional
    tap('RET', at=center(0, 90))
    yield from until(lambda: running() is None and ob.mode == 'EDIT')
    assert running() is None and ob.mode == 'EDIT'


def s5_grab_radius_then_region_group():
    """A Region group and proportional on: the radius picks the region (vertices outside
    the group move); O off in the drag: the group does (outside it, back at rest)."""
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    w = width(ob)
    x = rest[:, 0]
    group = np.flatnonzero(x > x.max() - 0.3 * w)     # the handle's 30 %
    from helpers import add_group
    add_group(ob, "R", group)
    s.roi_group = "R"
    s.proportional = True
    s.proportional_radius = 0.7 * w
    select_only(ob.data, handle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 60))

    def settled_drag():
        return (running() is not None and running().settle.at_rest
                and running().settle.iterations > 0 and np.abs(running().delta).max() > 0)
    yield from until(settled_drag, 30)
    outside_group = np.setdiff1d(np.arange(len(rest)), group)
    moved = np.abs(key_positions(ob).astype(float) - rest).max(axis=1)
    assert moved[outside_group].max() > 1e-3 * w, "proportional on: the radius, not the group"
    tap('O', at=center(0, 60))
    yield from until(lambda: "Proportional: off" in running().header_text, 5)
    event('MOUSEMOVE', at=center(0, 80))
    yield
    yield from until(settled_drag, 30)
    shown = key_positions(ob).astype(float)
    assert np.abs(shown[outside_group] - rest[outside_group]).max() < 1e-6 * w, \
        "off: the Region group again, the rest at rest"
    assert np.abs(shown[handle] - rest[handle]).max() > 0.01 * w
    tap('RET', at=center(0, 80))
    yield from until(lambda: running() is None and ob.mode == 'EDIT')


def s6_grab_measures_from_the_dragged_vertices():
    """Grab pins the handles it does not drag where they are shown; the radius is measured
    from the dragged vertices only, as Blender's from what it moves: nothing near the pinned
    handle is freed."""
    ob, handle = plane(), HANDLE[0]
    s = ob.edge_deform
    rest = positions(ob.data).astype(float)
    w = width(ob)
    x = rest[:, 0]
    middle = np.flatnonzero(np.abs(x - 0.5 * (x.min() + x.max())) < 0.05 * w)
    s.proportional = True
    s.proportional_radius = r = 0.2 * w
    near_pinned = (distance_to(rest, handle) <= r) & (distance_to(rest, middle) > r)
    assert near_pinned.any(), "the scene needs vertices near the handle and far from the drag"
    select_only(ob.data, middle)
    yield from grab_from_the_panel(ob)
    event('MOUSEMOVE', at=center(0, 40))
    yield from until(lambda: (running() is not None and running().settle.at_rest
                              and running().settle.iterations > 0
                              and np.abs(running().delta).max() > 0), 30)
    free = np.asarray(running().solver.binding.deformer.free_vertices)
    assert free.size > 0
    assert distance_to(rest, middle)[free].max() <= r * 1.0001, "free only within r of the dragged"
    shown = key_positions(ob).astype(float)
    assert np.abs(shown[middle] - rest[middle]).max() > 0.01 * w, "the drag moved them"
    assert np.abs(shown[near_pinned] - rest[near_pinned]).max() < 1e-6 * w, "near the pinned handle: at rest"
    tap('ESC', at=center(0, 40))
    yield from until(lambda: running() is None and ob.mode == 'EDIT')


SECTIONS = [s1_live_keys_and_circle, s2_live_resize_while_lifted,
            s3_live_refuses_a_radius_that_frees_nothing, s4_grab_keys_header_and_resize,
            s5_grab_radius_then_region_group, s6_grab_measures_from_the_dragged_vertices]
HANDLE = [None]


main(sidebar_sections(SECTIONS, HANDLE), limit_s=500)
