"""Writing the output: the only code that writes a result, the baked keys or an applied
shape into the mesh (lifecycle.py decides when, output_checks.py what it may overwrite).
Each RNA assignment tags the mesh for an update, so only what changed is assigned.
"""

import numpy as np

from . import mesh_arrays
from .output_checks import (REST_ATTRIBUTE, baked_key_names, check_key_name, owned_key,
                            shape_hash)


def _set(st, **values):
    """Assign only what changed (each RNA assignment tags the mesh for an update)."""
    for name, value in values.items():
        if getattr(st, name) != value:
            setattr(st, name, value)


def write(ob, binding, X, base_hash):
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
        mesh_arrays.write_key(kb, co)
        _show_live_instead_of_baked(mesh, kb)
        _set(st, output='SHAPE_KEY', output_key=kb.name, written=shape_hash(co), base=base_hash)
        mesh.shape_keys.update_tag()
    else:
        if st.output != 'MESH':
            mesh_arrays.write_vector_attribute(mesh, REST_ATTRIBUTE, binding.X)
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
    old = mesh_arrays.read_positions32(mesh).astype(np.float64)
    mesh_arrays.write_positions(mesh, co)
    keys = mesh.shape_keys
    if keys is None:
        return
    delta = co.astype(np.float64) - old
    for kb in keys.key_blocks:
        if kb == keys.reference_key:
            mesh_arrays.write_key(kb, co)
        elif kb.name not in skip:
            mesh_arrays.write_key(kb, mesh_arrays.read_key(kb).astype(np.float64) + delta)
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
        mesh_arrays.write_key(kb, X)
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
    K = mesh_arrays.read_key(kb).astype(np.float64)
    weight = 0.0 if kb.mute else float(kb.value)
    delta = weight * (K - mesh_arrays.read_key(kb.relative_key).astype(np.float64))
    if kb.vertex_group and kb.vertex_group in ob.vertex_groups:
        w = mesh_arrays.read_group_weights(ob, [kb.vertex_group])[kb.vertex_group]
        delta *= w[:, None]
    base = mesh_arrays.read_positions32(mesh).astype(np.float64) + delta
    # Keys relative to the output key keep their offset, now from the new base.
    moved = {o.name: base + (mesh_arrays.read_key(o) - K) for o in keys.key_blocks
             if o != kb and o != keys.reference_key and o.relative_key == kb}
    active = keys.key_blocks[min(ob.active_shape_key_index, len(keys.key_blocks) - 1)].name
    _move_base(mesh, base, skip={kb.name} | set(moved))
    for name, co in moved.items():
        mesh_arrays.write_key(keys.key_blocks[name], co)
        keys.key_blocks[name].relative_key = keys.reference_key
    ob.shape_key_remove(kb)
    keys = mesh.shape_keys
    if keys is not None:
        if len(keys.key_blocks) == 1 and mesh.edge_deform_state.made_key_datablock:
            ob.shape_key_clear()   # only the Basis the add-on added is left
        elif active in keys.key_blocks:
            ob.active_shape_key_index = keys.key_blocks.find(active)


def note_unheld_edit(mesh, count):
    """Grab Deform placed `count` vertices that no handle holds: a solve from the handles
    will move them (Live says so before it does)."""
    mesh.edge_deform_state.unheld = int(count)
