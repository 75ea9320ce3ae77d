"""Welding coincident vertices for a solve, and writing every copy back.

A mesh split along seams (UV seams, per-part export) has several vertices at one position.
Solved as they are, the copies move on their own and the seam can tear (the solve warns).
`Welding` maps such a mesh to one with each position once, and results back to every copy.
"""

import numpy as np


class Welding:
    """Copies of one position (bit-identical, used by faces) share one welded vertex.

    vertex: (n,) welded index of every original vertex; first: (n_welded,) the original
    vertex each welded one takes its data from (its lowest-index copy).
    """

    def __init__(self, V, F):
        V = np.asarray(V, dtype=np.float64)
        F = np.asarray(F, dtype=np.int64)
        n = len(V)
        used = np.zeros(n, dtype=bool)
        used[F[(F >= 0) & (F < n)]] = True  # bad indices are the core's to report
        key = np.arange(n)
        if used.any():
            idx = np.flatnonzero(used)
            _, first_of, inverse = np.unique(V[idx], axis=0, return_index=True, return_inverse=True)
            key[idx] = idx[first_of][inverse.reshape(-1)]
        # Welded vertices are numbered in the order of their first copy.
        self.first, self.vertex = np.unique(key, return_inverse=True)
        self.vertex = self.vertex.reshape(-1)
        self.n_original, self.n_welded = n, len(self.first)
        self.copies = n - self.n_welded  # vertices merged into another

    def mesh(self, V, F):
        """The welded mesh. Face indices out of range stay as they are, for the core to name."""
        F = np.asarray(F, dtype=np.int64)
        inside = (F >= 0) & (F < self.n_original)
        return np.asarray(V, dtype=np.float64)[self.first], np.where(inside, self.vertex[np.where(inside, F, 0)], F)

    def indices(self, idx, name):
        """Original vertex indices -> welded ones, each once (in first-seen order)."""
        if idx is None:
            return None
        idx = np.asarray(idx).reshape(-1)
        if idx.size and (idx.dtype.kind not in "iu" or idx.min() < 0 or idx.max() >= self.n_original):
            return idx  # let the core name the problem
        welded = self.vertex[idx]
        _, keep = np.unique(welded, return_index=True)
        return welded[np.sort(keep)]

    def handle_targets(self, handles, targets):
        """Targets for the welded handles; copies of one welded handle must agree."""
        handles = np.asarray(handles).reshape(-1)
        targets = np.asarray(targets, dtype=np.float64)
        welded = self.vertex[handles]
        _, keep = np.unique(welded, return_index=True)
        keep = np.sort(keep)
        chosen = targets[keep]
        slot = {w: k for k, w in enumerate(welded[keep])}
        for h, w in enumerate(welded):
            if not np.array_equal(targets[h], chosen[slot[w]]):
                other = handles[keep[slot[w]]]
                raise ValueError(f"handles {other} and {handles[h]} are copies of one welded vertex "
                                 f"but have different targets")
        return chosen

    def vertex_values(self, values):
        """A per-vertex array (n,) -> (n_welded,): the mean over each vertex's copies."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (self.n_original,):
            return values  # the core names the wrong length
        total = np.bincount(self.vertex, weights=values, minlength=self.n_welded)
        return total / np.bincount(self.vertex, minlength=self.n_welded)

    def unweld(self, X):
        """(n_welded,3) -> (n,3): every copy gets its welded vertex's position."""
        return np.asarray(X)[self.vertex]
