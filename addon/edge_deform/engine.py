"""The solver bridge: the object's settings as solver inputs and controller targets, the
method a solve asks for, results in the artist's words, and the session's cache of one
bound Deformer (a Binding) per mesh.

Reading and arithmetic: nothing here writes bpy data (lifecycle.py decides when the mesh
is written, mesh_io.py writes it). Mesh data is read only through mesh_io; settings and
transforms are read as attributes. This module alone reads or writes the cache.
"""

import dataclasses
import enum
import itertools
import time
from dataclasses import dataclass
from typing import List

import bpy
import numpy as np

from . import compat, mesh_io


Refused = mesh_io.EdgeDeformError


@dataclass
class HandleInput:
    group: str
    indices: np.ndarray
    controller: object         # bpy.types.Object, or None
    rest_inverse: object       # mathutils.Matrix: inverse of the controller's rest
    offset: object = None      # (k, 3) float64: where it holds them, from the rest; or None


@dataclass
class Inputs:
    domain: str
    handle_groups: List[HandleInput]
    handles: np.ndarray
    static: np.ndarray
    roi: object                # (k,) int64, or None: the whole mesh (or the radius's)
    stiffness: object          # float or (n,) float64
    roi_radius: object = None  # float (mesh units): the region within it of the handles
    roi_connected: bool = False   # ... measured over the surface


def _members(weights):
    return np.flatnonzero(weights > 0.0).astype(np.int64)


def gather_inputs(ob, require_handles=True):
    """Read the settings and vertex groups of `ob`; raise EdgeDeformError on bad input."""
    s = ob.edge_deform
    if require_handles and not s.handles:
        raise Refused("No handles: select vertices in Edit Mode and use Add Handle")
    names = []
    for h in s.handles:
        if not h.vertex_group:
            raise Refused("A handle has no vertex group")
        names.append(h.vertex_group)
    # Proportional on: the radius picks the region and the Region group is not read
    # (docs/decisions/0056).
    region_group = "" if s.proportional else s.roi_group
    for name in (s.static_group, region_group, s.stiffness_group):
        if name:
            names.append(name)
    for name in names:
        if name not in ob.vertex_groups:
            raise Refused("Vertex group '%s' does not exist (deleted or renamed?): "
                          "pick a group in the Edge Deform panel" % name)
    weights, holds = mesh_io.read_groups_and_holds(ob, names)

    groups, seen = [], np.zeros(len(ob.data.vertices), np.int32)
    for h in s.handles:
        idx = _members(weights[h.vertex_group])
        if idx.size == 0:
            raise Refused("Handle group '%s' is empty" % h.vertex_group)
        seen[idx] += 1
        groups.append(HandleInput(h.vertex_group, idx, h.controller,
                                  h.rest_matrix.inverted_safe(),
                                  None if holds is None else holds[idx]))
    if np.any(seen > 1):
        v = int(np.flatnonzero(seen > 1)[0])
        raise Refused("Vertex %d belongs to two handle groups; a vertex can follow "
                              "only one handle" % v)
    handles = (np.concatenate([g.indices for g in groups]) if groups
               else np.zeros(0, np.int64))

    static = np.zeros(0, np.int64)
    if s.static_group:
        static = _members(weights[s.static_group])
        if static.size == 0:
            raise Refused("Static group '%s' is empty" % s.static_group)
        overlap = np.intersect1d(static, handles)
        if overlap.size:
            raise Refused("%d vertices are both handle and static (e.g. vertex %d)"
                                  % (overlap.size, overlap[0]))
    roi = None
    if region_group:
        roi = _members(weights[region_group])
        if roi.size == 0:
            raise Refused("Region group '%s' is empty" % region_group)
    if s.stiffness_group:
        stiffness = np.clip(weights[s.stiffness_group].astype(np.float64), 0.0, 1.0)
    else:
        stiffness = float(s.stiffness)
    radius, connected = region_radius(s)
    return Inputs(s.domain, groups, handles, static, roi, stiffness, radius, connected)


# The first radius, while none was chosen (0): this fraction of the object's largest
# dimension. At an extremity it frees a median 10-17 % of the test meshes' vertices
# (record 0066); Blender's fixed 1 m freed 6 vertices of a 229-unit figure.
FITTED_FRACTION = 0.25


def fitted_radius(ob):
    """A first radius for `ob`, in its own units: FITTED_FRACTION of the largest side of
    its bounding box (1.0 for an empty mesh)."""
    corners = np.array([tuple(c) for c in ob.bound_box], np.float64)
    size = float(np.ptp(corners, axis=0).max())
    return FITTED_FRACTION * size if size > 0.0 else 1.0


def region_radius(settings):
    """(roi_radius, roi_connected) for the core: (None, False) while proportional is off.
    A radius never chosen (0; properties.py sets one when Proportional turns on, but a
    file may hold it on from before) is the fitted one."""
    if not settings.proportional:
        return None, False
    radius = float(settings.proportional_radius) or fitted_radius(settings.id_data)
    return radius, bool(settings.proportional_connected)


def with_global_changes(inputs, ob):
    """Inputs after a live change of the global λ or the domain (no group re-read)."""
    s = ob.edge_deform
    lam = inputs.stiffness if s.stiffness_group else float(s.stiffness)
    return Inputs(s.domain, inputs.handle_groups, inputs.handles, inputs.static,
                  inputs.roi, lam, inputs.roi_radius, inputs.roi_connected)


def with_region_changes(inputs, ob):
    """Inputs after a live change of the proportional radius or Connected Only while
    Proportional stays on: the Region group is not used then, so nothing is re-read."""
    radius, connected = region_radius(ob.edge_deform)
    return dataclasses.replace(inputs, roi_radius=radius, roi_connected=connected)


def controller_rest(ob, controller):
    """A controller's transform in the deformed object's space: what `rest_matrix` holds."""
    return ob.matrix_world.inverted_safe() @ controller.matrix_world


def missing_controllers(inputs):
    """Warnings for handles without a controller (e.g. the controller was deleted)."""
    return ["Handle '%s' has no controller (deleted?): it stays at its rest position"
            % g.group for g in inputs.handle_groups if g.controller is None]


def handle_targets(ob, X, inputs):
    """Targets (len(handles),3) in object space, in the order of inputs.handles.

    Controllers are read in the deformed object's space: a handle moves by the change of
    its controller's transform relative to the object since the rest (like a Hook), so
    moving the object together with controllers parented to it deforms nothing. What it
    moves is where the handle holds its vertices: the rest, plus their offsets
    (mesh_io.hold_offsets).
    4x4 products in mathutils and the per-vertex product with einsum: no BLAS/LAPACK
    call here, whose thread pool would fight the solver's OpenMP threads every update.
    """
    obmw_inv = ob.matrix_world.inverted_safe()
    out = []
    for g in inputs.handle_groups:
        P = X[g.indices] if g.offset is None else X[g.indices] + g.offset
        if g.controller is not None:
            A = np.array(obmw_inv @ g.controller.matrix_world @ g.rest_inverse)
            P = np.einsum("ij,kj->ik", P, A[:3, :3]) + A[:3, 3]
        out.append(P)
    return np.concatenate(out, axis=0)


def moving_handles(targets, X, inputs):
    """The handle groups' targets ((k,3) each, in the order of inputs.handle_groups) that
    are away from where the group holds its vertices at rest (by more than 1e-6 of the
    mesh's size): what the artist moves. None moved: every group (where a radius acts)."""
    least = 1e-6 * float(np.ptp(X, axis=0).max())
    groups, start = [], 0
    for g in inputs.handle_groups:
        held = X[g.indices] if g.offset is None else X[g.indices] + g.offset
        groups.append((targets[start:start + len(g.indices)], held))
        start += len(g.indices)
    moved = [t for t, held in groups if np.abs(t - held).max(initial=0.0) > least]
    return moved or [t for t, _ in groups]


def controller_state(ob, inputs):
    """A cheap fingerprint of the object's and controllers' transforms, to skip unchanged
    updates."""
    return (tuple(map(tuple, ob.matrix_world)),) + tuple(
        tuple(map(tuple, g.controller.matrix_world)) if g.controller else None
        for g in inputs.handle_groups)


# Acceleration "Automatic" (the default) names no method, so the package's own rule picks
# it (acceleration="auto": L-BFGS where λ = 1 on every term, Anderson below; docs/api.md,
# records 0043 and 0070); a method named here would override that rule.
AUTOMATIC = 'AUTO'
# The accelerations an artist may pick besides Automatic: (property item, the package's
# name). The add-on offers those of them that this build of the package has (its
# ACCELERATIONS).
ACCELERATIONS = (('ANDERSON', "anderson"), ('NONE', "none"))
# Drawn when the package cannot load (the first solve then reports why).
_WITHOUT_PACKAGE = ["anderson", "none"]


def offered_accelerations():
    """The package's names of the accelerations this build of `edgedeform` solves with
    (edgedeform.ACCELERATIONS), in the add-on's order."""
    try:
        known = compat.native_package().ACCELERATIONS
    except ImportError:
        return list(_WITHOUT_PACKAGE)
    return [name for _, name in ACCELERATIONS if name in known]


def acceleration(settings):
    """The package's name for the settings' acceleration, or None where the package's own
    measured rule decides: Automatic, and a method stored in a file by a build that had one
    this build lacks (Newton, retired in docs/decisions/0070)."""
    name = dict(ACCELERATIONS).get(settings.acceleration)
    return name if name in offered_accelerations() else None


def solve_report(result, waited_s, iterations):
    """A Solve's result in the artist's words: (details for the Info log, the summary).
    `iterations` is the total over Solve's chunks; `waited_s` the time the artist waited.
    The package's own "not converged" text counts one chunk and speaks of fixed points:
    it is replaced by figures in the details."""
    warnings = [w for w in result.warnings if not w.startswith("not converged")]
    details = [('WARNING', w) for w in warnings]
    estimate = float(result.distance_estimate)   # inf until the solver can estimate it
    how_far = ("estimated distance to the settled shape %.2g of the object's size" % estimate
               if np.isfinite(estimate) else "distance to the settled shape not yet known")
    details.append(('INFO', "Solve details: %d iterations, %s" % (iterations, how_far)))
    if result.converged:
        summary = "Solved: the shape settled (%d iterations, %.1f s)" % (iterations, waited_s)
    else:
        summary = ("Solved %d iterations (%.1f s), but the shape has not settled yet: raise "
                   "Iterations (Solver panel), make a smaller move, or use Live Deform to let "
                   "it settle" % (iterations, waited_s))
    return details, summary


# Exceptions an operator turns into a report; the package's FactorizationError is a
# RuntimeError.
USER_ERRORS = (mesh_io.EdgeDeformError, ValueError, IndexError, ImportError, RuntimeError)


# The proportional radius refused in the artist's words (the core's NoFreeVertexError).
WHERE_TO_CHANGE = "the Edge Deform panel, Static and Region"


# The scene's length unit, as its fields write it (Blender's unit tables, unit.cc):
# metres per unit and the suffix. 'ADAPTIVE' picks a unit per value, as to_string does.
LENGTH_UNITS = {'KILOMETERS': (1e3, " km"), 'METERS': (1.0, " m"), 'CENTIMETERS': (1e-2, " cm"),
                'MILLIMETERS': (1e-3, " mm"), 'MICROMETERS': (1e-6, " µm"),
                'MILES': (1609.344, " mi"), 'FEET': (0.3048, "'"), 'INCHES': (0.0254, '"'),
                'THOU': (2.54e-5, " thou")}


def length(value):
    """A length in the scene's units, as Blender's fields write it: "0.3 m" where the panel's
    Radius field says 0.3 m (to_string alone said "30 cm" beside it)."""
    units = bpy.context.scene.unit_settings
    try:
        metres = value * units.scale_length
        if units.system != 'NONE' and units.length_unit in LENGTH_UNITS:
            per_unit, suffix = LENGTH_UNITS[units.length_unit]
            amount = metres / per_unit
            return ("%.0f" if abs(amount) >= 1e3 else "%.3g") % amount + suffix
        return bpy.utils.units.to_string(units.system, 'LENGTH', metres, precision=3).strip()
    except (AttributeError, TypeError, ValueError):
        return "%.3g" % value


class NothingFree(mesh_io.EdgeDeformError):
    """The core's NoFreeVertexError, in plain words, with what was tried.
    Its text is for a tool that is not running: the panel is where the radius changes."""

    def __init__(self, radius, connected, reason=None):
        self.radius, self.connected = radius, connected
        self.reason = reason or ("No vertex can move within %s of the handles%s (they are "
                                 "too far, or Static holds them)" % (
                                     length(radius), " along the mesh" if connected else ""))
        super().__init__("%s: make the Radius larger or turn Proportional off (%s)"
                         % (self.reason, WHERE_TO_CHANGE))


# ------------------------------------------------------- the cache: when a Binding may be used
# It decides when a mesh's cached Binding may be used (same topology digest,
# rest shape and domain), builds a new one in stages when not, and is the one way to forget
# a mesh's Binding (Apply, Unbind, a cancelled tool, undo, a file load) or to make its next
# solve start cold (a tool ended, Bake's first frame).
#
# The stages are generators yielding (fraction, status text) before each long step; a new
# Binding enters the cache only after its last step, so closing one early changes nothing.



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
    binding.build(compat.native_package(), inputs.domain)
    yield fractions[1], "%s: factoring %s graph nodes…" % (
        what, _count(binding.deformer.n_nodes))
    sync(binding, inputs, owner)   # (Binding.bind_ms: the compute time)


def sync(binding, inputs, owner):
    """binding.sync, with the core's refusal of a radius that frees nothing in plain
    words."""
    try:
        binding.sync(compat.native_package(), inputs, owner)
    except ValueError as exc:
        raise plain(exc, inputs.roi_radius, inputs.roi_connected) from None


def plain(exc, radius, connected):
    """The error to report for the core's ValueError `exc`."""
    if radius is not None and isinstance(exc, compat.native_package().NoFreeVertexError):
        return NothingFree(radius, connected)
    return exc


def new_binding_steps(mesh, inputs, X, digest, what, fractions, owner):
    """A new Binding of `mesh` for the rest shape X, built in stages, then cached in place
    of the mesh's old one (which stays until the new one is complete)."""
    F = mesh_io.read_triangles(mesh)
    if F.shape[0] == 0:
        raise Refused("The mesh has no faces")
    binding = Binding(mesh.as_pointer(), mesh_io.topology_counts(mesh), digest,
                              X, F)
    yield from _graph_steps(binding, inputs, what, fractions, owner)
    _bindings[binding.mesh_pointer] = binding
    return binding


def binding_steps(mesh, inputs, X, digest, what, fractions, owner):
    """The cached Binding of `mesh` for this rest shape and domain, synced to `inputs`; a
    stale one (or one of the other domain) is replaced (new_binding_steps)."""
    binding = cached_binding(mesh.as_pointer())
    if (binding is not None and binding.digest == digest
            and binding.rest_key == rest_key(X) and binding.domain == inputs.domain):
        sync(binding, inputs, owner)
        return binding
    return (yield from new_binding_steps(mesh, inputs, X, digest, what, fractions, owner))


def cached_inputs(ob):
    """The inputs of this object's last sync (playback: groups cannot change), or None
    (also when the proportional settings changed since)."""
    binding = cached_binding(ob.data.as_pointer())
    inputs = None if binding is None else binding.inputs_of(ob.name_full)
    if inputs is None or binding.counts != mesh_io.topology_counts(ob.data):
        return None
    if region_radius(ob.edge_deform) != (inputs.roi_radius, inputs.roi_connected):
        return None     # the radius changed: read again (off: the Region group is read)
    return with_global_changes(inputs, ob)


def is_cached(mesh):
    return cached_binding(mesh.as_pointer()) is not None


def start_cold(mesh):
    """The next solve of this mesh starts from the rest shape, not from the last result
    (a tool ended or was cancelled; Bake's first frame). The Binding stays."""
    binding = cached_binding(mesh.as_pointer())
    if binding is not None:
        binding.start_cold()


def forget(mesh):
    """Drop the mesh's Binding: the next solve binds again (Apply, Unbind, a restore)."""
    _bindings.pop(mesh.as_pointer(), None)


def forget_all():
    """A file load or the add-on's unregister: no cached Binding is valid any more."""
    _bindings.clear()


def forget_all_but(mesh_pointers):
    """Undo or redo: forget the meshes that no longer exist."""
    for key in [key for key in _bindings if key not in mesh_pointers]:
        del _bindings[key]


# ------------------------------------------------------------------ the cache's entries
# Session cache: one Binding (a Deformer and its arrays) per mesh, for this Blender session.
#
# Keyed by the mesh datablock pointer; each entry also remembers the topology (counts and a
# digest) and the settings it was built from, so a stale entry is rebuilt, never reused.
# Entries are plain Python objects: they die with the session, and nothing here touches bpy.
# Only the functions above read or write the entries (they decide when one may be trusted,
# and are the one way to forget one); a Binding's state changes only through its methods.

_bindings = {}
_systems = itertools.count(1)   # Binding.system: unique over the session's Bindings


def _region(roi, roi_radius, roi_connected, roi_from=None):
    """set_constraints' region arguments: a list of vertices or a radius (the core refuses
    both at once), measured from roi_from (None: every handle)."""
    if roi_radius is None:
        return {"roi": roi}
    return {"roi_radius": roi_radius, "roi_connected": roi_connected, "roi_from": roi_from}


class Constraints(enum.Enum):
    """Whose handles the Deformer holds."""
    NONE = "none"            # none yet, or released: the next sync sets the settings'
    SETTINGS = "settings"    # the object's settings (handles, static, region)
    GRAB = "grab"            # Grab Deform's selection, until it ends


class Binding:
    """A Deformer bound to one mesh, with the constraints and stiffness it was given.

    Read-only for everyone else: the mesh's identity (`mesh_pointer`, `counts`, `digest`),
    its rest shape `X`, triangles `F`, the `deformer`, the `domain`, the `system` it
    solves and the `inputs` (with their owner) last synced. Changed only by build, sync,
    hold_grab, release_grab and start_cold."""

    def __init__(self, mesh_pointer, counts, digest, X, F):
        self.mesh_pointer = mesh_pointer
        self.counts = counts
        self.digest = digest
        self.X = X                  # rest positions (n,3) float64, object space
        self.F = F                  # loop triangles (m,3) int64
        self.rest_key = mesh_io.array_digest(X)
        self._bind_ms = 0.0
        self._deformer = None
        self._domain = None
        self._inputs = None
        self._inputs_owner = None
        self._constraints = Constraints.NONE
        self._constraint_key = None
        self._stiffness_key = None
        # The next solve starts cold (a new graph or new constraints): a warm start would
        # continue from a shape solved for other constraints.
        self._cold_start_due = True
        self._system = next(_systems)

    # ---------------------------------------------------------------- reading

    @property
    def deformer(self):
        return self._deformer

    @property
    def domain(self):
        return self._domain

    @property
    def constraints(self):
        return self._constraints

    @property
    def system(self):
        """Names the system the solver iterates on: changes with the graph, the constraints
        (the free vertices) and λ. The tools measure their speed again after a change
        (modal_rules.Settle.tick)."""
        return self._system

    @property
    def starts_cold(self):
        """The next solve starts from scratch (a new graph or new constraints) unless it is
        given a shape to start from (`initial`)."""
        return self._cold_start_due

    @property
    def bind_ms(self):
        """The compute time spent building and factoring this graph (not the wait around
        it, which is what Bind reports)."""
        return self._bind_ms

    def inputs_of(self, owner):
        """The inputs last synced for the object named `owner`, or None (another object's,
        Grab's temporary constraints, or none yet)."""
        if self._constraints != Constraints.SETTINGS or self._inputs_owner != owner:
            return None
        return self._inputs

    # ---------------------------------------------------------------- changing

    def build(self, ed, domain):
        """A new Deformer (the graph) for `domain`; constraints and stiffness come next."""
        t0 = time.perf_counter()
        self._deformer = ed.Deformer(self.X, self.F, domain=domain.lower())
        self._bind_ms = (time.perf_counter() - t0) * 1e3
        self._domain = domain
        self._constraints, self._constraint_key, self._stiffness_key = (
            Constraints.NONE, None, None)
        self._cold_start_due = True
        self._system = next(_systems)

    def sync(self, ed, inputs, owner):
        """Bring the Deformer in line with `inputs` (the settings of the object named
        `owner`), redoing only what changed.

        Raises ValueError/IndexError from the package; the Binding then keeps its old state
        for the parts that failed (their keys are only updated after success).
        """
        if self._deformer is None or self._domain != inputs.domain:
            self.build(ed, inputs.domain)
        t0, factored = time.perf_counter(), False
        ckey = (mesh_io.array_digest(inputs.handles, inputs.static, inputs.roi), inputs.roi_radius,
                inputs.roi_connected)
        # No handles (Grab Deform on a mesh without any: its selection is the handle, set
        # by hold_grab next): there are no settings' constraints to set.
        if inputs.handles.size and (self._constraints != Constraints.SETTINGS
                                    or ckey != self._constraint_key):
            factored = True
            self._constraints, self._constraint_key = Constraints.NONE, None
            self._system = next(_systems)
            self._deformer.set_constraints(handles=inputs.handles, static=inputs.static,
                                           **_region(inputs.roi, inputs.roi_radius,
                                                     inputs.roi_connected))
            self._constraints, self._constraint_key = Constraints.SETTINGS, ckey
            self._cold_start_due = True
        lam = inputs.stiffness
        skey = ("f", float(lam)) if np.isscalar(lam) else ("a", mesh_io.array_digest(lam))
        if skey != self._stiffness_key:
            factored = True
            self._stiffness_key = None
            self._system = next(_systems)
            self._deformer.set_stiffness(lam)
            self._stiffness_key = skey
        if factored:
            self._bind_ms += (time.perf_counter() - t0) * 1e3
        self._inputs, self._inputs_owner = inputs, owner

    def hold_grab(self, handles, static, roi, roi_radius=None, roi_connected=False,
                  roi_from=None):
        """Grab Deform's constraints (its selection), until release_grab."""
        self._constraints, self._constraint_key = Constraints.NONE, None
        self._system = next(_systems)
        self._deformer.set_constraints(handles=handles, static=static,
                                       **_region(roi, roi_radius, roi_connected, roi_from))
        self._constraints = Constraints.GRAB
        self._cold_start_due = True

    def release_grab(self):
        """Grab ended: the next sync sets the settings' constraints again."""
        if self._constraints == Constraints.GRAB:
            self._constraints, self._constraint_key = Constraints.NONE, None
        self._cold_start_due = True

    def start_cold(self):
        """The next solve starts from the rest shape (a tool ended; Bake's first frame)."""
        self._cold_start_due = True

    def solve(self, targets, iterations, tolerance, acceleration, warm=True, initial=None,
              check_claims=True):
        """One solve call. acceleration: the package's name of a method, or None: the
        package's measured rule chooses (docs/decisions/0043, 0070). warm: continue from the
        previous solve unless a cold start is due (with unchanged targets that continues
        the same accelerated iteration, so repeated short calls settle on the one long
        call's shape). check_claims: a convergence claim is first checked against J_G's
        slowest mode (the core's verify_claims: without it Live called the 50k koala
        settled 4.7e-3 of its size away, docs/decisions/0025)."""
        kwargs = dict(max_iterations=int(iterations), tolerance=float(tolerance),
                      verify_claims=bool(check_claims))
        if acceleration is not None:
            kwargs["acceleration"] = acceleration
        if initial is not None:
            r = self._deformer.solve(targets, warm_start=False, initial=initial, **kwargs)
        else:
            r = self._deformer.solve(targets, warm_start=bool(warm and not self._cold_start_due),
                                     **kwargs)
        self._cold_start_due = False
        return r


def cached_binding(mesh_pointer):
    """The mesh's Binding as cached, unchecked (is_cached, the tests)."""
    return _bindings.get(mesh_pointer)


def rest_key(X):
    return mesh_io.array_digest(X)
