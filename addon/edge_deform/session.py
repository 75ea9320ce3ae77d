"""Session cache: one Binding (a Deformer and its arrays) per mesh, for this Blender session.

Keyed by the mesh datablock pointer; each entry also remembers the topology (counts and a
digest) and the settings it was built from, so a stale entry is rebuilt, never reused.
Entries are plain Python objects: they die with the session, and nothing here touches bpy.
Only solver_cache.py reads or writes the entries (it decides when one may be trusted, and
is the one way to forget one); a Binding's state changes only through its methods.
"""

import enum
import hashlib
import itertools
import time

import numpy as np

_bindings = {}
_systems = itertools.count(1)   # Binding.system: unique over the session's Bindings


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
        self.rest_key = _digest(X)
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
        (settle.Settle.tick)."""
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
        ckey = (_digest(inputs.handles, inputs.static, inputs.roi), inputs.roi_radius,
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
        skey = ("f", float(lam)) if np.isscalar(lam) else ("a", _digest(lam))
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
