"""The one place where bpy data becomes NumPy arrays and back.

Everything goes through ``foreach_get``/``foreach_set`` (or one bulk call such as
``VertexGroup.add``), never a Python loop over vertices. Blender stores float32; the solver
wants float64, so positions are converted once, here.
"""

import hashlib

import bpy
import numpy as np

REST_ATTRIBUTE = ".edge_deform_rest"      # rest shape kept with the mesh (survives undo)
TOPOLOGY_PROP = "edge_deform_topology"    # topology digest recorded at bind
_READER_GROUP = ".EdgeDeformReadWeights"  # temporary geometry-nodes group
_READER_PREFIX = ".ed_w"


# ---------------------------------------------------------------- geometry

def vertex_count(mesh):
    return len(mesh.vertices)


def read_positions32(mesh):
    """Base-mesh vertex positions as float32 (n,3): exact copies for snapshots."""
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def read_positions(mesh):
    return read_positions32(mesh).astype(np.float64)


def read_triangles(mesh):
    """Loop triangles (m,3) int64: Blender's triangulation of quads and n-gons."""
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return tris.reshape(-1, 3).astype(np.int64)


def topology_counts(mesh):
    return (len(mesh.vertices), len(mesh.edges), len(mesh.loops), len(mesh.polygons))


def topology_digest(mesh):
    """Hash of the face-vertex lists: changes whenever connectivity changes."""
    loops = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", loops)
    sizes = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_total", sizes)
    h = hashlib.blake2b(digest_size=16)
    h.update(np.asarray(topology_counts(mesh), np.int64).tobytes())
    h.update(loops.tobytes())
    h.update(sizes.tobytes())
    return h.hexdigest()


def read_selection(ob):
    """Selected vertices (bool (n,)), synced from Edit Mode when needed."""
    if ob.mode == 'EDIT':
        ob.update_from_editmode()
    sel = np.empty(len(ob.data.vertices), bool)
    ob.data.vertices.foreach_get("select", sel)
    return sel


def matrix_to_numpy(matrix):
    return np.array(matrix, dtype=np.float64)


# ---------------------------------------------------------------- rest shape

def store_rest(mesh, X, digest):
    """Keep the rest shape in a hidden point attribute and the topology digest beside it."""
    attr = mesh.attributes.get(REST_ATTRIBUTE)
    if attr is None or attr.data_type != 'FLOAT_VECTOR' or attr.domain != 'POINT':
        if attr is not None:
            mesh.attributes.remove(attr)
        attr = mesh.attributes.new(REST_ATTRIBUTE, 'FLOAT_VECTOR', 'POINT')
    attr.data.foreach_set("vector", np.ascontiguousarray(X, np.float32).ravel())
    mesh[TOPOLOGY_PROP] = digest


def read_rest(mesh, digest):
    """The stored rest shape if it belongs to this topology, else None."""
    attr = mesh.attributes.get(REST_ATTRIBUTE)
    if attr is None or mesh.get(TOPOLOGY_PROP) != digest:
        return None
    X = np.empty(len(mesh.vertices) * 3, np.float32)
    attr.data.foreach_get("vector", X)
    return X.reshape(-1, 3).astype(np.float64)


def has_rest(mesh):
    return mesh.attributes.get(REST_ATTRIBUTE) is not None


def clear_rest(mesh):
    attr = mesh.attributes.get(REST_ATTRIBUTE)
    if attr is not None:
        mesh.attributes.remove(attr)
    if TOPOLOGY_PROP in mesh:
        del mesh[TOPOLOGY_PROP]


# ---------------------------------------------------------------- vertex groups

def _new_reader_group(names):
    """Geometry-nodes group copying each vertex group into a float point attribute."""
    ng = bpy.data.node_groups.new(_READER_GROUP, 'GeometryNodeTree')
    if hasattr(ng, "interface"):  # Blender 4.0+
        ng.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
        ng.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    else:
        ng.inputs.new('NodeSocketGeometry', "Geometry")
        ng.outputs.new('NodeSocketGeometry', "Geometry")
    gin = ng.nodes.new('NodeGroupInput')
    gout = ng.nodes.new('NodeGroupOutput')
    geometry = gin.outputs[0]
    for k, name in enumerate(names):
        read = ng.nodes.new('GeometryNodeInputNamedAttribute')
        read.data_type = 'FLOAT'
        read.inputs["Name"].default_value = name
        store = ng.nodes.new('GeometryNodeStoreNamedAttribute')
        store.data_type = 'FLOAT'
        store.domain = 'POINT'
        store.inputs["Name"].default_value = _READER_PREFIX + str(k)
        value_in = [s for s in store.inputs if s.enabled and s.name == "Value"][0]
        value_out = [s for s in read.outputs if s.enabled][0]
        ng.links.new(geometry, store.inputs["Geometry"])
        ng.links.new(value_out, value_in)
        geometry = store.outputs[0]
    ng.links.new(geometry, gout.inputs[0])
    return ng


def read_group_weights(ob, names):
    """{name: float32 (n,)} weights of the named vertex groups (0 outside the group).

    Blender has no bulk accessor for vertex-group weights, so a temporary geometry-nodes
    modifier copies them into attributes that ``foreach_get`` can read; the other modifiers
    are disabled meanwhile so that the evaluated mesh keeps the original vertices.
    """
    names = list(dict.fromkeys(names))
    if not names:
        return {}
    if ob.mode == 'EDIT':
        ob.update_from_editmode()
    n = len(ob.data.vertices)
    shown = [(m, m.show_viewport) for m in ob.modifiers]
    for m, _ in shown:
        m.show_viewport = False
    ng = _new_reader_group(names)
    mod = ob.modifiers.new("EdgeDeformRead", 'NODES')
    mod.node_group = ng
    mod.show_in_editmode = True
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = ob.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        try:
            if len(mesh.vertices) != n:
                raise RuntimeError("could not read vertex groups (evaluated mesh differs)")
            out = {}
            for k, name in enumerate(names):
                w = np.empty(n, np.float32)
                mesh.attributes[_READER_PREFIX + str(k)].data.foreach_get("value", w)
                out[name] = w
        finally:
            evaluated.to_mesh_clear()
    finally:
        ob.modifiers.remove(mod)
        bpy.data.node_groups.remove(ng)
        for m, state in shown:
            m.show_viewport = state
    return out


def ensure_group(ob, name):
    vg = ob.vertex_groups.get(name)
    if vg is None:
        vg = ob.vertex_groups.new(name=name)
    return vg


def assign_group(ob, name, indices, weight=1.0, replace_all=False):
    """Give `indices` the weight in group `name`; replace_all first empties the group.

    VertexGroup.add/remove refuse to run in Edit Mode: callers switch to Object Mode.
    """
    vg = ensure_group(ob, name)
    if replace_all:
        vg.remove(range(len(ob.data.vertices)))
    idx = np.asarray(indices, np.int64)
    if idx.size:
        vg.add(idx.tolist(), float(weight), 'REPLACE')
    return vg


# ---------------------------------------------------------------- output

def _shape_key_co(key_block, n):
    co = np.empty(n * 3, np.float32)
    key_block.data.foreach_get("co", co)
    return co.reshape(-1, 3)


def read_output(ob, output, key_name):
    """Positions (float64 (n,3)) the add-on last wrote, or the base mesh."""
    mesh = ob.data
    keys = mesh.shape_keys
    if output == 'SHAPE_KEY' and keys is not None and key_name in keys.key_blocks:
        return _shape_key_co(keys.key_blocks[key_name], len(mesh.vertices)).astype(np.float64)
    return read_positions(mesh)


def write_output(ob, output, key_name, X):
    """Write deformed positions into the shape key (created on demand) or the base mesh."""
    mesh = ob.data
    co = np.ascontiguousarray(X, np.float32).ravel()
    if output == 'SHAPE_KEY':
        if mesh.shape_keys is None:
            ob.shape_key_add(name="Basis", from_mix=False)
        key = mesh.shape_keys.key_blocks.get(key_name)
        if key is None:
            key = ob.shape_key_add(name=key_name, from_mix=False)
        key.data.foreach_set("co", co)
        key.value = 1.0
        key.mute = False
        mesh.shape_keys.update_tag()
    else:
        mesh.vertices.foreach_set("co", co)
        if mesh.shape_keys is not None:
            mesh.shape_keys.reference_key.data.foreach_set("co", co)
            mesh.shape_keys.update_tag()
    mesh.update()


def remove_shape_key(ob, key_name):
    keys = ob.data.shape_keys
    if keys is not None and key_name in keys.key_blocks:
        ob.shape_key_remove(keys.key_blocks[key_name])


class OutputSnapshot:
    """Exact copy of what the add-on may overwrite, for a bit-exact cancel."""

    def __init__(self, ob, key_name):
        mesh = ob.data
        self.key_name = key_name
        self.co = read_positions32(mesh)
        keys = mesh.shape_keys
        self.had_keys = keys is not None
        self.active_index = ob.active_shape_key_index
        self.reference = None
        self.key = None
        if keys is not None:
            self.reference = _shape_key_co(keys.reference_key, len(mesh.vertices))
            kb = keys.key_blocks.get(key_name)
            if kb is not None:
                self.key = (_shape_key_co(kb, len(mesh.vertices)), kb.value, kb.mute)

    def restore(self, ob):
        mesh = ob.data
        mesh.vertices.foreach_set("co", self.co.ravel())
        keys = mesh.shape_keys
        if keys is not None:
            if not self.had_keys:
                ob.shape_key_clear()
            else:
                keys.reference_key.data.foreach_set("co", self.reference.ravel())
                kb = keys.key_blocks.get(self.key_name)
                if self.key is None:
                    if kb is not None:
                        ob.shape_key_remove(kb)
                elif kb is not None:
                    kb.data.foreach_set("co", self.key[0].ravel())
                    kb.value, kb.mute = self.key[1], self.key[2]
                ob.active_shape_key_index = self.active_index
                keys.update_tag()
        mesh.update()


def evaluated_positions(ob, depsgraph=None):
    """Positions as displayed (shape keys and modifiers applied), float64 (n,3)."""
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return read_positions(mesh)
    finally:
        evaluated.to_mesh_clear()
