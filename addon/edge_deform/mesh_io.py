"""The mesh: the one place where bpy data becomes NumPy arrays and back, and the only
writer of what the mesh stores (its `edge_deform_state`, the rest and hold attributes,
the add-on's shape keys). In order: the arrays (no policy); the checks every solve passes
before its first write; the writes; the shape shown; where handles hold their vertices.

Everything goes through ``foreach_get``/``foreach_set`` (or one bulk call such as
``VertexGroup.add``), never a Python loop over vertices. Blender stores float32; the solver
wants float64, so positions are converted once, here. When to write is decided by
lifecycle.py.
"""

import hashlib

import bpy
import numpy as np


_READER_GROUP = ".EdgeDeformReadWeights"  # temporary geometry-nodes group
_READER_OBJECT = ".EdgeDeformReader"      # temporary object sharing the mesh
_READER_PREFIX = ".ed_w"


# ------------------------------------------------------------------ geometry

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


def array_digest(*arrays):
    """Hash of the arrays' exact bytes, types and shapes (float32 positions: detects any
    edit); None hashes as a word of its own."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        if a is None:
            h.update(b"none")
            continue
        a = np.ascontiguousarray(a)
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


# ------------------------------------------------------------------ shape keys

def read_key(key_block):
    """A shape key's positions, float32 (n,3)."""
    co = np.empty(len(key_block.data) * 3, np.float32)
    collection, prop = _key_points(key_block)
    collection.foreach_get(prop, co)
    return co.reshape(-1, 3)


def write_key(key_block, co):
    collection, prop = _key_points(key_block)
    collection.foreach_set(prop, np.ascontiguousarray(co, np.float32).ravel())


# ------------------------------------------------------------------ point attributes

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


# ------------------------------------------------------------------ vertex groups

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


# ------------------------------------------------------------------ checks before a write
# What the output may overwrite, and when what the mesh stores stops being valid: the
# checks every solve passes before its first write, so a refused operation changes nothing.
#
# Invalidation rules (docs/addon.md has the states, lifecycle.py describes them):
#   - a topology change: the rest is re-read from the base mesh (UNBOUND, KEY OUTPUT);
#     with MESH OUTPUT the base holds a deformed shape, so the solve refuses: "Bind again";
#   - user edits: with MESH OUTPUT, a base mesh that differs from what was written last
#     (hash `state.written`) was edited by the user: refuse, Bind makes the edit the rest.
#     With KEY OUTPUT, edits of the base mesh simply become the new rest; edits of the
#     output key itself (base unchanged) are refused: Apply keeps them;
#   - keys the add-on did not make are never written: an output name that is empty, the
#     base ("Basis" or the reference key) or a key of the user's is refused;
#   - undo and reload: the state comes back with the mesh; the in-memory cache
#     (engine.py) is checked against the topology digest and the rest shape on every
#     use.

# The rest shape, kept beside the base mesh while the base holds the output (MESH OUTPUT).
REST_ATTRIBUTE = ".edge_deform_rest"


class EdgeDeformError(Exception):
    """A problem the user can fix; operators report the message and cancel."""


Refused = EdgeDeformError


def shape_hash(co):
    """What `state.written` and `state.base` store: a digest of float32 positions."""
    return array_digest(np.ascontiguousarray(co, np.float32))


def owned_key(mesh):
    """The output shape key made by the add-on, if it still exists."""
    st, keys = mesh.edge_deform_state, mesh.shape_keys
    if st.output != 'SHAPE_KEY' or keys is None or not st.output_key:
        return None
    return keys.key_blocks.get(st.output_key)


def baked_key_names(mesh):
    return [n for n in mesh.edge_deform_state.baked_keys.split("\n") if n]


def check_key_name(ob, name, allowed=()):
    """Refuse an output key name that would overwrite the base or a key of the user's."""
    keys = ob.data.shape_keys
    if not name.strip():
        raise Refused("The output shape key has no name: type one in Output > Shape Key")
    base = keys.reference_key.name if keys is not None else "Basis"
    if name in {"Basis", base}:
        raise Refused("The output shape key cannot be '%s': that is the base shape. "
                      "Choose another name in Output > Shape Key" % name)
    if keys is not None and name in keys.key_blocks and name not in allowed:
        raise Refused("A shape key named '%s' already exists and was not made by Edge "
                      "Deform: choose another name in Output > Shape Key (your key is left "
                      "as it is)" % name)


def check_output(ob, digest):
    """Raise Refused if writing the output now would lose or corrupt something."""
    s, mesh = ob.edge_deform, ob.data
    st = mesh.edge_deform_state
    if st.output == 'MESH':
        if s.output != 'MESH':
            raise Refused("The base mesh holds the last deformation (Output was Mesh): "
                          "Apply or Bind first, or set Output back to Mesh")
        if st.topology != digest:
            raise Refused("The mesh topology changed since the last solve and the base mesh "
                          "holds the deformed shape: press Bind to make the current mesh "
                          "the rest shape")
        if shape_hash(read_positions32(mesh)) != st.written:
            raise Refused("The mesh was edited since the last solve: press Bind to keep "
                          "the edits as the new rest shape (or undo them)")
        if read_vector_attribute(mesh, REST_ATTRIBUTE) is None:
            raise Refused("The rest shape stored with the mesh is missing: press Bind")
        return
    kb = owned_key(mesh)
    if kb is not None:
        if s.output != 'SHAPE_KEY':
            raise Refused("The shape key '%s' holds the last deformation: Apply it or "
                          "delete it first, or set Output back to Shape Key" % kb.name)
        base = shape_hash(read_positions32(mesh))
        if (st.topology == digest and base == st.base
                and shape_hash(read_key(kb)) != st.written):
            raise Refused("The shape key '%s' was edited since the last solve: Apply to "
                          "keep the edits, or delete the key to solve again" % kb.name)
    if s.output == 'SHAPE_KEY':
        check_key_name(ob, s.shape_key_name, allowed=(kb.name,) if kb is not None else ())


def rest_shape(mesh):
    """The rest shape, float64 (n,3): kept beside the base while it holds the output."""
    if mesh.edge_deform_state.output == 'MESH':
        X = read_vector_attribute(mesh, REST_ATTRIBUTE)
        if X is None:
            raise Refused("The rest shape stored with the mesh is missing: press Bind")
        return X.astype(np.float64)
    return read_positions(mesh)


class SolveStart:
    """What a solve reads from the mesh before it binds, in one pass, after every check:
    the topology digest, the rest shape (n, 3) float64 and the hash of the base."""

    def __init__(self, ob):
        mesh = ob.data
        self.digest = topology_digest(mesh)
        check_output(ob, self.digest)
        self.rest = rest_shape(mesh)
        self.base_hash = shape_hash(read_positions32(mesh))


# ------------------------------------------------------------------ writes
# Writing the output: the only code that writes a result, the baked keys or an applied
# shape into the mesh (lifecycle.py decides when, the checks above what it may overwrite).
# Each RNA assignment tags the mesh for an update, so only what changed is assigned.

def _set(st, **values):
    """Assign only what changed (each RNA assignment tags the mesh for an update)."""
    for name, value in values.items():
        if getattr(st, name) != value:
            setattr(st, name, value)


def write_result(ob, binding, X, base_hash):
    s, mesh = ob.edge_deform, ob.data
    st = mesh.edge_deform_state
    co = np.ascontiguousarray(X, np.float32)
    if s.output == 'SHAPE_KEY':
        kb = owned_key(mesh)
        if mesh.shape_keys is None:
            ob.shape_key_add(name="Basis", from_mix=False)
            st.made_key_datablock = True
        elif st.output == 'NONE':
            st.made_key_datablock = False
        if kb is not None and kb.name != s.shape_key_name:
            kb.name = s.shape_key_name          # the output name changed in the settings
        if kb is None:
            active = ob.active_shape_key_index
            kb = ob.shape_key_add(name=s.shape_key_name, from_mix=False)
            kb.value, kb.mute = 1.0, False      # later: the user's mix is left alone
            ob.active_shape_key_index = active
        write_key(kb, co)
        _show_live_instead_of_baked(mesh, kb)
        _set(st, output='SHAPE_KEY', output_key=kb.name, written=shape_hash(co), base=base_hash)
        mesh.shape_keys.update_tag()
    else:
        if st.output != 'MESH':
            write_vector_attribute(mesh, REST_ATTRIBUTE, binding.X)
        _move_base(mesh, co)
        _set(st, output='MESH', output_key="", written=shape_hash(co))
    _set(st, topology=binding.digest, unheld=0)   # (a solve placed every vertex)
    mesh.update()


def _show_live_instead_of_baked(mesh, live):
    """The live key and the baked keys never add up: a new result in the live key mutes
    the add-on's baked keys and shows the live key (Bake set it to 0); Bake does the
    reverse (write_baked). Esc of a tool puts every key's value and mute back."""
    baked = [mesh.shape_keys.key_blocks.get(n) for n in baked_key_names(mesh)]
    baked = [kb for kb in baked if kb is not None]
    if not baked:
        return
    for kb in baked:
        if not kb.mute:
            kb.mute = True
    if live.value == 0.0:
        live.value = 1.0


def _move_base(mesh, co, skip=()):
    """The base mesh becomes `co`; every other shape key moves with it, so that each keeps
    its offset from the key it is relative to (the keys stay valid for the new base)."""
    old = read_positions32(mesh).astype(np.float64)
    write_positions(mesh, co)
    keys = mesh.shape_keys
    if keys is None:
        return
    delta = co.astype(np.float64) - old
    for kb in keys.key_blocks:
        if kb == keys.reference_key:
            write_key(kb, co)
        elif kb.name not in skip:
            write_key(kb, read_key(kb).astype(np.float64) + delta)
    keys.update_tag()


def write_baked(ob, frames, results, step):
    """Bake: one key per frame, keyed 1 on its frame and 0 on its neighbours. Only keys
    the add-on baked before are replaced; a user's key of the same name is refused."""
    mesh, s = ob.data, ob.edge_deform
    ours = set(baked_key_names(mesh))
    names = ["%s.%04d" % (s.shape_key_name, f) for f in frames]
    for name in names:
        check_key_name(ob, name, allowed=ours)
    st = mesh.edge_deform_state
    if mesh.shape_keys is None:
        ob.shape_key_add(name="Basis", from_mix=False)
        if st.output == 'NONE':
            st.made_key_datablock = True
    active = ob.active_shape_key_index
    for name in names:   # a re-bake replaces the previous keys
        old = mesh.shape_keys.key_blocks.get(name)
        if old is not None:
            ob.shape_key_remove(old)
    for f, name, X in zip(frames, names, results):
        kb = ob.shape_key_add(name=name, from_mix=False)
        write_key(kb, X)
        for frame, value in ((f - step, 0.0), (f, 1.0), (f + step, 0.0)):
            kb.value = value
            kb.keyframe_insert("value", frame=frame)
    ob.active_shape_key_index = min(active, len(mesh.shape_keys.key_blocks) - 1)
    st.baked_keys = "\n".join(sorted(ours | set(names)))
    for name in ours:   # (a result written since the last bake muted them)
        kb = mesh.shape_keys.key_blocks.get(name)
        if kb is not None and kb.mute:
            kb.mute = False
    live = owned_key(mesh)
    if live is not None:
        live.value = 0.0   # the baked keys replace the live result
    st.unheld = 0
    mesh.update()
    return names


def apply_key(ob, kb):
    """Fold the output key into the base exactly as it shows (its value, mute and vertex
    group), move every other key along, remove the output key."""
    mesh = ob.data
    keys = mesh.shape_keys
    K = read_key(kb).astype(np.float64)
    weight = 0.0 if kb.mute else float(kb.value)
    delta = weight * (K - read_key(kb.relative_key).astype(np.float64))
    if kb.vertex_group and kb.vertex_group in ob.vertex_groups:
        w = read_group_weights(ob, [kb.vertex_group])[kb.vertex_group]
        delta *= w[:, None]
    base = read_positions32(mesh).astype(np.float64) + delta
    # Keys relative to the output key keep their offset, now from the new base.
    moved = {o.name: base + (read_key(o) - K) for o in keys.key_blocks
             if o != kb and o != keys.reference_key and o.relative_key == kb}
    active = keys.key_blocks[min(ob.active_shape_key_index, len(keys.key_blocks) - 1)].name
    _move_base(mesh, base, skip={kb.name} | set(moved))
    for name, co in moved.items():
        write_key(keys.key_blocks[name], co)
        keys.key_blocks[name].relative_key = keys.reference_key
    ob.shape_key_remove(kb)
    keys = mesh.shape_keys
    if keys is not None:
        if len(keys.key_blocks) == 1 and mesh.edge_deform_state.made_key_datablock:
            ob.shape_key_clear()   # only the Basis the add-on added is left
        elif active in keys.key_blocks:
            ob.active_shape_key_index = keys.key_blocks.find(active)


def store_base_as_rest(mesh, topology):
    """The base mesh as it is is the rest (Bind: `topology` its digest; Unbind: ""): a base
    that held the output is accepted as the new rest, and every handle holds its rest."""
    st = mesh.edge_deform_state
    remove_attribute(mesh, REST_ATTRIBUTE)   # (stored only while the base holds the output)
    clear_holds(mesh)
    if st.output == 'MESH':
        st.output, st.written = 'NONE', ""
    st.topology, st.unheld = topology, 0


def store_applied(mesh):
    """Apply folded the shape shown into the base: it is the rest, held where it is."""
    remove_attribute(mesh, REST_ATTRIBUTE)
    clear_holds(mesh)
    st = mesh.edge_deform_state
    st.output, st.output_key, st.written, st.base, st.unheld = 'NONE', "", "", "", 0


# Every field of `mesh.edge_deform_state` (properties.py): a restore puts each one back.
STATE_FIELDS = ("output", "output_key", "made_key_datablock", "topology", "written", "base",
                "baked_keys", "unheld")


def stored_state(mesh):
    """The state's fields and the stored rest, for a tool's bit-exact cancel (a tool
    writes no hold before it ends)."""
    st = mesh.edge_deform_state
    return {name: getattr(st, name) for name in STATE_FIELDS}, read_vector_attribute(
        mesh, REST_ATTRIBUTE)


def restore_stored_state(mesh, stored):
    """Put back what stored_state() returned."""
    fields, rest = stored
    st = mesh.edge_deform_state
    for name, value in fields.items():
        setattr(st, name, value)
    if rest is None:
        remove_attribute(mesh, REST_ATTRIBUTE)
    else:
        write_vector_attribute(mesh, REST_ATTRIBUTE, rest)


def note_unheld_edit(mesh, count):
    """Grab Deform placed `count` vertices that no handle holds: a solve from the handles
    will move them (Live says so before it does)."""
    mesh.edge_deform_state.unheld = int(count)


# ------------------------------------------------------------------ the shape shown
# The add-on's shape as the artist sees it in Object Mode: the base mesh with the add-on's
# own shape keys (its live key and its baked keys) mixed as Blender mixes relative keys:
# each key's value, mute and vertex group, relative to its reference, and only the active
# key when it is pinned. The artist's own keys are left out: the add-on's output never holds
# them, and they are added on top of it on screen.
#
# What a tool starts from (docs/decisions/0040): Grab Deform (its start and the handles it
# pins), Live Deform (its first solve, and any solve after a rebind), Add Handle (where the
# new handle holds its vertices). After Bake, at a baked frame, that is the frame shown, not
# the live key hidden under it.

def _addon_keys(ob):
    """The add-on's keys that add to what is shown, with their weights."""
    mesh = ob.data
    keys = mesh.shape_keys
    ours = [owned_key(mesh)] + [keys.key_blocks.get(name)
                                           for name in baked_key_names(mesh)]
    ours = [kb for kb in ours if kb is not None and kb != keys.reference_key]
    if ob.show_only_shape_key:   # pinned: the active key alone, at full weight
        active = ob.active_shape_key
        return [(kb, 1.0) for kb in ours if kb == active]
    return [(kb, float(kb.value)) for kb in ours if not kb.mute and kb.value != 0.0]


def addon_shape(ob):
    """(n, 3) float64 object-space positions (the object in Object Mode)."""
    mesh = ob.data
    base = read_positions(mesh)
    keys = mesh.shape_keys
    if keys is None:
        return base
    if not keys.use_relative:   # absolute keys blend by time: the add-on's key, as before
        kb = owned_key(mesh)
        return base if kb is None else read_key(kb).astype(np.float64)
    shape = base.copy()
    for kb, weight in _addon_keys(ob):
        delta = (read_key(kb).astype(np.float64)
                 - read_key(kb.relative_key).astype(np.float64))
        if kb.vertex_group and kb.vertex_group in ob.vertex_groups:
            group = read_group_weights(ob, [kb.vertex_group])[kb.vertex_group]
            delta *= group[:, None]
        shape += weight * delta
    return shape


# ------------------------------------------------------------------ where handles hold
# Where a handle holds its vertices while its controller stays at its rest transform: the
# rest shape, plus an offset for vertices the artist placed elsewhere and a handle took over
# (docs/decisions/0041):
#   - Add Handle on a deformed mesh: the new handle holds its vertices where they are shown;
#   - Grab Deform dragging vertices of a handle: the handle keeps them where the drag left
#     them, as a Hook keeps an Edit-Mode move of its vertices.
# A handle's targets are then (controller motion since its rest) · (rest + offset).
#
# The offsets are the point attribute HOLD_ATTRIBUTE on the mesh, beside the rest shape, so
# undo, redo, save and reload carry them; zero (or no attribute) means "at rest". Bind,
# Apply and Unbind make the mesh as it is the rest: they clear them (lifecycle.py); Remove
# Handle releases its vertices.

HOLD_ATTRIBUTE = ".edge_deform_hold"


def read_groups_and_holds(ob, names):
    """({group name: (n,) weights}, the holds' offsets or None): what the inputs read of
    the mesh, in one call."""
    return read_group_weights(ob, names), hold_offsets(ob.data)


def hold_offsets(mesh):
    """(n, 3) float64 offsets from the rest, or None: every handle holds its rest."""
    stored = read_vector_attribute(mesh, HOLD_ATTRIBUTE)
    return None if stored is None else stored.astype(np.float64)


def _store_holds(mesh, values):
    if not np.any(values):
        remove_attribute(mesh, HOLD_ATTRIBUTE)
    else:
        write_vector_attribute(mesh, HOLD_ATTRIBUTE, values)


def hold_at(mesh, rest, indices, where, motion=None):
    """From now on the handle of `indices` holds them at `where` ((k, 3), object space)
    while its controller has moved by `motion` (4x4 object-space matrix; None: not at all)
    since its rest. `rest`: the rest shape (n, 3). The object must be in Object Mode."""
    indices = np.asarray(indices, np.int64)
    if indices.size == 0:
        return
    at_rest = np.asarray(where, np.float64)
    if motion is not None:
        inverse = np.linalg.inv(np.asarray(motion, np.float64))
        at_rest = at_rest @ inverse[:3, :3].T + inverse[:3, 3]
    values = hold_offsets(mesh)
    if values is None:
        values = np.zeros((len(mesh.vertices), 3))
    values[indices] = at_rest - rest[indices]
    _store_holds(mesh, values)


def release_holds(mesh, indices):
    """The vertices `indices` are held at their rest again (their handle went)."""
    values = hold_offsets(mesh)
    if values is not None and len(indices):
        values[np.asarray(indices, np.int64)] = 0.0
        _store_holds(mesh, values)


def clear_holds(mesh):
    """Every handle holds its rest (the mesh as it is became the rest)."""
    remove_attribute(mesh, HOLD_ATTRIBUTE)
