"""Session cache: one Binding (Deformer + arrays) per mesh, for this Blender session.

Keyed by the mesh datablock pointer; each entry also remembers the topology (counts and a
digest) and the settings it was built from, so a stale entry is rebuilt, never reused.
Entries are plain Python objects: they die with the session, and nothing here touches bpy.
Only lifecycle.py uses this cache (it decides when an entry may be trusted).
"""

import hashlib

import numpy as np

_bindings = {}


def _digest(*arrays):
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        if a is None:
            h.update(b"none")
        else:
            a = np.ascontiguousarray(a)
            h.update(str((a.dtype.str, a.shape)).encode())
            h.update(a.tobytes())
    return h.hexdigest()


class Binding:
    """A Deformer bound to one mesh, with the constraint arrays it was given."""

    def __init__(self, mesh_pointer, counts, digest, X, F):
        self.mesh_pointer = mesh_pointer
        self.counts = counts
        self.digest = digest
        self.X = X                  # rest positions (n,3) float64, object space
        self.F = F                  # loop triangles (m,3) int64
        self.rest_key = _digest(X)
        self.deformer = None
        self.domain = None
        self.inputs = None          # the Inputs last synced
        self.inputs_owner = None    # name of the object whose settings they are
        self.constraint_key = None
        self.stiffness_key = None
        self.last = None            # last SolveResult, for warm starts
        self.bind_ms = 0.0

    def sync(self, ed, inputs):
        """Bring the Deformer in line with `inputs`, redoing only what changed.

        Raises ValueError/IndexError from the package; the Binding then keeps its old state
        for the parts that failed (their keys are only updated after success).
        """
        if self.deformer is None or self.domain != inputs.domain:
            self.build(ed, inputs.domain)
        ckey = _digest(inputs.handles, inputs.static, inputs.roi)
        if ckey != self.constraint_key:
            self.constraint_key = None
            self.deformer.set_constraints(handles=inputs.handles, static=inputs.static,
                                          roi=inputs.roi)
            self.constraint_key = ckey
            self.last = None
        lam = inputs.stiffness
        skey = ("f", float(lam)) if np.isscalar(lam) else ("a", _digest(lam))
        if skey != self.stiffness_key:
            self.stiffness_key = None
            self.deformer.set_stiffness(lam)
            self.stiffness_key = skey
        self.inputs = inputs

    def build(self, ed, domain):
        """A new Deformer (the graph) for `domain`; constraints and stiffness come next."""
        self.deformer = ed.Deformer(self.X, self.F, domain=domain.lower())
        self.domain = domain
        self.constraint_key = self.stiffness_key = None
        self.last = None

    def use_constraints(self, handles, static, roi):
        """Temporary constraints (the grab tool); the next sync() restores the settings'."""
        self.deformer.set_constraints(handles=handles, static=static, roi=roi)
        self.constraint_key = "temporary"
        self.last = None


def get(mesh_pointer):
    return _bindings.get(mesh_pointer)


def put(binding):
    _bindings[binding.mesh_pointer] = binding


def drop(mesh_pointer):
    _bindings.pop(mesh_pointer, None)


def clear():
    _bindings.clear()


def prune(live_pointers):
    """Forget meshes that no longer exist (deleted, or replaced by undo)."""
    for key in list(_bindings):
        if key not in live_pointers:
            del _bindings[key]


def rest_key(X):
    return _digest(X)
