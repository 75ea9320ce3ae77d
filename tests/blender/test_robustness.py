"""Background tests of docs/robustness.md: the add-on never loses an artist's work.

Shape keys and Apply, output names it must not use, edits it must not revert,
controllers in the object's space, hidden objects, modifiers, linked duplicates, save and
reopen, deleted controllers and groups. Each test asserts the geometry, the keys and the
message; refusals must leave everything bit-identical (helpers.refused)."""

import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (Matrix, Told, bpy, ed, expect_error, key_offsets,  # noqa: E402
                     key_positions, loop_triangles, mesh_fingerprint, np,
                     plane_with_end_groups, positions, refused, run, transform, visible)

TOL = 1e-5


def setup(output='SHAPE_KEY'):
    ob, ctrl, handle, static = plane_with_end_groups()
    ob.edge_deform.iterations = 20
    ob.edge_deform.output = output
    return ob, ctrl, handle, static, positions(ob.data).copy()


def lift(ctrl, dz=0.3, angle=0.3):
    ctrl.matrix_world = (Matrix.Translation(ctrl.matrix_world.translation
                                            + Matrix.Translation((0, 0, dz)).translation)
                         @ Matrix.Rotation(angle, 4, 'Y'))
    bpy.context.view_layer.update()


def expected(ob, rest, handle, static, iterations=20):
    """What the solver gives for the object's settings, from `rest` (the Python API)."""
    h = ob.edge_deform.handles[0]
    A = (np.linalg.inv(np.array(ob.matrix_world)) @ np.array(h.controller.matrix_world)
         @ np.linalg.inv(np.array(h.rest_matrix)))
    d = ed.Deformer(rest.astype(float), loop_triangles(ob.data), domain="edge")
    d.set_constraints(handles=handle, static=static, roi=None)
    d.set_stiffness(ob.edge_deform.stiffness)
    return d.solve(transform(A, rest[handle].astype(float)), max_iterations=iterations,
                   tolerance=ob.edge_deform.tolerance, warm_start=False,
                   verify_claims=True).positions  # as the add-on's solves


def add_user_key(ob, name, rest, value=0.5):
    """A user's key: a bump along y, relative to the basis."""
    if ob.data.shape_keys is None:
        ob.shape_key_add(name="Basis", from_mix=False)
    kb = ob.shape_key_add(name=name, from_mix=False)
    bump = rest.astype(np.float64).copy()
    bump[:, 1] += 0.05 * np.sin(4.0 * rest[:, 0])
    kb.data.foreach_set("co", bump.astype(np.float32).ravel())
    kb.value = value
    return kb


def edit_vertex(ob, index, offset, key_index=None):
    """Move one vertex in Edit Mode (of the given active shape key), as a user would."""
    import bmesh
    if key_index is not None:
        ob.active_shape_key_index = key_index
    bpy.ops.object.mode_set(mode='EDIT')
    bm = bmesh.from_edit_mesh(ob.data)
    bm.verts.ensure_lookup_table()
    bm.verts[index].co.z += offset
    bmesh.update_edit_mesh(ob.data)
    bpy.ops.object.mode_set(mode='OBJECT')


# ------------------------------------------------------------------ shape keys and Apply

def test_apply_keeps_visible_shape_and_user_keys():
    ob, ctrl, handle, static, rest = setup()
    add_user_key(ob, "Smile", rest, 0.5)
    ob.active_shape_key_index = 1                 # the user's key is the active one
    offsets = key_offsets(ob)
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.array_equal(positions(ob.data), rest), "the base mesh is untouched"
    assert np.abs(key_positions(ob) - expected(ob, rest, handle, static)).max() < TOL
    shown = visible(ob)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    keys = ob.data.shape_keys.key_blocks
    assert keys.keys() == ["Basis", "Smile"], keys.keys()
    assert np.abs(visible(ob) - shown).max() < TOL, "Apply keeps the shape the user sees"
    assert np.abs(key_offsets(ob)["Smile"] - offsets["Smile"]).max() < TOL, \
        "the user's key keeps its offset from the new basis"
    assert abs(keys["Smile"].value - 0.5) < 1e-7 and ob.active_shape_key_index == 1
    assert ob.data.edge_deform_state.output == 'NONE'


def test_apply_uses_value_and_mute():
    for value, mute in ((0.3, False), (1.0, True)):
        from helpers import reset_scene
        reset_scene()
        ob, ctrl, handle, static, rest = setup()
        lift(ctrl)
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        kb = ob.data.shape_keys.key_blocks["EdgeDeform"]
        K = key_positions(ob).astype(np.float64)
        kb.value, kb.mute = value, mute
        shown = visible(ob)
        assert bpy.ops.edge_deform.apply() == {'FINISHED'}
        assert ob.data.shape_keys is None, "only the add-on's Basis was left: removed"
        base = positions(ob.data).astype(np.float64)
        assert np.abs(base - shown).max() < TOL, (value, mute)
        if mute:
            assert np.array_equal(positions(ob.data), rest), "muted: nothing applied"
        else:
            assert np.abs(base - (rest + 0.3 * (K - rest))).max() < TOL


def test_apply_with_key_group_and_keys_relative_to_it():
    """The output key limited by a vertex group, and a user's key relative to the output
    key: Apply keeps the visible shape and that key's offset (now from the basis)."""
    ob, ctrl, handle, static, rest = setup()
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    half = np.flatnonzero(rest[:, 1] > np.median(rest[:, 1]))
    ob.vertex_groups.new(name="Half").add(half.tolist(), 0.5, 'REPLACE')
    out_key = ob.data.shape_keys.key_blocks["EdgeDeform"]
    out_key.vertex_group = "Half"
    on_top = add_user_key(ob, "OnTop", rest, 0.7)
    on_top.relative_key = out_key
    on_top.data.foreach_set("co", (key_positions(ob).astype(np.float64)
                                   + [0, 0, 0.02]).astype(np.float32).ravel())
    offset = key_offsets(ob)["OnTop"]
    shown = visible(ob)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    keys = ob.data.shape_keys.key_blocks
    assert keys.keys() == ["Basis", "OnTop"]
    assert keys["OnTop"].relative_key == keys["Basis"]
    assert np.abs(key_offsets(ob)["OnTop"] - offset).max() < TOL
    assert np.abs(visible(ob) - shown).max() < TOL


def test_mesh_output_with_user_keys():
    ob, ctrl, handle, static, rest = setup('MESH')
    add_user_key(ob, "Smile", rest, 0.5)
    offsets = key_offsets(ob)
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = expected(ob, rest, handle, static)
    assert np.abs(positions(ob.data) - out).max() < TOL, "the base holds the result"
    assert np.abs(key_offsets(ob)["Smile"] - offsets["Smile"]).max() < TOL, \
        "the user's key moved with the base"
    assert np.abs(visible(ob) - (out + 0.5 * offsets["Smile"])).max() < TOL
    lift(ctrl, 0.1, 0.1)                          # a second solve: still from the rest
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.abs(positions(ob.data) - expected(ob, rest, handle, static)).max() < TOL
    assert np.abs(key_offsets(ob)["Smile"] - offsets["Smile"]).max() < TOL
    shown = visible(ob)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "Smile"]
    assert np.abs(visible(ob) - shown).max() < TOL
    assert ob.data.attributes.get(".edge_deform_rest") is None


def test_output_key_names_refused():
    ob, ctrl, handle, static, rest = setup()
    lift(ctrl)
    s = ob.edge_deform
    for name in ("Basis", "", "   "):
        s.shape_key_name = name
        refused(bpy.ops.edge_deform.solve, "Shape Key", ob)
        assert ob.data.shape_keys is None
    # The user's keys: a renamed reference key and a key of their own.
    add_user_key(ob, "Mine", rest)
    ob.data.shape_keys.key_blocks["Basis"].name = "Rest"
    for name, fragment in (("Rest", "base shape"), ("Basis", "base shape"),
                           ("Mine", "not made by Edge Deform")):
        s.shape_key_name = name
        refused(bpy.ops.edge_deform.solve, fragment, ob)
    mine = key_positions(ob, "Mine").copy()
    s.shape_key_name = "Deform"
    for _ in range(3):                           # never piles up
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert ob.data.shape_keys.key_blocks.keys() == ["Rest", "Mine", "Deform"]
    s.shape_key_name = "Deform2"                 # renaming the output renames its key
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert ob.data.shape_keys.key_blocks.keys() == ["Rest", "Mine", "Deform2"]
    assert np.array_equal(key_positions(ob, "Mine"), mine)
    # Edit Mode toggles never put the result into the base.
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.object.mode_set(mode='OBJECT')
    assert np.array_equal(positions(ob.data), rest)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    assert ob.data.shape_keys.key_blocks.keys() == ["Rest", "Mine"], \
        "Apply keeps the user's keys"


def test_topology_change_with_output_key():
    ob, ctrl, handle, static, rest = setup()
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide()
    bpy.ops.object.mode_set(mode='OBJECT')
    base = positions(ob.data).copy()
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}   # rest = the new base
    assert np.array_equal(positions(ob.data), base)
    assert key_positions(ob).shape == base.shape
    assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "EdgeDeform"]


# ------------------------------------------------------------------ the user's edits

def test_mesh_output_edits_are_never_reverted():
    ob, ctrl, handle, static, rest = setup('MESH')
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    free = int(np.setdiff1d(np.arange(len(rest)), np.union1d(handle, static))[0])
    edit_vertex(ob, free, 0.2)
    edited = positions(ob.data).copy()
    msg = refused(bpy.ops.edge_deform.solve, "edited since the last solve", ob)
    assert "Bind" in msg
    assert np.array_equal(positions(ob.data), edited)
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}   # the edit becomes the rest
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.abs(positions(ob.data) - edited).max() < TOL, "the edit is kept"
    lift(ctrl, 0.1, 0.0)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.abs(positions(ob.data) - expected(ob, edited, handle, static)).max() < TOL


def test_shape_key_edits_are_never_reverted():
    ob, ctrl, handle, static, rest = setup()
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    free = int(np.setdiff1d(np.arange(len(rest)), np.union1d(handle, static))[0])
    edit_vertex(ob, free, 0.2, key_index=1)       # the output key is active: edits go there
    edited = key_positions(ob).copy()
    refused(bpy.ops.edge_deform.solve, "was edited since the last solve", ob)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}   # Apply keeps the edit
    assert np.abs(positions(ob.data) - edited).max() < TOL
    # Edits of the base mesh become the new rest shape.
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    edit_vertex(ob, free, -0.1, key_index=0)
    new_rest = positions(ob.data).copy()
    lift(ctrl, 0.1, 0.0)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.array_equal(positions(ob.data), new_rest)
    assert np.abs(key_positions(ob) - expected(ob, new_rest, handle, static)).max() < TOL


def test_output_mode_switch_refused():
    ob, ctrl, handle, static, rest = setup('MESH')
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    ob.edge_deform.output = 'SHAPE_KEY'
    refused(bpy.ops.edge_deform.solve, "holds the last deformation", ob)
    ob.edge_deform.output = 'MESH'
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    ob.edge_deform.output = 'SHAPE_KEY'
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    ob.edge_deform.output = 'MESH'
    refused(bpy.ops.edge_deform.solve, "holds the last deformation", ob)


# ------------------------------------------------------------------ transforms, visibility

def test_controller_parented_to_the_object():
    ob, ctrl, handle, static, rest = setup()
    ob.matrix_world = (Matrix.Translation((1, 2, 3)) @ Matrix.Rotation(0.7, 4, 'Z')
                       @ Matrix.Scale(1.5, 4))
    bpy.context.view_layer.update()
    ctrl.matrix_world = ob.matrix_world @ ctrl.matrix_world   # on the handle, in world
    bpy.context.view_layer.update()
    world = ctrl.matrix_world.copy()
    ctrl.parent = ob
    ctrl.matrix_parent_inverse = ob.matrix_world.inverted()
    bpy.context.view_layer.update()
    assert np.allclose(np.array(ctrl.matrix_world), np.array(world), atol=1e-6)
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    for M in (Matrix.Translation((-3, 1, 0.5)), Matrix.Rotation(1.1, 4, 'X')):
        ob.matrix_world = M @ ob.matrix_world   # the object moves, the controller with it
        bpy.context.view_layer.update()
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        assert np.abs(key_positions(ob) - rest).max() < TOL, "nothing moved relative to it"
    local = np.array(ob.matrix_world.inverted() @ ctrl.matrix_world)[:3, 3]
    ctrl.location.z += 0.4                      # the controller moves relative to the object
    bpy.context.view_layer.update()
    moved = np.array(ob.matrix_world.inverted() @ ctrl.matrix_world)[:3, 3] - local
    assert np.linalg.norm(moved) > 0.1
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = key_positions(ob)
    assert np.abs(out - expected(ob, rest, handle, static)).max() < TOL
    assert np.abs(out[handle] - rest[handle] - moved).max() < TOL, "moves by that motion"


def test_controllers_parented_to_a_rig():
    ob, ctrl, handle, static, rest = setup()
    ob.matrix_world = Matrix.Translation((0, 0, 1)) @ Matrix.Rotation(0.5, 4, 'X')
    rig = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(rig)
    rig.location = (2, 0, 0)
    bpy.context.view_layer.update()
    ctrl.matrix_world = ob.matrix_world @ ctrl.matrix_world
    bpy.context.view_layer.update()
    ctrl.parent = rig
    ctrl.matrix_parent_inverse = rig.matrix_world.inverted()
    bpy.context.view_layer.update()
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    obmw = np.array(ob.matrix_world)
    rig.location.z += 0.5                       # the rig moves: the handle follows it
    bpy.context.view_layer.update()
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = key_positions(ob)
    assert np.abs(out - expected(ob, rest, handle, static)).max() < TOL
    moved = transform(obmw, out[handle].astype(float)) - transform(obmw, rest[handle])
    assert np.abs(moved - [0, 0, 0.5]).max() < 1e-4, "world motion = the rig's"
    # Moving the object away from a controller it does not carry moves the handle
    # relative to the object, like a Hook: the handle stays where the controller is.
    ob.matrix_world = Matrix.Translation((0, 0, 0.25)) @ ob.matrix_world
    bpy.context.view_layer.update()
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out2 = key_positions(ob)
    assert np.abs(out2 - expected(ob, rest, handle, static)).max() < TOL
    world2 = transform(np.array(ob.matrix_world), out2[handle].astype(float))
    assert np.abs(world2 - transform(obmw, out[handle].astype(float))).max() < 1e-4


def test_hidden_object():
    for hide in ("hide_viewport", "hide_set"):
        from helpers import reset_scene
        reset_scene()
        ob, ctrl, handle, static, rest = setup()
        if hide == "hide_viewport":
            ob.hide_viewport = True
        else:
            ob.hide_set(True)
        assert bpy.ops.edge_deform.bind() == {'FINISHED'}, hide
        lift(ctrl)
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}, hide
        assert np.abs(key_positions(ob) - expected(ob, rest, handle, static)).max() < TOL
        # A bind that fails leaves the handles' rest transforms alone.
        ob.vertex_groups["S"].add(handle[:2].tolist(), 1.0, 'REPLACE')
        refused(bpy.ops.edge_deform.bind, "both handle and static", ob)
        ob.vertex_groups["S"].remove(handle[:2].tolist())
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        assert np.abs(key_positions(ob) - expected(ob, rest, handle, static)).max() < TOL, \
            "the deformation survived the failed bind"
        assert np.abs(key_positions(ob)[handle] - rest[handle]).max() > 0.1


def test_modifiers_subdivision_and_mirror():
    ob, ctrl, handle, static, rest = setup()
    ob.modifiers.new("Subdivision", 'SUBSURF')
    mirror = ob.modifiers.new("Mirror", 'MIRROR')
    mirror.use_axis = (False, True, False)
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = key_positions(ob).copy()
    assert np.abs(out - expected(ob, rest, handle, static)).max() < TOL
    assert [m.name for m in ob.modifiers] == ["Subdivision", "Mirror"]
    assert all(m.show_viewport for m in ob.modifiers)
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    assert np.array_equal(positions(ob.data), out)
    assert len(ob.data.vertices) == len(rest) and len(ob.modifiers) == 2


# ------------------------------------------------------------------ sharing, files

def test_two_objects_one_mesh():
    for output in ('SHAPE_KEY', 'MESH'):
        from helpers import reset_scene
        reset_scene()
        a, ctrl_a, handle, static, rest = setup(output)
        b = bpy.data.objects.new("planeB", a.data)         # a linked duplicate
        bpy.context.scene.collection.objects.link(b)
        b.matrix_world = Matrix.Translation((0, 3, 0)) @ Matrix.Rotation(0.4, 4, 'Z')
        ctrl_b = bpy.data.objects.new("B_ctrl", None)
        bpy.context.scene.collection.objects.link(ctrl_b)
        bpy.context.view_layer.update()
        ctrl_b.matrix_world = b.matrix_world @ ctrl_a.matrix_world
        bpy.context.view_layer.update()
        sb = b.edge_deform
        sb.static_group, sb.iterations, sb.output = "S", 20, output
        h = sb.handles.add()
        h.vertex_group, h.controller = "H", ctrl_b
        h.rest_matrix = b.matrix_world.inverted() @ ctrl_b.matrix_world
        lift(ctrl_a, 0.3, 0.2)
        lift(ctrl_b, -0.2, 0.0)
        for ob in (a, b, a):        # each solve starts from the shared rest shape
            from helpers import activate
            activate(ob)
            bpy.context.view_layer.update()
            assert bpy.ops.edge_deform.solve() == {'FINISHED'}, (output, ob.name)
            shown = key_positions(ob) if output == 'SHAPE_KEY' else positions(ob.data)
            assert np.abs(shown - expected(ob, rest, handle, static)).max() < TOL, \
                (output, ob.name)
        # Playback reuses the groups of the last sync: never the other object's settings.
        from edge_deform import lifecycle
        lifecycle.deform(a)
        r = lifecycle.deform(b, reuse_inputs=True, iterations=20)[1].positions
        assert np.abs(r - expected(b, rest, handle, static)).max() < TOL, output
        if output == 'SHAPE_KEY':
            assert np.array_equal(positions(a.data), rest)
            assert a.data.shape_keys.key_blocks.keys() == ["Basis", "EdgeDeform"]


def test_save_reopen_solve():
    path = os.path.join(tempfile.mkdtemp(), "bound.blend")
    for output in ('MESH', 'SHAPE_KEY'):
        from helpers import reset_scene
        reset_scene()
        ob, ctrl, handle, static, rest = setup(output)
        assert bpy.ops.edge_deform.bind() == {'FINISHED'}
        lift(ctrl)
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        ob, ctrl = bpy.data.objects["plane"], bpy.data.objects["H_ctrl"]
        from helpers import activate
        activate(ob)
        assert ob.data.edge_deform_state.output == output
        lift(ctrl, 0.1, 0.1)
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}, output
        shown = key_positions(ob) if output == 'SHAPE_KEY' else positions(ob.data)
        assert np.abs(shown - expected(ob, rest, handle, static)).max() < TOL, output
        if output == 'SHAPE_KEY':
            assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "EdgeDeform"]
            assert np.array_equal(positions(ob.data), rest)


# ------------------------------------------------------------------ deleted things

def test_deleted_controller_and_group():
    ob, ctrl, handle, static, rest = setup()
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    lift(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    bpy.data.objects.remove(ctrl)
    with Told() as told:
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert told.has('WARNING', "Handle 'H' has no controller"), told.messages
    assert np.abs(key_positions(ob)[handle] - rest[handle]).max() < TOL, "back at rest"
    ob.vertex_groups.remove(ob.vertex_groups["S"])
    before = mesh_fingerprint(ob)
    with Told() as told:
        expect_error(bpy.ops.edge_deform.solve, "'S' does not exist (deleted or renamed?)")
    assert told.has('ERROR', "does not exist")
    assert mesh_fingerprint(ob) == before


def test_bake_never_replaces_user_keys():
    ob, ctrl, handle, static, rest = setup()
    add_user_key(ob, "EdgeDeform.0003", rest)
    ctrl.keyframe_insert("location", frame=1)
    ctrl.location.z += 0.3
    ctrl.keyframe_insert("location", frame=5)
    refused(lambda: bpy.ops.edge_deform.bake(use_scene_range=False, frame_start=1,
                                             frame_end=5, frame_step=2),
            "not made by Edge Deform", ob)
    ob.data.shape_keys.key_blocks["EdgeDeform.0003"].name = "Mine"
    for _ in range(2):                          # a re-bake replaces its own keys only
        assert bpy.ops.edge_deform.bake(use_scene_range=False, frame_start=1, frame_end=5,
                                        frame_step=2) == {'FINISHED'}
    assert ob.data.shape_keys.key_blocks.keys() == [
        "Basis", "Mine", "EdgeDeform.0001", "EdgeDeform.0003", "EdgeDeform.0005"]


def test_frame_handler_problem_is_shown():
    from edge_deform import operators_bind
    ob, ctrl, handle, static, rest = setup()
    ob.edge_deform.animate = True
    bpy.context.scene.frame_set(2)
    assert operators_bind.frame_problem(ob) is None
    ob.vertex_groups.remove(ob.vertex_groups["S"])
    bpy.context.scene.frame_set(3)              # the handler must not raise
    assert "'S' does not exist" in operators_bind.frame_problem(ob)
    ob.vertex_groups.new(name="S").add(static.tolist(), 1.0, 'REPLACE')
    bpy.context.scene.frame_set(4)
    assert operators_bind.frame_problem(ob) is None


if __name__ == "__main__":
    run([test_apply_keeps_visible_shape_and_user_keys, test_apply_uses_value_and_mute,
         test_apply_with_key_group_and_keys_relative_to_it,
         test_mesh_output_with_user_keys, test_output_key_names_refused,
         test_topology_change_with_output_key, test_mesh_output_edits_are_never_reverted,
         test_shape_key_edits_are_never_reverted, test_output_mode_switch_refused,
         test_controller_parented_to_the_object, test_controllers_parented_to_a_rig,
         test_hidden_object, test_modifiers_subdivision_and_mirror,
         test_two_objects_one_mesh, test_save_reopen_solve,
         test_deleted_controller_and_group, test_bake_never_replaces_user_keys,
         test_frame_handler_problem_is_shown])
