"""edgedeform: triangle-mesh deformation on the edge-based graph.

A local/global solver that blends a rigid 1-form energy (weight lambda) with a rotation- and
scale-aware Laplacian energy (weight 1 - lambda), with lambda per vertex. See docs/api.md.
"""

import inspect
import types

import numpy as np

from . import _core
from ._core import FactorizationError, NoFreeVertexError, SolveResult, build_info
from ._core import Deformer as _NativeDeformer
from ._core import metrics
from .format_error import MeshFormatError
from .welding import Welding

__all__ = ["Deformer", "SolveResult", "FactorizationError", "NoFreeVertexError",
           "MeshFormatError", "Welding", "build_info", "metrics", "ACCELERATIONS", "SOLVE_DEFAULTS",
           "SOLVE_INT_RANGES"]
__version__ = build_info()["version"]

# What Deformer.solve takes, as the core defines it (SolveOptions and the table of
# native/bindings/bind_solve.cpp): the method names, and every keyword argument's default.
# The command line, the add-on and the docs read these instead of restating them.
ACCELERATIONS = tuple(_core.ACCELERATIONS)
SOLVE_DEFAULTS = types.MappingProxyType(dict(_core.SOLVE_DEFAULTS))
# solve()'s options after `targets`, in order, as a signature to bind arguments to.
_SOLVE_OPTIONS = inspect.Signature([inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=value)
                                    for name, value in SOLVE_DEFAULTS.items()])
# (low, high) of each integer option, as the core checks it: {"max_iterations": (1, 2**31 - 1), ...}
SOLVE_INT_RANGES = types.MappingProxyType(dict(_core.SOLVE_INT_RANGES))


def _sparse(coo):
    """A (rows, cols, vals, shape) COO tuple as a SciPy CSR matrix when SciPy is importable."""
    rows, cols, vals, shape = coo
    try:
        import scipy.sparse
    except ImportError:
        return rows, cols, vals
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=shape)


def _points(V):
    try:
        V = np.asarray(V, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    return V if V.ndim == 2 and V.shape[1] == 3 else None


class _WeldedResult:
    """A SolveResult of the welded mesh, with positions for every original vertex."""

    def __init__(self, result, welding):
        self._result = result
        self.positions = welding.unweld(result.positions)

    def __getattr__(self, name):
        return getattr(self._result, name)

    def __repr__(self):
        return repr(self._result)


class Deformer(_NativeDeformer):
    """Deformer(V, F, domain="edge", clamp_negative_weights=True, weld=False). See docs/api.md.

    weld=True solves with vertices that share a position (unwelded seams) merged, and gives
    every copy the merged vertex's position; indices, stiffness and positions stay those of
    the mesh as given. Inspection (edges, arcs, weights, ...) then describes the welded mesh.
    """

    def __init__(self, V, F, domain="edge", clamp_negative_weights=True, weld=False):
        points = _points(V) if weld else None
        self._welding = Welding(points, F) if points is not None else None
        self._handles = None
        if self._welding is not None:
            V, F = self._welding.mesh(points, F)
        super().__init__(V, F, domain, clamp_negative_weights)

    @property
    def n_vertices(self):
        """vertices of the mesh as given (with weld=True: before welding)"""
        return super().n_vertices if self._welding is None else self._welding.n_original

    @property
    def welded_copies(self):
        """How many vertices weld=True merged into a copy of theirs (0 without weld)."""
        return 0 if self._welding is None else self._welding.copies

    def set_constraints(self, handles, static=None, roi=None, roi_radius=None, roi_connected=False,
                        roi_from=None):
        w = self._welding
        if w is None:
            return super().set_constraints(handles, static, roi, roi_radius, roi_connected, roi_from)
        h, s = w.indices(handles, "handles"), w.indices(static, "static")
        if h is not None and s is not None and h.dtype.kind in "iu" and s.dtype.kind in "iu":
            both = np.intersect1d(h, s)
            if both.size:
                raise ValueError(f"vertices {w.first[both[:5]].tolist()} are welded copies of both a "
                                 f"handle and a static vertex")
        super().set_constraints(h, s, w.indices(roi, "roi"), roi_radius, roi_connected,
                                w.indices(roi_from, "roi_from"))
        self._handles = np.asarray(handles).reshape(-1)

    def set_stiffness(self, stiffness):
        w = self._welding
        if w is None or np.ndim(stiffness) == 0:
            return super().set_stiffness(stiffness)
        return super().set_stiffness(w.vertex_values(stiffness))

    def _rows(self, X, name):
        X = np.asarray(X, dtype=np.float64)
        if X.ndim != 2 or len(X) != self._welding.n_original:
            raise ValueError(f"{name} has shape {X.shape}, expected ({self._welding.n_original}, 3)")
        return X[self._welding.first]

    def solve(self, targets, *args, **kwargs):
        # Python's own error for a misspelt, doubled or extra argument ("got an unexpected
        # keyword argument 'max_iter'"), not pybind11's, which prints every argument's value.
        options = _SOLVE_OPTIONS.bind(*args, **kwargs).arguments
        w = self._welding
        if w is None:
            return super().solve(targets, **options)
        if self._handles is None:
            raise ValueError("set_constraints(handles=...) must be called before solve")
        T = np.asarray(targets, dtype=np.float64)
        if T.ndim != 2 or len(T) != len(self._handles):
            raise ValueError(f"targets has shape {T.shape}, expected one row per handle "
                             f"({len(self._handles)}, 3)")
        if options.get("initial") is not None:
            options["initial"] = self._rows(options["initial"], "initial")
        return _WeldedResult(super().solve(w.handle_targets(self._handles, T), **options), w)

    def energy(self, X):
        return super().energy(X if self._welding is None else self._rows(X, "X"))

    # help() shows the native signatures and docs (typed arguments, shapes, defaults), not
    # the pass-through signatures of the welding layer above.
    __init__.__doc__ = (_NativeDeformer.__init__.__doc__ +
                        "\nweld: solve with vertices that share a position merged (see the class doc).")
    set_constraints.__doc__ = _NativeDeformer.set_constraints.__doc__
    set_stiffness.__doc__ = _NativeDeformer.set_stiffness.__doc__
    solve.__doc__ = _NativeDeformer.solve.__doc__
    energy.__doc__ = _NativeDeformer.energy.__doc__

    def laplacian(self):
        """Graph Laplacian (n_nodes x n_nodes; L_ii = sum_j w_ij, L_ij = -w_ij): SciPy CSR, or
        (rows, cols, vals) without SciPy."""
        return _sparse(self._laplacian_coo())

    def node_matrix(self):
        """P (n_nodes x n_vertices), D in the edge domain: SciPy CSR, or (rows, cols, vals)."""
        return _sparse(self._node_matrix_coo())

    def __repr__(self):
        return (f"<edgedeform.Deformer domain={self.domain!r} vertices={self.n_vertices} "
                f"nodes={self.n_nodes}>")
