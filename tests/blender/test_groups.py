"""Background tests of the selection operators: add_handle, set_static, set_roi,
assign_stiffness (value and presets, Edit Mode and Weight Paint mask), paint_stiffness,
and of the settings' scripting contract."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (Told, bpy, expect_error, load, make_object,  # noqa
                     np, positions, run, select_only)


def members(ob, name):
    """Test-side reading of a vertex group: {vertex: weight} (independent of mesh_io)."""
    vg = ob.vertex_groups[name]
    out = {}
    for v in ob.data.vertices:
        for g in v.groups:
            if g.group == vg.index:
                out[v.index] = g.weight
    return out


def select(ob, idx):
    """Select exactly `idx` and enter Edit Mode (as any selection tool would leave it)."""
    if ob.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')
    select_only(ob.data, idx)
    ob.data.update()
    bpy.ops.object.mode_set(mode='EDIT')


def spot():
    V, F = load("spot_low_resolution.obj")
    return make_object("spot", V, F), V


def test_contract_fields():
    ob, _ = spot()
    s = ob.edge_deform
    for name in ("handles", "static_group", "roi_group", "stiffness_group", "stiffness",
                 "domain", "iterations", "tolerance", "output"):
        assert hasattr(s, name), name
    assert (s.domain, s.output, s.static_group, s.roi_group) == ('EDGE', 'SHAPE_KEY', "", "")
    h = s.handles.add()
    assert h.vertex_group == "" and h.controller is None
    s.domain, s.output = 'PRIMAL', 'MESH'


def test_add_handle():
    ob, V = spot()
    top = np.flatnonzero(V[:, 1] > np.percentile(V[:, 1], 90))
    select(ob, top)
    assert bpy.ops.edge_deform.add_handle() == {'FINISHED'}
    assert ob.mode == 'EDIT'
    s = ob.edge_deform
    assert len(s.handles) == 1
    h = s.handles[0]
    assert sorted(members(ob, h.vertex_group)) == top.tolist()
    centroid = V[top].mean(axis=0)
    assert np.allclose(h.controller.matrix_world.translation, centroid, atol=1e-5)
    assert np.allclose(np.array(h.rest_matrix), np.array(h.controller.matrix_world))
    # A second handle takes its vertices out of the first.
    first = h.vertex_group   # (collection items move when the collection grows)
    select(ob, top[:5])
    assert bpy.ops.edge_deform.add_handle() == {'FINISHED'}
    assert len(s.handles) == 2 and s.handles[1].vertex_group != first
    bpy.ops.object.mode_set(mode='OBJECT')
    assert sorted(members(ob, s.handles[1].vertex_group)) == top[:5].tolist()
    assert sorted(members(ob, s.handles[0].vertex_group)) == top[5:].tolist()
    # Nothing selected: a clear error (through op_common.tell, as every message), nothing added.
    select(ob, [])
    with Told() as told:
        expect_error(bpy.ops.edge_deform.add_handle, "no vertices selected")
    assert told.has('ERROR', "No vertices selected"), told.messages
    assert len(s.handles) == 2


def test_static_and_roi():
    ob, V = spot()
    low = np.flatnonzero(V[:, 1] < np.percentile(V[:, 1], 20))
    select(ob, low)
    assert bpy.ops.edge_deform.set_static() == {'FINISHED'}
    s = ob.edge_deform
    assert s.static_group and sorted(members(ob, s.static_group)) == low.tolist()
    select(ob, low[:10])   # replaces, not adds
    bpy.ops.edge_deform.set_static()
    bpy.ops.object.mode_set(mode='OBJECT')
    assert sorted(members(ob, s.static_group)) == low[:10].tolist()
    select(ob, np.arange(100))
    assert bpy.ops.edge_deform.set_roi() == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    assert sorted(members(ob, s.roi_group)) == list(range(100))
    assert s.roi_group != s.static_group


def test_assign_stiffness_presets():
    ob, V = spot()
    s = ob.edge_deform
    s.stiffness = 0.3
    a, b, c = np.arange(0, 10), np.arange(10, 20), np.arange(20, 30)
    for idx, preset, value in ((a, 'SOFT', 0.0), (b, 'MEDIUM', 0.5), (c, 'RIGID', 1.0)):
        select(ob, idx)
        assert bpy.ops.edge_deform.assign_stiffness(preset=preset) == {'FINISHED'}
    select(ob, [40, 41])
    assert bpy.ops.edge_deform.assign_stiffness(preset='VALUE', value=0.8) == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    w = members(ob, s.stiffness_group)
    assert len(w) == len(V), "the group covers every vertex (unpainted keep the global λ)"
    assert all(abs(w[i]) < 1e-6 for i in a) and all(abs(w[i] - 0.5) < 1e-6 for i in b)
    assert all(abs(w[i] - 1.0) < 1e-6 for i in c) and abs(w[40] - 0.8) < 1e-6
    assert abs(w[100] - 0.3) < 1e-6
    # The add-on reads the same weights in bulk.
    from edge_deform import mesh_io
    bulk = mesh_io.read_group_weights(ob, [s.stiffness_group])[s.stiffness_group]
    assert np.allclose(bulk, [w[i] for i in range(len(V))])


def test_weight_paint_mask_and_paint_button():
    ob, V = spot()
    assert bpy.ops.edge_deform.paint_stiffness() == {'FINISHED'}
    assert ob.mode == 'WEIGHT_PAINT'
    s = ob.edge_deform
    assert ob.vertex_groups.active.name == s.stiffness_group
    # Weight Paint with the vertex selection mask: assign works on the masked vertices.
    ob.data.use_paint_mask_vertex = True
    sel = np.zeros(len(V), bool)
    sel[[3, 4, 5]] = True
    ob.data.vertices.foreach_set("select", sel)
    assert bpy.ops.edge_deform.assign_stiffness(preset='RIGID') == {'FINISHED'}
    bpy.ops.object.mode_set(mode='OBJECT')
    w = members(ob, s.stiffness_group)
    assert [w[i] for i in (3, 4, 5)] == [1.0, 1.0, 1.0] and abs(w[6] - 0.5) < 1e-6


def test_group_ops_leave_positions():
    ob, V = spot()
    before = positions(ob.data).copy()
    select(ob, np.arange(30))
    bpy.ops.edge_deform.add_handle()
    select(ob, np.arange(100, 130))
    bpy.ops.edge_deform.set_static()
    bpy.ops.object.mode_set(mode='OBJECT')
    assert np.array_equal(positions(ob.data), before)
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}


if __name__ == "__main__":
    run([test_contract_fields, test_add_handle, test_static_and_roi,
         test_assign_stiffness_presets, test_weight_paint_mask_and_paint_button,
         test_group_ops_leave_positions])
