"""The lifecycle of a bound mesh: its rest shape, its output, its stored state, and when
each of them stops being valid. Operators, Live Deform, Grab Deform, the frame handler
and Bake all come here to bind, solve, apply or unbind; nothing else decides when the
rest shape or the output is written.

States (docs/addon.md has the diagram). They are stored on the Mesh, next to the data
they describe (`mesh.edge_deform_state`, plus the point attribute REST_ATTRIBUTE), so
undo, redo, save and reload carry them together with the vertices, and two objects
sharing one mesh share one rest shape and one output:

  UNBOUND     state.output == 'NONE': the base mesh is the rest shape.
  KEY OUTPUT  state.output == 'SHAPE_KEY': the key `state.output_key` was made by the
              add-on and holds the last result; the base mesh (the rest) is untouched.
  MESH OUTPUT state.output == 'MESH': the base mesh holds the last result; the rest shape
              is kept in the point attribute REST_ATTRIBUTE.

The checks before any write and every write of what the mesh stores are mesh_io.py's,
the solver cache engine.py's, and a tool's exact cancel modal.py's (Snapshot). The app
handlers at the end keep the cache honest across file loads and undo.
"""

import time

import bpy
from bpy.app.handlers import persistent

from . import engine, mesh_io, modal_rules
from .mesh_io import owned_key


Refused = mesh_io.EdgeDeformError


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
                                  engine.acceleration(self.ob.edge_deform), warm, initial,
                                  check_claims)

    def settings_changed(self):
        """Follow a change of the global λ or the domain (Live Deform's keys)."""
        self.inputs = engine.with_global_changes(self.inputs, self.ob)
        engine.sync(self.binding, self.inputs, self.ob.name_full)

    def region_changed(self):
        """Follow a new proportional radius or Connected Only while Proportional stays on
        (Live's wheel, the panel's field): the constraints again, without re-reading the
        groups, the mesh or the output (a wheel step at 560k vertices: 405 -> 140 ms).
        Raises Refused when the radius frees nothing; the inputs are then unchanged."""
        inputs = engine.with_region_changes(self.inputs, self.ob)
        engine.sync(self.binding, inputs, self.ob.name_full)
        self.inputs = inputs

    def hold_grab(self, handles, static, roi, roi_radius=None, roi_connected=False,
                  roi_from=None):
        """Grab Deform's constraints; `release_grab` returns to the settings'. A radius
        (measured from roi_from, None: every handle) that frees nothing is refused in plain
        words, the previous constraints gone."""
        try:
            self.binding.hold_grab(handles, static, roi, roi_radius, roi_connected, roi_from)
        except ValueError as exc:
            raise engine.plain(exc, roi_radius, roi_connected) from None

    def release_grab(self):
        self.binding.release_grab()

    def write(self, X):
        if output_settings(self.ob) != self.output:
            raise Refused("The Output settings changed: solve again")
        mesh_io.write_result(self.ob, self.binding, X, self.base_hash)


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
        forget_deleted_controllers(ob)
        inputs = engine.gather_inputs(ob, require_handles=require_handles)
    start = mesh_io.SolveStart(ob)   # the mesh read once, checked before anything changes
    # (The owner: a linked duplicate has settings of its own.)
    binding = yield from engine.binding_steps(
        ob.data, inputs, start.rest, start.digest, what or "'%s'" % ob.name, fractions,
        ob.name_full)
    return ObjectSolver(ob, inputs, binding, start.base_hash)


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
        n = modal_rules.iterations_within(chunk_ms, ms_per_iteration, most=limit - done)
        t0 = time.perf_counter()
        r = solver.solve(targets, n, s.tolerance, warm=done > 0)
        ms_per_iteration = (time.perf_counter() - t0) * 1e3 / max(1, r.iterations)
        done += r.iterations
        if modal_rules.is_settled(r) or done >= limit or r.iterations < n:
            break
    solver.write(r.positions)
    return solver, r, done


def deform(ob, warm=False, reuse_inputs=False, iterations=None):
    """Bind if needed, solve from the controllers, write: (ObjectSolver, SolveResult)."""
    s = ob.edge_deform
    solver = prepare(ob, engine.cached_inputs(ob) if reuse_inputs else None)
    r = solver.solve(solver.targets(), iterations or s.iterations, s.tolerance, warm=warm)
    solver.write(r.positions)
    return solver, r


# ------------------------------------------------------------------ bind, apply, unbind

def bind_steps(ob):
    """The current base mesh and controller transforms become the rest. A generator
    yielding (fraction, text) before each long stage (reading, building the graph,
    factoring: progress for the user), returning the Binding. Nothing is written unless
    every stage succeeds."""
    yield 0.0, "Binding '%s': reading %d vertices and the groups…" % (
        ob.name, len(ob.data.vertices))
    inputs = engine.gather_inputs(ob)
    mesh = ob.data
    digest = mesh_io.topology_digest(mesh)
    binding = yield from engine.new_binding_steps(
        mesh, inputs, mesh_io.read_positions(mesh), digest, "Binding '%s'" % ob.name,
        (0.2, 0.4), ob.name_full)
    mesh_io.store_base_as_rest(mesh, digest)
    record_rest_transforms(ob)
    return binding


def apply(ob):
    """Make what the user sees the new base mesh and rest shape (see mesh_io.apply_key)."""
    mesh = ob.data
    st = mesh.edge_deform_state
    if mesh.shape_keys is not None and not mesh.shape_keys.use_relative:
        raise Refused("Apply needs relative shape keys (Shape Keys > Relative is off)")
    if st.output == 'NONE' or (st.output == 'SHAPE_KEY' and owned_key(mesh) is None):
        deform(ob)   # nothing shown yet: solve now (may refuse; nothing written then)
    if st.output == 'SHAPE_KEY':
        mesh_io.apply_key(ob, owned_key(mesh))
    mesh_io.store_applied(mesh)
    record_rest_transforms(ob)
    engine.forget(mesh)
    mesh.update()


def is_bound(mesh):
    """Has this mesh a binding (cached solver, or a result it holds)? What the panel's
    Bind/Unbind swap shows; the same test Unbind uses to say whether it did anything."""
    return engine.is_cached(mesh) or mesh.edge_deform_state.output != 'NONE'


def unbind(ob):
    """Forget the cache and the stored rest: the mesh as it is becomes the rest. The
    output key stays the add-on's (the next solve writes it again)."""
    mesh = ob.data
    was = is_bound(mesh)
    engine.forget(mesh)
    mesh_io.store_base_as_rest(mesh, "")
    return was


def forget_deleted_controllers(ob):
    """Let go of controllers deleted from every scene: X leaves the object in the file, in
    no collection, kept only by the handle's pointer. The handle then has no controller,
    as after bpy.data.objects.remove (a warning; it holds its vertices at rest), and the
    file keeps no such object."""
    for h in ob.edge_deform.handles:
        if h.controller is not None and not h.controller.users_collection:
            h.controller = None


def record_rest_transforms(ob):
    """The controllers' current transforms become their rest (Bind, Apply)."""
    for h in ob.edge_deform.handles:
        if h.controller is not None:
            h.rest_matrix = engine.controller_rest(ob, h.controller)


# ------------------------------------------------------------------ undo, file loads, saves
# Keep the session cache honest across file loads and undo, and tell running tools; keep
# no deleted controller in a saved file.
#
# Undo and file loads replace mesh datablocks, so cached bindings may point at freed
# meshes (whose addresses Blender may reuse). Every cache hit is re-checked anyway (topology
# and rest shape, engine.binding_steps); this frees memory early, and counts undo/redo steps
# so that a modal tool notices that the data it holds were replaced and ends cleanly. Before
# a save, handles let go of controllers deleted from every scene (forget_deleted_controllers
# above), so the file does not keep them outside every collection.

_generation = [0]


def generation():
    """Changes after every undo, redo and file load."""
    return _generation[0]


@persistent
def _on_load(*_args):
    _generation[0] += 1
    engine.forget_all()


@persistent
def _on_undo(*_args):
    _generation[0] += 1
    engine.forget_all_but({mesh.as_pointer() for mesh in bpy.data.meshes})


@persistent
def _on_save(*_args):
    for ob in bpy.data.objects:
        if ob.type == 'MESH' and getattr(ob, "edge_deform", None) is not None:
            forget_deleted_controllers(ob)


_HANDLERS = ((bpy.app.handlers.load_post, _on_load),
             (bpy.app.handlers.save_pre, _on_save),
             (bpy.app.handlers.undo_post, _on_undo),
             (bpy.app.handlers.redo_post, _on_undo))


def register_handlers():
    for handlers, fn in _HANDLERS:
        if fn not in handlers:
            handlers.append(fn)


def unregister_handlers():
    for handlers, fn in _HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
