"""Turn the object's settings into solver inputs and controller targets; solve; describe.

Pure reading and arithmetic: nothing here writes bpy data (lifecycle.py owns the rest
shape and the output). bpy data is read only through mesh_arrays.
"""

import math
from dataclasses import dataclass, field
from typing import List, Optional

import bpy
import numpy as np

from . import mesh_arrays


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
    for name in (s.static_group, s.roi_group, s.stiffness_group):
        if name:
            names.append(name)
    for name in names:
        if name not in ob.vertex_groups:
            raise EdgeDeformError("Vertex group '%s' does not exist (deleted or renamed?): "
                                  "pick a group in the Edge Deform panel" % name)
    weights = mesh_arrays.read_group_weights(ob, names)

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


def controller_rest(ob, controller):
    """A controller's transform in the deformed object's space: what `rest_matrix` holds."""
    return ob.matrix_world.inverted_safe() @ controller.matrix_world


def record_rest_transforms(ob):
    """The controllers' current transforms become their rest (Bind, Apply)."""
    for h in ob.edge_deform.handles:
        if h.controller is not None:
            h.rest_matrix = controller_rest(ob, h.controller)


def missing_controllers(inputs):
    """Warnings for handles without a controller (e.g. the controller was deleted)."""
    return ["Handle '%s' has no controller (deleted?): it stays at its rest position"
            % g.group for g in inputs.handle_groups if g.controller is None]


def handle_targets(ob, X, inputs):
    """Targets (len(handles),3) in object space, in the order of inputs.handles.

    Controllers are read in the deformed object's space: a handle moves by the change of
    its controller's transform relative to the object since the rest (like a Hook), so
    moving the object together with controllers parented to it deforms nothing.
    4x4 products in mathutils and the per-vertex product with einsum: no BLAS/LAPACK
    call here, whose thread pool would fight the solver's OpenMP threads every update.
    """
    obmw_inv = ob.matrix_world.inverted_safe()
    out = []
    for g in inputs.handle_groups:
        P = X[g.indices]
        if g.controller is not None:
            A = np.array(obmw_inv @ g.controller.matrix_world @ g.rest_inverse)
            P = np.einsum("ij,kj->ik", P, A[:3, :3]) + A[:3, 3]
        out.append(P)
    return np.concatenate(out, axis=0)


def controller_state(ob, inputs):
    """A cheap fingerprint of the object's and controllers' transforms, to skip unchanged
    updates."""
    return (tuple(map(tuple, ob.matrix_world)),) + tuple(
        tuple(map(tuple, g.controller.matrix_world)) if g.controller else None
        for g in inputs.handle_groups)


class IterationBudget:
    """Iterations per tick for the modal tools: at most `iterations`, and no more than fit
    in `budget_ms` (at least two), so a large mesh stays responsive; the tools keep
    iterating on later ticks until the solve converges."""

    def __init__(self, budget_ms=40.0):
        self.budget_ms = budget_ms
        self.ms_per_iteration = None

    def iterations(self, limit):
        # At least two: warm solve calls of one iteration each follow the same iterates
        # but may not report convergence (measured on the plane, a shear-and-bend at
        # λ 0.5: still unconverged after 1500 one-iteration calls, where calls of 2 or
        # more stop at iteration 1519, as one long call does). A 50k mesh at ~43 ms an
        # iteration got one iteration a tick and might never settle.
        least = min(2, int(limit))
        if not self.ms_per_iteration:
            return least        # first tick: measure
        return max(least, min(int(limit), int(self.budget_ms / self.ms_per_iteration)))

    def record(self, result, elapsed_ms):
        self.ms_per_iteration = elapsed_ms / max(1, result.iterations)


def status(result, elapsed_ms=None, iterations=None):
    """The one place where a solve result becomes words for the user: (level, text) lines
    for reports and headers, and whether the tools may stop iterating. `iterations` and
    `elapsed_ms` may be totals over several solves (Live settles over many ticks)."""
    # "settled" only when the solver's distance estimate says converged (docs/api.md).
    count = result.iterations if iterations is None else iterations
    text = "%s, %d iterations" % ("settled" if result.converged else "settling…", count)
    if elapsed_ms is not None:
        text += ", %.0f ms" % elapsed_ms if elapsed_ms >= 10 else ", %.1f ms" % elapsed_ms
    lines = [('WARNING', w) for w in result.warnings]
    return lines, text, bool(result.converged)


# The modal tools (Live, Grab) keep iterating on later ticks until the solve converges. Past
# this many iterations since the last change they stop and say so, as a cold solve stops at
# the package's default max_iterations: some shapes never report convergence (a mode that
# does not contract: docs/benchmarks.md, "spectrum"; or a tolerance of 0), and an idle tool
# must not keep a core busy and the mesh creeping for ever.
SETTLE_LIMIT = 2000


def settle_status(result, elapsed_ms, iterations, resume_hint):
    """status() for the modal tools, over the iterations since the last change: (header
    text, whether to stop iterating until something changes)."""
    _, text, converged = status(result, elapsed_ms, iterations)
    if converged or iterations < SETTLE_LIMIT:
        return text, converged
    estimate = float(result.distance_estimate)
    how_far = ("estimated %.0e of the size away" % estimate if math.isfinite(estimate)
               else "distance unknown")
    # (Worded without "settled", which the header shows only for a converged solve.)
    return ("stopped after %d iterations, not converged (%s); %s to go on"
            % (iterations, how_far, resume_hint)), True


# Exceptions an operator turns into a report; the package's FactorizationError is a
# RuntimeError.
USER_ERRORS = (EdgeDeformError, ValueError, IndexError, ImportError, RuntimeError)
