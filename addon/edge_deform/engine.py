"""Turn the object's settings into solver inputs and controller targets; describe results.

Pure reading and arithmetic: nothing here writes bpy data (lifecycle.py owns the rest
shape, the output and the controllers' rest transforms). Mesh data is read only through
mesh_arrays; settings and transforms are read as attributes.
"""

import dataclasses
from dataclasses import dataclass
from typing import List

import numpy as np

from . import handle_holds, mesh_arrays, native


class EdgeDeformError(Exception):
    """A problem the user can fix; operators report the message and cancel."""


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
        raise EdgeDeformError("No handles: select vertices in Edit Mode and use Add Handle")
    names = []
    for h in s.handles:
        if not h.vertex_group:
            raise EdgeDeformError("A handle has no vertex group")
        names.append(h.vertex_group)
    # Proportional on: the radius picks the region and the Region group is not read
    # (docs/decisions/0056).
    region_group = "" if s.proportional else s.roi_group
    for name in (s.static_group, region_group, s.stiffness_group):
        if name:
            names.append(name)
    for name in names:
        if name not in ob.vertex_groups:
            raise EdgeDeformError("Vertex group '%s' does not exist (deleted or renamed?): "
                                  "pick a group in the Edge Deform panel" % name)
    weights = mesh_arrays.read_group_weights(ob, names)
    holds = handle_holds.offsets(ob.data)

    groups, seen = [], np.zeros(len(ob.data.vertices), np.int32)
    for h in s.handles:
        idx = _members(weights[h.vertex_group])
        if idx.size == 0:
            raise EdgeDeformError("Handle group '%s' is empty" % h.vertex_group)
        seen[idx] += 1
        groups.append(HandleInput(h.vertex_group, idx, h.controller,
                                  h.rest_matrix.inverted_safe(),
                                  None if holds is None else holds[idx]))
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
    if region_group:
        roi = _members(weights[region_group])
        if roi.size == 0:
            raise EdgeDeformError("Region group '%s' is empty" % region_group)
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
    (handle_holds.py).
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
        known = native.get().ACCELERATIONS
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
USER_ERRORS = (EdgeDeformError, ValueError, IndexError, ImportError, RuntimeError)
