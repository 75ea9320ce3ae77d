"""The one-step map in rotation coordinates, for bench_spectrum.py --radius.

At a fixed point x* with local fit (R*, s*), a state is z = (omega_t, sigma_t) per energy term:
the rotations R*_t exp([omega_t]) and the scales s*_t + sigma_t. The map psi takes z through a
global step (positions, Deformer._global_step) and the next local fit (Deformer._local_fit)
back to such coordinates; psi(0) = 0 at the fixed point, and its Jacobian has the eigenvalues
of J_G (D_R A^-1 B against A^-1 B D_R). A Newton method on the rotations would step in these
coordinates: how far its linear model holds is measured the same way as for positions.
"""

import numpy as np


def skew(w):
    """(k, 3) vectors -> (k, 3, 3) cross-product matrices."""
    K = np.zeros(w.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    return K - np.swapaxes(K, -1, -2)


def exp_so3(w):
    """Rodrigues: (k, 3) rotation vectors -> (k, 3, 3) rotations."""
    angle = np.linalg.norm(w, axis=-1)[..., None, None]
    K = skew(w)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0, np.sin(safe) / safe)
    b = np.where(small, 0.5, (1.0 - np.cos(safe)) / safe ** 2)
    return np.eye(3) + a * K + b * (K @ K)


def log_so3(R):
    """(k, 3, 3) rotations (angles below pi) -> (k, 3) rotation vectors."""
    vee = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                    R[..., 1, 0] - R[..., 0, 1]], axis=-1) / 2.0
    cos = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos)
    sin = np.sin(angle)
    factor = np.where(angle < 1e-8, 1.0, angle / np.where(sin == 0.0, 1.0, sin))
    return vee * factor[..., None]


class RotationCoordinates:
    """psi and the coordinates of shapes near the fixed point X of Deformer d."""

    def __init__(self, d, X):
        self.d, self.X = d, X
        self.free_vertices = np.asarray(d.free_vertices)
        self.R, self.s = d._local_fit(X)

    def of_shape(self, Y):
        """z of the local fit at the full shape Y."""
        R, s = self.d._local_fit(Y)
        return np.column_stack([log_so3(np.swapaxes(self.R, 1, 2) @ R), s - self.s])

    def psi(self, z):
        """z -> the global step's shape for (R* exp(omega), s* + sigma) -> its fit's z."""
        Y = self.X.copy()
        Y[self.free_vertices] = self.d._global_step(self.X, self.R @ exp_so3(z[:, :3]), self.s + z[:, 3])
        return self.of_shape(Y)

    def direction(self, free_mask, v, eps=1e-6):
        """The z direction of a position direction v (rows over free_mask's vertices):
        the local fit's central difference."""
        plus, minus = self.X.copy(), self.X.copy()
        plus[free_mask] += eps * v
        minus[free_mask] -= eps * v
        return (self.of_shape(plus) - self.of_shape(minus)) / (2.0 * eps)


def largest_row(a):
    return float(np.linalg.norm(a, axis=1).max())
