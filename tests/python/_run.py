"""Building and solving a Deformer the way most tests need it."""

import numpy as np

import edgedeform as ed


def deformer(V, F, domain, lam, handles, static=(), roi=None, **kwargs):
    d = ed.Deformer(V, F, domain=domain, **kwargs)
    d.set_constraints(handles=np.asarray(handles, dtype=np.int64),
                      static=np.asarray(static, dtype=np.int64), roi=roi)
    d.set_stiffness(lam)
    return d


def max_dev(X, Y):
    return float(np.abs(np.asarray(X) - np.asarray(Y)).max())


def iterations_until_close(d, targets, goal, atol, max_iterations, chunk=5):
    """Run the local/global iteration from the naive solve in chunks (each chunk warm-
    starts from the previous one, which continues the same iteration) until the
    positions are within atol of goal. Returns (iterations, deviation) or (None, dev)."""
    r = d.solve(targets, max_iterations=chunk, tolerance=0.0, warm_start=False)
    total = r.iterations
    while True:
        dev = max_dev(r.positions, goal)
        if dev <= atol:
            return total, dev
        if total >= max_iterations or not np.all(np.isfinite(r.positions)):
            return None, dev
        r = d.solve(targets, max_iterations=chunk, tolerance=0.0, warm_start=True)
        total += r.iterations
