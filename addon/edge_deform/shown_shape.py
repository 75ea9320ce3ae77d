"""The add-on's shape as the artist sees it in Object Mode: the base mesh with the add-on's
own shape keys (its live key and its baked keys) mixed as Blender mixes relative keys:
each key's value, mute and vertex group, relative to its reference, and only the active
key when it is pinned. The artist's own keys are left out: the add-on's output never holds
them, and they are added on top of it on screen.

What a tool starts from (docs/decisions/0040): Grab Deform (its start and the handles it
pins), Live Deform (its first solve, and any solve after a rebind), Add Handle (where the
new handle holds its vertices). After Bake, at a baked frame, that is the frame shown, not
the live key hidden under it.
"""

import numpy as np

from . import mesh_arrays, output_checks


def _addon_keys(ob):
    """The add-on's keys that add to what is shown, with their weights."""
    mesh = ob.data
    keys = mesh.shape_keys
    ours = [output_checks.owned_key(mesh)] + [keys.key_blocks.get(name)
                                           for name in output_checks.baked_key_names(mesh)]
    ours = [kb for kb in ours if kb is not None and kb != keys.reference_key]
    if ob.show_only_shape_key:   # pinned: the active key alone, at full weight
        active = ob.active_shape_key
        return [(kb, 1.0) for kb in ours if kb == active]
    return [(kb, float(kb.value)) for kb in ours if not kb.mute and kb.value != 0.0]


def addon_shape(ob):
    """(n, 3) float64 object-space positions (the object in Object Mode)."""
    mesh = ob.data
    base = mesh_arrays.read_positions(mesh)
    keys = mesh.shape_keys
    if keys is None:
        return base
    if not keys.use_relative:   # absolute keys blend by time: the add-on's key, as before
        kb = output_checks.owned_key(mesh)
        return base if kb is None else mesh_arrays.read_key(kb).astype(np.float64)
    shape = base.copy()
    for kb, weight in _addon_keys(ob):
        delta = (mesh_arrays.read_key(kb).astype(np.float64)
                 - mesh_arrays.read_key(kb.relative_key).astype(np.float64))
        if kb.vertex_group and kb.vertex_group in ob.vertex_groups:
            group = mesh_arrays.read_group_weights(ob, [kb.vertex_group])[kb.vertex_group]
            delta *= group[:, None]
        shape += weight * delta
    return shape
