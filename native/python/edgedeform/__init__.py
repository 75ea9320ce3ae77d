"""edgedeform: triangle-mesh deformation on the edge-based graph.

A local/global solver that blends a rigid 1-form energy (weight lambda) with a rotation- and
scale-aware Laplacian energy (weight 1 - lambda), with lambda per vertex. See docs/api.md.
"""

from ._core import FactorizationError, SolveResult, build_info
from ._core import Deformer as _NativeDeformer
from ._core import metrics

__all__ = ["Deformer", "SolveResult", "FactorizationError", "build_info", "metrics"]
__version__ = build_info()["version"]


def _sparse(coo):
    """A (rows, cols, vals, shape) COO tuple as a SciPy CSR matrix when SciPy is importable."""
    rows, cols, vals, shape = coo
    try:
        import scipy.sparse
    except ImportError:
        return rows, cols, vals
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=shape)


class Deformer(_NativeDeformer):
    """Deformer(V, F, domain="edge", clamp_negative_weights=True). See docs/api.md."""

    def laplacian(self):
        """Graph Laplacian (n_nodes x n_nodes): SciPy CSR, or (rows, cols, vals) without SciPy."""
        return _sparse(self._laplacian_coo())

    def node_matrix(self):
        """P (n_nodes x n_vertices), D in the edge domain: SciPy CSR, or (rows, cols, vals)."""
        return _sparse(self._node_matrix_coo())

    def __repr__(self):
        return (f"<edgedeform.Deformer domain={self.domain!r} vertices={self.n_vertices} "
                f"nodes={self.n_nodes}>")
