"""solve_lift.cpp's fixed solve through the Python module: the `windows` tests run it with
Linux's module and with the installed win_amd64 wheel in Windows' CPython (under wine here),
on 1 and 2 threads, and compare the outputs (compare_positions.py).

    solve_lift.py INPUT OUTPUT ITERATIONS

INPUT and OUTPUT as solve_lift.cpp's (make_lift_input.py writes INPUT); every double printed
exactly (%.17g). Prints the solver, the Python and the times.
"""

import platform
import sys

import numpy as np

import edgedeform as ed


def read_input(path):
    with open(path) as f:
        nv, nf, nh, ns, lam = f.readline().split()
        nv, nf, nh, ns = int(nv), int(nf), int(nh), int(ns)
        V = np.loadtxt(f, max_rows=nv, ndmin=2)
        F = np.loadtxt(f, dtype=np.int64, max_rows=nf, ndmin=2)
        handles = np.array(f.readline().split(), dtype=np.int64)
        static = np.array(f.readline().split(), dtype=np.int64)
        targets = np.loadtxt(f, max_rows=nh, ndmin=2)
    assert V.shape == (nv, 3) and F.shape == (nf, 3) and targets.shape == (nh, 3)
    assert len(handles) == nh and len(static) == ns
    return V, F, handles, static, targets, float(lam)


def main():
    source, out, iterations = sys.argv[1], sys.argv[2], int(sys.argv[3])
    V, F, handles, static, targets, lam = read_input(source)
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(lam)
    r = d.solve(targets, max_iterations=iterations, tolerance=0.0, acceleration="none",
                warm_start=False)
    X = np.asarray(r.positions)
    energy = float(r.energies[-1]) if len(r.energies) else 0.0
    with open(out, "w") as f:
        f.write("%d %d %.17g\n" % (len(X), r.iterations, energy))
        f.writelines("%.17g %.17g %.17g\n" % tuple(x) for x in X)
    info = ed.build_info()
    per_iteration = (r.local_ms + r.rhs_ms + r.solve_ms) / max(1, r.iterations)
    print("solve_lift.py: %s on %s %s, %d threads: %d vertices, %d iterations, energy %.17g, "
          "factor %.0f ms (%.0f nonzeros), %.0f ms per iteration"
          % (info["solver"], platform.system(), platform.python_version(), info["threads"],
             len(X), r.iterations, energy, r.factor_ms, d.factor_nonzeros, per_iteration),
          flush=True)


if __name__ == "__main__":
    main()
