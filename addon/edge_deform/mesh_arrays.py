"""The one place where bpy data becomes NumPy arrays and back (no policy here).

Everything goes through ``foreach_get``/``foreach_set`` (or one bulk call such as
``VertexGroup.add``), never a Python loop over vertices. Blender stores float32; the solver
wants float64, so positions are converted once, here. What may be written where, and when,
is decided by lifecycle.py.
"""

import hashlib

import bpy
import numpy as np

_READER_GROUP = ".EdgeDeformReadWeights"  # temporary geometry-nodes group
_READER_OBJECT = ".EdgeDeformReader"      # temporary object sharing the mesh
_READER_PREFIX = ".ed_w"


# ---------------------------------------------------------------- geometry

def _positions(mesh):
    """(collection, property) of the vertex positions: the "position" attribute where
    Blender has one (3.5+), whose foreach_get/set copy the array in one go (0.5 ms at 560k
    vertices against 30-60 ms for mesh.vertices' "co"); else the vertices."""
    attr = mesh.attributes.get("position")
    if attr is not None and attr.data_type == 'FLOAT_VECTOR' and attr.domain == 'POINT':
        return attr.data, "vector"
    return mesh.vertices, "co"


def _key_points(key_block):
    """(collection, property) of a shape key's positions: ShapeKey.points where Blender has
    it (4.1+; 0.5 ms at 560k vertices against 30 ms for .data), else .data."""
    return getattr(key_block, "points", key_block.data), "co"


def read_positions32(mesh):
    """Base-mesh vertex positions as float32 (n,3): exact copies for snapshots."""
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    collection, prop = _positions(mesh)
    collection.foreach_get(prop, co)
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


def array_digest(a):
    """Hash of an array's exact bytes (float32 positions: detects any edit)."""
    a = np.ascontiguousarray(a)
    h = hashlib.blake2b(digest_size=16)
    h.update(str((a.dtype.str, a.shape)).encode())
    h.update(a.tobytes())
    return h.hexdigest()


def write_positions(mesh, co):
    collection, prop = _positions(mesh)
    collection.foreach_set(prop, np.ascontiguousarray(co, np.float32).ravel())


def read_selection(ob):
    """Selected vertices (bool (n,)), synced from Edit Mode when needed."""
    if ob.mode == 'EDIT':
        ob.update_from_editmode()
    sel = np.empty(len(ob.data.vertices), bool)
    ob.data.vertices.foreach_get("select", sel)
    return sel


def selected_face_vertices(mesh):
    """The vertices of the selected faces (Weight Paint's face mask), sorted, int64."""
    sel = np.zeros(len(mesh.polygons), bool)
    mesh.polygons.foreach_get("select", sel)
    total = np.zeros(len(mesh.polygons), np.int64)
    mesh.polygons.foreach_get("loop_total", total)
    corners = np.zeros(len(mesh.loops), np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    return np.unique(corners[np.repeat(sel, total)])


def matrix_to_numpy(matrix):
    return np.array(matrix, dtype=np.float64)


# ---------------------------------------------------------------- shape keys

def read_key(key_block):
    """A shape key's positions, float32 (n,3)."""
    co = np.empty(len(key_block.data) * 3, np.float32)
    collection, prop = _key_points(key_block)
    collection.foreach_get(prop, co)
    return co.reshape(-1, 3)


def write_key(key_block, co):
    collection, prop = _key_points(key_block)
    collection.foreach_set(prop, np.ascontiguousarray(co, np.float32).ravel())


# ---------------------------------------------------------------- point attributes

def write_vector_attribute(mesh, name, X):
    attr = mesh.attributes.get(name)
    if attr is None or attr.data_type != 'FLOAT_VECTOR' or attr.domain != 'POINT':
        if attr is not None:
            mesh.attributes.remove(attr)
        attr = mesh.attributes.new(name, 'FLOAT_VECTOR', 'POINT')
    attr.data.foreach_set("vector", np.ascontiguousarray(X, np.float32).ravel())


def read_vector_attribute(mesh, name):
    """float32 (n,3), or None when the mesh has no such point attribute."""
    attr = mesh.attributes.get(name)
    if attr is None or attr.data_type != 'FLOAT_VECTOR' or attr.domain != 'POINT':
        return None
    X = np.empty(len(mesh.vertices) * 3, np.float32)
    attr.data.foreach_get("vector", X)
    return X.reshape(-1, 3)


def remove_attribute(mesh, name):
    attr = mesh.attributes.get(name)
    if attr is not None:
        mesh.attributes.remove(attr)


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

    Blender has no bulk accessor for vertex-group weights, so a geometry-nodes modifier
    copies them into attributes that ``foreach_get`` can read. It runs on a temporary
    object sharing the mesh (vertex groups live on the mesh), linked to the scene's own
    collection: the user's object, its modifiers and its visibility are never touched, and
    a hidden object reads like a visible one.
    """
    names = list(dict.fromkeys(names))
    if not names:
        return {}
    if ob.mode == 'EDIT':
        ob.update_from_editmode()
    mesh = ob.data
    n = len(mesh.vertices)
    ng = _new_reader_group(names)
    reader = bpy.data.objects.new(_READER_OBJECT, mesh)
    try:
        mod = reader.modifiers.new("EdgeDeformRead", 'NODES')
        mod.node_group = ng
        mod.show_in_editmode = True   # the shared mesh may be in Edit Mode (grab)
        bpy.context.scene.collection.objects.link(reader)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = reader.evaluated_get(depsgraph)
        out_mesh = evaluated.to_mesh()
        try:
            if len(out_mesh.vertices) != n:
                raise RuntimeError("could not read vertex groups (evaluated mesh differs)")
            out = {}
            for k, name in enumerate(names):
                attr = out_mesh.attributes.get(_READER_PREFIX + str(k))
                if attr is None:
                    raise RuntimeError("could not read vertex group '%s'" % name)
                w = np.empty(n, np.float32)
                attr.data.foreach_get("value", w)
                out[name] = w
        finally:
            evaluated.to_mesh_clear()
    finally:
        bpy.data.objects.remove(reader)
        bpy.data.node_groups.remove(ng)
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


def evaluated_positions(ob, depsgraph=None):
    """Positions as displayed (shape keys and modifiers applied), float64 (n,3)."""
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return read_positions(mesh)
    finally:
        evaluated.to_mesh_clear()
