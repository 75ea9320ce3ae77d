"""Where a handle holds its vertices while its controller stays at its rest transform: the
rest shape, plus an offset for vertices the artist placed elsewhere and a handle took over
(docs/decisions/0041):
  - Add Handle on a deformed mesh: the new handle holds its vertices where they are shown;
  - Grab Deform dragging vertices of a handle: the handle keeps them where the drag left
    them, as a Hook keeps an Edit-Mode move of its vertices.
A handle's targets are then (controller motion since its rest) · (rest + offset).

The offsets are the point attribute HOLD_ATTRIBUTE on the mesh, beside the rest shape, so
undo, redo, save and reload carry them; zero (or no attribute) means "at rest". Bind,
Apply and Unbind make the mesh as it is the rest: they clear them (lifecycle.py); Remove
Handle releases its vertices.
"""

import numpy as np

from . import mesh_arrays

HOLD_ATTRIBUTE = ".edge_deform_hold"


def offsets(mesh):
    """(n, 3) float64 offsets from the rest, or None: every handle holds its rest."""
    stored = mesh_arrays.read_vector_attribute(mesh, HOLD_ATTRIBUTE)
    return None if stored is None else stored.astype(np.float64)


def _store(mesh, values):
    if not np.any(values):
        mesh_arrays.remove_attribute(mesh, HOLD_ATTRIBUTE)
    else:
        mesh_arrays.write_vector_attribute(mesh, HOLD_ATTRIBUTE, values)


def hold(mesh, rest, indices, where, motion=None):
    """From now on the handle of `indices` holds them at `where` ((k, 3), object space)
    while its controller has moved by `motion` (4x4 object-space matrix; None: not at all)
    since its rest. `rest`: the rest shape (n, 3). The object must be in Object Mode."""
    indices = np.asarray(indices, np.int64)
    if indices.size == 0:
        return
    at_rest = np.asarray(where, np.float64)
    if motion is not None:
        inverse = np.linalg.inv(np.asarray(motion, np.float64))
        at_rest = at_rest @ inverse[:3, :3].T + inverse[:3, 3]
    values = offsets(mesh)
    if values is None:
        values = np.zeros((len(mesh.vertices), 3))
    values[indices] = at_rest - rest[indices]
    _store(mesh, values)


def release(mesh, indices):
    """The vertices `indices` are held at their rest again (their handle went)."""
    values = offsets(mesh)
    if values is not None and len(indices):
        values[np.asarray(indices, np.int64)] = 0.0
        _store(mesh, values)


def clear(mesh):
    """Every handle holds its rest (the mesh as it is became the rest)."""
    mesh_arrays.remove_attribute(mesh, HOLD_ATTRIBUTE)
