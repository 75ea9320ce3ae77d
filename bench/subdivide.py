"""Large benchmark meshes made from the stored ones: each triangle split into four at its edge
midpoints (the surface stays where it is, the vertex count grows about fourfold), so the
repository need not carry a 560k-vertex file. Used by bench_roi_scale.py."""

import numpy as np

from edits import UNPACKED, mesh_path


def split_in_four(V, F):
    """One midpoint subdivision: (V', F') with a new vertex on each edge and four faces per face."""
    corners = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    edges, edge_of = np.unique(np.sort(corners, axis=1), axis=0, return_inverse=True)
    edge_of = edge_of.reshape(-1)
    m, n = len(F), len(V)
    ab, bc, ca = (n + edge_of[k * m:(k + 1) * m] for k in range(3))
    a, b, c = F.T
    faces = np.vstack([np.column_stack(t) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return np.vstack([V, 0.5 * (V[edges[:, 0]] + V[edges[:, 1]])]), faces.astype(F.dtype)


def subdivided(name, splits):
    """Mesh `name` (a benchmark mesh file) split `splits` times, cached as .npz in
    bench/results/cache/meshes/ (a child process then loads it without the subdivision's
    temporaries in its peak memory). Returns (V, F, path of the cache)."""
    from edgedeform.mesh_files import read_mesh
    cache = UNPACKED / f"{name}.split{splits}.npz"
    if cache.is_file():
        with np.load(cache) as z:
            return z["V"], z["F"], cache
    V, F = read_mesh(str(mesh_path(name)))
    for _ in range(splits):
        V, F = split_in_four(V, F)
    cache.parent.mkdir(parents=True, exist_ok=True)
    part = cache.with_name(cache.name + ".part.npz")
    np.savez(part, V=V, F=F)
    part.replace(cache)   # whole or absent, also when two runs race
    return V, F, cache
