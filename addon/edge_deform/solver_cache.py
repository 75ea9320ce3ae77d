"""The add-on's side of the solver cache (session.py): the only module that reads or writes
its entries. It decides when a mesh's cached Binding may be used (same topology digest,
rest shape and domain), builds a new one in stages when not, and is the one way to forget
a mesh's Binding (Apply, Unbind, a cancelled tool, undo, a file load) or to make its next
solve start cold (a tool ended, Bake's first frame).

The stages are generators yielding (fraction, status text) before each long step; a new
Binding enters the cache only after its last step, so closing one early changes nothing.
"""

from . import engine, mesh_arrays, native, proportional, session

Refused = engine.EdgeDeformError


def _count(n):
    """150k, 1.2M: a count for a status text."""
    for size, unit in ((1e6, "M"), (1e3, "k")):
        if n >= size:
            return "%.3g%s" % (n / size, unit)
    return str(n)


def _graph_steps(binding, inputs, what, fractions, owner):
    """Build `binding`'s graph for inputs.domain and factor it: yields (fraction, text)
    before each of these two long stages (the status text names the work)."""
    graph = "edge" if inputs.domain == 'EDGE' else "vertex"
    yield fractions[0], "%s: building the %s graph of %d triangles…" % (
        what, graph, len(binding.F))
    binding.build(native.get(), inputs.domain)
    yield fractions[1], "%s: factoring %s graph nodes…" % (
        what, _count(binding.deformer.n_nodes))
    sync(binding, inputs, owner)   # (Binding.bind_ms: the compute time)


def sync(binding, inputs, owner):
    """binding.sync, with the core's refusal of a radius that frees nothing in plain
    words."""
    try:
        binding.sync(native.get(), inputs, owner)
    except ValueError as exc:
        raise plain(exc, inputs.roi_radius, inputs.roi_connected) from None


def plain(exc, radius, connected):
    """The error to report for the core's ValueError `exc`."""
    if radius is not None and isinstance(exc, native.get().NoFreeVertexError):
        return proportional.NothingFree(radius, connected)
    return exc


def new_binding_steps(mesh, inputs, X, digest, what, fractions, owner):
    """A new Binding of `mesh` for the rest shape X, built in stages, then cached in place
    of the mesh's old one (which stays until the new one is complete)."""
    F = mesh_arrays.read_triangles(mesh)
    if F.shape[0] == 0:
        raise Refused("The mesh has no faces")
    binding = session.Binding(mesh.as_pointer(), mesh_arrays.topology_counts(mesh), digest,
                              X, F)
    yield from _graph_steps(binding, inputs, what, fractions, owner)
    session.put(binding)
    return binding


def binding_steps(mesh, inputs, X, digest, what, fractions, owner):
    """The cached Binding of `mesh` for this rest shape and domain, synced to `inputs`; a
    stale one (or one of the other domain) is replaced (new_binding_steps)."""
    binding = session.get(mesh.as_pointer())
    if (binding is not None and binding.digest == digest
            and binding.rest_key == session.rest_key(X) and binding.domain == inputs.domain):
        sync(binding, inputs, owner)
        return binding
    return (yield from new_binding_steps(mesh, inputs, X, digest, what, fractions, owner))


def cached_inputs(ob):
    """The inputs of this object's last sync (playback: groups cannot change), or None
    (also when the proportional settings changed since)."""
    binding = session.get(ob.data.as_pointer())
    inputs = None if binding is None else binding.inputs_of(ob.name_full)
    if inputs is None or binding.counts != mesh_arrays.topology_counts(ob.data):
        return None
    if engine.region_radius(ob.edge_deform) != (inputs.roi_radius, inputs.roi_connected):
        return None     # the radius changed: read again (off: the Region group is read)
    return engine.with_global_changes(inputs, ob)


def is_cached(mesh):
    return session.get(mesh.as_pointer()) is not None


def start_cold(mesh):
    """The next solve of this mesh starts from the rest shape, not from the last result
    (a tool ended or was cancelled; Bake's first frame). The Binding stays."""
    binding = session.get(mesh.as_pointer())
    if binding is not None:
        binding.start_cold()


def forget(mesh):
    """Drop the mesh's Binding: the next solve binds again (Apply, Unbind, a restore)."""
    session.drop(mesh.as_pointer())


def forget_all():
    """A file load or the add-on's unregister: no cached Binding is valid any more."""
    session.clear()


def forget_all_but(mesh_pointers):
    """Undo or redo: forget the meshes that no longer exist."""
    session.prune(mesh_pointers)
