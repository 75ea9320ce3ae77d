"""Real-window test of the modal tools' mishaps (Xvfb, --enable-event-simulate), docs/robustness.md:
  - undo (the menu's ed.undo) during Live Deform: the tool ends with a message, the scene
    is Blender's undo step, nothing is written afterwards; redo works;
  - the object deleted during Live: the tool ends, the mesh is restored bit-exact;
  - Edit Mode entered during Live (the menu), a topology edit, then Esc: back in Object
    Mode with the original mesh bit-exact (vertices, faces, no leftover key);
  - the same, back to Object Mode first: Live binds the new topology and goes on; Esc
    still restores the original;
  - the output name changed to "Basis" during Live: refused, the base never written; a
    valid name renames the add-on's key; Esc restores;
  - a controller deleted during Live: a warning, the handle returns to rest; Ctrl+Z is
    refused with a message;
  - Grab Deform: Ctrl+Z during the drag is ignored, Esc restores; Enter, then undo and
    redo outside the tool.
No exception may escape anywhere (window_harness checks sys.excepthook)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import Told, bpy, key_positions, np, positions, select_only  # noqa: E402
from window_harness import center, grab_until_moved, main, override, setup, tap, until  # noqa: E402


def plane():
    return bpy.data.objects.get("plane")


def ctrl():
    return bpy.data.objects["H_ctrl"]


def faces(mesh):
    f = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", f)
    return f


def start_live():
    bpy.context.view_layer.objects.active = plane()
    plane().select_set(True)
    with override():
        assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}


def live_follows(handle, rest, dz):
    return lambda: plane().data.shape_keys is not None and abs(
        key_positions(plane())[handle[0], 2] - rest[handle[0], 2] - dz) < 1e-4


def fresh():
    handle, static = setup()
    ob = plane()
    ob.edge_deform.iterations = 8
    with override():
        bpy.ops.ed.undo_push(message="setup")
    return ob, handle, static, positions(ob.data).copy()


def steps():
    tap('ESC')   # dismiss the splash screen
    yield
    told = Told().__enter__()

    # ------------------------------------------------------------ undo during live
    ob, handle, static, rest = fresh()
    ob.edge_deform.stiffness = 0.6             # a change, then a second step to undo to
    with override():
        bpy.ops.ed.undo_push(message="stiffness")
    start_live()
    ctrl().location.z += 0.3
    yield from until(live_follows(handle, rest, 0.3))
    assert plane().data.shape_keys is not None
    with override():
        bpy.ops.ed.undo()                      # what Edit > Undo does
    yield from until(lambda: told.has('WARNING', "Live Deform ended"))
    assert told.has('WARNING', "Live Deform ended: Undo"), told.messages
    ob = plane()
    assert ob.data.shape_keys is None and np.array_equal(positions(ob.data), rest)
    assert abs(ob.edge_deform.stiffness - 0.5) < 1e-7, "the undo step's state"
    ctrl().location.z += 0.2                   # the tool has ended: nothing follows
    for _ in range(4):
        yield
    assert plane().data.shape_keys is None
    with override():
        bpy.ops.ed.redo()
    yield
    assert abs(plane().edge_deform.stiffness - 0.6) < 1e-7, "redo"
    print("undo during live: ok")

    # ------------------------------------------------------------ object deleted during live
    ob, handle, static, rest = fresh()
    mesh_name = ob.data.name
    start_live()
    ctrl().location.z += 0.3
    yield from until(live_follows(handle, rest, 0.3))
    told.messages.clear()
    bpy.context.view_layer.objects.active = ob
    for other in bpy.context.view_layer.objects:
        other.select_set(other == ob)
    with override():
        bpy.ops.object.delete()                # X in the viewport
    yield from until(lambda: told.has('WARNING', "object was deleted"))
    assert told.has('WARNING', "Live Deform ended: the object was deleted"), told.messages
    assert plane() is None
    mesh = bpy.data.meshes[mesh_name]
    assert mesh.shape_keys is None and np.array_equal(positions(mesh), rest), \
        "the orphaned mesh is back as it was"
    print("object deleted during live: ok")

    # ------------------------------------------------------------ topology edit, then Esc
    for back_to_object in (False, True):
        ob, handle, static, rest = fresh()
        rest_faces = faces(ob.data)
        z0 = ctrl().location.z
        start_live()
        ctrl().location.z += 0.3
        yield from until(live_follows(handle, rest, 0.3))
        # Live made the controller the active object (G/R/S move it): the artist picks
        # the mesh before entering its Edit Mode.
        bpy.context.view_layer.objects.active = plane()
        with override():
            bpy.ops.object.mode_set(mode='EDIT')   # from the mode menu
        yield
        with override():
            bpy.ops.mesh.select_all(action='SELECT')
            bpy.ops.mesh.subdivide()
        for _ in range(3):
            yield
        if back_to_object:
            with override():
                bpy.ops.object.mode_set(mode='OBJECT')
            n = len(plane().data.vertices)
            assert n > len(rest)
            ctrl().location.z += 0.1             # live goes on with the new topology
            yield from until(lambda: key_positions(plane()).shape[0] == n and abs(
                key_positions(plane())[handle[0], 2] - rest[handle[0], 2] - 0.4) < 1e-3)
        tap('ESC')
        yield from until(lambda: plane().mode == 'OBJECT'
                         and len(plane().data.vertices) == len(rest))
        ob = plane()
        assert ob.mode == 'OBJECT'
        assert ob.data.shape_keys is None, "no key left behind"
        assert np.array_equal(positions(ob.data), rest), "bit-exact vertices"
        assert np.array_equal(faces(ob.data), rest_faces), "the original faces"
        assert [g.name for g in ob.vertex_groups] == ["H", "S"]
        assert ctrl().location.z == z0, "the controller is back"
        print("topology edit during live, then Esc (back to Object Mode first: %s): ok"
              % back_to_object)

    # ------------------------------------------------------------ output renamed during live
    ob, handle, static, rest = fresh()
    start_live()
    ctrl().location.z += 0.3
    yield from until(live_follows(handle, rest, 0.3))
    told.messages.clear()
    ob.edge_deform.shape_key_name = "Basis"   # typed in the panel while Live runs
    ctrl().location.z += 0.1
    yield from until(lambda: told.has('ERROR', "cannot be 'Basis'"))
    assert told.has('ERROR', "cannot be 'Basis'"), told.messages
    assert np.array_equal(positions(ob.data), rest), "the base was never written"
    assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "EdgeDeform"]
    ob.edge_deform.shape_key_name = "Deform"  # a valid name: Live goes on, renaming its key
    yield from until(lambda: ob.data.shape_keys.key_blocks.keys() == ["Basis", "Deform"]
                     and abs(key_positions(ob, "Deform")[handle[0], 2]
                             - rest[handle[0], 2] - 0.4) < 1e-4)
    assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "Deform"]
    tap('ESC')
    yield from until(lambda: plane().data.shape_keys is None)
    assert plane().data.shape_keys is None and np.array_equal(positions(plane().data), rest)
    assert plane().edge_deform.shape_key_name == "Deform"
    print("output renamed during live (refused, then renamed): ok")

    # ------------------------------------------------------------ controller deleted
    ob, handle, static, rest = fresh()
    start_live()
    ctrl().location.z += 0.3
    yield from until(live_follows(handle, rest, 0.3))
    told.messages.clear()
    bpy.data.objects.remove(ctrl())
    yield from until(lambda: told.has('WARNING', "has no controller"))
    assert told.has('WARNING', "Handle 'H' has no controller"), told.messages
    yield from until(lambda: np.abs(key_positions(plane())[handle]
                                    - rest[handle]).max() < 1e-4)
    assert np.abs(key_positions(plane())[handle] - rest[handle]).max() < 1e-4, \
        "the handle is back at rest"
    tap('Z', ctrl=True)                        # Ctrl+Z: refused while Live runs
    yield from until(lambda: told.has('WARNING', "before undoing"))
    assert told.has('WARNING', "Confirm or cancel Live Deform before undoing")
    assert not told.has('WARNING', "Live Deform ended"), "no undo happened"
    assert plane().data.shape_keys is not None
    tap('ESC')
    yield from until(lambda: plane().data.shape_keys is None)
    assert np.array_equal(positions(plane().data), rest)
    print("controller deleted during live, Ctrl+Z refused: ok")

    # ------------------------------------------------------------ grab: Ctrl+Z, undo, redo
    ob, handle, static, rest = fresh()
    select_only(ob.data, handle)
    bpy.context.view_layer.objects.active = ob
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.ed.undo_push(message="edit mode")
    yield from grab_until_moved(ob, handle, rest)
    tap('Z', at=center(0, 70), ctrl=True)      # ignored while dragging
    for _ in range(3):
        yield
    assert ob.mode == 'OBJECT' and ob.data.shape_keys is not None, "still grabbing"
    tap('ESC', at=center(0, 70))
    yield from until(lambda: ob.mode == 'EDIT')
    with override():
        bpy.ops.object.mode_set(mode='OBJECT')
    assert ob.data.shape_keys is None and np.array_equal(positions(ob.data), rest)
    with override():
        bpy.ops.object.mode_set(mode='EDIT')
    yield from grab_until_moved(ob, handle, rest)
    tap('RET', at=center(0, 70))
    yield from until(lambda: ob.mode == 'EDIT')
    for _ in range(3):
        yield
    with override():
        bpy.ops.object.mode_set(mode='OBJECT')
    grabbed = key_positions(plane()).copy()
    with override():
        bpy.ops.ed.undo_push(message="after grab")
        bpy.ops.ed.undo()
        bpy.ops.ed.undo()
    yield
    ob = plane()
    if ob.mode != 'OBJECT':
        with override():
            bpy.ops.object.mode_set(mode='OBJECT')
    assert ob.data.shape_keys is None and np.array_equal(positions(ob.data), rest), \
        "undo takes the grab back"
    with override():
        bpy.ops.ed.redo()
        bpy.ops.ed.redo()
    yield
    ob = plane()
    if ob.mode != 'OBJECT':
        with override():
            bpy.ops.object.mode_set(mode='OBJECT')
    assert np.array_equal(key_positions(ob), grabbed), "redo brings it back"
    print("grab: Ctrl+Z ignored, Esc, Enter, undo/redo: ok")


main(steps)
