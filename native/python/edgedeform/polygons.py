"""Polygon faces as two flat arrays, and what the mesh files derive from them.

A face list is `sizes` (k,) corner counts and `corners` (sum(sizes),) vertex indices, so
that quads and n-gons keep their shape through a deformation (the solver only sees the
fan triangulation).
"""

import numpy as np


def starts(sizes):
    """Index into `corners` of each face's first corner."""
    out = np.zeros(len(sizes), dtype=np.int64)
    np.cumsum(sizes[:-1], out=out[1:])
    return out


def fan_triangles(sizes, corners):
    """(m,3) triangles (v0, vi, vi+1) of every face, in face order."""
    sizes = np.asarray(sizes, dtype=np.int64)
    corners = np.asarray(corners, dtype=np.int64)
    first = starts(sizes)
    face = np.repeat(np.arange(len(sizes)), sizes - 2)
    # i-th triangle of its face: 1, 2, ..., size-2
    i = np.arange(len(face)) - np.repeat(np.cumsum(sizes - 2) - (sizes - 2), sizes - 2) + 1
    s = first[face]
    return np.stack([corners[s], corners[s + i], corners[s + i + 1]], axis=1)


def next_corner(sizes):
    """For each corner, the index (into `corners`) of the next corner of its face."""
    sizes = np.asarray(sizes, dtype=np.int64)
    first = np.repeat(starts(sizes), sizes)
    within = np.arange(int(sizes.sum())) - first
    return first + (within + 1) % np.repeat(sizes, sizes)


def face_normals(P, sizes, corners):
    """Area-weighted normals (Newell's method: exact for planar n-gons, sensible for others)."""
    corners = np.asarray(corners, dtype=np.int64)
    nxt = corners[next_corner(sizes)]
    cross = 0.5 * np.cross(P[corners], P[nxt])
    face = np.repeat(np.arange(len(sizes)), sizes)
    out = np.zeros((len(sizes), 3))
    np.add.at(out, face, cross)
    return out


def accumulate_unit(groups, vectors, n, fallback):
    """Unit sums of `vectors` grouped by `groups` into n slots; slots whose sum is zero (or
    that no vector reaches) keep `fallback`."""
    acc = np.zeros((n, 3))
    np.add.at(acc, groups, vectors)
    length = np.linalg.norm(acc, axis=1)
    out = np.array(fallback, dtype=np.float64, copy=True)
    ok = length > 0.0
    out[ok] = acc[ok] / length[ok, None]
    return out


def vertex_normals(P, sizes, corners, fallback):
    """Per-vertex unit normals: the area-weighted normals of the faces around each vertex."""
    N = face_normals(P, sizes, corners)
    face = np.repeat(np.arange(len(sizes)), sizes)
    return accumulate_unit(np.asarray(corners, dtype=np.int64), N[face], len(P), fallback)
