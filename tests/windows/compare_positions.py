"""Compares solve_lift outputs: each must have the reference's vertex count and iteration
count, and positions within TOL of the rest mesh's bounding-box diagonal of the reference's.

    compare_positions.py TOL INPUT REFERENCE OUTPUT [OUTPUT ...]

TOL 0 demands bit-identical positions (the same build on another thread count).
"""

import sys

import numpy as np


def read(path):
    with open(path) as f:
        nv, iterations, energy = f.readline().split()
        X = np.loadtxt(f, dtype=float, ndmin=2)
    assert X.shape == (int(nv), 3), (path, X.shape, nv)
    return int(iterations), float(energy), X


def diagonal(input_path):
    with open(input_path) as f:
        nv = int(f.readline().split()[0])
        V = np.loadtxt(f, dtype=float, max_rows=nv, ndmin=2)
    return float(np.linalg.norm(np.ptp(V, axis=0)))


def main():
    tol, input_path, reference = float(sys.argv[1]), sys.argv[2], sys.argv[3]
    diag = diagonal(input_path)
    its, energy, X = read(reference)
    assert its > 0 and np.all(np.isfinite(X)), reference
    failed = False
    for path in sys.argv[4:]:
        its2, energy2, Y = read(path)
        gap = float(np.abs(Y - X).max()) / diag
        ok = its2 == its and (gap <= tol if tol > 0 else np.array_equal(X, Y))
        failed |= not ok
        print("%s: %d iterations, energy %.15g (reference %.15g, %d iterations); largest "
              "coordinate gap %.3g of the diagonal (allowed %s): %s"
              % (path, its2, energy2, energy, its, gap, tol if tol > 0 else "0, bit-identical",
                 "OK" if ok else "FAILED"), flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
