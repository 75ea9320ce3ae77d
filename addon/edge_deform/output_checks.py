"""What the output may overwrite, and when what the mesh stores stops being valid: the
checks every solve passes before its first write, so a refused operation changes nothing.

Invalidation rules (docs/addon.md has the states, lifecycle.py describes them):
  - a topology change: the rest is re-read from the base mesh (UNBOUND, KEY OUTPUT);
    with MESH OUTPUT the base holds a deformed shape, so the solve refuses: "Bind again";
  - user edits: with MESH OUTPUT, a base mesh that differs from what was written last
    (hash `state.written`) was edited by the user: refuse, Bind makes the edit the rest.
    With KEY OUTPUT, edits of the base mesh simply become the new rest; edits of the
    output key itself (base unchanged) are refused: Apply keeps them;
  - keys the add-on did not make are never written: an output name that is empty, the
    base ("Basis" or the reference key) or a key of the user's is refused;
  - undo and reload: the state comes back with the mesh; the in-memory cache
    (solver_cache.py) is checked against the topology digest and the rest shape on every
    use.
"""

import numpy as np

from . import engine, mesh_arrays

# The rest shape, kept beside the base mesh while the base holds the output (MESH OUTPUT).
REST_ATTRIBUTE = ".edge_deform_rest"
Refused = engine.EdgeDeformError


def shape_hash(co):
    """What `state.written` and `state.base` store: a digest of float32 positions."""
    return mesh_arrays.array_digest(np.ascontiguousarray(co, np.float32))


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
        if shape_hash(mesh_arrays.read_positions32(mesh)) != st.written:
            raise Refused("The mesh was edited since the last solve: press Bind to keep "
                          "the edits as the new rest shape (or undo them)")
        if mesh_arrays.read_vector_attribute(mesh, REST_ATTRIBUTE) is None:
            raise Refused("The rest shape stored with the mesh is missing: press Bind")
        return
    kb = owned_key(mesh)
    if kb is not None:
        if s.output != 'SHAPE_KEY':
            raise Refused("The shape key '%s' holds the last deformation: Apply it or "
                          "delete it first, or set Output back to Shape Key" % kb.name)
        base = shape_hash(mesh_arrays.read_positions32(mesh))
        if (st.topology == digest and base == st.base
                and shape_hash(mesh_arrays.read_key(kb)) != st.written):
            raise Refused("The shape key '%s' was edited since the last solve: Apply to "
                          "keep the edits, or delete the key to solve again" % kb.name)
    if s.output == 'SHAPE_KEY':
        check_key_name(ob, s.shape_key_name, allowed=(kb.name,) if kb is not None else ())


def rest_shape(mesh):
    """The rest shape, float64 (n,3): kept beside the base while it holds the output."""
    if mesh.edge_deform_state.output == 'MESH':
        X = mesh_arrays.read_vector_attribute(mesh, REST_ATTRIBUTE)
        if X is None:
            raise Refused("The rest shape stored with the mesh is missing: press Bind")
        return X.astype(np.float64)
    return mesh_arrays.read_positions(mesh)
