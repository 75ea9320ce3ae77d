"""Background tests: frame-change handler, bake, and the exact output snapshot used by the
modal tools' cancel."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (bpy, key_positions, np, plane_with_end_groups,  # noqa: E402
                     positions, run, transform)


def setup():
    ob, ctrl, handle, static = plane_with_end_groups()
    ob.edge_deform.iterations = 30
    ob.edge_deform.tolerance = 1e-7
    rest_matrix = ctrl.matrix_world.copy()
    # Animated controller: rest at frame 1, lifted and turned at frame 9.
    ctrl.keyframe_insert("location", frame=1)
    ctrl.keyframe_insert("rotation_euler", frame=1)
    ctrl.location.z += 0.4
    ctrl.rotation_euler.y = 0.5
    ctrl.keyframe_insert("location", frame=9)
    ctrl.keyframe_insert("rotation_euler", frame=9)
    return ob, ctrl, rest_matrix, handle, static, positions(ob.data).copy()


def targets(ctrl, rest_matrix, rest, handle):
    M = np.array(ctrl.matrix_world) @ np.linalg.inv(np.array(rest_matrix))
    return transform(M, rest[handle].astype(float))


def test_frame_handler():
    ob, ctrl, rest_matrix, handle, static, rest = setup()
    scene = bpy.context.scene
    ob.edge_deform.animate = True
    for frame in (3, 6, 9):
        scene.frame_set(frame)
        out = key_positions(ob)
        assert np.abs(out[handle] - targets(ctrl, rest_matrix, rest, handle)).max() < 1e-5
        assert np.array_equal(out[static], rest[static])
    assert np.abs(out - rest).max() > 0.1
    # The playback path reuses the groups of the last sync (no geometry-nodes read) and
    # solves the same problem: handles on target, static at rest.
    from edge_deform import lifecycle, mesh_io
    reader = mesh_io.read_group_weights
    mesh_io.read_group_weights = None          # any group read would now fail
    try:
        reused = lifecycle.deform(ob, warm=True, reuse_inputs=True)[1].positions
    finally:
        mesh_io.read_group_weights = reader
    assert np.abs(reused[handle] - targets(ctrl, rest_matrix, rest, handle)).max() < 1e-5
    assert np.array_equal(reused[static], rest[static].astype(float))
    out = key_positions(ob).copy()
    ob.edge_deform.animate = False
    scene.frame_set(1)
    assert np.array_equal(key_positions(ob), out), "no update once switched off"


def test_bake():
    ob, ctrl, rest_matrix, handle, static, rest = setup()
    scene = bpy.context.scene
    assert bpy.ops.edge_deform.bake(use_scene_range=False, frame_start=1, frame_end=9,
                                    frame_step=2) == {'FINISHED'}
    keys = ob.data.shape_keys.key_blocks
    names = ["EdgeDeform.%04d" % f for f in (1, 3, 5, 7, 9)]
    assert all(n in keys for n in names)
    assert scene.frame_current == 1
    for f, name in zip((1, 3, 5, 7, 9), names):
        scene.frame_set(f)
        out = key_positions(ob, name)
        assert np.abs(out[handle] - targets(ctrl, rest_matrix, rest, handle)).max() < 1e-5
        assert np.array_equal(out[static], rest[static])
        # Keyed over time: this key is on at its frame, its neighbours are off.
        assert abs(keys[name].value - 1.0) < 1e-6
        assert all(abs(keys[n].value) < 1e-6 for n in names if n != name)
    # Between two baked frames the weights blend linearly.
    scene.frame_set(4)
    assert abs(keys[names[1]].value - 0.5) < 1e-6 and abs(keys[names[2]].value - 0.5) < 1e-6
    # Re-bake replaces, does not duplicate.
    n_keys = len(keys)
    bpy.ops.edge_deform.bake(use_scene_range=False, frame_start=1, frame_end=9, frame_step=2)
    assert len(ob.data.shape_keys.key_blocks) == n_keys


def test_snapshot_restores_bit_exact():
    """The modal tools' cancel: after writes in either output mode, with or without a
    user's shape key, everything is back bit-exact (keys, value, stored state)."""
    from edge_deform import lifecycle, mesh_io, modal
    ob, ctrl, rest_matrix, handle, static, rest = setup()
    noise = np.random.default_rng(1).normal(size=rest.shape)
    for output in ('SHAPE_KEY', 'MESH'):
        for had_key in (False, True):
            ob.shape_key_clear()
            if had_key:
                ob.shape_key_add(name="Basis")
                kb = ob.shape_key_add(name="Mine")
                kb.data.foreach_set("co", (rest + 0.01).ravel())
                kb.value = 0.3
            ob.edge_deform.output = output
            before_base = positions(ob.data).copy()
            before_key = key_positions(ob, "Mine").copy() if had_key else None
            snap = modal.Snapshot(ob)
            for _ in range(2):
                lifecycle.prepare(ob).write(rest + noise)
            shown = positions(ob.data) if output == 'MESH' else key_positions(ob)
            assert np.abs(shown - (rest + noise)).max() < 1e-6, (output, had_key)
            snap.restore(ob)
            snap.discard()
            assert np.array_equal(positions(ob.data), before_base), (output, had_key)
            assert ob.data.edge_deform_state.output == 'NONE'
            assert ob.data.attributes.get(mesh_io.REST_ATTRIBUTE) is None
            if had_key:
                assert ob.data.shape_keys.key_blocks.keys() == ["Basis", "Mine"]
                assert np.array_equal(key_positions(ob, "Mine"), before_key)
                assert abs(ob.data.shape_keys.key_blocks["Mine"].value - 0.3) < 1e-7
            else:
                assert ob.data.shape_keys is None, (output, had_key)


if __name__ == "__main__":
    run([test_frame_handler, test_bake, test_snapshot_restores_bit_exact])
