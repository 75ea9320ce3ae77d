"""Real-window test (Xvfb, --enable-event-simulate) of the artist walk-through:
one section per finding, each asserting what the artist sees (the view header's pixels,
who sets the status bar, the mode and the shape, the panel's redraw, the reports).

Each section runs on a fresh scene and the file goes on after a failed section, so one
run says which findings hold (the summary lists them); any failure fails the test.
Screenshots go to $EDGEDEFORM_TEST_OUT/artist_*.png.
"""

import os
import re
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bmesh  # noqa: E402
from bpy_extras.view3d_utils import location_3d_to_region_2d  # noqa: E402
from helpers import Told, add_group, bpy, key_positions, np, positions  # noqa: E402
from helpers import select_only, visible  # noqa: E402
from mathutils import Vector  # noqa: E402
from window_harness import (center, ctrl, event, g_drag, grab_until_moved,  # noqa: E402
                            keyed_lift, main, override, plane, run_sections, running, screenshot,
                            setup, tap, until, view3d)
from window_ui import window_pixels  # noqa: E402


def start_live():
    bpy.context.view_layer.objects.active = plane()
    plane().select_set(True)
    with override():
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}


def region(kind):
    _, area, _ = view3d()
    return [r for r in area.regions if r.type == kind][0]


def crop(px, r):
    return px[r.y:r.y + r.height, r.x:r.x + r.width, :3]


def screen_xy(ob, idx, co):
    """The window pixels of the object-space points co[idx] (mean)."""
    _, area, reg = view3d()
    rv3d = area.spaces.active.region_3d
    mw = ob.matrix_world
    pts = [location_3d_to_region_2d(reg, rv3d, mw @ Vector(p)) for p in co[idx]]
    return np.array([[p.x, p.y] for p in pts]).mean(axis=0) + [reg.x, reg.y]


class StatusBarWatch:
    """Records every call of the add-on's compat.status_bar (who takes the status bar)."""

    def __enter__(self):
        from edge_deform import compat
        self.calls, self.original = [], compat.status_bar

        def watched(workspace, draw):
            self.calls.append(draw)
            return self.original(workspace, draw)
        compat.status_bar = watched
        return self

    def __exit__(self, *exc):
        from edge_deform import compat
        compat.status_bar = self.original
        return False

    def taken(self):
        return [c for c in self.calls if c is not None]


# ---------------------------------------------------------------------------- findings

def f01_grab_from_the_panel_is_pointer_relative():
    """Finding 1: Grab Deform from the panel's button moves nothing until the pointer moves
    in the view, then follows it pixel for pixel, as Blender's own G does."""
    ob = plane()
    handle = HANDLE[0]
    select_only(ob.data, handle)
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
    rest = positions(ob.data).astype(float)
    # Blender's G on the same selection, 40 px to the right (read while it runs), then Esc.
    start = center()                          # where Grab Deform's drag starts below
    yield from g_drag((20, 0), (40, 0), confirm=False)
    for _ in range(2):
        yield
    bm = bmesh.from_edit_mesh(ob.data)
    bm.verts.ensure_lookup_table()
    g_moved = np.array([tuple(v.co) for v in bm.verts])
    g_px = screen_xy(ob, handle, g_moved) - screen_xy(ob, handle, rest)
    tap('ESC', at=center(40, 0))
    for _ in range(3):
        yield
    assert abs(g_px[0] - 40) < 2.5, "Blender's G moved the selection %s px" % g_px
    # Grab Deform from the sidebar's button: the pointer is over the sidebar.
    ui = region('UI')
    button = (ui.x + ui.width // 2, ui.y + ui.height - 70)
    event('MOUSEMOVE', at=button)
    yield
    win, area, _ = view3d()
    # (A panel button calls its operator in the view's main region: INVOKE_REGION_WIN.)
    with bpy.context.temp_override(window=win, area=area, region=ui, screen=win.screen):
        assert bpy.ops.edge_deform.grab('INVOKE_REGION_WIN') == {'RUNNING_MODAL'}
    yield
    event('MOUSEMOVE', at=start)              # into the view: the drag starts here
    for _ in range(5):
        yield
    shown = key_positions(ob).astype(float) if ob.data.shape_keys else positions(ob.data)
    assert np.abs(shown - rest).max() < 1e-4, \
        "entering the view moved the selection %.3f" % np.abs(shown - rest).max()
    event('MOUSEMOVE', at=center(20, 0))
    yield
    event('MOUSEMOVE', at=center(40, 0))
    yield from until(lambda: ob.data.shape_keys is not None
                     and abs((screen_xy(ob, handle, key_positions(ob).astype(float))
                              - screen_xy(ob, handle, rest))[0] - 40) < 2.5)
    px = screen_xy(ob, handle, key_positions(ob).astype(float)) - screen_xy(ob, handle, rest)
    screenshot("artist_grab_from_button.png")
    assert np.abs(px - g_px).max() < 2.5, \
        "Grab Deform moved %s px where G moved %s px" % (px, g_px)
    tap('ESC', at=center(40, 0))
    yield from until(lambda: running() is None and ob.mode == 'EDIT')
    print("  grab from the button: %s px, G: %s px" % (px.round(1), g_px.round(1)))


def f02_edit_mode_shows_the_grab():
    """Finding 2: after confirming Grab Deform, Edit Mode shows the mesh as dragged."""
    ob = plane()
    handle = HANDLE[0]
    select_only(ob.data, handle)
    rest = positions(ob.data).astype(float)
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
    yield from grab_until_moved(ob, handle, rest, dy=60, least=0.05)
    tap('RET', at=center(0, 60))
    yield from until(lambda: running() is None and ob.mode == 'EDIT')
    assert ob.mode == 'EDIT', "back in Edit Mode"
    dragged = key_positions(ob).astype(float)
    bm = bmesh.from_edit_mesh(ob.data)
    bm.verts.ensure_lookup_table()
    shown = np.array([tuple(bm.verts[i].co) for i in range(len(bm.verts))])
    screenshot("artist_edit_mode_after_grab.png")
    assert np.abs(shown[handle] - dragged[handle]).max() < 1e-5, \
        "Edit Mode shows the undeformed mesh (%.3f from the dragged shape)" % \
        np.abs(shown[handle] - dragged[handle]).max()
    assert np.linalg.norm(shown[handle] - rest[handle], axis=1).min() > 0.05


def f03_live_leaves_the_header_and_status_bar():
    """Finding 3: the view's header keeps Blender's menus during Live, and Live never
    takes the status bar (a G inside Live shows its own hints there)."""
    header = region('HEADER')
    event('MOUSEMOVE', at=center(0, -150))
    yield
    before = crop(window_pixels("artist_header_before.png"), header)
    with StatusBarWatch() as bar:
        start_live()
        ctrl().location.z += 0.2
        yield from until(lambda: plane().data.shape_keys is not None)
        for _ in range(5):
            yield
        during = crop(window_pixels("artist_header_live.png"), header)
        changed = np.mean(np.abs(during - before).max(axis=2) > 0.05)
        assert changed < 0.01, "Live changed %.0f %% of the header's pixels" % (100 * changed)
        # G on the controller inside Live: Blender's transform owns header and status bar.
        bpy.context.view_layer.objects.active = ctrl()
        ctrl().select_set(True)
        plane().select_set(False)
        yield from g_drag((30, 0), confirm=False)
        for _ in range(3):
            yield
        screenshot("artist_g_inside_live.png")
        tap('RET', at=center(30, 0))
        for _ in range(4):
            yield
        assert not bar.taken(), "Live set the status bar %d times" % len(bar.taken())
    tap('ESC')
    yield from until(lambda: running() is None)


def f04_enter_over_a_field_edits_it():
    """Finding 4: Enter with the pointer over the sidebar (its fields) does not end Live."""
    start_live()
    ctrl().location.z += 0.2
    yield from until(lambda: plane().data.shape_keys is not None)
    ui = region('UI')
    over = (ui.x + ui.width // 2, ui.y + ui.height // 2)
    event('MOUSEMOVE', at=over)
    yield
    tap('RET', at=over)
    for _ in range(5):
        yield
    assert running() is not None, "Enter over the sidebar ended Live"
    tap('ESC', at=over)       # (leaves a field's text editing, if one started)
    yield
    event('MOUSEMOVE', at=center())
    yield
    tap('RET')
    yield from until(lambda: running() is None)
    assert running() is None, "Enter over the view keeps"


def f05_panel_redraws_after_bind():
    """Finding 5: the sidebar redraws when Bind ends (its Bind button becomes Unbind), the
    pointer resting on the view."""
    from edge_deform import lifecycle
    drawn = []
    handle = bpy.types.SpaceView3D.draw_handler_add(
        lambda: drawn.append(time.perf_counter()), (), 'UI', 'POST_PIXEL')
    try:
        event('MOUSEMOVE', at=center(0, -150))
        for _ in range(5):
            yield
        with Told() as told:
            with override():
                assert bpy.ops.edge_deform.bind('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
            yield from until(lambda: told.has('INFO', "Bound"))
            done = time.perf_counter()
            assert lifecycle.is_bound(plane().data)
            for _ in range(10):
                yield
        print("  f05: %d sidebar draws, %d after Bound" % (len(drawn), sum(t > done for t in drawn)))
        assert any(t > done for t in drawn), "the sidebar was not redrawn after Bind"
        screenshot("artist_panel_after_bind.png")
    finally:
        bpy.types.SpaceView3D.draw_handler_remove(handle, 'UI')


def f06_a_refused_key_says_why_on_screen():
    """Finding 6: Ctrl+Z and the λ keys with a painted group are refused where the artist
    looks: over the view, and the status bar is Blender's (its report banner shows)."""
    ob = plane()
    add_group(ob, "Stiff", np.arange(len(ob.data.vertices)), 0.8)
    ob.edge_deform.stiffness_group = "Stiff"
    with StatusBarWatch() as bar, Told() as told:
        start_live()
        yield from until(lambda: plane().data.shape_keys is not None)
        tap('Z', ctrl=True)
        yield from until(lambda: told.has('WARNING', "before undoing"))
        for _ in range(3):
            yield
        tool = running()
        text = getattr(tool, "text", None)
        shown = getattr(text, "drawn", None) or []
        assert any("before undoing" in line for line in shown), shown
        screenshot("artist_refused_undo.png")
        assert not bar.taken(), "Live's hints cover the status bar's report"
    tap('ESC')
    yield from until(lambda: running() is None)


def f07_clearing_the_painted_group_is_followed():
    """Finding 7: clearing the painted stiffness group during Live re-solves with the
    global λ, and Esc brings the group back."""
    ob = plane()
    add_group(ob, "Stiff", np.arange(len(ob.data.vertices)), 1.0)
    ob.edge_deform.stiffness_group = "Stiff"
    ob.edge_deform.stiffness = 0.0
    start_live()
    ctrl().location.z += 0.4
    yield from until(lambda: plane().data.shape_keys is not None and abs(
        ctrl().location.z) > 0 and running() is not None
        and "settled" in (getattr(running(), "status_text", "") or
                          getattr(running(), "header_text", "") or ""), 60)
    painted = key_positions(ob).copy()
    ob.edge_deform.stiffness_group = ""
    yield from until(lambda: np.abs(key_positions(ob) - painted).max() > 1e-3, 20)
    assert np.abs(key_positions(ob) - painted).max() > 1e-3, \
        "nothing re-solved after the painted group was cleared"
    tap('ESC')
    yield from until(lambda: running() is None)
    assert ob.edge_deform.stiffness_group == "Stiff", "Esc brings the group back"


def f08_baked_keys_and_live_do_not_add_up():
    """Finding 8: after Bake Frames, Live at a baked frame shows the controller's pose
    once: the handle where the controller is, not twice as far."""
    scene = bpy.context.scene
    ob = plane()
    handle = HANDLE[0]
    rest = positions(ob.data).astype(float)
    c = ctrl()
    z0 = keyed_lift(c, 0.125, 9)
    scene.frame_set(1)
    with override():
        assert bpy.ops.edge_deform.bake('EXEC_DEFAULT', True) == {'FINISHED'}
    scene.frame_set(5)
    yield
    start_live()
    c.animation_data_clear()
    c.location.z = z0 + 0.0625            # re-pose at frame 5
    yield from until(lambda: running() is not None and abs(
        (visible(ob)[handle, 2] - rest[handle, 2]).mean() - 0.0625) < 2e-3, 20)
    lift = (visible(ob)[handle, 2] - rest[handle, 2]).mean()
    screenshot("artist_live_after_bake.png")
    assert abs(lift - 0.0625) < 2e-3, "the handle shows %.4f above rest for a 0.0625 move" % lift
    tap('ESC')
    yield from until(lambda: running() is None)
    baked = [kb for kb in ob.data.shape_keys.key_blocks if kb.name.startswith("EdgeDeform.")]
    assert baked and not any(kb.mute for kb in baked), "Esc unmutes the baked keys"


def f09_solve_reports_speak_to_the_artist():
    """Finding 9: an unconverged Solve says what happened and what to do, without the
    solver's jargon or a chunk's count, and never "settling…"."""
    ob = plane()
    ob.edge_deform.iterations = 200
    ob.edge_deform.tolerance = 0.0          # never converges: Solve stops at 200
    ctrl().location.z += 0.5
    bpy.context.view_layer.update()
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.solve('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        yield from until(lambda: told.has('INFO', "Solved"), 60)
    texts = [t for _, t in told.messages]
    summary = [t for t in texts if t.startswith("Solved")]
    assert summary, texts
    assert not any("settling" in t for t in summary), summary
    assert not any("fixed point" in t or "max_iterations" in t for t in texts), texts
    assert "200 iterations" in summary[-1] and "Iterations" in summary[-1], summary


def f10_times_are_the_wait():
    """Finding 10: Bind's report shows the time the artist waited."""
    with Told() as told:
        t0 = time.perf_counter()
        with override():
            assert bpy.ops.edge_deform.bind('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        yield from until(lambda: told.has('INFO', "Bound"))
        waited = time.perf_counter() - t0
    [text] = [t for _, t in told.messages if t.startswith("Bound")]
    m = re.search(r"([\d.]+) (ms|s)\b", text)
    assert m, text
    shown = float(m.group(1)) / (1e3 if m.group(2) == "ms" else 1.0)
    assert shown >= 0.5 * waited - 0.05, "Bind says %s after a %.2f s wait" % (text, waited)


def f12_live_from_a_controller():
    """Finding 12: with the controller active, Live Deform is available (menu, F3), as
    the panel's button is."""
    bpy.context.view_layer.objects.active = ctrl()
    ctrl().select_set(True)
    plane().select_set(False)
    with override():
        assert bpy.ops.edge_deform.live.poll(), "Live Deform is greyed out"
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    yield
    assert running() is not None and running().object_name == plane().name_full
    tap('ESC')
    yield from until(lambda: running() is None)


def f13_live_leaves_blenders_keys():
    """Finding 13: ] / [ (Select Hierarchy) and Ctrl+Wheel (pan) keep their meaning
    during Live: λ does not change."""
    start_live()
    yield from until(lambda: plane().data.shape_keys is not None)
    event('MOUSEMOVE', at=center())
    yield
    for kind, mods in (('RIGHT_BRACKET', {}), ('LEFT_BRACKET', {}),
                       ('WHEELUPMOUSE', {"ctrl": True})):
        tap(kind, **mods)
        for _ in range(3):
            yield
        assert plane().edge_deform.stiffness == 0.5, "%s changed λ" % kind
    assert running() is not None
    tap('ESC')
    yield from until(lambda: running() is None)


FINDINGS = [f01_grab_from_the_panel_is_pointer_relative, f02_edit_mode_shows_the_grab,
            f03_live_leaves_the_header_and_status_bar, f04_enter_over_a_field_edits_it,
            f05_panel_redraws_after_bind, f06_a_refused_key_says_why_on_screen,
            f07_clearing_the_painted_group_is_followed, f08_baked_keys_and_live_do_not_add_up,
            f09_solve_reports_speak_to_the_artist, f10_times_are_the_wait,
            f12_live_from_a_controller, f13_live_leaves_blenders_keys]


HANDLE = [None]   # the handle's vertex indices of the scene setup() made


def steps():
    tap('ESC')   # dismiss the splash screen
    yield

    def fresh_scene(_finding):
        HANDLE[0], _ = setup()
        yield
    yield from run_sections(FINDINGS, fresh_scene)


main(steps, limit_s=540)
