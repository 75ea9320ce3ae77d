"""Real-window test (run under Xvfb with --enable-event-simulate).

Drives the modal tools the way a user does, with simulated mouse and key events:
  live: a scripted controller move re-solves; Alt+] and Alt+[ change λ; G moves
        the controller through Blender's own transform tool; Esc restores bit-exact;
        Enter confirms as one undo step and Ctrl+Z (ed.undo) takes it back;
  grab: in Edit Mode the selected vertices follow the mouse, X constrains the axis, Esc
        restores, Enter confirms.
Screenshots go to $EDGEDEFORM_TEST_OUT. Steps run from a bpy.app timer so that Blender's
event loop handles each simulated event between steps.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import bpy, key_positions, np, positions, select_only  # noqa: E402
from window_harness import (center, event, g_drag, main, override, screenshot,  # noqa: E402
                            setup, tap, until)


def plane():
    return bpy.data.objects["plane"]


def ctrl():
    return bpy.data.objects["H_ctrl"]


def steps():
    tap('ESC')   # dismiss the splash screen, which would eat the first events
    yield
    handle, static = setup()
    rest = positions(plane().data).copy()
    yield
    with override():
        bpy.ops.ed.undo_push(message="setup")

    # ---------------------------------------------------------------- live, then Esc
    with override():
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    c0 = ctrl().matrix_world.copy()
    ctrl().location.z += 0.3          # a script moves the controller
    yield from until(lambda: plane().data.shape_keys is not None and abs(
        key_positions(plane())[handle[0], 2] - rest[handle[0], 2] - 0.3) < 1e-4)
    out = key_positions(plane())
    assert np.abs(out[handle, 2] - (rest[handle, 2] + 0.3)).max() < 1e-4, "handles follow"
    assert np.array_equal(out[static], rest[static])
    tap('RIGHT_BRACKET', alt=True)
    yield from until(lambda: abs(plane().edge_deform.stiffness - 0.55) < 1e-6)
    assert abs(plane().edge_deform.stiffness - 0.55) < 1e-6, "Alt+] raises λ"
    tap('LEFT_BRACKET', alt=True)
    tap('LEFT_BRACKET', alt=True)
    yield from until(lambda: abs(plane().edge_deform.stiffness - 0.45) < 1e-6)
    tap('RIGHT_BRACKET', alt=True)
    tap('RIGHT_BRACKET', alt=True)
    yield from until(lambda: abs(plane().edge_deform.stiffness - 0.55) < 1e-6)
    assert abs(plane().edge_deform.stiffness - 0.55) < 1e-6, "Alt+] and Alt+[ change λ"
    plane().edge_deform.domain = 'PRIMAL'   # from the sidebar: Live follows it
    # G on the controller with Blender's transform tool, while live keeps solving.
    bpy.context.view_layer.objects.active = ctrl()
    ctrl().select_set(True)
    plane().select_set(False)
    yield from g_drag((60, 0), (120, 0))
    yield from until(lambda: abs((key_positions(plane())[handle, 0] - rest[handle, 0]).mean()
                                 - (ctrl().matrix_world.translation.x - c0.translation.x))
                     < 1e-3 and ctrl().matrix_world.translation.x - c0.translation.x > 0.05)
    moved_x = ctrl().matrix_world.translation.x - c0.translation.x
    assert moved_x > 0.05, "G moved the controller (%f)" % moved_x
    out = key_positions(plane())
    assert abs((out[handle, 0] - rest[handle, 0]).mean() - moved_x) < 1e-3, \
        "handles follow a G move"
    screenshot("live.png")
    tap('ESC')
    yield from until(lambda: plane().data.shape_keys is None)
    ob = plane()
    assert ob.data.shape_keys is None, "Esc removed the key it created"
    assert np.array_equal(positions(ob.data), rest), "Esc restores bit-exact"
    assert (ob.edge_deform.stiffness, ob.edge_deform.domain) == (0.5, 'EDGE')
    assert np.allclose(np.array(ctrl().matrix_world), np.array(c0)), "controller restored"
    print("live + Esc: ok")

    # ---------------------------------------------------------------- live, Enter, undo
    bpy.context.view_layer.objects.active = plane()
    plane().select_set(True)
    with override():
        bpy.ops.ed.undo_push(message="before live")
    with override():
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    ctrl().location.z += 0.2
    yield from until(lambda: plane().data.shape_keys is not None and abs(
        key_positions(plane())[handle[0], 2] - rest[handle[0], 2] - 0.2) < 1e-4)
    tap('RET')
    for _ in range(3):   # let the operator finish and push its undo step
        yield
    out = key_positions(plane()).copy()
    assert np.abs(out[handle, 2] - (rest[handle, 2] + 0.2)).max() < 1e-4, "Enter keeps it"
    with override():
        bpy.ops.ed.undo()
    yield
    ob = plane()   # undo replaces the datablocks: fetch again
    assert ob.data.shape_keys is None and np.array_equal(positions(ob.data), rest), \
        "one undo step takes the live session back"
    with override():
        bpy.ops.ed.redo()
    yield
    assert np.array_equal(key_positions(plane()), out), "redo brings it back"
    print("live + Enter + undo/redo: ok")

    # ---------------------------------------------------------------- mouse: RMB, LMB
    kept = key_positions(plane()).copy()
    with override():
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    ctrl().location.z += 0.1
    yield from until(lambda: abs(key_positions(plane())[handle[0], 2]
                                 - kept[handle[0], 2] - 0.1) < 1e-4)
    from edge_deform import modal
    event('MOUSEMOVE', at=center(0, -150))   # away from the plane: a click, no selection
    yield
    tap('LEFTMOUSE', at=center(0, -150))
    for _ in range(5):
        yield
    assert modal.running_tool() is not None, "a selection click does not end Live"
    ctrl().location.z -= 0.1                 # live goes on: the mesh follows
    yield from until(lambda: np.abs(key_positions(plane()) - kept).max() < 1e-4)
    tap('ESC')
    yield from until(lambda: modal.running_tool() is None)
    assert np.array_equal(key_positions(plane()), kept), "Esc restores bit-exact"
    print("live: a left click selects, Live goes on; Esc: ok")

    # ---------------------------------------------------------------- solve + undo
    with override():
        bpy.ops.ed.undo_push(message="before solve")
    before = key_positions(plane()).copy()
    ctrl().location.z += 0.25
    bpy.context.view_layer.update()
    with override():
        assert bpy.ops.edge_deform.solve('EXEC_DEFAULT', True) == {'FINISHED'}
    assert not np.array_equal(key_positions(plane()), before)
    with override():
        bpy.ops.ed.undo()
    yield
    assert np.array_equal(key_positions(plane()), before), "undo of solve"
    print("solve + undo: ok")

    # ---------------------------------------------------------------- grab in Edit Mode
    ob = plane()
    ob.shape_key_clear()
    ob.data.update()
    select_only(ob.data, handle)
    bpy.context.view_layer.objects.active = ob
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
    event('MOUSEMOVE', at=center())
    yield
    with override():
        assert bpy.ops.edge_deform.grab('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    event('MOUSEMOVE', at=center(80, 60))   # diagonal drag, then constrain to X
    yield from until(lambda: ob.data.shape_keys is not None and np.abs(
        key_positions(ob)[handle] - rest[handle]).min(axis=0).max() > 0.01)
    free = key_positions(ob)
    assert np.linalg.norm(free[handle] - rest[handle], axis=1).min() > 0.01, "drag moves"
    assert np.abs(free[handle, 1:] - rest[handle, 1:]).max() > 0.01, "free, not along X"
    tap('X', at=center(80, 60))
    yield from until(lambda: np.abs(key_positions(ob)[handle, 1:] - rest[handle, 1:]).max()
                     < 1e-5)
    out = key_positions(ob)
    d = out[handle] - rest[handle]
    assert d[:, 0].min() > 0.01, "dragged right"
    assert np.abs(d[:, 1:]).max() < 1e-5, "X constraint"
    assert np.array_equal(out[static], rest[static])
    others = np.setdiff1d(np.arange(len(rest)), np.union1d(handle, static))
    assert np.abs(out[others] - rest[others]).max() > 0.01, "the rest follows"
    screenshot("grab.png")
    tap('ESC', at=center(80, 60))
    yield from until(lambda: ob.mode == 'EDIT')
    assert ob.mode == 'EDIT', "back in Edit Mode"
    with override():
        bpy.ops.object.mode_set(mode='OBJECT')
    assert ob.data.shape_keys is None and np.array_equal(positions(ob.data), rest), \
        "Esc restores the grab"
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
    event('MOUSEMOVE', at=center())
    yield
    with override():
        bpy.ops.edge_deform.grab('INVOKE_DEFAULT')
    # Tolerance 0 never converges: the resting grab must give up (at a lower limit than
    # the add-on's, so that a loaded machine's slow ticks reach it in time).
    from edge_deform import modal_rules
    modal_rules.SETTLE_LIMIT, limit = 200, modal_rules.SETTLE_LIMIT
    ob.edge_deform.tolerance = 0.0
    event('MOUSEMOVE', at=center(0, 70))
    yield from until(lambda: ob.data.shape_keys is not None and np.linalg.norm(
        key_positions(ob)[handle] - rest[handle], axis=1).min() > 0.01)
    grab = modal.running_tool()
    yield from until(lambda: "stopped after" in (grab.header_text or ""), 60)
    assert "not converged" in grab.header_text and "move the mouse to go on" in \
        grab.header_text, grab.header_text
    shape = key_positions(ob).copy()
    for _ in range(20):
        yield
    assert np.array_equal(key_positions(ob), shape), "a grab that gave up leaves the mesh"
    ob.edge_deform.tolerance, modal_rules.SETTLE_LIMIT = 1e-3, limit
    tap('RET', at=center(0, 70))
    yield from until(lambda: ob.mode == 'EDIT')
    with override():
        bpy.ops.object.mode_set(mode='OBJECT')
    out = key_positions(ob)
    assert np.linalg.norm(out[handle] - rest[handle], axis=1).min() > 0.01, \
        "Enter keeps the grab"
    print("grab: ok (and it stops settling after the limit, saying so)")


main(steps)
