"""Turn the object's settings into solver inputs, keep the Binding fresh, solve, write.

Operators, the modal tools and the frame handler all go through here, so that every entry
point computes the same deformation from the same settings. bpy data is read and written
only through mesh_io; this module handles matrices and index arrays.
"""

import time
from dataclasses import dataclass, field
from typing import List, Optional

import bpy
import numpy as np

from . import mesh_io, native, session


class EdgeDeformError(Exception):
    """A problem the user can fix; operators report the message and cancel."""


@dataclass
class HandleInput:
    group: str
    indices: np.ndarray
    controller: Optional[bpy.types.Object]
    rest_inverse: object       # mathutils.Matrix: inverse of the controller's rest


@dataclass
class Inputs:
    domain: str
    handle_groups: List[HandleInput]
    handles: np.ndarray
    static: np.ndarray
    roi: Optional[np.ndarray]
    stiffness: object          # float or (n,) float64
    groups_key: tuple = field(default=())


def _members(weights):
    return np.flatnonzero(weights > 0.0).astype(np.int64)


def gather_inputs(ob, require_handles=True):
    """Read the settings and vertex groups of `ob`; raise EdgeDeformError on bad input."""
    s = ob.edge_deform
    if require_handles and not s.handles:
        raise EdgeDeformError("No handles: select vertices in Edit Mode and use Add Handle")
    names = []
    for h in s.handles:
        if not h.vertex_group:
            raise EdgeDeformError("A handle has no vertex group")
        names.append(h.vertex_group)
    for label, name in (("static", s.static_group), ("region", s.roi_group),
                        ("stiffness", s.stiffness_group)):
        if name:
            names.append(name)
    for name in names:
        if name not in ob.vertex_groups:
            raise EdgeDeformError("Vertex group '%s' does not exist" % name)
    weights = mesh_io.read_group_weights(ob, names)

    groups, seen = [], np.zeros(len(ob.data.vertices), np.int32)
    for h in s.handles:
        idx = _members(weights[h.vertex_group])
        if idx.size == 0:
            raise EdgeDeformError("Handle group '%s' is empty" % h.vertex_group)
        seen[idx] += 1
        groups.append(HandleInput(h.vertex_group, idx, h.controller,
                                  h.rest_matrix.inverted_safe()))
    if np.any(seen > 1):
        v = int(np.flatnonzero(seen > 1)[0])
        raise EdgeDeformError("Vertex %d belongs to two handle groups; a vertex can follow "
                              "only one handle" % v)
    handles = (np.concatenate([g.indices for g in groups]) if groups
               else np.zeros(0, np.int64))

    static = np.zeros(0, np.int64)
    if s.static_group:
        static = _members(weights[s.static_group])
        if static.size == 0:
            raise EdgeDeformError("Static group '%s' is empty" % s.static_group)
        overlap = np.intersect1d(static, handles)
        if overlap.size:
            raise EdgeDeformError("%d vertices are both handle and static (e.g. vertex %d)"
                                  % (overlap.size, overlap[0]))
    roi = None
    if s.roi_group:
        roi = _members(weights[s.roi_group])
        if roi.size == 0:
            raise EdgeDeformError("Region group '%s' is empty" % s.roi_group)
    if s.stiffness_group:
        stiffness = np.clip(weights[s.stiffness_group].astype(np.float64), 0.0, 1.0)
    else:
        stiffness = float(s.stiffness)
    return Inputs(s.domain, groups, handles, static, roi, stiffness)


def with_global_changes(inputs, ob):
    """Inputs after a live change of the global λ or the domain (no group re-read)."""
    s = ob.edge_deform
    lam = inputs.stiffness if s.stiffness_group else float(s.stiffness)
    return Inputs(s.domain, inputs.handle_groups, inputs.handles, inputs.static,
                  inputs.roi, lam)


def _rest_positions(mesh, digest):
    """The rest shape: kept in the mesh when output went to the base mesh, else the base."""
    X = mesh_io.read_rest(mesh, digest)
    if X is not None:
        return X
    if mesh_io.has_rest(mesh):
        raise EdgeDeformError(
            "The mesh topology changed after binding and the base mesh holds the deformed "
            "shape: press Bind to make the current mesh the rest shape")
    return mesh_io.read_positions(mesh)


def ensure_binding(ob, inputs, fresh=False, check=True):
    """The up-to-date Binding of `ob` for `inputs` (built or rebuilt when needed).

    fresh: forget the stored rest shape and cached state (the Bind operator).
    check: compare the full topology digest and rest shape (skipped inside a modal tool,
    where the mesh cannot change under us; the counts are still compared).
    """
    ed = native.get()
    mesh = ob.data
    pointer = mesh.as_pointer()
    counts = mesh_io.topology_counts(mesh)
    binding = session.get(pointer)
    if fresh:
        mesh_io.clear_rest(mesh)
        binding = None
    if binding is not None and binding.counts != counts:
        binding = None
    if binding is None or check:
        digest = mesh_io.topology_digest(mesh)
        if binding is not None and binding.digest != digest:
            binding = None
        X = _rest_positions(mesh, digest)
        if binding is None or binding.rest_key != session.rest_key(X):
            t0 = time.perf_counter()
            F = mesh_io.read_triangles(mesh)
            if F.shape[0] == 0:
                raise EdgeDeformError("The mesh has no faces")
            binding = session.Binding(pointer, counts, digest, X, F)
            binding.sync(ed, inputs)
            binding.bind_ms = (time.perf_counter() - t0) * 1e3
            session.put(binding)
            return binding
    binding.sync(ed, inputs)
    return binding


def record_rest_transforms(ob):
    """The controllers' current transforms become their rest (Add Handle, Bind, Apply)."""
    for h in ob.edge_deform.handles:
        if h.controller is not None:
            h.rest_matrix = h.controller.matrix_world.copy()


def handle_targets(ob, binding, inputs):
    """Targets (len(handles),3) in object space, in the order of inputs.handles.

    4x4 products in mathutils and the per-vertex product with einsum: no BLAS/LAPACK
    call here, whose thread pool would fight the solver's OpenMP threads every update.
    """
    obmw = ob.matrix_world
    obmw_inv = obmw.inverted()
    out = []
    for g in inputs.handle_groups:
        P = binding.X[g.indices]
        if g.controller is not None:
            A = np.array(obmw_inv @ g.controller.matrix_world @ g.rest_inverse @ obmw)
            P = np.einsum("ij,kj->ik", P, A[:3, :3]) + A[:3, 3]
        out.append(P)
    return np.concatenate(out, axis=0)


def controller_state(inputs):
    """A cheap fingerprint of the controllers' transforms, to skip unchanged updates."""
    return tuple(tuple(map(tuple, g.controller.matrix_world)) if g.controller else None
                 for g in inputs.handle_groups)


def solve(binding, targets, iterations, tolerance, warm=True, acceleration='ANDERSON'):
    """One solve; warm-starts from the previous result of this binding when allowed (with
    unchanged targets that continues the same, accelerated, iteration)."""
    warm = bool(warm and binding.last is not None)
    result = binding.deformer.solve(targets, max_iterations=int(iterations),
                                    tolerance=float(tolerance), warm_start=warm,
                                    acceleration=acceleration.lower())
    binding.last = result
    return result


class IterationBudget:
    """Iterations per tick for the modal tools: at most `iterations`, and no more than fit
    in `budget_ms` (at least one), so a large mesh stays responsive; the tools keep
    iterating on later ticks until the solve converges."""

    def __init__(self, budget_ms=40.0):
        self.budget_ms = budget_ms
        self.ms_per_iteration = None

    def iterations(self, limit):
        if not self.ms_per_iteration:
            return 1            # first tick: measure
        return max(1, min(int(limit), int(self.budget_ms / self.ms_per_iteration)))

    def record(self, result, elapsed_ms):
        self.ms_per_iteration = elapsed_ms / max(1, result.iterations)


def write(ob, binding, positions):
    s = ob.edge_deform
    if s.output == 'MESH' and not mesh_io.has_rest(ob.data):
        # The base mesh is about to hold the deformation: keep the rest shape beside it.
        mesh_io.store_rest(ob.data, binding.X, binding.digest)
    mesh_io.write_output(ob, s.output, s.shape_key_name, positions)


def deform(ob, warm=True, fresh=False, reuse_inputs=False):
    """Gather, bind, solve from the controllers, write. Returns (binding, result).

    reuse_inputs: take the groups read at the last sync (animation playback, where groups
    cannot be edited) instead of reading them again; falls back to reading when the mesh
    has no current binding.
    """
    s = ob.edge_deform
    binding = session.get(ob.data.as_pointer())
    if (reuse_inputs and binding is not None and binding.inputs is not None
            and binding.counts == mesh_io.topology_counts(ob.data)
            and binding.constraint_key != "temporary"):
        inputs = with_global_changes(binding.inputs, ob)
        binding = ensure_binding(ob, inputs, check=False)
    else:
        inputs = gather_inputs(ob)
        binding = ensure_binding(ob, inputs, fresh=fresh)
    result = solve(binding, handle_targets(ob, binding, inputs), s.iterations, s.tolerance,
                   warm=warm, acceleration=s.acceleration)
    write(ob, binding, result.positions)
    return binding, result


# Exceptions an operator turns into a report; the package's FactorizationError is a
# RuntimeError.
USER_ERRORS = (EdgeDeformError, ValueError, IndexError, ImportError, RuntimeError)
