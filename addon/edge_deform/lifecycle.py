"""The lifecycle of a bound mesh: its rest shape, its output, its stored state, and when
each of them stops being valid. Nothing else in the add-on writes the rest shape or the
output: operators, Live Deform, Grab Deform, the frame handler and Bake all come here.

States (docs/addon.md has the diagram). They are stored on the Mesh, next to the data
they describe (`mesh.edge_deform_state`, plus the point attribute REST_ATTRIBUTE), so
undo, redo, save and reload carry them together with the vertices, and two objects
sharing one mesh share one rest shape and one output:

  UNBOUND     state.output == 'NONE': the base mesh is the rest shape.
  KEY OUTPUT  state.output == 'SHAPE_KEY': the key `state.output_key` was made by the
              add-on and holds the last result; the base mesh (the rest) is untouched.
  MESH OUTPUT state.output == 'MESH': the base mesh holds the last result; the rest shape
              is kept in the point attribute REST_ATTRIBUTE.

Invalidation rules, checked before anything is written (`_check_output`):
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
Every check runs before the first write, so a refused operation changes nothing.
"""

import time

import bpy
import numpy as np

from . import engine, handle_holds, mesh_arrays, native, settle, solver_cache, solve_method

REST_ATTRIBUTE = ".edge_deform_rest"
STATE_FIELDS = ("output", "output_key", "made_key_datablock", "topology", "written", "base",
                "baked_keys", "unheld")
Refused = engine.EdgeDeformError


def _state(mesh):
    return mesh.edge_deform_state


def _hash(co):
    return mesh_arrays.array_digest(np.ascontiguousarray(co, np.float32))


# ------------------------------------------------------------------ ownership and checks

def owned_key(mesh):
    """The output shape key made by the add-on, if it still exists."""
    st, keys = _state(mesh), mesh.shape_keys
    if st.output != 'SHAPE_KEY' or keys is None or not st.output_key:
        return None
    return keys.key_blocks.get(st.output_key)


def baked_key_names(mesh):
    return [n for n in _state(mesh).baked_keys.split("\n") if n]


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


def _check_output(ob, digest):
    """Raise Refused if writing the output now would lose or corrupt something."""
    s, mesh = ob.edge_deform, ob.data
    st = _state(mesh)
    if st.output == 'MESH':
        if s.output != 'MESH':
            raise Refused("The base mesh holds the last deformation (Output was Mesh): "
                          "Apply or Bind first, or set Output back to Mesh")
        if st.topology != digest:
            raise Refused("The mesh topology changed since the last solve and the base mesh "
                          "holds the deformed shape: press Bind to make the current mesh "
                          "the rest shape")
        if _hash(mesh_arrays.read_positions32(mesh)) != st.written:
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
        base = _hash(mesh_arrays.read_positions32(mesh))
        if (st.topology == digest and base == st.base
                and _hash(mesh_arrays.read_key(kb)) != st.written):
            raise Refused("The shape key '%s' was edited since the last solve: Apply to "
                          "keep the edits, or delete the key to solve again" % kb.name)
    if s.output == 'SHAPE_KEY':
        check_key_name(ob, s.shape_key_name, allowed=(kb.name,) if kb is not None else ())


def rest_shape(mesh):
    """The rest shape, float64 (n,3): kept beside the base while it holds the output."""
    if _state(mesh).output == 'MESH':
        X = mesh_arrays.read_vector_attribute(mesh, REST_ATTRIBUTE)
        if X is None:
            raise Refused("The rest shape stored with the mesh is missing: press Bind")
        return X.astype(np.float64)
    return mesh_arrays.read_positions(mesh)


# ------------------------------------------------------------------ solving

def _to_end(steps):
    """Run a generator of stages in one go; its result."""
    while True:
        try:
            next(steps)
        except StopIteration as done:
            return done.value


class ObjectSolver:
    """One object's settings tied to its mesh's Binding, after every check: what a tool
    holds while it solves. `write` is the only way a result reaches the mesh."""

    def __init__(self, ob, inputs, binding, base_hash):
        self.ob, self.inputs, self.binding = ob, inputs, binding
        self.base_hash = base_hash   # the base cannot change while an ObjectSolver is used
        self.output = output_settings(ob)   # what the checks were made for

    def warnings(self):
        return engine.missing_controllers(self.inputs)

    def targets(self):
        return engine.handle_targets(self.ob, self.binding.X, self.inputs)

    def solve(self, targets, iterations, tolerance, warm=True, initial=None, check_claims=True):
        """One solve; warm-starts from this binding's previous result when allowed (with
        unchanged targets that continues the same accelerated iteration, so a drag that
        stops settles on the cold solve's shape). check_claims: see Binding.solve."""
        return self.binding.solve(targets, iterations, tolerance,
                                  solve_method.requested(self.ob.edge_deform), warm, initial,
                                  check_claims)

    def settings_changed(self):
        """Follow a change of the global λ or the domain (Live Deform's keys)."""
        self.inputs = engine.with_global_changes(self.inputs, self.ob)
        self.binding.sync(native.get(), self.inputs, self.ob.name_full)

    def hold_grab(self, handles, static, roi):
        """Grab Deform's constraints; `release_grab` returns to the settings'."""
        self.binding.hold_grab(handles, static, roi)

    def release_grab(self):
        self.binding.release_grab()

    def write(self, X):
        if output_settings(self.ob) != self.output:
            raise Refused("The Output settings changed: solve again")
        _write(self.ob, self.binding, X, self.base_hash)


def output_settings(ob):
    """The settings that decide where the output goes (a change needs new checks)."""
    return ob.edge_deform.output, ob.edge_deform.shape_key_name


def prepare_steps(ob, inputs=None, require_handles=True, what=None,
                  fractions=(0.0, 0.5)):
    """Check the object and its mesh and bind: a generator that yields (fraction, text)
    before building and factoring a graph when the cached one cannot be used (a new
    domain, rest or topology), and returns an ObjectSolver ready to solve, or raises Refused
    before anything changes. `what` starts the status texts."""
    if inputs is None:
        inputs = engine.gather_inputs(ob, require_handles=require_handles)
    mesh = ob.data
    digest = mesh_arrays.topology_digest(mesh)
    _check_output(ob, digest)
    # (The owner: a linked duplicate has settings of its own.)
    binding = yield from solver_cache.binding_steps(
        mesh, inputs, rest_shape(mesh), digest, what or "'%s'" % ob.name, fractions,
        ob.name_full)
    return ObjectSolver(ob, inputs, binding, _hash(mesh_arrays.read_positions32(mesh)))


def prepare(ob, inputs=None, require_handles=True):
    """prepare_steps in one go."""
    return _to_end(prepare_steps(ob, inputs, require_handles))


def deform_steps(ob, chunk_ms=100.0):
    """Solve from scratch in chunks of iterations, for a Solve that Esc can stop: a
    generator yielding (fraction, text) between chunks; writes only after the last chunk
    and returns (ObjectSolver, SolveResult of the last chunk, iterations in all). The chunks
    continue one iteration (warm starts with unchanged targets keep the Anderson history,
    docs/api.md), so the result is the one-call `deform(ob)`'s."""
    s = ob.edge_deform
    # A graph to build first (the domain changed since the last solve) is named in the
    # status; the progress then follows the iterations.
    solver = yield from prepare_steps(ob, what="Deforming '%s'" % ob.name,
                                      fractions=(0.0, 0.0))
    targets, limit, done, ms_per_iteration = solver.targets(), int(s.iterations), 0, None
    while True:
        yield done / max(1, limit), "Deforming '%s': %d/%d iterations…" % (ob.name, done, limit)
        n = settle.iterations_within(chunk_ms, ms_per_iteration, most=limit - done)
        t0 = time.perf_counter()
        r = solver.solve(targets, n, s.tolerance, warm=done > 0)
        ms_per_iteration = (time.perf_counter() - t0) * 1e3 / max(1, r.iterations)
        done += r.iterations
        if settle.is_settled(r) or done >= limit or r.iterations < n:
            break
    solver.write(r.positions)
    return solver, r, done


def deform(ob, warm=False, reuse_inputs=False, iterations=None):
    """Bind if needed, solve from the controllers, write: (ObjectSolver, SolveResult)."""
    s = ob.edge_deform
    solver = prepare(ob, solver_cache.cached_inputs(ob) if reuse_inputs else None)
    r = solver.solve(solver.targets(), iterations or s.iterations, s.tolerance, warm=warm)
    solver.write(r.positions)
    return solver, r


# ------------------------------------------------------------------ writing the output

def _set(st, **values):
    """Assign only what changed (each RNA assignment tags the mesh for an update)."""
    for name, value in values.items():
        if getattr(st, name) != value:
            setattr(st, name, value)


def _write(ob, binding, X, base_hash):
    s, mesh = ob.edge_deform, ob.data
    st = _state(mesh)
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
        _set(st, output='SHAPE_KEY', output_key=kb.name, written=_hash(co), base=base_hash)
        mesh.shape_keys.update_tag()
    else:
        if st.output != 'MESH':
            mesh_arrays.write_vector_attribute(mesh, REST_ATTRIBUTE, binding.X)
        _move_base(mesh, co)
        _set(st, output='MESH', output_key="", written=_hash(co))
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
    st = _state(mesh)
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


# ------------------------------------------------------------------ bind, apply, unbind

def bind(ob):
    """Bind in one go (see bind_steps)."""
    return _to_end(bind_steps(ob))


def bind_steps(ob):
    """The current base mesh and controller transforms become the rest. A generator
    yielding (fraction, text) before each long stage (reading, building the graph,
    factoring: progress for the user), returning the Binding. Nothing is written unless
    every stage succeeds."""
    yield 0.0, "Binding '%s': reading %d vertices and the groups…" % (
        ob.name, len(ob.data.vertices))
    inputs = engine.gather_inputs(ob)
    mesh = ob.data
    digest = mesh_arrays.topology_digest(mesh)
    binding = yield from solver_cache.new_binding_steps(
        mesh, inputs, mesh_arrays.read_positions(mesh), digest, "Binding '%s'" % ob.name,
        (0.2, 0.4), ob.name_full)
    st = _state(mesh)
    if st.output == 'MESH':   # the base holds the shape the user accepts as the new rest
        mesh_arrays.remove_attribute(mesh, REST_ATTRIBUTE)
        st.output, st.written = 'NONE', ""
    st.topology, st.unheld = digest, 0
    handle_holds.clear(mesh)   # the handles hold the new rest
    record_rest_transforms(ob)
    return binding


def apply(ob):
    """Make what the user sees the new base mesh and rest shape (see _apply_key)."""
    mesh = ob.data
    st = _state(mesh)
    if mesh.shape_keys is not None and not mesh.shape_keys.use_relative:
        raise Refused("Apply needs relative shape keys (Shape Keys > Relative is off)")
    if st.output == 'NONE' or (st.output == 'SHAPE_KEY' and owned_key(mesh) is None):
        deform(ob)   # nothing shown yet: solve now (may refuse; nothing written then)
    if st.output == 'SHAPE_KEY':
        _apply_key(ob, owned_key(mesh))
    mesh_arrays.remove_attribute(mesh, REST_ATTRIBUTE)
    handle_holds.clear(mesh)   # the shape shown, held where it is, is the new rest
    st.output, st.output_key, st.written, st.base, st.unheld = 'NONE', "", "", "", 0
    record_rest_transforms(ob)
    solver_cache.forget(mesh)
    mesh.update()


def _apply_key(ob, kb):
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
        if len(keys.key_blocks) == 1 and _state(mesh).made_key_datablock:
            ob.shape_key_clear()   # only the Basis the add-on added is left
        elif active in keys.key_blocks:
            ob.active_shape_key_index = keys.key_blocks.find(active)


def is_bound(mesh):
    """Has this mesh a binding (cached solver, or a result it holds)? What the panel's
    Bind/Unbind swap shows; the same test Unbind uses to say whether it did anything."""
    return solver_cache.is_cached(mesh) or _state(mesh).output != 'NONE'


def unbind(ob):
    """Forget the cache and the stored rest: the mesh as it is becomes the rest. The
    output key stays the add-on's (the next solve writes it again)."""
    mesh = ob.data
    st = _state(mesh)
    was = is_bound(mesh)
    solver_cache.forget(mesh)
    mesh_arrays.remove_attribute(mesh, REST_ATTRIBUTE)
    handle_holds.clear(mesh)
    if st.output == 'MESH':
        st.output, st.written = 'NONE', ""
    st.topology, st.unheld = "", 0
    return was


def note_unheld_edit(mesh, count):
    """Grab Deform placed `count` vertices that no handle holds: a solve from the handles
    will move them (Live says so before it does)."""
    _state(mesh).unheld = int(count)


def record_rest_transforms(ob):
    """The controllers' current transforms become their rest (Bind, Apply)."""
    for h in ob.edge_deform.handles:
        if h.controller is not None:
            h.rest_matrix = engine.controller_rest(ob, h.controller)


# ------------------------------------------------------------------ cancel: exact restore

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
        st = _state(mesh)
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
        st = _state(mesh)
        for name, value in self.state.items():
            setattr(st, name, value)
        if self.rest is None:
            mesh_arrays.remove_attribute(mesh, REST_ATTRIBUTE)
        else:
            mesh_arrays.write_vector_attribute(mesh, REST_ATTRIBUTE, self.rest)
        mesh.update()
        solver_cache.forget(mesh)
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
