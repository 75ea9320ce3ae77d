"""Cancel's exact restore: a Snapshot of everything a modal tool may change, put back
bit-exact on Esc (or when the tool's object was deleted under it).
"""

import bpy

from . import mesh_arrays, solver_cache
from .output_checks import REST_ATTRIBUTE

# Every field of `mesh.edge_deform_state` (properties.py): a restore puts each one back.
STATE_FIELDS = ("output", "output_key", "made_key_datablock", "topology", "written", "base",
                "baked_keys", "unheld")


class Snapshot:
    """Everything a modal tool may change, for a bit-exact cancel: the vertices, every
    shape key (positions, value, mute), the active key, the stored state and rest, and a
    full copy of the mesh for when the topology changed meanwhile (an edit during Live)."""

    def __init__(self, ob):
        mesh = ob.data
        self.mesh = mesh
        self.digest = mesh_arrays.topology_digest(mesh)
        self.co = mesh_arrays.read_positions32(mesh)
        keys = mesh.shape_keys
        self.keys = None if keys is None else [
            (kb.name, mesh_arrays.read_key(kb), kb.value, kb.mute) for kb in keys.key_blocks]
        self.active = ob.active_shape_key_index
        st = mesh.edge_deform_state
        self.state = {name: getattr(st, name) for name in STATE_FIELDS}
        self.rest = mesh_arrays.read_vector_attribute(mesh, REST_ATTRIBUTE)
        self.copy = mesh.copy()

    def _arrays_fit(self, mesh):
        if mesh_arrays.topology_digest(mesh) != self.digest:
            return False
        names = [] if mesh.shape_keys is None else mesh.shape_keys.key_blocks.keys()
        return self.keys is None or all(k[0] in names for k in self.keys)

    def restore(self, ob):
        """Put the mesh back as it was (the object must be in Object Mode, or deleted:
        ob None). Returns the mesh, which is a new datablock after a topology change."""
        mesh = self.mesh
        if not self._arrays_fit(mesh):
            name = mesh.name
            mesh.user_remap(self.copy)   # every object using the mesh gets the copy
            bpy.data.meshes.remove(mesh)
            self.copy.name = name
            self.mesh, self.copy = self.copy, None
            return self.mesh
        mesh_arrays.write_positions(mesh, self.co)
        with _any_object(ob, mesh) as owner:
            keys = mesh.shape_keys
            if self.keys is None:
                if keys is not None:
                    owner.shape_key_clear()
            else:
                names = [k[0] for k in self.keys]
                for kb in [kb for kb in keys.key_blocks if kb.name not in names]:
                    owner.shape_key_remove(kb)
                for name, co, value, mute in self.keys:
                    kb = keys.key_blocks[name]
                    mesh_arrays.write_key(kb, co)
                    kb.value, kb.mute = value, mute
                owner.active_shape_key_index = self.active
                keys.update_tag()
        st = mesh.edge_deform_state
        for name, value in self.state.items():
            setattr(st, name, value)
        if self.rest is None:
            mesh_arrays.remove_attribute(mesh, REST_ATTRIBUTE)
        else:
            mesh_arrays.write_vector_attribute(mesh, REST_ATTRIBUTE, self.rest)
        mesh.update()
        # The graph stays (a cancelled Live on an unbound mesh left it "Not bound" and the
        # next Live bound again: 4.5 s on a 44k mesh): the cache checks the topology and
        # the rest before it uses it. The next solve starts cold, not from the cancelled
        # shape.
        solver_cache.start_cold(mesh)
        return mesh

    def discard(self):
        """Free the copy (the tool ended). Safe after undo removed it."""
        copy, self.copy = self.copy, None
        try:
            if copy is not None and copy.name in bpy.data.meshes \
                    and bpy.data.meshes[copy.name] == copy:
                bpy.data.meshes.remove(copy)
        except ReferenceError:
            pass


class _any_object:
    """An object using `mesh` for the Object-level shape-key calls: `ob`, or a temporary
    one when the object was deleted and only the mesh is left."""

    def __init__(self, ob, mesh):
        self.ob, self.mesh, self.temporary = ob, mesh, None

    def __enter__(self):
        if self.ob is not None and self.ob.data == self.mesh:
            return self.ob
        self.temporary = bpy.data.objects.new(".EdgeDeformRestore", self.mesh)
        return self.temporary

    def __exit__(self, *exc):
        if self.temporary is not None:
            bpy.data.objects.remove(self.temporary)
        return False
